"""The fast eigenstrain operator and solvers: the same numbers as the direct sums and the plain transforms,
by every code path (compiled or numpy, pyFFTW or scipy), and the iteration counts they are built for."""
import numpy as np
import pytest

import framework as fw
from framework import _fused, fft, inclusions, indenters, loads, materials, schedules
from framework.inclusions import equivalent
from framework.inclusions.field import InclusionProblem
from framework.operators.eigenstrain import (ENTRIES, FOLDED_GAP, HalfSpaceEigenstrain, _stiffness_coefficients,
                                             potential_kernel_items, stress_from_strain)
from framework.operators.kernels import subsurface_stress

NU = 0.3
GLASS = materials.Elastic(70e9, 0.22)

# grid shape, layers, box start, box shape, whole patch (and a move)
BOXES = [((24, 20), 10, (8, 6, 0), (7, 5, 4), False),       # touching the surface
         ((40, 36), 16, (5, 9, 3), (9, 11, 6), False),      # off-centre, odd and even sides
         ((30, 30), 20, (11, 12, 9), (6, 5, 8), False),     # deep, tall
         ((40, 34), 14, (12, 8, 2), (9, 7, 5), True)]       # a box that moves over the grid
# cuboids square in x1, x2: a square lattice and half the kernels stored (eigenstrain.box_lattice)
SQUARE_BOXES = [((40, 40), 16, (5, 9, 3), (15, 16, 6), False),   # 30 x 32 padded -> 32 x 32
                ((34, 30), 12, (4, 3, 2), (8, 8, 5), True)]      # square, moving


def box_case(shape, layers, start, box, whole, average=True, starts=None, square=False):
    grid = fw.Grid(shape=shape, size=(shape[0] * 1e-4, shape[1] * (1e-4 if square else 1.1e-4)),
                   depth=layers * 0.9e-4, layers=layers)
    return grid, HalfSpaceEigenstrain(grid, NU, start, box, whole_patch=whole, average=average, starts=starts)


