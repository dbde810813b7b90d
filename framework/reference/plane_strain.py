"""Plane-strain stresses under line loads: Flamant, the uniform strip, the Hertz line contact.

A pressure ``p(x1)`` uniform along ``x2`` on a half-space is a plane-strain
problem in the ``(x1, x3)`` plane. Closed forms, as given in K. L. Johnson,
*Contact Mechanics*, Cambridge University Press (1985), chapter 2 (line
loading of a half-space) and section 4.2 (line contact of cylinders):

* :func:`line_load_stress`: Flamant's concentrated line load;
* :func:`strip_stress`: a uniform pressure on the strip ``|x1| <= b``;
* :func:`hertz_line_stress`: the Hertz pressure ``p0 sqrt(1 - x1^2/b^2)``,
  after E. McEwen, "Stresses in elastic cylinders in contact along a
  generatrix", Phil. Mag. 40 (1949) 454-459;
* :func:`plane_strain_stress_by_quadrature`: Flamant's solution integrated
  numerically over any pressure, which checks the two closed forms above
  without sharing their algebra.

The strip and McEwen's forms were derived here again by integrating
Flamant's stresses (angles measured from the ``x3`` axis, positive towards
``+x1``; Johnson's printed angles run the other way, so that the signs of
his ``sin 2 theta`` terms differ) and are checked against the quadrature in
``tests/test_stress_line_contact.py``.

Conventions: ``x1`` across the load, ``x3 >= 0`` depth, pressure positive in
compression, stresses positive in tension, Voigt order ``xx, yy, zz, yz, xz,
xy`` with ``x2`` along the load: ``yz = xy = 0`` and ``yy = nu (xx + zz)``.
"""
import numpy as np
from scipy.integrate import quad

from .._validation import check_poisson, check_positive, check_real
from ..errors import ParameterError


def _plane_strain(xx, zz, xz, nu):
    """Voigt stresses ``(..., 6)`` from the in-plane components (plane strain)."""
    zero = np.zeros_like(xx)
    return np.stack([xx, nu * (xx + zz), zz, zero, xz, zero], axis=-1)


def _points(x1, x3):
    x1, x3 = np.broadcast_arrays(np.asarray(x1, dtype=float), np.asarray(x3, dtype=float))
    if np.any(x3 < 0.0):
        raise ParameterError(f"x3 must be >= 0 [m] (depth into the solid), got minimum {float(x3.min())!r}")
    return x1, x3 + 0.0


def line_load_stress(x1, x3, *, poisson):
    """Stress under a unit compressive line load along ``x2`` at the origin (Flamant).

    Parameters
    ----------
    x1 : array_like
        Distance from the line of the load across it [m].
    x3 : array_like
        Depth, ``x3 > 0`` (or ``x1 != 0`` on the surface) [m].
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    ndarray, shape ``broadcast(x1, x3).shape + (6,)``
        Stress per unit load per unit length [1/m], Voigt order.

    Notes
    -----
    Johnson (1985), sec. 2.2: a purely radial stress
    ``s_rr = -(2/pi) cos(theta) / r``, theta from the ``x3`` axis, i.e.
    ``s11 = -(2/pi) x1^2 x3 / r^4``, ``s33 = -(2/pi) x3^3 / r^4``,
    ``s13 = -(2/pi) x1 x3^2 / r^4``.
    """
    nu = check_poisson(poisson)
    x, z = _points(x1, x3)
    scale = -(2.0 / np.pi) * z / (x * x + z * z) ** 2
    return _plane_strain(scale * x * x, scale * z * z, scale * x * z, nu)


def strip_stress(x1, x3, *, half_width, pressure, poisson):
    """Stress under a uniform pressure on the strip ``|x1| <= half_width``.

    Parameters
    ----------
    x1 : array_like
        Distance from the centre line of the strip [m].
    x3 : array_like
        Depth, ``x3 >= 0`` [m].
    half_width : float
        Half-width b of the strip [m].
    pressure : float
        Uniform pressure p [Pa], positive in compression.
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    ndarray, shape ``broadcast(x1, x3).shape + (6,)``
        Stress [Pa], Voigt order; on the surface ``s11 = s33 = -p`` on the
        strip, 0 outside and ``-p/2`` on its edges (the mean of both sides),
        ``s13 = 0``.

    Notes
    -----
    With ``theta_1 = atan2(x1 + b, x3)`` and ``theta_2 = atan2(x1 - b, x3)``
    (the directions of the two edges seen from the field point, measured
    from the ``x3`` axis), Flamant's stresses integrated over the strip
    (``x1 - s = x3 tan theta``) give::

        s11 = -(p/2pi) [2 (theta_1 - theta_2) - (sin 2theta_1 - sin 2theta_2)]
        s33 = -(p/2pi) [2 (theta_1 - theta_2) + (sin 2theta_1 - sin 2theta_2)]
        s13 =  (p/2pi) (cos 2theta_1 - cos 2theta_2)

    (Johnson 1985, ch. 2, whose angles run the other way.)
    """
    half_width = check_positive(half_width, name="half_width", unit="m")
    pressure = check_real(pressure, name="pressure")
    nu = check_poisson(poisson)
    x, z = _points(x1, x3)
    theta_1 = np.arctan2(x + half_width, z)
    theta_2 = np.arctan2(x - half_width, z)
    opening = 2.0 * (theta_1 - theta_2)
    sines = np.sin(2.0 * theta_1) - np.sin(2.0 * theta_2)
    scale = pressure / (2.0 * np.pi)
    # on the surface s13 = 0, the edges included (the mean of both sides, not the limit from below)
    shear = np.where(z > 0.0, scale * (np.cos(2.0 * theta_1) - np.cos(2.0 * theta_2)), 0.0)
    return _plane_strain(-scale * (opening - sines), -scale * (opening + sines), shear, nu)


