"""Independent checks of the cuboid-eigenstrain quadrature references (framework.reference.eigenstrain).

The module integrates the Green's function over the cuboid's faces.  Here the
same strains come from other routes written in the test: volume quadrature of
the second derivatives of Kelvin's solution (from Mura's potentials ``1/r``
and ``r``), the interior formula of a polyhedral inclusion (Eshelby's sphere
plus an angular integral), the exact trace of the strain of a dilatation, the
far field of a point eigenstrain, finite differences of Mindlin's solution
(free surface, Navier's equations, reciprocity, Boussinesq's limit) and
Mindlin & Cheng's (1950) centre of dilatation.
"""
import time

import numpy as np
import pytest

from framework.errors import ParameterError
from framework.reference.boussinesq import point_load_displacement
from framework.reference.eigenstrain import (kelvin_cuboid_strain, kelvin_point_force_displacement,
                                             mindlin_cuboid_strain, mindlin_cuboid_surface_displacement,
                                             mindlin_point_force_displacement)

NU = 0.3
LAMBDA = 2.0 * NU / (1.0 - 2.0 * NU)  # Lame's first constant for a unit shear modulus
EIGENSTRAIN = np.array([[1.0, 0.2, -0.1], [0.2, -0.5, 0.3], [-0.1, 0.3, 0.7]]) * 1e-3
CENTER = np.array([0.2, -0.1, 0.3])
HALF = np.array([1.0, 0.7, 0.5])


def eigenstress(eps):
    """C : eps for a unit shear modulus."""
    return 2.0 * eps + LAMBDA * np.trace(eps, axis1=-2, axis2=-1)[..., None, None] * np.eye(3)


def kelvin_second_derivatives(r):
    """d^2 G_ij / dx_l dx_k of Kelvin's solution (mu = 1) at offsets ``r`` (n, 3): shape (n, i, j, l, k).

    From G_ij = [delta_ij / r - (d_ij r) / (4 (1-nu))] / (4 pi) (Mura 1987, chapter 1), with
    d_lk (1/r) = (3 n_l n_k - delta_lk) / r^3 and
    d_ijlk r = [-(dd + dd + dd) + 3 (6 terms delta n n) - 15 n n n n] / r^3.
    """
    rr = np.linalg.norm(r, axis=1)
    n = r / rr[:, None]
    d = np.eye(3)
    inv = (3.0 * np.einsum("pl,pk->plk", n, n) - d) / rr[:, None, None] ** 3
    dddd = (np.einsum("ij,lk->ijlk", d, d) + np.einsum("il,jk->ijlk", d, d) + np.einsum("ik,jl->ijlk", d, d))
    ddnn = sum(np.einsum(spec, d, n, n) for spec in
               ("ij,pl,pk->pijlk", "il,pj,pk->pijlk", "ik,pj,pl->pijlk",
                "jl,pi,pk->pijlk", "jk,pi,pl->pijlk", "lk,pi,pj->pijlk"))
    nnnn = np.einsum("pi,pj,pl,pk->pijlk", n, n, n, n)
    fourth = (-dddd + 3.0 * ddnn - 15.0 * nnnn) / rr[:, None, None, None, None] ** 3
    return (np.einsum("ij,plk->pijlk", d, inv) - fourth / (4.0 * (1.0 - NU))) / (4.0 * np.pi)


def strain_of_gradient(gradient):
    return 0.5 * (gradient + np.swapaxes(gradient, -1, -2))


def gauss_line(low, high, pieces, order=10):
    """Composite Gauss-Legendre nodes and weights on [low, high], ``pieces`` equal cells."""
    x, w = np.polynomial.legendre.leggauss(order)
    edges = np.linspace(low, high, pieces + 1)
    mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * (edges[1:] - edges[:-1])
    return (mid[:, None] + half[:, None] * x).ravel(), (half[:, None] * w).ravel()


def gauss_box(low, high, pieces, order=10):
    """Tensor Gauss-Legendre nodes (N, 3) and weights (N,) on the box [low, high]."""
    axes = [gauss_line(a, b, pieces, order) for a, b in zip(low, high)]
    nodes = np.stack(np.meshgrid(*(a[0] for a in axes), indexing="ij"), axis=-1).reshape(-1, 3)
    weights = np.einsum("i,j,k->ijk", *(a[1] for a in axes)).ravel()
    return nodes, weights


