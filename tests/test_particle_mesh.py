"""The particle-mesh eigenstrain operator (issue 26: a cost that follows the bodies) against the box operator.

The reference is :class:`~framework.operators.eigenstrain.HalfSpaceEigenstrain` on the box around the cuboids, itself
checked against direct sums of Chiu's closed forms and against Eshelby's solution (``test_reference_eigenstrain``,
``test_reference_eshelby``). The particle mesh replaces its far field by a coarse box's and keeps its near field
exact (near tables), so it must (1) match the reference to a stated error that falls as the near radius grows, (2) be
the reference's own field, to the tables' round-off, for pairs within the near radius, (3) give the same numbers by
its compiled and numpy near sums. Measured on the four spheres below (radius 4 cuboids, one 4 cuboids under the
surface, two 13 cuboids apart), largest difference over the largest strain, random / uniform eigenstrains:
near 5: 6.4e-3 / 1.6e-2, near 6: 2.4e-3 / 5.8e-3, near 8: 4.1e-4 / 1.7e-3, near 10: 1.2e-4 / 8.0e-4,
near 12: 5.4e-5 / 3.2e-4.
"""
import numpy as np
import pytest

import framework as fw
from framework import _fused
from framework.errors import ParameterError, ShapeError
from framework.operators.eigenstrain import HalfSpaceEigenstrain
from framework.operators.particle_mesh import ParticleMeshEigenstrain, axis_stencils, ball_offsets, stencil_weights

H = 1e-5
POISSON = 0.3
START, SHAPE = (32, 32, 2), (32, 32, 24)
CENTRES = [(40, 40, 10), (52, 44, 14), (44, 55, 20), (56, 56, 8)]


def grid():
    return fw.Grid(shape=(96, 96), size=(96 * H, 96 * H), depth=40 * H, layers=40)


@pytest.fixture(scope="module")
def spheres():
    """Four spheres of radius 4 cuboids: the cells, their mask in the box and the box operator's strains."""
    lattice = np.stack(np.meshgrid(*[np.arange(s, s + m) for s, m in zip(START, SHAPE)], indexing="ij"), axis=-1)
    mask = np.zeros(SHAPE, bool)
    for centre in CENTRES:
        mask |= ((lattice - np.array(centre)) ** 2).sum(axis=-1) <= 16
    cells = lattice[mask]
    exact = HalfSpaceEigenstrain(grid(), POISSON, START, SHAPE)
    rng = np.random.default_rng(1)
    cases = {"random": rng.standard_normal((len(cells), 6)),
             "uniform": np.tile([1e-3, 0.0, 0.0, 0.0, 0.0, 5e-4], (len(cells), 1))}
    strains = {}
    for name, values in cases.items():
        field = np.zeros((*SHAPE, 6))
        field[mask] = values
        strains[name] = exact.strain(field)[mask]
    return cells, cases, strains


@pytest.fixture(scope="module")
def mesh8(spheres):
    """The particle mesh of the four spheres at near 8 (its tables take 4 s: made once here)."""
    return ParticleMeshEigenstrain(grid(), POISSON, spheres[0], near=8.0)


def errors(operator, cases, strains):
    return {name: np.abs(operator.strain(values) - strains[name]).max() / np.abs(strains[name]).max()
            for name, values in cases.items()}


def test_stencil_weights_carry_a_fine_cuboid_less_a_coarse_one():
    """Each weight stands for a coarse cuboid (width 1 in coarse units): the weighted coarse cuboids have the moments
    0 .. 3 of the fine cuboid (width 1/2, volume ratio 1/8 along each axis) they replace; without the cuboids'
    widths (cumulant 0) they are Lagrange's interpolation weights, exact on cubics."""
    for x in (-0.25, 0.25):
        for shift in (-2, -1, 0):
            nodes = shift + np.arange(4)
            weights = stencil_weights(x, nodes, (0.25 - 1.0) / 12.0)
            for k in range(4):
                coarse = sum(w * ((n + 0.5) ** (k + 1) - (n - 0.5) ** (k + 1)) / (k + 1) for w, n in zip(weights, nodes))
                fine = 2.0 * ((x + 0.25) ** (k + 1) - (x - 0.25) ** (k + 1)) / (k + 1)
                assert coarse == pytest.approx(fine, abs=1e-13)
            lagrange = stencil_weights(x, nodes, 0.0)
            cubic = np.array([1.0, -2.0, 0.5, 3.0])
            assert lagrange @ np.polyval(cubic, nodes) == pytest.approx(np.polyval(cubic, x), abs=1e-13)