@pytest.mark.parametrize("case", BOXES + [(*box, "square") for box in SQUARE_BOXES])
@pytest.mark.parametrize("average", [True, False])
def test_product_equals_direct_sums_on_boxes_of_several_shapes(case, average):
    """Every term of the FFT product (infinite space, mirror, Boussinesq correction) against the direct corner
    sums and Love sums over the same box, at cells in the corners and inside, to 1e-12 of the strain; on cuboids
    square in x1, x2 with half the kernels stored (the others read permuted), a box's sides equal or not."""
    square = case[-1] == "square"
    grid, operator = box_case(*case[:5], average=average, square=square)
    assert operator.symmetric == square
    if case[4]:
        operator.move((3, -2))
    rng = np.random.default_rng(7)
    eigen = rng.normal(size=(*operator.shape, 6)) * 1e-3
    strain = operator.strain(eigen)
    m1, m2, m3 = operator.shape
    cells = [(0, 0, 0), (m1 - 1, m2 - 1, m3 - 1), (m1 // 2, m2 // 3, m3 // 2)]
    s1, s2, s3 = operator.start
    points = np.array([[grid.x1[s1 + i], grid.x2[s2 + j], grid.x3[s3 + k]] for i, j, k in cells])
    direct = operator.strain_at(points, eigen, average=average)
    assert np.abs(direct - np.array([strain[c] for c in cells])).max() <= 1e-12 * np.abs(strain).max()


def test_quarter_spectra_equal_the_full_transform():
    """The kernels' spectra built from one octant by DCT/DST-I equal the real FFT of the whole wrapped lattice."""
    grid, operator = box_case(*BOXES[1])
    n1, n2 = operator.fft_shape[:2]
    faces = [(np.arange(-m, m) + 0.5) * h for m, h in zip(operator.shape, operator.spacing)]
    coefficients = _stiffness_coefficients(NU)
    full = {entry: 0.0 for entry in ENTRIES}
    for key, values in potential_kernel_items(*faces, cell=operator.spacing):
        for entry in ENTRIES:
            full[entry] = full[entry] + coefficients[entry][key] * values
    for e, entry in enumerate(ENTRIES):
        wrapped = np.zeros(operator.fft_shape)
        offsets = np.ix_(*[np.r_[np.arange(m), np.arange(-m + 1, 0)] for m in operator.shape])
        wrapped[offsets] = full[entry][np.ix_(*[np.r_[np.arange(m - 1, 2 * m - 1), np.arange(0, m - 1)]
                                                for m in operator.shape])]
        expected = np.fft.rfftn(wrapped)[:n1 // 2 + 1, :n2 // 2 + 1]
        assert np.abs(expected.imag).max() <= 1e-12 * np.abs(expected).max()
        assert np.abs(operator._direct[e] - expected.real).max() <= 1e-12 * np.abs(expected).max()


def test_surface_maps_equal_direct_sums():
    """Betti's surface displacement and the stress of a surface pressure at the box, against Love's sums."""
    grid, operator = box_case(*BOXES[1])
    rng = np.random.default_rng(3)
    eigen = rng.normal(size=(*operator.shape, 6)) * 1e-3
    displacement = operator.surface_displacement(eigen)
    dx1, dx2 = grid.spacing
    centres = np.stack(np.meshgrid(*(axis[b] for axis, b in zip((grid.x1, grid.x2, grid.x3), operator.box)),
                                   indexing="ij"), axis=-1)
    weights = np.array([1, 1, 1, 2, 2, 2.0])
    for i, j in [(0, 0), (20, 17), (39, 35), (7, 30)]:
        stress = subsurface_stress(centres[..., 0] - grid.x1[i], centres[..., 1] - grid.x2[j], centres[..., 2],
                                   half1=dx1 / 2, half2=dx2 / 2, poisson=NU)
        expected = operator.spacing[2] * np.sum(stress * eigen * weights)
        assert displacement[i, j] == pytest.approx(expected, abs=1e-12 * np.abs(displacement).max())
    pressure = np.zeros(grid.shape)
    pressure[10:25, 14:30] = rng.random((15, 16)) * 1e6
    stress = operator.pressure_stress(pressure)
    x1, x2 = grid.coordinates()
    for cell in [(0, 0, 0), (8, 10, 5), (4, 3, 2)]:
        point = centres[cell]
        expected = np.einsum("ij,ijc->c", pressure, subsurface_stress(point[0] - x1, point[1] - x2, point[2],
                                                                        half1=dx1 / 2, half2=dx2 / 2, poisson=NU))
        assert np.abs(stress[cell] - expected).max() <= 1e-12 * np.abs(stress).max()


@pytest.mark.parametrize("case", [BOXES[1], BOXES[3]])
def test_product_with_its_surface_displacement(case):
    """``strain(e, displacement=True)`` (which shares the transforms when the patch is the grid) is the product
    and the surface displacement computed apart."""
    _, operator = box_case(*case)
    eigen = np.random.default_rng(9).normal(size=(*operator.shape, 6))
    strain, displacement = operator.strain(eigen, displacement=True)
    assert np.array_equal(strain, operator.strain(eigen))
    alone = operator.surface_displacement(eigen)
    assert np.abs(displacement - alone).max() <= 1e-14 * np.abs(alone).max()


@pytest.mark.parametrize("path", ["numpy loops", "scipy transforms"])
def test_every_code_path_gives_the_same_product(path):
    """Compiled and numpy passes, pyFFTW and scipy transforms: the same products and preconditioner to rounding."""
    case = BOXES[3]
    grid, operator = box_case(*case)
    eigen = np.random.default_rng(5).normal(size=(*operator.shape, 6))
    strain, displacement = operator.strain(eigen), operator.surface_displacement(eigen)
    if path == "numpy loops":
        with _fused.use_compiled(False):
            other, moved = operator.strain(eigen), operator.surface_displacement(eigen)
            # the product with the displacement (a whole-grid patch: the traction and Betti's sums share transforms)
            whole = HalfSpaceEigenstrain(grid, operator.poisson, operator.start, operator.shape, whole_patch=True)
            pair = whole.strain(eigen, displacement=True)
        compiled = whole.strain(eigen, displacement=True)
        for a, b in zip(pair, compiled):
            assert np.abs(a - b).max() <= 1e-13 * np.abs(b).max()
    else:
        with fft.use_backend("scipy"):
            _, again = box_case(*case)
            other, moved = again.strain(eigen), again.surface_displacement(eigen)
    assert np.abs(other - strain).max() <= 1e-13 * np.abs(strain).max()
    assert np.abs(moved - displacement).max() <= 1e-13 * np.abs(displacement).max()


@pytest.mark.skipif(not _fused.numba_available(), reason="numba is not installed (the jit extra)")
@pytest.mark.parametrize("lattice, symmetric", [((60, 64, 31), False), ((8, 6, 70), False), ((10, 12, 1), False),
                                                 ((6, 10, 33), False), ((4, 4, 9), False), ((4, 4, 9), True),
                                                 ((12, 12, 70), True), ((64, 64, 33), True)])
def test_compiled_box_loops_equal_their_numpy_forms(lattice, symmetric):
    """Each compiled loop of the eigenstrain operator on random fields equals its numpy form to rounding (1e-14):
    the stiffness pass on half lattices of one q3 up to more than two of its chunks (CHUNK), not whole vectors of 8
    (its rows' ends are scratch), with every kernel stored or, on square lattices, half of them (read permuted for
    q1 and q2 swapped); the surface sums and spreads; the copies between box fields, component lines and surface
    planes; Hooke's law inverted."""
    from framework.operators import _box_loops
    n1, n2, h = lattice
    rng = np.random.default_rng(sum(lattice))

    def complex_normal(*shape):
        return rng.normal(size=shape) + 1j * rng.normal(size=shape)
    # a block of q3 (N1, N2, 6, b) as BoxFFT lays it out: each row q1 followed by a padding
    spectra = np.zeros((n1, 6 * n2 * h + 3), complex)[:, :6 * n2 * h].reshape(n1, n2, 6, h)
    spectra[...] = complex_normal(n1, n2, 6, h)
    table = _box_loops.kernel_table(n1 // 2 + 1, n2 // 2 + 1, symmetric)[0]
    stored = table[..., 0].max() + 1
    direct, mirror = rng.normal(size=(stored, 21, h)), complex_normal(stored, 21, h)
    every = _box_loops.pass_items(table, range(n2 // 2 + 1))
    some = _box_loops.pass_items(table, [0, n2 // 2] if n2 > 2 else [0])     # columns and their reversals only
    first, second = np.array([a for a, _ in ENTRIES]), np.array([b for _, b in ENTRIES])
    parity1, parity2 = np.array([1.0, -1, 1, -1, 1, -1]), np.array([1.0, 1, -1, -1, 1, 1])
    m1, m2, layers, width = max(2, n1 // 2), max(2, n2 // 2), 3, n2 + 5
    field = rng.normal(size=(m1, m2, layers, 6))
    weights, lines = rng.normal(size=6), rng.normal(size=(m1 + 1, m2, 6, layers + 2))
    surface = complex_normal(6, n1, h)
    kernels, factors, parities = rng.normal(size=(6 * layers, n1 // 2 + 1, h)), complex_normal(6 * layers), \
        rng.choice([-1.0, 1.0], 6 * layers)
    planes = rng.normal(size=(6, m1, width))
    results = {}
    for compiled in (False, True):
        with _fused.use_compiled(compiled):
            passes = _box_loops.loops()
            assert (passes is _box_loops.NumpyLoops) is not compiled
            out = [spectra.copy(), spectra.copy(), np.zeros((n1, h), complex), np.empty((6, n1, h), complex),
                   np.zeros((6, m1, width)), field.copy(), field.copy(), np.full((m1 + 1, m2 + 2, 6, layers + 4), 7.0),
                   np.empty_like(field), field.reshape(-1, 6).copy()]
            for spectra_out, items in zip(out[:2], (every, some)):
                padded = np.zeros((n1, 6 * n2 * h + 3), complex)[:, :6 * n2 * h].reshape(n1, n2, 6, h)
                padded[...] = spectra_out
                passes.stiffness(padded, direct, mirror, items, _box_loops.PERMUTATION, first, second, parity1,
                                 parity2, np.array([1.0, 1, 1, -1, -1, 1]))
                spectra_out[...] = padded
            passes.surface_sum(out[2], kernels, factors, parities, surface, 6)
            passes.surface_spread(out[3], kernels, factors, parities, surface[0], 12)
            passes.surface_planes(out[4], field, 1, 4)
            passes.surface_add(out[5], planes, 2, 3, 0.5, True)
            passes.surface_add(out[6], planes, 0, 3, 0.5, False)
            passes.take_lines(out[7], field, weights, layers + 3)
            passes.put_lines(out[8], lines, weights)
            passes.compliance(out[9], 0.3)
            by_columns = spectra.copy()          # every column in turn (BoxFFT's by_columns) is the whole pass
            for column in range(n2 // 2 + 1):
                passes.stiffness(by_columns, direct, mirror, _box_loops.pass_items(table, [column]),
                                 _box_loops.PERMUTATION, first, second, parity1, parity2, np.array([1.0, 1, 1, -1, -1, 1]))
            out.append(by_columns)
            results[compiled] = out
    for plain, fast in zip(*results.values()):
        assert np.abs(fast - plain).max() <= 1e-14 * np.abs(plain).max()
    plain = results[False]
    assert np.abs(plain[10] - plain[0]).max() <= 1e-14 * np.abs(plain[0]).max()
    # the pass over some columns changes those and their reversals only
    touched = np.zeros(n2, bool)
    touched[[0, n2 // 2, -(n2 // 2)]] = True
    assert np.array_equal(plain[1][:, ~touched], spectra[:, ~touched])
    assert np.array_equal(plain[1][:, touched], plain[0][:, touched])
    assert np.array_equal(plain[4][..., 4:4 + m2], np.moveaxis(field[:, :, 1], -1, 0))
    # the lines (m1, m2, 6, >= layers): the field's components weighted, then zeros up to the length asked
    assert np.array_equal(plain[7][:m1, :m2, :, :layers], np.moveaxis(field, 3, 2) * weights[:, None])
    assert not plain[7][:m1, :m2, :, layers:layers + 3].any() and np.all(plain[7][:m1, :m2, :, layers + 3:] == 7.0)
    assert np.all(plain[7][m1:] == 7.0) and np.all(plain[7][:, m2:] == 7.0)
    assert np.array_equal(plain[8], np.moveaxis(lines[:m1, :m2, :, :layers], 2, 3) * weights)
    # Hooke's law (unit modulus) gives the stress back
    assert np.abs(stress_from_strain(plain[9], 0.3) - field.reshape(-1, 6)).max() <= 1e-14 * np.abs(field).max()


def stiff_sphere_problem(**options):
    grid = fw.Grid(shape=(32, 32), size=(0.8e-3, 0.8e-3), depth=0.5e-3, layers=20)
    body = inclusions.Ellipsoid(center=(0.0, 0.0, 0.25e-3), semi_axes=(0.15e-3,) * 3, material=GLASS)
    return InclusionProblem(grid, materials.Elastic(3e9, 0.35), inclusions.InclusionSet([body])).problem


def test_fourier_preconditioner_halves_the_products():
    """Glass in a polymer (23 times stiffer), 12 cuboids across, to 1e-10: each cuboid solved alone takes 43
    products, the Fourier preconditioner 24; its matrices stored for a quarter of the wavenumbers (isotropic
    materials) or for all of them (a turned anisotropic one) give the same preconditioner."""
    applied = np.array([1e-3, 0, 0, 0, 2e-4, 0])
    counts, solutions = {}, {}
    for name in ("local", "fourier"):
        problem = stiff_sphere_problem()
        problem.preconditioner, problem.recycled.kept = name, 0
        solution = problem.solve(applied, tolerance=1e-10)
        assert solution.success and solution.residual <= 1e-10
        counts[name], solutions[name] = solution.iterations, solution.eigenstrain
    assert counts["local"] <= 48 and counts["fourier"] <= 28 and counts["fourier"] < 0.65 * counts["local"]
    scale = np.abs(solutions["fourier"]).max()
    assert np.abs(solutions["local"] - solutions["fourier"]).max() <= 1e-8 * scale
    quarter = equivalent.FourierPreconditioner(problem.operator, problem.contrast[0], problem.matrix)
    assert quarter.matrices.shape[:2] == tuple(n // 2 + 1 for n in problem.operator.fft_shape[:2])
    field = np.random.default_rng(2).normal(size=(*problem.operator.shape, 6))
    full = equivalent.FourierPreconditioner.__new__(equivalent.FourierPreconditioner)
    full.operator, full.parities, full.lattice = problem.operator, (np.ones(6), np.ones(6)), "padded"
    rows, columns = (np.arange(n) for n in problem.operator.fft_shape[:2])
    index = np.ix_(np.minimum(rows, len(rows) - rows), np.minimum(columns, len(columns) - columns))
    signs = [np.where(axis[:, None] > len(axis) // 2, p[None, :], 1.0) for axis, p in zip((rows, columns),
                                                                                      quarter.parities)]
    sign = signs[0][:, None, None, :] * signs[1][None, :, None, :]
    full.matrices = quarter.matrices[index] * sign[..., :, None] * sign[..., None, :]
    expected = full(field)
    assert np.abs(quarter(field) - expected).max() <= 1e-12 * np.abs(expected).max()
    with _fused.use_compiled(False):
        assert np.abs(quarter(field) - expected).max() <= 1e-12 * np.abs(expected).max()


@pytest.mark.parametrize("recycling", [False, True])
def test_a_large_boxs_gmres_keeps_only_its_basis(monkeypatch, recycling):
    """A box too large to keep its directions' strains (IMAGES_BYTES) and, without recycling, its directions:
    restarted every 4 iterations, the residual carried by the Arnoldi relation and the strain of the solution
    computed by one product at the end. The same eigenstrain as the solve that keeps everything (to 1e-9 of its
    scale, both at 1e-11), the true residual below the tolerance (recomputed here from the operator), one product
    more than the iterations."""
    applied = np.array([1e-3, 0, 0, 0, 2e-4, 0])
    reference = stiff_sphere_problem()
    reference.recycled.kept = 0
    expected = reference.solve(applied, tolerance=1e-11)
    monkeypatch.setattr(equivalent, "IMAGES_BYTES", 0)
    monkeypatch.setattr(equivalent, "GMRES_BYTES", 1)          # the shortest restart (4)
    problem = stiff_sphere_problem()
    if not recycling:
        problem.recycled.kept = 0
    solution = problem.solve(applied, tolerance=1e-11)
    assert solution.success and problem.products == solution.iterations + 1
    assert solution.iterations > 4                              # restarted
    scale = np.abs(expected.eigenstrain).max()
    assert np.abs(solution.eigenstrain - expected.eigenstrain).max() <= 1e-9 * scale
    cells = problem.cells
    strain = problem.operator.strain(solution.eigenstrain)
    assert np.abs(solution.strain - (applied + strain)).max() <= 1e-12 * np.abs(strain).max()
    # (C_I - C_M) D[e*] + C_M e* = (C_M - C_I) e0, i.e. (C_I - C_M) (e0 + D[e*]) + C_M e* = 0
    mismatch = (problem.per_material(problem.contrast, (applied + strain)[cells] * equivalent.MANDEL)
                + (solution.eigenstrain[cells] * equivalent.MANDEL) @ problem.matrix.T)
    right = problem.per_material(problem.contrast, np.broadcast_to(applied, strain.shape)[cells] * equivalent.MANDEL)
    assert np.linalg.norm(mismatch) <= 1e-10 * np.linalg.norm(right)


@pytest.mark.parametrize("inner", [True, False])
def test_recycled_directions_shorten_a_sequence_of_similar_solves(inner):
    """Right-hand sides that change a little from solve to solve (a load moving over the body): the directions
    kept from the earlier solves cut the later ones' products: 9, 8, 7, 6, 5, 5 with the filled cell's system
    solved on the body (the default; 9, 8, 7, 6, 5, 4 with the kernels' values by numpy's forms, which differ by
    4e-15: the last solve's fourth residual sits at the tolerance), 23, 20, 17, 16, 14, 12 with its inverse alone."""
    problem = stiff_sphere_problem()
    problem.inner = inner
    cells = np.array(problem.cells).T
    products = []
    for shift in range(6):
        ramp = np.exp(-0.5 * ((cells[:, 0] - 6.0 - shift) / 4.0) ** 2)[:, None]
        right = ramp * np.array([1, 0.2, -0.3, 0, 0.1, 0]) * 1e8
        before = problem.products
        _, _, iterations, residual, success = problem.solve_for(right, tolerance=1e-9)
        assert success and residual <= 1e-9
        products.append(problem.products - before)
    assert products[0] >= (8 if inner else 18) and products[0] <= (12 if inner else 30)
    assert max(products[3:]) <= 0.75 * products[0] and products[-1] <= 0.6 * products[0]
    snapshot = problem.recycled.snapshot()
    again = equivalent.RecycledSpace(problem.size)
    again.restore(snapshot)
    assert all(np.array_equal(getattr(again, name), getattr(problem.recycled, name))
               for name in ("directions", "strains", "images"))
    images = problem.recycled.images
    assert np.abs(images @ images.T - np.eye(len(images))).max() <= 1e-10


def coupled(schedule, matrix, bodies, tolerance):
    grid = fw.Grid(shape=(48, 40), size=(1.2e-3, 1.0e-3), depth=0.5e-3, layers=20)
    indenter = indenters.FlatPunch(radius=0.2e-3) if isinstance(schedule, schedules.Eccentric) else \
        indenters.Sphere(radius=5e-3)
    return fw.Simulation(grid=grid, material=matrix, indenter=indenter, schedule=schedule, inclusions=bodies,
                         options={"coupling_tolerance": tolerance}).run()


VISCO = materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(1e9, 0.05), (1e9, 0.5)], poisson=0.35)
QUICK = materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(1e9, 0.005), (1e9, 0.02)], poisson=0.35)
ONE = [inclusions.Ellipsoid(center=(0.05e-3, 0.0, 0.15e-3), semi_axes=(0.08e-3,) * 3, material=GLASS)]
TWO = [inclusions.Ellipsoid(center=(-0.13e-3, 0.0, 0.14e-3), semi_axes=(0.08e-3,) * 3, material=GLASS),
       inclusions.Ellipsoid(center=(0.1e-3, 0.04e-3, 0.16e-3), semi_axes=(0.1e-3, 0.08e-3, 0.09e-3),
                            material=materials.Elastic(0.6e9, 0.3))]
PATHS = {
    "static elastic, one body": (schedules.Static(load=[5.0, 10.0]), materials.Elastic(3e9, 0.35), ONE),
    "static viscoelastic, two bodies": (schedules.Static(load=loads.Step(8.0), times=[1e-3, 0.05, 0.4]), VISCO, TWO),
    "eccentric elastic, two bodies": (schedules.Eccentric(load=[6.0], offset=(0.03e-3, 0.0)),
                                      materials.Elastic(3e9, 0.35), TWO),
    "rolling viscoelastic, one body": (schedules.Rolling(load=8.0, velocity=(1e-3, 0.0), distance=0.1e-3), QUICK,
                                       ONE),
}


@pytest.mark.parametrize("path", [name for name in PATHS if "one body" in name])
def test_solving_the_filled_cell_on_the_body_changes_the_products_not_the_answer(path):
    """One body: the Fourier preconditioner solving its filled cell's system on the body's cuboids (the default)
    against its inverse alone (the former preconditioner), at the default coupling tolerance: the same pressure,
    approach, eigenstrains and friction to 1e-6 of their scale, and about half the products or fewer (static, two
    load steps: 14 against 30; rolling, five steps: 36 against 81)."""
    schedule, matrix, bodies = PATHS[path]
    runs, products = {}, {}
    for inner in (True, False):
        grid = fw.Grid(shape=(48, 40), size=(1.2e-3, 1.0e-3), depth=0.5e-3, layers=20)
        indenter = indenters.Sphere(radius=5e-3)
        simulation = fw.Simulation(grid=grid, material=matrix, indenter=indenter, schedule=schedule,
                                   inclusions=bodies, options={"coupling_tolerance": 1e-8})
        problem = simulation._inclusion_problem.problem
        assert problem.inner
        problem.inner = inner
        runs[inner], products[inner] = simulation.run(), problem.products
    for a, b in zip(runs[True].records, runs[False].records):
        assert np.abs(a.pressure - b.pressure).max() <= 1e-6 * b.pressure.max()
        assert np.abs(a.eigenstrain - b.eigenstrain).max() <= 1e-6 * np.abs(b.eigenstrain).max()
        assert a.approach == pytest.approx(b.approach, rel=1e-6)
    if isinstance(schedule, schedules.Rolling):
        friction = runs[False].friction_coefficient
        assert np.abs(runs[True].friction_coefficient - friction).max() <= 1e-6 * np.abs(friction).max()
    assert products[True] <= 0.6 * products[False]


@pytest.mark.parametrize("path", list(PATHS))
def test_every_coupled_path_converges_to_the_tightly_solved_answer(path):
    """Static, eccentric and rolling; elastic and viscoelastic matrices; one and two bodies: the default coupling
    tolerance (1e-8) gives the pressure, friction, approach and eigenstrains of a 1e-12 solve to 1e-6 of their
    scale, as the former nested solves did, and every step's eigenstrains answer its pressure."""
    schedule, matrix, bodies = PATHS[path]
    loose, tight = coupled(schedule, matrix, bodies, 1e-8), coupled(schedule, matrix, bodies, 1e-12)
    for a, b in zip(loose.records, tight.records):
        assert np.abs(a.pressure - b.pressure).max() <= 1e-6 * b.pressure.max()
        assert np.abs(a.eigenstrain - b.eigenstrain).max() <= 1e-6 * np.abs(b.eigenstrain).max()
        assert a.approach == pytest.approx(b.approach, rel=1e-6)
    if isinstance(schedule, schedules.Rolling):
        friction = tight.friction_coefficient
        assert np.abs(loose.friction_coefficient - friction).max() <= 1e-6 * np.abs(friction).max()


def test_rolling_step_products_are_few():
    """A viscoelastic rolling run over a glass sphere: one product per coupling iteration, and few of them (this
    case: 8 and 8 for the rest and the first step, then 8, 7, 7, 7, 6, 6, 5 one cell on each; 8 and 9, then 8, 8,
    7, 7, 7, 6, 6 stopping on the last change alone, below; with the filled cell's inverse alone as the
    preconditioner, 17 and 20, then 20, 17, 13, 12, 12, 10, 9)."""
    grid = fw.Grid(shape=(48, 32), size=(1.2e-3, 0.8e-3), depth=0.4e-3, layers=16)
    body = inclusions.Ellipsoid(center=(0.1e-3, 0.0, 0.14e-3), semi_axes=(0.08e-3,) * 3, material=GLASS)
    simulation = fw.Simulation(grid=grid, material=QUICK, indenter=indenters.Sphere(radius=5e-3),
                               schedule=schedules.Rolling(load=8.0, velocity=(1e-3, 0.0), distance=0.2e-3),
                               inclusions=[body])
    result = simulation.run()
    couplings = np.array([record.couplings for record in result.records])
    assert couplings.max() <= 10 and couplings[-3:].max() <= 8
    # a product per iteration but the last (converged), and one per move for the last eigenstrains' strain
    assert simulation._inclusion_problem.problem.products == couplings.sum() - len(couplings) + len(couplings) - 1


def test_estimated_distance_reads_the_contraction_from_the_residuals():
    """The distance of an iterate from the fixed point: its last change times r / (1 - r), r the ratio of the last
    two residuals, where they fell by CONTRACTION_LIMIT or more; else (a slow or growing residual, the first
    iteration, a change of 1: no displacement yet) the change itself."""
    from framework.inclusions.coupling import CONTRACTION_LIMIT, estimated_distance
    assert estimated_distance(2e-7, 1e-9, 5e-8) == pytest.approx(2e-7 * 0.02 / 0.98, rel=1e-12)
    assert estimated_distance(2e-7, 1e-9, None) == 2e-7
    assert estimated_distance(2e-7, 0.9 * CONTRACTION_LIMIT * 1e-8, 1e-8) < 2e-7
    assert estimated_distance(2e-7, 1.1 * CONTRACTION_LIMIT * 1e-8, 1e-8) == 2e-7
    assert estimated_distance(2e-7, 2e-8, 1e-8) == 2e-7                     # the residual grew
    assert estimated_distance(1.0, 1e-9, 1e-6) == 1.0


def test_the_estimated_distance_stops_a_coupling_earlier_with_the_same_answer(monkeypatch):
    """A step stops once the estimated distance from its fixed point (the last change times the residuals'
    contraction) meets the coupling tolerance, with the residual at that tolerance: against the last change alone
    (CONTRACTION_LIMIT 0), the rolling run of test_rolling_step_products_are_few takes fewer products (61 against 65)
    for the same pressure, eigenstrains, approach and friction to 1e-7 of their scale (measured 1.6e-8; the
    coupling tolerance is 1e-8 of the surface displacement)."""
    from framework.inclusions import coupling
    grid = fw.Grid(shape=(48, 32), size=(1.2e-3, 0.8e-3), depth=0.4e-3, layers=16)
    body = inclusions.Ellipsoid(center=(0.1e-3, 0.0, 0.14e-3), semi_axes=(0.08e-3,) * 3, material=GLASS)
    runs, products, default = {}, {}, coupling.CONTRACTION_LIMIT
    for limit in (default, 0.0):
        monkeypatch.setattr(coupling, "CONTRACTION_LIMIT", limit)
        simulation = fw.Simulation(grid=grid, material=QUICK, indenter=indenters.Sphere(radius=5e-3),
                                   schedule=schedules.Rolling(load=8.0, velocity=(1e-3, 0.0), distance=0.2e-3),
                                   inclusions=[body])
        runs[limit], products[limit] = simulation.run(), simulation._inclusion_problem.problem.products
    estimated, changed = runs[default], runs[0.0]
    gaps = []
    for a, b in zip(estimated.records, changed.records):
        gaps += [np.abs(a.pressure - b.pressure).max() / b.pressure.max(),
                 np.abs(a.eigenstrain - b.eigenstrain).max() / np.abs(b.eigenstrain).max(),
                 abs(a.approach - b.approach) / abs(b.approach)]
    friction = changed.friction_coefficient
    gaps.append(np.abs(estimated.friction_coefficient - friction).max() / np.abs(friction).max())
    assert max(gaps) <= 1e-7
    assert products[default] < products[0.0]


def test_predictor_extrapolates_in_time():
    """The moved step's start: Lagrange's polynomial through the last steps, exact for a quadratic in time on
    unequal steps; the last step's eigenstrain where fewer than two steps are known, where the times do not
    increase, or where the last step is not the one the coupling holds."""
    from framework.inclusions.coupling import predicted
    field = np.random.default_rng(3).normal(size=(5, 6))
    at = [0.1, 0.25, 0.3]
    past = [(t, field * (1.0 + 2.0 * t - 3.0 * t ** 2)) for t in at]
    expected = field * (1.0 + 2.0 * 0.42 - 3.0 * 0.42 ** 2)
    assert np.abs(predicted(past, 0.42, past[-1][1]) - expected).max() <= 1e-12 * np.abs(expected).max()
    linear = predicted(past[1:], 0.42, past[-1][1])
    assert np.abs(linear - (past[2][1] + (past[2][1] - past[1][1]) * 0.12 / 0.05)).max() <= 1e-12
    last = past[-1][1]
    assert predicted(past[-1:], 0.42, last) is last
    assert predicted(past, 0.3, last) is last
    assert predicted(past, 0.42, last + 1.0) is not None and np.array_equal(predicted(past, 0.42, last + 1.0),
                                                                              last + 1.0)


def test_fourier_preconditioner_on_the_boxs_own_lattice_or_the_box_grown_by_a_gap(monkeypatch):
    """Where the bodies' periodic images stay OWN_LATTICE_GAP cuboids apart on the box's own lattice (half the
    padded one), the Fourier preconditioner works there: eight times fewer points, the same solution, at most
    two GMRES iterations more (this glass sphere, 12 cuboids across in a 20 x 20 x 22 box: 9 against 8 on the
    padded lattice, to 1e-10; with the filled cell's inverse alone, not solving its system on the body, 25
    against 24). A box the body fills (margin 0: images touching on the own lattice, 32 there) takes the box
    grown by FOLDED_GAP (12^3 -> 20^3 points instead of 24^3): the same solution, at most two iterations more
    (measured 9 against 9; 26 against 24 with the inverse alone)."""
    applied = np.array([1e-3, 0, 0, 0, 2e-4, 0])
    grid = fw.Grid(shape=(32, 32), size=(0.8e-3, 0.8e-3), depth=0.6e-3, layers=24)
    body = inclusions.Ellipsoid(center=(0.0, 0.0, 0.3e-3), semi_axes=(0.15e-3,) * 3, material=GLASS)
    for margin, chosen in ((0.1e-3, "own"), (0.0, "folded")):
        counts, solutions = {}, {}
        for lattice in (chosen, "padded"):
            problem = InclusionProblem(grid, materials.Elastic(3e9, 0.35), inclusions.InclusionSet([body]),
                                       margin=margin).problem
            assert problem._lattice == chosen and problem.preconditioner == "fourier"
            problem._lattice, problem.recycled.kept = lattice, 0
            solution = problem.solve(applied, tolerance=1e-10)
            assert solution.success
            counts[lattice], solutions[lattice] = solution.iterations, solution.eigenstrain
            shape = problem.operator.lattice_shape(lattice)
            assert problem._fourier[1].matrices.shape[:3] == tuple(n // 2 + 1 for n in shape)
            assert (problem.operator._folded is not None) == (chosen == "folded")     # built only where it serves
        if chosen == "folded":
            assert problem.operator.folded_shape == tuple(fft.even_size(m + FOLDED_GAP) for m in problem.operator.shape)
        assert counts[chosen] <= counts["padded"] + 2 and counts["padded"] <= 11
        assert np.abs(solutions[chosen] - solutions["padded"]).max() <= 1e-8 * np.abs(solutions["padded"]).max()


def test_a_stiff_body_filling_its_box_solves_its_cell_on_the_folded_lattice():
    """A glass sphere of radius 7.4 cuboids in a polymer, in its own 16^3 box (margin 0), to 1e-10: the cell's system
    is solved on the folded lattice (24^3), on the cell's clipped symbol (``equivalent.CLIP_SYMBOL``: unclipped it
    could be indefinite there, and had been moved to the padded lattice, 32^3). Measured: 9 GMRES iterations on either
    lattice; the same solution."""
    h = 1e-5
    grid = fw.Grid(shape=(96, 96), size=(96 * h, 96 * h), depth=48 * h, layers=48)
    body = inclusions.InclusionSet([inclusions.Ellipsoid(center=(0.3 * h, 0.1 * h, 15.2 * h), semi_axes=(7.4 * h,) * 3,
                                                         material=GLASS)])
    applied = np.array([1e-3, 0.0, -1e-3, 0.0, 0.0, 0.0])
    solutions = {}
    for lattice in ("folded", "padded"):
        problem = InclusionProblem(grid, materials.Elastic(3e9, 0.35), body, margin=0.0).problem
        assert problem.operator.shape == (16, 16, 16) and problem.inner and problem._lattice == "folded"
        problem._lattice = lattice
        solutions[lattice] = problem.solve(applied, tolerance=1e-10)
        assert solutions[lattice].success
    assert solutions["folded"].iterations <= 10
    reference = np.abs(solutions["padded"].eigenstrain).max()
    assert np.abs(solutions["folded"].eigenstrain - solutions["padded"].eigenstrain).max() <= 1e-8 * reference


def test_the_filled_cells_symbol_lies_in_the_green_operators_range(monkeypatch):
    """A box's kernels on a periodic lattice are its own, cut off beyond the box: their symbol ``D(q)`` overshoots the
    continuous Green operator's range [0, 1] (eigenvalues in the matrix's energy), on a 16^3 box from -0.027 to 1.102
    (padded lattice) and from -0.055 to 1.082 (folded). The Fourier preconditioner's cell takes it clipped to [0, 1]
    (``equivalent.CLIP_SYMBOL``): its operator ``(C_I - C_M) D + C_M`` stays nonsingular whatever the contrast."""
    grid = fw.Grid(shape=(20, 20), size=(20e-5, 20e-5), depth=20e-5, layers=20)
    operator = HalfSpaceEigenstrain(grid, 0.35, (1, 1, 1), (16, 16, 16))
    unit = equivalent.isotropic_mandel(1.0, 0.35)
    inverse = np.linalg.inv(np.linalg.cholesky(unit))
    contrast = 24.0 * unit
    for lattice in ("padded", "folded"):
        ranges = {}
        for clip in (False, True):
            monkeypatch.setattr(equivalent, "CLIP_SYMBOL", clip)
            cell = equivalent.FourierPreconditioner(operator, contrast, unit, lattice, forward=contrast)
            kernel = (cell.forward - unit) / 24.0                     # the forward operator is contrast D + matrix
            values = np.linalg.eigvalsh(np.einsum("ab,...bc,dc->...ad", inverse, kernel, inverse))
            ranges[clip] = values.min(), values.max()
        assert ranges[False][0] < -0.02 and ranges[False][1] > 1.05
        assert -1e-12 <= ranges[True][0] and ranges[True][1] <= 1.0 + 1e-12


@pytest.mark.parametrize("case", ["soft", "glass"])
def test_the_cells_system_on_a_clipped_symbol_is_solved_in_few_iterations(monkeypatch, case):
    """The bodies' system in the filled cell (the inner solve, on the folded lattice) with the cell's symbol clipped
    and not: a body 0.05 times as stiff as steel, and a glass sphere in a polymer, each filling a 16^3 box (margin 0),
    to 1e-10. Measured: 74 against 152 transforms of the cell, 68 against 200; the same solution."""
    h = 1e-5
    grid = fw.Grid(shape=(20, 20), size=(20 * h, 20 * h), depth=20 * h, layers=20)
    matrix, body = ((materials.Elastic(210e9, 0.3), materials.Elastic(10.5e9, 0.3)) if case == "soft"
                    else (materials.Elastic(3e9, 0.35), GLASS))
    sphere = inclusions.InclusionSet([inclusions.Ellipsoid(center=(0.0, 0.0, 9 * h), semi_axes=(8 * h * (1 - 1e-9),) * 3,
                                                           material=body)])
    filled = equivalent.EquivalentInclusionProblem._filled
    counts, solutions = {}, {}
    for clip in (False, True):
        monkeypatch.setattr(equivalent, "CLIP_SYMBOL", clip)
        calls = []
        monkeypatch.setattr(equivalent.EquivalentInclusionProblem, "_filled",
                            lambda self, *args, **kwargs: calls.append(1) or filled(self, *args, **kwargs))
        problem = InclusionProblem(grid, matrix, sphere, margin=0.0, recycle=False).problem
        assert problem.inner and problem._lattice == "folded"
        solution = problem.solve(np.array([1e-3, 0.0, -1e-3, 0.0, 0.0, 0.0]), tolerance=1e-10)
        assert solution.success
        counts[clip], solutions[clip] = len(calls), solution.eigenstrain
    assert counts[True] <= 90 and counts[True] < counts[False] / 2
    scale = np.abs(solutions[True]).max()
    assert np.abs(solutions[True] - solutions[False]).max() <= 1e-8 * scale


def test_the_folded_kernels_are_built_only_where_the_preconditioner_takes_that_lattice():
    """Bodies filling their box: a glass sphere in a polymer (the Fourier preconditioner, on the folded lattice) builds
    the kernels on the folded lattice; two spheres of different materials (preconditioned cuboid by cuboid) build none
    (they had been built for nothing: a fifth of the padded ones' memory, 13 % of a 109 x 109 x 28 box's build)."""
    h = 1e-5
    grid = fw.Grid(shape=(96, 96), size=(96 * h, 96 * h), depth=48 * h, layers=48)
    polymer, soft_glass = materials.Elastic(3e9, 0.35), materials.Elastic(20e9, 0.22)

    def made(*bodies):
        spheres = inclusions.InclusionSet([inclusions.Ellipsoid(center=(0.3 * h + 16 * h * k, 0.1 * h, 15.2 * h),
                                                                semi_axes=(7.4 * h,) * 3, material=body)
                                           for k, body in enumerate(bodies)])
        problem = InclusionProblem(grid, polymer, spheres, margin=0.0).problem
        return problem.preconditioner, problem.operator._folded is not None, problem.operator.folded_shape

    assert made(GLASS) == ("fourier", True, (24, 24, 24))
    assert made(GLASS, soft_glass) == ("local", False, (64, 32, 32))


@pytest.mark.parametrize("lattice", ["own", "folded"])
def test_folded_kernels_are_the_padded_kernels_summed_over_the_periods(lattice):
    """The infinite-space kernels on a preconditioner's periodic cell equal the padded lattice's kernels taken back
    to offsets by numpy's inverse FFT, summed modulo the cell and transformed again (to 1e-12 of the largest);
    the parities of the entries are those of their components' indices."""
    grid, operator = box_case((24, 20), 16, (3, 2, 2), (13, 11, 12), False)
    padded, cell = operator.fft_shape, operator.lattice_shape(lattice)
    assert all(m <= n < N for m, n, N in zip(operator.shape, cell, padded))
    stored, (first, second), _ = operator.infinite_spectra("padded")
    folded = operator.infinite_spectra(lattice)[0]
    assert folded.shape == (21, *(n // 2 + 1 for n in cell))

    def full(factor, parities, shape):      # the whole DFT of an entry from its real factor on q >= 0
        index = np.ix_(*[np.minimum(np.arange(n), n - np.arange(n)) for n in shape])
        signs = [np.where(np.arange(n) > n // 2, p, 1.0) for n, p in zip(shape, parities)]
        phase = (-1j) ** sum(p < 0 for p in parities)
        return factor[index] * signs[0][:, None, None] * signs[1][None, :, None] * signs[2][None, None, :] * phase

    for e, (a, b) in enumerate(zip(first, second)):
        components = equivalent.COMPONENTS[a] + equivalent.COMPONENTS[b]
        parities = [(-1.0) ** components.count(axis) for axis in range(3)]
        values = np.fft.ifftn(full(stored[e], parities, padded))
        assert np.abs(values.imag).max() <= 1e-12 * np.abs(values.real).max()
        offsets = [np.where(np.arange(N) > N // 2, np.arange(N) - N, np.arange(N)) % n for N, n in zip(padded, cell)]
        summed = np.zeros(cell)
        np.add.at(summed, np.ix_(*offsets), values.real)
        expected = np.fft.fftn(summed)
        got = full(folded[e], parities, cell)
        assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()


@pytest.mark.parametrize("path", ["keys together", "one key at a time"])
def test_compiled_closed_forms_give_the_kernels_of_the_numpy_ones(monkeypatch, path):
    """The kernels' lattices evaluated compiled equal the numpy forms' to 1e-12 of their largest value: the loop
    over all 21 keys at once (compiled_lattice, from COMPILED_LATTICE_POINTS points while their values fit in
    LATTICE_KEYS_BYTES) and the numba ufuncs one key at a time (lattice_forms, larger lattices from
    COMPILED_FORMS_POINTS); here both from any size (measured 4e-15 and 1.4e-13 on a 64^3 box's lattices)."""
    pytest.importorskip("numba")
    from framework.operators import eigenstrain
    together = path == "keys together"
    monkeypatch.setattr(eigenstrain, "COMPILED_LATTICE_POINTS", 0)
    monkeypatch.setattr(eigenstrain, "COMPILED_FORMS_POINTS", 0)
    if not together:
        monkeypatch.setattr(eigenstrain, "LATTICE_KEYS_BYTES", 0)
    grid = fw.Grid(shape=(16, 14), size=(16e-6, 14e-6), depth=12e-6, layers=12)
    spectra = {}
    for flag in (True, False):
        with _fused.use_compiled(flag):
            assert (eigenstrain.compiled_lattice(1000) is not None) is (flag and together)
            assert (eigenstrain.lattice_forms(1) is eigenstrain.CORNER_FORMS) is not flag
            operator = HalfSpaceEigenstrain(grid, 0.3, (2, 1, 1), (11, 9, 10))
            spectra[flag] = (operator._direct, operator._mirror)
    for compiled, plain in zip(spectra[True], spectra[False]):
        assert np.abs(compiled - plain).max() <= 1e-12 * np.abs(plain).max()


def test_a_dispersion_is_preconditioned_by_a_share_of_its_contrast():
    """The Fourier preconditioner fills the box with the bodies' material, matrix between them included: one body
    (FOURIER_BODIES) at its own contrast with the matrix, more at DISPERSION_CONTRAST of it (60 glass spheres at
    10 % in a polymer did not converge in 500 iterations at their own, 16 at 0.3, 28 cuboid by cuboid:
    bench/dispersion.py's case; 12 at 20 % under a contact did not converge in 100 couplings). The bodies' system
    in that cell, solved on their cuboids (the default), uses the filled cell at their own contrast and its
    inverse at the share. Here 17 glass spheres, to 1e-10: 9 iterations; with the cell's inverse alone 21 at the
    share and 25 at their own contrast (28 before the kernels were folded), 37 cuboid by cuboid (the inner solve
    at the bodies' own contrast throughout: 10)."""
    grid = fw.Grid(shape=(40, 40), size=(40e-6, 40e-6), depth=12e-6, layers=12)
    centres = [(x, y, 6e-6) for x in np.arange(-15e-6, 16e-6, 10e-6) for y in np.arange(-15e-6, 16e-6, 10e-6)]
    spheres = [inclusions.Ellipsoid(center=c, semi_axes=(3e-6,) * 3, material=GLASS) for c in centres]
    matrix = materials.Elastic(3e9, 0.35)
    assert equivalent.FOURIER_BODIES == 1
    one = InclusionProblem(grid, matrix, inclusions.InclusionSet(spheres[:1])).problem
    assert one.preconditioner == "fourier" and one._share == 1.0
    spheres.append(inclusions.Ellipsoid(center=(0.0, 0.0, 6e-6), semi_axes=(3e-6,) * 3, material=GLASS))
    counts, solutions = {}, {}
    for name, share, inner in (("fourier", None, True), ("fourier", None, False), ("local", None, False),
                               ("fourier", 1.0, False)):
        many = InclusionProblem(grid, matrix, inclusions.InclusionSet(spheres)).problem
        assert many.preconditioner == "fourier" and many._share == equivalent.DISPERSION_CONTRAST and many.inner
        many.preconditioner, many.recycled.kept, many.inner = name, 0, inner
        if share is not None:
            many._share = share
        solution = many.solve(np.array([1e-3, 0, -1e-3, 0, 0, 0]), tolerance=1e-10)
        counts[name, share, inner], solutions[name, share, inner] = solution.iterations, solution.eigenstrain
    alone = counts["fourier", None, False]
    assert counts["fourier", None, True] <= 10 and counts["fourier", None, True] <= 0.5 * alone
    assert alone <= 23 and alone < 0.7 * counts["local", None, False] and alone < counts["fourier", 1.0, False]
    scale = np.abs(solutions["local", None, False]).max()
    for key in solutions:
        assert np.abs(solutions[key] - solutions["local", None, False]).max() <= 1e-8 * scale


def test_a_large_box_may_give_its_preconditioner_memory_by_the_cuboid(monkeypatch):
    """The Fourier preconditioner's matrices fit in FOURIER_BYTES, or in FOURIER_CUBOID_BYTES a box cuboid where that
    is more (a large dispersion's box: 300 glass spheres at 8 cuboids per radius had 32 products a step cuboid by
    cuboid). Here the 17 glass spheres of the test above with FOURIER_BYTES below their matrices: cuboid by cuboid
    without the allowance (37 iterations to 1e-10), the Fourier cell's system on the bodies with it (9)."""
    grid = fw.Grid(shape=(40, 40), size=(40e-6, 40e-6), depth=12e-6, layers=12)
    centres = [(x, y, 6e-6) for x in np.arange(-15e-6, 16e-6, 10e-6) for y in np.arange(-15e-6, 16e-6, 10e-6)]
    spheres = [inclusions.Ellipsoid(center=c, semi_axes=(3e-6,) * 3, material=GLASS) for c in [*centres, (0, 0, 6e-6)]]
    matrix = materials.Elastic(3e9, 0.35)
    monkeypatch.setattr(equivalent, "FOURIER_BYTES", 1024)
    counts = {}
    for per_cuboid in (0, 600):     # (a small box on its folded lattice: 504 bytes a cuboid with the transforms)
        monkeypatch.setattr(equivalent, "FOURIER_CUBOID_BYTES", per_cuboid)
        problem = InclusionProblem(grid, matrix, inclusions.InclusionSet(spheres)).problem
        lattice = problem.operator.lattice_shape(problem._lattice)
        n1, n2, n3 = lattice
        needed = (2 * (n1 // 2 + 1) * (n2 // 2 + 1) * (n3 // 2 + 1) * 36 * 8      # the inverse and the operator
                  + (problem.operator.transform_bytes("folded") if problem._lattice == "folded" else 0))
        assert (needed <= per_cuboid * np.prod(problem.operator.shape)) == (per_cuboid > 0)
        assert (problem.preconditioner, problem.inner) == (("fourier", True) if per_cuboid else ("local", False))
        problem.recycled.kept = 0
        counts[per_cuboid] = problem.solve(np.array([1e-3, 0, -1e-3, 0, 0, 0]), tolerance=1e-10).iterations
    assert counts[600] <= 10 and counts[0] >= 30


def test_max_couplings_is_an_option():
    """``Options.max_couplings`` bounds a step's coupling iterations (None: 100): a step that needs more raises
    ConvergenceError naming the option; it is checked as a positive integer before any step."""
    schedule, matrix, bodies = PATHS["static elastic, one body"]
    with pytest.raises(fw.errors.ConvergenceError, match="Options.max_couplings"):
        fw.Simulation(grid=fw.Grid(shape=(48, 40), size=(1.2e-3, 1.0e-3), depth=0.5e-3, layers=20), material=matrix,
                      indenter=indenters.Sphere(radius=5e-3), schedule=schedule, inclusions=bodies,
                      options={"max_couplings": 2}).run()
    for bad in (0, -3, 2.5, True, "10"):
        with pytest.raises(fw.errors.ParameterError, match="max_couplings"):
            fw.Options(max_couplings=bad)
    assert fw.Options().max_couplings is None and fw.Options(max_couplings=250).max_couplings == 250


@pytest.mark.parametrize("case", [BOXES[1], BOXES[3]])
def test_pressure_stress_on_a_window_equals_the_whole_grids(case, monkeypatch):
    """The contact's stress at the box from transforms over the loaded cells and the footprint (grown by the slack)
    equals the whole grid's map to 1e-12: a compact pressure beside the box, one that grows out of the window (a new
    window), one over the whole grid (the grid's map), and after the box moved (a rolling box)."""
    from framework.operators import eigenstrain as module
    monkeypatch.setattr(module, "PRESSURE_WINDOW_SLACK", 2)      # (the test's grids are small)
    grid, operator = box_case(*case)
    rng = np.random.default_rng(5)
    whole = operator._grid_map()
    patches = [(slice(2, 9), slice(3, 8)), (slice(1, 20), slice(2, 25)), (slice(0, grid.shape[0]),
                                                                           slice(0, grid.shape[1]))]
    for step, patch in enumerate(patches):
        if case[-1] and step == 1:
            operator.move((2, -1))
        pressure = np.zeros(grid.shape)
        pressure[patch] = rng.random(pressure[patch].shape) * 1e6
        expected = whole.box_stress(whole.spectrum(pressure))
        windowed = operator.pressure_stress(pressure)
        assert np.abs(windowed - expected).max() <= 1e-12 * np.abs(expected).max()
        if step == 0:       # a window smaller than the grid was used
            assert operator._pressure_surface is not whole
            union = max(9, operator.start[0] + operator.shape[0]) - min(2, operator.start[0])
            assert operator._pressure_surface.size[0] <= union + 2 * module.PRESSURE_WINDOW_SLACK < grid.shape[0]
    assert not operator.pressure_stress(np.zeros(grid.shape)).any()


@pytest.mark.parametrize("path", ["static elastic, one body", "rolling viscoelastic, one body"])
def test_a_large_boxs_coupling_keeps_its_iterates_on_the_bodies(path, monkeypatch):
    """Iterates whose strains are kept on the bodies' cuboids only (a box too large for ANDERSON_BYTES), and the
    next step's start on an unmoved box by one product: the same pressure, eigenstrain and stress as the
    iterates kept on the whole box, both solved to a coupling tolerance of 1e-10, to 1e-7 of their scale (rounding
    of the combined strains against a fresh product steers a step one iteration apart at times; at the default 1e-8
    they differ by up to 5e-6, within its inclusion tolerance 1e-7)."""
    from framework.inclusions import coupling
    schedule, matrix, bodies = PATHS[path]
    solve = coupling.ContactCoupling.solve

    def run():
        steps = []

        def counted(self, solve_contact):
            step = solve(self, solve_contact)
            steps.append(step.couplings)
            return step
        monkeypatch.setattr(coupling.ContactCoupling, "solve", counted)
        grid = fw.Grid(shape=(48, 40), size=(1.2e-3, 1.0e-3), depth=0.5e-3, layers=20)
        sim = fw.Simulation(grid=grid, material=matrix, indenter=indenters.Sphere(radius=5e-3), schedule=schedule,
                            inclusions=bodies, options={"coupling_tolerance": 1e-10})
        return sim.run(), sim._inclusion_problem.problem.products, steps

    whole, products, steps = run()
    monkeypatch.setattr(coupling, "ANDERSON_BYTES", 0)
    cells, cell_products, cell_steps = run()
    assert len(cell_steps) == len(steps) and max(abs(a - b) for a, b in zip(steps, cell_steps)) <= 1
    # no product after the last iteration: the next step on an unmoved box computes its start's strain by one
    # (measured: static 39 products for 42 iterations kept whole, 41 on the bodies; rolling 103 and 101 for 104, 102)
    unmoved = len(steps) - 1 if path.startswith("static") else 0
    assert cell_products - sum(cell_steps) == products - sum(steps) + unmoved
    for step in range(len(whole.times)):
        for name in ("pressure", "eigenstrain", "inclusion_stress"):
            a, b = getattr(whole.records[step], name), getattr(cells.records[step], name)
            assert np.abs(a - b).max() <= 1e-7 * np.abs(a).max()


def test_square_boxes_store_half_the_kernels():
    """Cuboids square in x1, x2 and a nearly square padded lattice (within SQUARE_LATTICE_RATIO): the lattice made
    square and the kernels of q1 <= q2 stored, (Q + 1) / 2Q of them; cuboids that are not square, or a lattice
    further from square, keep every kernel. The products agree with the direct sums
    (test_product_equals_direct_sums_on_boxes_of_several_shapes)."""
    from framework.operators.eigenstrain import box_lattice
    assert box_lattice((30, 31, 30), (1.0, 1.0, 1.0)) == ((64, 64, 60), True)          # 60 x 64 -> 64 x 64
    assert box_lattice((30, 31, 30), (1.0, 1.1, 1.0)) == ((60, 64, 60), False)
    assert box_lattice((20, 31, 30), (1.0, 1.0, 1.0)) == ((40, 64, 60), False)
    sizes = {}
    for square in (False, True):
        grid = fw.Grid(shape=(40, 40), size=(40e-4, 40e-4 * (1.0 if square else 1.1)), depth=16 * 0.9e-4, layers=16)
        operator = HalfSpaceEigenstrain(grid, NU, (5, 9, 3), (15, 15, 6))
        assert operator.symmetric == square and operator.fft_shape == (30, 30, 12)
        sizes[square] = sum(part.nbytes for block in operator._kernel_blocks.values() for part in block)
    q = 30 // 2 + 1
    assert sizes[True] * 2 * q == sizes[False] * (q + 1)