def gauss_face(low, high, axis, plane, pieces, order=10):
    """Tensor Gauss-Legendre nodes (N, 3) and area weights (N,) on the face x_axis = plane of the box [low, high]."""
    others = [a for a in range(3) if a != axis]
    (a, wa), (b, wb) = (gauss_line(low[o], high[o], pieces, order) for o in others)
    nodes = np.empty((a.size, b.size, 3))
    nodes[..., axis] = plane
    nodes[..., others[0]] = a[:, None]
    nodes[..., others[1]] = b[None, :]
    return nodes.reshape(-1, 3), np.outer(wa, wb).ravel()


def derivative(function, x, axis, step):
    """Fourth-order central difference of ``function`` at ``x`` along ``axis``."""
    e = np.zeros(3)
    e[axis] = step
    return (function(x - 2 * e) - 8 * function(x - e) + 8 * function(x + e) - function(x + 2 * e)) / (12 * step)


# --- Kelvin ---------------------------------------------------------------------------------------------------

def test_kelvin_gauss_rule_converges_to_1e_10():
    """Doubling the rule's order changes the strain by < 1e-10 of |eps*| half a half-size from the faces."""
    points = CENTER + np.array([[0.0, 0.0, 0.0], [0.4, 0.3, -0.25], [-1.5, 0.2, 0.1], [0.3, 0.35, 0.75],
                                [2.0, -1.5, 1.0], [0.95, 0.0, 0.0]])
    args = dict(center=CENTER, half_sizes=HALF, eigenstrain=EIGENSTRAIN, poisson=NU)
    coarse = kelvin_cuboid_strain(points, order=10, **args)
    fine = kelvin_cuboid_strain(points, order=20, **args)
    assert np.abs(coarse - fine).max() < 1e-10 * np.abs(EIGENSTRAIN).max()


def test_kelvin_matches_volume_quadrature_outside():
    """Outside the cuboid: u_i,k = -sigma*_jl int_V G_ij,lk dV' by plain volume Gauss quadrature."""
    points = CENTER + np.array([[2.0, 0.3, -0.2], [0.1, -1.6, 0.4], [0.5, 0.5, 1.5], [-3.0, 2.0, 1.0]])
    nodes, weights = gauss_box(CENTER - HALF, CENTER + HALF, pieces=3, order=8)
    sigma = eigenstress(EIGENSTRAIN)
    expected = np.array([strain_of_gradient(-np.einsum("pijlk,jl,p->ik", kelvin_second_derivatives(x - nodes),
                                                       sigma, weights)) for x in points])
    strain = kelvin_cuboid_strain(points, center=CENTER, half_sizes=HALF, eigenstrain=EIGENSTRAIN, poisson=NU)
    assert np.abs(strain - expected).max() < 1e-10 * np.abs(expected).max()


def test_kelvin_interior_matches_polyhedral_inclusion_formula():
    """Inside: eps(x) = S_sphere : eps* - sym sigma*_jl int_{S^2} G_ij,lk(w) ln rho(w) dw (ball removed around x).

    Eigenstrain in a ball around x gives Eshelby's uniform S : eps*; the rest of the
    cuboid is integrated in spherical coordinates about x, the radial integral of
    the degree -3 kernel being ln(rho(w)/a) (the a-term integrates to 0 over the
    sphere).  The angular integral is taken over the faces, dw = |n.(y-x)| dS/|y-x|^3.
    """
    d = np.eye(3)
    eshelby = ((5 * NU - 1) * np.einsum("ij,kl->ijkl", d, d)
               + (4 - 5 * NU) * (np.einsum("ik,jl->ijkl", d, d) + np.einsum("il,jk->ijkl", d, d))) / (15 * (1 - NU))
    sigma = eigenstress(EIGENSTRAIN)
    low, high = CENTER - HALF, CENTER + HALF
    points = CENTER + np.array([[0.0, 0.0, 0.0], [0.5, -0.3, 0.2], [-0.4, 0.25, -0.2]])
    for x in points:
        total = np.zeros((3, 3))
        for axis in range(3):
            for plane in (low[axis], high[axis]):
                nodes, weights = gauss_face(low, high, axis, plane, pieces=8)
                offset = nodes - x
                rho = np.linalg.norm(offset, axis=1)
                solid_angle = np.abs(offset[:, axis]) / rho**3 * weights
                kernel = kelvin_second_derivatives(offset / rho[:, None])
                total += np.einsum("pijlk,jl,p->ik", kernel, sigma, solid_angle * np.log(rho))
        expected = np.einsum("ijkl,kl->ij", eshelby, EIGENSTRAIN) - strain_of_gradient(total)
        strain = kelvin_cuboid_strain(x[None], center=CENTER, half_sizes=HALF, eigenstrain=EIGENSTRAIN, poisson=NU)
        assert np.abs(strain[0] - expected).max() < 1e-10 * np.abs(EIGENSTRAIN).max()


