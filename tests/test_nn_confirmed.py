"""The friction network on the direction-confirmed velocity (:mod:`fricctl.compensators.nn_confirmed`):
its rule sample by sample, what it changes in the loop (encoder flicker at rest) and what it does
not (motion), its refusals, and the fricctl pipeline that uses it."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from fricctl import controllers as ctl
from fricctl.compensators import ConfirmedNNCompensator, NNCompensator, make
from fricctl.compensators import nn_confirmed
from fricctl.compensators.nn_confirmed import network_compensator
from fricctl.netlayout import forward_packed
from fricctl.nn import FrictionNet
from fricctl.params import paper_actuator
from fricctl.simulate import simulate

P = paper_actuator()
CC = shutil.which("gcc") or shutil.which("cc")
COUNT = P.encoder_resolution
FC, G = 0.05, 0.5  # Fc/(1 - g) = 0.1 N*m < Fs: flicker alone cannot break the joint loose


def _friction_like_net() -> FrictionNet:
    """``Fc*tanh(omega/w0) + g*T0*tanh(Tm/T0)``: the rest branch ``g*Tm`` and the sliding branch
    ``+-Fc`` from one count per sample on, as a trained net has them."""
    w0, t0 = 0.3 * COUNT / P.sample_time, 10.0
    return FrictionNet(w1=[[0.0, 1.0 / w0], [1.0 / t0, 0.0]], b1=[0.0, 0.0], w2=[FC, G * t0], b2=0.0,
                       input_offset=[0.0, 0.0], input_scale=[1.0, 1.0], output_offset=0.0,
                       output_scale=1.0, envelope_low=[-1.0, -1.0], envelope_high=[1.0, 1.0])


NET = _friction_like_net()


def test_rule_reads_a_count_against_the_last_difference_as_rest():
    comp = ConfirmedNNCompensator(NET)
    cc = comp.compiled()
    p, x = cc.params, cc.state.copy()
    ts, tm = P.sample_time, 0.05
    counts = [0, 1, -1, 1, 1, 2, -1, -1, 0, -3, 1, 0, 0, 1, 0, -1, 3]
    # what the network must be fed: a difference against the last nonzero one (or before any),
    # of any size, is rest; a difference the way of the last nonzero one -- zeros between, slow
    # motion, included -- is motion
    fed = [0, 0, 0, 0, 1, 2, 0, -1, 0, -3, 0, 0, 0, 1, 0, 0, 0]
    for c, f in zip(counts, fed):
        got = nn_confirmed.step(p, x, tm, c * COUNT / ts, ts)
        assert got == forward_packed(p, tm, f * COUNT / ts)
        assert (got != forward_packed(p, tm, c * COUNT / ts)) == (f != c)


def test_flicker_at_rest_chatters_on_the_backward_difference_and_not_when_confirmed():
    # the joint at rest on an encoder edge, no control torque, the edge flickering with the
    # consistent bench's jitter (0.25 count): the backward difference switches the network
    # between its branches; the confirmed velocity almost never does (a flicker that spans two
    # counts, or two flickers in one direction, still passes: jitter of many counts is motion
    # to this rule)
    c = ctl.open_loop(ctl.constant(0.0))
    runs = {k: simulate(P, c, comp, duration=2.0, position_noise_std=0.25 * COUNT,
                        rng=np.random.default_rng(3))
            for k, comp in (("bd", NNCompensator(NET)),
                            ("confirmed", ConfirmedNNCompensator(NET)))}
    assert np.count_nonzero(np.diff(runs["bd"].q_meas)) > 200  # the encoder does flicker
    assert np.abs(runs["bd"].q).max() == 0.0  # and the joint does not move
    changes = {k: int(np.count_nonzero(np.diff(np.sign(r.torque_motor[r.torque_motor != 0]))))
               for k, r in runs.items()}
    assert changes["bd"] > 100 and changes["confirmed"] <= changes["bd"] / 20, changes


def test_motion_is_compensated_the_same_once_confirmed():
    # a sinusoid well above breakaway, noise-free: the network sees rest only on the first count
    # of the run and on the first count after each reversal (its direction not yet confirmed),
    # a few samples among hundreds that move; the motion stays that of the backward difference
    c = ctl.open_loop(ctl.sinusoid(3.0 * P.static, 1.0))
    a = simulate(P, c, NNCompensator(NET), duration=2.0)
    b = simulate(P, c, ConfirmedNNCompensator(NET), duration=2.0)
    dy = np.diff(b.q_meas)
    moves = np.flatnonzero(dy)
    flips = np.count_nonzero(np.sign(dy[moves[1:]]) != np.sign(dy[moves[:-1]]))
    assert 2 <= flips <= 8  # the sinusoid's reversals (4 in 2 s), with a few stops between
    rest = np.isclose(b.friction_est[moves + 1], [NET(tm, 0.0) for tm in b.torque_motor[moves + 1]])
    assert rest.sum() == flips + 1 and rest.sum() < 0.02 * moves.size
    assert np.abs(a.q - b.q).max() < 0.05 * np.abs(a.q).max()


@pytest.mark.parametrize("kw, match", [({"scale": -1.0}, "scale"), ({"scale": float("nan")}, "scale"),
                                       ({"clip": 1}, "clip")])
def test_bad_parameters_are_refused(kw, match):
    with pytest.raises(ValueError, match=match):
        ConfirmedNNCompensator(NET, **kw)
    with pytest.raises(ValueError, match="FrictionNet"):
        ConfirmedNNCompensator(lambda tm, w: 0.0 * tm)


def test_make_builds_it_from_a_net_and_refuses_it_without():
    comp = make("nn_confirmed", P, net=NET, scale=0.95)
    assert comp.scale == 0.95 and comp.stateful and comp.estimator is NET
    for bad in ({"net": "net.json"}, {}):
        with pytest.raises(ValueError, match="nn_confirmed: net must be a trained"):
            make("nn_confirmed", P, **bad)
    with pytest.raises(ValueError, match="velocity"):
        network_compensator(NET, "filtered")
    assert type(network_compensator(NET, "backward-difference")) is NNCompensator


def test_the_fricctl_pipeline_feeds_the_confirmed_velocity_and_the_paper_s_the_backward_difference():
    from fricctl.paper.network import pipeline_velocity

    assert pipeline_velocity("fricctl") == "confirmed"
    assert pipeline_velocity("paper") == "backward-difference"
    with pytest.raises(ValueError, match="pipeline"):
        pipeline_velocity("mine")


@pytest.mark.skipif(CC is None, reason="no C compiler (cc or gcc) on PATH")
def test_c_confirmed_velocity_matches_the_compiled_step(tmp_path):
    import subprocess

    from fricctl.nn.c_export import c_header, c_source

    (tmp_path / "net.c").write_text(c_source(NET, name="net"))
    (tmp_path / "net.h").write_text(c_header(NET, name="net"))
    counts = [0, 1, -1, 1, 1, 2, -1, -1, 0, -3, 1, 1, -2, 0, -1, 1, 0, 1]
    ts, tm = P.sample_time, 0.05
    main = tmp_path / "main.c"
    main.write_text('#include <stdio.h>\n#include "net.h"\nint main(void) {\n    double st = 0.0;\n'
                    f"    const double c[] = {{{', '.join(str(k) for k in counts)}}};\n"
                    f"    for (int i = 0; i < {len(counts)}; ++i) {{\n"
                    f"        double w = net_confirmed_velocity(&st, c[i] * {COUNT!r} / {ts!r}, {ts!r});\n"
                    f'        printf("%.17g\\n", net_compensation({tm!r}, w, 1.0, 0));\n    }}\n    return 0;\n}}\n')
    exe = tmp_path / "main"
    subprocess.run([CC, "-std=c99", "-Wall", "-Werror", "-O2", str(main), str(tmp_path / "net.c"), "-o",
                    str(exe), "-lm"], check=True, capture_output=True)
    got = [float(x) for x in subprocess.run([str(exe)], check=True, capture_output=True,
                                            text=True).stdout.split()]
    cc = ConfirmedNNCompensator(NET).compiled()
    x = cc.state.copy()
    want = [nn_confirmed.step(cc.params, x, tm, k * COUNT / ts, ts) for k in counts]
    np.testing.assert_allclose(got, want, rtol=1e-14, atol=1e-16)


def test_cli_runs_it_with_a_net_and_refuses_it_without(tmp_path, capsys):
    import json

    from fricctl.cli import main
    from fricctl.nn import save_net

    path = save_net(NET, tmp_path / "net.json")
    common = ["simulate", "--controller", "pd", "--kp", "2", "--kd", "0.05", "--reference", "step:0.2",
              "--duration", "1", "--json"]
    assert main([*common, "--compensation", "nn,nn_confirmed", "--net", str(path)]) == 0
    runs = json.loads(capsys.readouterr().out)["runs"]
    assert [r["compensator"] for r in runs] == ["NN", "NN (confirmed velocity)"]
    assert main([*common, "--compensation", "nn_confirmed"]) == 2
    err = capsys.readouterr().err
    assert "--compensation nn_confirmed needs --net" in err and err.count("\n") == 1


def test_cli_tells_when_a_net_runs_on_another_velocity_than_its_pipeline_s(tmp_path, capsys):
    import json
    from dataclasses import replace

    from fricctl.cli import main
    from fricctl.nn import save_net

    common = ["simulate", "--controller", "pd", "--kp", "2", "--kd", "0.05", "--reference", "step:0.2",
              "--duration", "1", "--json"]
    for pipeline, right, wrong in (("fricctl", "nn_confirmed", "nn"), ("paper", "nn", "nn_confirmed")):
        path = save_net(replace(NET, metadata={"pipeline": pipeline}), tmp_path / f"{pipeline}.json")
        assert main([*common, "--compensation", f"{right},{wrong}", "--net", str(path)]) == 0
        runs = json.loads(capsys.readouterr().out)["runs"]
        notes = [[w for w in r["warnings"] if "pipeline" in w] for r in runs]
        assert notes[0] == [] and len(notes[1]) == 1
        assert f"trained by the {pipeline} pipeline" in notes[1][0] and f"--compensation {right} runs" in notes[1][0]
    # a net that does not say its pipeline gets no note
    path = save_net(NET, tmp_path / "plain.json")
    assert main([*common, "--compensation", "nn", "--net", str(path)]) == 0
    assert not [w for w in json.loads(capsys.readouterr().out)["warnings"] if "pipeline" in w]
