"""Random dispersions of inhomogeneities: particles and short fibres filling a region of the subsurface.

:func:`random_dispersion` places spheres or prolate spheroids by random sequential addition (Widom 1966,
J. Chem. Phys. 44, 3888), the largest first: each body gets its orientation once, then centres drawn uniformly where it lies
wholly inside the region until one leaves every placed body at least ``gap`` away. The overlap test is the
Perram-Wertheim contact function (:func:`~framework.inclusions.bodies.contact_function`) of the bodies grown by
half the gap, behind cheaper tests that settle most pairs: a spatial hash of the centres (only bodies in the
neighbouring cells are compared), their bounding spheres (apart: disjoint) and inscribed spheres (crossing: an
overlap), points of either long axis inside the other body (an overlap), and the contact function's defining maximum
sampled on a few ``lambda`` (any sample above 1 proves the pair disjoint). Only the pairs left undecided call the
exact contact function.

Random sequential addition jams: monodisperse spheres stop near a volume fraction of 0.38 (Torquato, Uche &
Stillinger 2006, Phys. Rev. E 74, 061308), elongated bodies far lower; beyond, :func:`random_dispersion` raises
instead of looping.
"""
import numbers
from functools import partial

import numpy as np
from scipy.optimize import brentq

from .._validation import check_quantity, check_real
from ..errors import InclusionError, ParameterError
from ..materials import AnisotropicElastic, Elastic
from .bodies import TOUCH_TOLERANCE, Ellipsoid, InclusionSet, contact_function

#: Largest volume fraction asked for: random sequential addition jams well below it (0.38 for spheres); a packing
#: denser than random close packing (0.64) is out of reach of any random placement.
MAX_FRACTION = 0.6
#: Centres drawn for one body before the fraction is declared out of reach. Near the jamming limit the share of
#: free space falls towards zero; 20 000 draws find a hole of 1e-4 of the region with probability 0.86, and cost
#: about a second for spheres.
MAX_ATTEMPTS = 20_000
#: Values of ``lambda`` in (0, 1) at which the Perram-Wertheim function is sampled before the exact maximum is
#: sought: any sample above 1 proves two ellipsoids disjoint. 15 points settle all but pairs within a few percent of
#: contact.
LAMBDA_SAMPLES = np.linspace(0.0, 1.0, 17)[1:-1]
#: Directions (angle from the long axis, in [0, pi/2]) at which the growth of a spheroid is checked
#: (:func:`_growth`): the shortfall of the support function is smooth in the angle, so 2049 samples find its least
#: value to ~1e-7 of the gap.
GROWTH_SAMPLES = 2049
#: Points along a body's long axis, as fractions of its long semi-axis, that prove an overlap when one lies inside the
#: other body: crossing fibres mostly hold one, and settle without the contact function.
AXIS_POINTS = np.linspace(-1.0, 1.0, 13)[1:-1]
ORIENTATIONS = ("random", "planar", "aligned")


def _check_region(region):
    """``region`` as a (3, 2) float array of increasing pairs [m], below the surface (x3 >= 0)."""
    try:
        bounds = np.asarray(region, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"region must be three pairs (lo, hi) [m] along x1, x2, x3, got {region!r}") from exc
    if bounds.shape != (3, 2) or not np.all(np.isfinite(bounds)):
        raise ParameterError(f"region must be three finite pairs (lo, hi) [m] along x1, x2, x3, got {region!r}")
    for axis, (low, high) in enumerate(bounds.tolist()):
        if not low < high:
            raise ParameterError(f"region[{axis}] = ({low!r}, {high!r}): expected lo < hi along x{axis + 1}")
    if bounds[2, 0] < 0.0:
        raise ParameterError(f"region[2] = {tuple(bounds[2].tolist())!r} starts above the surface; expected "
                             f"depths x3 >= 0")
    return bounds


