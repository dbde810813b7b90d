"""Ellipsoidal elastic inhomogeneities in the half-space, their orientation and their placement on the grid.

Coordinates: ``x1, x2`` in the surface plane, ``x3 >= 0`` the depth (THEORY.md sec. 1, 8). An
ellipsoid of centre ``c``, semi-axes ``a`` and orientation ``R`` (columns: the directions of the
semi-axes in the global frame) is the set ``(x - c)^T A^-1 (x - c) <= 1`` with the shape matrix
``A = R diag(a^2) R^T``.
"""
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.spatial import cKDTree

from .._validation import LIMITS, check_finite_array, check_quantity, check_real
from ..errors import InclusionError, ParameterError, ShapeError
from ..grid import Grid
from ..materials import AnisotropicElastic, Elastic, rotate_stiffness

#: Largest deviation ``max |R^T R - I|`` accepted in an orientation; the matrix is then made exactly orthogonal.
ORTHOGONALITY_TOLERANCE = 1e-9

_ROUNDING = 1e-14  # max |R^T R - I| of a rotation computed in double precision

#: Fewest cuboids per semi-axis that the equivalent inclusion method accepts (along each semi-axis direction).
MIN_CELLS_PER_SEMI_AXIS = 3
#: Relative tolerance of that count: far above the rounding of a quotient of sizes (~1e-16), far below any
#: resolution that matters.
CELLS_TOLERANCE = 1e-9

#: Ellipsoids whose Perram-Wertheim contact function is at most ``1 + TOUCH_TOLERANCE`` touch or overlap.
TOUCH_TOLERANCE = 1e-12

#: Columns per cuboid side of the rule that measures the share of a cuboid inside an ellipsoid
#: (:meth:`Ellipsoid.cell_fractions`): ``FRACTION_COLUMNS^2`` columns along x3, each cut by the ellipsoid
#: exactly (the roots of a quadratic). At 8 cuboids per semi-axis the shares add up to the ellipsoid's volume
#: within 7e-6 (a sphere) and 4e-5 (a tilted ellipsoid 1 : 0.7 : 0.45) placed anywhere, within 1.5e-4 for a sphere
#: centred on a cuboid corner (the columns meet its outline in step); with 4 columns 8e-5 and 3e-4.
FRACTION_COLUMNS = 8

_AXES = "xyz"


def _axis_rotation(axis, angle):
    """Rotation by ``angle`` [rad] about global axis ``axis`` (0, 1, 2), right-handed."""
    c, s = np.cos(angle), np.sin(angle)
    j, k = (axis + 1) % 3, (axis + 2) % 3
    rotation = np.eye(3)
    rotation[j, j] = rotation[k, k] = c
    rotation[k, j], rotation[j, k] = s, -s
    return rotation


def euler_orientation(phi, theta, psi, convention="zxz"):
    """Orientation matrix from intrinsic Euler (or Tait-Bryan) angles.

    The body frame starts aligned with ``x1, x2, x3``; it is turned by ``phi`` about its axis
    ``convention[0]``, then by ``theta`` about its (moved) axis ``convention[1]``, then by ``psi``
    about its (twice moved) axis ``convention[2]``, each right-handed. For the default ``"zxz"``:
    ``R = Rz(phi) Rx(theta) Rz(psi)``. The columns of ``R`` are the rotated axes, i.e. the directions
    of the semi-axes ``a1, a2, a3`` in the global frame, as :class:`Ellipsoid` expects. (The same
    matrix as scipy's ``Rotation.from_euler(convention.upper(), ...)`` and as extrinsic rotations
    about the fixed axes in the reverse order.)

    Parameters
    ----------
    phi, theta, psi : float
        The three angles [rad].
    convention : str
        Three of ``x, y, z`` with no two consecutive equal (``"zxz"``, ``"zyz"``, ``"xyz"``, ...).

    Returns
    -------
    ndarray, shape (3, 3)
        Rotation matrix (orthonormal, determinant +1).
    """
    if not (isinstance(convention, str) and len(convention) == 3 and set(convention) <= set(_AXES)
            and convention[0] != convention[1] and convention[1] != convention[2]):
        raise ParameterError(f"convention must be three of 'x', 'y', 'z' with no two consecutive equal "
                             f"(e.g. 'zxz', 'xyz'), got {convention!r}")
    angles = [check_real(value, name=name) for name, value in (("phi", phi), ("theta", theta), ("psi", psi))]
    rotation = np.eye(3)
    for letter, angle in zip(convention, angles):
        rotation = rotation @ _axis_rotation(_AXES.index(letter), angle)
    return rotation


