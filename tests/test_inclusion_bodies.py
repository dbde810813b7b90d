"""Inhomogeneity bodies: anisotropic stiffness, ellipsoids, their orientation, overlap and placement on the grid.

References are written here by hand: rotation matrices about one axis, the ellipsoid's quadratic
form in its own frame, the surface sampled densely, the exact volume 4/3 pi a1 a2 a3, the
closed-form cubic stiffness rotated by 45 degrees, and the touching scale of two ellipsoids found
by a convex minimisation (independent of the Perram-Wertheim function under test).
"""
import numpy as np
import pytest
from scipy.optimize import minimize
from scipy.spatial.transform import Rotation

import framework as fw
from framework import config, errors, inclusions, materials
from framework.materials import isotropic_tensor, rotate_stiffness, tensor_to_voigt, voigt_to_tensor

STEEL = materials.Elastic(young=210e9, poisson=0.3)
C11, C12, C44 = 168.4e9, 121.4e9, 75.4e9  # copper, cubic [Pa]


def cubic_voigt(c11=C11, c12=C12, c44=C44):
    stiffness = np.diag([c11, c11, c11, c44, c44, c44])
    stiffness[:3, :3] += c12 * (1.0 - np.eye(3))
    return stiffness


def rotation_about(axis, angle):
    """Rotation matrices written out by hand."""
    c, s = np.cos(angle), np.sin(angle)
    return {0: np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
            1: np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            2: np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


def ellipsoid(center=(0.0, 0.0, 1.0), semi_axes=(0.3, 0.2, 0.1), orientation=None, material=STEEL):
    return inclusions.Ellipsoid(center=center, semi_axes=semi_axes, material=material, orientation=orientation)


# --- stiffness ---------------------------------------------------------------------------------------------

def test_voigt_convention_gives_the_stress_of_the_tensor():
    """sigma_ij = C_ijkl e_kl equals C6 @ [e11, e22, e33, 2e23, 2e13, 2e12] in the order 11 22 33 23 13 12."""
    rng = np.random.default_rng(0)
    c6 = rng.normal(size=(6, 6))
    c6 = c6 @ c6.T
    strain = rng.normal(size=(3, 3))
    strain = strain + strain.T
    stress = np.einsum("ijkl,kl->ij", voigt_to_tensor(c6), strain)
    engineering = [strain[0, 0], strain[1, 1], strain[2, 2], 2 * strain[1, 2], 2 * strain[0, 2], 2 * strain[0, 1]]
    voigt_stress = [stress[0, 0], stress[1, 1], stress[2, 2], stress[1, 2], stress[0, 2], stress[0, 1]]
    np.testing.assert_allclose(voigt_stress, c6 @ engineering, rtol=1e-12)
    assert voigt_to_tensor(c6)[1, 2, 0, 1] == c6[3, 5] and voigt_to_tensor(c6)[2, 1, 1, 0] == c6[3, 5]


def test_voigt_round_trip():
    rng = np.random.default_rng(1)
    c6 = rng.normal(size=(6, 6))
    np.testing.assert_array_equal(tensor_to_voigt(voigt_to_tensor(c6)), c6)
    tensor = voigt_to_tensor(c6 + c6.T)
    np.testing.assert_array_equal(voigt_to_tensor(tensor_to_voigt(tensor)), tensor)


def test_anisotropic_from_the_isotropic_voigt_matrix_equals_elastic():
    young, poisson = 70e9, 0.33
    lame = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    shear = young / (2 * (1 + poisson))
    c6 = np.diag([lame + 2 * shear] * 3 + [shear] * 3)
    c6[:3, :3] += lame * (1 - np.eye(3))
    material = materials.AnisotropicElastic(c6)
    elastic = materials.Elastic(young=young, poisson=poisson)
    np.testing.assert_allclose(material.stiffness_tensor, elastic.stiffness_tensor, rtol=1e-12, atol=1e-12 * young)
    np.testing.assert_allclose(tensor_to_voigt(elastic.stiffness_tensor), c6, rtol=1e-12, atol=1e-12 * young)


def test_rotation_leaves_an_isotropic_tensor_unchanged():
    tensor = isotropic_tensor(210e9, 0.3)
    rotation = Rotation.from_rotvec([0.3, -1.1, 0.7]).as_matrix()
    np.testing.assert_allclose(rotate_stiffness(tensor, rotation), tensor, rtol=0, atol=1e-12 * 210e9)


def test_cubic_stiffness_rotated_about_x3():
    tensor = voigt_to_tensor(cubic_voigt())
    np.testing.assert_allclose(rotate_stiffness(tensor, rotation_about(2, np.pi / 2)), tensor, atol=1e-12 * C11)
    rotated = tensor_to_voigt(rotate_stiffness(tensor, rotation_about(2, np.pi / 4)))
    expected = cubic_voigt()
    expected[0, 0] = expected[1, 1] = (C11 + C12) / 2 + C44   # closed form of the cubic crystal turned 45 deg
    expected[0, 1] = expected[1, 0] = (C11 + C12) / 2 - C44
    expected[5, 5] = (C11 - C12) / 2
    np.testing.assert_allclose(rotated, expected, rtol=0, atol=1e-12 * C11)


def test_ellipsoid_stiffness_is_given_in_its_own_frame():
    """An orthotropic stiffness on an ellipsoid turned 90 deg about x3: its own a1 axis lies along x2."""
    c6 = cubic_voigt()
    c6[0, 0] = 300e9
    body = ellipsoid(material=materials.AnisotropicElastic(c6), orientation=rotation_about(2, np.pi / 2))
    global_voigt = tensor_to_voigt(body.stiffness_tensor)
    assert global_voigt[1, 1] == pytest.approx(300e9, rel=1e-12)
    assert global_voigt[0, 0] == pytest.approx(C11, rel=1e-12)
    np.testing.assert_allclose(ellipsoid(orientation=rotation_about(0, 0.4)).stiffness_tensor,
                               STEEL.stiffness_tensor, atol=1e-12 * STEEL.young)


@pytest.mark.parametrize("stiffness, message", [
    (np.eye(5) * 1e9, r"stiffness must be a 6x6 Voigt matrix \[Pa\], got shape \(5, 5\)"),
    (cubic_voigt() + np.diag([0, 0, 0, 0, 0, np.nan]), r"stiffness must be finite everywhere, got nan at index \(5, 5\)"),
    (cubic_voigt() + np.outer(np.eye(6)[0], np.eye(6)[1]) * 1e6,
     r"stiffness must be symmetric, got \|C\[0,1\] - C\[1,0\]\| = 1e\+06 Pa"),
    (cubic_voigt(c12=C11 * 1.2), r"stiffness must be positive definite .*smallest eigenvalue -[0-9.e+]+ Pa"),
    (cubic_voigt() * 1e7, r"stiffness\[0,0\] must lie between 0.001 and 1e\+15 Pa"),
    ("steel", r"stiffness must be an array of real numbers, got str"),
])
def test_bad_stiffness(stiffness, message):
    with pytest.raises((errors.ParameterError, errors.ShapeError), match=message):
        materials.AnisotropicElastic(stiffness)


def test_stiffness_symmetric_to_rounding_is_accepted_and_made_exact():
    c6 = cubic_voigt()
    c6[0, 1] *= 1 + 1e-14
    material = materials.AnisotropicElastic(c6)
    np.testing.assert_array_equal(material.stiffness, material.stiffness.T)
    assert not material.stiffness.flags.writeable


def test_incompressible_elastic_has_no_stiffness_tensor():
    with pytest.raises(errors.ParameterError, match=r"poisson = 0.5 \(incompressible\) has no finite stiffness"):
        materials.Elastic(young=1e9, poisson=0.5).stiffness_tensor


# --- orientation -------------------------------------------------------------------------------------------

def test_axis_angle_tilts_a1_in_the_x1_x3_plane():
    rotation = inclusions.axis_angle_orientation(axis=[0.0, 2.0, 0.0], angle=np.pi / 6)
    np.testing.assert_allclose(rotation, rotation_about(1, np.pi / 6), atol=1e-15)
    np.testing.assert_allclose(rotation[:, 0], [np.cos(np.pi / 6), 0.0, -np.sin(np.pi / 6)], atol=1e-15)


def test_euler_angles_intrinsic_zxz():
    phi, theta, psi = 0.3, 1.2, -0.8
    by_hand = rotation_about(2, phi) @ rotation_about(0, theta) @ rotation_about(2, psi)
    np.testing.assert_allclose(inclusions.euler_orientation(phi, theta, psi), by_hand, atol=1e-15)
    np.testing.assert_allclose(inclusions.euler_orientation(phi, theta, psi),
                               Rotation.from_euler("ZXZ", [phi, theta, psi]).as_matrix(), atol=1e-15)
    # phi = 90 deg alone turns a1 onto x2 and a2 onto -x1
    np.testing.assert_allclose(inclusions.euler_orientation(np.pi / 2, 0.0, 0.0)[:, :2],
                               [[0, -1], [1, 0], [0, 0]], atol=1e-15)
    for convention in ("zyz", "xyz", "yxz"):
        np.testing.assert_allclose(inclusions.euler_orientation(phi, theta, psi, convention=convention),
                                   Rotation.from_euler(convention.upper(), [phi, theta, psi]).as_matrix(), atol=1e-15)


@pytest.mark.parametrize("kwargs, message", [
    (dict(convention="zzx"), r"convention must be three of 'x', 'y', 'z' .* got 'zzx'"),
    (dict(convention="ZXZ"), r"convention must be .* got 'ZXZ'"),
    (dict(theta=float("inf")), r"theta must be a finite real number, got inf"),
])
def test_bad_euler_angles(kwargs, message):
    arguments = dict(phi=0.1, theta=0.2, psi=0.3) | kwargs
    with pytest.raises(errors.ParameterError, match=message):
        inclusions.euler_orientation(**arguments)


def test_bad_axis():
    with pytest.raises(errors.ParameterError, match=r"axis must be a non-zero vector, got \[0.0, 0.0, 0.0\]"):
        inclusions.axis_angle_orientation(axis=[0, 0, 0], angle=1.0)


# --- one ellipsoid -----------------------------------------------------------------------------------------

def test_contains_matches_the_quadratic_form_of_a_tilted_ellipsoid():
    center, axes = np.array([0.1, -0.2, 1.0]), np.array([0.5, 0.3, 0.1])
    rotation = rotation_about(1, np.pi / 6) @ rotation_about(2, 0.4)
    body = ellipsoid(center=center, semi_axes=axes, orientation=rotation)
    points = center + np.random.default_rng(2).uniform(-0.6, 0.6, size=(5000, 3))
    own = [(points - center) @ rotation[:, k] for k in range(3)]           # coordinates along the semi-axes
    by_hand = (own[0] / axes[0]) ** 2 + (own[1] / axes[1]) ** 2 + (own[2] / axes[2]) ** 2 <= 1.0
    inside = body.contains(points)
    assert inside.shape == (5000,) and 100 < inside.sum() < 4900
    np.testing.assert_array_equal(inside, by_hand)
    tip = rotation[:, 0] * axes[0]       # the ends of a1: just inside, just outside
    assert body.contains([center + tip * (1 - 1e-9), center - tip * (1 + 1e-9)]).tolist() == [True, False]


def test_bounds_are_the_extremes_of_the_surface():
    body = ellipsoid(center=(0.2, 0.1, 1.0), semi_axes=(0.5, 0.3, 0.1),
                     orientation=inclusions.euler_orientation(0.7, 0.9, -0.4))
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 1201), np.linspace(0, np.pi, 601), indexing="ij")
    sphere = np.stack([np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)], axis=-1).reshape(-1, 3)
    surface = np.asarray(body.center) + (sphere * body.semi_axes) @ body.orientation.T
    lower, upper = body.bounds()
    half = (upper - lower) / 2
    assert np.all(surface.min(axis=0) >= lower - 1e-12) and np.all(surface.max(axis=0) <= upper + 1e-12)
    np.testing.assert_allclose(surface.max(axis=0), upper, rtol=0, atol=3e-5 * half.max())   # sampling step 5e-3 rad
    np.testing.assert_allclose(surface.min(axis=0), lower, rtol=0, atol=3e-5 * half.max())
    assert body.volume == pytest.approx(4 / 3 * np.pi * 0.5 * 0.3 * 0.1, rel=1e-15)