def test_kelvin_dilatation_trace_is_exact():
    """A dilatation eps* I gives u = grad of a Newtonian potential: tr eps = (1+nu)/(1-nu) eps* inside, 0 outside.

    At the centre of a cube, cubic symmetry makes the strain isotropic: (1+nu)/(3(1-nu)) eps* I.
    """
    points = CENTER + np.array([[0.0, 0.0, 0.0], [0.5, -0.3, 0.25], [-0.9, 0.6, 0.4], [1.5, 0.2, 0.1],
                                [0.3, 0.35, 0.75], [3.0, -2.0, 1.0]])
    inside = np.all(np.abs(points - CENTER) < HALF, axis=1)
    strain = kelvin_cuboid_strain(points, center=CENTER, half_sizes=HALF, eigenstrain=1e-3 * np.eye(3), poisson=NU)
    trace = np.trace(strain, axis1=1, axis2=2)
    assert np.abs(trace - np.where(inside, (1 + NU) / (1 - NU) * 1e-3, 0.0)).max() < 1e-12
    cube = kelvin_cuboid_strain(CENTER[None], center=CENTER, half_sizes=[0.6] * 3, eigenstrain=1e-3 * np.eye(3),
                                poisson=NU)
    assert np.abs(cube[0] - (1 + NU) / (3 * (1 - NU)) * 1e-3 * np.eye(3)).max() < 1e-14


def test_kelvin_far_field_is_a_point_eigenstrain():
    """Far away the cuboid acts as a point eigenstrain of volume V: u_i,k = -V sigma*_jl G_ij,lk.

    The cuboid's first moments vanish, so the relative error falls like (h/R)^2.
    """
    direction = np.array([0.48, -0.6, 0.64])
    sigma = eigenstress(EIGENSTRAIN)
    volume = 8.0 * np.prod(HALF)
    errors = []
    for distance in (20.0, 40.0, 80.0):
        offset = distance * direction
        point = -volume * np.einsum("pijlk,jl->pik", kelvin_second_derivatives(offset[None]), sigma)
        strain = kelvin_cuboid_strain((CENTER + offset)[None], center=CENTER, half_sizes=HALF,
                                      eigenstrain=EIGENSTRAIN, poisson=NU)
        errors.append(np.abs(strain - strain_of_gradient(point)).max() / np.abs(strain).max())
    assert errors[-1] < 1e-3
    assert np.allclose(np.log2(np.array(errors[:-1]) / errors[1:]), 2.0, atol=0.05)


# --- Mindlin's point force ----------------------------------------------------------------------------------

def mindlin_stress(x, source, step=1e-3):
    """Stress (3 force directions j, 3, 3) of Mindlin's solution (mu = 1) at ``x`` by finite differences."""
    def field(y):
        return mindlin_point_force_displacement(y[None], source, shear_modulus=1.0, poisson=NU)[0]
    gradient = np.stack([derivative(field, x, k, step) for k in range(3)], axis=-1)  # (i, j, k)
    strain = 0.5 * (gradient + np.transpose(gradient, (2, 1, 0)))
    strain = np.transpose(strain, (1, 0, 2))  # (j, i, k)
    return 2.0 * strain + LAMBDA * np.trace(strain, axis1=1, axis2=2)[:, None, None] * np.eye(3)


