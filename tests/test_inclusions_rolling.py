"""A sphere rolling over a viscoelastic half-space that holds an inhomogeneity (transient; THEORY.md secs. 7-8)."""
import numpy as np
import pytest

import framework as fw
from framework import inclusions, indenters, materials, schedules

NU = 0.3
SOLID = materials.StandardLinearSolid(e_inf=100e9, e_1=100e9, tau=1e-4, poisson=NU)   # wake V tau = 0.1 mm
CELL = 25e-6


def run(material=None, start=0.4e-3, distance=0.8e-3, matrix=SOLID):
    """R = 10 mm, 40 N (contact radius ~0.1 mm) rolling at 1 m/s along x1 over a sphere r = 0.08 mm,
    centre 0.12 mm deep, that starts ``start`` ahead of the body; 25 um cells, one step per cell."""
    grid = fw.Grid(shape=(64, 28), size=(64 * CELL, 28 * CELL), depth=0.3e-3, layers=12)
    bodies = None if material is None else [
        inclusions.Ellipsoid(center=(start, 0.0, 0.12e-3), semi_axes=(0.08e-3,) * 3, material=material)]
    simulation = fw.Simulation(grid=grid, material=matrix, indenter=indenters.Sphere(radius=10e-3),
                               schedule=schedules.Rolling(load=40.0, velocity=(1.0, 0.0), distance=distance),
                               inclusions=bodies, options={"tolerance": 1e-10})
    return simulation.run()


@pytest.fixture(scope="module")
def homogeneous():
    return run()


@pytest.fixture(scope="module")
def stiff():
    return run(materials.Elastic(600e9, 0.22))


def test_matrix_stiffness_inhomogeneity_changes_nothing():
    """On an elastic matrix, an inhomogeneity of the matrix's stiffness carried under the body: no change."""
    steel = materials.Elastic(200e9, NU)
    plain = run(matrix=steel, distance=0.3e-3)
    same = run(steel, matrix=steel, distance=0.3e-3)
    for a, b in zip(same.records, plain.records):
        assert np.abs(a.pressure - b.pressure).max() <= 1e-10 * b.pressure.max()
        assert a.approach == pytest.approx(b.approach, rel=1e-10)
    assert np.abs(same.eigenstrain(-1)).max() <= 1e-14


@pytest.mark.slow
def test_stiff_inhomogeneity_raises_the_pressure_and_flips_the_friction_change(homogeneous, stiff):
    """Ahead of the axis it adds pressure where the sphere's slope resists the motion (more friction),
    behind it where the slope pushes (less): the friction's change flips sign as the body passes."""
    change = stiff.friction_coefficient - homogeneous.friction_coefficient
    position = stiff.position[:, 0]
    relative = position - 0.4e-3                      # the body's position relative to the inhomogeneity
    friction = homogeneous.friction_coefficient
    # far from it (0.35 mm ahead, 0.4 mm behind: 3.5 and 4 contact radii) the homogeneous transient
    assert abs(change[2]) < 0.02 * friction[2] and abs(change[-1]) < 0.01 * friction[-1]
    assert np.all(np.diff(np.abs(change[relative > 0.15e-3])) < 0)        # it fades behind the body
    approaching = change[(relative > -0.2e-3) & (relative < -0.08e-3)]
    leaving = change[(relative > 0.0) & (relative < 0.2e-3)]
    assert approaching.min() > 0 and leaving.max() < 0
    above = np.argmin(np.abs(relative))
    assert stiff.max_pressure[above] > 1.3 * homogeneous.max_pressure[above]
    # the eigenstrains ride with the material: the indicator's centre follows the body's motion
    for step in (0, len(stiff) - 1):
        cells = np.argwhere(stiff.inhomogeneity(step) > 0)
        x1 = stiff.grid.x1[cells[:, 0]].mean()
        assert x1 == pytest.approx(0.4e-3 - position[step], abs=CELL / 2)


