"""Validation of periodic and partly periodic grids against ``framework.reference``.

Steel ``E = 210 GPa``, ``nu = 0.3``. Doubly periodic grids use the sampled
Fourier kernel ``2/|q|`` (mean displacement zero), grids periodic along one
axis the exact cell integral of ``(2/pi) K0(|q| s)`` along the open axis (the
plane-strain logarithm for the mode ``q = 0``).

Measured when these tests were written (pyFFTW backend):

* Westergaard, 256 x 4 cells per wavelength, partial contact at pbar = 0.3 p*
  and 0.7 p*: half-width -0.49 % / +0.29 % (-0.23 / +0.23 cell: the count is
  quantised to whole cells), RMS pressure error 7.5e-4 / 8.8e-4 of the RMS
  reference pressure (dominated by the cells at the contact edges); full
  contact at 1.5 p*: pressure exact to 1.4e-15 p*, subsurface sigma_33 to
  7e-16 p*;
* Hertz line contact, 48.8 cells per half-width, side 4.1 b, 4 cells along the
  axis: half-width +0.45 % (cell count; +0.22 cell), -2.6e-5 from a fit of
  p^2 against x^2, peak pressure -6e-5, pressure error 6e-5 p0 inside
  |x| < 0.9 b (1.9e-2 p0 in the edge cells); the transposed grid agrees to
  <= 1e-11 at solver tolerance 1e-12 (to ~1e-9 at the default 1e-8: the
  two FFT layouts round differently and the solve stops within its tolerance);
* sphere, 16 cells per contact radius, period 8 a: doubly periodic peak
  pressure +0.233 % above the non-periodic one, the periodic-image estimate
  being +0.250 %; periodic along one axis only: +0.058 %.
"""
import numpy as np
import pytest

import framework as fw
from framework import indenters, materials, reference, schedules
from framework.operators.surface import SurfaceCompliance

MATERIAL = materials.Elastic(young=210e9, poisson=0.3)
E_STAR = MATERIAL.contact_modulus


def run(grid, indenter, options=None, **schedule):
    return fw.Simulation(grid=grid, material=MATERIAL, indenter=indenter,
                         schedule=schedules.Static(**schedule), options=options).run()


# ---------------------------------------------------------------------------
# Westergaard wavy surface on a doubly periodic grid
# ---------------------------------------------------------------------------

WAVELENGTH = 1e-3
AMPLITUDE = 1e-6
WAVE_CELLS = (256, 4)
WESTERGAARD = reference.Westergaard(amplitude=AMPLITUDE, wavelength=WAVELENGTH, contact_modulus=E_STAR)
P_STAR = WESTERGAARD.full_contact_pressure


def wave_grid(**layers):
    n1, n2 = WAVE_CELLS
    return fw.Grid(shape=(n1, n2), size=(WAVELENGTH, WAVELENGTH * n2 / n1), periodic=(True, True), **layers)


WAVE = indenters.HeightMap(lambda x1, x2: AMPLITUDE * (1 - np.cos(2 * np.pi * x1 / WAVELENGTH)))


@pytest.fixture(scope="module", params=[0.3, 0.7], ids=lambda f: f"pbar={f}p*")
def westergaard_partial(request):
    grid = wave_grid()
    mean_pressure = request.param * P_STAR
    result = run(grid, WAVE, load=mean_pressure * grid.size[0] * grid.size[1])
    return grid, mean_pressure, result


def test_westergaard_pressure_is_uniform_along_the_crests(westergaard_partial):
    _, _, result = westergaard_partial
    pressure = result.pressure(0)
    assert np.abs(pressure - pressure[:, :1]).max() <= 1e-12 * pressure.max()


def test_westergaard_contact_half_width(westergaard_partial):
    """Cells in contact along x1 times dx1 / 2: within 1 % and 0.6 cell of Westergaard's a.

    The count is quantised to whole cells (each edge is at a cell boundary of
    the count), so at 47 (0.3 p*) and 81 (0.7 p*) cells per half-width the
    quantisation alone allows up to 1.1 % / 0.6 %; measured -0.23 / +0.23 cell.
    """
    grid, mean_pressure, result = westergaard_partial
    dx1 = grid.spacing[0]
    half_width = np.count_nonzero(result.pressure(0)[:, 0] > 0) * dx1 / 2
    expected = WESTERGAARD.contact_half_width(mean_pressure)
    assert expected / dx1 >= 30
    assert half_width == pytest.approx(expected, rel=0.01)
    assert abs(half_width - expected) <= 0.6 * dx1


