"""The constant torque (``offset``) against direction asymmetry, and EMPS told the same way
with and without a supplied model (issue 21, items 3-4).

Seeds: ``[2141, i]`` while building; ``[2142, i]`` (rotary) and ``[2143, i]`` (linear) for
the rates, never looked at while building.
"""

import numpy as np
import pytest

from fricctl.bench.hidden_effects import hidden_effect_record
from fricctl.datasets import Run
from fricctl.diagnose.causes import Baseline
from fricctl.diagnose.signals import estimate_signals
from fricctl.diagnose.twin import effect_free_twin


def _shifted(run: Run, off: float) -> Run:
    return Run(t=run.t, torque=run.torque + off, position=run.position,
               reference=run.reference, units=run.units, source="offset added")


def test_twin_carries_the_models_offset():
    # the twin of a model with a constant torque c, on the record shifted by c, is the twin
    # of the model without it on the record (the same physics): the chain's floor must not
    # hold the offset (it did: EMPS's floor was hypot(3.16, 0.66) N with the IDIM-LS model)
    rec = hidden_effect_record(np.random.default_rng([2141, 0]), cause="none", duration=10.0,
                               nominal=True)
    off = 0.3 * rec.nominal.friction.coulomb_pos
    from dataclasses import replace
    plain = effect_free_twin(Baseline(estimate_signals(rec.run, 8), rec.nominal, None)).rms
    moved = effect_free_twin(Baseline(estimate_signals(_shifted(rec.run, off), 8),
                                      replace(rec.nominal, offset=off), None)).rms
    # reference: the same simulation up to the constant (rounding of the encoder only)
    assert moved == pytest.approx(plain, rel=0.05)
    assert moved < 0.5 * off


# ----------------------------------------------------------------------------- judged by removal
def test_supplied_terms_are_removed_to_be_judged():
    from fricctl.diagnose import judged_by_removal
    from fricctl.friction import Coulomb, PositionRipple, Stribeck, Viscous
    from fricctl.plant import JointModel

    m = JointModel(inertia=2.0, friction=Viscous(pos=3.0, neg=5.0) + Coulomb(pos=1.2, neg=0.8)
                   + Stribeck(0.4, 0.05) + PositionRipple(0.1, 0.2, 0.3), offset=-0.3)
    core, held = judged_by_removal(m)
    # candidate order (registry): stribeck, asymmetry, position_ripple, ..., offset
    assert held == ("stribeck", "asymmetry", "position_ripple", "offset")
    assert core.friction.ripple_amplitude == 0.0
    fr = core.friction
    # neutral values by hand: mean levels both ways, no excess, no offset
    assert (fr.viscous_pos, fr.viscous_neg) == (4.0, 4.0)
    assert fr.coulomb_pos == fr.coulomb_neg == pytest.approx(1.0, rel=1e-15)
    assert fr.stribeck_pos == fr.stribeck_neg == 0.0 and core.offset == 0.0
    assert core.inertia == m.inertia
    plain = JointModel(inertia=2.0, friction=Viscous(4.0) + Coulomb(1.0))
    assert judged_by_removal(plain) == (plain, ())


# ----------------------------------------------------------------------------- identifiability
def test_a_coulomb_asymmetry_is_read_as_the_same_offset(monkeypatch):
    # Coulomb Fc+c forward and Fc-c backward is a constant torque c on a rigid joint (same
    # sliding torque, same breakaway band): the diagnosis names the offset, of size c
    # (reference: the injected levels; tolerance 10 % of c, a seeded noisy recovery)
    from fricctl.diagnose import causes, diagnose
    from fricctl.friction import Coulomb, Viscous

    def coulomb_asymmetry(name, rng, act):
        c = 0.3 * act.coulomb
        friction = Viscous(act.viscous) + Coulomb(pos=act.coulomb + c, neg=act.coulomb - c)
        return act.rigid(magnitude=dict(c=c), friction=friction, breakaway=act.coulomb + c)

    monkeypatch.setattr(causes, "inject", coulomb_asymmetry)
    rec = hidden_effect_record(np.random.default_rng([2141, 1]), cause="asymmetry",
                               duration=20.0)
    d = diagnose(rec.run)
    assert d.causes == ("offset",), d.report()
    c = rec.magnitude["c"]
    assert d.extended.offset == pytest.approx(c, rel=0.1)
    assert "slides the same way" in d.evidence
    assert causes.get("offset").held_by(rec.truth)  # the levels differ: an offset held


