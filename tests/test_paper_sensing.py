"""The sensing of a bench (issue 22, item 2): which claims each item changes, and where.

A bench's sensing (:class:`fricctl.paper.benches.Sensing`) is data: encoder edge jitter (position
noise before quantisation), current-loop torque noise, the drive's torque ripple (periodic in
position), the velocity estimate.  The references here are the claims' own criteria, the stuck
band's closed form, and the bench without sensing as the control: with its sensing off, a
figure's runs are today's bit for bit.  The Coulomb runs of Fig. 16 do not involve the
network's weights, so their seeds are seeds of the sensing noise (one trained network,
:meth:`~fricctl.paper.PaperNetwork.sensed_on`), each verdict a count over those seeds.
"""

from __future__ import annotations

import numpy as np
import pytest

import fricctl.controllers as ctl
from fricctl import paper
from fricctl.bench.experiments import predicted_dead_zone
from fricctl.compensators import CoulombCompensator
from fricctl.paper import fig16, fig17, train_paper_network
from fricctl.paper.benches import bench
from fricctl.paper.common import AGED_SCALE, COULOMB_AT_FC, COULOMB_AT_FS, designs
from fricctl.simulate import simulate

#: Seeds of the sensing noise each verdict is counted over [-].
SEEDS = range(5)


@pytest.fixture(scope="module")
def nets():
    return {name: train_paper_network(bench=name, fast=True, seed=0, pipeline="fricctl")
            for name in ("literal", "consistent")}


def _pair(net, b) -> tuple[int, int]:
    """(seeds where fig16-coulomb-fs holds, seeds where fig16-coulomb-fc holds) on bench ``b``."""
    fs = fc = 0
    for k in SEEDS:
        r = fig16.run(net.sensed_on(b, k))
        fs += fig16.claim_fig16_coulomb_fs(r, b).passed
        fc += fig16.claim_fig16_coulomb_fc(r, b).passed
    return fs, fc


def test_sensing_off_is_the_noise_free_run_bit_for_bit(nets):
    net = nets["consistent"]
    off = bench("consistent").with_sensing("off", encoder_jitter=0.0, torque_noise=0.0, torque_ripple=0.0)
    r = fig16.run(net.sensed_on(off, 3))
    p, d = off.linked_actuator, designs(off)["fig16-17"]
    level = r.coulomb_level(COULOMB_AT_FS)
    ref = simulate(p, ctl.pd_control(d.kp, d.kd, ctl.step(np.deg2rad(30.0))),
                   CoulombCompensator.symmetric(level / r.scale, scale=r.scale), duration=3.0,
                   friction=p.friction_model().scaled(r.friction_scale))
    np.testing.assert_array_equal(r.runs[COULOMB_AT_FS].q_meas, ref.q_meas)
    np.testing.assert_array_equal(r.runs[COULOMB_AT_FS].torque_motor, ref.torque_motor)
    with pytest.raises(ValueError, match="differs from the network's bench 'consistent' in more than"):
        net.sensed_on(bench("literal"))


@pytest.mark.parametrize("name", ["literal", "consistent"])
def test_encoder_jitter_alone_makes_the_breakaway_level_chatter(nets, name):
    # the paper (Fig. 16): Coulomb compensation at the breakaway level oscillates, at a smaller
    # level the oscillation disappears.  Noise-free, nothing flickers: neither level oscillates
    # (fs fails, fc has nothing to disappear); torque noise alone (0.1 % of Tmax) moves no encoder
    # edge either; the edge jitter alone reproduces the pair in every seed, on both benches
    net, sensing = nets[name], bench("consistent").sensing
    base = bench(name).with_sensing("ripple off", torque_ripple=0.0)
    off = base.with_sensing("off", encoder_jitter=0.0, torque_noise=0.0)
    torque = base.with_sensing("torque noise alone", encoder_jitter=0.0, torque_noise=sensing.torque_noise)
    jitter = base.with_sensing("edge jitter alone", encoder_jitter=sensing.encoder_jitter, torque_noise=0.0)
    assert _pair(net, off) == (0, 0)
    assert _pair(net, torque) == (0, 0)
    assert _pair(net, jitter) == (len(SEEDS), len(SEEDS))


def test_the_consistent_bench_reproduces_the_coulomb_pair(nets):
    b = bench("consistent")
    assert _pair(nets["consistent"], b) == (len(SEEDS), len(SEEDS))


@pytest.mark.slow
@pytest.mark.parametrize("name, low, high", [("consistent", 0.15, 0.5), ("literal", 0.2, 0.4)])
def test_the_coulomb_pair_is_not_a_knife_edge_of_the_jitter(nets, name, low, high):
    # measured (benchmarks/README.md, the bench's torque noise on): the pair holds in every seed
    # from ``low`` to ``high`` counts, and not at 0.05 count on either bench; at half a count on
    # the literal bench the claims' criterion (> 3 counts peak to peak: motion) reads the
    # jitter itself as motion at the smaller level in some seeds
    noise = bench("consistent").sensing.torque_noise
    for sigma in sorted({low, 0.25, 0.3, high}):
        b = bench(name).with_sensing("sensitivity", encoder_jitter=sigma, torque_noise=noise, torque_ripple=0.0)
        assert _pair(nets[name], b) == (len(SEEDS), len(SEEDS)), sigma
    b = bench(name).with_sensing("sensitivity", encoder_jitter=0.05, torque_noise=noise, torque_ripple=0.0)
    assert _pair(nets[name], b)[0] < len(SEEDS)


