"""The certified trainer and the two pipelines (paper, fricctl)."""

import numpy as np
import pytest

from fricctl.datasets import FrictionPatterns
from fricctl.nn import smooth_friction_patterns
from fricctl.nn.pipelines import PIPELINES, pipeline, viscous_fit
from fricctl.nn.train import TRAINERS, Scaling
from fricctl.nn.train.certified import certify


def _patterns(rng, quantum=0.0157):
    # a smooth law sampled on the loop's velocity lattice (0 or k counts per sample), stuck
    # patterns Tat = Tm up to Fs = 0.18
    pats = smooth_friction_patterns(rng, n_sliding=600, n_stuck=300)
    om = np.round(pats.omega / quantum) * quantum
    return pats.tm, om, pats.friction - 0.0169 * pats.omega + 0.0169 * om, om == 0


def test_certified_trainer_meets_its_band_on_a_dense_grid():
    rng = np.random.default_rng(0)
    tm, om, f, rest = _patterns(rng)
    y = f - 0.0169 * om
    sc = Scaling.centred(tm, om, y, torque_scale=0.18, velocity_scale=0.0157)
    res = TRAINERS["certified"].train(tm, om, y, rng=rng, scaling=sc, sliding_velocity=0.0157,
                                      rest_torque=0.18, gain_band=(0.95, 0.98))
    net = res.net
    # independent check of the certificate: central finite differences of the net's output
    # (not its analytic torque_gain) on 4001 torques at rest; 1e-6 covers the differencing error
    tmg = np.linspace(-0.18, 0.18, 4001)
    h = 1e-6
    g = (net(tmg + h, 0 * tmg) - net(tmg - h, 0 * tmg)) / (2 * h)
    assert 0.95 - 1e-6 <= g.min() and g.max() <= 0.98 + 1e-6
    k = np.arange(1, 200) * 0.0157
    tt, ww = np.meshgrid(np.linspace(-tm.max(), tm.max(), 101), np.concatenate([-k, k]))
    gs = (net(tt + h, ww) - net(tt - h, ww)) / (2 * h)
    assert np.abs(gs).max() <= 0.3 + 1e-6          # bounded feedback of Tm while sliding
    assert abs(float(net(0.0, 0.0))) < 1e-9          # no torque at rest without load
    cert = net.metadata["certificate"]
    assert cert["passed"] and cert["gain_min"] == pytest.approx(g.min(), abs=1e-5)


def test_certified_trainer_refuses_a_band_at_or_above_one():
    rng = np.random.default_rng(1)
    tm, om, f, _ = _patterns(rng)
    sc = Scaling.centred(tm, om, f, torque_scale=0.18, velocity_scale=0.0157)
    with pytest.raises(ValueError, match="lo <= hi < 1"):
        TRAINERS["certified"].train(tm, om, f, rng=rng, scaling=sc, sliding_velocity=0.0157,
                                    gain_band=(0.97, 1.0))
    with pytest.raises(ValueError, match="sliding_velocity"):
        TRAINERS["certified"].train(tm, om, f, rng=rng, scaling=sc)


def test_certify_fails_a_net_with_gain_above_one():
    rng = np.random.default_rng(2)
    tm, om, f, rest = _patterns(rng)
    # the paper's recipe on the same patterns: least squares, range scaling (no band)
    net = TRAINERS["casadi"].train(tm, om, 1.3 * f, rng=rng).net
    cert = certify(net, gain_band=(0.95, 0.98), sliding_slope=0.3, rest_torque=0.18,
                   sliding_velocity=0.0157)
    assert not cert.passed and cert.gain_max > 0.98


def test_viscous_fit_recovers_the_line():
    w = np.linspace(-3, 3, 61)
    f = 0.02 * w + 0.1 * np.sign(w)
    vf = viscous_fit(w, f)
    assert vf.viscous == pytest.approx(0.02, rel=1e-12) and vf.coulomb == pytest.approx(0.1, rel=1e-12)
    with pytest.raises(ValueError, match="both directions"):
        viscous_fit(np.abs(w) + 1, f)