def test_mindlin_surface_is_traction_free():
    """sigma_i3 = 0 at x3 = 0, extrapolated (cubic error) from 3 depths where the stencil fits in x3 >= 0."""
    source = np.array([0.3, -0.2, 1.3])
    scale = np.abs(mindlin_stress(np.array([0.5, 0.1, 0.8]), source)).max()
    for x in ([0.0, 0.0, 0.0], [1.2, -0.7, 0.0], [-2.0, 1.5, 0.0]):
        t1, t2, t3 = (mindlin_stress(np.array(x) + [0.0, 0.0, depth], source, step=2.5e-4)[:, :, 2]
                      for depth in (1e-3, 2e-3, 3e-3))
        assert np.abs(t1).max() > 1e-6 * scale  # the stencil depth is not trivially traction free
        assert np.abs(3 * t1 - 3 * t2 + t3).max() < 1e-7 * scale


def test_mindlin_satisfies_navier_equations():
    """div sigma = 0 away from the force, by finite differences of the stress."""
    source = np.array([0.3, -0.2, 1.3])
    for x in ([0.5, 0.1, 0.8], [-1.0, 0.7, 0.3], [0.3, -0.2, 2.5]):
        x = np.array(x)
        divergence = sum(derivative(lambda y: mindlin_stress(y, source)[:, :, k], x, k, 3e-3) for k in range(3))
        assert np.abs(divergence).max() < 1e-7 * np.abs(mindlin_stress(x, source)).max()


def test_mindlin_reciprocity_kelvin_limit_and_boussinesq():
    """G_ij(x, x') = G_ji(x', x); deep down Mindlin -> Kelvin like 1/depth; a surface force is Boussinesq's."""
    x = np.array([[0.5, 0.1, 0.8], [-1.0, 0.7, 0.3], [2.0, 1.0, 3.0]])
    source = np.array([0.3, -0.2, 1.3])
    forward = mindlin_point_force_displacement(x, source, shear_modulus=1.0, poisson=NU)
    backward = np.stack([mindlin_point_force_displacement(source[None], y, shear_modulus=1.0, poisson=NU)[0]
                         for y in x])
    assert np.abs(forward - np.swapaxes(backward, 1, 2)).max() < 1e-14 * np.abs(forward).max()
    gaps = []
    for depth in (100.0, 200.0):
        deep = np.array([0.0, 0.0, depth])
        points = deep + [[0.5, 0.3, -0.2]]
        difference = (mindlin_point_force_displacement(points, deep, shear_modulus=1.0, poisson=NU)
                      - kelvin_point_force_displacement(points, deep, shear_modulus=1.0, poisson=NU))
        gaps.append(np.abs(difference).max())
    assert gaps[0] < 1e-2 * np.abs(kelvin_point_force_displacement(points, deep, shear_modulus=1.0,
                                                                    poisson=NU)).max()
    assert gaps[0] / gaps[1] == pytest.approx(2.0, rel=1e-2)
    young = 2.0 * (1.0 + NU)
    points = np.array([[0.5, 0.1, 0.0], [-1.0, 0.7, 0.3], [2.0, 1.0, 3.0]])
    surface = mindlin_point_force_displacement(points, np.zeros(3), shear_modulus=1.0, poisson=NU)[:, :, 2]
    expected = point_load_displacement(points[:, 0], points[:, 1], points[:, 2], young=young, poisson=NU)
    assert np.abs(surface - expected).max() < 1e-14 * np.abs(expected).max()


# --- Mindlin's cuboid -----------------------------------------------------------------------------------------

BURIED = np.array([0.2, -0.1, 0.8])  # top face at depth 0.3