# -- the drive's torque ripple ----------------------------------------------------------------------
#: Where the ripple's period starts at q = 0 [rad]: four quarters of it.
PHASES = (0.0, 0.5 * np.pi, np.pi, 1.5 * np.pi)


@pytest.fixture(scope="module")
def consistent_nets():
    """Three fast fricctl networks of the consistent bench (a result that depends on the training
    seed is asserted over several)."""
    return [train_paper_network(bench="consistent", fast=True, seed=k, pipeline="fricctl") for k in range(3)]


def _ripple_alone(phase, amplitude=None):
    b = bench("consistent")
    a = b.sensing.torque_ripple if amplitude is None else amplitude
    return b.with_sensing("ripple alone", encoder_jitter=0.0, torque_noise=0.0, torque_ripple=a,
                          torque_ripple_phase=phase)


def _fig17_errors(net, phases, amplitude=None):
    """|e_ss| [rad] of Fig. 17's compensated run with the ripple alone at each phase."""
    return np.array([abs(fig17.run(net.sensed_on(_ripple_alone(ph, amplitude))).steady_state_error[
        f"NN x {AGED_SCALE:g}"]) for ph in phases])


def test_the_ripple_alone_makes_nothing_flicker(nets):
    # the ripple is a torque the joint receives, the same at the same position: at rest it cannot
    # move an encoder edge, so the Coulomb pair stays absent (as noise-free), whatever the phase
    net = nets["consistent"]
    for ph in (0.0, np.pi, "random"):
        assert _pair(net, _ripple_alone(ph)) == (0, 0), ph


def test_the_ripple_decides_where_fig17_stops_through_its_phase(consistent_nets):
    # the stuck band: the network's fixed point Tm* = Kp e/(1 - s g) holds while
    # |Tm* - A sin(.)| <= phi Fs, so the joint stops within the band of phi Fs + A (the closed-form
    # bound, predicted_dead_zone); the ripple widens it by A (1 - s g)/Kp only, but moves *where*
    # the slow approach ends by more than that: at one phase beyond the claim's 0.3 deg, at
    # another inside it -- so a fixed phase would decide fig17-nn, and the bench draws it per run
    b = bench("consistent")
    p, s, a = b.actuator, AGED_SCALE, b.sensing.torque_ripple
    decided = 0
    for net in consistent_nets:
        kp = designs(b)["fig16-17"].kp
        e = _fig17_errors(net, PHASES)
        band = predicted_dead_zone(net.net, s * p.static + a, scale=s).largest / kp
        assert np.all(e <= band + p.encoder_resolution), (np.rad2deg(e), np.rad2deg(band))
        widening = a * (1.0 - s * net.net.gain_at_rest()) / kp
        assert np.ptp(e) > widening
        limit = np.deg2rad(paper.ACCURACY_DEG)
        decided += bool(e.min() < limit < e.max())
    assert decided >= 2  # measured 3 of 3 (fast networks 0-2)


@pytest.mark.slow
def test_the_ripples_effect_grows_with_its_amplitude(consistent_nets):
    # the spread of Fig. 17's stop over the phases, per network, against the ripple's amplitude
    # (0.1-2 % of Tmax): no ripple, no spread (the runs are the same); it grows with A -- the
    # shipped 1 % is not a knife edge of the effect, and a tenth of it already moves the stop
    tmax = bench("consistent").actuator.max_torque
    fractions = (0.0, 0.001, 0.005, 0.01, 0.02)
    for net in consistent_nets:
        spreads = [np.ptp(_fig17_errors(net, PHASES, f * tmax)) for f in fractions]
        assert spreads[0] == 0.0 and spreads[1] > 0.0, spreads
        assert spreads[-1] > spreads[1], np.rad2deg(spreads)


def test_the_literal_bench_runs_are_the_plant_alone_bit_for_bit(nets):
    # the literal bench has no sensing: every figure run is the simulation of its plant as before
    # the sensing existed (no friction argument, no noise) -- its table unchanged, bit for bit
    from fricctl.compensators import NoCompensation
    from fricctl.paper import fig09, fig11

    net = nets["literal"]
    assert bench("literal").sensing.ideal
    p = net.params
    r9 = fig09.run(net)
    c9 = ctl.open_loop(ctl.sinusoid(1.1 * p.static, 0.5))
    ref = simulate(p, c9, net.compensator(), duration=4.0)
    np.testing.assert_array_equal(r9.with_nn.q_meas, ref.q_meas)
    np.testing.assert_array_equal(r9.with_nn.torque_motor, ref.torque_motor)
    r11 = fig11.run(net)
    d = designs(bench("literal"))["fig11-12"]
    ref = simulate(p, ctl.p_control(d.kp, ctl.step(np.deg2rad(25.0))), NoCompensation(), duration=3.0)
    np.testing.assert_array_equal(r11.run.q_meas, ref.q_meas)
    np.testing.assert_array_equal(r11.run.torque_motor, ref.torque_motor)


def test_coulomb_claims_say_what_a_seed_draws():
    # Fig. 16's Coulomb claims say what changes from seed to seed: the sensing noise where the bench
    # has it, the ripple's phase alone where the ripple is its only random item (it listed noise
    # levels of 0 there), nothing on a noise-free bench without ripple
    from fricctl.paper.fig16 import _seeds_note

    full = _seeds_note(bench("consistent"))
    assert "encoder edge jitter 0.25 counts" in full and "phase drawn for each run" in full
    ripple_only = _seeds_note(bench("consistent").with_sensing("a test", encoder_jitter=0.0,
                                                                torque_noise=0.0))
    assert "each seed draws the ripple's phase" in ripple_only and "jitter" not in ripple_only
    assert "seed changes nothing" in _seeds_note(bench("literal"))
