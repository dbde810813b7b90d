"""Inputs that ran silently to a meaningless result (issue 23, item 6) now end in an error naming them."""
import numpy as np
import pytest

import framework as fw
from framework import errors, indenters, materials, schedules

GRID = fw.Grid(shape=(16, 16), size=(1e-3, 1e-3))


def simulation(schedule, options=None):
    return fw.Simulation(grid=GRID, material=materials.PMMA, indenter=indenters.Sphere(radius=5e-3),
                         schedule=schedule, options=options)


def test_a_steady_run_refuses_the_hereditary_history_it_would_ignore():
    with pytest.raises(errors.ParameterError, match=r"options.history = 'hereditary' has no meaning for a steady run"):
        simulation(schedules.Rolling(load=1.0, velocity=(1e-3, 0.0), steady=True), {"history": "hereditary"})
    simulation(schedules.Rolling(load=1.0, velocity=(1e-3, 0.0), steady=True))   # the default is fine


def test_a_steady_run_with_millions_of_loads_is_refused():
    with pytest.raises(errors.ParameterError, match=r"load: a steady run solves one steady state per load, got "
                                                    r"2000000 loads, more than 1000000"):
        simulation(schedules.Rolling(load=np.linspace(0.5, 1.0, 2_000_000), velocity=(1e-3, 0.0), steady=True))


GRID3 = fw.Grid(shape=(32, 32), size=(1e-3, 1e-3), depth=0.5e-3, layers=16)


def sphere(young):
    from framework import inclusions
    return inclusions.Ellipsoid(center=(0.0, 0.0, 0.25e-3), semi_axes=(0.1e-3,) * 3,
                                material=materials.Elastic(young=young, poisson=0.3))


def test_a_stiff_sphere_reads_its_rigid_limit_at_any_point():
    """The stress at a point inside a stiff sphere was C_I : strain, which multiplied the gap between the point
    strain and the cell-averaged one by the stiffness ratio (a 1000x stiffer sphere's centre read -0.2 MPa for
    2.27): now C_M : (strain - e*). At ratios 1e3, 1e4 and 1e6 the point stress at the centre cuboid equals the
    cuboid's stress from the solve to 2 %, and the cuboid's converges to the rigid limit (1e4 against 1e6: 5e-4)."""
    matrix = materials.Elastic(young=1e3, poisson=0.3)   # a soft gel
    strain = np.diag([1e-3, 0.0, 0.0])
    centre = [[1.5625e-5, 1.5625e-5, 0.25e-3 + 1.5625e-5]]   # the centre of a cuboid next to the sphere's centre
    cells = []
    for ratio in (1e3, 1e4, 1e6):
        solution = fw.solve_inclusions(GRID3, matrix, [sphere(1e3 * ratio)], strain)
        cell = solution.stress[tuple(n // 2 for n in solution.stress.shape[:3])]
        np.testing.assert_allclose(solution.stress_at(centre)[0], cell, rtol=0.02, atol=0.02 * np.abs(cell).max())
        cells.append(cell)
    np.testing.assert_allclose(cells[1], cells[2], rtol=0, atol=2e-3 * np.abs(cells[2]).max())   # measured 5e-4


def test_inclusions_stiffer_than_any_solid_and_large_strains_are_refused():
    matrix = materials.Elastic(young=1e9, poisson=0.3)
    with pytest.raises(errors.ParameterError, match=r"inclusions\[0\].material is stiffer than any solid"):
        fw.solve_inclusions(GRID3, matrix, [sphere(1e15)], np.diag([1e-3, 0.0, 0.0]))   # 5000 x steel
    soft = materials.Elastic(young=1.0, poisson=0.3)
    with pytest.raises(errors.ParameterError, match=r"2e\+07 times stiffer than the matrix .* at most 1e\+06"):
        fw.solve_inclusions(GRID3, soft, [sphere(2e7)], np.diag([1e-3, 0.0, 0.0]))
    with pytest.raises(errors.ParameterError, match=r"applied_strain must be small, .* at most 0.1 .* got .* 10"):
        fw.solve_inclusions(GRID3, matrix, [sphere(2e11)], np.diag([10.0, 0.0, 0.0]))


def hertz_run(cells_per_radius):
    """An elastic sphere (R = 10 mm, W = 100 N on steel: Hertz radius a = 0.133 mm) on a grid of 8 radii."""
    young, poisson, radius, load = 200e9, 0.3, 10e-3, 100.0
    a = (3 * load * radius * (1 - poisson**2) / (4 * young)) ** (1 / 3)
    h = a / cells_per_radius
    cells = int(np.ceil(8 * cells_per_radius)) | 1
    grid = fw.Grid(shape=(cells, cells), size=(cells * h, cells * h))
    result = fw.Simulation(grid=grid, material=materials.Elastic(young=young, poisson=poisson),
                           indenter=indenters.Sphere(radius=radius), schedule=schedules.Static(load=load, times=[0.0])).run()
    return result.max_pressure[0] / (3 * load / (2 * np.pi * a**2)) - 1


def test_a_contact_a_few_cells_wide_is_warned_of():
    """The threshold (4 cells per contact radius) against Hertz: 2 cells put the peak pressure 2.6 % high (warned),
    6 cells 0.2 % (silent); the warning gives the numbers and the cell size to use."""
    from framework.simulation import MIN_CELLS_PER_RADIUS
    assert MIN_CELLS_PER_RADIUS == 4
    with pytest.warns(errors.ResolutionWarning, match=r"the contact radius at step 0 is .* m, 2(\.\d)? cells of .* "
                                                      r"fewer than 4 cells per contact radius .*\(cells of .* m or smaller"):
        coarse = hertz_run(2.0)
    assert coarse > 0.01
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error", errors.ResolutionWarning)
        fine = hertz_run(6.0)
    assert abs(fine) < 0.01
