"""Checks of framework.reference.eshelby against independent computations.

- Eshelby tensors against Mura's (1987, eq. 11.39) unit-sphere integral of the
  Green's function in Fourier form, which shares nothing with the I-integrals;
  the I-integrals against their defining lambda-integrals by adaptive quadrature.
- Closed forms: sphere, penny-shaped crack and circular cylinder limits (Mura 11.3),
  THEORY's elliptic-integral and spheroid forms at well separated semi-axes.
- Interior fields against the sphere's closed forms (bulk and shear), rotations,
  a cubic inclusion.
- Mindlin & Cheng against image + Boussinesq correction by quadrature.
- Hertz axis stresses against Boussinesq ring-load quadrature; the dilute approach
  change against Sneddon's axisymmetric contact solved with the Mindlin & Cheng
  surface displacement added to the profile.
"""
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import ellipeinc, ellipkinc, ellipkm1
from scipy.spatial.transform import Rotation

from framework.errors import ParameterError, ShapeError
from framework.reference import (dilatation_strength, dilatation_surface_displacement, dilute_approach_change,
                                 eshelby_integrals, eshelby_tensor, hertz_axis_stress, hertz_axis_stress_rate,
                                 interior_solution, isotropic_stiffness)

NU = 0.3
YOUNG = 2.0e9


def stiffness(young, poisson):
    """Isotropic stiffness written out component by component (independent of the module's einsum)."""
    shear = young / (2 * (1 + poisson))
    lame = 2 * shear * poisson / (1 - 2 * poisson)
    tensor = np.zeros((3, 3, 3, 3))
    for i in range(3):
        for j in range(3):
            tensor[i, i, j, j] += lame
            tensor[i, j, i, j] += shear
            tensor[i, j, j, i] += shear
    return tensor


def eshelby_by_fourier_integral(semi_axes, poisson, polar=2, nodes=160):
    """Mura (1987) eq. 11.39: S_ijmn = (1/8 pi) C_pqmn int_{|zeta|=1} [n_j n_q A_ip + n_i n_q A_jp] dA.

    ``n`` is the unit vector along ``xi = zeta / a`` and ``A = (delta - n n / (2 (1 - nu))) / mu`` the
    inverse of the acoustic tensor C_ijkl n_j n_l of the isotropic matrix.  The integrand is even
    (zeta -> -zeta): one hemisphere about the semi-axis ``polar``, doubled.  ``s`` the ratio of that
    semi-axis to the others' geometric mean, the polar coordinate is clustered where a flat or
    slender spheroid makes the integrand steep: ``t = cos(theta) = s sinh(u)`` if s < 1,
    ``theta = sinh(u) / s`` if s > 1; Gauss-Legendre in u, trapezoid (spectral) in azimuth.
    """
    axes = np.asarray(semi_axes, float) / max(semi_axes)
    others = [k for k in range(3) if k != polar]
    ratio = axes[polar] / np.sqrt(axes[others[0]] * axes[others[1]])
    nodes_u, weights_u = np.polynomial.legendre.leggauss(nodes)
    if ratio <= 1.0:
        limit = np.arcsinh(1.0 / ratio)
        u = 0.5 * limit * (nodes_u + 1)
        t, wt = ratio * np.sinh(u), weights_u * 0.5 * limit * ratio * np.cosh(u)
    else:
        limit = np.arcsinh(0.5 * np.pi * ratio)
        u = 0.5 * limit * (nodes_u + 1)
        theta = np.sinh(u) / ratio
        t, wt = np.cos(theta), weights_u * 0.5 * limit * np.cosh(u) / ratio * np.sin(theta)
    phi = 2 * np.pi * np.arange(2 * nodes) / (2 * nodes)
    t, phi = np.meshgrid(t, phi, indexing="ij")
    weights = np.broadcast_to(2 * wt[:, None] * (2 * np.pi / phi.shape[1]), t.shape).ravel()
    zeta = np.empty(t.shape + (3,))
    zeta[..., polar] = t
    zeta[..., others[0]] = np.sqrt(1 - t**2) * np.cos(phi)
    zeta[..., others[1]] = np.sqrt(1 - t**2) * np.sin(phi)
    xi = zeta.reshape(-1, 3) / axes
    n = xi / np.linalg.norm(xi, axis=1, keepdims=True)
    shear = 1.0 / (2 * (1 + poisson))
    inverse = (np.eye(3) - n[:, :, None] * n[:, None, :] / (2 * (1 - poisson))) / shear
    kernel = np.einsum("a,aj,aq,aip->ijpq", weights, n, n, inverse)
    kernel = kernel + kernel.transpose(1, 0, 2, 3)
    return np.einsum("pqmn,ijpq->ijmn", stiffness(1.0, poisson), kernel) / (8 * np.pi)