def test_axis_stencils_are_centred_and_one_sided_at_the_surface():
    nodes, _ = axis_stencils(np.arange(8), 0, 3, 0.0, lowest=0)
    assert nodes[:, 0].tolist() == [0, 0, 0, 0, 0, 1, 1, 2]        # fine 0 .. 2 one-sided, the rest centred
    # coarse cells hold fine 1-2, 3-4, ...: 10 is the second of coarse 4, 11 the first of coarse 5
    nodes, _ = axis_stencils(np.array([10, 11]), 1, 3, 0.0)
    assert nodes.tolist() == [[3, 4, 5, 6], [3, 4, 5, 6]]


def test_near_ball():
    offsets = ball_offsets(2.0)
    assert len(offsets) == 33 and offsets[0].tolist() == [0, 0, 0]
    assert np.all((offsets ** 2).sum(axis=1) <= 4)


@pytest.mark.parametrize("near, random, uniform", [(5.0, 8e-3, 2e-2), (8.0, 6e-4, 2.5e-3)])
def test_matches_the_box_operator_to_its_stated_error(spheres, mesh8, near, random, uniform):
    cells, cases, strains = spheres
    operator = mesh8 if near == 8.0 else ParticleMeshEigenstrain(grid(), POISSON, cells, near=near)
    error = errors(operator, cases, strains)
    assert error["random"] < random and error["uniform"] < uniform, error


def test_error_falls_as_the_near_field_grows(spheres):
    cells, cases, strains = spheres
    previous = None
    for near in (4.0, 5.0, 6.0):
        error = errors(ParticleMeshEigenstrain(grid(), POISSON, cells, near=near), cases, strains)
        if previous is not None:
            assert error["random"] < 0.6 * previous["random"] and error["uniform"] < 0.7 * previous["uniform"], \
                (near, error, previous)
        previous = error


def test_pairs_within_the_near_field_are_the_box_operators(spheres):
    """One loaded cuboid: at every target within the near radius the particle mesh gives the box operator's strain.
    The tables are its own values where they were made: each layer down to ``shallow`` (8 with near 4), and the
    deeper classes at ``shallow`` and ``shallow + 1``, to the Boussinesq patches of the small boxes they were made
    in (1-2e-9 of the largest strain). A deeper source takes the latter's tables: the coarse path's error on its
    mirror image and surface, at twice the depth, differs there (9e-6 at layer 20)."""
    cells, _, _ = spheres
    operator = ParticleMeshEigenstrain(grid(), POISSON, cells, near=4.0)
    assert operator.shallow == 8
    exact = HalfSpaceEigenstrain(grid(), POISSON, START, SHAPE)
    local = cells - np.array(START)
    for centre, tolerance in (((56, 56, 6), 1e-8), ((56, 56, 8), 1e-8), ((44, 55, 20), 2e-5)):
        source = int(np.flatnonzero((cells == np.array(centre)).all(axis=1))[0])
        near = np.flatnonzero(((cells - np.array(centre)) ** 2).sum(axis=1) <= 16.0)
        for component in (0, 4):
            values = np.zeros((len(cells), 6))
            values[source, component] = 1.0
            field = np.zeros((*SHAPE, 6))
            field[tuple(local.T)] = values
            reference = exact.strain(field)[tuple(local[near].T)]
            difference = np.abs(operator.strain(values)[near] - reference).max() / np.abs(reference).max()
            assert difference < tolerance, (centre, component, difference)


