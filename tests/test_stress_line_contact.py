"""Subsurface stresses on grids periodic along one axis (line contacts).

The operator sums Love's rectangle coefficients over the periodic images of
each cell (``kernels.periodic_subsurface_stress``: plane-strain strip plus
tapered image sums). It is checked against

* direct image sums written here: ``M`` images of Love's rectangle on each
  side, the images beyond replaced by the strip minus the band they cover,
  each smeared over its period (error ~1/M^3: 4e-14 at M = 3000);
* the plane-strain closed forms of :mod:`framework.reference.plane_strain`
  (uniform strip, McEwen's Hertz line contact), themselves checked against
  quadrature of Flamant's line load, which is checked against the
  Boussinesq point load integrated along the line;
* symmetry and equilibrium.

Measured when written: kernel vs direct image sums <= 1.7e-13 (relative to
the pressure, 4e-14 of it the direct sums' own truncation); operator vs direct
sums over cells and images <= 3.6e-13; band of cells vs the strip <= 4e-16;
period mean, mirror symmetries, transposition <= 5e-16; Hertz line contact from the framework's own
solve vs McEwen, max over all components at depths 0.25 b .. 2.75 b:
9.0e-4 p0 at 12 cells per half-width, 1.6e-4 at 24, 3.2e-5 at 48 (order 2.5
then 2.3, the error largest at the shallowest layer).
"""
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

import framework as fw
from framework import indenters, materials, reference, schedules
from framework.errors import ParameterError, ShapeError
from framework.operators import SubsurfaceStress
from framework.operators.kernels import periodic_subsurface_stress, strip_stress, subsurface_stress

NU = 0.3
# sign of each Voigt component under x1 -> -x1 and under x2 -> -x2
X1_PARITY = np.array([1, 1, 1, 1, -1, -1])
X2_PARITY = np.array([1, 1, 1, -1, 1, -1])
SWAP = [1, 0, 2, 4, 3, 5]  # Voigt components seen from transposed axes


def image_sum(x1, x2, x3, *, half1, half2, cells, images=3000):
    """Love's rectangle summed directly over its images ``x2 + m L``, ``|m| <= images``.

    ``x1`` (and the stress) may carry leading axes of cells to sum over; the
    images beyond ``images`` periods are smeared over their periods: the
    plane-strain strip minus the band ``|y - x2| < (images + 1/2) L``, with
    pressure ``1/cells``.
    """
    period = 2 * half2 * cells
    m = np.arange(-images, images + 1)
    x1, x2 = np.asarray(x1, dtype=float)[..., None], np.asarray(x2, dtype=float)[..., None]
    direct = subsurface_stress(x1, x2 + m * period, x3, half1=half1, half2=half2, poisson=NU).sum(axis=-2)
    band = subsurface_stress(x1, x2, x3, half1=half1, half2=(images + 0.5) * period, poisson=NU)[..., 0, :]
    strip = reference.strip_stress(x1[..., 0], x3, half_width=half1, pressure=1.0, poisson=NU)
    return direct + (strip - band) / cells


def test_bad_arguments_are_named():
    with pytest.raises(ParameterError, match=r"cells must be an integer >= 1, got 0"):
        periodic_subsurface_stress(np.zeros(3), 0.0, half1=0.5, half2=0.5, cells=0, poisson=NU)
    with pytest.raises(ParameterError, match=r"x3 must be >= 0 \[m\], got -1.0"):
        periodic_subsurface_stress(np.zeros(3), -1.0, half1=0.5, half2=0.5, cells=2, poisson=NU)
    with pytest.raises(ShapeError, match=r"x1 must have 1 dimensions, got shape \(2, 2\)"):
        periodic_subsurface_stress(np.zeros((2, 2)), 0.0, half1=0.5, half2=0.5, cells=2, poisson=NU)
    with pytest.raises(ParameterError, match=r"x3 must be >= 0 \[m\] \(depth into the solid\), got minimum -0.5"):
        reference.hertz_line_stress(0.0, -0.5, half_width=1.0, max_pressure=1.0, poisson=NU)
    with pytest.raises(ParameterError, match=r"max_pressure must be positive \[Pa\], got -1.0"):
        reference.hertz_line_stress(0.0, 0.5, half_width=1.0, max_pressure=-1.0, poisson=NU)


def line_grid(shape, periodic, spacing=(1.0, 0.7), **layers):
    return fw.Grid(shape=shape, size=(shape[0] * spacing[0], shape[1] * spacing[1]), periodic=periodic, **layers)