def integrals_by_quadrature(semi_axes):
    """I_i and I_ij from their lambda-integrals (Mura eqs. 11.18-11.19), s = exp(v), by quad."""
    x = np.asarray(semi_axes, float) ** 2
    factor = 2 * np.pi * np.sqrt(np.prod(x))
    breaks = np.sort(np.log(x))
    low, high = breaks[0] - 45.0, breaks[-1] + 30.0  # the tails beyond are below 1e-19 of the integral

    def integral(*indices):
        def integrand(v):
            s = np.exp(v)
            return factor * s / (np.prod(x[list(indices)] + s) * np.sqrt(np.prod(x + s)))
        return quad(integrand, low, high, points=breaks, epsabs=0.0, epsrel=1e-13, limit=400)[0]

    return (np.array([integral(i) for i in range(3)]),
            np.array([[integral(i, j) for j in range(3)] for i in range(3)]))


ASPECTS = [(1, 1, 1), (2, 1, 1), (1, 1, 0.5), (3, 2, 1), (10, 3, 1), (1, 3, 2), (0.5, 1, 1),
           (1, 1 + 1e-4, 0.5), (1, 1 - 1e-7, 0.5), (1, 1 + 1e-10, 0.5), (0.5, 1, 1 - 1e-4), (0.5, 1, 1 + 1e-7),
           (1 + 1e-10, 0.5, 1), (1, 1 - 1e-5, 1 - 2e-5), (1, 1 - 1e-8, 1 + 1e-8)]


@pytest.mark.parametrize("semi_axes", ASPECTS)
def test_eshelby_tensor_matches_fourier_integral(semi_axes):
    """Every component within 1e-11 of the largest, whatever the order and near-equality of the semi-axes."""
    expected = eshelby_by_fourier_integral(semi_axes, NU, nodes=80)
    assert np.abs(eshelby_tensor(semi_axes, NU) - expected).max() < 1e-11


@pytest.mark.parametrize("semi_axes, polar", [((1, 1, 1e-3), 2), ((1e-3, 1, 1), 0), ((1, 1e-3, 1e-3), 0),
                                              ((1e-3, 1e-3, 1), 2), ((1, 1, 1e-3 * (1 + 1e-7)), 2)])
def test_eshelby_tensor_matches_fourier_integral_at_aspect_ratio_1e3(semi_axes, polar):
    """Penny- and needle-like spheroids, aspect 1e-3, every component within 1e-10 of the largest."""
    expected = eshelby_by_fourier_integral(semi_axes, NU, polar=polar, nodes=200)
    assert np.abs(eshelby_tensor(semi_axes, NU) - expected).max() < 1e-10


@pytest.mark.parametrize("semi_axes", [(1, 1, 1), (3, 2, 1), (10, 3, 1), (1, 1, 1e-3), (1, 1e-3, 1e-3),
                                       (1, 1e-3, 2e-3), (1e-3, 1, 0.3), (1, 1 + 1e-10, 0.5),
                                       (1, 1 - 1e-7, 1 - 2e-7), (1, 0.3, 0.3 * (1 + 1e-4)), (2e-6, 3e-6, 1e-6)])
def test_eshelby_integrals_match_lambda_quadrature(semi_axes):
    """I_i and I_ij to 1e-12 relative (measured: below 1e-15), including metres-scale ellipsoids."""
    single, double = eshelby_integrals(semi_axes)
    single_q, double_q = integrals_by_quadrature(semi_axes)
    assert np.abs(single / single_q - 1).max() < 1e-12
    assert np.abs(double / double_q - 1).max() < 1e-12
    assert abs(single.sum() - 4 * np.pi) < 1e-13  # Mura eq. 11.20