def test_westergaard_partial_contact_pressure(westergaard_partial):
    """Pressure at the cell centres vs Westergaard's p(x): relative RMS error below 5e-3 (measured <= 9e-4)."""
    grid, mean_pressure, result = westergaard_partial
    expected = WESTERGAARD.pressure(grid.x1, mean_pressure)
    simulated = result.pressure(0)[:, 0]
    rms_error = np.sqrt(np.mean((simulated - expected) ** 2))
    assert rms_error < 5e-3 * np.sqrt(np.mean(expected**2))
    assert result.max_pressure[0] == pytest.approx(expected.max(), rel=0.01)
    assert np.mean(simulated) == pytest.approx(mean_pressure, rel=1e-10)


@pytest.fixture(scope="module")
def westergaard_full():
    """Full contact at pbar = 1.5 p*, on a grid with layers down to one wavelength."""
    grid = wave_grid(depth=WAVELENGTH, layers=8)
    mean_pressure = 1.5 * P_STAR
    result = run(grid, WAVE, load=mean_pressure * grid.size[0] * grid.size[1])
    return grid, mean_pressure, result


def test_westergaard_full_contact_pressure(westergaard_full):
    """p = pbar + p* cos(k x1) everywhere; the brief asked for 1e-3 p*, asserted 1e-6 p* (measured 1e-15).

    The cosine of the grid's wavelength is an eigenvector of the doubly
    periodic operator, so the discrete solution is the continuous one.
    """
    grid, mean_pressure, result = westergaard_full
    pressure = result.pressure(0)
    assert np.all(pressure > 0)
    expected = WESTERGAARD.pressure(grid.x1, mean_pressure)[:, None]
    assert np.abs(pressure - expected).max() < 1e-6 * P_STAR


def test_westergaard_full_contact_subsurface_stress(westergaard_full):
    """Stresses of the cosine mode at the layer centres (plane strain; cf. Johnson 1985, ch. 2).

    For ``p = pbar + p* cos(k x1)``, ``k = 2 pi / lambda``, ``z`` the depth:
    ``s33 = -pbar - p* (1 + k z) e^{-kz} cos(k x1)`` (the mean part is -pbar at
    every depth), and for the oscillating parts, which satisfy equilibrium with
    it (checked by hand: d s11/dx1 + d s13/dz = 0, d s13/dx1 + d s33/dz = 0)
    and plane strain: ``s11 = -p* (1 - k z) e^{-kz} cos``,
    ``s13 = -p* k z e^{-kz} sin``, ``s22 = nu (s11 + s33) = -2 nu p* e^{-kz} cos``;
    ``s12 = s23 = 0``. Within 1e-6 p* (measured 7e-16).
    """
    grid, mean_pressure, result = westergaard_full
    stress = result.stress(0)
    assert stress.shape == grid.shape + (grid.layers, 6)
    k = 2 * np.pi / WAVELENGTH
    x1 = grid.x1[:, None, None]
    z = grid.x3[None, None, :]
    decay = np.exp(-k * z)
    cos, sin = np.cos(k * x1), np.sin(k * x1)
    tolerance = 1e-6 * P_STAR
    expected_33 = -mean_pressure - P_STAR * (1 + k * z) * decay * cos
    assert np.abs(stress[..., 2] - expected_33).max() < tolerance
    assert np.abs(stress[..., 4] - (-P_STAR * k * z * decay * sin)).max() < tolerance
    oscillating = stress - stress.mean(axis=0, keepdims=True)
    assert np.abs(oscillating[..., 0] - (-P_STAR * (1 - k * z) * decay * cos)).max() < tolerance
    assert np.abs(oscillating[..., 1] - (-2 * MATERIAL.poisson * P_STAR * decay * cos)).max() < tolerance
    assert np.abs(stress[..., 3]).max() < tolerance
    assert np.abs(stress[..., 5]).max() < tolerance