# ---------------------------------------------------------------------------
# the plane-strain references
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("x1, x3", [(0.0, 0.5), (0.7, 0.2), (-1.5, 2.0), (3.0, 0.1)])
def test_flamant_line_load_is_the_point_load_integrated_along_the_line(x1, x3):
    """Flamant's stresses, s22 = nu (s11 + s33) included, equal Boussinesq's point load integrated over x2 (1e-10)."""
    expected = np.array([quad(lambda s, k=k: reference.point_load_stress(x1, s, x3, poisson=NU)[k],
                              -np.inf, np.inf, epsabs=1e-13, epsrel=1e-12)[0] for k in range(6)])
    flamant = reference.line_load_stress(x1, x3, poisson=NU)
    assert np.abs(flamant - expected).max() <= 1e-10 * np.abs(expected).max()


POINTS = [(0.0, 0.5), (0.3, 0.1), (-0.7, 0.4), (1.2, 0.3), (-2.0, 1.5), (0.99, 0.01), (0.5, 3.0)]


@pytest.mark.parametrize("x1, x3", POINTS)
def test_strip_and_mcewen_match_the_quadrature_of_flamant(x1, x3):
    """Closed forms vs Flamant integrated over the pressure: 1e-12 of the peak pressure (measured 1e-15)."""
    b, p0 = 1.0, 2.0
    # p0 = 2 W' / (pi b) and b^2 = 4 W' R / (pi E*) give W' = pi b p0 / 2, E* = 2 p0 R / b
    hertz = reference.HertzCylinder(radius=1.0, load_per_length=np.pi * b * p0 / 2, contact_modulus=2 * p0 / b)
    assert hertz.half_width == pytest.approx(b) and hertz.max_pressure == pytest.approx(p0)
    quadrature = reference.plane_strain_stress_by_quadrature(hertz.pressure, x1, x3, support=(-b, b), poisson=NU)
    assert np.abs(hertz.stress(x1, x3, NU) - quadrature).max() <= 1e-12 * p0
    uniform = reference.plane_strain_stress_by_quadrature(lambda s: p0, x1, x3, support=(-b, b), poisson=NU)
    strip = reference.strip_stress(x1, x3, half_width=b, pressure=p0, poisson=NU)
    assert np.abs(strip - uniform).max() <= 1e-12 * p0


def test_mcewen_surface_and_largest_shear_on_the_centre_line():
    """On the surface s11 = s33 = -p(x); below the centre the principal shear peaks at 0.300 p0 at 0.786 b.

    Johnson (1985, sec. 4.2) quotes tau_1 = 0.300 p0 at z = 0.78 b; on the centre line
    tau_1 / p0 = zeta - zeta^2 / sqrt(1 + zeta^2) (zeta = z/b), whose maximum is
    0.300283 at zeta = 0.786151.
    """
    b, p0 = 2.0, 3.0
    x = np.linspace(-1.5 * b, 1.5 * b, 31)
    surface = reference.hertz_line_stress(x, 0.0, half_width=b, max_pressure=p0, poisson=NU)
    hertz = p0 * np.sqrt(np.clip(1 - (x / b) ** 2, 0, None))
    assert np.abs(surface[:, [0, 2]] + hertz[:, None]).max() <= 1e-14 * p0
    assert np.abs(surface[:, 4]).max() <= 1e-14 * p0

    def shear(zeta):
        s = reference.hertz_line_stress(0.0, zeta * b, half_width=b, max_pressure=p0, poisson=NU)
        return -0.5 * (s[0] - s[2]) / p0

    found = minimize_scalar(shear, bounds=(0.1, 2.0), method="bounded", options={"xatol": 1e-10})
    assert -found.fun == pytest.approx(0.300283, abs=1e-6)
    assert found.x == pytest.approx(0.786151, abs=1e-5)


def test_kernel_strip_is_the_reference_strip():
    """kernels.strip_stress (the limit of Love's rectangle) equals Johnson's strip from Flamant (1e-14)."""
    x1, x3 = np.meshgrid(np.linspace(-4, 4, 41), np.r_[0.0, 0.01, 0.3, 1.0, 7.0], indexing="ij")
    kernel = strip_stress(x1, x3, half1=0.75, poisson=NU)
    expected = reference.strip_stress(x1, x3, half_width=0.75, pressure=1.0, poisson=NU)
    assert np.abs(kernel - expected).max() <= 1e-14


