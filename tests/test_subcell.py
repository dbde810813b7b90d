"""Sub-cell geometry of the inhomogeneities: cuboids cut by a body's boundary as laminates (issue 23, item 5).

References written here, independent of the code they check: Backus's (1962) closed forms for a stack of
isotropic layers, the jump conditions at a bonded plane interface, the ellipsoid's volume, points sampled
inside each cuboid, and Eshelby's uniform interior stress (framework.reference.eshelby).
"""
import numpy as np
import pytest

import framework as fw
from framework import inclusions, materials
from framework.errors import ParameterError
from framework.inclusions.field import InclusionProblem
from framework.inclusions.subcell import laminate, phase_strains
from framework.operators.eigenstrain import COMPONENTS
from framework.reference import eshelby

STEEL = materials.Elastic(210e9, 0.3)
CARBIDE = materials.Elastic(600e9, 0.22)        # the README example's tungsten carbide
APPLIED = np.array([[1e-3, 0.4e-3, -0.2e-3], [0.4e-3, -0.5e-3, 0.3e-3], [-0.2e-3, 0.3e-3, 0.8e-3]])
TILT = inclusions.axis_angle_orientation((0.3, 1.0, 0.2), np.radians(30.0))


def vector(tensor):
    return np.array([tensor[..., i, j] for i, j in COMPONENTS]).T


def lame(young, poisson):
    return young * poisson / ((1 + poisson) * (1 - 2 * poisson)), young / (2 * (1 + poisson))


# --- the laminate --------------------------------------------------------------------------------

def backus(first, second, fraction):
    """Backus (1962): stiffness tensor of layers normal to x3, isotropic (lambda, mu), ``fraction`` of the first."""
    def mean(g):
        return fraction * g(*first) + (1 - fraction) * g(*second)
    c33 = 1 / mean(lambda lam, mu: 1 / (lam + 2 * mu))
    ratio = mean(lambda lam, mu: lam / (lam + 2 * mu))
    c11 = mean(lambda lam, mu: 4 * mu * (lam + mu) / (lam + 2 * mu)) + ratio ** 2 * c33
    c66, c44, c13 = mean(lambda lam, mu: mu), 1 / mean(lambda lam, mu: 1 / mu), ratio * c33
    voigt = np.array([[c11, c11 - 2 * c66, c13, 0, 0, 0], [c11 - 2 * c66, c11, c13, 0, 0, 0],
                      [c13, c13, c33, 0, 0, 0], [0, 0, 0, c44, 0, 0], [0, 0, 0, 0, c44, 0], [0, 0, 0, 0, 0, c66]])
    return materials.voigt_to_tensor(voigt)


def test_laminate_of_isotropic_layers_is_backus_in_any_direction():
    """Layers normal to x3 give Backus's transversely isotropic stiffness; turned, the same tensor turned."""
    inside = eshelby.isotropic_stiffness(CARBIDE.young, CARBIDE.poisson)
    outside = eshelby.isotropic_stiffness(STEEL.young, STEEL.poisson)
    fractions = np.array([0.0, 0.2, 0.5, 0.9, 1.0])
    stiffness, _ = laminate(inside, outside, fractions, np.tile([0.0, 0.0, 2.0], (len(fractions), 1)))
    for f, got in zip(fractions, stiffness):
        expected = backus(lame(CARBIDE.young, CARBIDE.poisson), lame(STEEL.young, STEEL.poisson), f)
        assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()
    rotation = TILT
    turned, _ = laminate(inside, outside, [0.3], [rotation @ [0.0, 0.0, 1.0]])
    expected = eshelby.rotate_tensor(backus(lame(CARBIDE.young, CARBIDE.poisson), lame(STEEL.young, STEEL.poisson),
                                            0.3), rotation)
    assert np.abs(turned[0] - expected).max() <= 1e-12 * np.abs(expected).max()