def test_compiled_and_numpy_near_sums_agree(spheres):
    if not _fused.numba_available():
        pytest.skip("numba is not installed: the numpy near sums are the only ones")
    cells, cases, _ = spheres
    operator = ParticleMeshEigenstrain(grid(), POISSON, cells, near=3.0)
    with _fused.use_compiled(True):
        compiled = operator.strain(cases["random"])
        compiled_surface = operator.surface_displacement(cases["random"])
        compiled_stress = operator.pressure_stress(compiled_surface * 1e13)
    with _fused.use_compiled(False):
        plain = operator.strain(cases["random"])
        plain_surface = operator.surface_displacement(cases["random"])
        plain_stress = operator.pressure_stress(compiled_surface * 1e13)
    assert np.abs(compiled - plain).max() < 1e-12 * np.abs(plain).max()
    assert np.abs(compiled_surface - plain_surface).max() < 1e-12 * np.abs(plain_surface).max()
    assert np.abs(compiled_stress - plain_stress).max() < 1e-12 * np.abs(plain_stress).max()


def test_bad_input_is_named():
    cells = np.array([[40, 40, 10], [41, 40, 10]])
    with pytest.raises(ParameterError, match="periodic"):
        ParticleMeshEigenstrain(fw.Grid(shape=(8, 8), size=(1.0, 1.0), depth=1.0, layers=4, periodic=(True, True)),
                                POISSON, [[1, 1, 1]])
    with pytest.raises(ParameterError, match="average must be a bool"):
        ParticleMeshEigenstrain(grid(), POISSON, cells, average=1)
    with pytest.raises(ParameterError, match="order must be an odd integer"):
        ParticleMeshEigenstrain(grid(), POISSON, cells, order=2)
    with pytest.raises(ParameterError, match="near must be"):
        ParticleMeshEigenstrain(grid(), POISSON, cells, near=1.0)
    with pytest.raises(ParameterError, match="cells must be integer"):
        ParticleMeshEigenstrain(grid(), POISSON, cells.astype(float))
    with pytest.raises(ParameterError, match="grid's cuboids"):
        ParticleMeshEigenstrain(grid(), POISSON, [[40, 40, 40]])
    with pytest.raises(ParameterError, match="distinct"):
        ParticleMeshEigenstrain(grid(), POISSON, [[40, 40, 10], [40, 40, 10]])
    operator = ParticleMeshEigenstrain(grid(), POISSON, cells, near=2.0)
    with pytest.raises(ShapeError, match="eigenstrain has shape"):
        operator.strain(np.zeros((3, 6)))


def four_glass_spheres():
    """Four glass spheres of radius 4.2 cuboids, one 6 cuboids under the surface (centres in cuboids: x1, x2 from the
    grid's middle, x3 from the surface)."""
    from framework import inclusions, materials
    glass = materials.Elastic(70e9, 0.22)
    centres = [(-8, -8, 12), (4, -4, 16), (-4, 7, 22), (8, 8, 10)]
    return inclusions.InclusionSet([inclusions.Ellipsoid(center=tuple(c * H for c in centre), semi_axes=(4.2 * H,) * 3,
                                                         material=glass) for centre in centres])


@pytest.fixture(scope="module")
def glass_in_polymer():
    """Four glass spheres (radius 4.2 cuboids, one 6 cuboids under the surface) in a polymer under a uniform strain,
    solved on the box around them (``fw.solve_inclusions``, the reference) and on their cuboids alone."""
    from framework import materials
    from framework.inclusions.dispersed import solve_on_bodies
    polymer, bodies = materials.Elastic(3e9, 0.35), four_glass_spheres()
    applied = np.array([[1e-3, 5e-4, 0.0], [5e-4, 0.0, 0.0], [0.0, 0.0, -1e-3]])
    box = fw.solve_inclusions(grid(), polymer, bodies, applied, tolerance=1e-10)
    mesh = solve_on_bodies(grid(), polymer, bodies, applied, tolerance=1e-10, near=8.0)
    return box, mesh, bodies