def _check_sizes(radius):
    """``[(radius [m], volume share)]`` from a constant or a list of (radius, weight); shares add up to 1."""
    if isinstance(radius, numbers.Real) and not isinstance(radius, bool):
        return [(check_quantity(radius, name="radius", unit="m"), 1.0)]
    if isinstance(radius, (str, bytes)) or not hasattr(radius, "__iter__") or len(list(radius)) == 0:
        raise ParameterError(f"radius must be a radius [m] or a non-empty list of (radius, weight), got {radius!r}")
    sizes = []
    for k, item in enumerate(radius):
        if isinstance(item, (str, bytes)) or not hasattr(item, "__len__") or len(item) != 2:
            raise ParameterError(f"radius[{k}] must be a pair (radius [m], weight), got {item!r}")
        size = check_quantity(item[0], name=f"radius[{k}][0] (a radius)", unit="m")
        weight = check_real(item[1], name=f"radius[{k}][1] (a weight)")
        if weight <= 0.0:
            raise ParameterError(f"radius[{k}][1] (a weight) must be positive, got {weight!r}")
        sizes.append((size, weight))
    total = sum(weight for _, weight in sizes)
    return [(size, weight / total) for size, weight in sizes]


def _check_direction(orientation):
    """``orientation`` as ``"random"``, ``"planar"`` or a unit vector (3,) (``"aligned"``: x1)."""
    if isinstance(orientation, str):
        if orientation not in ORIENTATIONS:
            raise ParameterError(f"orientation must be one of {list(ORIENTATIONS)} or a direction (3 numbers), "
                                 f"got {orientation!r}")
        return np.array([1.0, 0.0, 0.0]) if orientation == "aligned" else orientation
    try:
        direction = np.asarray(orientation, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"orientation must be one of {list(ORIENTATIONS)} or a direction (3 numbers), "
                             f"got {orientation!r}") from exc
    if direction.shape != (3,) or not np.all(np.isfinite(direction)):
        raise ParameterError(f"orientation as a direction must be 3 finite numbers, got {orientation!r}")
    length = np.linalg.norm(direction)
    if length == 0.0:
        raise ParameterError(f"orientation as a direction must be non-zero, got {orientation!r}")
    return direction / length


def _check_seed(seed):
    if seed is None:
        return None
    if not isinstance(seed, numbers.Integral) or isinstance(seed, bool) or seed < 0:
        raise ParameterError(f"seed must be an integer >= 0 or None (a fresh one each call), got {seed!r}")
    return int(seed)


def _turn_x1_to(direction):
    """The least rotation (3, 3) taking ``x1`` to the unit vector ``direction`` (Rodrigues' formula)."""
    cosine = direction[0]
    axis = np.array([0.0, -direction[2], direction[1]])     # x1 x direction
    sine = np.linalg.norm(axis)
    if sine < 1e-12:
        return np.eye(3) if cosine > 0.0 else np.diag([-1.0, -1.0, 1.0])   # half a turn about x3
    k = axis / sine
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return cosine * np.eye(3) + sine * cross + (1.0 - cosine) * np.outer(k, k)


def _draw_orientation(kind, rng):
    """A rotation whose first column is the long axis: ``kind`` itself (a fixed rotation), or drawn as ``"planar"``
    or ``"random"`` asks."""
    if isinstance(kind, np.ndarray):
        return kind
    if kind == "planar":
        angle = 2.0 * np.pi * rng.random()
        c, s = np.cos(angle), np.sin(angle)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    # isotropic: cos(theta) uniform on [-1, 1], azimuth and the turn about the long axis uniform on [0, 2 pi)
    cosine, azimuth, spin = 2.0 * rng.random() - 1.0, 2.0 * np.pi * rng.random(), 2.0 * np.pi * rng.random()
    sine = np.sqrt(1.0 - cosine * cosine)
    direction = np.array([sine * np.cos(azimuth), sine * np.sin(azimuth), cosine])
    c, s = np.cos(spin), np.sin(spin)
    return _turn_x1_to(direction) @ np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _growth(long, across, half_gap):
    """Least ``t`` such that the spheroid of semi-axes ``(long + t, across + t, across + t)`` holds every point
    within ``half_gap`` [m] of the one ``(long, across, across)``.

    The ellipsoid grown by ``t`` holds the parallel body iff its support function exceeds the spheroid's by
    ``half_gap`` in every direction ``u``: ``sqrt((a + t)^2 u1^2 + (b + t)^2 u_perp^2) - sqrt(a^2 u1^2 + b^2
    u_perp^2) >= half_gap``. The difference equals ``t`` along the axes and dips between them: ``t = half_gap``
    leaves a spheroid of aspect 10 only 0.6 of the gap. ``t`` is the root of the least difference minus
    ``half_gap``, between ``half_gap`` and ``half_gap * long / across`` (the scaled spheroid, which holds the
    parallel body). Spheres: ``t = half_gap`` exactly.
    """
    if half_gap == 0.0 or long == across:
        return half_gap
    angle = np.linspace(0.0, 0.5 * np.pi, GROWTH_SAMPLES)
    c2, s2 = np.cos(angle) ** 2, np.sin(angle) ** 2
    base = np.sqrt(long ** 2 * c2 + across ** 2 * s2)

    def shortfall(t):
        return np.min(np.sqrt((long + t) ** 2 * c2 + (across + t) ** 2 * s2) - base) - half_gap

    high = half_gap * long / across
    if shortfall(high) <= 0.0:  # only by rounding: the scaled spheroid holds the parallel body
        return high
    return brentq(shortfall, half_gap, high, xtol=1e-12 * high)


