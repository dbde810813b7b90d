"""Boussinesq point load on an elastic half-space, and quadrature references.

Displacements and stresses caused by a concentrated normal force on the
surface of a linear elastic, isotropic half-space (J. Boussinesq,
*Application des potentiels a l'etude de l'equilibre et du mouvement des
solides elastiques*, Gauthier-Villars, Paris, 1885), in the form of
K. L. Johnson, *Contact Mechanics*, Cambridge University Press (1985),
section 3.2, eqs. 3.20-3.21.  Integrating them numerically over a rectangle
gives a reference for the closed-form influence coefficients of
:mod:`framework.operators.kernels` that shares no algebra with them.

Conventions: ``x1``, ``x2`` in the surface plane, ``x3 >= 0`` depth into the
solid, the unit force acts at the origin in ``+x3`` (pressing on the
solid), displacement ``u3`` positive into the solid, stresses positive in
tension, Voigt order ``xx, yy, zz, yz, xz, xy``.
"""
import numpy as np
from scipy.integrate import cubature, quad

from .._validation import check_poisson, check_positive, check_real

#: Tolerances of the quadratures below, on results of order one.
_ATOL = 1e-14
_RTOL = 1e-13


def point_load_displacement(x1, x2, x3, *, young, poisson):
    """Displacement caused by a unit normal point force (Boussinesq).

    Parameters
    ----------
    x1, x2 : array_like
        Surface coordinates of the field points relative to the force [m].
    x3 : array_like
        Depth of the field points, ``x3 >= 0`` [m]; broadcast with ``x1``,
        ``x2``.  The origin itself is singular.
    young : float
        Young's modulus E [Pa].
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    ndarray, shape ``broadcast(x1, x2, x3).shape + (3,)``
        Displacement ``(u1, u2, u3)`` per newton of force [m/N]; ``u3`` is
        positive into the solid.

    Notes
    -----
    Johnson (1985) eq. 3.20 with ``P = 1``, rho the distance to the force
    and r its projection on the surface::

        u_r = (1+nu)/(2 pi E) [x3 r / rho^3 - (1-2nu) r / (rho (rho+x3))]
        u_3 = (1+nu)/(2 pi E) [2 (1-nu) / rho + x3^2 / rho^3]

    The radial term is written without ``1/r`` so that the axis is regular.
    """
    young = check_positive(young, name="young", unit="Pa")
    nu = check_poisson(poisson)
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x1, x2, x3)))
    rho = np.sqrt(x * x + y * y + z * z)
    c = (1.0 + nu) / (2.0 * np.pi * young)
    radial = c * (z / rho**3 - (1.0 - 2.0 * nu) / (rho * (rho + z)))  # u_r / r
    u3 = c * (2.0 * (1.0 - nu) / rho + z * z / rho**3)
    return np.stack([radial * x, radial * y, u3], axis=-1)


def point_load_stress(x1, x2, x3, *, poisson):
    """Stress caused by a unit normal point force (Boussinesq).

    Parameters
    ----------
    x1, x2 : array_like
        Surface coordinates of the field points relative to the force [m].
    x3 : array_like
        Depth of the field points, ``x3 > 0`` (or ``r > 0`` on the surface)
        [m]; broadcast with ``x1``, ``x2``.
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    ndarray, shape ``broadcast(x1, x2, x3).shape + (6,)``
        Stress per newton of force [Pa/N = 1/m^2], tension positive, Voigt
        order ``xx, yy, zz, yz, xz, xy``.

    Notes
    -----
    Johnson (1985) eq. 3.21 with ``P = 1`` gives, in cylindrical coordinates
    (``rho^2 = r^2 + x3^2``, and ``(1 - x3/rho)/r^2 = 1/(rho (rho+x3))``)::

        s_rr = [(1-2nu) / (rho (rho+x3)) - 3 x3 r^2 / rho^5] / (2 pi)
        s_tt = -(1-2nu) [1 / (rho (rho+x3)) - x3 / rho^3] / (2 pi)
        s_33 = -3 x3^3 / (2 pi rho^5)
        s_r3 = -3 r x3^2 / (2 pi rho^5)

    Rotated to Cartesian axes (``s_xx = s_rr cos^2 + s_tt sin^2``,
    ``s_xy = (s_rr - s_tt) sin cos``) and simplified so that no ``1/r``
    remains, which keeps the axis ``r = 0`` regular::

        s_xx = [(1-2nu) (x^2 - y^2 + x3^2 + x3 y^2/(rho+x3)) / (rho^3 (rho+x3))
                - 3 x3 x^2 / rho^5] / (2 pi)
        s_xy = [(1-2nu) x y (2 rho + x3) / (rho^3 (rho+x3)^2)
                - 3 x3 x y / rho^5] / (2 pi)
    """
    nu = check_poisson(poisson)
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x1, x2, x3)))
    rho = np.sqrt(x * x + y * y + z * z)
    rz = rho + z
    k = 1.0 / (2.0 * np.pi)
    a = (1.0 - 2.0 * nu) / (rho**3 * rz)
    b = 3.0 * z / rho**5
    sxx = k * (a * (x * x - y * y + z * z + z * y * y / rz) - b * x * x)
    syy = k * (a * (y * y - x * x + z * z + z * x * x / rz) - b * y * y)
    szz = -k * b * z * z
    syz = -k * b * z * y
    sxz = -k * b * z * x
    sxy = k * x * y * (a * (2.0 * rho + z) / rz - b)
    return np.stack([sxx, syy, szz, syz, sxz, sxy], axis=-1)