def test_laminate_layers_meet_the_interface_conditions():
    """Anisotropic layers, any normal: the strains average to the mean, differ by sym(a (x) n) (the displacement is
    continuous), carry the same traction, and their stresses average to C_lam : e."""
    rng = np.random.default_rng(5)
    cubic = np.diag([0.0] * 6)
    cubic[:3, :3] = 200e9
    np.fill_diagonal(cubic, [500e9] * 3 + [150e9] * 3)
    inside = eshelby.rotate_tensor(materials.voigt_to_tensor(cubic), inclusions.euler_orientation(0.3, 1.1, -0.4))
    outside = eshelby.isotropic_stiffness(STEEL.young, STEEL.poisson)
    normal = rng.normal(size=(4, 3))
    fraction = np.array([0.1, 0.35, 0.6, 0.97])
    strain = rng.normal(size=(4, 3, 3)) * 1e-3
    strain = 0.5 * (strain + strain.transpose(0, 2, 1))
    stiffness, jump = laminate(inside, outside, fraction, normal)
    first, second = phase_strains(jump, fraction, strain)
    f = fraction[:, None, None]
    assert np.abs(f * first + (1 - f) * second - strain).max() <= 1e-15
    n = normal / np.linalg.norm(normal, axis=1)[:, None]
    for k in range(4):
        tangents = np.linalg.svd(n[k][None])[2][1:]         # two unit vectors normal to n
        difference = first[k] - second[k]
        assert np.abs(tangents @ difference @ tangents.T).max() <= 1e-12 * np.abs(strain).max()
        traction = (np.einsum("ijkl,kl->ij", inside, first[k]) - np.einsum("ijkl,kl->ij", outside, second[k])) @ n[k]
        assert np.abs(traction).max() <= 1e-12 * 210e9 * np.abs(strain).max()
        mean = (fraction[k] * np.einsum("ijkl,kl->ij", inside, first[k])
                + (1 - fraction[k]) * np.einsum("ijkl,kl->ij", outside, second[k]))
        assert np.abs(np.einsum("ijkl,kl->ij", stiffness[k], strain[k]) - mean).max() <= 1e-12 * np.abs(mean).max()
    assert np.abs(stiffness - stiffness.transpose(0, 3, 4, 1, 2)).max() <= 1e-12 * np.abs(stiffness).max()


def test_laminate_refuses_bad_input():
    c = eshelby.isotropic_stiffness(STEEL.young, STEEL.poisson)
    with pytest.raises(ParameterError, match=r"fraction must lie in \[0, 1\], got values from -0.1"):
        laminate(c, c, [-0.1], [[0, 0, 1]])
    with pytest.raises(ParameterError, match="normal must be non-zero"):
        laminate(c, c, [0.5], [[0, 0, 0]])


# --- volume fractions ------------------------------------------------------------------------------