@pytest.mark.parametrize("poisson", [-0.5, 0.0, 0.3, 0.5])
def test_sphere_closed_form(poisson):
    tensor = eshelby_tensor((2e-3, 2e-3, 2e-3), poisson)
    for i, j in [(0, 1), (1, 2), (2, 0)]:
        assert tensor[i, i, i, i] == pytest.approx((7 - 5 * poisson) / (15 * (1 - poisson)), rel=1e-14)
        assert tensor[i, i, j, j] == pytest.approx((5 * poisson - 1) / (15 * (1 - poisson)), abs=1e-15)
        assert tensor[i, j, i, j] == pytest.approx((4 - 5 * poisson) / (15 * (1 - poisson)), rel=1e-14)


def test_penny_and_cylinder_limits():
    """Mura (1987) section 11.3: flat (a3 -> 0) and long (a3 -> inf) circular spheroids, errors O(ratio)."""
    penny = eshelby_tensor((1.0, 1.0, 1e-8), NU)
    assert penny[2, 2, 2, 2] == pytest.approx(1.0, abs=1e-7)
    assert penny[2, 2, 0, 0] == pytest.approx(NU / (1 - NU), abs=1e-7)
    assert penny[0, 2, 0, 2] == pytest.approx(0.5, abs=1e-7)
    assert abs(penny[0, 0, 0, 0]) + abs(penny[0, 0, 1, 1]) + abs(penny[0, 1, 0, 1]) < 1e-7
    cylinder = eshelby_tensor((1e-8, 1e-8, 1.0), NU)
    expected = {(0, 0, 0, 0): (5 - 4 * NU) / (8 * (1 - NU)), (0, 0, 1, 1): (4 * NU - 1) / (8 * (1 - NU)),
                (0, 0, 2, 2): NU / (2 * (1 - NU)), (0, 1, 0, 1): (3 - 4 * NU) / (8 * (1 - NU)),
                (0, 2, 0, 2): 0.25, (2, 2, 2, 2): 0.0, (2, 2, 0, 0): 0.0}
    for index, value in expected.items():
        assert cylinder[index] == pytest.approx(value, abs=1e-12)


def test_theory_elliptic_and_spheroid_forms():
    """THEORY's appendix forms (Mura eqs. 11.22, 11.27-11.28) where they are well conditioned."""
    a1, a2, a3 = 3.0, 2.0, 1.0
    theta = np.arcsin(np.sqrt(1 - a3**2 / a1**2))
    m = (a1**2 - a2**2) / (a1**2 - a3**2)  # scipy's parameter is k^2
    f, e = ellipkinc(theta, m), ellipeinc(theta, m)
    i1 = 4 * np.pi * a1 * a2 * a3 * (f - e) / ((a1**2 - a2**2) * np.sqrt(a1**2 - a3**2))
    i3 = (4 * np.pi * a1 * a2 * a3 * (a2 * np.sqrt(a1**2 - a3**2) / (a1 * a3) - e)
          / ((a2**2 - a3**2) * np.sqrt(a1**2 - a3**2)))
    single, double = eshelby_integrals((a1, a2, a3))
    np.testing.assert_allclose(single, [i1, 4 * np.pi - i1 - i3, i3], rtol=1e-13)
    assert double[0, 1] == pytest.approx((single[1] - single[0]) / (a1**2 - a2**2), rel=1e-13)
    assert 3 * double[0, 0] == pytest.approx(4 * np.pi / a1**2 - double[0, 1] - double[0, 2], rel=1e-13)
    a, c = 1.0, 0.2  # oblate a1 = a2 > a3
    oblate = 2 * np.pi * a**2 * c / (a**2 - c**2) ** 1.5 * (np.arccos(c / a) - c / a * np.sqrt(1 - c**2 / a**2))
    np.testing.assert_allclose(eshelby_integrals((a, a, c))[0][:2], oblate, rtol=1e-13)
    prolate = 2 * np.pi * a * c**2 / (a**2 - c**2) ** 1.5 * (a / c * np.sqrt(a**2 / c**2 - 1) - np.arccosh(a / c))
    np.testing.assert_allclose(eshelby_integrals((a, c, c))[0][1:], prolate, rtol=1e-13)


def test_isotropic_stiffness():
    np.testing.assert_allclose(isotropic_stiffness(YOUNG, NU), stiffness(YOUNG, NU), rtol=1e-15)


def bulk_and_shear(young, poisson):
    return young / (3 * (1 - 2 * poisson)), young / (2 * (1 + poisson))