def axis_angle_orientation(axis, angle):
    """Orientation matrix of a right-handed rotation by ``angle`` [rad] about ``axis`` (Rodrigues' formula).

    Parameters
    ----------
    axis : array_like, shape (3,)
        Rotation axis in the global frame (any non-zero length).
    angle : float
        Rotation angle [rad].

    Returns
    -------
    ndarray, shape (3, 3)
        ``R = cos(angle) I + sin(angle) [k]_x + (1 - cos(angle)) k k^T``, ``k`` the unit axis.
    """
    axis = check_finite_array(axis, name="axis", shape=(3,))
    length = np.linalg.norm(axis)
    if length == 0.0:
        raise ParameterError(f"axis must be a non-zero vector, got {axis.tolist()!r}")
    k = axis / length
    angle = check_real(angle, name="angle")
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.cos(angle) * np.eye(3) + np.sin(angle) * cross + (1.0 - np.cos(angle)) * np.outer(k, k)


def _check_orientation(orientation):
    """``orientation`` as an exactly orthogonal rotation matrix, or raise saying how far it is from one."""
    if orientation is None:
        return np.eye(3)
    rotation = check_finite_array(orientation, name="orientation", shape=(3, 3))
    deviation = np.max(np.abs(rotation.T @ rotation - np.eye(3)))
    if deviation > ORTHOGONALITY_TOLERANCE:
        raise ParameterError(f"orientation must be a rotation matrix (orthonormal columns: the semi-axes' "
                             f"directions), got max |R^T R - I| = {deviation:.3g}; expected at most "
                             f"{ORTHOGONALITY_TOLERANCE:g}")
    determinant = np.linalg.det(rotation)
    if determinant < 0.0:
        raise ParameterError(f"orientation must be a proper rotation (det = +1), got det = {determinant:.6g} "
                             f"(a reflection); swap two columns or negate one")
    if deviation <= _ROUNDING:
        return rotation  # orthogonal to double precision: kept bit for bit, so that a saved one reads back equal
    u, _, vt = np.linalg.svd(rotation)
    return u @ vt  # the nearest rotation: removes the rounding of typed-in matrices


