"""A shared test helper: an open-loop record of a joint under a given feedforward torque."""

import numpy as np

from fricctl.simulate import Schedule, simulate_schedule


def open_loop_run(joint, feedforward, sample_time, noise_seed, noise=0.002):
    """The package's sampled loop with no controller (kp = kd = 0), ``feedforward`` [N*m] per
    sample, a 3.14e-5 rad encoder, torque limit 5 N*m and white process noise of ``noise``
    N*m drawn from ``noise_seed``; the record as a :class:`fricctl.datasets.Run`."""
    n = feedforward.size
    zeros = np.zeros(n)
    start = np.zeros(n, dtype=bool)
    start[0] = True
    sim = simulate_schedule(joint, Schedule(kp=zeros, kd=zeros, reference=zeros,
                                            feedforward=feedforward, segment_start=start),
                            sample_time=sample_time, max_torque=5.0, encoder_resolution=3.14e-5,
                            noise=np.random.default_rng(noise_seed).normal(0, noise, n))
    return sim.to_run()