@pytest.mark.parametrize("kwargs, error, message", [
    (dict(center=(0, 0, 0)), errors.ParameterError, r"center\[2\] \(the depth of the centre\) must be positive \[m\], got 0.0"),
    (dict(center=(0, 0, -1e-3)), errors.ParameterError, r"center\[2\] .* must be positive \[m\], got -0.001"),
    (dict(center=(0, 1)), errors.ShapeError, r"center has shape \(2,\), expected \(3,\)"),
    (dict(center=(2e6, 0, 1)), errors.ParameterError, r"center\[0\] must lie within \+-1e\+06 m"),
    (dict(semi_axes=(0.1, 0.0, 0.1)), errors.ParameterError, r"semi_axes\[1\] must be positive \[m\], got 0.0"),
    (dict(semi_axes=(0.1, 0.1, float("nan"))), errors.ParameterError, r"semi_axes must be finite everywhere, got nan"),
    (dict(material=materials.PMMA), errors.ParameterError,
     r"material must be materials.Elastic or materials.AnisotropicElastic \(inhomogeneities are elastic\), got Viscoelastic"),
    (dict(material=210e9), errors.ParameterError, r"material must be .* got float"),
    (dict(orientation=np.eye(2)), errors.ShapeError, r"orientation has shape \(2, 2\), expected \(3, 3\)"),
    (dict(orientation=np.diag([1.0, 1.0, 1.001])), errors.ParameterError,
     r"orientation must be a rotation matrix .*got max \|R\^T R - I\| = 0.002"),
    (dict(orientation=np.diag([1.0, -1.0, 1.0])), errors.ParameterError,
     r"orientation must be a proper rotation \(det = \+1\), got det = -1 \(a reflection\)"),
])
def test_bad_ellipsoid(kwargs, error, message):
    with pytest.raises(error, match=message):
        ellipsoid(**kwargs)


