"""Figures of runs, friction laws and the dead zone, inspected under Agg."""
import matplotlib.pyplot as plt
import numpy as np
import pytest

from fricctl import figures
from fricctl.compensators import NNCompensator
from fricctl.controllers import p_control, step
from fricctl.bench.experiments import dead_zone
from fricctl.params import paper_actuator
from fricctl.simulate import simulate

P = paper_actuator()


def test_response_torques_and_stuck():
    res = simulate(P, p_control(1.0, step(0.5)), duration=2.0)
    fig, (a, b) = plt.subplots(2)
    assert figures.plot_response(res, ax=a) is a
    assert [l.get_drawstyle() for l in a.lines][0] == "steps-post"  # the reference is held
    np.testing.assert_allclose(a.lines[1].get_ydata(), np.rad2deg(res.q))
    assert "[deg]" in a.get_ylabel() and "[s]" in a.get_xlabel()
    figures.plot_stuck(res, ax=a)
    assert len(a.patches) == len(res.stuck_intervals())
    # issue 25: the shading drawn after plot_response's legend has its entry in it
    assert "stuck (ω = 0)" in [t.get_text() for t in a.get_legend().get_texts()]
    figures.plot_torques(res, ax=b)
    assert all(l.get_drawstyle() == "steps-post" for l in b.lines)
    assert "[N·m]" in b.get_ylabel()
    with pytest.raises(ValueError, match="unit"):
        figures.plot_response(res, unit="grad")


def test_friction_law_and_dead_zone():
    ax = figures.plot_friction_law(P.friction_model())
    band = ax.lines[2]
    assert tuple(band.get_ydata()) == pytest.approx((-0.18, 0.18))
    assert "[rad/s]" in ax.get_xlabel() and "[N·m]" in ax.get_ylabel()
    dz = [dead_zone(P), dead_zone(P, NNCompensator(lambda tm, w: 0.5 * tm))]
    ax = figures.plot_dead_zone(dz)
    assert len(ax.lines) == 5  # two curves, two dead-zone markers, one threshold
    assert f"{100 * dz[0].fraction:.2f} %" in ax.get_legend().get_texts()[0].get_text()
    assert dz[0].fraction == pytest.approx(0.127, abs=0.002)  # paper: 12.7 % of Tmax


def test_lazy_table_lists_every_submodules_names():
    """The package's name table (imported on first use) is each submodule's ``__all__``, and
    every listed name resolves to that module's object."""
    import importlib

    for module in figures.SUBMODULES:
        mod = importlib.import_module(f"fricctl.figures.{module}")
        assert tuple(mod.__all__) == figures._WHERE[module], module
        for name in mod.__all__:
            assert getattr(figures, name) is getattr(mod, name)
    assert set(figures.__all__) <= set(dir(figures))
    with pytest.raises(AttributeError, match="plot_nothing"):
        figures.plot_nothing