def test_solve_on_bodies_matches_the_box_solve(glass_in_polymer):
    """The same cuboids as the box solve, the same system: the eigenstrains within the operator's error (measured
    2.8e-3 of the largest, stress 3.2e-3), each body's mean eigenstrain within 2e-4 of the largest. Preconditioned
    body by body (each in its own filled periodic cell), 9 flexible GMRES iterations to 1e-10, as many as the box
    solve's Fourier preconditioner (cuboid by cuboid: 40)."""
    box, mesh, bodies = glass_in_polymer
    assert mesh.success and mesh.residual < 1e-10
    assert mesh.iterations <= 12 and mesh.products == mesh.iterations      # D[x] carried by the solver
    assert len(mesh.cells) == np.count_nonzero(box.inhomogeneity)
    assert np.array_equal(box.inhomogeneity[tuple(mesh.cells.T)], mesh.body + 1)
    assert np.array_equal(mesh.cells, np.argwhere(box.inhomogeneity))     # the grid's C order, as the box's
    reference = box.eigenstrain[tuple(mesh.cells.T)]
    scale = np.abs(reference).max()
    assert np.abs(mesh.eigenstrain - reference).max() < 5e-3 * scale
    for k in range(len(bodies)):
        mine = mesh.eigenstrain[mesh.body == k].mean(axis=0)
        assert np.abs(mine - reference[mesh.body == k].mean(axis=0)).max() < 2e-4 * scale
    start = np.array([s.start for s in box.box])
    stress = box.stress[tuple((mesh.cells - start).T)]
    assert np.abs(mesh.stress - stress).max() < 5e-3 * np.abs(stress).max()


def test_solve_on_bodies_checks_its_input():
    from framework import inclusions, materials
    from framework.inclusions.dispersed import solve_on_bodies
    body = inclusions.Ellipsoid(center=(0.0, 0.0, 12 * H), semi_axes=(4 * H,) * 3, material=materials.Elastic(70e9, 0.22))
    polymer = materials.Elastic(3e9, 0.35)
    with pytest.raises(ParameterError, match="applied_strain must be small"):
        solve_on_bodies(grid(), polymer, [body], np.eye(3))
    with pytest.raises(ParameterError, match="tolerance must lie"):
        solve_on_bodies(grid(), polymer, [body], np.eye(3) * 1e-3, tolerance=0.0)
    with pytest.raises(ParameterError, match="matrix must be"):
        solve_on_bodies(grid(), "polymer", [body], np.eye(3) * 1e-3)


def test_a_dispersion_solved_on_its_bodies():
    """30 glass spheres (radius 4 cuboids) at 10 % in a slab 1-7 radii deep (``bench/particle_mesh.py --bodies 30
    --cells-per-radius 4``), solved to 1e-8 on the box and on the bodies (near 8). Measured: eigenstrains within
    6.8e-3 of the largest, rms 2.6e-3, the bodies' means within 7.5e-4 of the largest eigenstrain; 13 flexible GMRES
    iterations (the box solve's 7); the 30 bodies' cuboids span boxes of 3 shapes, whose filled cells they share."""
    from framework import inclusions, materials
    from framework.inclusions.dispersed import BodyPreconditioner, solve_on_bodies
    radius, cell = 0.1e-3, 0.025e-3
    side = np.sqrt(30 * 4.0 / 3.0 * np.pi * radius ** 3 / 0.1 / (6 * radius))
    slab = ((-side / 2, side / 2), (-side / 2, side / 2), (radius, 7 * radius))
    glass, polymer = materials.Elastic(70e9, 0.22), materials.Elastic(3e9, 0.35)
    bodies = inclusions.random_dispersion(0.1, slab, radius, glass, gap=0.25 * radius, seed=0)
    n = int(np.ceil((side + 8 * radius) / cell / 32.0)) * 32
    wide = fw.Grid(shape=(n, n), size=(n * cell, n * cell), depth=32 * cell, layers=32)
    applied = np.diag([1e-3, 0.0, -1e-3])
    box = fw.solve_inclusions(wide, polymer, bodies, applied, tolerance=1e-8)
    mesh = solve_on_bodies(wide, polymer, bodies, applied, tolerance=1e-8, near=8.0)
    assert len(bodies) == 30 and mesh.success and mesh.iterations <= 16
    reference = box.eigenstrain[tuple(mesh.cells.T)]
    difference = mesh.eigenstrain - reference
    assert np.abs(difference).max() < 1.2e-2 * np.abs(reference).max()
    assert np.sqrt((difference ** 2).mean() / (reference ** 2).mean()) < 5e-3
    means = [np.abs(difference[mesh.body == k].mean(axis=0)).max() for k in range(len(bodies))]
    assert max(means) < 1.5e-3 * np.abs(reference).max()
    shared = BodyPreconditioner(wide, polymer.poisson, mesh.cells, mesh.body, [b.stiffness_tensor for b in bodies],
                                polymer.young)
    assert len({key for _, key in shared.problems}) <= 6


