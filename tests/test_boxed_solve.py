"""Warm-started contact solves iterate on a box around the cells the contact can reach (framework.boxed_solve)."""
import numpy as np
import pytest

import framework as fw
from framework import boxed_solve, indenters, materials, schedules

SOLID = materials.StandardLinearSolid(e_inf=1e7, e_1=9e7, tau=1.0, poisson=0.5)


def run(schedule, boxed=True, shape=(128, 64)):
    grid = fw.Grid(shape=shape, size=(12e-3, 6e-3))
    sim = fw.Simulation(grid=grid, material=SOLID, indenter=indenters.Sphere(radius=10e-3), schedule=schedule,
                        options={"time_tolerance": None})    # the box's solves at the given steps, none between
    if boxed:
        return sim.run()
    margin = boxed_solve.BOX_MARGIN
    boxed_solve.BOX_MARGIN = 1e9                  # a box as large as the grid: the whole grid, as before
    try:
        return sim.run()
    finally:
        boxed_solve.BOX_MARGIN = margin


def test_a_transient_roll_on_its_box_equals_the_whole_grid():
    """A sphere rolling from rest over 30 cells: the same pressure, approach and friction as the solves on the
    whole grid, to the solver's tolerance (1e-8)."""
    schedule = schedules.Rolling(load=0.2, velocity=(5e-5, 0.0), distance=30 * 12e-3 / 128)
    boxed, whole = run(schedule), run(schedule, boxed=False)
    for a, b in zip(boxed.records, whole.records):
        assert np.abs(a.pressure - b.pressure).max() <= 1e-7 * b.pressure.max()
        assert np.abs(a.displacement - b.displacement).max() <= 1e-7 * np.abs(b.displacement).max()
        assert a.approach == pytest.approx(b.approach, rel=1e-8)
    assert np.allclose(boxed.friction_coefficient, whole.friction_coefficient, rtol=1e-6, atol=0.0)


def test_a_contact_that_leaves_its_box_is_solved_on_the_whole_grid(monkeypatch):
    """A load 20,000 times the last step's: the contact outgrows the box around the last one, a cell
    outside it interpenetrates, and the step is solved again on the whole grid, started from the box's pressure."""
    shapes = []
    solve = boxed_solve.solve_normal

    def counted(apply, base, **kwargs):
        shapes.append(np.shape(base))
        return solve(apply, base, **kwargs)
    monkeypatch.setattr(boxed_solve, "solve_normal", counted)
    schedule = schedules.Static(load=[1e-4, 2.0], times=[1.0, 2.0])
    boxed = run(schedule, shape=(512, 256))
    monkeypatch.undo()
    whole = run(schedule, boxed=False, shape=(512, 256))
    assert shapes[-2] == (32, 32) and shapes[-1] == (512, 256)
    for a, b in zip(boxed.records, whole.records):
        assert np.abs(a.pressure - b.pressure).max() <= 1e-7 * b.pressure.max()
        assert np.all(a.gap >= -1e-6 * np.abs(a.displacement).max())
