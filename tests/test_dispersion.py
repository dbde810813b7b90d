"""Random dispersions of particles and fibres (inclusions.random_dispersion) and the [[dispersions]] scenario table.

References written here, not taken from the code under test: the bodies' volumes 4/3 pi a1 a2 a3 from their semi-axes;
containment in the region from points sampled on each body's surface; the gap between two spheres as the distance of
their centres less the radii, and between spheroids from points sampled on one body's parallel surface (at the gap)
tested against the other's quadratic form; overlaps by the Perram-Wertheim function over every pair whose centres lie
closer than their longest semi-axes; the isotropic moments <cos^2> = 1/3 (space) and 1/2 (plane) of the long axis.
"""
import copy
import importlib
import tomllib

import numpy as np
import pytest

from framework import errors, materials, scenario
from framework.inclusions import InclusionSet, contact_function, random_dispersion
from framework.inclusions import bodies as bodies_module
from framework.inclusions.dispersion import MAX_FRACTION, _growth

GLASS = materials.Elastic(young=70e9, poisson=0.22)
REGION = ((0.0, 1e-3), (0.0, 1e-3), (0.05e-3, 0.55e-3))    # 1 x 1 x 0.5 mm below 50 um of matrix
REGION_VOLUME = 1e-3 * 1e-3 * 0.5e-3


def analytic_volume(bodies):
    return sum(4.0 / 3.0 * np.pi * np.prod(body.semi_axes) for body in bodies)


def surface_points(body, count=400, offset=0.0):
    """Points on the body's surface (or on its parallel surface ``offset`` [m] outside), from a Fibonacci sphere."""
    k = np.arange(count) + 0.5
    polar, azimuth = np.arccos(1.0 - 2.0 * k / count), np.pi * (1.0 + 5.0 ** 0.5) * k
    unit = np.stack([np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), np.cos(polar)], axis=1)
    axes = np.asarray(body.semi_axes)
    local = unit * axes                                   # on the ellipsoid in its own frame
    normal = unit / axes                                  # the gradient of x^T diag(1/a^2) x, up to a factor 2
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    return np.asarray(body.center) + (local + offset * normal) @ body.orientation.T


def close_pairs(bodies):
    """Pairs whose bounding spheres (radius: the longest semi-axis) meet: the only ones that can touch."""
    centers = np.array([body.center for body in bodies])
    reach = np.array([max(body.semi_axes) for body in bodies])
    distance = np.linalg.norm(centers[:, None] - centers[None], axis=-1)
    i, j = np.nonzero(np.triu(distance <= reach[:, None] + reach[None], k=1))
    return list(zip(i, j))


def inside(body, points):
    offset = points - np.asarray(body.center)
    local = offset @ body.orientation
    return np.sum(np.square(local / np.asarray(body.semi_axes)), axis=1) <= 1.0


def long_axes(bodies):
    return np.array([body.orientation[:, 0] for body in bodies])


# --- fraction, placement, overlaps ------------------------------------------------------------------------------

@pytest.mark.parametrize("radius, aspect, fraction", [
    (0.04e-3, 1.0, 0.25),                                  # 466 spheres
    ([(0.05e-3, 1.0), (0.025e-3, 2.0)], 1.0, 0.15),        # two sizes, a third / two thirds of the volume
    (0.02e-3, 4.0, 0.06),                                  # 269 fibres, aspect 4, random
])
def test_the_fraction_is_the_one_asked_and_every_body_lies_in_the_region(radius, aspect, fraction):
    """Fraction from the analytic volumes within 1 % (relative) of the asked one; 400 surface points of every body
    inside the region; every body the spheroid (aspect r, r, r); two sizes share the volume by their weights."""
    bodies = random_dispersion(fraction, REGION, radius, GLASS, aspect=aspect, seed=7)
    assert len(bodies) > 100
    assert abs(analytic_volume(bodies) / REGION_VOLUME - fraction) <= 0.01 * fraction
    low, high = np.array(REGION).T
    for body in bodies:
        points = surface_points(body)
        assert np.all(points >= low) and np.all(points <= high)
        a1, a2, a3 = body.semi_axes
        assert a2 == a3 and a1 == pytest.approx(aspect * a2, rel=1e-14)
    if isinstance(radius, list):
        large = [body for body in bodies if body.semi_axes[1] == 0.05e-3]
        assert analytic_volume(large) / analytic_volume(bodies) == pytest.approx(1.0 / 3.0, rel=0.03)
        assert all(body.semi_axes[1] == 0.05e-3 for body in bodies[:len(large)])    # the largest placed first


