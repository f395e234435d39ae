"""The virtual bench: the paper's experiments and records with hidden effects.

* :mod:`fricctl.bench.experiments` -- the paper's training experiments, friction
  patterns, network training and the dead zone;
* :mod:`fricctl.bench.hidden_effects` -- seeded records of a randomly drawn actuator
  with an effect the diagnosis must find;
* :mod:`fricctl.bench.end_stops` -- the bench's loop with ideal rigid end stops (records in
  which the joint hits a limit, ``hidden_effect_record(end_stops=...)``).

Both simulate with :mod:`fricctl.simulate`; nothing here is imported by the physics
or the identification layers.
"""