@dataclass(frozen=True, eq=False)
class Ellipsoid:
    """An elastic ellipsoidal inhomogeneity below the surface.

    Parameters
    ----------
    center : array_like, shape (3,)
        Centre ``(x1, x2, x3)`` [m]; ``x3 > 0`` is its depth.
    semi_axes : array_like, shape (3,)
        Semi-axes ``(a1, a2, a3)`` [m], each > 0.
    material : materials.Elastic or materials.AnisotropicElastic
        Stiffness of the inhomogeneity (elastic: a viscoelastic inhomogeneity is refused). An
        anisotropic stiffness is given in the ellipsoid's own frame, whose axes are the semi-axes'
        directions (the columns of ``orientation``); :attr:`stiffness_tensor` is the global one.
    orientation : array_like, shape (3, 3), optional
        Rotation matrix whose columns are the directions of the semi-axes ``a1, a2, a3`` in the global
        frame (:func:`euler_orientation`, :func:`axis_angle_orientation`); None: aligned with
        ``x1, x2, x3``. Refused if not orthonormal within :data:`ORTHOGONALITY_TOLERANCE` or a
        reflection; stored exactly orthogonal.

    Two ellipsoids compare equal when all four members are equal.
    """

    center: tuple
    semi_axes: tuple
    material: object
    orientation: np.ndarray = field(default=None, repr=False)

    def __post_init__(self):
        center = check_finite_array(self.center, name="center", shape=(3,))
        for i in (0, 1):
            if abs(center[i]) > LIMITS["m"][1]:
                raise ParameterError(f"center[{i}] must lie within +-{LIMITS['m'][1]:g} m, "
                                     f"the range this framework accepts, got {center[i]!r}")
        check_quantity(center[2], name="center[2] (the depth of the centre)", unit="m")
        semi_axes = check_finite_array(self.semi_axes, name="semi_axes", shape=(3,))
        for k, value in enumerate(semi_axes):
            check_quantity(value, name=f"semi_axes[{k}]", unit="m")
        if not isinstance(self.material, (Elastic, AnisotropicElastic)):
            raise ParameterError(f"material must be materials.Elastic or materials.AnisotropicElastic "
                                 f"(inhomogeneities are elastic), got {type(self.material).__name__}")
        if isinstance(self.material, Elastic) and self.material.poisson == 0.5:
            raise ParameterError(f"material.poisson = {self.material.poisson!r} (incompressible) gives an "
                                 f"inhomogeneity no finite stiffness tensor, which the equivalent-inclusion method "
                                 f"needs; expected poisson < 0.5 (e.g. 0.4999, nearly incompressible)")
        rotation = _check_orientation(self.orientation)
        rotation.setflags(write=False)
        object.__setattr__(self, "center", tuple(float(x) for x in center))
        object.__setattr__(self, "semi_axes", tuple(float(a) for a in semi_axes))
        object.__setattr__(self, "orientation", rotation)

    def __eq__(self, other):
        if not isinstance(other, Ellipsoid):
            return NotImplemented
        return (self.center == other.center and self.semi_axes == other.semi_axes
                and self.material == other.material and np.array_equal(self.orientation, other.orientation))

    def __hash__(self):
        return hash((self.center, self.semi_axes, self.material, self.orientation.tobytes()))

    @property
    def volume(self):
        """``4/3 pi a1 a2 a3`` [m^3]."""
        a1, a2, a3 = self.semi_axes
        return 4.0 / 3.0 * np.pi * a1 * a2 * a3

    @property
    def shape_matrix(self):
        """``A = R diag(a^2) R^T`` [m^2]: the ellipsoid is ``(x - c)^T A^-1 (x - c) <= 1``."""
        return (self.orientation * np.square(self.semi_axes)) @ self.orientation.T

    @property
    def stiffness_tensor(self):
        """Stiffness ``C_ijkl`` of the inhomogeneity in the global frame [Pa], shape (3, 3, 3, 3)."""
        return rotate_stiffness(self.material.stiffness_tensor, self.orientation)

    def _quadratic_form(self):
        """``A^-1 = R diag(1/a^2) R^T`` [1/m^2]."""
        return (self.orientation / np.square(self.semi_axes)) @ self.orientation.T

    def contains(self, points):
        """Whether each point lies inside the ellipsoid or on its surface.

        Parameters
        ----------
        points : array_like, shape (..., 3)
            Points ``(x1, x2, x3)`` [m].

        Returns
        -------
        ndarray of bool, shape (...)
        """
        points = check_finite_array(points, name="points")
        if points.ndim == 0 or points.shape[-1] != 3:
            raise ShapeError(f"points must have shape (n, 3), got {points.shape}")
        offset = points - np.asarray(self.center)
        return np.einsum("...i,ij,...j->...", offset, self._quadratic_form(), offset) <= 1.0

    def bounds(self):
        """Exact axis-aligned bounding box ``(lower, upper)``, two arrays (3,) [m].

        The half-extent along global axis ``i`` is ``sqrt(sum_k (R_ik a_k)^2) = sqrt(A_ii)``.
        """
        half = np.sqrt(np.diag(self.shape_matrix))
        center = np.asarray(self.center)
        return center - half, center + half

    def cell_fractions(self, x1, x2, x3, spacing):
        """Share of each cuboid of a lattice that lies inside the ellipsoid, and the outward normal there.

        A cuboid lies wholly inside (share 1) or wholly outside (share 0) when its centre is farther from the
        boundary than its half-diagonal can reach: ``sqrt(q(x))``, ``q(x) = (x - c)^T A^-1 (x - c)``, changes by
        at most ``|dx| / a_min`` over a step ``dx``. Each other cuboid is split into ``FRACTION_COLUMNS^2``
        columns along x3, and each column's chord through the ellipsoid (the interval where ``q <= 1``,
        a quadratic in x3) is clipped to the cuboid: the share is the mean clipped length over ``dx3``.

        Parameters
        ----------
        x1, x2, x3 : ndarray, 1-D
            Cuboid centres [m] along each axis.
        spacing : sequence of 3 float
            Cuboid sizes ``(dx1, dx2, dx3)`` [m].

        Returns
        -------
        fraction : ndarray, shape (len(x1), len(x2), len(x3))
            Volume fraction of each cuboid inside the ellipsoid, in [0, 1].
        normal : ndarray, shape (len(x1), len(x2), len(x3), 3)
            Unit outward normal of the level surface of ``q`` through each cuboid centre (``A^-1 (x - c)``
            normalised; the boundary's normal where a cuboid is cut).
        """
        spacing = np.asarray(spacing, dtype=float)
        center = np.asarray(self.center)
        form = self._quadratic_form()
        offset = np.stack(np.meshgrid(x1, x2, x3, indexing="ij"), axis=-1) - center
        gradient = offset @ form
        level = np.sqrt(np.maximum(np.einsum("...i,...i->...", offset, gradient), 0.0))
        reach = 0.5 * np.linalg.norm(spacing) / min(self.semi_axes)
        fraction = (level < 1.0).astype(float)
        cut = np.argwhere(np.abs(level - 1.0) <= reach * (1.0 + 1e-9))
        if len(cut):
            columns = (np.arange(FRACTION_COLUMNS) + 0.5) / FRACTION_COLUMNS - 0.5
            u1, u2 = (values.ravel() for values in np.meshgrid(columns * spacing[0], columns * spacing[1],
                                                                indexing="ij"))
            base = offset[tuple(cut.T)]                                     # (m, 3)
            p1, p2 = base[:, :1] + u1, base[:, 1:2] + u2                    # (m, columns^2)
            # q = form33 t^2 + 2 b t + c <= 1 along the column, t = x3 - c3
            b = form[0, 2] * p1 + form[1, 2] * p2
            c = form[0, 0] * p1 ** 2 + 2.0 * form[0, 1] * p1 * p2 + form[1, 1] * p2 ** 2 - 1.0
            discriminant = b * b - form[2, 2] * c
            root = np.sqrt(np.maximum(discriminant, 0.0))
            low, high = (-b - root) / form[2, 2], (-b + root) / form[2, 2]
            bottom, top = base[:, 2:3] - 0.5 * spacing[2], base[:, 2:3] + 0.5 * spacing[2]
            clipped = np.clip(np.minimum(high, top) - np.maximum(low, bottom), 0.0, None)
            length = np.where(discriminant > 0.0, clipped, 0.0)
            fraction[tuple(cut.T)] = np.clip(length.mean(axis=1) / spacing[2], 0.0, 1.0)
        size = np.linalg.norm(gradient, axis=-1, keepdims=True)
        normal = np.divide(gradient, size, out=np.zeros_like(gradient), where=size > 0.0)
        return fraction, normal


