"""Influence coefficients of a uniformly loaded rectangle on a half-space.

Closed forms of A. E. H. Love, "The stress produced in a semi-infinite
solid by pressure on part of the boundary", Phil. Trans. R. Soc. A 228
(1929) 377-420, as integrated from the Boussinesq point load in
K. L. Johnson, *Contact Mechanics*, Cambridge University Press (1985),
section 3.2.  They are validated against adaptive quadrature of the point
load (:mod:`framework.reference.boussinesq`) in ``tests/test_kernels.py``
to better than 1e-12 of the pressure.

Finding on the candidate formulas of THEORY.md: all six stress components
and the surface displacement are correct as written, signs of the shear
components included (``s13 = -(p/2pi) Sum x3^2/(R (Y+R))`` equals
``+(p/2pi) Sum x3^2 Y/(R (X^2+x3^2))``, negative for ``x1 > 0`` like the
point load's ``s_r3``).  Three terms are, however, numerically unsafe and are
evaluated here in equivalent forms:

* ``1/(R (Y+R)) = 1/(X^2+x3^2) - Y/(R (X^2+x3^2))``: ``Y + R`` cancels for
  ``Y < 0`` and is ``0/0`` at ``X = x3 = 0``; the first part depends on
  ``X`` only and drops out of the corner sum, so ``-x3 X/(R (Y+R))`` becomes
  ``x3 X Y/(R (X^2+x3^2))`` (same for the ``X + R`` terms);
* ``R - x3 = (X^2+Y^2)/(R+x3)`` (cancellation at depth);
* ``X ln(Y+R)`` in the displacement becomes ``X asinh(Y/|X|)``, which differs
  by ``X ln|X|`` (dropping out of the corner sum) and tends to 0 with ``X``
  instead of giving ``0 * ln 0`` or losing all digits when ``|X| << -Y``.

Arctangents are taken with ``arctan2`` on non-negative denominators, which
gives the correct limits at ``x3 = 0`` (``+-pi/2``) and the mean value on the
edges of the loaded area; ``0/0`` terms are set to their limit 0.

Two kernels follow from Love's: :func:`strip_stress`, the plane-strain strip
(the rectangle's limit for an infinite length along ``x2``), and
:func:`periodic_subsurface_stress`, the rectangle summed over its periodic
images along ``x2`` (grids periodic along one axis: line contacts).

Conventions: ``x1``, ``x2`` in the surface plane, ``x3 >= 0`` depth into the
solid; uniform pressure ``p = 1`` pressing into the solid (``+x3``) on
``|xi| <= half1``, ``|eta| <= half2``; tension positive; ``u3`` positive
into the solid; Voigt order ``xx, yy, zz, yz, xz, xy``.
"""
import numpy as np
from scipy.special import erf

from .._validation import check_finite_array, check_non_negative, check_poisson, check_positive, check_positive_int
from ..errors import ParameterError


def _ratio(num, den):
    """``num / den``, and 0 where ``den == 0`` (num vanishes there too)."""
    safe = den > 0.0
    return np.where(safe, num / np.where(safe, den, 1.0), 0.0)


def _corner_sum(term, x1, x2, half1, half2):
    """``F(x+a, y+b) - F(x+a, y-b) - F(x-a, y+b) + F(x-a, y-b)``.

    With ``X = x1 - xi`` the load ``xi`` in [-a, a] maps to X in
    [x1-a, x1+a], so this is the definite 2-D integral of the field whose
    mixed derivative d2F/dXdY is the point-load kernel.
    """
    total = 0.0
    for s1 in (1.0, -1.0):
        for s2 in (1.0, -1.0):
            total = total + (s1 * s2) * term(x1 + s1 * half1, x2 + s2 * half2)
    return total