def _counts(sizes, target, aspect):
    """Bodies per size class (largest first) whose volumes add up nearest to ``target`` [m^3] class by class.

    Each class's count is rounded to reach the cumulative volume asked up to it, so that the rounding of the larger
    classes is made up by the smaller ones: the total misses ``target`` by at most half the smallest body.
    """
    counts, placed, asked = [], 0.0, 0.0
    for size, share in sorted(sizes, key=lambda item: -item[0]):
        volume = 4.0 / 3.0 * np.pi * aspect * size ** 3
        asked += share * target
        count = max(int(round((asked - placed) / volume)), 0)
        counts.append((size, count))
        placed += count * volume
    return counts


class _Placed:
    """The bodies placed so far (at most ``capacity``), grown by half the gap, in a spatial hash of cell ``cell`` [m].

    ``outer`` and ``inner`` are a grown body's bounding and inscribed sphere radii [m], ``shapes`` its shape matrix.
    """

    def __init__(self, cell, capacity):
        self.cell = cell
        self.cells = {}
        self.count = 0
        self.centers, self.shapes = np.zeros((capacity, 3)), np.zeros((capacity, 3, 3))
        self.forms, self.axes = np.zeros((capacity, 3, 3)), np.zeros((capacity, 3))   # A^-1 [1/m^2], long axis [m]
        self.outer, self.inner = np.zeros(capacity), np.zeros(capacity)
        self.grown = []

    def _key(self, center):
        return tuple(int(k) for k in np.floor(center / self.cell))

    def neighbours(self, center):
        """Indices of the bodies in the 27 cells around ``center``: all that may reach a body within the cell."""
        i, j, k = self._key(center)
        found = []
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                for dk in (-1, 0, 1):
                    found.extend(self.cells.get((i + di, j + dj, k + dk), ()))
        return np.array(found, dtype=int)

    def free(self, center, shape, form, axis, outer, inner, grown):
        """Whether a grown body of ``center``, ``shape`` matrix and sphere radii leaves every placed one disjoint.

        Disjoint: Perram-Wertheim contact function > 1 + tolerance. ``form`` is the inverse of ``shape``, ``axis``
        the long semi-axis as a vector [m]; ``grown()`` makes the body as an :class:`Ellipsoid` for the pairs only the
        exact contact function settles.
        """
        near = self.neighbours(center)
        if len(near) == 0:
            return True
        offset = self.centers[near] - center
        distance2 = np.einsum("ij,ij->i", offset, offset)
        close = distance2 <= (self.outer[near] + outer) ** 2 * (1.0 + TOUCH_TOLERANCE)
        if not np.any(close):
            return True
        near, offset, distance2 = near[close], offset[close], distance2[close]
        if np.any(distance2 < (self.inner[near] + inner) ** 2):
            return False  # the inscribed spheres cross
        spheres = (self.outer[near] == self.inner[near]) & (outer == inner)
        if np.any(spheres):
            return False  # two spheres, the bounding spheres are the bodies: they touch within the tolerance
        # a point of either long axis inside the other body
        mine = center + AXIS_POINTS[:, None] * axis - self.centers[near][:, None]                 # (pairs, points, 3)
        if np.any(np.einsum("npi,nij,npj->np", mine, self.forms[near], mine) <= 1.0):
            return False
        theirs = self.centers[near][:, None] + AXIS_POINTS[:, None] * self.axes[near][:, None] - center
        if np.any(np.einsum("npi,ij,npj->np", theirs, form, theirs) <= 1.0):
            return False
        # F(lambda) = lambda (1 - lambda) r^T [(1 - lambda) A + lambda B]^-1 r at a few lambda, all pairs at once
        lam = LAMBDA_SAMPLES[None, :, None, None]
        matrices = (1.0 - lam) * self.shapes[near][:, None] + lam * shape
        rhs = np.broadcast_to(offset[:, None, :, None], (*matrices.shape[:2], 3, 1))
        values = LAMBDA_SAMPLES * (1.0 - LAMBDA_SAMPLES) * np.einsum(
            "pli,pli->pl", np.broadcast_to(offset[:, None, :], matrices.shape[:3]),
            np.linalg.solve(matrices, rhs)[..., 0])
        undecided = near[values.max(axis=1) <= 1.0 + TOUCH_TOLERANCE]
        if len(undecided) == 0:
            return True
        body = grown()
        return all(contact_function(self.grown[n], body) > 1.0 + TOUCH_TOLERANCE for n in undecided)

    def add(self, body, form, axis, outer, inner):
        n = self.count
        self.cells.setdefault(self._key(np.asarray(body.center)), []).append(n)
        self.centers[n], self.shapes[n], self.outer[n], self.inner[n] = body.center, body.shape_matrix, outer, inner
        self.forms[n], self.axes[n] = form, axis
        self.grown.append(body)
        self.count += 1