def test_the_bodies_preconditioner_is_nearly_linear():
    """The coupling's Anderson mixing takes the preconditioner for a linear map; the bodies' one is an inner GMRES per
    body, solved to ``dispersed.BODY_TOLERANCE``. Measured on the four glass spheres, ``|M(a + b) - M(a) - M(b)|``
    over ``|M(a + b)|``, random and smooth a, b: 3.7e-3 / 1.4e-2 at the box path's inner tolerance 0.1 (the roll over
    30 spheres at 8 cuboids per radius stalled there), 1.7e-3 / 3.4e-3 at 3e-2, 5.1e-4 / 6.9e-4 at 1e-2."""
    from framework import materials
    from framework.inclusions.dispersed import BODY_TOLERANCE, BodyPreconditioner, body_cells
    polymer, bodies = materials.Elastic(3e9, 0.35), four_glass_spheres()
    cells, body = body_cells(grid(), bodies)
    precondition = BodyPreconditioner(grid(), polymer.poisson, cells, body, [b.stiffness_tensor for b in bodies],
                                      polymer.young)
    assert BODY_TOLERANCE <= 1e-2
    x = cells / 10.0
    pairs = {"random": np.random.default_rng(1).standard_normal((2, len(cells), 6)),
             "smooth": (np.sin(x[:, :1] + np.arange(6)) * np.cos(x[:, 2:3]), np.cos(2 * x[:, 1:2] + np.arange(6)))}
    for name, (a, b) in pairs.items():
        both = precondition(a + b)
        departure = np.linalg.norm(both - precondition(a) - precondition(b)) / np.linalg.norm(both)
        assert departure < 2e-3, name


def test_each_bodys_inner_system_has_a_positive_spectrum(monkeypatch):
    """Each body's system in its periodic cell, right-preconditioned by the cell's inverse, as the inner solve
    iterates on it: a sphere of radius 8 cuboids in its 16^3 box, on the folded lattice (the box grown by 8 cuboids).
    On the cell's clipped symbol (``equivalent.CLIP_SYMBOL``) its Ritz values (40 Arnoldi steps) lie in [1.0001, 5.02]; on the
    kernels' own symbol, which overshoots [0, 1], they reached -5.24 (6.1 at the top)."""
    from framework import inclusions, materials
    from framework.inclusions import equivalent
    from framework.inclusions.dispersed import BodyPreconditioner, body_cells
    glass, polymer = materials.Elastic(70e9, 0.22), materials.Elastic(3e9, 0.35)
    body = inclusions.InclusionSet([inclusions.Ellipsoid(center=(0.3 * H, 0.1 * H, 15.2 * H), semi_axes=(8 * H,) * 3,
                                                         material=glass)])
    cells, owner = body_cells(grid(), body)
    ranges = {}
    for clip in (False, True):
        monkeypatch.setattr(equivalent, "CLIP_SYMBOL", clip)
        problem = BodyPreconditioner(grid(), polymer.poisson, cells, owner, [body[0].stiffness_tensor],
                                     polymer.young).problems[0][0]
        assert problem.operator.shape == (16, 16, 16) and problem.inner and problem._lattice == "folded"
        problem._local_solve(np.ones(6 * len(cells)))       # the cell's matrices
        steps, size = 40, 6 * len(cells)
        basis, hessenberg = [np.random.default_rng(0).standard_normal(size)], np.zeros((steps + 1, steps))
        basis[0] /= np.linalg.norm(basis[0])
        for j in range(steps):
            w = problem._filled(problem._filled(basis[j]), forward=True)
            for _ in range(2):
                weights = np.array(basis) @ w
                hessenberg[:j + 1, j] += weights
                w -= weights @ np.array(basis)
            hessenberg[j + 1, j] = np.linalg.norm(w)
            basis.append(w / hessenberg[j + 1, j])
        ritz = np.linalg.eigvals(hessenberg[:steps, :steps])
        ranges[clip] = ritz.real.min(), ritz.real.max(), np.abs(ritz.imag).max()
    assert ranges[False][0] < 0.0
    assert ranges[True][2] < 1e-6
    assert ranges[True][0] > 0.99 and ranges[True][1] < 8.0, ranges[True]