def _x_asinh(a, b):
    """``a asinh(b/|a|)``, with its limit 0 for ``a -> 0``."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        t = a * np.arcsinh(b / np.abs(a))
    return np.where(np.isfinite(t), t, 0.0)


def surface_displacement(x1, x2, *, half1, half2):
    """Surface normal displacement under a uniformly loaded rectangle.

    Parameters
    ----------
    x1, x2 : array_like
        Surface coordinates of the field points relative to the centre of
        the rectangle [m]; broadcast together.
    half1, half2 : float
        Half-widths of the rectangle along x1 and x2 [m].

    Returns
    -------
    ndarray, shape ``broadcast(x1, x2).shape``
        ``u3`` for unit pressure and unit compliance ``(1 - nu^2)/E = 1``
        [m]; multiply by ``p (1 - nu^2)/E`` for a physical solid.  Positive
        (into the solid) everywhere, finite on the rectangle, its edges and
        corners, and tending to ``4 half1 half2 / (pi r)`` far away.

    Notes
    -----
    Integral of the Boussinesq surface displacement ``1/(pi r)`` (Johnson
    1985, eq. 3.22) over the rectangle (Love 1929)::

        u3 = (1/pi) Sum [X asinh(Y/|X|) + Y asinh(X/|Y|)]

    over the four corners ``X = x1 -+ half1``, ``Y = x2 -+ half2``; this
    equals the classical ``X ln(Y+R) + Y ln(X+R)`` up to terms that cancel
    in the corner sum. Far away the corner sum cancels: it loses ``(r/dx)^2``
    of its digits (1e-10 at 300 cells, 1e-6 at 3e5). Beyond 300 cell sizes
    the mean of ``1/(pi r)`` over the rectangle is taken from its multipole
    expansion instead, ``(4ab/pi)[1/r + (a^2 (2x1^2 - x2^2) + b^2 (2x2^2 -
    x1^2))/(6 r^5)]`` (``a, b`` the half-widths), whose next term is
    ``(a/r)^4 < 1e-12`` relative there.
    """
    half1 = check_positive(half1, name="half1", unit="m")
    half2 = check_positive(half2, name="half2", unit="m")
    x1, x2 = np.broadcast_arrays(np.asarray(x1, dtype=float), np.asarray(x2, dtype=float))
    r2 = x1**2 + x2**2
    far = r2 > (600.0 * max(half1, half2)) ** 2
    if not far.any():
        return _corner_sum(lambda X, Y: _x_asinh(X, Y) + _x_asinh(Y, X), x1, x2, half1, half2) / np.pi
    out = np.empty(r2.shape)
    near = ~far
    out[near] = _corner_sum(lambda X, Y: _x_asinh(X, Y) + _x_asinh(Y, X), x1[near], x2[near], half1, half2) / np.pi
    X1, X2, inverse = x1[far], x2[far], 1 / np.sqrt(r2[far])
    out[far] = 4 * half1 * half2 / np.pi * inverse * (
        1 + (half1**2 * (2 * X1**2 - X2**2) + half2**2 * (2 * X2**2 - X1**2)) * inverse**4 / 6)
    return out


def _stress_corner_term(X, Y, z, nu):
    """Antiderivative ``F`` of the six point-load stresses at one corner.

    Returns an array ``X.shape + (6,)``; ``(1/2pi) * corner sum`` of it is
    the stress under the rectangle.  Each expression was checked by
    differentiation (d2F/dXdY = Boussinesq stress) and by quadrature.
    """
    X2, Y2, z2 = X * X, Y * Y, z * z
    R = np.sqrt(X2 + Y2 + z2)
    XY = X * Y
    with np.errstate(divide="ignore", invalid="ignore"):
        # T = atan(XY/(zR)); atan2 gives +-pi/2 at z = 0 and 0 on the edges.
        T = np.arctan2(XY, z * R)
        # R - z without cancellation at depth (0 at a surface corner).
        rmz = _ratio(X2 + Y2, R + z)
        # atan(XY(R-z)/(X^2 R + z Y^2)): denominators >= 0, no branch jump;
        # atan2(0, 0) = 0 is the limit at X = Y = 0 and on X = 0 (Y = 0).
        A1 = np.arctan2(XY * rmz, X2 * R + z * Y2)
        A2 = np.arctan2(XY * rmz, Y2 * R + z * X2)
        q1 = _ratio(z * XY, R * (X2 + z2))  # = -zX/(R(Y+R)) + f(X)
        q2 = _ratio(z * XY, R * (Y2 + z2))  # = -zY/(R(X+R)) + f(Y)
        s12 = -_ratio(z, R)
        if nu != 0.5:  # ln(R+z) = -inf at a corner on the surface: singular
            s12 = s12 - (1.0 - 2.0 * nu) * np.log(R + z)
    return np.stack([
        -2.0 * nu * T - (1.0 - 2.0 * nu) * A1 + q1,  # xx
        -2.0 * nu * T - (1.0 - 2.0 * nu) * A2 + q2,  # yy
        -(T + q1 + q2),  # zz
        _ratio(z2 * X, R * (Y2 + z2)),  # yz = -z^2/(R(X+R)) + f(Y)
        _ratio(z2 * Y, R * (X2 + z2)),  # xz = -z^2/(R(Y+R)) + f(X)
        s12,  # xy
    ], axis=-1)


def subsurface_stress(x1, x2, x3, *, half1, half2, poisson):
    """Stress under a uniformly loaded rectangle (Love 1929), all six components.

    Parameters
    ----------
    x1, x2 : array_like
        Surface coordinates of the field points relative to the centre of
        the rectangle [m].
    x3 : array_like
        Depth of the field points, ``x3 >= 0`` [m]; broadcast with ``x1``
        and ``x2``.  ``x3 = 0`` gives the surface limit.
    half1, half2 : float
        Half-widths of the rectangle along x1 and x2 [m].
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    ndarray, shape ``broadcast(x1, x2, x3).shape + (6,)``
        Stress per unit pressure [Pa/Pa = -], tension positive, Voigt order
        ``xx, yy, zz, yz, xz, xy``.  On the surface ``s33 = -1`` inside the
        rectangle, 0 outside and -1/2 on its edges (mean of the two sides);
        ``s12`` is logarithmically infinite at the corners of the rectangle
        on the surface (for ``nu < 0.5``) and only there.

    Notes
    -----
    With the corner sum ``Sum`` of :func:`surface_displacement`,
    ``R = sqrt(X^2 + Y^2 + x3^2)`` and ``T = atan(X Y/(x3 R))``::

        s11 = (1/2pi) Sum [-2 nu T - (1-2nu) atan(X Y (R-x3)/(X^2 R + x3 Y^2))
                           + x3 X Y/(R (X^2+x3^2))]
        s22 = the same with X and Y exchanged
        s33 = -(1/2pi) Sum [T + (x3 X Y/R) (1/(X^2+x3^2) + 1/(Y^2+x3^2))]
        s23 = (1/2pi) Sum x3^2 X/(R (Y^2+x3^2))
        s13 = (1/2pi) Sum x3^2 Y/(R (X^2+x3^2))
        s12 = -(1/2pi) Sum [(1-2nu) ln(R+x3) + x3/R]
    """
    half1 = check_positive(half1, name="half1", unit="m")
    half2 = check_positive(half2, name="half2", unit="m")
    nu = check_poisson(poisson)
    x1, x2, x3 = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x1, x2, x3)))
    if np.any(x3 < 0.0):
        raise ParameterError(f"x3 must be >= 0 (depth into the solid), got min {x3.min()!r}")
    x3 = x3 + 0.0  # turns -0.0 into +0.0, so that atan2(., z R) keeps its branch
    stress = _corner_sum(lambda X, Y: _stress_corner_term(X, Y, x3, nu), x1, x2, half1, half2)
    return stress / (2.0 * np.pi)


def strip_stress(x1, x3, *, half1, poisson):
    """Plane-strain stress under a uniform pressure on the strip ``|xi| <= half1`` (all ``x2``).

    Parameters
    ----------
    x1 : array_like
        Offset of the field points from the centre line of the strip [m].
    x3 : array_like
        Depth of the field points, ``x3 >= 0`` [m]; broadcast with ``x1``.
    half1 : float
        Half-width of the strip [m].
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    ndarray, shape ``broadcast(x1, x3).shape + (6,)``
        Stress per unit pressure [-], Voigt order ``xx, yy, zz, yz, xz, xy``;
        ``yz = xy = 0`` and ``yy = nu (xx + zz)`` (plane strain).  On the
        surface ``zz = xx = -1`` on the strip, 0 outside, -1/2 on its edges.

    Notes
    -----
    The limit of Love's rectangle (:func:`subsurface_stress`) as its length
    along ``x2`` tends to infinity: the corner terms of ``Y -> +inf`` minus
    ``Y -> -inf`` leave, with ``t = atan2(X, x3)`` and ``X = x1 -+ half1``::

        s11 = (1/2pi) Sum [-2 t + 2 x3 X/(X^2+x3^2)]
        s33 = (1/2pi) Sum [-2 t - 2 x3 X/(X^2+x3^2)]
        s13 = (1/2pi) Sum 2 x3^2/(X^2+x3^2)

    summed as ``F(x1 + half1) - F(x1 - half1)``; ``t`` is the angle between
    the ``x3`` axis and the edge ``X = 0`` seen from the field point. This is
    the uniform strip of Johnson (1985, ch. 2) in the angle form of
    :func:`framework.reference.strip_stress`, derived there from Flamant's
    line load instead (the tests compare the two).
    """
    half1 = check_positive(half1, name="half1", unit="m")
    nu = check_poisson(poisson)
    x1, x3 = np.broadcast_arrays(np.asarray(x1, dtype=float), np.asarray(x3, dtype=float))
    if np.any(x3 < 0.0):
        raise ParameterError(f"x3 must be >= 0 (depth into the solid), got min {float(x3.min())!r}")
    x3 = x3 + 0.0

    def antiderivative(X):
        t = np.arctan2(X, x3)
        r2 = X * X + x3 * x3
        return np.stack([-2.0 * t + 2.0 * _ratio(x3 * X, r2), -4.0 * nu * t, -2.0 * t - 2.0 * _ratio(x3 * X, r2),
                         np.zeros_like(t), 2.0 * _ratio(x3 * x3, r2), np.zeros_like(t)], axis=-1)

    return (antiderivative(x1 + half1) - antiderivative(x1 - half1)) / (2.0 * np.pi)


# Taper of the image sums of periodic_subsurface_stress, in periods: flat to within
# erfc(REACH/WIDTH) = 6e-14 near the load, Fourier transform exp(-pi^2 WIDTH^2) = 8e-14 at
# one cycle per period, below 1e-17 beyond REACH + 6 WIDTH = 20 periods (the sums stop there).
_IMAGE_REACH, _IMAGE_WIDTH, _IMAGE_PERIODS = 9.5, 1.75, 20
# Beyond this distance from the loaded strip [periods] the images add a uniform strip:
# the varying part decays like exp(-2 pi distance / period) < 1e-17.
_IMAGE_FAR = 7.0
# Sign of each stress component under x2 -> -x2 (Voigt order).
_X2_PARITY = np.array([1.0, 1.0, 1.0, -1.0, 1.0, -1.0])


def periodic_subsurface_stress(x1, x3, *, half1, half2, cells, poisson):
    """Stress under a uniformly loaded rectangle repeated periodically along ``x2``.

    The rectangle ``|xi| <= half1``, ``|eta| <= half2`` and its images shifted
    by ``m L`` along ``x2`` (all integers ``m``, period ``L = 2 half2 cells``)
    carry a unit pressure: the kernel of a grid of ``cells`` cells periodic
    along ``x2`` and open along ``x1``.

    Parameters
    ----------
    x1 : array_like, 1-D
        Offsets of the field points along the open axis [m].
    x3 : float
        Depth of the field points, ``x3 >= 0`` [m].
    half1, half2 : float
        Half-widths of the rectangle along x1 and x2 [m].
    cells : int
        Number of cells per period along x2.
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    ndarray, shape ``(x1.size, cells, 6)``
        Stress per unit pressure [-] at ``(x1, j 2 half2, x3)``, ``j = 0 .. cells - 1``,
        Voigt order ``xx, yy, zz, yz, xz, xy``.

    Notes
    -----
    The sum over images ``G_j = Sum_{n = j mod cells} D_n`` of the rectangle
    kernels ``D_n`` (:func:`subsurface_stress` at ``x2 = 2 n half2``) decays
    only like ``1/n^2``. The cells of all ``n`` tile the strip, so that
    ``Sum_n D_n`` is the plane-strain strip :func:`strip_stress`, and ::

        G_j = [strip - Sum_n w_n D_n] / cells + Sum_{n = j mod cells} w_n D_n
              + Sum_n (1 - w_n) (c_n - 1/cells) D_n

    with ``c_n = 1`` on the images of ``j`` (else 0) and any taper ``w_n``. The
    last sum is dropped: ``(1 - w_n) D_n`` is smooth on the scale of a period
    and ``c_n - 1/cells`` has no mean, so by Poisson's summation formula it is
    the spectrum of ``(1 - w) D`` at one cycle per period and beyond. With the
    analytic taper ``w(t) = [erf((R - t)/W) + erf((R + t)/W)] / 2`` (``t = n / cells``
    in periods, ``R = 9.5``, ``W = 1.75``) that spectrum is below ``exp(-pi^2 W^2)``
    and ``erfc(R/W)`` (the taper is flat to that level where ``D_n`` is not
    smooth, next to the load): ~1e-13 of the pressure; direct image sums agree
    to 2e-13 (tests/test_stress_line_contact.py). The varying part
    of ``G_j`` (the modes ``q = 2 pi k / L``) decays like ``exp(-q d)`` with the
    distance ``d`` to the loaded strip, so beyond ``7 L`` the kernel is the
    strip's ``strip / cells`` alone.
    """
    half1 = check_positive(half1, name="half1", unit="m")
    half2 = check_positive(half2, name="half2", unit="m")
    cells = check_positive_int(cells, name="cells")
    nu = check_poisson(poisson)
    x3 = check_non_negative(x3, name="x3", unit="m") + 0.0
    x1 = check_finite_array(x1, name="x1", ndim=1)
    period = 2.0 * half2 * cells
    kernel = np.repeat(strip_stress(x1, x3, half1=half1, poisson=nu)[:, None, :] / cells, cells, axis=1)
    distance = np.hypot(np.maximum(np.abs(x1) - half1, 0.0), x3)
    near = np.flatnonzero(distance < _IMAGE_FAR * period)
    if cells == 1 or near.size == 0:  # one cell per period tiles the strip exactly
        return kernel
    # n = -P cells .. (P + 1) cells - 1, so that n mod cells is the last index of a reshape
    behind, ahead = _IMAGE_PERIODS * cells, (_IMAGE_PERIODS + 1) * cells
    t = np.arange(-behind, ahead) / cells
    taper = 0.5 * (erf((_IMAGE_REACH - t) / _IMAGE_WIDTH) + erf((_IMAGE_REACH + t) / _IMAGE_WIDTH))
    edges = (np.arange(ahead + 1) - 0.5) * 2.0 * half2  # of the cells n >= 0
    chunk = max(1, 200_000 // edges.size)
    for start in range(0, near.size, chunk):
        rows = near[start:start + chunk]
        # corner terms on the shared cell edges along x2, differenced into the cells D_n, n >= 0;
        # D_{-n} = D_n for the components even in x2, -D_n for yz and xy
        corner = (_stress_corner_term((x1[rows] + half1)[:, None], edges[None, :], x3, nu)
                  - _stress_corner_term((x1[rows] - half1)[:, None], edges[None, :], x3, nu))
        ahead_cells = corner[:, 1:] - corner[:, :-1]
        cells_n = np.concatenate([ahead_cells[:, behind:0:-1] * _X2_PARITY, ahead_cells], axis=1)
        tapered = cells_n * (taper[:, None] / (2.0 * np.pi))
        images = tapered.reshape(rows.size, -1, cells, 6).sum(axis=1)
        kernel[rows] += images - tapered.sum(axis=1)[:, None, :] / cells
    return kernel