@pytest.mark.parametrize("young_inclusion, poisson_inclusion", [(2e8, 0.2), (2e11, 0.35), (1e-3, 0.0)])
def test_sphere_inhomogeneity_closed_forms(young_inclusion, poisson_inclusion):
    """Bulk and shear parts: eps_in = eps0 (3K_M + 4 mu_M)/(3K_I + 4 mu_M), eps0 / (1 + beta (mu_I/mu_M - 1))."""
    bulk_m, shear_m = bulk_and_shear(YOUNG, NU)
    bulk_i, shear_i = bulk_and_shear(young_inclusion, poisson_inclusion)
    beta = 2 * (4 - 5 * NU) / (15 * (1 - NU))
    applied = np.array([[1.0, 0.4, -0.2], [0.4, -0.5, 0.3], [-0.2, 0.3, 0.8]]) * 1e-3
    volumetric = np.trace(applied) / 3 * np.eye(3)
    expected = (volumetric * (3 * bulk_m + 4 * shear_m) / (3 * bulk_i + 4 * shear_m)
                + (applied - volumetric) / (1 + beta * (shear_i / shear_m - 1)))
    solution = interior_solution((1e-4, 1e-4, 1e-4), None, YOUNG, NU, stiffness(young_inclusion, poisson_inclusion),
                                 applied)
    np.testing.assert_allclose(solution.strain, expected, rtol=1e-12, atol=1e-15)
    inclusion_stress = np.einsum("ijkl,kl->ij", stiffness(young_inclusion, poisson_inclusion), expected)
    np.testing.assert_allclose(solution.stress, inclusion_stress, rtol=1e-12, atol=1e-12 * YOUNG * 1e-3)
    # Equivalence: the matrix material with eps* carries the same stress.
    matrix_stress = np.einsum("ijkl,kl->ij", stiffness(YOUNG, NU), solution.strain - solution.eigenstrain)
    np.testing.assert_allclose(matrix_stress, solution.stress, atol=1e-12 * YOUNG * 1e-3)


def test_same_material_gives_no_eigenstrain():
    rotation = Rotation.from_euler("zyx", [0.3, -1.1, 0.7]).as_matrix()
    applied = np.array([[1.0, 0.4, -0.2], [0.4, -0.5, 0.3], [-0.2, 0.3, 0.8]]) * 1e-3
    solution = interior_solution((3e-5, 2e-5, 1e-5), rotation, YOUNG, NU, stiffness(YOUNG, NU), applied)
    assert np.abs(solution.eigenstrain).max() < 1e-14 * 1e-3
    np.testing.assert_allclose(solution.strain, applied, atol=1e-17)


def cubic_stiffness(c11, c12, c44):
    tensor = np.zeros((3, 3, 3, 3))
    for i in range(3):
        for j in range(3):
            tensor[i, i, j, j] = c11 if i == j else c12
            if i != j:
                tensor[i, j, i, j] = tensor[i, j, j, i] = c44
    return tensor


def test_cubic_sphere_and_rotation():
    """A cubic sphere: its bulk, (C11-C12)/2 and C44 modes follow the isotropic closed forms; a rotation
    of ellipsoid, stiffness and strain together rotates the answer."""
    c11, c12, c44 = 1.7e10, 1.2e10, 0.75e10
    cubic = cubic_stiffness(c11, c12, c44)
    bulk_m, shear_m = bulk_and_shear(YOUNG, NU)
    beta = 2 * (4 - 5 * NU) / (15 * (1 - NU))
    sphere = (1e-4, 1e-4, 1e-4)
    hydro = interior_solution(sphere, None, YOUNG, NU, cubic, 1e-3 * np.eye(3)).strain
    np.testing.assert_allclose(hydro, 1e-3 * np.eye(3) * (3 * bulk_m + 4 * shear_m) / (c11 + 2 * c12 + 4 * shear_m),
                               rtol=1e-12, atol=1e-18)
    for mode, modulus in [(np.diag([1.0, -1.0, 0.0]), (c11 - c12) / 2), (np.array([[0, 1, 0], [1, 0, 0], [0, 0, 0.]]), c44)]:
        strain = interior_solution(sphere, None, YOUNG, NU, cubic, 1e-3 * mode).strain
        np.testing.assert_allclose(strain, 1e-3 * mode / (1 + beta * (modulus / shear_m - 1)), rtol=1e-12, atol=1e-18)
    rotation = Rotation.from_euler("zyx", [0.3, -1.1, 0.7]).as_matrix()
    applied = np.array([[1.0, 0.4, -0.2], [0.4, -0.5, 0.3], [-0.2, 0.3, 0.8]]) * 1e-3
    axes = (3e-5, 2e-5, 1e-5)
    local = interior_solution(axes, None, YOUNG, NU, cubic, applied)
    rotated_stiffness = np.einsum("ia,jb,kc,ld,abcd->ijkl", rotation, rotation, rotation, rotation, cubic)
    rotated = interior_solution(axes, rotation, YOUNG, NU, rotated_stiffness, rotation @ applied @ rotation.T)
    for name in ("eigenstrain", "strain", "stress"):
        value = getattr(local, name)
        np.testing.assert_allclose(getattr(rotated, name), rotation @ value @ rotation.T,
                                   atol=1e-13 * np.abs(value).max())