def test_rounded_orientation_is_made_exactly_orthogonal():
    typed = np.round(inclusions.euler_orientation(0.1, 0.2, 0.3), 11)
    body = ellipsoid(orientation=typed)
    np.testing.assert_allclose(body.orientation.T @ body.orientation, np.eye(3), atol=1e-15)
    np.testing.assert_allclose(body.orientation, typed, atol=1e-10)


# --- sets: overlap, indicator, placement ---------------------------------------------------------------------

def touching_scale_squared(first, second):
    """min over x of max(q_A(x), q_B(x)): the square of the scale at which the two ellipsoids touch."""
    forms = [np.linalg.inv(body.shape_matrix) for body in (first, second)]
    centers = [np.asarray(body.center) for body in (first, second)]

    def q(x, k):
        return (x - centers[k]) @ forms[k] @ (x - centers[k])

    constraints = [{"type": "ineq", "fun": (lambda z, k=k: z[3] - q(z[:3], k))} for k in (0, 1)]
    middle = 0.5 * (centers[0] + centers[1])
    start = np.append(middle, max(q(middle, 0), q(middle, 1)))
    best = minimize(lambda z: z[3], start, constraints=constraints, method="SLSQP",
                    options={"ftol": 1e-14, "maxiter": 500})
    # SLSQP may stop at the optimum saying it cannot improve further: check the point is feasible instead
    return max(q(best.x[:3], 0), q(best.x[:3], 1))


