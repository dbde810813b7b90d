"""The contact solver converges on every valid contact, from one cell to a hundred.

For each grid (open and doubly periodic, odd and even sizes) a sphere is
pressed over a band of loads whose Hertz contact grows from well under one
cell to about a hundred cells. Every solve must converge, the contact area
must never shrink as the load grows, and the solution must satisfy
complementarity and force balance when checked with an influence operator
built here, independently of ``framework.operators``:

* open grids: Love's closed form for the normal displacement of a uniformly
  loaded rectangle, summed directly over the loaded cells (no FFT);
* doubly periodic grids: the kernel ``2/|q|`` turned into a real-space
  influence function by an explicit discrete Fourier sum (dense matrices of
  complex exponentials, no FFT).
"""
import numpy as np
import pytest

import framework as fw
from framework import indenters, loads, materials, schedules
from framework.operators.surface import SurfaceCompliance

STEEL = materials.Elastic(young=210e9, poisson=0.3)
SIDE = 1.2e-3          # m, grid side
RADIUS = 10e-3         # m, the README's steel ball
TOLERANCE = dict(tolerance=1e-10, residual_tolerance=1e-8)


def love_influence(dx1, dx2, offsets1, offsets2):
    """``K`` (per unit contact compliance) of a unit pressure on a ``dx1 x dx2`` cell, Love (1929).

    ``u3 = C* / pi * sum_corners F(X, Y)`` with ``F = X asinh(Y/X) + Y asinh(X/Y)``
    (Johnson 1985, eq. 3.25, written with asinh, which is finite on the cell
    edges; ``F = 0`` where ``X`` or ``Y`` vanishes).
    """
    def f(x, y):
        with np.errstate(divide="ignore", invalid="ignore"):
            a = np.where(x != 0, x * np.arcsinh(y / np.where(x != 0, np.abs(x), 1.0)), 0.0)
            b = np.where(y != 0, y * np.arcsinh(x / np.where(y != 0, np.abs(y), 1.0)), 0.0)
        return a + b

    h1, h2 = dx1 / 2, dx2 / 2
    return (f(offsets1 + h1, offsets2 + h2) - f(offsets1 + h1, offsets2 - h2)
            - f(offsets1 - h1, offsets2 + h2) + f(offsets1 - h1, offsets2 - h2)) / np.pi


def test_love_influence_against_quadrature():
    # the kernel above, checked by quadrature of 1/(pi r) over the cell, and at the centre of the
    # unit square against int 1/r dA = 4 ln(1 + sqrt 2)
    from scipy import integrate
    assert love_influence(1.0, 1.0, np.array(0.0), np.array(0.0)) == pytest.approx(4 * np.log(1 + np.sqrt(2)) / np.pi,
                                                                                  rel=1e-14)
    for x, y in [(1.3, 0.4), (-2.0, 3.0), (0.0, 1.5)]:
        value = integrate.dblquad(lambda t, s: 1 / (np.pi * np.hypot(x - s, y - t)), -0.5, 0.5, -0.5, 0.5,
                                  epsabs=1e-11)[0]
        assert love_influence(1.0, 1.0, np.array(x), np.array(y)) == pytest.approx(value, rel=1e-7)


def periodic_influence(grid):
    """Real-space influence of one cell on a doubly periodic grid: ``(1/N) sum_q (2/|q|) e^{i q x}``."""
    n1, n2 = grid.shape
    m1, m2 = np.fft.fftfreq(n1) * n1, np.fft.fftfreq(n2) * n2
    q = np.hypot(*np.meshgrid(2 * np.pi * m1 / grid.size[0], 2 * np.pi * m2 / grid.size[1], indexing="ij"))
    spectrum = np.where(q > 0, 2.0 / np.where(q > 0, q, 1.0), 0.0)
    d1 = np.exp(2j * np.pi * np.outer(np.arange(n1), m1) / n1)   # offsets x modes
    d2 = np.exp(2j * np.pi * np.outer(np.arange(n2), m2) / n2)
    return (d1 @ spectrum @ d2.T).real / (n1 * n2)                # indexed by wrapped offsets


def displacement(grid, pressure):
    """``K * p`` [Pa m] by direct summation over the loaded cells."""
    x1, x2 = grid.coordinates()
    loaded = np.flatnonzero(pressure.ravel())
    out = np.zeros(grid.shape)
    if all(grid.periodic):
        kernel = periodic_influence(grid)
        i1, i2 = np.indices(grid.shape)
        for j in loaded:
            j1, j2 = divmod(j, grid.shape[1])
            out += pressure.flat[j] * kernel[(i1 - j1) % grid.shape[0], (i2 - j2) % grid.shape[1]]
        return out
    for j in loaded:
        out += pressure.flat[j] * love_influence(*grid.spacing, x1 - x1.flat[j], x2 - x2.flat[j])
    return out