def test_spheres_keep_the_gap():
    """Every pair of spheres: centre distance - r_i - r_j >= gap (to rounding); some pair comes within 30 % of it."""
    gap = 0.01e-3
    bodies = random_dispersion(0.2, REGION, [(0.04e-3, 1.0), (0.03e-3, 1.0)], GLASS, gap=gap, seed=2)
    centers = np.array([body.center for body in bodies])
    radii = np.array([body.semi_axes[0] for body in bodies])
    clearance = np.linalg.norm(centers[:, None] - centers[None], axis=-1) - radii[:, None] - radii[None]
    clearance = clearance[np.triu_indices(len(bodies), k=1)]
    assert clearance.min() >= gap * (1.0 - 1e-9)
    assert clearance.min() <= 1.3 * gap


def test_fibres_neither_overlap_nor_come_closer_than_the_gap():
    """Fibres of aspect 6 with a gap: no pair overlaps (Perram-Wertheim F > 1 over every pair whose bounding
    spheres meet); 600 points on each one's parallel surface at 0.999 gap lie outside its neighbours."""
    gap = 0.01e-3
    bodies = random_dispersion(0.05, REGION, 0.02e-3, GLASS, aspect=6.0, gap=gap, seed=3)
    pairs = close_pairs(bodies)
    assert len(bodies) > 80 and len(pairs) > 50
    for i, j in pairs:
        assert contact_function(bodies[i], bodies[j]) > 1.0
        assert not np.any(inside(bodies[j], surface_points(bodies[i], 600, offset=0.999 * gap)))


def test_the_growth_holds_the_parallel_body():
    """The spheroid grown by _growth(a, b, h) clears the original by h: the least distance from 1000 points of its
    outline to 10 000 points of the original's (the meridian section) is h within 1e-4; growing by h alone falls
    short (0.62 h at aspect 10)."""
    a, b, h = 10.0, 1.0, 0.5
    t = _growth(a, b, h)
    inner = np.linspace(0.0, 0.5 * np.pi, 10_000)
    outer = np.linspace(0.0, 0.5 * np.pi, 1000)

    def clearance(grow):
        points = np.stack([(a + grow) * np.cos(outer), (b + grow) * np.sin(outer)], axis=1)
        ring = np.stack([a * np.cos(inner), b * np.sin(inner)], axis=1)
        return min(np.min(np.linalg.norm(ring[k:k + 1000, None] - points[None], axis=-1))
                   for k in range(0, len(ring), 1000))

    assert clearance(t) == pytest.approx(h, rel=1e-4)
    assert clearance(h) == pytest.approx(0.62 * h, rel=0.02)
    assert _growth(2.0, 2.0, h) == h


# --- orientation ----------------------------------------------------------------------------------------------

def test_random_orientation_is_isotropic():
    """269 fibres: the mean of cos^2 of the long axis' angle to each axis is 1/3 within 0.06 (3.5 standard errors,
    sqrt(4/45 / 269) = 0.018), and the mean long axis (sign ignored, folded to x3 >= 0) has x1, x2 near 0."""
    bodies = random_dispersion(0.06, REGION, 0.02e-3, GLASS, aspect=4.0, seed=7)
    axes = long_axes(bodies)
    np.testing.assert_allclose(np.mean(axes ** 2, axis=0), 1.0 / 3.0, atol=0.06)
    folded = axes * np.sign(axes[:, 2:3])
    np.testing.assert_allclose(np.mean(folded[:, :2], axis=0), 0.0, atol=0.08)
    assert np.mean(np.abs(axes[:, 2])) == pytest.approx(0.5, abs=0.05)     # |cos theta| uniform on [0, 1]


def test_planar_orientation_lies_in_the_surface_plane():
    """'planar': the long axis has no x3 component (to rounding), <cos^2> = 1/2 with x1 and x2 within 0.07."""
    bodies = random_dispersion(0.04, REGION, 0.02e-3, GLASS, aspect=4.0, orientation="planar", seed=1)
    axes = long_axes(bodies)
    assert len(bodies) > 140
    assert np.max(np.abs(axes[:, 2])) < 1e-15
    np.testing.assert_allclose(np.mean(axes[:, :2] ** 2, axis=0), 0.5, atol=0.07)