def test_mindlin_gauss_rule_converges_to_1e_10():
    points = np.array([[0.0, 0.0, 0.0], [0.3, 0.2, 0.0], [1.5, 0.2, 0.0], [0.4, 0.1, 0.6], [0.2, 0.1, 1.55]])
    args = dict(center=BURIED, half_sizes=HALF, eigenstrain=EIGENSTRAIN, poisson=NU)
    coarse = mindlin_cuboid_strain(points, order=10, **args)
    fine = mindlin_cuboid_strain(points, order=20, **args)
    assert np.abs(coarse - fine).max() < 1e-10 * np.abs(EIGENSTRAIN).max()


def test_mindlin_cuboid_surface_is_traction_free():
    points = np.array([[0.0, 0.0, 0.0], [0.3, 0.2, 0.0], [1.5, 0.2, 0.0], [-2.0, 3.0, 0.0]])
    strain = mindlin_cuboid_strain(points, center=BURIED, half_sizes=HALF, eigenstrain=EIGENSTRAIN, poisson=NU)
    stress = eigenstress(strain)
    assert np.abs(stress[:, :, 2]).max() < 1e-12 * np.abs(stress).max()
    assert np.abs(stress).max() > 1e-2 * np.abs(EIGENSTRAIN).max()


def test_mindlin_cuboid_tends_to_kelvin_deep_down():
    """The surface's effect at the cuboid falls like depth^-3 (the image of a force dipole)."""
    gaps = []
    for depth in (10.0, 20.0, 40.0):
        center = np.array([0.0, 0.0, depth])
        points = center + np.array([[0.1, 0.2, -0.3], [1.0, 0.5, 0.7]])
        args = dict(center=center, half_sizes=HALF, eigenstrain=EIGENSTRAIN, poisson=NU)
        gaps.append(np.abs(mindlin_cuboid_strain(points, **args) - kelvin_cuboid_strain(points, **args)).max())
    assert gaps[-1] < 1e-5 * np.abs(EIGENSTRAIN).max()
    assert np.allclose(np.log2(np.array(gaps[:-1]) / gaps[1:]), 3.0, atol=0.05)


def test_mindlin_surface_displacement_is_mindlin_cheng_centre_of_dilatation():
    """A small cube (V = 8 h^3) of dilatation eps* at depth c: u_r = 4(1-nu) C r/R^3, u_3 = -4(1-nu) C c/R^3,
    C = (1+nu) eps* V / (4 pi (1-nu)) (Mindlin & Cheng 1950).  Cubic symmetry leaves an error ~ (h/c)^4."""
    depth, eps = 2.0, 1e-3
    xy = np.array([[0.0, 0.0], [1.0, 0.5], [3.0, -1.0]])
    radius = np.linalg.norm(xy, axis=1)
    distance = np.hypot(radius, depth)
    errors = []
    for half in (0.2, 0.1):
        strength = (1 + NU) * eps * 8 * half**3 / (4 * np.pi * (1 - NU))
        expected = 4 * (1 - NU) * strength / distance[:, None] ** 3 * np.column_stack([xy, -depth + 0 * radius])
        u = mindlin_cuboid_surface_displacement(xy, center=[0.0, 0.0, depth], half_sizes=[half] * 3,
                                                eigenstrain=eps * np.eye(3), poisson=NU)
        errors.append(np.abs(u - expected).max() / np.abs(expected).max())
    assert errors[-1] < 1e-5
    assert np.log2(errors[0] / errors[1]) == pytest.approx(4.0, abs=0.1)


def test_mindlin_surface_displacement_matches_surface_strain():
    """d u_1 / d x_1 and d u_2 / d x_2 of the surface displacement (finite differences) are the surface strains."""
    args = dict(center=BURIED, half_sizes=HALF, eigenstrain=EIGENSTRAIN, poisson=NU)
    for x in ([0.4, 0.1], [1.5, -0.6]):
        x = np.array(x + [0.0])
        strain = mindlin_cuboid_strain(x[None], **args)[0]
        def surface(y):
            return mindlin_cuboid_surface_displacement(y[None, :2], **args)[0]
        gradient = np.column_stack([derivative(surface, x, k, 1e-3) for k in range(2)])[:2]  # d u_i / d x_k, i, k < 2
        assert np.abs(strain_of_gradient(gradient) - strain[:2, :2]).max() < 1e-9 * np.abs(EIGENSTRAIN).max()