def contact_function(first, second):
    """Perram & Wertheim (1985) contact function of two ellipsoids.

    ``F = max over lambda in [0, 1] of lambda (1 - lambda) r^T [(1 - lambda) A + lambda B]^-1 r``,
    ``r`` the vector between the centres, ``A``, ``B`` the shape matrices ``R diag(a^2) R^T``. The
    ellipsoids are disjoint iff ``F > 1``, touch at ``F = 1`` and overlap below. ``F`` is
    evaluated in the frame where ``A = I`` and ``B`` is diagonal, where it is a sum of three
    rational terms in ``lambda``.

    Parameters
    ----------
    first, second : Ellipsoid

    Returns
    -------
    float
        ``F`` (dimensionless); ``(|r| / (a + b))^2`` for two spheres of radii ``a``, ``b``.
    """
    factor = np.linalg.cholesky(first.shape_matrix)  # A = L L^T
    whitened = np.linalg.solve(factor, np.linalg.solve(factor, second.shape_matrix).T)  # L^-1 B L^-T
    scales, basis = np.linalg.eigh(0.5 * (whitened + whitened.T))
    weights = np.square(basis.T @ np.linalg.solve(factor, np.subtract(second.center, first.center)))

    def negative(lam):
        return -lam * (1.0 - lam) * np.sum(weights / (1.0 - lam + lam * scales))

    best = minimize_scalar(negative, bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-12})
    return float(-best.fun)


