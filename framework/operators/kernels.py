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

Conventions: ``x1``, ``x2`` in the surface plane, ``x3 >= 0`` depth into the
solid; uniform pressure ``p = 1`` pressing into the solid (``+x3``) on
``|xi| <= half1``, ``|eta| <= half2``; tension positive; ``u3`` positive
into the solid; Voigt order ``xx, yy, zz, yz, xz, xy``.
"""
import numpy as np

from .._validation import check_poisson, check_positive
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
    in the corner sum.
    """
    half1 = check_positive(half1, name="half1", unit="m")
    half2 = check_positive(half2, name="half2", unit="m")
    x1, x2 = np.asarray(x1, dtype=float), np.asarray(x2, dtype=float)
    return _corner_sum(lambda X, Y: _x_asinh(X, Y) + _x_asinh(Y, X), x1, x2, half1, half2) / np.pi


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
