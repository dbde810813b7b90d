"""Fields at points on the faces, edges and corners of cuboids and surface cells: one-sided limits.

The strain of uniform eigenstrains in cuboids (Chiu 1977, corner sums of
:mod:`framework.operators.eigenstrain`) and the stress of a uniform pressure on
surface cells at the surface (Love 1929, :mod:`framework.operators.kernels`)
are closed forms in the offsets ``t = x - corner``. On a face plane an offset
vanishes and the forms give ``0/0``, ``atan(+-inf)`` with the sign of a signed
zero, or ``log 0``: a point there read garbage (the centre of a body on an even
grid, a lattice corner, gave -628 MPa for Eshelby's +369 MPa).

Convention (every kind of point, inside or outside the bodies, at the surface
and at the bottom of the grid): a point within :data:`FACE_TOLERANCE` of a
lattice plane lies on it and belongs to the cuboid (cell) on its positive side,
the one ``floor`` picks (:func:`lattice_index`); its value is the limit from
inside that cuboid, along the line towards its centre. Each offset that
vanishes is taken as ``eps * d`` with ``d`` the cuboid's half sizes and
``eps -> 0+``, and each term of the closed forms is replaced by its limit,
found from the leading term ``c eps^p`` of every quantity (:class:`Leading`):
every sum in the forms is of terms of one sign (the cancelling ``r + t`` is
written ``(r^2 - t^2)/(r - t)`` for ``t < 0``), so the leading terms are exact.

- Where the field is continuous (inside a region of uniform eigenstrain, or of
  uniform pressure at the surface), this is its value: the terms that depend on
  the direction of approach, and the ``log eps`` of the logarithms, cancel
  between the neighbouring cuboids.
- Where it is discontinuous (a body's boundary, a face between cuboids of
  different eigenstrain, an edge of a loaded cell at the surface), it is the
  value on the positive side: the side of larger x1, x2, x3, where ``floor``
  puts the point.
- On an edge or corner whose cuboids carry different eigenstrains (a body's
  staircase edge, and inside a body wherever the solved eigenstrain changes
  between cuboids) the model's strain is logarithmically infinite (Chiu 1977;
  the same for the pressure's ``s12`` at a loaded corner at the surface). There
  the logarithms are taken at ``eps = 1``: the singular ``log(distance)`` is
  evaluated at the distance from the edge to the chosen cuboid's centre, the
  rest of the field is its limit. The value is finite and does not depend on
  the units.
"""
import numpy as np

#: A point within this fraction of a cuboid's (cell's) size from a lattice plane lies on it. Far below any
#: distance a user means (1 nm in 25 um cells is 4e-5) and far above rounding of the coordinates (1e-15).
FACE_TOLERANCE = 1e-10


class Leading:
    """The leading term ``c eps^p`` of quantities as ``eps -> 0+`` (arrays ``c != 0`` and ``p``)."""

    __slots__ = ("c", "p")

    def __init__(self, c, p):
        self.c, self.p = c, p

    def __mul__(self, other):
        return Leading(self.c * other.c, self.p + other.p)

    def __truediv__(self, other):
        return Leading(self.c / other.c, self.p - other.p)

    def __add__(self, other):
        """Sum of two quantities of the same sign: the lower power leads, equal powers add."""
        p = np.minimum(self.p, other.p)
        return Leading(np.where(self.p == p, self.c, 0.0) + np.where(other.p == p, other.c, 0.0), p)

    def __neg__(self):
        return Leading(-self.c, self.p)

    def square(self):
        return self * self

    def sqrt(self):
        return Leading(np.sqrt(self.c), 0.5 * self.p)

    def limit(self):
        """Limit of a bounded quantity (``p >= 0``): ``c`` at ``p = 0``, else 0."""
        return np.where(self.p == 0, self.c, 0.0)

    def arctan(self):
        """Limit of ``atan`` of the quantity: ``+-pi/2`` when it grows without bound."""
        return np.where(self.p < 0, np.sign(self.c) * (np.pi / 2),
                        np.where(self.p == 0, np.arctan(self.c), 0.0))

    def log(self):
        """Finite part of ``log``: ``log c``, the ``p log eps`` dropped (it cancels between neighbours)."""
        return np.log(self.c)

    def select(self, mask, other):
        """This quantity where ``mask``, ``other`` elsewhere."""
        return Leading(np.where(mask, self.c, other.c), np.where(mask, self.p, other.p))


def leading_offsets(offsets, direction, tolerance):
    """The offsets as :class:`Leading` quantities: ``(offset, 0)``, or ``(direction, 1)`` where ``|offset| <= tolerance``.

    ``offsets`` and ``direction`` (positive) broadcast; the zeros are approached from the positive side.
    """
    offsets = np.asarray(offsets, dtype=float)
    zero = np.abs(offsets) <= tolerance
    direction = np.broadcast_to(direction, offsets.shape)
    return Leading(np.where(zero, direction, offsets), zero.astype(float))