@pytest.mark.parametrize("orientation, direction", [
    ("aligned", (1.0, 0.0, 0.0)),
    ((0.0, 3.0, 4.0), (0.0, 0.6, 0.8)),
    ((-1.0, 0.0, 0.0), (-1.0, 0.0, 0.0)),
])
def test_fixed_orientations(orientation, direction):
    """'aligned' puts every long axis along x1, a vector along itself normalised; semi-axes 3r, r, r."""
    bodies = random_dispersion(0.03, REGION, 0.03e-3, GLASS, aspect=3.0, orientation=orientation, seed=4)
    for body in bodies:
        np.testing.assert_allclose(body.orientation[:, 0], direction, atol=1e-15)
        np.testing.assert_allclose(body.orientation.T @ body.orientation, np.eye(3), atol=1e-15)


# --- reproducibility and limits ---------------------------------------------------------------------------------

def test_the_same_seed_gives_the_same_set():
    first = random_dispersion(0.05, REGION, 0.04e-3, GLASS, aspect=2.0, seed=11)
    again = random_dispersion(0.05, REGION, 0.04e-3, GLASS, aspect=2.0, seed=11)
    other = random_dispersion(0.05, REGION, 0.04e-3, GLASS, aspect=2.0, seed=12)
    assert first == again
    assert first != other and len(first) == len(other)
    assert random_dispersion(0.05, REGION, 0.04e-3, GLASS, aspect=2.0) != first    # seed None: a fresh one


def test_an_unreachable_fraction_raises_saying_how_far_it_got():
    """A fraction beyond random sequential addition's jamming (a wide gap here) raises naming the fraction, the
    fraction reached and the attempts."""
    with pytest.raises(errors.InclusionError, match=r"fraction = 0\.3 cannot be reached: \d+ of \d+ bodies placed "
                                                    r"\(fraction 0\.[0-9]+\).*20000 attempts"):
        random_dispersion(0.3, ((0, 1e-3), (0, 1e-3), (0, 0.5e-3)), 0.08e-3, GLASS, gap=0.04e-3, seed=0)


def test_the_overlap_check_of_a_set_follows_the_neighbours(monkeypatch):
    """InclusionSet's own check of 597 fibres calls the contact function only for pairs whose bounding spheres meet
    (fewer than 3 per body), not for the 178 000 pairs; an overlap among them is still found."""
    bodies = list(random_dispersion(0.1, ((0, 0.5e-3), (0, 0.5e-3), (0, 0.5e-3)), 0.01e-3, GLASS, aspect=5.0,
                                    seed=1))
    calls = []

    def counted(first, second):
        calls.append(1)
        return contact_function(first, second)

    monkeypatch.setattr(bodies_module, "contact_function", counted)
    InclusionSet(bodies)
    assert len(bodies) == 597 and len(calls) < 3 * len(bodies)
    moved = bodies_module.Ellipsoid(np.add(bodies[5].center, (1e-6, 0.0, 0.0)), bodies[5].semi_axes, GLASS,
                                    bodies[5].orientation)
    with pytest.raises(errors.InclusionError, match=r"inclusions\[5\] and inclusions\[597\] overlap"):
        InclusionSet(bodies + [moved])


