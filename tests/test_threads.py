"""Tests of fricctl._threads: one BLAS thread around the trainers' loops, restored after."""

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

from fricctl._threads import one_blas_thread
from fricctl.nn import smooth_friction_patterns
from fricctl.nn.train import TRAINERS, LoopResult, Trainer


def blas_threads():
    """Threads of each loaded BLAS library, by its file (NumPy's, SciPy's, ...)."""
    return {lib["filepath"]: lib["num_threads"] for lib in threadpool_info()
            if lib["user_api"] == "blas"}


@pytest.fixture
def two_blas_threads():
    """Every BLAS at two threads, whatever this machine's default (one core would make
    "limited to one" hold without the limit)."""
    np.ones((2, 2)) @ np.ones((2, 2))  # NumPy's BLAS is loaded
    with threadpool_limits(limits=2, user_api="blas"):
        before = blas_threads()
        assert before and set(before.values()) == {2}, before
        yield before


def test_one_blas_thread_limits_every_blas_and_restores_it(two_blas_threads):
    with one_blas_thread():
        inside = blas_threads()
    assert inside.keys() == two_blas_threads.keys()
    assert set(inside.values()) == {1}
    assert blas_threads() == two_blas_threads


def test_one_blas_thread_restores_after_an_exception(two_blas_threads):
    with pytest.raises(RuntimeError, match="inside"):
        with one_blas_thread():
            raise RuntimeError("inside")
    assert blas_threads() == two_blas_threads


def test_nested_blocks_restore_on_the_outer_exit(two_blas_threads):
    with one_blas_thread():
        with one_blas_thread():
            pass
        assert set(blas_threads().values()) == {1}
    assert blas_threads() == two_blas_threads


def test_a_trainers_loop_runs_with_one_blas_thread(two_blas_threads):
    # the seam every registered trainer goes through (Trainer.train) sets the limit: a
    # loop that records the BLAS threads it runs with stands in for a trainer's
    seen = []

    def recording_loop(problem):
        seen.append(blas_threads())
        return LoopResult(theta=problem.initial_theta(), loss=np.array([1.0]),
                          elapsed=np.array([0.0]))

    probe = Trainer(name="probe", description="records its BLAS threads", step="iteration",
                    loop=recording_loop)
    p = smooth_friction_patterns(np.random.default_rng(0), n_sliding=50, n_stuck=0)
    probe.train(p.tm, p.omega, p.friction, hidden=2, rng=np.random.default_rng(1))
    assert len(seen) == 1 and set(seen[0].values()) == {1}, seen
    assert blas_threads() == two_blas_threads


def test_a_real_training_leaves_blas_as_it_found_it(two_blas_threads):
    p = smooth_friction_patterns(np.random.default_rng(0), n_sliding=200, n_stuck=0)
    TRAINERS["casadi"].train(p.tm, p.omega, p.friction, hidden=2, rng=np.random.default_rng(1),
                             restarts=1, max_iterations=5)
    assert blas_threads() == two_blas_threads
