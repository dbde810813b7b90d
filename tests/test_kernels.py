"""Influence coefficients of a loaded rectangle against Boussinesq quadrature.

The reference (point load, Johnson 1985 eqs. 3.20-3.21) is itself checked
first: its stresses are Hooke's law applied to the finite-difference strain
of its displacements, they are in equilibrium and carry the unit load.
"""
import numpy as np
import pytest
from scipy.integrate import quad

from framework.errors import ParameterError
from framework.operators.kernels import subsurface_stress, surface_displacement
from framework.reference.boussinesq import (
    point_load_displacement, point_load_stress, rectangle_displacement_by_quadrature,
    rectangle_stress_by_quadrature)

VOIGT = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]


def _tensor(voigt):
    """3x3 stress tensors from Voigt vectors, shape (..., 6) -> (..., 3, 3)."""
    out = np.empty(voigt.shape[:-1] + (3, 3))
    for k, (i, j) in enumerate(VOIGT):
        out[..., i, j] = out[..., j, i] = voigt[..., k]
    return out


def _gradient(field, points, h):
    """Fourth-order central differences: d field_i / d x_j, shape (n, ..., 3)."""
    grads = []
    for j in range(3):
        d = np.zeros(3)
        d[j] = h
        f = [field(*(points + s * d).T) for s in (-2, -1, 1, 2)]
        grads.append((f[0] - 8.0 * f[1] + 8.0 * f[2] - f[3]) / (12.0 * h))
    return np.stack(grads, axis=-1)


@pytest.fixture(scope="module")
def field_points():
    rng = np.random.default_rng(7)
    pts = rng.uniform(-2.0, 2.0, size=(40, 3))
    pts[:, 2] = np.abs(pts[:, 2]) + 0.2
    return pts


# --------------------------------------------------------------- reference ---

@pytest.mark.parametrize("nu", [0.0, 0.25, 0.45])
def test_point_load_stress_is_hooke_of_displacement(field_points, nu):
    young = 3.0
    lam = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    mu = young / (2.0 * (1.0 + nu))
    grad = _gradient(lambda x, y, z: point_load_displacement(x, y, z, young=young, poisson=nu),
                     field_points, h=1e-4)
    strain = 0.5 * (grad + np.swapaxes(grad, -1, -2))
    hooke = lam * np.trace(strain, axis1=-2, axis2=-1)[:, None, None] * np.eye(3) + 2.0 * mu * strain
    stress = _tensor(point_load_stress(*field_points.T, poisson=nu))
    scale = np.abs(stress).max(axis=(-2, -1))[:, None, None]
    assert np.max(np.abs(hooke - stress) / scale) < 1e-6


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.5])
def test_point_load_stress_is_in_equilibrium(field_points, nu):
    grad = _gradient(lambda x, y, z: _tensor(point_load_stress(x, y, z, poisson=nu)),
                     field_points, h=1e-4)
    divergence = np.einsum("nijj->ni", grad)
    scale = np.abs(point_load_stress(*field_points.T, poisson=nu)).max(axis=-1)
    scale /= np.linalg.norm(field_points, axis=-1)  # stress gradients ~ stress / distance
    assert np.max(np.abs(divergence) / scale[:, None]) < 1e-7


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.5])
def test_point_load_surface_is_traction_free(nu):
    r = np.linspace(0.1, 5.0, 30)
    s = point_load_stress(r * np.cos(1.0), r * np.sin(1.0), 0.0, poisson=nu)
    assert np.all(s[:, 2:5] == 0.0)


@pytest.mark.parametrize("depth", [0.01, 1.0, 50.0])
def test_point_load_carries_the_unit_load(depth):
    # Force on a plane x3 = depth: 2 pi int s33 r dr must balance the load.
    def ring(r):
        return 2.0 * np.pi * r * point_load_stress(r, 0.0, depth, poisson=0.3)[2]
    force = quad(ring, 0.0, depth, epsabs=1e-14)[0] + quad(ring, depth, np.inf, epsabs=1e-14)[0]
    assert force == pytest.approx(-1.0, abs=1e-10)


# ------------------------------------------------------------------ stress ---