@pytest.mark.parametrize("change, pattern", [
    ({"fraction": 0.0}, r"fraction must be a volume fraction in \(0, 0\.6\], got 0\.0"),
    ({"fraction": 0.7}, r"fraction .* got 0\.7"),
    ({"fraction": True}, r"fraction .* got True"),
    ({"region": ((0, 1e-3), (0, 1e-3))}, r"region must be three finite pairs"),
    ({"region": ((0, 1e-3), (1e-3, 0), (0, 1e-3))}, r"region\[1\] = \(0\.001, 0\.0\): expected lo < hi along x2"),
    ({"region": ((0, 1e-3), (0, 1e-3), (-1e-4, 1e-3))}, r"region\[2\] .* above the surface"),
    ({"region": "box"}, r"region must be three"),
    ({"radius": -1e-5}, r"radius must be positive \[m\], got -1e-05"),
    ({"radius": []}, r"radius must be a radius \[m\] or a non-empty list"),
    ({"radius": [(1e-5, 1.0), (2e-5, 0.0)]}, r"radius\[1\]\[1\] \(a weight\) must be positive, got 0\.0"),
    ({"radius": [(0.0, 1.0)]}, r"radius\[0\]\[0\] \(a radius\) must be positive"),
    ({"radius": [(1e-5, 1.0, 2.0)]}, r"radius\[0\] must be a pair"),
    ({"material": materials.PMMA}, r"material must be materials\.Elastic or materials\.AnisotropicElastic"),
    ({"aspect": 0.5}, r"aspect must be >= 1 .* got 0\.5"),
    ({"aspect": float("nan")}, r"aspect must be a finite real number"),
    ({"orientation": "isotropic"}, r"orientation must be one of \['random', 'planar', 'aligned'\]"),
    ({"orientation": (1.0, 0.0)}, r"orientation as a direction must be 3 finite numbers, got \(1\.0, 0\.0\)"),
    ({"orientation": (0.0, 0.0, 0.0)}, r"orientation as a direction must be non-zero"),
    ({"gap": -1e-6}, r"gap must be >= 0 \[m\], got -1e-06"),
    ({"seed": 1.5}, r"seed must be an integer >= 0 or None .* got 1\.5"),
    ({"seed": -1}, r"seed must be an integer >= 0 or None .* got -1"),
    ({"radius": 0.3e-3}, r"radius = 0\.0003 m \(a sphere\): the bodies span up to 0\.0006 m along x1, the region "
                         r"only 0\.0005 m"),
    ({"radius": 0.1e-3, "aspect": 4.0, "orientation": "planar"}, r"span up to 0\.0008 m along x1.*only 0\.0005"),
    ({"fraction": 1e-6}, r"fraction = 1e-06 .* holds less than half a body"),
])
def test_bad_input_names_the_parameter(change, pattern):
    arguments = dict(fraction=0.1, region=((0, 0.5e-3), (0, 1e-3), (0, 0.5e-3)), radius=0.05e-3, material=GLASS,
                     seed=0)
    arguments.update(change)
    with pytest.raises(errors.ParameterError, match=pattern):
        random_dispersion(**arguments)


# --- scenario files and sweeps ----------------------------------------------------------------------------------

SCENARIO = """
[grid]
shape = [24, 24]
size = [0.6e-3, 0.6e-3]
depth = 0.3e-3
layers = 12
[material]
type = "Elastic"
young = 3e9
poisson = 0.35
[indenter]
type = "Sphere"
radius = 5e-3
[schedule]
load = 1.0
[[dispersions]]
fraction = 0.1
region = [[-0.25e-3, 0.25e-3], [-0.25e-3, 0.25e-3], [0.02e-3, 0.28e-3]]
radius = 80e-6
material = { young = 70e9, poisson = 0.22 }
seed = 3
"""


@pytest.mark.filterwarnings("ignore::framework.errors.ResolutionWarning")
def test_a_dispersions_table_is_the_same_call_and_runs():
    """The table's bodies equal random_dispersion's with its arguments (3 glass spheres, 10 % of the region); the run
    takes them: a stiffer body than the plain matrix, the approach under 1 N below the one without them."""
    tables = tomllib.loads(SCENARIO)
    simulation = scenario.parse(copy.deepcopy(tables)).simulation
    expected = random_dispersion(0.1, ((-0.25e-3, 0.25e-3), (-0.25e-3, 0.25e-3), (0.02e-3, 0.28e-3)), 80e-6,
                                 GLASS, seed=3)
    assert list(simulation.inclusions) == list(expected) and len(expected) == 3
    plain = dict(copy.deepcopy(tables))
    del plain["dispersions"]
    filled = simulation.run().approach[-1]
    assert filled < scenario.parse(plain).simulation.run().approach[-1]


def test_dispersions_add_to_the_inclusions_tables():
    tables = tomllib.loads(SCENARIO)
    tables["inclusions"] = [{"center": [0.0, 0.0, 0.2e-3], "semi_axes": [0.1e-3, 0.1e-3, 0.1e-3],
                             "material": {"young": 70e9, "poisson": 0.22}}]
    tables["dispersions"][0]["region"] = [[-0.25e-3, 0.25e-3], [-0.25e-3, 0.25e-3], [0.02e-3, 0.08e-3]]
    tables["dispersions"][0]["radius"] = 25e-6
    tables["grid"]["shape"] = [80, 80]
    tables["grid"]["layers"] = 40
    bodies = scenario.inclusions_from_tables(tables["inclusions"]) + scenario.dispersions_from_tables(
        tables["dispersions"])
    assert len(bodies) == 1 + len(random_dispersion(0.1, ((-0.25e-3, 0.25e-3), (-0.25e-3, 0.25e-3),
                                                          (0.02e-3, 0.08e-3)), 25e-6, GLASS, seed=3))


