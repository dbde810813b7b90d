"""Rigid indenter bodies, each a height ``h(x1, x2) >= 0`` above its lowest point.

The axis of an axisymmetric body passes through the origin of the grid; the
height is the separation from the undeformed flat surface when the body just
touches it. Bodies with vertical walls (flat punches) use a wall as high as
``WALL`` times the larger grid side, far above any small-strain displacement.
Radii lie between 1e-12 and 1e6 m and heights within +/-1e6 m
(``framework._validation.LIMITS``).
"""
from dataclasses import dataclass, field

import numpy as np

from ._validation import LIMITS, check_bool, check_finite_array, check_quantity
from .errors import ParameterError, ShapeError

WALL = 1.0


class Indenter:
    """Base class: subclasses define :meth:`height`."""

    def height(self, x1, x2):  # pragma: no cover - interface
        """Height [m] of the body above the undeformed surface at ``(x1, x2)`` [m]."""
        raise NotImplementedError

    def reach(self, grid):
        """Cells the body can touch at all (all of them but for a punch's walls)."""
        return np.ones(grid.shape, bool)

    def slopes(self, x1, x2):
        """Slopes ``(dh/dx1, dh/dx2)`` [-] of the body at ``(x1, x2)`` [m]; None where only the grid can tell."""
        return None

    def slopes_on_grid(self, grid):
        """Slopes ``(dh/dx1, dh/dx2)`` on the cells of ``grid``: the body's own, else central differences.

        They give the rolling resistance ``F_t = sum p (grad h . m) dA`` of a
        body moving along ``m`` (THEORY.md sec. 7).
        """
        x1, x2 = grid.coordinates()
        exact = self.slopes(x1, x2)
        if exact is not None:
            return tuple(np.broadcast_to(np.asarray(s, dtype=float), grid.shape) for s in exact)
        heights = self.on_grid(grid)
        return tuple(np.gradient(heights, spacing, axis=axis) if n > 1 else np.zeros(grid.shape)
                     for axis, (spacing, n) in enumerate(zip(grid.spacing, grid.shape)))

    def on_grid(self, grid):
        """Height on the cells of ``grid`` [m], checked finite and within the lengths of ``LIMITS``."""
        x1, x2 = grid.coordinates()
        name = f"{type(self).__name__} height"
        heights = check_finite_array(self.height(x1, x2), name=name, shape=grid.shape)
        largest = LIMITS["m"][1]
        if np.abs(heights).max() > largest:
            bad = np.unravel_index(np.argmax(np.abs(heights)), heights.shape)
            raise ParameterError(f"{name} must lie within +/-{largest:g} m, got {float(heights[bad])!r} at index "
                                 f"{tuple(int(i) for i in bad)}")
        return heights


def _wall(x1, x2):
    return WALL * max(np.ptp(x1), np.ptp(x2), np.finfo(float).tiny) + 0.0 * x1


@dataclass(frozen=True)
class Sphere(Indenter):
    """Rigid sphere.

    Parameters
    ----------
    radius : float
        Sphere radius [m].
    exact : bool
        False (default): the paraboloid ``r^2 / (2 R)`` of Hertz theory.
        True: the exact sphere ``R - sqrt(R^2 - r^2)`` (height ``R`` beyond ``r = R``).
    """

    radius: float
    exact: bool = False

    def __post_init__(self):
        object.__setattr__(self, "radius", check_quantity(self.radius, name="radius", unit="m"))
        object.__setattr__(self, "exact", check_bool(self.exact, name="exact"))

    def height(self, x1, x2):
        r2 = np.asarray(x1) ** 2 + np.asarray(x2) ** 2
        if not self.exact:
            return r2 / (2 * self.radius)
        return self.radius - np.sqrt(np.maximum(self.radius**2 - r2, 0.0))

    def slopes(self, x1, x2):
        x1, x2 = np.asarray(x1, dtype=float), np.asarray(x2, dtype=float)
        if not self.exact:
            return x1 / self.radius, x2 / self.radius
        # the exact sphere's slope r / sqrt(R^2 - r^2), vertical (bounded here) where it ends at r = R
        root = np.sqrt(np.maximum(self.radius**2 - x1**2 - x2**2, (1e-6 * self.radius) ** 2))
        return x1 / root, x2 / root