def test_mindlin_surface_displacement_above_a_cuboid_touching_the_surface():
    """On the top face of a cuboid at the surface the kernel's 1/r singularity is integrable: the rule converges."""
    args = dict(center=[0.2, -0.1, 0.5], half_sizes=HALF, eigenstrain=EIGENSTRAIN, poisson=NU)
    xy = np.array([[0.0, 0.0], [0.2, -0.1], [1.2, 0.6], [3.0, 0.0]])
    coarse = mindlin_cuboid_surface_displacement(xy, order=8, **args)
    fine = mindlin_cuboid_surface_displacement(xy, order=16, **args)
    assert np.abs(coarse - fine).max() < 1e-8 * np.abs(fine).max()


@pytest.mark.parametrize("call, match", [
    (dict(poisson=0.5), r"poisson must lie in \(-1, 0.5\) .* got 0.5"),
    (dict(eigenstrain=[[0, 1e-3, 0], [0, 0, 0], [0, 0, 0]]), "eigenstrain must be a symmetric"),
    (dict(half_sizes=[1.0, 0.0, 1.0]), r"half_sizes must be positive \[m\], got \[1.0, 0.0, 1.0\]"),
    (dict(center=[0.0, 0.0, 0.4]), r"center\[2\] - half_sizes\[2\] must be >= 0 \[m\], got -0.1$"),
    (dict(points=[[0.0, 0.0, -1.0]]), "points must lie in the half-space x3 >= 0, got x3 = -1$"),
    (dict(points=[[1.2, 0.0, 0.5]]), r"points must not lie on them, got \[1.2, 0.0, 0.5\]"),
    (dict(points=[[0.0, 0.0]]), r"points must have shape \(n, 3\), got \(1, 2\)"),
    (dict(order=1), "order must be an integer >= 2, got 1"),
])
def test_cuboid_strain_rejects_bad_input(call, match):
    args = dict(points=[[0.0, 0.0, 2.0]], center=BURIED, half_sizes=HALF, eigenstrain=EIGENSTRAIN, poisson=NU)
    args.update(call)
    with pytest.raises(ParameterError, match=match):
        mindlin_cuboid_strain(args.pop("points"), **args)


def test_surface_displacement_rejects_points_with_a_depth():
    with pytest.raises(ParameterError, match=r"points must have shape \(n, 2\), got \(1, 3\)"):
        mindlin_cuboid_surface_displacement([[0.0, 0.0, 0.0]], center=BURIED, half_sizes=HALF,
                                            eigenstrain=EIGENSTRAIN, poisson=NU)


@pytest.mark.slow
def test_accuracy_and_cost_study():
    """Error of the default rule (order 10) against order 24 over 50 points x 3 cuboids, and its cost.

    Points lie at least half a half-size from every face; measured: about 1e-11 of |eps*|, a few ms per point.
    """
    rng = np.random.default_rng(1)
    worst, elapsed, count = 0.0, 0.0, 0
    for center, half in (([0.0, 0.0, 1.0], [1.0, 1.0, 1.0]), ([0.3, 0.1, 0.25], [0.5, 2.0, 0.25]),
                         ([0.0, 0.0, 3.0], [0.2, 0.3, 1.0])):
        center, half = np.array(center), np.array(half)
        points = center + rng.uniform(-3, 3, (200, 3)) * half
        points[:, 2] = np.abs(points[:, 2])
        gap = np.abs(np.abs(points - center) - half) / half
        points = points[np.all(gap >= 0.5, axis=1)][:50]
        for function in (kelvin_cuboid_strain, mindlin_cuboid_strain):
            args = dict(center=center, half_sizes=half, eigenstrain=EIGENSTRAIN, poisson=NU)
            start = time.perf_counter()
            strain = function(points, **args)
            elapsed += time.perf_counter() - start
            count += len(points)
            worst = max(worst, np.abs(strain - function(points, order=24, **args)).max() / np.abs(EIGENSTRAIN).max())
    print(f"worst relative error {worst:.2e}, {1e3 * elapsed / count:.1f} ms per point")
    assert worst < 1e-9