# ---------------------------------------------------------------------------
# Hertz line contact on a grid periodic along the cylinder axis
# ---------------------------------------------------------------------------

CYLINDER_RADIUS = 0.01
HALF_WIDTH = 1e-4
LOAD_PER_LENGTH = np.pi * E_STAR * HALF_WIDTH**2 / (4 * CYLINDER_RADIUS)
HERTZ_LINE = reference.HertzCylinder(radius=CYLINDER_RADIUS, load_per_length=LOAD_PER_LENGTH,
                                     contact_modulus=E_STAR)
LINE_CELLS, LINE_SIDE, LINE_AXIS_CELLS = 200, 4.1 * HALF_WIDTH, 4  # 48.8 cells per half-width
TIGHT = {"tolerance": 1e-12, "residual_tolerance": 1e-10}


@pytest.fixture(scope="module")
def line_contact():
    """The same line contact along x2 (periodic x2) and along x1 (periodic x1), solved tightly."""
    dx = LINE_SIDE / LINE_CELLS
    width = LINE_AXIS_CELLS * dx
    load = LOAD_PER_LENGTH * width
    along_x2 = fw.Grid(shape=(LINE_CELLS, LINE_AXIS_CELLS), size=(LINE_SIDE, width), periodic=(False, True))
    along_x1 = fw.Grid(shape=(LINE_AXIS_CELLS, LINE_CELLS), size=(width, LINE_SIDE), periodic=(True, False))
    result = run(along_x2, indenters.Cylinder(radius=CYLINDER_RADIUS, axis=1), options=TIGHT, load=load)
    transposed = run(along_x1, indenters.Cylinder(radius=CYLINDER_RADIUS, axis=0), options=TIGHT, load=load)
    return along_x2, along_x1, result, transposed


def test_hertz_line_contact_half_width_and_peak(line_contact):
    """Half-width (cell count) within 1 % and peak pressure within 1e-3 of Hertz, at 48.8 cells per half-width.

    The cell count is quantised (+0.22 cell measured here; an edge landing
    just outside a cell centre can add up to ~0.6 cell), so the sub-cell
    half-width from a least-squares fit of ``p^2 = p0^2 (1 - x^2/b^2)``
    (linear in ``x^2``) over the cells with ``|x| < 0.9 b`` is also checked,
    within 2e-3 (measured -2.6e-5).
    """
    grid, _, result, _ = line_contact
    dx1 = grid.spacing[0]
    assert HERTZ_LINE.half_width / dx1 >= 30
    pressure = result.pressure(0)
    assert np.abs(pressure - pressure[:, :1]).max() <= 1e-9 * pressure.max()
    profile = pressure[:, 0]
    half_width = np.count_nonzero(profile > 0) * dx1 / 2
    assert half_width == pytest.approx(HERTZ_LINE.half_width, rel=0.01)
    assert result.half_width[0] == pytest.approx(half_width, rel=1e-12)  # the series a user reads
    assert line_contact[3].half_width[0] == pytest.approx(half_width, rel=1e-12)
    assert result.max_pressure[0] == pytest.approx(HERTZ_LINE.max_pressure, rel=1e-3)
    x1 = grid.x1
    inner = np.abs(x1) < 0.9 * HERTZ_LINE.half_width
    slope, intercept = np.polyfit(x1[inner] ** 2, profile[inner] ** 2, 1)
    assert np.sqrt(-intercept / slope) == pytest.approx(HERTZ_LINE.half_width, rel=2e-3)
    # profile: 6e-5 p0 inside |x| < 0.9 b, 1.9e-2 p0 at worst in the cell that straddles each edge
    error = np.abs(profile - HERTZ_LINE.pressure(x1))
    assert error[inner].max() < 1e-3 * HERTZ_LINE.max_pressure
    assert error.max() < 0.05 * HERTZ_LINE.max_pressure