@pytest.mark.parametrize("name", sorted(PIPELINES))
def test_pipelines_on_the_fast_bench(name):
    from fricctl.paper import train_paper_network

    net = train_paper_network(bench="literal", fast=True, seed=0, pipeline=name)
    assert net.pipeline == name and net.net.metadata["pipeline"] == name
    if name == "fricctl":
        c = net.trained.certificate
        assert c.passed and 0.98 <= c.gain_min <= c.gain_max <= 0.99
        # the viscous term taken out is the bench's b = 0.0169 (paper) within 10 %: the patterns
        # are sliding friction measured through the encoder and the estimator
        assert net.trained.viscous_removed == pytest.approx(0.0169, rel=0.1)
        # breakaway transients (omega_hat = 0 with the encoder moving) were not trained on
        assert net.net.metadata["dropped_breakaway_transients"] > 0
    else:
        assert net.trained.viscous_removed == 0.0 and net.trained.certificate is None
    with pytest.raises(ValueError, match="pipeline"):
        pipeline("literal")


def test_paper_pipeline_trains_what_train_network_trains_from_the_same_seed():
    # Chapter 4 (Exercise 2) takes the pipeline's own net for "LM as the pipeline trains it" on
    # the pipeline's seed instead of training it again: the same subset draw and the same starts
    # from one generator, so the same weights and loss history, bit for bit (the cache's JSON
    # round trip of the pipeline's net included)
    from fricctl.bench.experiments import train_network
    from fricctl.paper import train_paper_network

    run = train_paper_network(bench="literal", fast=True, seed=0, pipeline="paper")
    assert len(run.train) > 4000  # the subset draw is part of what must agree
    again = train_network(run.train, rng=np.random.default_rng(0))
    assert np.array_equal(again.history.loss, run.trained.history.loss)
    for name in ("w1", "b1", "w2", "b2", "input_offset", "input_scale", "output_offset",
                 "output_scale"):
        assert np.array_equal(getattr(again.net, name), getattr(run.net, name)), name


def test_pipeline_input_is_checked():
    with pytest.raises(ValueError, match="at_rest"):
        FrictionPatterns(tm=[0.0, 1.0], omega=[0.0, 1.0], friction=[0.0, 1.0], at_rest=[1, 0],
                         velocity_quantum=0.01)
    with pytest.raises(ValueError, match="velocity_quantum"):
        FrictionPatterns(tm=[0.0, 1.0], omega=[0.0, 1.0], friction=[0.0, 1.0],
                         at_rest=np.array([True, False]), velocity_quantum=0.0)
    # the fricctl pipeline scales the velocity by the quantum: patterns without it are refused
    tm, om, f, rest = _patterns(np.random.default_rng(5))
    with pytest.raises(ValueError, match="velocity_quantum"):
        pipeline("fricctl").train(FrictionPatterns(tm=tm, omega=om, friction=f, at_rest=rest),
                                  rng=np.random.default_rng(0))


def test_cache_reads_back_the_same_network_and_retrains_on_a_new_key(tmp_path, monkeypatch):
    from fricctl.nn.cache import cached_pipeline_net
    from fricctl.nn.pipelines import PipelineNet

    monkeypatch.setenv("FRICCTL_CACHE", str(tmp_path))
    rng = np.random.default_rng(3)
    tm, om, f, rest = _patterns(rng)
    calls = []

    def make():
        calls.append(1)
        return pipeline("fricctl").train(FrictionPatterns(tm=tm, omega=om, friction=f, at_rest=rest,
                                                          velocity_quantum=0.0157),
                                         rng=np.random.default_rng(0), max_patterns=600)

    a = cached_pipeline_net({"k": 1}, make)
    b = cached_pipeline_net({"k": 1}, make)
    assert len(calls) == 1                                   # the second came from the file
    assert isinstance(b, PipelineNet) and b.net.to_json() == a.net.to_json()
    assert b.certificate == a.certificate and np.array_equal(b.used, a.used)
    np.testing.assert_array_equal(b.history.loss, a.history.loss)
    cached_pipeline_net({"k": 2}, make)                      # another configuration trains
    assert len(calls) == 2
    for f_ in (tmp_path / "nets").glob("*.json"):            # a damaged entry is retrained
        f_.write_text("{not json")
    cached_pipeline_net({"k": 1}, make)
    assert len(calls) == 3
    monkeypatch.setenv("FRICCTL_CACHE", "off")               # switched off: always trains
    cached_pipeline_net({"k": 1}, make)
    assert len(calls) == 4