@pytest.mark.parametrize("change, pattern", [
    ({"shape": "sphere"}, r"dispersions\[0\]: unknown key\(s\) \['shape'\]"),
    ({"seed": None}, r"dispersions\[0\]: missing required key\(s\) \['seed'\]"),
    ({"fraction": 0.9}, r"dispersions\[0\]: fraction must be a volume fraction in \(0, 0\.6\], got 0\.9"),
    ({"material": {"young": 70e9}}, r"dispersions\[0\]\.material: expected the keys young and poisson"),
    ({"orientation": [1, 0]}, r"dispersions\[0\]: orientation as a direction must be 3 finite numbers"),
])
def test_a_bad_dispersions_table_is_refused_naming_the_key(change, pattern):
    tables = tomllib.loads(SCENARIO)
    table = tables["dispersions"][0]
    for key, value in change.items():
        if value is None:
            del table[key]
        else:
            table[key] = value
    with pytest.raises(scenario.ScenarioError, match=pattern):
        scenario.parse(tables)


@pytest.mark.filterwarnings("ignore::framework.errors.ResolutionWarning")
def test_a_sweep_varies_the_fraction_and_the_seed():
    """Dotted keys dispersions.0.seed and dispersions.0.fraction reach the table: other bodies, more bodies."""
    builder = importlib.import_module("framework.sweep.builder").ScenarioBuilder(tomllib.loads(SCENARIO))
    base = builder().inclusions
    reseeded = builder(**{"dispersions.0.seed": 4}).inclusions
    fuller = builder(**{"dispersions.0.fraction": 0.2}).inclusions
    assert reseeded != base and len(reseeded) == len(base) == 3
    assert len(fuller) == 6
    assert MAX_FRACTION == 0.6


def test_one_body_in_a_dispersion_is_the_one_body_run():
    """A dispersion of a single body (its fraction that body's volume in the region) is the same physics as the
    body given alone: a coupled contact run over it gives the same pressure, eigenstrains and approach, bit for
    bit, as the run over the same ellipsoid written out."""
    import framework as fw
    from framework import indenters, schedules
    from framework.inclusions import Ellipsoid
    glass = materials.Elastic(70e9, 0.22)
    radius = 0.1e-3
    region = ((-0.15e-3, 0.15e-3), (-0.15e-3, 0.15e-3), (0.1e-3, 0.4e-3))
    volume = np.prod([hi - lo for lo, hi in region])
    one = random_dispersion(4 / 3 * np.pi * radius**3 / volume, region, radius, glass, seed=5)
    assert len(one) == 1
    body = one[0]
    alone = Ellipsoid(center=tuple(body.center), semi_axes=(radius,) * 3, material=glass)
    grid = fw.Grid(shape=(32, 32), size=(0.8e-3, 0.8e-3), depth=0.5e-3, layers=20)
    runs = [fw.Simulation(grid=grid, material=materials.Elastic(3e9, 0.35), indenter=indenters.Sphere(radius=5e-3),
                          schedule=schedules.Static(load=[2.0]), inclusions=bodies).run() for bodies in (one, [alone])]
    for a, b in zip(*(run.records for run in runs)):
        assert np.array_equal(a.pressure, b.pressure) and np.array_equal(a.eigenstrain, b.eigenstrain)
        assert a.approach == b.approach


def test_overlapping_tables_are_named_by_table():
    """A body of an [[inclusions]] table overlapping one a [[dispersions]] table placed, or two dispersions' bodies
    overlapping, are named by their table and place in it, not by their place in the combined list."""
    tables = tomllib.loads(SCENARIO)
    placed = random_dispersion(0.1, ((-0.25e-3, 0.25e-3), (-0.25e-3, 0.25e-3), (0.02e-3, 0.28e-3)), 80e-6, GLASS,
                               seed=3)
    tables["inclusions"] = [{"center": list(placed[1].center), "semi_axes": [20e-6] * 3,
                             "material": {"young": 70e9, "poisson": 0.22}}]
    with pytest.raises(errors.FrameworkError, match=r"inclusions\[0\] and dispersions\[0\] body 1 overlap"):
        scenario.parse(copy.deepcopy(tables))
    del tables["inclusions"]
    tables["dispersions"].append(dict(tables["dispersions"][0]))        # the same bodies again
    with pytest.raises(errors.FrameworkError, match=r"dispersions\[0\] body 0 and dispersions\[1\] body 0 overlap"):
        scenario.parse(tables)
