"""A sine history is followed finely whatever the output times.

Reference: a rigid flat punch (radius a) under an approach history on a standard
linear solid. Its contact area is the face at every positive load, so the
pressure is the elastic one times ``g(t) = int_0^t E(t - s) d delta(s)``
(Lee & Radok's correspondence with a fixed contact set), and the load ratio
``P(t) / P(0) = g(t) / (E(0) delta(0))`` is independent of the grid. For
``delta(s) = m + A sin(w s)`` (a jump to ``m`` at 0) and
``E(t) = e_inf + e_1 exp(-t/tau)``,

    g(t) = E(t) m + e_inf A sin(w t) + e_1 A w Re[(exp(i w t) - exp(-t/tau)) / (1/tau + i w)].

The amplitude keeps the load positive (the ratio stays above 0.13).
"""
import numpy as np
import pytest

import framework as fw
from framework import indenters, loads, materials, schedules

E_INF, E_1, TAU = 1e9, 2e9, 0.2            # Pa, Pa, s
SOLID = materials.StandardLinearSolid(e_inf=E_INF, e_1=E_1, tau=TAU, poisson=0.3)
RADIUS = 1e-3                              # m
MEAN, AMPLITUDE, PERIOD, CYCLES = 1e-6, 0.25e-6, 1.0, 3


def load_ratio(t):
    w = 2 * np.pi / PERIOD
    relaxation = E_INF + E_1 * np.exp(-t / TAU)
    sine = E_INF * AMPLITUDE * np.sin(w * t) \
        + E_1 * AMPLITUDE * w * np.real((np.exp(1j * w * t) - np.exp(-t / TAU)) / (1 / TAU + 1j * w))
    return (relaxation * MEAN + sine) / ((E_INF + E_1) * MEAN)


def punch_run(times, material=SOLID):
    history = loads.Cyclic(mean=MEAN, amplitude=AMPLITUDE, period=PERIOD, cycles=CYCLES)
    return fw.Simulation(grid=fw.Grid(shape=(25, 25), size=(3 * RADIUS, 3 * RADIUS)), material=material,
                         indenter=indenters.FlatPunch(radius=RADIUS),
                         schedule=schedules.Static(approach=history, times=times),
                         options={"time_tolerance": None}).run()    # the sine's own resolution, fixed steps


def test_output_once_per_period_follows_the_sine():
    """Output times at the same phase used to see a constant approach: 20 % off the reference."""
    coarse = punch_run(np.arange(CYCLES + 1.0))
    assert np.abs(coarse.load / coarse.load[0] / load_ratio(coarse.times) - 1).max() < 1e-3
    dense_times = np.linspace(0.0, CYCLES, 64 * CYCLES + 1)
    dense = punch_run(dense_times)
    assert np.abs(dense.load / dense.load[0] / load_ratio(dense_times) - 1).max() < 1e-3
    same = np.searchsorted(dense_times, coarse.times)
    assert np.abs(dense.load[same] / coarse.load - 1).max() < 1e-3


def test_stepping_error_falls_as_the_square_of_the_step(monkeypatch):
    errors = []
    for stations in (16, 32):
        monkeypatch.setattr(loads, "STATIONS_PER_PERIOD", stations)
        result = punch_run([0.0, float(CYCLES)])
        errors.append(abs(result.load[-1] / result.load[0] / load_ratio(CYCLES) - 1))
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.15)


def test_an_elastic_solid_takes_no_extra_steps(monkeypatch):
    """Without memory each output time is its own solve: nothing to resolve in between."""
    import framework.boxed_solve as boxed_solve
    import framework.simulation as simulation
    calls = []
    original = simulation.solve_normal
    for module in (simulation, boxed_solve):   # the first solve, and the warm-started ones on a box
        monkeypatch.setattr(module, "solve_normal", lambda *a, **k: calls.append(1) or original(*a, **k))
    result = punch_run(np.arange(CYCLES + 1.0), material=materials.Elastic(young=E_INF + E_1, poisson=0.3))
    assert len(calls) == CYCLES + 2  # the output times and the left side of the jump at t = 0
    assert np.allclose(result.load / result.load[0], 1.0, rtol=1e-10)
