"""Tests of the compensator comparison (fricctl.compare): contenders, plants, metrics, protocol,
figure; the runs without trained networks (the networks' rows are under ``slow``)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from fricctl.compare import (CONTENDERS, EXPERIMENTS, METRICS, PLANTS, REGISTERED, ComparisonResult,
                             check_plant, compare, make_contender, realise)
from fricctl.compare.experiments import hf_share, limit_cycle, scaled
from fricctl.compensators import (Compensator, ConfirmedNNCompensator, CoulombCompensator, NNCompensator,
                                  NoCompensation)
from fricctl.paper.benches import bench
from fricctl.paper.common import designs
from fricctl.params import PAPER_LINK_INERTIA

B = bench("literal")
D = designs(B)["fig13-14"]

#: The fast table: the contenders that train nothing, three experiments, two plants.
FAST = dict(compensators=("none", "coulomb_breakaway"), experiments=("pd_steps", "coast", "dead_zone"),
            plants=("nominal", "delay_1"), seeds=3)


@pytest.fixture(scope="module")
def small():
    return compare(**FAST)


# ------------------------------------------------------------------ contenders
def test_coulomb_levels_come_from_the_design_model():
    # literal bench (paper): Fc = 0.144 N*m (assumption), Fs = 0.18 N*m (paper, Section 4)
    c = make_contender("coulomb", B.model, D, B.actuator.sample_time)
    s = make_contender("coulomb_breakaway", B.model, D, B.actuator.sample_time)
    assert isinstance(c, CoulombCompensator) and type(s) is type(c)
    assert (c.coulomb_pos, c.coulomb_neg) == pytest.approx((0.144, 0.144), abs=1e-12)
    assert (s.coulomb_pos, s.coulomb_neg) == pytest.approx((0.18, 0.18), abs=1e-12)
    # from the model given, not from the bench: a model with another friction gives its levels
    other = B.model.__class__.from_params(B.actuator.replace(coulomb=0.1, static=0.15), source="test")
    assert make_contender("coulomb_breakaway", other, D, 0.002).coulomb_pos == pytest.approx(0.15)
    assert isinstance(make_contender("none", B.model, D, 0.002), NoCompensation)


def test_network_contender_is_built_from_a_given_network_without_training():
    from fricctl.nn import FrictionNet

    net = FrictionNet(w1=[[0.0, 5.0]], b1=[0.0], w2=[1.0], b2=0.0, input_offset=[0, 0],
                      input_scale=[1, 1], output_offset=0.0, output_scale=0.1,
                      envelope_low=[-1, -1], envelope_high=[1, 1])
    comp = make_contender("nn", B.model, D, 0.002, seed=3, options={"network": net.to_json()})
    # the fricctl pipeline's network on its velocity (the direction-confirmed one)
    assert isinstance(comp, ConfirmedNNCompensator) and comp.name == "nn"
    assert comp.estimator.to_json() == net.to_json()
    # the paper's on the backward difference
    comp = make_contender("nn_paper", B.model, D, 0.002, seed=3, options={"network": net.to_json()})
    assert type(comp) is NNCompensator and comp.estimator.to_json() == net.to_json()


@pytest.mark.parametrize("call, match", [
    (lambda: make_contender("bogus", B.model, D, 0.002), "unknown compensator 'bogus'"),
    (lambda: make_contender("coulomb", B.model, D, 0.002, options={"level": 1}), "takes no option 'level'"),
    (lambda: make_contender("coulomb", B.actuator, D, 0.002), "JointModel"),
    (lambda: make_contender("none", B.model, D, 0.002, seed=-1), "seed"),
    (lambda: make_contender("nn", B.model, D, 0.001, options={"network": "{}"}), "trained at the bench's Ts"),
    (lambda: make_contender("nn", B.model, D, 0.002, options={"bench": "bogus"}), "bench"),
])
def test_bad_contender_arguments_raise(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_every_registered_compensator_is_a_contender():
    from fricctl import compensators

    have = set(compensators.available())
    for name in REGISTERED:
        assert name in have and name in CONTENDERS
    for name in ("none", "coulomb", "coulomb_breakaway", "nn", "nn_paper"):
        assert name in CONTENDERS


def test_lugre_observer_on_a_model_without_lugre_gets_the_assumed_bristle():
    from fricctl.compare.contenders import BRISTLE_COUNTS

    b = bench("literal")
    m = b.model
    assert m.friction.lugre_sigma0 == 0.0
    obs = make_contender("lugre_observer", m, designs(b)["fig13-14"], m.sample_time)
    fs = m.friction.breakaway(1)
    assert fs == pytest.approx(0.18)  # the paper's static friction, not Fc = 0.144
    assert obs.sigma0 == pytest.approx(fs / (BRISTLE_COUNTS * m.encoder_resolution))
    assert obs.sigma1 == pytest.approx(math.sqrt(obs.sigma0 * m.inertia))
    given = make_contender("lugre_observer", m, designs(b)["fig13-14"], m.sample_time,
                           options={"sigma0": 500.0, "sigma1": 2.0})
    assert (given.sigma0, given.sigma1) == (500.0, 2.0)
    # a stiffness given alone: the assumed damping rule applies to it, sqrt(sigma0 * I)
    alone = make_contender("lugre_observer", m, designs(b)["fig13-14"], m.sample_time, options={"sigma0": 500.0})
    assert alone.sigma1 == pytest.approx(math.sqrt(500.0 * m.inertia), rel=1e-12)


@pytest.mark.parametrize("options, match", [
    ({"sigma0": -1.0}, "sigma0 must be > 0 N\\*m/rad, got -1.0"),
    ({"sigma0": 0.0}, "sigma0 must be > 0 N\\*m/rad"),
    ({"sigma0": float("inf")}, "sigma0 must be finite"),
    ({"sigma0": "stiff"}, "sigma0 must be a real number"),
    ({"sigma0": 500.0, "sigma1": -2.0}, "sigma1 must be >= 0 N\\*m\\*s/rad"),
])
def test_lugre_observer_bristle_not_physical_is_a_value_error(options, match):
    b = bench("literal")
    with pytest.raises(ValueError, match=match):
        make_contender("lugre_observer", b.model, designs(b)["fig13-14"], b.model.sample_time, options=options)
    with pytest.raises(ValueError, match="options of 'lugre_observer': " + match):
        compare(compensators=("lugre_observer",), experiments=("pd_steps",), plants=("nominal",), seeds=1,
                bench="literal", options={"lugre_observer": options})


# ------------------------------------------------------------------ plants
def test_every_plant_is_a_plain_json_object_and_realises():
    for name, p in PLANTS.items():
        d = check_plant(name)
        assert d["name"] == name and json.loads(json.dumps(d)) == d
        realise(d, B.actuator)


def test_realise_applies_each_field():
    base = B.actuator
    nominal = realise("nominal", base)
    assert nominal.params == base and nominal.delay == 0 and nominal.compensation_scale == 1.0
    w = np.linspace(-1, 1, 41)
    f0 = nominal.friction.torque(w)
    # friction x1.2: every term x1.2 (closed form)
    np.testing.assert_allclose(realise("friction_1.2", base).friction.torque(w), 1.2 * f0, rtol=1e-12)
    # the paper's wear: friction and compensation x 0.95 (Fig. 16)
    wear = realise("wear", base)
    np.testing.assert_allclose(wear.friction.torque(w), 0.95 * f0, rtol=1e-12)
    assert wear.compensation_scale == 0.95
    assert realise("link", base).params.link_inertia == PAPER_LINK_INERTIA
    # 500 counts/rev: a count 4x the bench's 2000
    assert realise("encoder_500", base).params.encoder_resolution == pytest.approx(4 * base.encoder_resolution)
    assert realise("stribeck_2", base).params.stribeck_velocity == pytest.approx(2 * base.stribeck_velocity)
    assert realise("delay_1", base).delay == 1
    assert realise("noise", base).noise_std == 0.002 and nominal.noise_std == 0.0
    # a plant of the caller's: any subset of the fields
    mine = realise({"name": "mine", "friction_scale": 0.5, "delay": 2}, base)
    assert mine.delay == 2
    np.testing.assert_allclose(mine.friction.torque(w), 0.5 * f0, rtol=1e-12)


@pytest.mark.parametrize("plant, match", [
    ({"friction_scale": 1.2}, "needs a 'name'"),
    ({"name": "x", "friction": 1.2}, "unknown field 'friction'"),
    ({"name": "x", "friction_scale": -1.0}, "friction_scale"),
    ({"name": "x", "delay": 0.5}, "delay"),
    ({"name": "x", "encoder_counts": 0}, "encoder_counts"),
    ({"name": "x", "torque_noise": -0.1}, "torque_noise"),
    ("bogus", "unknown plant 'bogus'"),
    (3, "name or a mapping"),
])
def test_bad_plants_raise(plant, match):
    with pytest.raises(ValueError, match=match):
        check_plant(plant)


# ------------------------------------------------------------------ measurements
def test_hf_share_of_a_sum_of_two_tones():
    # equal-amplitude tones at 5 Hz and 100 Hz, whole periods: half the variance above 25 Hz
    t = 0.002 * np.arange(2000)
    x = np.sin(2 * np.pi * 5 * t) + np.sin(2 * np.pi * 100 * t)
    assert hf_share(x, 0.002) == pytest.approx(50.0, abs=1e-9)
    assert hf_share(np.full(100, 0.3), 0.002) == 0.0  # a held torque has none


def test_limit_cycle_below_half_a_count_is_none():
    t = 0.002 * np.arange(3000)
    a, f = limit_cycle(t, 0.4e-4 * np.sin(2 * np.pi * 5 * t), 1e-4)
    assert a == pytest.approx(0.4e-4, rel=1e-3) and f == 0.0
    a, f = limit_cycle(t, 3e-4 * np.sign(np.sin(2 * np.pi * 7 * t + 0.1)), 1e-4)  # a relay's square wave
    assert a == pytest.approx(3e-4) and f == pytest.approx(7.0, abs=0.25)


def test_scaled_sets_the_compensation_scale():
    c = CoulombCompensator.symmetric(0.18)
    assert scaled(c, 1.0) is c and scaled(c, 0.95).scale == 0.95

    class Bare(Compensator):  # the interface, without a scale field
        name = "bare"

    with pytest.raises(ValueError, match="no compensation scale"):
        scaled(Bare(), 0.95)


# ------------------------------------------------------------------ the protocol
def test_one_row_per_compensator_experiment_and_plant(small):
    r = small
    assert len(r.rows) == 2 * 3 * 2
    keys = [(x["compensator"], x["experiment"], x["plant"]["name"]) for x in r.rows]
    assert len(set(keys)) == len(keys)
    for x in r.rows:
        assert x["plant"] == check_plant(x["plant"]["name"])
        # neither contender depends on the seed: one run each, said so
        assert x["seeds"] == [0] and x["seeded"] is False
        ex = EXPERIMENTS[x["experiment"]]
        assert tuple(x["metrics"]) == ex.metrics
        for m, s in x["metrics"].items():
            assert s["unit"] == METRICS[m][0]
            assert s["median"] == s["min"] == s["max"] == s["values"][0]
        rw = x["runaway"]
        assert rw["runs"] == 1 and rw["rate"] == rw["passed"] / rw["runs"]
        assert (rw["passed"] == 1) == (not rw["failures"])


def test_physics_of_the_small_table(small):
    r = small
    # no compensation: the dead zone is the breakaway level, 12.7 % of Tmax by the bench's
    # definition Tmax = Fs/0.127, within one step of the 200-level grid (0.0995 % of Tmax)
    dz = r.row("none", "dead_zone", "nominal")["metrics"]
    assert dz["dead_zone"]["median"] == pytest.approx(12.7, abs=0.1)
    # friction only slows a coasting joint: without compensation no excess over the viscous decay
    assert r.row("none", "coast", "nominal")["metrics"]["coast_excess"]["median"] <= 1e-9
    # Coulomb at the breakaway level Fs over-compensates the sliding friction (Fc < Fs): while
    # the joint coasts the net torque Fs - Fc - stribeck(w) > 0 pushes it, above the decay
    assert r.row("coulomb_breakaway", "coast", "nominal")["metrics"]["coast_excess"]["median"] > 0


def test_json_and_markdown(small):
    d = json.loads(small.to_json())
    assert set(d) >= {"rows", "bench", "compensators", "experiments", "plants", "seeds", "metrics"}
    assert d["rows"] == json.loads(json.dumps(list(small.rows)))
    md = small.table()
    for en in FAST["experiments"]:
        assert f"## {en}:" in md
    assert "| compensator | plant | steady_state_error [deg] |" in md
    n_lines = sum(1 for line in md.splitlines() if line.startswith("| none |")
                  or line.startswith("| coulomb_breakaway |"))
    assert n_lines == len(small.rows)


def test_a_plant_with_noise_runs_every_compensator_over_the_seeds():
    r = compare(compensators=("none",), experiments=("pd_steps",), plants=("noise", "nominal"), seeds=3)
    noisy, clean = r.row("none", "pd_steps", "noise"), r.row("none", "pd_steps", "nominal")
    assert noisy["seeded"] is True and noisy["seeds"] == [0, 1, 2]
    assert clean["seeded"] is False and clean["seeds"] == [0]
    # each seed its own noise: three different efforts; the same seed again, the same number
    effort = noisy["metrics"]["effort_rms"]["values"]
    assert len(set(effort)) == 3
    again = compare(compensators=("none",), experiments=("pd_steps",), plants=("noise",), seeds=1)
    assert again.row("none", "pd_steps", "noise")["metrics"]["effort_rms"]["values"] == effort[:1]


@pytest.mark.parametrize("kwargs, match", [
    (dict(compensators=("bogus",)), "unknown compensator"),
    (dict(compensators=("none", "none")), "twice"),
    (dict(experiments=("bogus",)), "unknown experiment"),
    (dict(plants=({"name": "a"}, {"name": "a"})), "share a name"),
    (dict(seeds=0), "seeds"),
    (dict(bench="bogus"), "bench"),
    (dict(compensators=("none",), options={"nn": {}}), "not compared"),
    (dict(compensators=("nn",), options={"nn": {"bench": "literal"}}), "not the compared bench"),
    (dict(executor=object()), "Executor"),
])
def test_bad_compare_arguments_raise(kwargs, match):
    with pytest.raises(ValueError, match=match):
        compare(**{"compensators": ("none",), "experiments": ("coast",), "plants": ("nominal",),
                   **kwargs})


def test_a_thread_pool_gives_the_serial_rows(small):
    # the same jobs through an Executor (threads here; processes and Dask in the slow tests)
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(2) as ex:
        r = compare(**FAST, executor=ex)
    assert r.to_json() == small.to_json()


def test_plot_comparison(small):
    from fricctl.figures import plot_comparison

    ax = plot_comparison(small, experiment="coast", metric="coast_excess")
    assert [t.get_text() for t in ax.get_xticklabels()] == ["nominal", "delay_1"]
    assert ax.get_ylabel() == "coast_excess [%]"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["none", "coulomb_breakaway"]
    # the medians drawn are the rows' (filled where every runaway check passed, open otherwise)
    drawn = sorted(float(y) for line in ax.get_lines() if line.get_marker() == "o" for y in line.get_ydata())
    want = sorted(small.row(c, "coast", p)["metrics"]["coast_excess"]["median"]
                  for c in FAST["compensators"] for p in FAST["plants"])
    assert drawn == pytest.approx(want)
    with pytest.raises(ValueError, match="metric"):
        plot_comparison(small, experiment="coast", metric="tracking_rms")


# ------------------------------------------------------------------ issue 23: factor and runaway criteria
def _linear_net(gain: float) -> str:
    """A network whose estimate is ``gain * Tm`` (to 1e-6 relative over |Tm| <= Tmax): tanh of
    a 1e-3-scaled input, scaled back; its gain at rest is ``gain``."""
    from fricctl.nn import FrictionNet

    net = FrictionNet(w1=[[1e-3, 0.0]], b1=[0.0], w2=[gain * 1e3], b2=0.0, input_offset=[0, 0],
                      input_scale=[1, 1], output_offset=0.0, output_scale=1.0,
                      envelope_low=[-10, -100], envelope_high=[10, 100])
    assert net.gain_at_rest() == pytest.approx(gain, rel=1e-12)
    return net.to_json()


def test_dead_zone_factor_of_a_gain_at_rest_is_its_closed_form():
    # at rest (omega_hat = 0) a compensator T^at = g*Tm makes Tm(k+1) = Tc(k) + g*Tm(k): Tm settles
    # at Tc/(1 - g), so the open-loop joint breaks away at Tc = (1 - g)*Fs: the dead zone shrinks
    # by 1/(1 - g) (FrictionNet.gain_at_rest's closed form); Coulomb at Fs gives nothing at rest
    # (sign(0) = 0): factor 1.  Tolerance: the dead zone is read on a grid of 0.0995 % of Tmax
    r = compare(compensators=("nn", "coulomb_breakaway"), experiments=("dead_zone",), plants=("nominal",),
                seeds=1, options={"nn": {"network": _linear_net(0.5)}})
    nn = r.row("nn", "dead_zone", "nominal")["metrics"]
    none_dz = 12.7  # % of Tmax: Fs = 0.127 Tmax (the bench's definition; test_physics_of_the_small_table)
    assert nn["dead_zone"]["median"] == pytest.approx(0.5 * none_dz, abs=0.1)
    assert nn["dead_zone_factor"]["median"] == pytest.approx(2.0, abs=2 * (0.1 / 6.35 + 0.1 / 12.7))
    assert r.row("coulomb_breakaway", "dead_zone", "nominal")["metrics"]["dead_zone_factor"]["median"] == 1.0


def test_a_friction_estimate_with_gain_at_rest_above_one_fails_the_wind_up_check():
    # under the sinusoid at 10 % of Tmax (below Fs): with g = 1.5 Tm(k+1) = Tc(k) + 1.5 Tm(k) grows
    # until the drive saturates; with g = 0.5 Tm = 2 Tc stays within |Tc| + Fs (2 Tc < Tc + Fs)
    def runaway(gain):
        r = compare(compensators=("nn",), experiments=("dead_zone",), plants=("nominal",), seeds=1,
                    options={"nn": {"network": _linear_net(gain)}})
        return r.row("nn", "dead_zone", "nominal")["runaway"]

    bad, ok = runaway(1.5), runaway(0.5)
    assert bad["criterion"] == ok["criterion"] == "wind-up"
    assert bad["passed"] == 0 and bad["runs"] == 1 and "wind-up" in bad["failures"][0]
    assert ok["passed"] == 1


def _step30(plant, comp):
    from fricctl import controllers as ctl
    from fricctl.simulate import simulate

    c = ctl.pd_control(D.kp, D.kd, ctl.step(float(np.deg2rad(30.0))))
    return simulate(plant, c, comp, duration=3.0)


def test_divergence_passes_bounded_transients_and_fails_real_runaways():
    import control

    from fricctl.compensators import DisturbanceObserver, IntegralAction
    from fricctl.paper import divergence, wind_up

    p = B.actuator
    # integral action: the continuous PID loop I s^3 + (b + Kd) s^2 + Kp s + Ki is stable iff
    # Ki < (b + Kd) Kp / I (Routh); python-control's poles say the same
    ki_max = (D.viscous + D.kd) * D.kp / D.inertia

    def stable(ki):
        return bool(np.all(np.real(control.poles(control.tf([ki], [D.inertia, D.viscous + D.kd, D.kp, ki])))
                           < 0))

    assert stable(0.5 * ki_max) and not stable(1.5 * ki_max)
    half = _step30(p, IntegralAction(ki=0.5 * ki_max, max_torque=p.max_torque))
    assert not wind_up(half).passed  # beyond the friction bound: the integral's transient ...
    assert divergence(half).passed  # ... dies out
    unstable = _step30(p, IntegralAction(ki=1.5 * ki_max, max_torque=p.max_torque))
    d = divergence(unstable)
    assert not d.passed and d.value > 90  # a sustained oscillation: the excess has not decayed
    # a DOB told 4x the joint's inertia: with the default Q bandwidth 1/(10 Ts) the loop settles,
    # with 1/(2 Ts) it oscillates at the drive's saturation to the run's end
    big = 4 * p.total_inertia
    calm = _step30(p, DisturbanceObserver(inertia=big, bandwidth=1 / (10 * p.sample_time)))
    assert divergence(calm).passed
    wild = _step30(p, DisturbanceObserver(inertia=big, bandwidth=1 / (2 * p.sample_time)))
    assert not divergence(wild).passed
    assert np.max(np.abs(wild.torque_motor[-250:])) == p.max_torque
    # the DOB of the actuator alone on the link plant: it supplies the link's inertia torque at the
    # start of the step (beyond the friction bound), and the transient dies out
    linked = _step30(B.linked_actuator, DisturbanceObserver.from_model(
        B.model, bandwidth=1 / (10 * p.sample_time)))
    assert not wind_up(linked).passed and divergence(linked).passed


def test_the_integral_clamp_uses_the_loops_saturation_on_every_bench_and_plant():
    # issue 23 item 6: IntegralAction's clamp compares the held Tm (clipped by the loop at the
    # simulated plant's max_torque) with its own max_torque: the two must be the same number
    from fricctl.compare.protocol import _model
    from fricctl.paper.benches import BENCHES

    for name in BENCHES:
        b = bench(name)
        for en, ex in EXPERIMENTS.items():
            if not ex.closed_loop:
                continue
            comp = make_contender("integral", _model(name, ex.linked), designs(b)[ex.design],
                                  b.actuator.sample_time)
            for pl in PLANTS:
                base = b.linked_actuator if ex.linked else b.actuator
                assert comp.max_torque == realise(pl, base).params.max_torque, (name, en, pl)


def test_the_table_says_which_torque_check_each_row_used():
    r = compare(compensators=("none", "dob", "integral"), experiments=("pd_steps", "coast"),
                plants=("nominal",), seeds=1)
    assert r.row("none", "pd_steps", "nominal")["runaway"]["criterion"] == "wind-up"
    assert r.row("dob", "pd_steps", "nominal")["runaway"]["criterion"] == "divergence"
    assert r.row("integral", "pd_steps", "nominal")["runaway"]["criterion"] == "divergence"
    assert r.row("integral", "coast", "nominal")["runaway"]["criterion"] is None  # not applicable
    md = r.table()
    assert "| runaway | torque check |" in md
    assert "| 1/1 | divergence |" in md and "| 1/1 | wind-up |" in md
    assert "- `divergence`: not a friction estimate" in md


def test_given_networks_are_run_per_seed_and_nothing_is_trained(monkeypatch):
    # issue 23 item 5: `networks` (seed k's at index k) and `network` (every seed) are the nets run;
    # the training (and the disk cache it reads) is never reached
    import fricctl.compare.contenders as contenders

    def refuse(*a):
        raise AssertionError("a network was trained although one was given")

    monkeypatch.setattr(contenders, "_trained", refuse)
    nets = [_linear_net(0.5), _linear_net(0.25)]
    r = compare(compensators=("nn",), experiments=("dead_zone",), plants=("nominal",), seeds=2,
                options={"nn": {"networks": nets}})
    dz = r.row("nn", "dead_zone", "nominal")["metrics"]["dead_zone"]["values"]
    # seed 0 ran g = 0.5, seed 1 g = 0.25: dead zones (1 - g) * 12.7 % of Tmax, within a grid step
    assert dz == pytest.approx([0.5 * 12.7, 0.75 * 12.7], abs=0.1)
    same = compare(compensators=("nn",), experiments=("dead_zone",), plants=("nominal",), seeds=2,
                   options={"nn": {"network": nets[1]}})
    assert same.row("nn", "dead_zone", "nominal")["metrics"]["dead_zone"]["values"] == [dz[1], dz[1]]
    for bad, match in (({"networks": nets[:1]}, "none for seed 1"), ({"networks": nets[0]}, "list of JSON"),
                       ({"networks": [nets[0], 3]}, "networks\\[1\\] must be a string")):
        with pytest.raises(ValueError, match=match):
            compare(compensators=("nn",), experiments=("dead_zone",), plants=("nominal",), seeds=2,
                    options={"nn": bad})


# ------------------------------------------------------------------ slow: networks, processes, Dask
@pytest.mark.slow
def test_networks_over_seeds():
    r = compare(compensators=("nn", "nn_paper"), experiments=("pd_steps", "coast"), plants=("nominal",),
                seeds=2, options={"nn": {"fast": True}, "nn_paper": {"fast": True}})
    for x in r.rows:
        assert x["seeds"] == [0, 1] and x["seeded"] is True
        for s in x["metrics"].values():
            assert len(s["values"]) == 2
            vals = [v for v in s["values"] if v is not None and math.isfinite(v)]
            if vals:
                assert s["min"] == min(vals) and s["max"] == max(vals)
        assert x["runaway"]["runs"] == 2


@pytest.mark.slow
def test_dask_local_cluster_gives_the_serial_rows_bit_for_bit(small):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        r = compare(**FAST, executor=client.get_executor())
    assert r.to_json() == small.to_json()
    assert r.rows == small.rows


@pytest.mark.slow
def test_dask_local_cluster_gives_the_serial_rows_with_a_network_state_and_noise():
    # issue 23 item 4: a trained network (fast training, once, here), the stateful compensators
    # (the LuGre observer and the DOB carry a state through the compiled loop), a plant with
    # torque noise drawn per seed: the Dask rows are the serial ones bit for bit
    distributed = pytest.importorskip("distributed")
    from fricctl.paper import train_paper_network

    net = train_paper_network(bench="literal", seed=0, pipeline="fricctl", fast=True).net.to_json()
    run = dict(compensators=("nn", "lugre_observer", "dob"), experiments=("pd_steps", "dead_zone"),
               plants=("nominal", "noise"), seeds=2, bench="literal", options={"nn": {"network": net}})
    serial = compare(**run)
    noisy = serial.row("dob", "pd_steps", "noise")
    assert noisy["seeded"] and len(set(noisy["metrics"]["effort_rms"]["values"])) == 2  # noise per seed
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        r = compare(**run, executor=client.get_executor())
    assert r.to_json() == serial.to_json()
    assert r.rows == serial.rows


def test_a_compensator_of_the_position_error_is_not_applicable_open_loop():
    res = compare(compensators=["integral"], experiments=["coast", "pd_steps"], plants=["nominal"],
                  seeds=1, bench="literal")
    coast, steps = res.row("integral", "coast", "nominal"), res.row("integral", "pd_steps", "nominal")
    assert "open loop" in coast["not_applicable"] and coast["runaway"]["runs"] == 0
    assert coast["metrics"]["coast_excess"]["median"] is None
    assert "not_applicable" not in steps and steps["runaway"]["runs"] == 1
    assert steps["metrics"]["steady_state_error"]["median"] is not None
    md = res.table()
    assert "| integral | nominal | n/a | n/a | n/a | not applicable (open loop) |" in md
    assert "- integral / coast: not applicable: integral acts on the position error" in md
    json.loads(res.to_json())


def test_a_misspelt_option_of_a_registered_compensator_is_a_value_error():
    with pytest.raises(ValueError, match="options of 'dob'.*bandwith"):
        compare(compensators=["dob"], experiments=["pd_steps"], plants=["nominal"], seeds=1,
                bench="literal", options={"dob": {"bandwith": 5.0}})


def test_the_table_says_when_the_bench_sensing_is_not_applied():
    # the claims of a bench run with its sensing; this table does not: on a bench with sensing it
    # says so (a reader of one reproduce folder must not take the two for one sensing)
    for name, sensed in (("literal", False), ("consistent", True)):
        r = compare(compensators=("none",), experiments=("coast",), plants=("nominal",), seeds=1,
                    bench=name)
        assert ("**not applied**" in r.table()) == sensed
        assert r.as_dict()["bench_sensing_applied"] is False


# ------------------------------------------------------------------ the limit cycle, judged on the record
RES = B.actuator.encoder_resolution


def _record(q, tm):
    """A hand-made closed-loop run on the literal bench (PD, reference held at 0): the true position
    ``q`` [rad], its encoder reading (floor to the count) and the motor torque ``tm`` [N*m]."""
    from dataclasses import replace

    from fricctl import controllers as ctl
    from fricctl.simulate import simulate

    ts = B.actuator.sample_time
    base = simulate(B.actuator, ctl.pd_control(D.kp, D.kd, ctl.constant(0.0)), duration=len(q) * ts)
    assert base.t.size == len(q)
    q = np.asarray(q, dtype=float)
    return replace(base, q=q, q_meas=np.floor(q / RES) * RES, torque_motor=np.asarray(tm, dtype=float))


def test_oscillation_on_hand_made_records():
    from fricctl.compare import oscillation
    from fricctl.paper.runaway import STEADY

    t = B.actuator.sample_time * np.arange(4000)  # 8 s; the judged half 4 s
    wave = 100 * RES * np.sin(2 * np.pi * 2.0 * t)  # 100 counts at 2 Hz: 8 periods in the judged half
    held = np.full(t.size, 0.05)
    o = oscillation(_record(wave, 0.05 * np.sign(wave)))
    # closed form: amplitude 100 counts (to the sampling of the peak, 500 samples a period:
    # within 1 - cos(pi/500)), frequency 2 Hz (crossings sampled to one Ts in 4 s)
    assert o.verdict == "limit cycle" and o.duration == pytest.approx(8.0)
    assert o.amplitude == pytest.approx(100 * RES, rel=1e-4) and o.frequency == pytest.approx(2.0, rel=1e-3)
    # the same decaying with a time constant of 4 s: the last two half-cycles swing exp(-3.5/4) =
    # 42 % of the first two's, under STEADY: a ring that dies out is no limit cycle, nor is it none
    o = oscillation(_record(wave * np.exp(-t / 4.0), held))
    assert o.verdict == "not judged" and math.isnan(o.amplitude) and "decays" in o.reason
    assert math.exp(-3.5 / 4.0) < STEADY
    # two periods in the judged half (0.5 Hz over 4 s), of which 1.5 between its first and last
    # crossing (4 crossings, phase 0.3 rad): too few to compare two periods' swing
    o = oscillation(_record(100 * RES * np.sin(2 * np.pi * 0.5 * t + 0.3), held))
    assert o.verdict == "not judged" and "1.5 period(s), under 2" in o.reason
    # the joint at rest: under a held torque none; with a torque that still winds (a ramp of
    # 0.01 N*m/s, an integral against the stuck joint) not judged: a breakaway may come
    rest = np.full(t.size, 5.5 * RES)
    o = oscillation(_record(rest, held))
    assert o.verdict == "none" and o.amplitude == 0.0 and o.frequency == 0.0 and "held torque" in o.reason
    o = oscillation(_record(rest, 0.05 + 0.01 * t))
    assert o.verdict == "not judged" and "winding" in o.reason and "changes by 0.04 N*m" in o.reason
    # a dither across one count boundary (0.3 count peak to peak): under half a count, none
    o = oscillation(_record(5.0 * RES + 0.15 * RES * np.sin(2 * np.pi * 2.0 * t), 0.05 * np.sign(wave)))
    assert o.verdict == "none" and "under half a count" in o.reason
    with pytest.raises(ValueError, match="periods"):
        oscillation(_record(wave, held), periods=0)


def _hunt(plant_params, duration=None):
    """The limit-cycle experiment of the integral contender (the PID of Fig. 14's design) on the
    literal bench's actuator ``plant_params`` (its own friction, no delay, no noise)."""
    from fricctl.compare.plants import Realised

    comp = make_contender("integral", B.model, D, B.actuator.sample_time)
    pl = Realised(params=plant_params, friction=plant_params.friction_model(), delay=0,
                  compensation_scale=1.0, noise_std=0.0)
    return comp, EXPERIMENTS["limit_cycle"].run(B, pl, comp, D, np.random.default_rng(0))


def test_integral_action_hunts_and_the_limit_cycle_experiment_reports_it():
    from fricctl import controllers as ctl
    from fricctl.compare.experiments import LC_DURATION, LC_MAX_DURATION
    from fricctl.simulate import simulate

    p = B.actuator
    comp, o = _hunt(p)
    m = o.metrics
    # with Coulomb and static friction the integral hunts: the run was extended past its first
    # 6 s (where the joint sits still with the integral winding) and the row holds a cycle
    assert LC_DURATION < m["limit_cycle_duration"] <= LC_MAX_DURATION and not o.warnings
    assert m["limit_cycle_amplitude"] > np.rad2deg(100 * RES) and m["limit_cycle_frequency"] > 0
    # an independent reading of the period: the first peak of the autocorrelation of q over the
    # judged half (one sample of resolution); the crossings' frequency within 2 %
    run = simulate(p, ctl.pd_control(D.kp, D.kd, ctl.step(float(np.deg2rad(30.0)))), comp,
                   duration=m["limit_cycle_duration"])
    x = run.q[run.t.size // 2:] - run.q[run.t.size // 2:].mean()
    ac = np.correlate(x, x, "full")[x.size - 1:]
    first_neg = int(np.argmax(ac < 0))
    lag = first_neg + int(np.argmax(ac[first_neg:x.size // 2]))
    assert 1.0 / (lag * p.sample_time) == pytest.approx(m["limit_cycle_frequency"], rel=0.02)
    # the hand calculation of a hunt: each half-period the integral carries the torque across the
    # friction band 2 Fs at the rate Ki*A, so the period is about 4 Fs/(Ki A); within 15 % (the
    # error while stuck is not quite the amplitude A, nor is the band swept from end to end)
    a = np.deg2rad(m["limit_cycle_amplitude"])
    assert 1.0 / m["limit_cycle_frequency"] == pytest.approx(4 * p.static / (comp.ki * a), rel=0.15)


def test_without_dry_friction_the_integral_has_no_limit_cycle():
    # viscous friction only: the PID is linear and its loop stable (design_ki checks the poles);
    # what is left is the encoder's one-count dither around the target, under half a count
    comp, o = _hunt(B.actuator.replace(coulomb=0.0, static=0.0))
    assert o.metrics["limit_cycle_frequency"] == 0.0 and not o.warnings
    assert o.metrics["limit_cycle_amplitude"] < np.rad2deg(0.5 * RES)


def test_a_limit_cycle_the_run_cannot_judge_is_not_reported_as_none(monkeypatch):
    # the integral's hunt takes ~25 s a period: with the runs capped at 12 s the row must say it
    # could not judge (no amplitude, a warning), not that there is no limit cycle
    import fricctl.compare.experiments as experiments

    monkeypatch.setattr(experiments, "LC_MAX_DURATION", 2 * experiments.LC_DURATION)
    r = compare(compensators=("none", "integral"), experiments=("limit_cycle",), plants=("nominal",), seeds=1)
    row = r.row("integral", "limit_cycle", "nominal")
    assert row["metrics"]["limit_cycle_amplitude"]["median"] is None
    assert row["metrics"]["limit_cycle_duration"]["median"] == 12.0
    assert any(w.startswith("not judged: the joint") for w in row["warnings"])
    assert "not judged: the joint" in r.table()
    none = r.row("none", "limit_cycle", "nominal")  # at rest under a held torque after 6 s: judged
    assert none["metrics"]["limit_cycle_amplitude"]["median"] == 0.0 and not none["warnings"]
    assert none["metrics"]["limit_cycle_duration"]["median"] == 6.0


def test_a_check_too_short_for_its_period_says_so_in_the_row(monkeypatch):
    # the plumbing: a runaway check whose record is too short for part of its criterion (judged
    # False) reaches the row's warnings, and the run is counted as not judged, not as a pass (the
    # review: a run its record could not judge read "1/1" under the runs that passed)
    from dataclasses import replace
    from types import MappingProxyType

    import fricctl.compare.experiments as experiments
    import fricctl.compare.protocol as protocol
    from fricctl.compare.experiments import Outcome
    from fricctl.paper.runaway import RunawayCheck

    short = RunawayCheck(name="divergence", value=10.0, unit="%", limit=50.0, passed=True, judged=False,
                         reason="no divergence: ...; too short to judge whether it is sustained")

    def run(bench, pl, comp, design, rng):
        return Outcome(metrics={m: 0.0 for m in EXPERIMENTS["pd_steps"].metrics}, checks=(short,))

    table = MappingProxyType({**EXPERIMENTS, "pd_steps": replace(EXPERIMENTS["pd_steps"], run=run)})
    monkeypatch.setattr(experiments, "EXPERIMENTS", table)
    monkeypatch.setattr(protocol, "EXPERIMENTS", table)
    row = compare(compensators=("integral",), experiments=("pd_steps",), plants=("nominal",),
                  seeds=1).row("integral", "pd_steps", "nominal")
    assert row["warnings"] == [short.reason]
    assert (row["runaway"]["passed"], row["runaway"]["runs"], row["runaway"]["not_judged"]) == (0, 1, 1)
    assert row["runaway"]["rate"] is None  # no run judged: no rate


def test_a_network_driven_outside_its_training_envelope_is_a_row_warning():
    # auditC item 9 (compare): a net run outside its training box said nothing.  A hand net with
    # a small envelope in the coast experiment (open-loop pulse of 2 Fs, then coasting); the
    # reference: the same deterministic run simulated here and its inputs (Tm_k, omega_hat_k)
    # counted against the box
    from fricctl import controllers as ctl
    from fricctl.compare.plants import Realised
    from fricctl.nn import FrictionNet
    from fricctl.paper import coast as coast_test
    from fricctl.simulate import simulate

    p = B.actuator
    net = FrictionNet(w1=[[0.0, 5.0]], b1=[0.0], w2=[1.0], b2=0.0, input_offset=[0, 0],
                      input_scale=[1, 1], output_offset=0.0, output_scale=0.02,
                      envelope_low=[-0.5, -0.2], envelope_high=[0.5, 0.2])
    pl = Realised(params=p, friction=p.friction_model(), delay=0, compensation_scale=1.0,
                  noise_std=0.0)
    counts = []
    for comp in (NNCompensator(net), NNCompensator(net.replace(envelope_low=[-1e3, -1e3],
                                                               envelope_high=[1e3, 1e3]))):
        o = EXPERIMENTS["coast"].run(B, pl, comp, D, np.random.default_rng(0))
        amp = coast_test.PULSE_FACTOR * p.static
        r = simulate(p, ctl.open_loop(ctl.sequence([amp, 0.0], [coast_test.PULSE_DURATION,
                                                                 coast_test.COAST_DURATION])),
                     comp, duration=coast_test.PULSE_DURATION + coast_test.COAST_DURATION)
        n = int(np.count_nonzero(comp.estimator.outside_envelope(r.torque_motor, r.omega_hat)))
        said = [w for w in o.warnings if "outside its training envelope" in w]
        if n:
            assert len(said) == 1 and f"for {n * p.sample_time:.3g} s" in said[0]
        else:
            assert said == []
        counts.append(n)
    assert counts[0] > 0 and counts[1] == 0      # the small box is left, the wide one is not


def test_warnings_alike_over_seeds_are_one_line():
    # a network outside its envelope for a few samples in every seed made 43 lines of
    # comparison.md on `make reproduce` (review R12): alike warnings (the same sentence, other
    # numbers) are one line naming the seeds, each number as its range over them (the worst
    # seed is not hidden behind the first: review R13); others stay one per seed; a seed's two
    # alike warnings are never merged into one; a digit inside a name is not a number
    from fricctl.compare.protocol import _by_seed

    said = [(0, "outside for 0.004 s (0.0167 % of the samples): |Tm| 1.417 N*m, 1.05x"),
            (1, "outside for 9.6 s (40 % of the samples): |Tm| 1.417 N*m, 2.5x"),
            (3, "not judged: the joint never moved"),
            (4, "outside for 2e-03 s (1 % of the samples): offset -3.2 N*m, 1.1x"),
            (1, "outside for 0.5 s (2 % of the samples): |Tm| 1.4 N*m, 1.2x"),
            (5, "L1 norm above"), (6, "L2 norm above")]
    assert _by_seed(said, 10) == [
        "seeds 0, 1 (2 of 10): outside for 0.004 to 9.6 s (0.0167 to 40 % of the samples): "
        "|Tm| 1.417 N*m, 1.05 to 2.5x",
        "seed 3: not judged: the joint never moved",
        "seed 4: outside for 2e-03 s (1 % of the samples): offset -3.2 N*m, 1.1x",
        "seed 1: outside for 0.5 s (2 % of the samples): |Tm| 1.4 N*m, 1.2x",
        "seed 5: L1 norm above", "seed 6: L2 norm above"]