def load_band(grid, cells=100):
    """Loads [N] from a Hertz contact of radius 0.3 dx to one of ``cells`` cells in area."""
    dx = grid.spacing[0]
    radii = np.geomspace(0.3 * dx, np.sqrt(cells / np.pi) * dx, 24)
    return 4 * STEEL.contact_modulus * radii**3 / (3 * RADIUS)


def check_solution(grid, record, load, offset=None):
    p = record.pressure
    assert record.success
    assert np.all(p >= 0)
    assert p.sum() * grid.cell_area == pytest.approx(load, rel=1e-10)
    u = displacement(grid, p) / STEEL.contact_modulus
    np.testing.assert_allclose(u, record.displacement, rtol=0, atol=1e-9 * np.abs(u).max())
    heights = indenters.Sphere(radius=RADIUS).on_grid(grid)
    x1, x2 = grid.coordinates()
    slope1, slope2 = np.tan(record.tilt)
    gap = heights + u - (record.approach + slope1 * x1 + slope2 * x2)
    if offset is not None:  # both moments balance: the load acts at the offset
        np.testing.assert_allclose([(p * x1).sum() / p.sum(), (p * x2).sum() / p.sum()], offset,
                                   rtol=0, atol=1e-10 * grid.spacing[0])
    scale = np.abs(u).max()
    contact = p > 0
    if not contact.any():
        assert load == 0 and gap.min() >= 0
        return
    assert np.abs(gap[contact]).max() <= 1e-6 * scale
    assert gap[~contact].min() >= -1e-6 * scale


GRIDS = [((32, 32), False), ((33, 33), False), ((64, 64), False), ((65, 65), False),
         ((17, 17), True), ((31, 31), True), ((32, 32), True), ((33, 33), True), ((32, 33), True)]


@pytest.mark.parametrize("shape, periodic", GRIDS, ids=[f"{s[0]}x{s[1]}-{'periodic' if p else 'open'}"
                                                        for s, p in GRIDS])
def test_every_load_from_one_cell_to_a_hundred_converges(shape, periodic):
    grid = fw.Grid(shape=shape, size=(SIDE, SIDE * shape[1] / shape[0]), periodic=(periodic, periodic))
    band = load_band(grid)
    warm = fw.Simulation(grid=grid, material=STEEL, indenter=indenters.Sphere(radius=RADIUS),
                         schedule=schedules.Static(load=band), options=TOLERANCE).run()
    areas = warm.contact_area
    assert areas[0] <= 4 * grid.cell_area and areas[-1] >= 90 * grid.cell_area  # the apex: 1, 2 or 4 cells
    assert np.all(np.diff(areas) >= 0), f"contact area shrank: {areas / grid.cell_area}"
    for record, load in zip(warm.records, band):
        check_solution(grid, record, load)
    for load in band[::3]:  # cold starts, each from the solver's own initial guess
        cold = fw.Simulation(grid=grid, material=STEEL, indenter=indenters.Sphere(radius=RADIUS),
                             schedule=schedules.Static(load=load), options=TOLERANCE).run()
        check_solution(grid, cold.records[0], load)
        np.testing.assert_allclose(cold.pressure(0), warm.pressure(int(np.flatnonzero(band == load)[0])),
                                   rtol=0, atol=1e-6 * cold.max_pressure[0])


@pytest.mark.parametrize("shape", [(33, 33), (32, 32)])
@pytest.mark.parametrize("offset", [(0.3, 0.0), (1.7, -0.6)])
def test_eccentric_sphere_band(shape, offset):
    """A sphere carries an offset load at any size: it tilts, and its contact rolls to the load."""
    grid = fw.Grid(shape=shape, size=(SIDE, SIDE))
    offset = tuple(np.multiply(offset, grid.spacing))
    band = load_band(grid)[::2]
    for load in band:
        result = fw.Simulation(grid=grid, material=STEEL, indenter=indenters.Sphere(radius=RADIUS),
                               schedule=schedules.Eccentric(load=load, offset=offset), options=TOLERANCE).run()
        check_solution(grid, result.records[0], load, offset)