def _breaks(x, half):
    """Integration breaks on [-half, half]: the ends and the clipped point.

    Splitting at the point of the interval nearest to the field point puts
    the peak of a near-singular integrand at a corner of the sub-domains,
    where the adaptive rule resolves it well.
    """
    c = min(max(x, -half), half)
    return [-half] + ([c] if -half < c < half else []) + [half]


def rectangle_stress_by_quadrature(x1, x2, x3, *, half1, half2, poisson):
    """Stress under a uniformly loaded rectangle by adaptive 2-D quadrature.

    Integrates :func:`point_load_stress` over the loaded rectangle
    ``|xi| <= half1``, ``|eta| <= half2`` with unit compressive pressure,
    with :func:`scipy.integrate.cubature` (Gauss-Kronrod 21 x 21 rule,
    absolute tolerance about 1e-14).

    Parameters
    ----------
    x1, x2 : float
        Surface coordinates of the field point [m].
    x3 : float
        Depth of the field point, ``x3 > 0`` [m].
    half1, half2 : float
        Half-widths of the rectangle along x1 and x2 [m].
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    ndarray, shape (6,)
        Stress per unit pressure [Pa/Pa = -], tension positive, Voigt order
        ``xx, yy, zz, yz, xz, xy``.
    """
    x1, x2 = check_real(x1, name="x1"), check_real(x2, name="x2")
    x3 = check_positive(x3, name="x3", unit="m")
    half1 = check_positive(half1, name="half1", unit="m")
    half2 = check_positive(half2, name="half2", unit="m")
    nu = check_poisson(poisson)

    def integrand(q):  # q[:, 0] = xi, q[:, 1] = eta: load point positions
        return point_load_stress(x1 - q[:, 0], x2 - q[:, 1], x3, poisson=nu)

    total = np.zeros(6)
    b1, b2 = _breaks(x1, half1), _breaks(x2, half2)
    for lo1, hi1 in zip(b1[:-1], b1[1:]):
        for lo2, hi2 in zip(b2[:-1], b2[1:]):
            res = cubature(integrand, [lo1, lo2], [hi1, hi2], rule="gk21",
                           atol=_ATOL, rtol=_RTOL, max_subdivisions=100_000)
            if res.status != "converged":
                raise RuntimeError(f"cubature did not converge at ({x1}, {x2}, {x3}): error {res.error}")
            total += res.estimate
    return total


def _corner_integral(u, v):
    """Integral of 1/(pi r) over the rectangle with corners (0, 0) and (u, v).

    Polar coordinates centred at the singular corner: the Jacobian ``r``
    cancels ``1/r``, the radial integral is the distance to the far edge,
    ``u/cos(t)`` or ``v/sin(t)``, and a smooth angular integral remains.
    The result is odd in ``u`` and in ``v`` (signed area element).
    """
    au, av = abs(u), abs(v)
    if au == 0.0 or av == 0.0:
        return 0.0
    tc = np.arctan2(av, au)  # angle of the far corner
    kw = dict(epsabs=_ATOL, epsrel=_RTOL, limit=200)
    near = quad(lambda t: au / np.cos(t), 0.0, tc, **kw)[0]
    far = quad(lambda t: av / np.sin(t), tc, 0.5 * np.pi, **kw)[0]
    return np.sign(u) * np.sign(v) * (near + far) / np.pi


def rectangle_displacement_by_quadrature(x1, x2, *, half1, half2):
    """Surface displacement under a uniformly loaded rectangle by quadrature.

    Unit compressive pressure on ``|xi| <= half1``, ``|eta| <= half2`` and
    unit compliance ``(1 - nu^2)/E = 1``, so that a point force gives
    ``u3 = 1/(pi r)`` (Johnson 1985, eq. 3.22).

    Parameters
    ----------
    x1, x2 : float
        Surface coordinates of the field point [m].
    half1, half2 : float
        Half-widths of the rectangle along x1 and x2 [m].

    Returns
    -------
    float
        Normal displacement ``u3`` into the solid [m per (Pa m^2/N)], i.e.
        multiply by ``p (1 - nu^2)/E`` for a physical solid.

    Notes
    -----
    With ``X = x1 - xi`` and ``Y = x2 - eta`` the loaded rectangle becomes
    ``x1-half1 <= X <= x1+half1``, ``x2-half2 <= Y <= x2+half2``, and its
    integral is the inclusion-exclusion sum of four rectangles that have the
    singular point ``X = Y = 0`` as a corner, each integrated in polar
    coordinates by :func:`scipy.integrate.quad` (tolerance about 1e-14).
    """
    x1, x2 = check_real(x1, name="x1"), check_real(x2, name="x2")
    half1 = check_positive(half1, name="half1", unit="m")
    half2 = check_positive(half2, name="half2", unit="m")
    return (_corner_integral(x1 + half1, x2 + half2) - _corner_integral(x1 - half1, x2 + half2)
            - _corner_integral(x1 + half1, x2 - half2) + _corner_integral(x1 - half1, x2 - half2))