def test_void_ellipsoid_is_traction_free_inside():
    """A cavity (C_I = 0) has zero stress inside, its eigenstrain equals its strain."""
    solution = interior_solution((3e-5, 2e-5, 1e-5), None, YOUNG, NU, np.zeros((3, 3, 3, 3)), 1e-3 * np.eye(3))
    assert np.abs(solution.stress).max() == 0.0
    np.testing.assert_allclose(solution.eigenstrain, solution.strain, rtol=1e-14)


def test_dilatation_strength_from_continuity():
    """C from continuity of u_r and s_rr at r = a: inside eps = alpha eps* delta (alpha unknown),
    s_rr = 3K (alpha - 1) eps*; outside u = C x / r^3, s_rr = -4 mu C / a^3; u_r(a) = alpha eps* a = C / a^2."""
    radius, eigenstrain = 2e-5, 1e-3
    bulk, shear = bulk_and_shear(YOUNG, NU)
    system = np.array([[3 * bulk * eigenstrain, 4 * shear / radius**3], [eigenstrain * radius, -1 / radius**2]])
    alpha, strength = np.linalg.solve(system, [3 * bulk * eigenstrain, 0.0])
    assert dilatation_strength(radius, eigenstrain, NU) == pytest.approx(strength, rel=1e-13)
    assert alpha == pytest.approx(eshelby_tensor((radius,) * 3, NU)[0, 0, :, :].trace(), rel=1e-13)


def test_mindlin_cheng_surface_displacement():
    """Source + image (u_r doubled, u_3 cancelled, normal traction doubled) + Boussinesq response to the
    pressure p = 4 mu C (r^2 - 2c^2)/R^5 that frees the surface, integrated numerically."""
    depth, strength = 1e-3, 1e-12
    shear = 1.0 / (2 * (1 + NU))  # displacements do not depend on the modulus

    def pressure(s):
        return 4 * shear * strength * (s * s - 2 * depth**2) / (s * s + depth**2) ** 2.5

    def boussinesq_u3(r):
        # u_3(r) = (1 - nu)/(2 pi mu) int p(s) s int_0^2pi dphi / |x - s| ds, ring kernel 4 K(m)/(r + s).
        def integrand(s):
            return pressure(s) * s * 4 * ellipkm1(((r - s) / (r + s)) ** 2) / (r + s)  # K(m), 1 - m exact
        pieces = [quad(integrand, lo, hi, epsabs=0, epsrel=1e-12, limit=400)[0]
                  for lo, hi in [(0, r), (r, r + 50 * depth), (r + 50 * depth, np.inf)]]
        return (1 - NU) / (2 * np.pi * shear) * sum(pieces)

    def boussinesq_ur(r):
        # Only the load inside r acts: u_r = -(1 - 2 nu)/(4 pi mu r) int_0^r 2 pi s p(s) ds.
        inside = quad(lambda s: 2 * np.pi * s * pressure(s), 0, r, epsabs=0, epsrel=1e-12)[0]
        return -(1 - 2 * NU) / (4 * np.pi * shear * r) * inside

    for r in [0.3 * depth, depth, 2.5 * depth]:
        radial, normal = dilatation_surface_displacement(r, depth, strength, NU)
        distance = np.hypot(r, depth)
        image_ur = 2 * strength * r / distance**3
        assert radial == pytest.approx(image_ur + boussinesq_ur(r), rel=1e-9)
        assert normal == pytest.approx(boussinesq_u3(r), rel=1e-10)
        assert normal < 0.0  # a dilatation lifts the surface