def test_surface_displacement_against_the_box_operator(spheres, mesh8):
    """Betti's surface displacement of the bodies' eigenstrains (the contact's part of a coupling): the coarse box's,
    interpolated to the grid's cells, and the fine operator's own within the near radius of the cells within
    ``shallow`` layers of the surface. Measured on the four spheres, largest difference over the largest displacement,
    random / uniform eigenstrains: near 6: 1.1e-2 / 8.0e-3; near 8: 6.0e-3 / 6.2e-3; near 10: 2.8e-3 / 3.6e-3; the
    coarse box alone 5.2e-2 / 1.7e-2. A shallow cuboid's own displacement within the near radius is the fine
    operator's to rounding."""
    cells, cases, _ = spheres
    operator = mesh8
    exact = HalfSpaceEigenstrain(grid(), POISSON, START, SHAPE)
    local = tuple((cells - np.array(START)).T)
    for name, values in cases.items():
        field = np.zeros((*SHAPE, 6))
        field[local] = values
        reference = exact.surface_displacement(field)
        scale = np.abs(reference).max()
        assert np.abs(operator.surface_displacement(values) - reference).max() < 8e-3 * scale, name
        assert np.abs(operator.coarse.surface_displacement(values) - reference).max() > 1e-2 * scale, name
        strain, surface = operator.strain(values, displacement=True)     # one spread for both (a coupling's product)
        assert np.allclose(strain, operator.strain(values), rtol=0, atol=1e-12 * np.abs(strain).max())
        assert np.allclose(surface, operator.surface_displacement(values), rtol=0, atol=1e-12 * scale)
    source = int(np.flatnonzero((cells == np.array([56, 56, 6])).all(axis=1))[0])
    for component in (0, 2, 4):
        values = np.zeros((len(cells), 6))
        values[source, component] = 1.0
        field = np.zeros((*SHAPE, 6))
        field[local] = values
        reference = exact.surface_displacement(field)[52:61, 52:61]
        assert np.abs(operator.surface_displacement(values)[52:61, 52:61] - reference).max() < 1e-12 * np.abs(
            reference).max()


def test_pressure_stress_is_the_surface_displacements_transpose(spheres, mesh8):
    """The contact's stress at the cells (Love's coefficients through the coarse box, near tables for shallow cells)
    is the transpose of :meth:`surface_displacement` by Betti's theorem, ``sum p u3 dA = sum s : e* dV``, to
    rounding; against the box operator's, largest difference over the largest stress: a Hertz pressure (radius 20
    cells) 4.1e-3, random pressures 5.6e-3, one loaded cell 5.5e-4."""
    from framework.operators.eigenstrain import CONTRACTION
    cells, cases, _ = spheres
    operator = mesh8
    exact = HalfSpaceEigenstrain(grid(), POISSON, START, SHAPE)
    local = tuple((cells - np.array(START)).T)
    x1, x2 = np.meshgrid(np.arange(96), np.arange(96), indexing="ij")
    hertz = 1e8 * np.sqrt(np.clip(1.0 - ((x1 - 48) ** 2 + (x2 - 48) ** 2) / 20.0 ** 2, 0.0, None))
    rough = 1e8 * np.random.default_rng(2).random((96, 96))
    for pressure, tolerance in ((hertz, 6e-3), (rough, 8e-3)):
        reference = exact.pressure_stress(pressure)[local]
        stress = operator.pressure_stress(pressure)
        assert np.abs(stress - reference).max() < tolerance * np.abs(reference).max()
        work_surface = np.sum(pressure * operator.surface_displacement(cases["random"])) * H * H
        work_body = np.sum(stress * cases["random"] * CONTRACTION) * H ** 3
        assert work_surface == pytest.approx(work_body, rel=1e-11)
    with pytest.raises(ShapeError, match="pressure has shape"):
        operator.pressure_stress(np.zeros((4, 4)))