@pytest.mark.slow
def test_results_with_rolling_inhomogeneities_round_trip(stiff, tmp_path):
    stiff.save(tmp_path / "r.h5")
    loaded = fw.load_result(tmp_path / "r.h5")
    for step in (0, len(stiff) // 2, -1):
        assert np.array_equal(loaded.eigenstrain(step), stiff.eigenstrain(step))
        assert np.array_equal(loaded.inhomogeneity(step), stiff.inhomogeneity(step))
        assert np.array_equal(loaded.stress(step), stiff.stress(step))


@pytest.mark.slow
def test_slice_pictures_draw_the_inhomogeneity_where_the_material_carried_it(stiff, tmp_path):
    """Body-frame pictures: the outline moves back by the distance rolled (0.4 mm between steps 8 and 24)."""
    import copy
    import matplotlib.image
    viz = pytest.importorskip("viz")
    drawn = {step: viz.render(stiff, tmp_path / f"with{step}.png", "von_mises", step, kind="slice") for step in (8, 24)}
    # the same run without the outline: a copy made once the run's stress has been computed (the copy keeps its
    # operators and the bodies' cuboids; the test had relied on an earlier test of the module computing them)
    plain = copy.copy(stiff)
    plain.inclusions = None
    centres = []
    for step in (8, 24):
        viz.render(plain, tmp_path / f"without{step}.png", "von_mises", step, kind="slice", clim=drawn[step].clim)
        image = matplotlib.image.imread(tmp_path / f"with{step}.png")[..., :3]
        other = matplotlib.image.imread(tmp_path / f"without{step}.png")[..., :3]
        outline = np.any(np.abs(image - other) > 0.1, axis=-1) & (image.max(axis=-1) < 0.15)
        assert outline.sum() > 100
        centres.append(np.argwhere(outline)[:, 1].mean())
    width = 1e-3 * 0.4 / (64 * CELL)                 # the rolled distance as a fraction of the grid's length
    # the grid spans ~800 of the 1200 pixels: a shift of ~200 pixels; ask for more than 125
    assert centres[0] - centres[1] > 0.5 * width * 1000


@pytest.mark.slow
@pytest.mark.parametrize("young, poisson, inner", [(600e9, 0.22, False), (20e9, 0.3, True)])
def test_resume_puts_the_inhomogeneity_where_the_material_had_carried_it(tmp_path, stop_after, young, poisson, inner):
    """A rolling run over an inhomogeneity, stopped after 3 steps and resumed: equal to the whole run, bit for bit.
    A carbide body (contrast 3, its box on the folded lattice: the filled cell's inverse alone preconditions) and a
    soft one (contrast 0.1: the preconditioner solves the body's system in its filled cell, a map that changes
    with its input)."""
    def simulation():
        grid = fw.Grid(shape=(64, 28), size=(64 * CELL, 28 * CELL), depth=0.3e-3, layers=12)
        body = [inclusions.Ellipsoid(center=(0.2e-3, 0.0, 0.12e-3), semi_axes=(0.08e-3,) * 3,
                                     material=materials.Elastic(young, poisson))]
        return fw.Simulation(grid=grid, material=SOLID, indenter=indenters.Sphere(radius=10e-3),
                             schedule=schedules.Rolling(load=40.0, velocity=(1.0, 0.0), distance=0.125e-3),
                             inclusions=body)

    whole = simulation().run()
    assert simulation()._inclusion_problem.problem.inner is inner

    stop_after(simulation(), 3, tmp_path / "c.h5")
    resumed = simulation().run(resume=tmp_path / "c.h5")
    assert len(resumed) == len(whole)
    for a, b in zip(resumed.records, whole.records):
        assert a.inclusion_start == b.inclusion_start
        assert np.array_equal(a.pressure, b.pressure) and np.array_equal(a.eigenstrain, b.eigenstrain)
