"""The virtual bench: the paper's experiments and records with hidden effects.

* :mod:`fricctl.bench.experiments` -- the paper's training experiments, friction
  patterns, network training and the dead zone;
* :mod:`fricctl.bench.hidden_effects` -- seeded records of a randomly drawn actuator
  with an effect the diagnosis must find.

Both simulate with :mod:`fricctl.simulate`; nothing here is imported by the physics
or the identification layers.
"""