@pytest.mark.parametrize("semi_axes, orientation", [((1.0, 1.0, 1.0), None), ((1.0, 0.7, 0.45), TILT)])
def test_fractions_add_up_to_the_volume_and_match_sampled_points(semi_axes, orientation):
    """At 8 cuboids per semi-axis (off the lattice) the shares add up to 4/3 pi a1 a2 a3 within 1e-4 (measured
    7e-6 and 4e-5); cut cuboids against 24^3 points each (sampling error ~1e-3); cuboids with every corner inside
    are whole."""
    h = 1e-3 / 8
    body = inclusions.Ellipsoid(center=(0.23 * h, -0.17 * h, 3e-3 + 0.31 * h),
                                semi_axes=tuple(1e-3 * s for s in semi_axes), material=CARBIDE, orientation=orientation)
    axes = [np.arange(-10, 10) * h + h / 2, np.arange(-10, 10) * h + h / 2, 3e-3 + np.arange(-10, 10) * h + h / 2]
    fraction, owner, normal = inclusions.InclusionSet([body]).fractions(*axes, (h, h, h))
    assert abs(fraction.sum() * h ** 3 / body.volume - 1) < 1e-4
    assert np.all((fraction >= 0) & (fraction <= 1)) and np.array_equal(owner, (fraction > 0).astype(int))
    centres = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    samples = ((np.arange(24) + 0.5) / 24 - 0.5) * h
    offsets = np.stack(np.meshgrid(samples, samples, samples, indexing="ij"), axis=-1).reshape(-1, 3)
    cut = np.argwhere((fraction > 0) & (fraction < 1))
    for index in cut[np.random.default_rng(0).choice(len(cut), 12, replace=False)]:
        sampled = body.contains(centres[tuple(index)] + offsets).mean()
        assert abs(fraction[tuple(index)] - sampled) < 5e-3
    corners = np.array([[i, j, k] for i in (-0.5, 0.5) for j in (-0.5, 0.5) for k in (-0.5, 0.5)]) * h
    convex_whole = np.all([body.contains(centres + c) for c in corners], axis=0)     # a convex body holds them all
    assert np.all(fraction[convex_whole] == 1)
    # the 8 x 8 columns miss slivers between them: a cuboid the body reaches only at a corner may read 0 for up
    # to 0.7 % of its volume (measured); the shares of whole and empty cuboids with a corner on the other side
    near = ~convex_whole & ((fraction == 1) | (fraction == 0)) & np.any([body.contains(centres + c) for c in corners],
                                                                        axis=0)
    for index in np.argwhere(near):
        assert abs(fraction[tuple(index)] - body.contains(centres[tuple(index)] + offsets).mean()) < 1e-2
    outward = centres - np.array(body.center)
    reached = fraction > 0
    assert np.all(np.einsum("...i,...i->...", normal[reached], outward[reached]) > 0)   # pointing out of the body


# --- the equivalent inclusion method with laminate cuboids -------------------------------------------

def deep_sphere(cells, geometry):
    """A carbide sphere (radius 1 mm) 6 radii deep in steel, ``cells`` cuboids per radius, centred on a corner."""
    a, h, n = 1e-3, 1e-3 / cells, 4 * cells
    grid = fw.Grid(shape=(n, n), size=(n * h, n * h), depth=7.5 * a, layers=int(round(7.5 * cells)))
    body = inclusions.Ellipsoid(center=(0.0, 0.0, 6 * a), semi_axes=(a, a, a), material=CARBIDE)
    solution = fw.solve_inclusions(grid, STEEL, [body], APPLIED, geometry=geometry)
    expected = vector(eshelby.interior_solution(body.semi_axes, body.orientation, STEEL.young, STEEL.poisson,
                                                body.stiffness_tensor, APPLIED).stress)
    return solution, expected, grid


def errors(stress, expected):
    """(error of the mean, largest error) of a set of cuboid stresses, relative to the largest Eshelby component."""
    scale = np.abs(expected).max()
    return np.abs(stress.mean(axis=0) - expected).max() / scale, np.abs(stress - expected).max() / scale


def body_side(solution, grid):
    """Stress [Pa] (Voigt, (m, 6)) on the body's side of each cut cuboid with at least half its volume in the body,
    from its mean strain ``C_M^-1 : s + e*`` and the laminate's jump."""
    box = solution.box
    fraction = solution.fraction[box]
    cut = tuple(np.argwhere((fraction >= 0.5) & (fraction < 1)).T)
    body = solution._problem.inclusions[0]
    coordinates = (grid.x1[box[0]], grid.x2[box[1]], grid.x3[box[2]])
    _, _, normal = inclusions.InclusionSet([body]).fractions(*coordinates, (*grid.spacing, grid.layer_thickness))
    matrix = eshelby.isotropic_stiffness(STEEL.young, STEEL.poisson)
    stress = np.zeros((len(cut[0]), 3, 3))
    eigenstrain = np.zeros_like(stress)
    for c, (i, j) in enumerate(COMPONENTS):
        stress[:, i, j] = stress[:, j, i] = solution.stress[cut][:, c]
        eigenstrain[:, i, j] = eigenstrain[:, j, i] = solution.eigenstrain[box][cut][:, c]
    trace = np.trace(stress, axis1=1, axis2=2)[:, None, None] * np.eye(3)
    strain = ((1 + STEEL.poisson) * stress - STEEL.poisson * trace) / STEEL.young + eigenstrain    # Hooke, inverted
    _, jump = laminate(body.stiffness_tensor, matrix, fraction[cut], normal[cut])
    inside, _ = phase_strains(jump, fraction[cut], strain)
    return vector(np.einsum("ijkl,mkl->mij", body.stiffness_tensor, inside))