@dataclass(frozen=True)
class FlatPunch(Indenter):
    """Rigid flat-ended cylindrical punch with a sharp edge.

    Parameters
    ----------
    radius : float
        Punch radius [m].
    """

    radius: float

    def __post_init__(self):
        object.__setattr__(self, "radius", check_quantity(self.radius, name="radius", unit="m"))

    def height(self, x1, x2):
        r = np.hypot(x1, x2)
        return np.where(r <= self.radius, 0.0, _wall(x1, x2))

    def reach(self, grid):
        return np.hypot(*grid.coordinates()) <= self.radius

    def slopes(self, x1, x2):  # the face is flat; the walls carry no pressure
        zero = np.zeros(np.broadcast_shapes(np.shape(x1), np.shape(x2)))
        return zero, zero


@dataclass(frozen=True)
class RoundedFlatPunch(Indenter):
    """Flat punch with a rounded edge (Ciavarella 1999; seed 001 eq. 5).

    ``h = 0`` for ``r <= flat_radius`` and ``(r - flat_radius)^2 / (2 edge_radius)`` beyond.

    Parameters
    ----------
    flat_radius : float
        Radius ``b`` of the flat face [m] (0 gives a sphere of radius ``edge_radius``).
    edge_radius : float
        Radius of curvature ``Rc`` of the rounded edge [m].
    """

    flat_radius: float
    edge_radius: float

    def __post_init__(self):
        object.__setattr__(self, "flat_radius",
                           check_quantity(self.flat_radius, name="flat_radius", unit="m", zero=True))
        object.__setattr__(self, "edge_radius", check_quantity(self.edge_radius, name="edge_radius", unit="m"))

    def height(self, x1, x2):
        excess = np.maximum(np.hypot(x1, x2) - self.flat_radius, 0.0)
        return excess**2 / (2 * self.edge_radius)

    def slopes(self, x1, x2):
        r = np.hypot(x1, x2)
        excess = np.maximum(r - self.flat_radius, 0.0)
        scale = np.divide(excess, self.edge_radius * r, out=np.zeros(np.shape(r)), where=r > 0)
        return scale * x1, scale * x2


@dataclass(frozen=True)
class Cylinder(Indenter):
    """Rigid cylinder lying on the surface (parabolic profile across its axis).

    Parameters
    ----------
    radius : float
        Cylinder radius [m].
    axis : int
        Surface axis the cylinder lies along: 0 (x1) or 1 (x2).
    """

    radius: float
    axis: int = 1

    def __post_init__(self):
        object.__setattr__(self, "radius", check_quantity(self.radius, name="radius", unit="m"))
        if not isinstance(self.axis, (int, np.integer)) or isinstance(self.axis, bool) or self.axis not in (0, 1):
            raise ParameterError(f"axis must be 0 (along x1) or 1 (along x2), got {self.axis!r}")
        object.__setattr__(self, "axis", int(self.axis))

    def height(self, x1, x2):
        across = np.asarray(x2 if self.axis == 0 else x1)
        return across**2 / (2 * self.radius)

    def slopes(self, x1, x2):
        zero = np.zeros(np.broadcast_shapes(np.shape(x1), np.shape(x2)))
        if self.axis == 0:
            return zero, np.asarray(x2) / self.radius + zero
        return np.asarray(x1) / self.radius + zero, zero


@dataclass(frozen=True)
class HeightMap(Indenter):
    """Rigid body of any shape, from an array on the grid or a function.

    Parameters
    ----------
    heights : ndarray or callable
        Heights [m] on the grid's cells (shape ``(n1, n2)``), or a function
        ``heights(x1, x2)`` of the cell-centre coordinates [m]. Heights are used
        as given: the approach is measured from their zero level.
    """

    heights: object = field(repr=False)

    def __post_init__(self):
        if not callable(self.heights):
            object.__setattr__(self, "heights_array",
                               check_finite_array(self.heights, name="heights", ndim=2))

    def height(self, x1, x2):
        if callable(self.heights):
            return np.asarray(self.heights(x1, x2))  # on_grid converts it, saying what was wrong
        if np.shape(x1) != self.heights_array.shape:
            raise ShapeError(f"heights has shape {self.heights_array.shape}, the grid has shape {np.shape(x1)}")
        return self.heights_array

