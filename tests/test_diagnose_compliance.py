"""Compliance: the resonance refined between the grid's points, and the checks that keep a
refined spring from standing for what is not a spring (fricctl.diagnose.causes.compliance).

Seeds ``[2034, i]``, chosen before looking at their results.
"""

import math

import numpy as np
import pytest

from fricctl.bench.hidden_effects import hidden_effect_record
from fricctl.diagnose.causes import REGISTRY, Baseline, Term
from fricctl.diagnose.causes import backlash as backlash_cause
from fricctl.diagnose.causes import compliance as compliance_cause
from fricctl.diagnose.crossval import Problem, full_fit
from fricctl.diagnose.signals import estimate_signals


def _natural(rec) -> float:
    """The hidden spring's natural frequency on the load side [rad/s]."""
    return math.sqrt(rec.magnitude["stiffness"] / rec.magnitude["load_inertia"])


def _spring_share(base, wl, zeta):
    return backlash_cause.drop_share(base, compliance_cause._spring_column(base.sig, wl, zeta),
                                     base.current_residual)


@pytest.mark.parametrize("i", [0, 1])
def test_the_refined_resonance_is_nearer_the_hidden_one_than_the_grid(i):
    # the grid steps the natural frequency 33 % (8 per decade) where a lightly damped
    # resonance's band is 2*zeta wide; the refined variant fits between its points
    rec = hidden_effect_record(np.random.default_rng([2034, i]), cause="compliance",
                               nominal=True, duration=30.0)
    sig = estimate_signals(rec.run, 8)
    base = Baseline(sig, rec.nominal, None)
    cause = REGISTRY["compliance"]
    grid = full_fit(Problem(sig, None), list(cause.variants(base, None)))
    best = full_fit(Problem(sig, None), base.variants(cause, None))
    true = _natural(rec)
    assert abs(math.log(best.variant.h[0] / true)) < abs(math.log(grid.variant.h[0] / true))
    assert abs(math.log(best.variant.h[0] / true)) < math.log(1.05)
    assert best.sse < grid.sse


def test_a_damping_at_the_bound_of_the_search_cannot_be_told():
    rec = hidden_effect_record(np.random.default_rng([2034, 2]), cause="none", nominal=True,
                               duration=10.0)
    sig = estimate_signals(rec.run, 8)
    base = Baseline(sig, rec.nominal, None)
    hook = REGISTRY["compliance"].identifiable
    wl = 2 * np.pi * 0.3 * sig.cutoff
    top = compliance_cause.REFINE_ZETA[1]
    reason = hook(base, Term(h=(wl, top), coef=np.array([0.3 * base.inertia])))
    assert reason is not None and "bound of its search" in reason
    below = hook(base, Term(h=(wl, 0.9 * top), coef=np.array([0.3 * base.inertia])))
    assert below is None or "bound of its search" not in below


def test_a_spring_a_sinusoid_in_time_matches_cannot_be_told():
    # a torque periodic in time (foreign to the list of causes) makes the joint move at its
    # frequency; a spring tuned there rides on that motion, and one sinusoid in time
    # removes at least as much
    rec = hidden_effect_record(np.random.default_rng([2034, 3]), cause="none",
                               foreign="time_sine", excitation="closed_loop", duration=20.0,
                               nominal=True)
    sig = estimate_signals(rec.run, 8)
    base = Baseline(sig, rec.nominal, None)
    wl = 2 * np.pi * rec.foreign_magnitude["frequency"]
    term = Term(h=(wl, 0.05), coef=np.array([0.3 * base.inertia]))
    reason = compliance_cause._periodic_in_time(base, term)
    assert reason is not None and "periodic in time" in reason
    # and the cause's own test says so
    told = REGISTRY["compliance"].identifiable(base, term)
    assert told is not None and "periodic in time" in told


def test_a_true_spring_is_not_a_sinusoid_in_time():
    # a resonance rings with the phase of each change of the motion: no one sinusoid over the
    # record follows it
    rec = hidden_effect_record(np.random.default_rng([2034, 4]), cause="compliance",
                               nominal=True, duration=30.0)
    sig = estimate_signals(rec.run, 8)
    base = Baseline(sig, rec.nominal, None)
    m = rec.magnitude
    wl = _natural(rec)
    zeta = m["damping"] / (2 * math.sqrt(m["stiffness"] * m["load_inertia"]))
    term = Term(h=(wl, zeta), coef=np.array([m["load_inertia"]]))
    spring = _spring_share(base, wl, zeta)
    assert spring > 0.5
    assert compliance_cause._periodic_in_time(base, term) is None
    assert REGISTRY["compliance"].identifiable(base, term) is None


def test_a_dead_band_beside_the_refined_spring_refuses_it():
    # a backlash whose refined spring removes more than the dead band alone, its damping inside
    # the search's bounds: the dead band fitted beside it removes the naming line of what the
    # spring leaves, which a true spring leaves it (0-3 % on development records)
    rec = hidden_effect_record(np.random.default_rng([2034, 21]), cause="backlash", nominal=True,
                               excitation="mixed", sample_time=0.001, duration=20.0)
    sig = estimate_signals(rec.run, 8)
    base = Baseline(sig, rec.nominal, None)
    best = full_fit(Problem(sig, None), base.variants(REGISTRY["compliance"], None))
    term = Term(h=best.variant.h, coef=best.theta)
    assert best.variant.h[1] < compliance_cause.REFINE_ZETA[1]
    reason = REGISTRY["compliance"].identifiable(base, term)
    assert reason is not None and "fitted beside it" in reason, reason