def test_contact_function_against_the_touching_scale():
    rng = np.random.default_rng(3)
    for _ in range(12):
        pair = [ellipsoid(center=rng.uniform(-1, 1, 3) + [0, 0, 5], semi_axes=rng.uniform(0.2, 1.5, 3),
                          orientation=Rotation.random(random_state=rng).as_matrix()) for _ in range(2)]
        expected, value = touching_scale_squared(*pair), inclusions.contact_function(*pair)
        # any point bounds the minimum from above and PW's lambda-maximum is its dual: value <= expected
        assert value == pytest.approx(expected, rel=1e-10) and value <= expected * (1 + 1e-12)
    spheres = ellipsoid(semi_axes=(0.2,) * 3), ellipsoid(center=(0.3, 0.4, 1.0), semi_axes=(0.3,) * 3)
    assert inclusions.contact_function(*spheres) == pytest.approx((0.5 / 0.5) ** 2, rel=1e-12)


@pytest.mark.parametrize("gap, overlapping", [(-1e-9, True), (0.0, True), (1e-9, False)])
def test_two_spheres_at_twice_the_radius(gap, overlapping):
    radius = 0.1
    pair = [ellipsoid(semi_axes=(radius,) * 3),
            ellipsoid(center=(2 * radius * (1 + gap) / np.sqrt(2), 2 * radius * (1 + gap) / np.sqrt(2), 1.0),
                      semi_axes=(radius,) * 3)]
    if overlapping:
        with pytest.raises(errors.InclusionError, match=r"inclusions\[0\] and inclusions\[1\] overlap or touch"):
            inclusions.InclusionSet(pair)
    else:
        assert len(inclusions.InclusionSet(pair)) == 2