@pytest.mark.parametrize("nu", [0.0, 0.3, 0.5])
@pytest.mark.parametrize("aspect", [1.0, 3.0])
def test_subsurface_stress_matches_quadrature(nu, aspect):
    half1, half2 = 1.0, aspect
    # Inside, under an edge, just outside it, under a corner, outside, far.
    f1 = np.array([0.0, 0.4, 1.0, 1.05, 3.0])
    f2 = np.array([0.0, -0.7, 1.0, -2.0])
    depths = np.array([0.05, 0.3, 1.0, 3.0, 10.0])
    x1, x2, x3 = (g.ravel() for g in np.meshgrid(f1 * half1, f2 * half2, depths, indexing="ij"))
    closed = subsurface_stress(x1, x2, x3, half1=half1, half2=half2, poisson=nu)
    reference = np.array([rectangle_stress_by_quadrature(a, b, c, half1=half1, half2=half2, poisson=nu)
                          for a, b, c in zip(x1, x2, x3)])
    assert np.max(np.abs(closed - reference)) <= 1e-10


def test_stress_shape_and_broadcasting():
    s = subsurface_stress(np.zeros((4, 1, 1)), np.zeros((1, 3, 1)), np.array([0.0, 1.0]),
                          half1=1.0, half2=2.0, poisson=0.3)
    assert s.shape == (4, 3, 2, 6)
    with pytest.raises(ParameterError):
        subsurface_stress(0.0, 0.0, -1.0, half1=1.0, half2=1.0, poisson=0.3)


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.5])
def test_surface_limit(nu):
    # Inside, outside, on an edge (x1 = 1), under-corner-free points.
    x1 = np.array([0.0, 0.5, 0.9, 2.0, 0.5, 1.0, 1.0, 1.5])
    x2 = np.array([0.0, 0.5, -1.9, 0.0, 2.5, 0.0, -1.0, 3.0])
    on_edge = x1 == 1.0
    inside = (np.abs(x1) < 1.0) & (np.abs(x2) < 2.0)
    s0 = subsurface_stress(x1, x2, 0.0, half1=1.0, half2=2.0, poisson=nu)
    s_tiny = subsurface_stress(x1, x2, 1e-12, half1=1.0, half2=2.0, poisson=nu)
    s_small = subsurface_stress(x1, x2, 1e-7, half1=1.0, half2=2.0, poisson=nu)
    assert np.all(np.isfinite(s0)) and np.all(np.isfinite(s_tiny))
    assert np.allclose(s0[:, 2], np.where(inside, -1.0, np.where(on_edge, -0.5, 0.0)), rtol=0, atol=1e-15)
    assert np.all(s0[:, 3:5] == 0.0)  # traction-free surface, load normal
    # Known surface result inside the load: s11 + s22 = -(1 + 2 nu) p.
    assert np.allclose((s0[:, 0] + s0[:, 1])[inside], -(1.0 + 2.0 * nu), atol=1e-14)
    # Continuity with depth away from the edges (the edge itself is a line
    # where the shear under it tends to -p/pi, not to the surface value 0).
    off = ~on_edge
    assert np.max(np.abs(s_tiny[off] - s0[off])) < 1e-10
    assert np.max(np.abs(s_small[off] - s0[off])) < 1e-5
    assert np.max(np.abs(s_tiny[on_edge][:, [0, 1, 2, 5]] - s0[on_edge][:, [0, 1, 2, 5]])) < 1e-10


def test_stress_under_edges_and_corners_is_continuous():
    # Exactly under an edge or a corner (0/0 and atan branch cases) and 1e-9 off.
    x1 = np.array([1.0, 1.0, 0.0, -1.0])
    x2 = np.array([0.0, 3.0, -3.0, -3.0])
    for z in (1e-3, 0.5, 4.0):
        exact = subsurface_stress(x1, x2, z, half1=1.0, half2=3.0, poisson=0.3)
        for d1, d2 in ((1e-9, 0.0), (-1e-9, 0.0), (0.0, 1e-9), (1e-9, -1e-9)):
            near = subsurface_stress(x1 + d1, x2 + d2, z, half1=1.0, half2=3.0, poisson=0.3)
            assert np.max(np.abs(near - exact)) < 1e-6