def test_cells_moved_with_the_material_are_the_cells_built_there(spheres):
    """A rolling run's bodies move by whole cells (odd moves shift them by half a coarse cell across the grid): the
    operator moved by (1, 0) then (2, -2) gives what one built at the moved cells gives, to its coarse grid's extent
    (sized for every shift; measured 5e-8 in the strain, 2.5e-6 in the surface displacement at the grid's edges,
    5e-16 in the pressure stress)."""
    cells, cases, _ = spheres
    moving = ParticleMeshEigenstrain(grid(), POISSON, cells, near=5.0, shifts=[(0, 0), (1, 0), (3, -2)])
    moving.move((1, 0))
    moving.move((2, -2))
    fresh = ParticleMeshEigenstrain(grid(), POISSON, cells + [3, -2, 0], near=5.0)
    values = cases["random"]
    for method, tolerance in (("strain", 1e-6), ("surface_displacement", 1e-5)):
        a, b = getattr(moving, method)(values), getattr(fresh, method)(values)
        assert np.abs(a - b).max() < tolerance * np.abs(b).max(), method
    x1, x2 = np.meshgrid(np.arange(96), np.arange(96), indexing="ij")
    pressure = 1e8 * np.sqrt(np.clip(1.0 - ((x1 - 50) ** 2 + (x2 - 47) ** 2) / 20.0 ** 2, 0.0, None))
    a, b = moving.pressure_stress(pressure), fresh.pressure_stress(pressure)
    assert np.abs(a - b).max() < 1e-12 * np.abs(b).max()
    with pytest.raises(ParameterError, match="not one of the shifts"):
        moving.move((1, 0))


def test_a_contact_over_bodies_on_their_cuboids(glass_in_polymer):
    """``Options(inclusion_operator="particle_mesh")``: a sphere pressed (0.3 N, R = 5 mm) on the polymer over the
    four glass spheres, the coupling on the bodies' cuboids alone, against the box's. Measured: approach within
    1.3e-4, pressure 3.5e-4 of its peak, eigenstrains 3.5e-3 of the largest, the bodies' stress 2.7e-3; the
    result's stress field (made on the box on demand) as the box run's shape."""
    from framework import indenters, loads, materials, schedules
    _, _, bodies = glass_in_polymer
    runs = {}
    for operator in ("box", "particle_mesh"):
        runs[operator] = fw.Simulation(grid=grid(), material=materials.Elastic(3e9, 0.35),
                                       indenter=indenters.Sphere(radius=5e-3),
                                       schedule=schedules.Static(load=loads.Step(0.3), times=[1.0]), inclusions=bodies,
                                       options={"inclusion_operator": operator}).run()
    box, mesh = runs["box"].records[-1], runs["particle_mesh"].records[-1]
    assert abs(runs["particle_mesh"].approach[-1] / runs["box"].approach[-1] - 1.0) < 5e-4
    assert np.abs(mesh.pressure - box.pressure).max() < 1e-3 * box.pressure.max()
    assert np.abs(mesh.eigenstrain - box.eigenstrain).max() < 6e-3 * np.abs(box.eigenstrain).max()
    assert np.abs(mesh.inclusion_stress - box.inclusion_stress).max() < 5e-3 * np.abs(box.inclusion_stress).max()
    assert runs["particle_mesh"].stress(0).shape == runs["box"].stress(0).shape