def axis_stress_by_quadrature(pressure, contact_radius, depth, poisson):
    """Axis stress (s_rr, s_zz) of an axisymmetric pressure by Boussinesq rings (Johnson eq. 3.21)."""
    def ring(s, component):
        rho2 = s * s + depth * depth
        if component == "zz":
            return -3 * depth**3 / (2 * np.pi * rho2**2.5)
        return (-3 * depth * s * s / rho2**2.5 + (1 - 2 * poisson) * depth / rho2**1.5) / (4 * np.pi)

    return [quad(lambda t: pressure(contact_radius * np.sin(t)) * 2 * np.pi * contact_radius**2 * np.sin(t) * np.cos(t)
                 * ring(contact_radius * np.sin(t), component), 0, np.pi / 2, epsabs=0, epsrel=1e-12)[0]
            for component in ("rr", "zz")]


def test_hertz_axis_stress_and_rate_by_quadrature():
    load, radius = 5.0, 0.01
    contact_modulus = YOUNG / (1 - NU**2)
    a = (3 * load * radius / (4 * contact_modulus)) ** (1 / 3)
    p0 = 3 * load / (2 * np.pi * a * a)
    for depth in [0.2 * a, 0.48 * a, 1.5 * a]:
        stress = hertz_axis_stress(load, radius, YOUNG, NU, depth)
        radial, axial = axis_stress_by_quadrature(lambda r: p0 * np.sqrt(1 - (r / a) ** 2), a, depth, NU)
        np.testing.assert_allclose(np.diag(stress), [radial, radial, axial], rtol=1e-10)
        rate = hertz_axis_stress_rate(load, radius, YOUNG, NU, depth)
        # The flat punch of radius a per unit load, p = 1 / (2 pi a sqrt(a^2 - r^2)), in r = a sin t.
        punch = axis_stress_by_quadrature(lambda r: 1 / (2 * np.pi * a * np.sqrt(a * a - r * r)), a, depth, NU)
        np.testing.assert_allclose(np.diag(rate), [punch[0], punch[0], punch[1]], rtol=1e-9)
        step = 1e-4 * load
        difference = (hertz_axis_stress(load + step, radius, YOUNG, NU, depth)
                      - hertz_axis_stress(load - step, radius, YOUNG, NU, depth)) / (2 * step)
        np.testing.assert_allclose(np.diag(rate), np.diag(difference), rtol=1e-7)


def sneddon_approach(load, sphere_radius, young, poisson, surface_displacement):
    """Approach of a rigid sphere under ``load`` on a half-space whose surface is already displaced by
    ``surface_displacement(r)`` (u_3, into the solid), by Sneddon's (1965) integrals for the profile
    f(r) = r^2 / 2R + u(r) - u(0): delta - u(0) = a int_0^1 f'(a x) dx / sqrt(1 - x^2),
    W = 2 E* int_0^a r^2 f'(r) dr / sqrt(a^2 - r^2); x = sin t removes the square roots."""
    contact_modulus = young / (1 - poisson**2)

    def slope(r):
        step = 1e-6 * sphere_radius
        return r / sphere_radius + (surface_displacement(r + step) - surface_displacement(r - step)) / (2 * step)

    def load_at(a):
        return 2 * contact_modulus * a**2 * quad(lambda t: np.sin(t) ** 2 * slope(a * np.sin(t)), 0, np.pi / 2,
                                                 epsabs=0, epsrel=1e-13)[0]

    hertz_radius = (3 * load * sphere_radius / (4 * contact_modulus)) ** (1 / 3)
    a = brentq(lambda a: load_at(a) - load, 0.5 * hertz_radius, 2 * hertz_radius, xtol=1e-16, rtol=1e-15)
    return a * quad(lambda t: slope(a * np.sin(t)), 0, np.pi / 2, epsabs=0, epsrel=1e-13)[0] + surface_displacement(0.0)


def test_dilute_approach_change_against_sneddon_with_mindlin_cheng():
    """A small dilating sphere (eigenstrain eps* delta) under a Hertz contact: the approach change at fixed
    load, from Sneddon's solution with the Mindlin & Cheng surface displacement, is V (d sigma0/dW) : eps*;
    THEORY's V sigma0 : eps* / W is wrong for a sphere (here by a factor of about 1.4)."""
    load, sphere_radius, depth = 5.0, 0.01, 2e-4
    sphere, eigenstrain = 1e-5, 1e-3
    strength = dilatation_strength(sphere, eigenstrain, NU)

    def surface(r):
        return dilatation_surface_displacement(r, depth, strength, NU)[1]

    change = 0.5 * (sneddon_approach(load, sphere_radius, YOUNG, NU, surface)
                    - sneddon_approach(load, sphere_radius, YOUNG, NU, lambda r: -surface(r)))
    volume = 4 * np.pi * sphere**3 / 3
    rate = hertz_axis_stress_rate(load, sphere_radius, YOUNG, NU, depth)
    assert change == pytest.approx(volume * eigenstrain * np.trace(rate), rel=1e-7)
    secant = hertz_axis_stress(load, sphere_radius, YOUNG, NU, depth) / load
    assert abs(volume * eigenstrain * np.trace(secant) / change - 1) > 0.1