def test_offset_injected_as_a_constant_torque():
    # the bench applies the truth's offset at the joint: with the offset subtracted from the
    # recorded torque, the record is that of the model without it (reference: the predicted
    # residual of the truth is the noise's, far below the offset)
    from fricctl.diagnose.signals import predict

    rec = hidden_effect_record(np.random.default_rng([2141, 2]), cause="offset", duration=10.0)
    off = rec.magnitude["offset"]
    assert rec.truth.offset == off and rec.effect_free.offset == 0.0
    sig = estimate_signals(rec.run, 8)
    r = predict(rec.truth, sig).residual[sig.moving]
    assert abs(np.mean(r)) < 0.1 * abs(off)


# ----------------------------------------------------------------------------- rates (slow)
KINDS = ("offset", "asymmetry", "none")


def _rate_record(cause: str, axis: str, i: int):
    key = {"rotary": 2142, "linear": 2143}[axis]
    return hidden_effect_record(np.random.default_rng([key, 100 * KINDS.index(cause) + i]),
                                cause=cause, axis=axis)


@pytest.mark.slow
def test_offset_named_on_unseen_seeds():
    # issue 21's target for the new causes hidden alone: >= 85 % named exactly, on 20 records
    # (10 rotary, 10 linear; seeds never looked at while building); the asymmetry (now a
    # viscous split) still named; effect-free records: no cause
    from fricctl.diagnose import diagnose

    named = {k: [] for k in KINDS}
    for cause, n in (("offset", 10), ("asymmetry", 4), ("none", 4)):
        for axis in ("rotary", "linear"):
            for i in range(n):
                named[cause].append(diagnose(_rate_record(cause, axis, i).run).causes)
    assert sum(c == ("offset",) for c in named["offset"]) >= 0.85 * len(named["offset"]), named
    asym = named["asymmetry"]
    assert sum(c == ("asymmetry",) for c in asym) >= 0.75 * len(asym), named
    assert all(c == ("none",) for c in named["none"]), named


# ----------------------------------------------------------------------------- EMPS (slow)
@pytest.mark.slow
@pytest.mark.parametrize("name", ["DATA_EMPS.mat", "DATA_EMPS_PULSES.mat"])
def test_emps_same_causes_with_and_without_model(data_dir, tmp_path, capsys, name):
    # issue 21, item 4: `fricctl diagnose` names the same causes with and without --model
    # from `fricctl identify --recipe idim_ls` on the same file (which holds the -3.16 N
    # offset); the offset is judged by removal and the record supports the viscous
    # asymmetry instead; every named parameter physical (viscous > 0 both ways)
    import json

    from fricctl.cli import main

    path = str(data_dir / "emps" / name)
    model = tmp_path / "idim.json"
    assert main(["identify", path, "--recipe", "idim_ls", "--no-validation",
                 "--out", str(model)]) == 0
    capsys.readouterr()
    out = {}
    for key, extra in (("fit", []), ("model", ["--model", str(model)])):
        assert main(["diagnose", path, "--json", *extra]) == 0
        out[key] = json.loads(capsys.readouterr().out)
    assert out["fit"]["causes"] == out["model"]["causes"] == ["asymmetry"]
    assert out["model"]["held_by_model"] == ["offset"] and out["fit"]["held_by_model"] == []
    assert out["model"]["origin"] == {"asymmetry": "found"}
    for o in out.values():
        ext = o["extended"]
        assert 0 < ext["viscous_pos"] < ext["viscous_neg"]
        assert not o["explained"] and o["residual_over_floor"] > 2


def test_unsupported_offset_of_a_supplied_model_is_left_out_and_said():
    # a supplied model holding an offset the record does not have: removed to be judged, not
    # named, left out of the extended model with its provenance saying why; none named, as
    # without the model
    from dataclasses import replace

    from fricctl.diagnose import diagnose

    rec = hidden_effect_record(np.random.default_rng([2141, 3]), cause="none", duration=20.0,
                               nominal=True)
    wrong = replace(rec.nominal, offset=0.3 * rec.nominal.friction.coulomb_pos)
    d = diagnose(rec.run, wrong)
    assert d.causes == ("none",) and d.held == ("offset",) and d.origin == {}
    assert d.extended.offset == 0.0 and d.supplied is wrong
    prov = d.extended.provenance["offset"]
    assert prov.source == "diagnosed" and "not supported" in prov.note
    assert "the record does not support it" in d.evidence
    assert d.as_dict()["held_by_model"] == ["offset"]