def test_rolling_over_a_dispersion_on_its_bodies():
    """``bench/dispersion.py``'s 10 glass spheres (4 cuboids per radius) rolled over for 4 cells, the bodies carried
    by the material: the particle mesh's run against the box's. Measured (6 cells): friction within 2.4e-4 of the
    box run's, peak pressure 4e-4, the last eigenstrains 4.5e-3; 63 products against 55."""
    import os
    import sys
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "bench"))
    import dispersion
    runs = {}
    for operator in ("box", "particle_mesh"):
        simulation, _, _ = dispersion.setup(10, 4, 4, 0.1, 0, operator=operator)
        runs[operator] = simulation.run()
    box, mesh = runs["box"], runs["particle_mesh"]
    friction = np.array(box.friction_coefficient)
    assert np.abs(np.array(mesh.friction_coefficient) - friction).max() < 1e-3 * np.abs(friction).max()
    for a, b in zip(box.records, mesh.records):
        assert abs(b.pressure.max() / a.pressure.max() - 1.0) < 1e-3
    last = box.records[-1].eigenstrain
    assert np.abs(mesh.records[-1].eigenstrain - last).max() < 1e-2 * np.abs(last).max()


@pytest.mark.slow
def test_the_first_roll_over_many_fine_bodies_converges():
    """``bench/dispersion.py``'s 30 glass spheres at 8 cuboids per radius (64 300 body cuboids) on their cuboids: the
    rest indentation and the first roll step. With each body's inner solve at the box path's 0.1 the first roll step
    stalled at an equivalent-inclusion residual of 2e-4 in 100 couplings; at ``BODY_TOLERANCE`` measured 13 and 11
    products (about 25 s)."""
    import os
    import sys
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "bench"))
    import dispersion
    simulation, _, _ = dispersion.setup(30, 8, 4, 0.1, 0, operator="particle_mesh")
    problem, products, done = simulation._inclusion_problem.problem, [], 0
    for _, record in zip(range(2), simulation.steps()):
        products.append(problem.products - done)
        done = problem.products
        assert record.couplings <= 18
    assert products[0] <= 16 and products[1] <= 16, products


def test_the_operator_option_is_checked():
    from framework.options import Options
    with pytest.raises(ParameterError, match="inclusion_operator must be one of 'box', 'particle_mesh'"):
        Options(inclusion_operator="mesh")
    with pytest.raises(ParameterError, match="inclusion_geometry must be 'staircase'"):
        Options(inclusion_operator="particle_mesh", inclusion_geometry="laminate")


def test_a_roll_on_the_bodies_resumes_bit_for_bit(tmp_path, stop_after):
    """A rolling run over two bodies on their cuboids (``inclusion_operator="particle_mesh"``), stopped after 3 steps
    and resumed: the bodies where the material had carried them, every record equal to the whole run's."""
    from framework import indenters, inclusions, materials, schedules

    def simulation():
        cell = 25e-6
        wide = fw.Grid(shape=(64, 28), size=(64 * cell, 28 * cell), depth=0.3e-3, layers=12)
        bodies = [inclusions.Ellipsoid(center=(x, 0.0, 0.12e-3), semi_axes=(0.08e-3,) * 3,
                                      material=materials.Elastic(70e9, 0.22)) for x in (0.1e-3, 0.3e-3)]
        return fw.Simulation(grid=wide, material=materials.StandardLinearSolid(e_inf=3e9, e_1=3e9, tau=1e-4,
                                                                                 poisson=0.35),
                             indenter=indenters.Sphere(radius=10e-3),
                             schedule=schedules.Rolling(load=1.0, velocity=(1.0, 0.0), distance=0.125e-3),
                             inclusions=bodies, options={"inclusion_operator": "particle_mesh"})

    whole = simulation().run()
    stop_after(simulation(), 3, tmp_path / "c.h5")
    resumed = simulation().run(resume=tmp_path / "c.h5")
    assert len(resumed) == len(whole) > 4
    for a, b in zip(resumed.records, whole.records):
        assert a.inclusion_start == b.inclusion_start
        assert np.array_equal(a.pressure, b.pressure) and np.array_equal(a.eigenstrain, b.eigenstrain)