def hertz_line_stress(x1, x3, *, half_width, max_pressure, poisson):
    """Stress under the Hertz pressure ``p0 sqrt(1 - x1^2/b^2)`` of a line contact (McEwen 1949).

    Parameters
    ----------
    x1 : array_like
        Distance from the centre line of the contact [m].
    x3 : array_like
        Depth, ``x3 >= 0`` [m].
    half_width : float
        Semi-width b of the contact strip [m].
    max_pressure : float
        Peak pressure p0 [Pa].
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    ndarray, shape ``broadcast(x1, x3).shape + (6,)``
        Stress [Pa], Voigt order. On the centre line
        ``s33 = -p0 / sqrt(1 + x3^2/b^2)`` and
        ``s11 = -p0 [(1 + 2 x3^2/b^2) / sqrt(1 + x3^2/b^2) - 2 x3/b]``.

    Notes
    -----
    With ``A = b^2 - x1^2 + x3^2``, ``m^2 = (sqrt(A^2 + 4 x1^2 x3^2) + A)/2``,
    ``n^2 = (sqrt(A^2 + 4 x1^2 x3^2) - A)/2``, ``m >= 0`` and ``n`` of the
    sign of ``x1`` (``m + i n = sqrt(b^2 - (x1 + i x3)^2)`` up to sign)::

        s11 = -(p0/b) [m (1 + (x3^2 + n^2)/(m^2 + n^2)) - 2 x3]
        s33 = -(p0/b) m (1 - (x3^2 + n^2)/(m^2 + n^2))
        s13 = -(p0/b) n (m^2 - x3^2)/(m^2 + n^2)

    The shear carries the sign of Flamant's ``s13`` (negative for ``x1 > 0``
    in this frame; Johnson's printed sign belongs to his axes). ``m n = x1 x3``
    gives the smaller of ``m^2``, ``n^2`` without cancellation.
    """
    half_width = check_positive(half_width, name="half_width", unit="m")
    max_pressure = check_positive(max_pressure, name="max_pressure", unit="Pa")
    nu = check_poisson(poisson)
    x, z = _points(x1, x3)
    a = half_width
    big = a * a - x * x + z * z
    root = np.hypot(big, 2.0 * x * z)
    product = (x * z) ** 2  # m^2 n^2
    with np.errstate(divide="ignore", invalid="ignore"):
        m2 = np.where(big >= 0.0, 0.5 * (root + big), product / (0.5 * (root - big)))
        n2 = np.where(big >= 0.0, product / (0.5 * (root + big)), 0.5 * (root - big))
    m2, n2 = np.nan_to_num(m2), np.nan_to_num(n2)  # 0/0 at the edges x1 = +-b on the surface
    m, n = np.sqrt(m2), np.copysign(np.sqrt(n2), x)
    total = m2 + n2  # = root
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(total > 0.0, (z * z + n2) / total, 0.0)
        shear = np.where(total > 0.0, n * (m2 - z * z) / total, 0.0)
    scale = max_pressure / a
    return _plane_strain(-scale * (m * (1.0 + ratio) - 2.0 * z), -scale * m * (1.0 - ratio), -scale * shear, nu)


def plane_strain_stress_by_quadrature(pressure, x1, x3, *, support, poisson, breaks=()):
    """Flamant's stresses integrated numerically over a pressure ``p(s)``, at one point.

    Parameters
    ----------
    pressure : callable
        ``p(s)`` [Pa] for ``s`` in ``support``, positive in compression.
    x1, x3 : float
        The field point [m], ``x3 > 0``.
    support : tuple of float
        ``(low, high)``: the pressure vanishes outside [m].
    poisson : float
        Poisson's ratio nu [-].
    breaks : sequence of float
        Points of ``support`` where the quadrature is split (kinks of ``p``) [m].

    Returns
    -------
    ndarray, shape ``(6,)``
        Stress [Pa], Voigt order, by adaptive quadrature (relative tolerance 1e-12).
    """
    nu = check_poisson(poisson)
    if not x3 > 0.0:
        raise ParameterError(f"x3 must be > 0 [m] for the quadrature, got {x3!r}")
    points = np.unique(np.clip(np.asarray([*support, *breaks, x1], dtype=float), *support))
    components = []
    for k in (0, 2, 4):
        def integrand(s, k=k):
            return pressure(s) * line_load_stress(x1 - s, x3, poisson=nu)[k]

        components.append(sum(quad(integrand, low, high, epsabs=0.0, epsrel=1e-12, limit=400)[0]
                              for low, high in zip(points[:-1], points[1:])))
    return _plane_strain(*(np.asarray(c) for c in components), nu)