# ---------------------------------------------------------------------------
# the kernel: Love's rectangle summed over its periodic images
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("half1, half2, cells", [(0.5, 0.5, 4), (0.5, 0.1, 7), (0.05, 0.5, 2), (2.0, 0.5, 3)])
def test_periodic_kernel_equals_direct_image_sums(half1, half2, cells):
    """Within 1e-12 of the pressure (measured <= 1.7e-13) at the surface, just below it, and deep down.

    The offsets reach beyond 7 periods from the cell, where the kernel is the strip alone.
    """
    period = 2 * half2 * cells
    x1 = np.array([0.0, half1, 3 * half1, 2.0, 7.5 * period + half1])
    x2 = 2 * half2 * np.arange(cells)
    for x3 in (0.0, 0.05, 1.0, 8.0 * period):
        kernel = periodic_subsurface_stress(x1, x3, half1=half1, half2=half2, cells=cells, poisson=NU)
        direct = image_sum(x1[:, None], x2[None, :], x3, half1=half1, half2=half2, cells=cells)
        assert np.abs(kernel - direct).max() <= 1e-12


def test_direct_image_sums_have_converged():
    """The reference itself: 3000 and 12000 images agree to 1e-13.

    The smeared tail errs by ~1/M^3 (measured against the kernel: 1.0e-9, 3.9e-11,
    1.1e-12, 4.4e-14 at M = 100, 300, 1000, 3000).
    """
    args = dict(half1=0.5, half2=0.5, cells=3)
    for x3 in (0.0, 0.5):
        coarse = image_sum(0.3, 1.0, x3, **args)
        fine = image_sum(0.3, 1.0, x3, images=12000, **args)
        assert np.abs(coarse - fine).max() <= 1e-13


def test_one_cell_per_period_is_the_strip():
    """With one cell per period the images tile the strip: the kernel is exactly the strip."""
    x1 = np.linspace(-3, 3, 13)
    kernel = periodic_subsurface_stress(x1, 0.4, half1=0.5, half2=0.3, cells=1, poisson=NU)
    assert np.abs(kernel[:, 0] - strip_stress(x1, 0.4, half1=0.5, poisson=NU)).max() == 0.0


