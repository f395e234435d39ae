"""Presliding: friction depends on motion history near reversals and stops (LuGre bristles).

Regressor: ``LP(z - sign(w)) + kappa*LP(w*(1 - sign(w)*z))`` with ``z`` the normalised Dahl
bristle state along the encoder position: the bristles' deflection and their damping
``sigma1 = 2*zeta*sqrt(sigma0*I)`` (``sigma0 = Fc/xc``, ``kappa = sigma1/Fc`` with the
baseline's Coulomb level and inertia), for 14 presliding lengths ``xc`` from 3 to 150
encoder counts (shorter is below what the encoder resolves) and damping ratios ``zeta``
0.3, 0.6, 1; coefficient: the level ``>= 0`` the bristles carry.  The fitted model is
LuGre with ``sigma0 = Fc/xc`` and that damping ratio.
Bench: LuGre bristles, presliding length Fc/sigma0 = 6 .. 20 encoder counts, bristle damping
ratio 0.3 .. 1.

Notes
-----
The damping is tied to the deflection through the ratio ``zeta`` (one coefficient): a
free damping coefficient fits any residual that follows a reversal (a resonance's
ringing, a Stribeck mismatch), not only the bristles'.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...friction import FrictionModel, LuGre
from ...friction.presliding import bristle_state
from .base import Cause, coulomb_level


#: Shortest and longest presliding length searched [encoder counts].
COUNTS = (3.0, 150.0)
#: Damping ratios of the bristle mode searched [-].
DAMPING_RATIOS = (0.3, 0.6, 1.0)


def _sigma1(fc: float, xc: float, inertia: float, zeta: float) -> float:
    """Bristle damping of damping ratio ``zeta`` for stiffness ``fc/xc`` and ``inertia``."""
    return 2.0 * zeta * math.sqrt(max(fc, 0.0) / xc * max(inertia, 0.0))


def _variants(base, fold):
    sig = base.sig
    res = sig.resolution if sig.resolution > 0 else 1e-6 * np.ptp(sig.q)
    fc = max(coulomb_level(base.fitted), 1e-300)
    for nc in np.logspace(np.log10(COUNTS[0]), np.log10(COUNTS[1]), 14):
        xc = nc * res
        z = bristle_state(sig.q, xc, 0.0, 1.0)
        deflection = sig.filt(z - base.sign)
        damping = sig.filt(sig.w * (1.0 - np.sign(sig.w) * z))
        for zeta in DAMPING_RATIOS:
            kappa = _sigma1(fc, xc, base.inertia, zeta) / fc
            yield base.variant((float(xc), zeta), deflection + kappa * damping, (1,))


def _extend(model, term, base):
    xc, zeta = term.h
    d = model.friction.as_dict()
    fc = 0.5 * (d["coulomb_pos"] + d["coulomb_neg"])
    if min(d["coulomb_pos"], d["coulomb_neg"]) <= 0:
        return model
    d["static_excess_pos"] = d["static_excess_neg"] = 0.0
    return replace(model, friction=FrictionModel.from_dict(d) + LuGre(
        fc / xc, _sigma1(fc, xc, model.inertia, zeta)))


def _evidence(base, term, extended):
    sig, u = base.sig, base.labels
    xc, zeta = term.h
    counts = xc / sig.resolution if sig.resolution > 0 else float("nan")
    return (f"the friction builds up over a presliding displacement of {xc:.3g} {u.position} "
            f"({counts:.0f} encoder counts) after each reversal instead of switching with the "
            f"sign of the velocity; LuGre bristle stiffness sigma0 = "
            f"{extended.friction.lugre_sigma0:.4g} {u.stiffness}, bristle damping sigma1 = "
            f"{extended.friction.lugre_sigma1:.4g} {u.viscous} (damping ratio {zeta:g})")


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
    changes=("lugre_sigma0", "lugre_sigma1", "static_excess_pos", "static_excess_neg"),
    params=("presliding_level",), variants=_variants, extend=_extend, evidence=_evidence,
    inject=_inject)