def _sum_r(t, r, rest2):
    """``r + t`` with ``rest2 = r^2 - t^2``: for ``t < 0`` as ``rest2 / (r - t)``, sums of one sign only."""
    positive = t.c > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        return (r + t).select(positive, rest2 / (r + (-t)))


def _phi_diagonal(ti, tj, tk, r):
    return -(tj * tk / (ti * r)).arctan()


def _phi_mixed(ti, tj, tk, r):
    return _sum_r(tk, r, ti.square() + tj.square()).log()


def _psi_four(ti, tj, tk, r):
    ti2, tj2, tk2 = ti.square(), tj.square(), tk.square()
    return ((ti * tj / (r * _sum_r(tk, r, ti2 + tj2))).limit() + (ti * tk / (r * _sum_r(tj, r, ti2 + tk2))).limit()
            - 2 * (tj * tk / (ti * r)).arctan()
            + 2 * (ti * tj * tk * (r.square() + ti2) / (r * (ti2 + tj2) * (ti2 + tk2))).limit())


def _psi_three_one(ti, tj, tk, r):
    rho2 = ti.square() + tj.square()
    return _sum_r(tk, r, rho2).log() - (ti.square() * tk / (rho2 * r)).limit()


def _psi_two_two(ti, tj, tk, r):
    return -(ti * tj * tk / ((ti.square() + tj.square()) * r)).limit()


def _psi_two_one_one(ti, tj, tk, r):
    return (ti / r).limit()


#: The closed forms of :func:`~framework.operators.eigenstrain.corner_case`'s names, in :class:`Leading` arithmetic.
LIMIT_FORMS = {"phi_diagonal": _phi_diagonal, "phi_mixed": _phi_mixed, "psi_four": _psi_four,
               "psi_three_one": _psi_three_one, "psi_two_two": _psi_two_two, "psi_two_one_one": _psi_two_one_one}


def corner_function_limit(key, t):
    """One corner function ``D H`` of :mod:`framework.operators.eigenstrain` (``key`` a sorted index tuple) as the
    limit described in the module docstring; ``t`` three :class:`Leading` offsets. The same cases
    (:func:`~framework.operators.eigenstrain.corner_case`), written in :class:`Leading` arithmetic."""
    from .eigenstrain import corner_case
    name, (i, j, k) = corner_case(key)
    r = (t[0].square() + t[1].square() + t[2].square()).sqrt()
    return LIMIT_FORMS[name](t[i], t[j], t[k], r)


def cuboid_potentials(offsets, half, cell=None):
    """:func:`framework.operators.eigenstrain.cuboid_potentials` (derivatives of the cuboid potentials by corner
    sums, at any offsets ``(..., 3)`` [m] from the cuboids' centres) for targets anywhere, faces included.

    A corner offset within :data:`FACE_TOLERANCE` of the cuboid's size from zero is zero, approached from
    the positive side along the half sizes ``half``; those entries take the one-sided limits of the
    module docstring, the others the plain closed forms.
    """
    from .eigenstrain import KEYS, _corner_function, cell_average_rule
    half = np.asarray(half, dtype=float)
    total = {key: 0.0 for key in KEYS}
    for shift, weight in zip(*cell_average_rule(cell)):
        for corner in np.ndindex(2, 2, 2):
            signs = 1 - 2 * np.array(corner)
            t = [offsets[..., a] + shift[a] + signs[a] * half[a] for a in range(3)]
            zero = [np.abs(t[a]) <= FACE_TOLERANCE * 2 * half[a] for a in range(3)]
            on_plane = zero[0] | zero[1] | zero[2]
            sign = weight * np.prod(signs)
            r = np.sqrt(t[0] ** 2 + t[1] ** 2 + t[2] ** 2)
            if on_plane.any():
                near = [np.where(on_plane, 1.0, t[a]) for a in range(3)]   # placeholders, replaced below
                r = np.where(on_plane, 1.0, r)
                limits = [leading_offsets(t[a][on_plane], half[a], FACE_TOLERANCE * 2 * half[a]) for a in range(3)]
            else:
                near = t
            for key in KEYS:
                with np.errstate(divide="ignore", invalid="ignore"):
                    value = _corner_function(key, near, r)
                if on_plane.any():
                    value = np.array(value, dtype=float, copy=True)
                    value[on_plane] = corner_function_limit(key, limits)
                total[key] = total[key] + sign * value
    return total