def random_dispersion(fraction, region, radius, material, *, aspect=1.0, orientation="random", gap=0.0, seed=None):
    """A reproducible random set of spheres or prolate spheroids filling ``region`` to a volume ``fraction``.

    Random sequential addition, the largest bodies first (see the module's docstring): every body lies wholly
    inside ``region``, and any two stay at least ``gap`` apart (each grown by the least margin that holds all
    points within ``gap / 2`` of it, :func:`_growth`, then tested by the Perram-Wertheim contact function).

    Parameters
    ----------
    fraction : float
        Volume fraction of ``region`` filled by the bodies, in (0, 0.6]. The bodies' count is the one whose analytic
        volumes add up nearest to ``fraction`` times the region's volume (at most half the smallest body away:
        within 1 % from 50 bodies up). Random sequential addition jams near 0.38 for spheres and lower for fibres:
        a fraction beyond reach raises :class:`~framework.errors.InclusionError`.
    region : sequence of 3 pairs
        ``((x1 lo, hi), (x2 lo, hi), (x3 lo, hi))`` [m], depths ``x3 >= 0``.
    radius : float or list of (float, float)
        Semi-axis across the body [m] (a sphere's radius), or a size distribution as pairs ``(radius [m],
        weight)``: the weights (> 0, normalised) are the shares of the filled VOLUME each radius takes, as a sieve
        analysis gives them.
    material : materials.Elastic or materials.AnisotropicElastic
        Every body's stiffness (an anisotropic one in the body's frame, its first axis the long axis).
    aspect : float
        Long semi-axis over ``radius`` (>= 1): 1 gives spheres, > 1 prolate spheroids ``(aspect * radius, radius,
        radius)`` whose first semi-axis is the long one.
    orientation : str or array_like, shape (3,)
        Direction of the long axis: ``"random"`` (isotropic: cos of its angle to x3 uniform on [-1, 1], the
        azimuth and the turn about the long axis uniform), ``"planar"`` (uniform in the x1-x2 plane, the third
        semi-axis along x3), ``"aligned"`` (x1) or a direction (3 numbers, normalised). Spheres take the identity.
    gap : float
        Least distance between two bodies' surfaces [m], >= 0 (0: they may come arbitrarily close without touching).
    seed : int or None
        Seed of the random generator (``numpy.random.default_rng``): the same seed gives the same set on any
        machine; None a fresh one each call.

    Returns
    -------
    InclusionSet
        The bodies, largest first (in placement order).

    Raises
    ------
    ParameterError
        A bad argument (named), or bodies that cannot fit in the region in every orientation asked.
    InclusionError
        The fraction cannot be reached: a body found no room within :data:`MAX_ATTEMPTS` draws.
    """
    if not isinstance(fraction, numbers.Real) or isinstance(fraction, bool) or not 0.0 < fraction <= MAX_FRACTION:
        raise ParameterError(f"fraction must be a volume fraction in (0, {MAX_FRACTION}], got {fraction!r}")
    bounds = _check_region(region)
    sizes = _check_sizes(radius)
    if not isinstance(material, (Elastic, AnisotropicElastic)):
        raise ParameterError(f"material must be materials.Elastic or materials.AnisotropicElastic (inhomogeneities "
                             f"are elastic), got {type(material).__name__}")
    aspect = check_real(aspect, name="aspect")
    if aspect < 1.0:
        raise ParameterError(f"aspect must be >= 1 (the long semi-axis over the others: 1 spheres, > 1 prolate "
                             f"spheroids), got {aspect!r}")
    kind = _check_direction(orientation)
    if aspect == 1.0:
        kind = np.eye(3)   # spheres have no orientation to draw
    elif isinstance(kind, np.ndarray):
        kind = _turn_x1_to(kind)
    gap = check_quantity(gap, name="gap", unit="m", zero=True)
    seed = _check_seed(seed)
    sides = bounds[:, 1] - bounds[:, 0]
    for size, _ in sizes:
        _check_fits(size, aspect, kind, sides, orientation)

    region_volume = float(np.prod(sides))
    counts = _counts(sizes, fraction * region_volume, aspect)
    if sum(count for _, count in counts) == 0:
        smallest = min(size for size, _ in sizes)
        raise ParameterError(f"fraction = {fraction!r} of the region ({region_volume:.6g} m^3) holds less than half "
                             f"a body of radius {smallest:.6g} m and aspect {aspect:g}; expected a larger fraction or "
                             f"region, or smaller bodies")
    rng = np.random.default_rng(seed)
    growth = {size: _growth(aspect * size, size, 0.5 * gap) for size, _ in counts}
    largest = max(aspect * size + growth[size] for size, _ in counts)
    placed, bodies, volume = _Placed(2.0 * largest, sum(c for _, c in counts)), [], 0.0
    for size, count in counts:
        semi_axes = (aspect * size, size, size)
        grown_axes = tuple(a + growth[size] for a in semi_axes)
        for _ in range(count):
            rotation = _draw_orientation(kind, rng)
            half = np.sqrt(np.square(rotation * semi_axes).sum(axis=1))   # the body's half-extent along x1, x2, x3
            low, span = bounds[:, 0] + half, sides - 2.0 * half
            shape = (rotation * np.square(grown_axes)) @ rotation.T
            form = (rotation / np.square(grown_axes)) @ rotation.T
            axis = grown_axes[0] * rotation[:, 0]
            for _attempt in range(MAX_ATTEMPTS):
                center = low + span * rng.random(3)
                if placed.free(center, shape, form, axis, grown_axes[0], grown_axes[1],
                               partial(Ellipsoid, center, grown_axes, material, rotation)):
                    break
            else:
                reached = volume / region_volume
                raise InclusionError(
                    f"fraction = {fraction!r} cannot be reached: {len(bodies)} of "
                    f"{sum(c for _, c in counts)} bodies placed (fraction {reached:.4g}), the next one (radius "
                    f"{size:.6g} m, aspect {aspect:g}) found no room in {MAX_ATTEMPTS} attempts; random "
                    f"sequential addition jams near 0.38 for spheres and lower for elongated bodies or a wide gap: "
                    f"expected a smaller fraction or gap")
            placed.add(Ellipsoid(center, grown_axes, material, rotation), form, axis, grown_axes[0], grown_axes[1])
            bodies.append(Ellipsoid(center, semi_axes, material, rotation))
            volume += bodies[-1].volume
    return InclusionSet(bodies)


def _check_fits(size, aspect, kind, sides, orientation):
    """Raise unless a body of ``radius`` ``size`` fits in a region of ``sides`` [m] in every orientation drawn."""
    long = aspect * size
    if isinstance(kind, np.ndarray):
        extent = 2.0 * np.sqrt(np.square(kind * (long, size, size)).sum(axis=1))
    elif kind == "planar":
        extent = 2.0 * np.array([long, long, size])
    else:
        extent = np.full(3, 2.0 * long)
    for axis in range(3):
        if extent[axis] >= sides[axis]:
            shape = "a sphere" if aspect == 1.0 else f"aspect {aspect:g}, orientation {orientation!r}"
            raise ParameterError(
                f"radius = {size:.6g} m ({shape}): the bodies span up to {extent[axis]:.6g} m along x{axis + 1}, "
                f"the region only {sides[axis]:.6g} m; expected bodies smaller than the region")