def test_crossed_needles_overlap_only_when_turned_across():
    needle = dict(semi_axes=(1.0, 0.05, 0.05))
    first = ellipsoid(center=(0.0, 0.0, 2.0), **needle)
    for angle, overlapping in [(0.0, False), (np.pi / 2, True), (np.pi / 8, True), (np.pi / 30, False)]:
        # the second needle's middle lies 0.3 m beside the first's, its axis turned by `angle` about x3
        second = ellipsoid(center=(0.6, 0.3, 2.0), orientation=rotation_about(2, angle), **needle)
        value = inclusions.contact_function(first, second)
        assert (value < 1.0) == overlapping, (angle, value)
    # the same two needles, one above the other, cross without touching
    second = ellipsoid(center=(0.0, 0.0, 2.2), orientation=rotation_about(2, np.pi / 2), **needle)
    assert len(inclusions.InclusionSet([first, second])) == 2
    second = ellipsoid(center=(0.0, 0.0, 2.09), orientation=rotation_about(2, np.pi / 2), **needle)
    with pytest.raises(errors.InclusionError, match=r"inclusions\[0\] and inclusions\[1\] overlap"):
        inclusions.InclusionSet([first, second])


def test_ellipsoid_inside_another_overlaps():
    outer = ellipsoid(semi_axes=(0.5, 0.4, 0.3), orientation=rotation_about(0, 0.3))
    inner = ellipsoid(center=(0.05, 0.0, 1.02), semi_axes=(0.1, 0.05, 0.05), orientation=rotation_about(2, 1.0))
    far = ellipsoid(center=(3.0, 0.0, 1.0))
    assert inclusions.contact_function(outer, inner) < 1.0
    with pytest.raises(errors.InclusionError, match=r"inclusions\[1\] and inclusions\[2\] overlap"):
        inclusions.InclusionSet([far, outer, inner])


def test_set_is_a_sequence_of_ellipsoids():
    bodies = [ellipsoid(center=(x, 0.0, 1.0)) for x in (-1.0, 0.0, 1.0)]
    group = inclusions.InclusionSet(bodies)
    assert len(group) == 3 and list(group) == bodies and group[1] is bodies[1] and group[-1] is bodies[2]
    empty = inclusions.InclusionSet([])
    assert len(empty) == 0 and empty.bounds() is None
    assert not empty.indicator([0.0, 1.0], [0.0], [0.5]).any()
    empty.check_inside(fw.Grid(shape=(8, 8), size=(1.0, 1.0), periodic=(True, True)))
    lower, upper = group.bounds()
    np.testing.assert_allclose(lower, [-1.3, -0.2, 0.9])
    np.testing.assert_allclose(upper, [1.3, 0.2, 1.1])