def strain_at_points(points, centres, eigenstrain, half, poisson, chunk=200_000, cell=None):
    """Strain ``(n, 6)`` at ``points (n, 3)`` of an infinite body from cuboids by direct summation, points on
    faces, edges and corners included (:func:`cuboid_potentials`; see the module docstring).

    ``centres (N, 3)`` and ``eigenstrain (N, 6)`` give the cuboids and their eigenstrains (tensor shears),
    ``half`` their half sizes [m]. It costs ``n N`` kernel evaluations: for checks and a few points. With
    ``cell`` (sizes [m]) the strain is averaged over a cell centred on each point.
    """
    from .eigenstrain import strain_from_potentials
    points, centres = np.asarray(points, dtype=float), np.asarray(centres, dtype=float)
    out = np.zeros((len(points), 6))
    per_point = max(1, chunk // max(1, len(centres)))
    for begin in range(0, len(points), per_point):
        block = points[begin:begin + per_point]
        offsets = block[:, None, :] - centres[None, :, :]
        out[begin:begin + per_point] = strain_from_potentials(cuboid_potentials(offsets, half, cell),
                                                              eigenstrain[None], poisson).sum(axis=1)
    return out


def lattice_index(points, origin, spacing):
    """Index ``(n, 3)`` of the cuboid of a lattice that holds each point ``(n, 3)`` [m]: ``floor``, with a point
    within :data:`FACE_TOLERANCE` of a plane on it, so in the cuboid on its positive side (the convention of
    :func:`cuboid_potentials`)."""
    position = (np.asarray(points, dtype=float) - origin) / spacing
    return np.floor(position + FACE_TOLERANCE).astype(int)


def _surface_corner_limit(X, Y, nu):
    """Love's corner term (:func:`framework.operators.kernels._stress_corner_term`) at the surface ``x3 = 0``
    for :class:`Leading` offsets ``X, Y``: ``T = +-pi/2``, ``atan(Y/X)``, ``atan(X/Y)`` and ``ln R``
    (the finite part at a corner), the shears through x3 zero."""
    T = np.sign(X.c * Y.c) * (np.pi / 2)
    a1, a2 = (Y / X).arctan(), (X / Y).arctan()
    R = (X.square() + Y.square()).sqrt()
    s12 = -(1.0 - 2.0 * nu) * R.log() if nu != 0.5 else np.zeros_like(T)
    zero = np.zeros_like(T)
    return np.stack([-2.0 * nu * T - (1.0 - 2.0 * nu) * a1, -2.0 * nu * T - (1.0 - 2.0 * nu) * a2, -T,
                     zero, zero, s12], axis=-1)


def surface_cell_stress(x1, x2, *, half1, half2, poisson):
    """Stress ``(..., 6)`` per unit pressure at the surface ``x3 = 0`` of uniformly loaded rectangles, at offsets
    ``x1, x2`` [m] from their centres, the rectangles' edges and corners included.

    The one-sided limit from the cell on the positive side of an edge (see the module docstring) where
    :func:`framework.operators.kernels.subsurface_stress` gives the mean of the two sides (``s33 = -1/2``
    on an edge) or ``log 0`` (``s12`` at a corner).
    """
    x1, x2 = np.broadcast_arrays(np.asarray(x1, dtype=float), np.asarray(x2, dtype=float))
    total = 0.0
    for s1 in (1.0, -1.0):
        for s2 in (1.0, -1.0):
            X = leading_offsets(x1 + s1 * half1, half1, FACE_TOLERANCE * 2 * half1)
            Y = leading_offsets(x2 + s2 * half2, half2, FACE_TOLERANCE * 2 * half2)
            total = total + (s1 * s2) * _surface_corner_limit(X, Y, poisson)
    return total / (2.0 * np.pi)


def love_stress_at(points, x1, x2, pressure, *, spacing, poisson):
    """Stress ``(n, 6)`` [Pa] at points ``(n, 3)`` [m] of a piecewise-constant pressure ``pressure`` [Pa] on cells
    centred at ``x1, x2`` [m] (1-D arrays, one per loaded cell) of sizes ``spacing = (dx1, dx2)`` [m].

    Love's coefficients (:func:`framework.operators.kernels.subsurface_stress`), continuous below the
    surface; a point within :data:`FACE_TOLERANCE` of a cell's size from the surface is on it, where the
    stress jumps at the cells' edges: there it takes :func:`surface_cell_stress`, the side of larger x1, x2.
    """
    from .kernels import subsurface_stress
    dx1, dx2 = spacing
    out = np.empty((len(points), 6))
    surface = FACE_TOLERANCE * min(dx1, dx2)
    for i, (y1, y2, y3) in enumerate(np.asarray(points, dtype=float)):
        if y3 <= surface:
            coefficients = surface_cell_stress(y1 - x1, y2 - x2, half1=dx1 / 2, half2=dx2 / 2, poisson=poisson)
        else:
            coefficients = subsurface_stress(y1 - x1, y2 - x2, y3, half1=dx1 / 2, half2=dx2 / 2, poisson=poisson)
        out[i] = pressure @ coefficients
    return out