def _lattice_axes(x1, x2, x3):
    """The lattice's coordinates [m] as three finite, strictly increasing 1-D arrays (named in the errors)."""
    axes = []
    for name, values in (("x1", x1), ("x2", x2), ("x3", x3)):
        values = check_finite_array(values, name=name, ndim=1)
        if np.any(np.diff(values) <= 0.0):
            raise ParameterError(f"{name} must be strictly increasing, got {values.tolist()!r}")
        axes.append(values)
    return axes


@dataclass(frozen=True)
class InclusionSet(Sequence):
    """Any number of non-overlapping ellipsoidal inhomogeneities (a sequence of :class:`Ellipsoid`).

    Parameters
    ----------
    inclusions : sequence of Ellipsoid
        The inhomogeneities; may be empty (no inhomogeneity). Ellipsoids that overlap or touch
        (Perram-Wertheim contact function at most ``1 +`` :data:`TOUCH_TOLERANCE`) are refused.
    """

    inclusions: tuple = ()

    def __post_init__(self):
        if isinstance(self.inclusions, Ellipsoid) or isinstance(self.inclusions, (str, bytes)) \
                or not hasattr(self.inclusions, "__iter__"):
            raise ParameterError(f"inclusions must be a list of inclusions.Ellipsoid, "
                                 f"got {type(self.inclusions).__name__}")
        inclusions = tuple(self.inclusions)
        for i, body in enumerate(inclusions):
            if not isinstance(body, Ellipsoid):
                raise ParameterError(f"inclusions[{i}] must be an inclusions.Ellipsoid, got {type(body).__name__}")
        object.__setattr__(self, "inclusions", inclusions)
        self._check_disjoint()

    def _check_disjoint(self):
        """Raise for the first pair that overlaps or touches.

        Only pairs whose bounding spheres (radius: the longest semi-axis) meet, found by a k-d tree of the centres,
        and whose bounding boxes meet reach the contact function: hundreds of bodies cost about as many contact
        functions as they have neighbours, not ``N^2 / 2``.
        """
        if len(self.inclusions) < 2:
            return
        centers = np.array([body.center for body in self.inclusions])
        reach = np.array([max(body.semi_axes) for body in self.inclusions])
        boxes = [body.bounds() for body in self.inclusions]
        # pairs closer than the two largest bounding spheres, in index order: the first overlap found is reported
        pairs = sorted(cKDTree(centers).query_pairs(2.0 * reach.max() * (1.0 + 1e-9)))
        for i, j in pairs:
            distance = np.linalg.norm(centers[j] - centers[i])
            if distance > (reach[i] + reach[j]) * (1.0 + 1e-9):
                continue
            (low_i, high_i), (low_j, high_j) = boxes[i], boxes[j]
            if np.any(high_i < low_j) or np.any(high_j < low_i):
                continue
            value = contact_function(self.inclusions[i], self.inclusions[j])
            if value <= 1.0 + TOUCH_TOLERANCE:
                raise InclusionError(
                    f"inclusions[{i}] and inclusions[{j}] overlap or touch (Perram-Wertheim contact "
                    f"function F = {value:.12g}); expected F > 1: move them apart or make them smaller")

    def __len__(self):
        return len(self.inclusions)

    def __getitem__(self, index):
        return self.inclusions[index]

    def bounds(self):
        """Axis-aligned box ``(lower, upper)`` [m] around every inclusion; None for an empty set."""
        if not self.inclusions:
            return None
        boxes = [body.bounds() for body in self.inclusions]
        return np.min([low for low, _ in boxes], axis=0), np.max([high for _, high in boxes], axis=0)

    def indicator(self, x1, x2, x3):
        """Which inclusion holds each point of a lattice.

        Parameters
        ----------
        x1, x2, x3 : array_like, 1-D, increasing
            Lattice coordinates [m] (cuboid centres: ``grid.x1, grid.x2, grid.x3``).

        Returns
        -------
        ndarray of int, shape (len(x1), len(x2), len(x3))
            0 in the matrix, ``k + 1`` inside (or on the surface of) the ``k``-th inclusion; the
            smallest signed integer type that holds ``len(self)``.
        """
        axes = _lattice_axes(x1, x2, x3)
        dtype = next(t for t in (np.int8, np.int16, np.int32) if len(self) <= np.iinfo(t).max)
        field_ = np.zeros(tuple(len(values) for values in axes), dtype=dtype)
        for k, body in enumerate(self.inclusions):
            lower, upper = body.bounds()
            window, offsets = [], []
            for values, low, high, c in zip(axes, lower, upper, body.center):
                start, stop = np.searchsorted(values, low, "left"), np.searchsorted(values, high, "right")
                window.append(slice(start, stop))
                offsets.append(values[start:stop] - c)
            if any(s.start >= s.stop for s in window):
                continue
            form = body._quadratic_form()
            d = [offsets[0][:, None, None], offsets[1][None, :, None], offsets[2][None, None, :]]
            quadratic = sum(form[i, i] * d[i] ** 2 for i in range(3)) \
                + 2.0 * (form[0, 1] * d[0] * d[1] + form[0, 2] * d[0] * d[2] + form[1, 2] * d[1] * d[2])
            block = field_[tuple(window)]
            block[quadratic <= 1.0] = k + 1
        return field_

    def fractions(self, x1, x2, x3, spacing):
        """Share of each cuboid of a lattice inside the inclusions (:meth:`Ellipsoid.cell_fractions`).

        Parameters
        ----------
        x1, x2, x3 : array_like, 1-D, increasing
            Cuboid centres [m] (``grid.x1, grid.x2, grid.x3`` or a box of them).
        spacing : sequence of 3 float
            Cuboid sizes ``(dx1, dx2, dx3)`` [m].

        Returns
        -------
        fraction : ndarray of float, shape (len(x1), len(x2), len(x3))
            Volume fraction inside the inclusion ``owner`` names.
        owner : ndarray of int, shape (len(x1), len(x2), len(x3))
            0 where no inclusion reaches, else ``k + 1`` for the ``k``-th inclusion; a cuboid that two inclusions
            share (they pass within a cuboid of each other) goes to the one with the larger share, and the other's
            share there is dropped.
        normal : ndarray, shape (len(x1), len(x2), len(x3), 3)
            The owner's unit outward normal at the cuboid (:meth:`Ellipsoid.cell_fractions`).
        """
        axes = _lattice_axes(x1, x2, x3)
        spacing = check_finite_array(spacing, name="spacing", shape=(3,))
        if np.any(spacing <= 0.0):
            raise ParameterError(f"spacing must hold three cuboid sizes > 0 [m], got {spacing.tolist()!r}")
        shape = tuple(len(values) for values in axes)
        fraction, owner, normal = np.zeros(shape), np.zeros(shape, dtype=np.int32), np.zeros((*shape, 3))
        for k, body in enumerate(self.inclusions):
            lower, upper = body.bounds()
            window = tuple(slice(np.searchsorted(values, low - h / 2, "left"),
                                 np.searchsorted(values, high + h / 2, "right"))
                           for values, low, high, h in zip(axes, lower, upper, spacing))
            if any(s.start >= s.stop for s in window):
                continue
            share, direction = body.cell_fractions(*(values[s] for values, s in zip(axes, window)), spacing)
            larger = share > fraction[window]
            fraction[window] = np.where(larger, share, fraction[window])
            owner[window] = np.where(larger, k + 1, owner[window])
            normal[window] = np.where(larger[..., None], direction, normal[window])
        return fraction, owner, normal

    def check_inside(self, grid):
        """Raise :class:`~framework.errors.InclusionError` unless every inclusion is well placed on ``grid``.

        Each inclusion must lie strictly below the surface, inside the subsurface box
        (``|x1| <= L1/2``, ``|x2| <= L2/2``, ``x3 <= grid.depth``) and be resolved by at least
        :data:`MIN_CELLS_PER_SEMI_AXIS` cuboids along each semi-axis direction ``d``, counted as
        ``a_k / sqrt(sum_i (d_i h_i)^2)`` with ``h = (dx1, dx2, dx3)``. The grid must have layers and
        be open (the half-space eigenstrain operator is not periodic). An empty set passes any grid.

        Parameters
        ----------
        grid : framework.Grid
        """
        if not isinstance(grid, Grid):
            raise ParameterError(f"grid must be a framework.Grid, got {type(grid).__name__}")
        if not self.inclusions:
            return
        if any(grid.periodic):
            raise InclusionError(f"grid.periodic = {grid.periodic}: inclusions need an open grid (the half-space "
                                 f"eigenstrain operator is not periodic); expected periodic = (False, False)")
        if grid.layers == 0:
            raise InclusionError("grid.layers = 0: inclusions need subsurface layers; expected layers > 0 "
                                 "and a depth [m] that holds them")
        half_size = 0.5 * np.asarray(grid.size)
        spacing = np.array([*grid.spacing, grid.layer_thickness])
        for k, body in enumerate(self.inclusions):
            lower, upper = body.bounds()
            if lower[2] <= 0.0:
                raise InclusionError(
                    f"inclusions[{k}] cuts the surface: its top lies at x3 = {lower[2]:.6g} m (center[2] = "
                    f"{body.center[2]:.6g} m, half-extent along x3 {body.center[2] - lower[2]:.6g} m); "
                    f"expected x3 > 0: move it deeper or make it smaller")
            if upper[2] > grid.depth:
                raise InclusionError(
                    f"inclusions[{k}] leaves the subsurface box: its bottom lies at x3 = {upper[2]:.6g} m, "
                    f"deeper than grid.depth = {grid.depth:.6g} m; expected at most grid.depth")
            for i in (0, 1):
                if lower[i] < -half_size[i] or upper[i] > half_size[i]:
                    raise InclusionError(
                        f"inclusions[{k}] leaves the subsurface box along x{i + 1}: it spans "
                        f"[{lower[i]:.6g}, {upper[i]:.6g}] m, the grid [{-half_size[i]:.6g}, {half_size[i]:.6g}] m; "
                        f"expected inside: enlarge grid.size[{i}] or move it")
            cells = np.asarray(body.semi_axes) / np.sqrt(np.square(spacing[:, None] * body.orientation).sum(axis=0))
            for axis in range(3):
                # a semi-axis of exactly 3 cells comes out 2.9999999999999996 (a quotient of rounded sizes): the
                # tolerance forgives rounding, and the count is printed to enough digits to show any refused
                # value (below 3 (1 - 1e-9)) below 3
                if cells[axis] < MIN_CELLS_PER_SEMI_AXIS * (1.0 - CELLS_TOLERANCE):
                    raise InclusionError(
                        f"inclusions[{k}]: semi_axes[{axis}] = {body.semi_axes[axis]:.6g} m spans only "
                        f"{cells[axis]:.12g} cuboids along its direction "
                        f"{np.round(body.orientation[:, axis], 6).tolist()} "
                        f"(cuboids {spacing[0]:.3g} x {spacing[1]:.3g} x {spacing[2]:.3g} m); expected at least "
                        f"{MIN_CELLS_PER_SEMI_AXIS}: refine the grid or enlarge the inclusion")