@pytest.mark.parametrize("inclusion_list, message", [
    ([ellipsoid(), "ellipsoid"], r"inclusions\[1\] must be an inclusions.Ellipsoid, got str"),
    ([None], r"inclusions\[0\] must be an inclusions.Ellipsoid, got NoneType"),
    (ellipsoid(), r"inclusions must be a list of inclusions.Ellipsoid, got Ellipsoid"),
])
def test_bad_set(inclusion_list, message):
    with pytest.raises(errors.ParameterError, match=message):
        inclusions.InclusionSet(inclusion_list)


def test_indicator_marks_each_ellipsoid_and_agrees_with_contains():
    bodies = [ellipsoid(center=(-0.3, 0.1, 0.5), semi_axes=(0.2, 0.1, 0.15), orientation=rotation_about(1, 0.5)),
              ellipsoid(center=(0.3, -0.1, 0.6), semi_axes=(0.25, 0.1, 0.1), orientation=rotation_about(2, 1.0))]
    group = inclusions.InclusionSet(bodies)
    x1, x2, x3 = np.linspace(-0.7, 0.7, 57), np.linspace(-0.4, 0.4, 33), np.linspace(0.05, 1.0, 40)
    marks = group.indicator(x1, x2, x3)
    assert marks.shape == (57, 33, 40) and marks.dtype == np.int8
    points = np.stack(np.meshgrid(x1, x2, x3, indexing="ij"), axis=-1)
    expected = bodies[0].contains(points) * 1 + bodies[1].contains(points) * 2
    np.testing.assert_array_equal(marks, expected)
    assert (marks == 1).sum() > 100 and (marks == 2).sum() > 100
    with pytest.raises(errors.ParameterError, match=r"x2 must be strictly increasing"):
        group.indicator(x1, x2[::-1], x3)


def test_indicator_volume_converges_at_second_order():
    """Counted cuboids x cell volume -> 4/3 pi a1 a2 a3; the RMS error over random lattice shifts falls as h^2.

    (Lattice-point counting of a smooth convex body in 3-D: relative standard deviation ~ h^2.)
    """
    body = ellipsoid(center=(0.013, -0.021, 0.6), semi_axes=(0.4, 0.25, 0.15),
                     orientation=inclusions.euler_orientation(0.4, 0.7, 1.1))
    group = inclusions.InclusionSet([body])
    exact = 4 / 3 * np.pi * 0.4 * 0.25 * 0.15
    rng = np.random.default_rng(1)
    counts, rms = [16, 32, 64, 128], []
    for n in counts:
        h = 1.2 / n
        errors_ = []
        for shift in rng.random((8, 3)):
            x1, x2, x3 = ((np.arange(n) + shift[i]) * h - 0.6 * (i < 2) for i in range(3))
            errors_.append((group.indicator(x1, x2, x3) > 0).sum() * h**3 / exact - 1)
        rms.append(np.sqrt(np.mean(np.square(errors_))))
    order = -np.polyfit(np.log(counts), np.log(rms), 1)[0]
    assert order > 1.7, (order, rms)   # measured 1.99
    assert rms[-1] < 6e-4              # measured 3.5e-4 at 128^3


def grid(**kwargs):
    arguments = dict(shape=(64, 64), size=(2.0, 2.0), depth=1.0, layers=32) | kwargs
    return fw.Grid(**arguments)


def test_well_placed_inclusions_pass():
    tilted = ellipsoid(center=(0.5, -0.5, 0.5), semi_axes=(0.3, 0.15, 0.1), orientation=rotation_about(1, np.pi / 4))
    inclusions.InclusionSet([tilted, ellipsoid(center=(-0.5, 0.5, 0.5))]).check_inside(grid())