def test_laminate_sphere_matches_eshelby_at_8_cuboids_per_radius():
    """The whole cuboids' mean stress within 0.5 % of Eshelby's (measured 0.15 %; the staircase's 1.0 %) and every
    whole cuboid within 5 % (measured 3.1 %; the staircase's 11 %: its stripes); the body's side of each cut cuboid
    with at least half its volume in the body within 8 % (measured 5.6 %; the staircase's boundary cuboids 22 %)."""
    solution, expected, grid = deep_sphere(8, "laminate")
    assert solution.success
    mean, largest = errors(solution.stress[solution.fraction[solution.box] == 1], expected)
    assert mean < 5e-3 and largest < 0.05, (mean, largest)
    side = body_side(solution, grid)
    assert len(side) > 100
    assert errors(side, expected)[1] < 0.08, errors(side, expected)


def test_laminate_against_the_staircase_at_4_cuboids_per_radius():
    """Before and after on a coarse grid: the whole cuboids' mean stress 2.0 % -> 0.46 % off Eshelby's, the worst
    whole cuboid 8.3 % -> 2.0 % (measured); the indicator stays the staircase's, the cut cuboids carry a share of the
    eigenstrain (also those whose centre lies outside), and the fractions add up to the sphere's volume."""
    staircase, expected, grid = deep_sphere(4, "staircase")
    laminated, _, _ = deep_sphere(4, "laminate")
    whole = laminated.fraction[laminated.box] == 1
    before, after = errors(staircase.stress[whole], expected), errors(laminated.stress[whole], expected)
    assert before[0] > 0.015 and before[1] > 0.06, before
    assert after[0] < 0.006 and after[1] < 0.03, after
    assert np.array_equal(laminated.inhomogeneity, staircase.inhomogeneity)
    assert np.array_equal(staircase.fraction, (staircase.inhomogeneity > 0).astype(float))
    cut = (laminated.fraction > 0) & (laminated.fraction < 1)
    assert np.all(np.abs(laminated.eigenstrain[cut & (laminated.inhomogeneity == 0)]).max(axis=-1) > 0)
    assert abs(laminated.fraction.sum() * grid.spacing[0] ** 2 * grid.layer_thickness / (4 / 3 * np.pi * 1e-9) - 1) \
        < 3e-4


def test_geometry_is_checked():
    grid = fw.Grid(shape=(24, 24), size=(3e-3, 3e-3), depth=2e-3, layers=16)
    body = inclusions.Ellipsoid(center=(0, 0, 1e-3), semi_axes=(0.5e-3,) * 3, material=CARBIDE)
    with pytest.raises(ParameterError, match=r"geometry must be one of 'staircase', 'laminate', got 'smooth'"):
        fw.solve_inclusions(grid, STEEL, [body], APPLIED, geometry="smooth")
    with pytest.raises(ParameterError, match=r"geometry='laminate' needs an elastic matrix .* got Viscoelastic"):
        InclusionProblem(grid, materials.PMMA, inclusions.InclusionSet([body]), geometry="laminate")