def test_dilute_approach_change_signs_and_limits():
    load, sphere_radius, depth, radius = 5.0, 0.01, 2e-4, 1e-5
    stress = hertz_axis_stress(load, sphere_radius, YOUNG, NU, depth)
    rate = hertz_axis_stress_rate(load, sphere_radius, YOUNG, NU, depth)
    axes = (radius,) * 3

    def change(young_inclusion):
        inclusion = stiffness(young_inclusion, NU) if young_inclusion else np.zeros((3, 3, 3, 3))
        return dilute_approach_change(stress, axes, None, YOUNG, NU, inclusion, load, stress_rate=rate)

    assert change(0.5 * YOUNG) > 0.0  # a soft inhomogeneity under compression: the indenter sinks deeper
    assert change(2.0 * YOUNG) < 0.0
    # Weak contrast: eps* = (C_M - C_I) C_M^-1 sigma0 to first order, linear in the contrast.
    contrast = 1e-6
    weak = change((1 - contrast) * YOUNG)
    # With C_I = (1 - t) C_M: eps* = t eps0 + O(t^2), eps0 = C_M^-1 sigma0.
    bulk, shear = bulk_and_shear(YOUNG, NU)
    mean = np.trace(stress) / 3
    eps0 = mean / (3 * bulk) * np.eye(3) + (stress - mean * np.eye(3)) / (2 * shear)
    volume = 4 * np.pi * radius**3 / 3
    assert weak == pytest.approx(volume * contrast * np.sum(rate * eps0), rel=1e-5)
    # A cavity: eps* = its strain = the sphere closed forms with K_I = mu_I = 0.
    beta = 2 * (4 - 5 * NU) / (15 * (1 - NU))
    volumetric = np.trace(eps0) / 3 * np.eye(3)
    cavity = volumetric * (3 * bulk + 4 * shear) / (4 * shear) + (eps0 - volumetric) / (1 - beta)
    assert change(0.0) == pytest.approx(volume * np.sum(rate * cavity), rel=1e-9)
    # Default weight sigma0 / W (flat punch).
    assert dilute_approach_change(stress, axes, None, YOUNG, NU, stiffness(0.5 * YOUNG, NU), load) == pytest.approx(
        dilute_approach_change(stress, axes, None, YOUNG, NU, stiffness(0.5 * YOUNG, NU), load,
                               stress_rate=stress / load), rel=1e-15)


def test_bad_input():
    with pytest.raises(ParameterError, match="semi_axes must all be positive"):
        eshelby_tensor((1.0, 0.0, 1.0), NU)
    with pytest.raises(ShapeError, match=r"semi_axes has shape \(2,\), expected \(3,\)"):
        eshelby_tensor((1.0, 1.0), NU)
    with pytest.raises(ParameterError, match="poisson must lie in"):
        eshelby_tensor((1.0, 1.0, 1.0), 0.7)
    with pytest.raises(ParameterError, match="poisson must be < 0.5"):
        isotropic_stiffness(YOUNG, 0.5)
    with pytest.raises(ParameterError, match="orientation must be a rotation matrix"):
        interior_solution((1.0, 1.0, 1.0), -np.eye(3), YOUNG, NU, stiffness(YOUNG, NU), np.eye(3))
    with pytest.raises(ParameterError, match="applied_strain must have the minor symmetries"):
        interior_solution((1.0, 1.0, 1.0), None, YOUNG, NU, stiffness(YOUNG, NU), np.triu(np.ones((3, 3))))
    with pytest.raises(ShapeError, match="inclusion_stiffness has shape"):
        interior_solution((1.0, 1.0, 1.0), None, YOUNG, NU, np.eye(6), np.eye(3))
    with pytest.raises(ParameterError, match="depth must be positive"):
        dilatation_surface_displacement(1.0, -1.0, 1.0, NU)