@pytest.mark.parametrize("body, grid_kwargs, message", [
    (ellipsoid(center=(0, 0, 0.1), semi_axes=(0.3, 0.2, 0.1)), {},
     r"inclusions\[0\] cuts the surface: its top lies at x3 = 0 m .*expected x3 > 0"),
    (ellipsoid(center=(0, 0, 0.25), semi_axes=(0.3, 0.2, 0.1), orientation=rotation_about(1, np.pi / 2)), {},
     r"inclusions\[0\] cuts the surface: its top lies at x3 = -0.05 m \(center\[2\] = 0.25 m, half-extent along x3 0.3 m\)"),
    (ellipsoid(center=(0, 0, 0.95)), {},
     r"inclusions\[0\] leaves the subsurface box: its bottom lies at x3 = 1.05 m, deeper than grid.depth = 1 m"),
    (ellipsoid(center=(0.8, 0, 0.5)), {},
     r"inclusions\[0\] leaves the subsurface box along x1: it spans \[0.5, 1.1\] m, the grid \[-1, 1\] m"),
    (ellipsoid(center=(0, -0.9, 0.5)), {}, r"inclusions\[0\] leaves the subsurface box along x2: it spans \[-1.1, -0.7\] m"),
    (ellipsoid(center=(0, 0, 0.5)), dict(layers=0), r"grid.layers = 0: inclusions need subsurface layers"),
    (ellipsoid(center=(0, 0, 0.5)), dict(periodic=(False, True)),
     r"grid.periodic = \(False, True\): inclusions need an open grid .* expected periodic = \(False, False\)"),
    (ellipsoid(center=(0, 0, 0.5), semi_axes=(0.3, 0.2, 0.08)), {},
     r"inclusions\[0\]: semi_axes\[2\] = 0.08 m spans only 2.56 cuboids along its direction \[0.0, 0.0, 1.0\] "
     r"\(cuboids 0.0312 x 0.0312 x 0.0312 m\); expected at least 3"),
])
def test_badly_placed_inclusion(body, grid_kwargs, message):
    group = inclusions.InclusionSet([ellipsoid(center=(-0.6, -0.6, 0.5), semi_axes=(0.2, 0.2, 0.2)), body])
    message = message.replace(r"inclusions\[0\]", r"inclusions\[1\]")
    with pytest.raises(errors.InclusionError, match=message):
        group.check_inside(grid(**grid_kwargs))


def test_resolution_is_counted_along_the_tilted_semi_axis():
    """a1 along (1, 0, 1)/sqrt(2) on cuboids 0.1 x 0.1 x 0.02: a1 / sqrt((0.1^2 + 0.02^2) / 2) cells."""
    flat = grid(shape=(20, 20), layers=50)
    direction_spacing = np.sqrt((0.1**2 + 0.02**2) / 2)
    turned = rotation_about(1, -np.pi / 4)   # column 0 = (cos, 0, sin) 45 deg: a1 along (1, 0, 1)/sqrt(2)
    np.testing.assert_allclose(turned[:, 0], [1 / np.sqrt(2), 0, 1 / np.sqrt(2)], atol=1e-15)
    enough = 3.01 * direction_spacing
    inclusions.InclusionSet([ellipsoid(center=(0, 0, 0.5), semi_axes=(enough, 0.31, 0.31),
                                       orientation=turned)]).check_inside(flat)
    short = 2.99 * direction_spacing
    with pytest.raises(errors.InclusionError, match=r"semi_axes\[0\] = 0.215612 m spans only 2.99 cuboids along its "
                                                    r"direction \[0.707107, 0.0, 0.707107\]"):
        inclusions.InclusionSet([ellipsoid(center=(0, 0, 0.5), semi_axes=(short, 0.31, 0.31),
                                           orientation=turned)]).check_inside(flat)


def test_check_inside_wants_a_grid():
    with pytest.raises(errors.ParameterError, match=r"grid must be a framework.Grid, got tuple"):
        inclusions.InclusionSet([ellipsoid()]).check_inside((64, 64))


def test_configuration_round_trip():
    c6 = cubic_voigt()
    group = inclusions.InclusionSet([
        ellipsoid(material=materials.AnisotropicElastic(c6), orientation=inclusions.euler_orientation(0.3, 0.5, 0.2)),
        ellipsoid(center=(1.0, 0.0, 1.0))])
    data = config.describe(group)
    assert data["inclusions"][0]["material"]["type"] == "AnisotropicElastic"
    rebuilt = config.build(data)
    assert rebuilt == group and rebuilt is not group
    assert rebuilt[0].material == materials.AnisotropicElastic(c6) and hash(rebuilt[0]) == hash(group[0])