@pytest.mark.slow
def test_laminate_converges_with_a_smaller_constant_than_the_staircase():
    """6 to 16 cuboids per radius: the whole cuboids' mean stress at least 4 times closer to Eshelby's than the
    staircase's at every resolution (measured 0.24/1.23, 0.15/1.00, 0.125/0.64, 0.10/0.47 %), decreasing; first
    order (both): a cut cuboid's eigenstrain is uniform over the cuboid, not over its share of the body, so the
    layer of cut and next-to-cut cuboids keeps an error of a few per cent that does not shrink with the cuboid."""
    previous = np.inf
    for cells in (6, 8, 12, 16):
        staircase, expected, _ = deep_sphere(cells, "staircase")
        laminated, _, _ = deep_sphere(cells, "laminate")
        whole = laminated.fraction[laminated.box] == 1
        before, after = errors(staircase.stress[whole], expected)[0], errors(laminated.stress[whole], expected)[0]
        assert after < before / 4 and after < previous, (cells, before, after)
        previous = after


# --- in a Simulation -----------------------------------------------------------------------------

def _coupled(cells, geometry, body=True):
    """A ball (R = 5 mm, 20 N) on steel over a carbide sphere (radius 45 um, centre 0.1 mm deep)."""
    grid = fw.Grid(shape=(cells, cells), size=(0.6e-3, 0.6e-3), depth=0.3e-3, layers=cells // 2)
    bodies = [inclusions.Ellipsoid(center=(0.0, 0.0, 0.1e-3), semi_axes=(0.045e-3,) * 3, material=CARBIDE)]
    return fw.Simulation(grid=grid, material=STEEL, indenter=fw.indenters.Sphere(radius=5e-3),
                         schedule=fw.schedules.Static(load=[20.0]), inclusions=bodies if body else None,
                         options={"inclusion_geometry": geometry}).run()


@pytest.mark.filterwarnings("ignore::framework.errors.ResolutionWarning")
def test_a_coupled_run_with_laminate_cuboids_moves_less_under_refinement():
    """The body's change of the peak pressure and the approach at 3.6 and 7.2 cuboids per radius (48 and 96
    cells): the staircase's volume jumps with the grid (+9.06 % / +8.55 % peak pressure, -3.15 % / -2.94 %
    approach), the laminate's moves less than half as much (+8.23 % / +8.43 %, -2.95 % / -2.91 %)."""
    changes = {}
    for cells in (48, 96):
        plain = _coupled(cells, "staircase", body=False)
        for geometry in ("staircase", "laminate"):
            run = _coupled(cells, geometry)
            changes[geometry, cells] = (run.max_pressure[-1] / plain.max_pressure[-1] - 1,
                                        run.approach[-1] / plain.approach[-1] - 1)
    for k in range(2):
        stair = abs(changes["staircase", 48][k] - changes["staircase", 96][k])
        lam = abs(changes["laminate", 48][k] - changes["laminate", 96][k])
        assert lam < 0.5 * stair, (k, changes)
    assert 0.07 < changes["laminate", 96][0] < 0.10 and -0.035 < changes["laminate", 96][1] < -0.025


def test_the_geometry_option_is_checked():
    with pytest.raises(ParameterError, match=r"inclusion_geometry must be one of 'staircase', 'laminate', got 'smooth'"):
        fw.Options.from_value({"inclusion_geometry": "smooth"})
    grid = fw.Grid(shape=(32, 32), size=(0.6e-3, 0.6e-3), depth=0.3e-3, layers=16)
    body = [inclusions.Ellipsoid(center=(0.0, 0.0, 0.1e-3), semi_axes=(0.06e-3,) * 3, material=CARBIDE)]
    with pytest.raises(ParameterError, match=r"options.inclusion_geometry = 'laminate' needs an elastic matrix"):
        fw.Simulation(grid=grid, material=materials.PMMA, indenter=fw.indenters.Sphere(radius=5e-3),
                      schedule=fw.schedules.Static(load=[5.0]), inclusions=body,
                      options={"inclusion_geometry": "laminate"})