def test_cache_lock_released_when_a_trainer_fails_and_on_a_file_system_without_locks(tmp_path, monkeypatch):
    """A trainer that raises leaves no lock held (the next caller trains); a file system whose
    ``flock`` fails (some NFS mounts) trains without a lock instead of failing."""
    fcntl = pytest.importorskip("fcntl", reason="the lock is flock's (POSIX)")
    from fricctl.nn.cache import cached_pipeline_net

    monkeypatch.setenv("FRICCTL_CACHE", str(tmp_path))
    tm, om, f, rest = _patterns(np.random.default_rng(3))

    def net():
        return pipeline("fricctl").train(FrictionPatterns(tm=tm, omega=om, friction=f, at_rest=rest,
                                                          velocity_quantum=0.0157),
                                         rng=np.random.default_rng(0), max_patterns=600)

    def fail():
        raise RuntimeError("the trainer failed")

    with pytest.raises(RuntimeError, match="the trainer failed"):
        cached_pipeline_net({"k": 2}, fail)
    lock = next((tmp_path / "nets").glob("*.lock"))
    with open(lock, "a") as fh:  # free: a held flock would make this non-blocking attempt fail
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        fcntl.flock(fh, fcntl.LOCK_UN)
    assert cached_pipeline_net({"k": 2}, net).net is not None  # the next caller trains

    def no_locks(fd, op):
        raise OSError(37, "No locks available")

    monkeypatch.setattr(fcntl, "flock", no_locks)
    calls = []
    got = cached_pipeline_net({"k": 3}, lambda: calls.append(1) or net())
    assert calls == [1] and got.net is not None


def test_cache_makes_a_second_trainer_of_the_same_network_wait_and_read_it(tmp_path, monkeypatch):
    """Two trainers of one configuration at once (the book runs ``fricctl reproduce`` and the
    chapters side by side): the second waits for the first's network instead of training it
    again.  Two threads, each with its own open lock file, conflict under ``flock`` as two
    processes do."""
    import threading

    fcntl = pytest.importorskip("fcntl", reason="the lock is flock's (POSIX)")
    from fricctl.nn.cache import cached_pipeline_net

    monkeypatch.setenv("FRICCTL_CACHE", str(tmp_path))
    tm, om, f, rest = _patterns(np.random.default_rng(3))
    training, waiting, release = threading.Event(), threading.Event(), threading.Event()
    calls = []
    flock = fcntl.flock

    def noting_flock(fd, op):
        if threading.current_thread().name == "second":
            waiting.set()  # about to block on the first one's lock
        return flock(fd, op)

    monkeypatch.setattr(fcntl, "flock", noting_flock)

    def make():
        calls.append(threading.current_thread().name)
        training.set()
        if threading.current_thread().name == "second":
            waiting.set()  # nothing made it wait: it trains too (and the test fails)
        release.wait()  # the second caller asks while this one trains
        return pipeline("fricctl").train(FrictionPatterns(tm=tm, omega=om, friction=f, at_rest=rest,
                                                          velocity_quantum=0.0157),
                                         rng=np.random.default_rng(0), max_patterns=600)

    got = {}
    first = threading.Thread(target=lambda: got.update(first=cached_pipeline_net({"k": 1}, make)),
                             name="first")
    second = threading.Thread(target=lambda: got.update(second=cached_pipeline_net({"k": 1}, make)),
                              name="second")
    first.start()
    training.wait()
    second.start()
    waiting.wait()
    release.set()
    first.join()
    second.join()
    assert calls == ["first"]  # without the lock the second trains too: ["first", "second"]
    assert got["second"].net.to_json() == got["first"].net.to_json()
