"""Presliding: friction depends on motion history near reversals and stops (LuGre bristles).

Regressors: ``LP(z - sign(w))`` and ``LP(w*(1 - sign(w)*z))`` with ``z`` the normalised Dahl
bristle state along the encoder position, for 14 presliding lengths ``xc`` from 3 to 150
encoder counts (shorter is below what the encoder resolves); coefficients: the level the
bristles carry and the bristle damping ``sigma1``, both ``>= 0``, the damping at most
critical (``2*sqrt(sigma0*I)`` with the baseline's Coulomb level and inertia).  The fitted model is
LuGre with ``sigma0 = Fc/xc`` and the fitted ``sigma1``.
Bench: LuGre bristles, presliding length Fc/sigma0 = 6 .. 20 encoder counts, bristle damping
ratio 0.3 .. 1.

Notes
-----
With no damping fitted the model takes a damping ratio of 0.5 of the bristle mode, which
keeps the re-simulation from ringing.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...friction import FrictionModel, LuGre
from ..signals import dahl_state
from .base import Cause, coulomb_level


#: Shortest and longest presliding length searched [encoder counts].
COUNTS = (3.0, 150.0)


def _variants(base, fold):
    sig = base.sig
    res = sig.resolution if sig.resolution > 0 else 1e-6 * np.ptp(sig.q)
    fc = coulomb_level(base.fitted)
    for nc in np.logspace(np.log10(COUNTS[0]), np.log10(COUNTS[1]), 14):
        xc = nc * res
        z = dahl_state(sig.q, xc, 0.0)
        damping = sig.w * (1.0 - np.sign(sig.w) * z)
        # the bristles at most critically damped: sigma1 <= 2*sqrt(sigma0*I), sigma0 = Fc/xc
        yield base.variant(float(xc), np.column_stack([sig.filt(z - base.sign),
                                                       sig.filt(damping)]), (1, 1),
                           upper=(np.inf, 2.0 * math.sqrt(max(fc, 0.0) / xc * base.inertia)))


def _extend(model, term, base):
    d = model.friction.as_dict()
    sigma0 = max(0.5 * (d["coulomb_pos"] + d["coulomb_neg"]), 1e-12) / term.h
    s1 = float(term.coef[1]) if term.coef.size > 1 and term.coef[1] > 0 else math.sqrt(
        sigma0 * model.inertia)
    if min(d["coulomb_pos"], d["coulomb_neg"]) <= 0:
        return model
    d["static_pos"] = d["static_neg"] = 0.0
    return replace(model, friction=FrictionModel.from_dict(d) + LuGre(sigma0, s1))


def _evidence(base, term, extended):
    sig, u = base.sig, base.labels
    xc = term.h
    counts = xc / sig.resolution if sig.resolution > 0 else float("nan")
    return (f"the friction builds up over a presliding displacement of {xc:.3g} {u.position} "
            f"({counts:.0f} encoder counts) after each reversal instead of switching with the "
            f"sign of the velocity; LuGre bristle stiffness sigma0 = "
            f"{extended.friction.lugre_sigma0:.4g} {u.stiffness}, bristle damping sigma1 = "
            f"{extended.friction.lugre_sigma1:.4g} {u.viscous}")


def _inject(rng, act):
    fc = act.coulomb
    xc = rng.uniform(6.0, 20.0) * act.encoder_resolution * act.strength
    sigma0 = fc / xc
    sigma1 = rng.uniform(0.3, 1.0) * 2.0 * math.sqrt(sigma0 * act.inertia)
    # RK4 on z' = w - |w| z / xc needs h*|w|/xc < ~2.5 at the highest speed (~10 rad/s)
    nsub = int(min(max(40, math.ceil(act.sample_time * 12.0 * act.travel / xc / 1.5)), 2000))
    return act.rigid(magnitude=dict(sigma0=sigma0, sigma1=sigma1, presliding_length=xc),
                     friction=act.friction() + LuGre(sigma0, sigma1), substeps=nsub)


CAUSE = Cause(
    name="presliding", order=80,
    physical="friction depends on motion history near reversals and stops",
    changes=("lugre_sigma0", "lugre_sigma1", "static_pos", "static_neg"),
    params=("presliding_level", "bristle_damping"), variants=_variants, extend=_extend,
    evidence=_evidence,
    inject=_inject)