def test_hertz_line_contact_transposed_grid_agrees(line_contact):
    """periodic=(True, False) with Cylinder(axis=0) is the transpose of periodic=(False, True), axis=1.

    The operators agree to rounding; the solutions to 1e-10 of the peak when
    solved to tolerance 1e-12 (at the default 1e-8 the two FFT layouts round
    differently and the solves stop up to ~1e-9 apart).
    """
    along_x2, along_x1, result, transposed = line_contact
    field = np.random.default_rng(1).random(along_x2.shape)
    direct = SurfaceCompliance(along_x2).apply(field)
    swapped = SurfaceCompliance(along_x1).apply(field.T).T
    assert np.abs(swapped - direct).max() <= 1e-13 * np.abs(direct).max()
    peak = result.max_pressure[0]
    assert np.abs(transposed.pressure(0).T - result.pressure(0)).max() <= 1e-10 * peak
    assert transposed.approach[0] == pytest.approx(result.approach[0], rel=1e-10)
    assert transposed.load[0] == pytest.approx(result.load[0], rel=1e-12)


# ---------------------------------------------------------------------------
# A sphere on a period large compared with its contact
# ---------------------------------------------------------------------------

SPHERE_RADIUS = 0.01
SPHERE_CONTACT = 1e-4
SPHERE_CELLS_PER_RADIUS, SPHERE_PERIOD = 16, 8  # period in contact radii
# sum over the square lattice Z^2 \ {0} of 1/|j|^3 = 4 zeta(3/2) beta(3/2)
LATTICE_SUM = 9.0336


@pytest.fixture(scope="module")
def sphere_runs():
    hertz = reference.HertzSphere.from_contact_radius(SPHERE_RADIUS, SPHERE_CONTACT, E_STAR)
    n = SPHERE_CELLS_PER_RADIUS * SPHERE_PERIOD
    side = SPHERE_PERIOD * SPHERE_CONTACT
    results = {}
    for periodic in ((False, False), (True, True), (False, True), (True, False)):
        grid = fw.Grid(shape=(n, n), size=(side, side), periodic=periodic)
        results[periodic] = run(grid, indenters.Sphere(radius=SPHERE_RADIUS), load=hertz.load)
    return hertz, results


@pytest.mark.parametrize("periodic", [(True, True), (False, True), (True, False)])
def test_sphere_on_a_large_period_matches_the_open_grid(sphere_runs, periodic):
    """Period 8 a: peak pressure within 0.5 % of the non-periodic run (measured +0.23 %, +0.06 %)."""
    hertz, results = sphere_runs
    open_grid = results[(False, False)]
    assert open_grid.max_pressure[0] == pytest.approx(hertz.max_pressure, rel=0.005)
    assert results[periodic].max_pressure[0] == pytest.approx(open_grid.max_pressure[0], rel=0.005)
    assert results[periodic].contact_radius[0] == pytest.approx(open_grid.contact_radius[0], rel=0.01)


def test_sphere_periodic_images_raise_the_peak_as_estimated(sphere_runs):
    """The doubly periodic excess of peak pressure is the effect of the periodic images.

    Far images of the load ``W`` at the lattice points ``L j`` add, near the
    origin, ``u = const + (W / (pi E*)) r^2 S / (4 L^3)`` (S = sum |j|^-3 =
    9.0336), i.e. they increase the curvature 1/R of the gap by a factor
    ``2 S / (3 pi) (a/L)^3``; the Hertz peak scales as (1/R)^(2/3), so it rises by
    ``4 S / (9 pi) (a/L)^3`` = +0.250 % at L = 8 a. Measured +0.233 %
    (the rest: the sampled periodic kernel vs Love's cell integrals at 16
    cells per radius). Asserted within 20 %.
    """
    _, results = sphere_runs
    excess = results[(True, True)].max_pressure[0] / results[(False, False)].max_pressure[0] - 1
    estimate = 4 * LATTICE_SUM / (9 * np.pi) / SPHERE_PERIOD**3
    assert excess == pytest.approx(estimate, rel=0.2)
    # the mixed grids are transposes of each other
    mixed_x2, mixed_x1 = results[(False, True)], results[(True, False)]
    assert np.abs(mixed_x1.pressure(0).T - mixed_x2.pressure(0)).max() <= 1e-7 * mixed_x2.max_pressure[0]


def test_half_width_is_only_for_line_contacts(sphere_runs):
    _, results = sphere_runs
    assert np.isnan(results[(False, False)].half_width[0]) and np.isnan(results[(True, True)].half_width[0])
    row = results[(False, True)]
    assert row.half_width[0] == pytest.approx(row.contact_area[0] / (2 * row.grid.size[1]), rel=1e-15)