# ---------------------------------------------------------------------------
# the operator
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("shape", [(5, 3), (4, 4)])
@pytest.mark.parametrize("periodic_axis", [0, 1])
def test_varying_pressure_matches_direct_sums_over_cells_and_images(shape, periodic_axis):
    """A pressure varying along both axes: operator vs direct sums at a few points, 1e-12 p (measured 3.6e-13)."""
    periodic = (periodic_axis == 0, periodic_axis == 1)
    grid = line_grid(shape, periodic)
    pressure = np.random.default_rng(3).random(shape)
    depths = np.array([0.0, 0.35, 2.0])
    stress = SubsurfaceStress(grid, NU).apply(pressure, depths=depths)
    (d1, d2), open_axis = grid.spacing, 1 - periodic_axis
    x1, x2 = grid.coordinates()
    for i, j in [(0, 0), (shape[0] // 2, 1), (shape[0] - 1, shape[1] - 1)]:
        for k, x3 in enumerate(depths):
            if periodic_axis == 1:
                coefficients = image_sum(x1[i, j] - x1, x2[i, j] - x2, x3, half1=d1 / 2, half2=d2 / 2, cells=shape[1])
            else:
                coefficients = image_sum(x2[i, j] - x2, x1[i, j] - x1, x3, half1=d2 / 2, half2=d1 / 2,
                                         cells=shape[0])[..., SWAP]
            direct = np.einsum("ab,abc->c", pressure, coefficients)
            assert np.abs(stress[i, j, k] - direct).max() <= 1e-12, (open_axis, i, j, x3)


@pytest.mark.parametrize("shape", [(15, 4), (16, 5), (9, 1)])
@pytest.mark.parametrize("periodic_axis", [1, 0])
def test_band_uniform_along_the_periodic_axis_is_the_plane_strain_strip(shape, periodic_axis):
    """p on a band of cells, uniform along the periodic axis: Johnson's strip to 1e-10 p (measured 4e-16).

    Depths: the surface, within a cell, a few cells, and beyond 7 periods (strip-only kernel).
    """
    n_open, n_per = shape
    pressure = np.zeros(shape)
    pressure[3:8] = 2.5  # five cells, off centre
    grid = line_grid(shape, (False, True), spacing=(1.0, 0.4))
    if periodic_axis == 0:
        pressure, grid = pressure.T, line_grid(shape[::-1], (True, False), spacing=(0.4, 1.0))
    x_open = (np.arange(n_open) + 0.5) - 0.5 * n_open
    centre = 0.5 * (x_open[3] + x_open[7])
    depths = np.array([0.0, 0.3, 2.5, 7.5 * 0.4 * n_per + 0.1])
    stress = SubsurfaceStress(grid, NU).apply(pressure, depths=depths)
    expected = reference.strip_stress(x_open[:, None] - centre, depths[None, :], half_width=2.5, pressure=2.5,
                                      poisson=NU)
    if periodic_axis == 0:
        stress, expected = stress.transpose(1, 0, 2, 3), expected[..., SWAP]
    assert np.abs(stress - expected[:, None]).max() <= 1e-10 * 2.5


def test_transposed_grid_gives_the_transposed_stresses():
    """periodic=(True, False) on p.T equals periodic=(False, True) on p, axes and components swapped (1e-13)."""
    pressure = np.random.default_rng(5).random((9, 6))
    depths = [0.0, 0.5, 3.0]
    direct = SubsurfaceStress(line_grid((9, 6), (False, True)), NU).apply(pressure, depths=depths)
    swapped = SubsurfaceStress(fw.Grid(shape=(6, 9), size=(6 * 0.7, 9.0), periodic=(True, False)), NU)
    swapped = swapped.apply(pressure.T, depths=depths).transpose(1, 0, 2, 3)[..., SWAP]
    assert np.abs(swapped - direct).max() <= 1e-13


@pytest.mark.parametrize("periodic", [(False, True), (True, False)])
def test_mirrored_pressure_gives_mirrored_stresses(periodic):
    """Each component is even or odd under x1 -> -x1 and x2 -> -x2, on odd and even axes (1e-13)."""
    grid = line_grid((7, 6), periodic)
    pressure = np.random.default_rng(11).random(grid.shape)
    operator = SubsurfaceStress(grid, NU)
    depths = [0.0, 0.4, 2.0]
    stress = operator.apply(pressure, depths=depths)
    mirrored_1 = operator.apply(pressure[::-1], depths=depths)[::-1] * X1_PARITY
    mirrored_2 = operator.apply(pressure[:, ::-1], depths=depths)[:, ::-1] * X2_PARITY
    assert np.abs(mirrored_1 - stress).max() <= 1e-13
    assert np.abs(mirrored_2 - stress).max() <= 1e-13


def test_period_mean_is_the_plane_strain_field_of_the_mean_pressure():
    """Averaged over a period, the stresses are the plane-strain strips of the period-averaged pressure (1e-12)."""
    grid = line_grid((12, 5), (False, True))
    pressure = np.random.default_rng(2).random(grid.shape)
    depths = np.array([0.0, 0.2, 1.5, 6.0])
    mean = SubsurfaceStress(grid, NU).apply(pressure, depths=depths).mean(axis=1)
    x1 = grid.x1
    expected = sum(p * reference.strip_stress(x1[:, None] - x, depths[None, :], half_width=0.5, pressure=1.0,
                                              poisson=NU)
                   for p, x in zip(pressure.mean(axis=1), x1))
    assert np.abs(mean - expected).max() <= 1e-12


def test_deep_layer_carries_the_load_per_period():
    """Sum of s33 over a layer at 10 cells depth, plus the strips' s33 outside the grid, equals -load (1e-12).

    At a depth of 10 cells the cell-centre sum is the integral over x1 (Poisson's formula:
    the error is ~exp(-2 pi 10)); outside the grid the period-averaged stresses are the
    reference strips, summed on the same lattice to 1e5 cells, and beyond that Flamant's
    line load integrated (measured < 1e-15 of the load; the outside carries 1.2 %).
    """
    grid = line_grid((64, 4), (False, True))
    pressure = np.zeros(grid.shape)
    pressure[28:36] = np.random.default_rng(4).random((8, 4))
    depth = 10.0
    (d1, d2), period = grid.spacing, grid.size[1]
    inside = SubsurfaceStress(grid, NU).apply(pressure, depths=[depth])[..., 0, 2].sum() * d1 * d2
    offsets = np.arange(32, 100_000) + 0.5
    column = pressure.mean(axis=1)
    outside = 0.0
    for p, x in zip(column[28:36], grid.x1[28:36]):
        for side in (offsets, -offsets):
            outside += p * reference.strip_stress(side - x, depth, half_width=0.5, pressure=1.0,
                                                  poisson=NU)[:, 2].sum() * d1 * period
    load = pressure.sum() * d1 * d2
    far = quad(lambda x: reference.line_load_stress(x, depth, poisson=NU)[2], offsets[-1] + 0.5, np.inf,
               epsabs=0.0, epsrel=1e-10)[0]
    outside += 2 * far * load
    assert inside + outside == pytest.approx(-load, rel=1e-12)


# ---------------------------------------------------------------------------
# Hertz line contact solved by the framework vs McEwen
# ---------------------------------------------------------------------------

MATERIAL = materials.Elastic(young=210e9, poisson=NU)
CYLINDER_RADIUS, HALF_WIDTH = 0.01, 1e-4
LOAD_PER_LENGTH = np.pi * MATERIAL.contact_modulus * HALF_WIDTH**2 / (4 * CYLINDER_RADIUS)
HERTZ_LINE = reference.HertzCylinder(radius=CYLINDER_RADIUS, load_per_length=LOAD_PER_LENGTH,
                                     contact_modulus=MATERIAL.contact_modulus)
AXIS_CELLS = 4


def solve_line_contact(cells_per_half_width, periodic_axis=1):
    """The cylinder along the periodic axis; 4 b + 1 cell across it, 6 layers down to 3 b."""
    dx = HALF_WIDTH / cells_per_half_width
    n = 4 * cells_per_half_width + 1
    shape, size = (n, AXIS_CELLS), (n * dx, AXIS_CELLS * dx)
    if periodic_axis == 0:
        shape, size = shape[::-1], size[::-1]
    grid = fw.Grid(shape=shape, size=size, periodic=(periodic_axis == 0, periodic_axis == 1),
                   depth=3 * HALF_WIDTH, layers=6)
    return fw.Simulation(grid=grid, material=MATERIAL, indenter=indenters.Cylinder(radius=CYLINDER_RADIUS,
                                                                                   axis=periodic_axis),
                         schedule=schedules.Static(load=LOAD_PER_LENGTH * AXIS_CELLS * dx),
                         options={"tolerance": 1e-10}).run()


def mcewen_error(result, periodic_axis=1):
    """Largest |stress - McEwen| over all cells, layers and components [Pa]."""
    grid, stress = result.grid, result.stress(0)
    across = grid.x1 if periodic_axis == 1 else grid.x2
    expected = HERTZ_LINE.stress(across[:, None], grid.x3[None, :], NU)
    if periodic_axis == 0:
        stress, expected = stress.transpose(1, 0, 2, 3), expected[..., SWAP]
    return np.abs(stress - expected[:, None]).max()


@pytest.fixture(scope="module")
def line_contacts():
    return {cells: solve_line_contact(cells) for cells in (12, 24, 48)}


def test_hertz_line_contact_stresses_match_mcewen(line_contacts):
    """Within 2 % of p0 at 12 cells per half-width (measured 0.090 %), depths 0.25 b to 2.75 b."""
    p0 = HERTZ_LINE.max_pressure
    assert line_contacts[12].max_pressure[0] == pytest.approx(p0, rel=0.01)
    assert mcewen_error(line_contacts[12]) <= 0.02 * p0


def test_hertz_line_contact_stresses_converge_at_second_order(line_contacts):
    """Halving the cells divides the largest error by 2^2.5 then 2^2.3: an observed order >= 1.8."""
    errors = [mcewen_error(line_contacts[cells]) for cells in (12, 24, 48)]
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders >= 1.8), orders
    assert errors[-1] <= 1e-4 * HERTZ_LINE.max_pressure


def test_hertz_line_contact_along_x1_agrees(line_contacts):
    """The cylinder along a periodic x1: the same stresses, transposed, within 1e-8 p0 of the other run."""
    along_x1 = solve_line_contact(24, periodic_axis=0)
    p0 = HERTZ_LINE.max_pressure
    assert mcewen_error(along_x1, periodic_axis=0) == pytest.approx(mcewen_error(line_contacts[24]), rel=1e-4)
    swapped = along_x1.stress(0).transpose(1, 0, 2, 3)[..., SWAP]
    assert np.abs(swapped - line_contacts[24].stress(0)).max() <= 1e-8 * p0