@pytest.mark.parametrize("shape", [(33, 33), (32, 32)])
def test_approach_control_band(shape):
    grid = fw.Grid(shape=shape, size=(SIDE, SIDE))
    dx = grid.spacing[0]
    approaches = np.geomspace((0.3 * dx) ** 2, 30 * dx**2, 20) / RADIUS
    result = fw.Simulation(grid=grid, material=STEEL, indenter=indenters.Sphere(radius=RADIUS),
                           schedule=schedules.Static(approach=approaches), options=TOLERANCE).run()
    assert np.all(np.diff(result.contact_area) >= 0)
    for record in result.records:
        check_solution(grid, record, record.load)


def test_kelvin_voigt_ramp_starts_from_a_one_cell_contact():
    grid = fw.Grid(shape=(33, 33), size=(SIDE, SIDE))
    solid = materials.KelvinVoigt(young=2e9, viscosity=2e9, poisson=0.4)
    result = fw.Simulation(grid=grid, material=solid, indenter=indenters.Sphere(radius=RADIUS),
                           schedule=schedules.Static(load=loads.Ramp(end=5.0, duration=1.0),
                                                     times=np.linspace(0.01, 1.0, 12))).run()
    assert result.records[0].success and np.count_nonzero(result.pressure(0)) >= 1
    assert np.all(np.diff(result.contact_area) >= 0)


@pytest.mark.parametrize("n", [17, 31, 33, 35, 63, 99])
def test_odd_periodic_operator_is_the_full_complex_fft_of_two_over_q(n):
    grid = fw.Grid(shape=(n, n + 2), size=(1.0, (n + 2) / n), periodic=(True, True))
    operator = SurfaceCompliance(grid)
    rng = np.random.default_rng(n)
    a, b = rng.random(grid.shape), rng.random(grid.shape)
    q = np.hypot(*np.meshgrid(2 * np.pi * np.fft.fftfreq(n, 1 / n), 2 * np.pi * np.fft.fftfreq(n + 2, 1 / n),
                              indexing="ij"))
    spectrum = np.where(q > 0, 2 / np.where(q > 0, q, 1.0), 0.0)
    full = np.fft.ifft2(spectrum * np.fft.fft2(a))
    assert np.abs(full.imag).max() < 1e-13 * np.abs(full.real).max()
    np.testing.assert_allclose(operator.apply(a), full.real, rtol=0, atol=1e-13 * np.abs(full.real).max())
    assert np.sum(b * operator.apply(a)) == pytest.approx(np.sum(a * operator.apply(b)), rel=1e-13)


@pytest.mark.slow
@pytest.mark.parametrize("shape, periodic", [((127, 127), False), ((128, 128), False), ((129, 129), True),
                                             ((256, 256), True)])
def test_band_on_larger_grids(shape, periodic):
    """The same band on grids of the sizes users run (a minute in all: make test-all)."""
    grid = fw.Grid(shape=shape, size=(SIDE, SIDE), periodic=(periodic, periodic))
    band = load_band(grid, cells=400)
    result = fw.Simulation(grid=grid, material=STEEL, indenter=indenters.Sphere(radius=RADIUS),
                           schedule=schedules.Static(load=band), options=TOLERANCE).run()
    assert np.all(np.diff(result.contact_area) >= 0)
    for record, load in list(zip(result.records, band))[::4]:
        check_solution(grid, record, load)


def test_a_periodic_load_controlled_solve_starts_near_the_contact(monkeypatch):
    """On a doubly periodic grid a uniform pressure makes no displacement, so the start cannot be chosen
    by it: it is the cells within 4 times the displacement the load would make on an open square of the
    grid's area. The start must hold the contact and leave most of the grid out (before: the whole grid,
    51 iterations for a Hertz solve on 1024^2 cells instead of 24)."""
    from framework import solver
    grid = fw.Grid(shape=(128, 128), size=(2e-3, 2e-3), periodic=(True, True))
    heights = indenters.Sphere(radius=10e-3).on_grid(grid)
    operator = SurfaceCompliance(grid)
    starts = []
    iterate = solver._iterate
    monkeypatch.setattr(solver, "_iterate", lambda problem, pressure: starts.append(pressure.copy())
                        or iterate(problem, pressure))
    solution = fw.solve_normal(lambda p: operator.apply(p, 1e-9), heights, cell_area=grid.cell_area, load=2.0)
    start = starts[0] > 0
    assert np.all(start[solution.pressure > 0]) and start.mean() < 0.5
    assert solution.success and 0.02 < np.mean(solution.pressure > 0) < 0.2