def test_stress_symmetries():
    rng = np.random.default_rng(3)
    x1, x2, x3 = rng.uniform(-3.0, 3.0, 50), rng.uniform(-3.0, 3.0, 50), rng.uniform(0.0, 2.0, 50)
    kw = dict(poisson=0.27)
    s = subsurface_stress(x1, x2, x3, half1=0.7, half2=1.9, **kw)
    swapped = subsurface_stress(x2, x1, x3, half1=1.9, half2=0.7, **kw)
    assert np.allclose(s[:, [0, 1, 2, 3, 4, 5]], swapped[:, [1, 0, 2, 4, 3, 5]], rtol=0, atol=1e-14)
    mirror1 = subsurface_stress(-x1, x2, x3, half1=0.7, half2=1.9, **kw)
    mirror2 = subsurface_stress(x1, -x2, x3, half1=0.7, half2=1.9, **kw)
    # Reflection x1 -> -x1 flips the sign of the components with one index 1.
    assert np.allclose(mirror1, s * [1, 1, 1, 1, -1, -1], rtol=0, atol=1e-14)
    assert np.allclose(mirror2, s * [1, 1, 1, -1, 1, -1], rtol=0, atol=1e-14)


# ------------------------------------------------------------ displacement ---

@pytest.mark.parametrize("half2", [1.0, 3.0])
def test_surface_displacement_matches_quadrature(half2):
    f1 = np.array([0.0, 0.3, 1.0, -1.0, 1.0 + 1e-9, 1.2, -4.0, 25.0])
    f2 = np.array([0.0, -0.5, 1.0, -1.0, 1e-7, -3.0, 7.0])
    x1, x2 = (g.ravel() for g in np.meshgrid(f1, f2 * half2, indexing="ij"))
    closed = surface_displacement(x1, x2, half1=1.0, half2=half2)
    reference = np.array([rectangle_displacement_by_quadrature(a, b, half1=1.0, half2=half2)
                          for a, b in zip(x1, x2)])
    assert np.all(np.isfinite(closed))
    assert np.max(np.abs(closed - reference)) <= 1e-10


def test_surface_displacement_on_edges_with_roundoff():
    # X = 0 (or a round-off 1e-17) with Y < 0 is where X ln(Y + R) breaks down.
    exact = surface_displacement(1.0, -5.0, half1=1.0, half2=2.0)
    for dx in (1e-17, -1e-17, 1e-300, 5e-324):
        assert surface_displacement(1.0 + dx, -5.0, half1=1.0, half2=2.0) == pytest.approx(exact, abs=1e-14)
    assert exact == pytest.approx(rectangle_displacement_by_quadrature(1.0, -5.0, half1=1.0, half2=2.0),
                                  abs=1e-12)


@pytest.mark.parametrize("half1, half2", [(1.0, 1.0), (1.0, 3.0)])
def test_surface_displacement_far_field(half1, half2):
    angle = np.array([0.0, 0.4, 1.3, 2.5])
    for r in (30.0, 300.0, 3000.0):
        u = surface_displacement(r * np.cos(angle), r * np.sin(angle), half1=half1, half2=half2)
        point_force = 4.0 * half1 * half2 / (np.pi * r)
        assert np.max(np.abs(u / point_force - 1.0)) < (half1**2 + half2**2) / r**2


@pytest.mark.parametrize("distance", [200.0, 350.0, 3000.0, 3e5])
def test_surface_displacement_far_away_against_quadrature(distance):
    """Far from the cell the corner sum cancels; the multipole takes over beyond 300 cells: both meet quadrature."""
    from scipy import integrate
    x1, x2 = 0.6 * distance, 0.8 * distance
    value = integrate.dblquad(lambda t, s: 1 / (np.pi * np.hypot(x1 - s, x2 - t)), -0.5, 0.5, -0.5, 0.5,
                              epsabs=0, epsrel=1e-13)[0]
    assert surface_displacement(x1, x2, half1=0.5, half2=0.5) == pytest.approx(value, rel=2e-10)
