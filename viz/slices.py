"""Subsurface slices: which plane a ``kind="slice"`` picture shows, its stresses and its mesh.

The stresses are known at the cuboid centres. A slice at ``plane = origin``
shows the stresses interpolated linearly between the two layers of cells
whose centres bracket the plane, along its normal (the stress tensor is
interpolated, von Mises and the other measures are taken of it): exact when
the plane passes through cell centres, and on an even grid the plane
``x2 = 0`` is the plane ``x2 = 0``, not the nearest row of centres half a
cell away. Beyond the outermost centres (the last half cell) the outermost
cells are shown and the picture names their plane. The clipped 3-D view
(``clip=True``) shows whole cells, from the cell holding the plane on.
"""
import numbers
from dataclasses import dataclass

import numpy as np

from framework.errors import ParameterError

from . import _deps, meshes


@dataclass(frozen=True)
class Plane:
    """Where a slice lies: between the cell centres ``first`` and ``second`` along the normal.

    Attributes
    ----------
    axis : int
        The grid axis of the normal (0 for ``"x1"``, 1 for ``"x2"``).
    first, second : int
        Indices of the two layers of cells whose centres bracket the plane
        (equal when it passes through centres, or lies beyond the outermost).
    weight : float
        Share of ``second`` in the interpolated values, in ``[0, 1)``.
    position : float
        The plane the values belong to [m]: ``origin``, or the outermost
        centres when ``origin`` lies beyond them.
    """

    axis: int
    first: int
    second: int
    weight: float
    position: float


def plane_axis(plane):
    """Grid axis of a slice normal: 0 for ``"x1"``, 1 for ``"x2"``."""
    return 1 if plane == "x2" else 0


def centres(grid, plane):
    """Cell centres [m] along a slice normal."""
    return np.asarray(grid.x2 if plane == "x2" else grid.x1, dtype=float)


def corners(grid, plane):
    """Cell corners [m] along a slice normal."""
    return meshes.corner_coordinates(grid)[plane_axis(plane)]


def plane_index(grid, plane, origin):
    """Index of the cell holding the plane ``plane = origin``, or ParameterError when it is off the grid."""
    axis = plane_axis(plane)
    half = grid.size[axis] / 2
    if not (isinstance(origin, numbers.Real) and not isinstance(origin, bool) and np.isfinite(origin)) \
            or abs(origin) > half:
        raise ParameterError(f"origin of the {plane} slice must lie in [-{half:g}, {half:g}] m, got {origin!r}")
    return int(np.clip(np.floor((origin + half) / grid.spacing[axis]), 0, grid.shape[axis] - 1))


def locate(grid, plane, origin):
    """The :class:`Plane` of a slice at ``plane = origin`` [m] (checked like :func:`plane_index`)."""
    plane_index(grid, plane, origin)
    axis, c = plane_axis(plane), centres(grid, plane)
    if origin <= c[0] or origin >= c[-1]:
        end = 0 if origin <= c[0] else c.size - 1
        return Plane(axis, end, end, 0.0, float(c[end]))
    first = int(np.searchsorted(c, origin, side="right")) - 1
    weight = float((origin - c[first]) / (c[first + 1] - c[first]))
    if weight < 1e-9:  # on a row of centres (round-off): exactly those values
        return Plane(axis, first, first, 0.0, float(origin))
    if weight > 1 - 1e-9:
        return Plane(axis, first + 1, first + 1, 0.0, float(origin))
    return Plane(axis, first, first + 1, weight, float(origin))


def plane_stress(result, k, where):
    """Stress of step ``k`` in the plane ``where`` (a :class:`Plane`): ``(along, layers, 6)`` Voigt [Pa]."""
    stress = np.asarray(result.stress(k), dtype=float)
    first, second = np.take(stress, where.first, axis=where.axis), np.take(stress, where.second, axis=where.axis)
    return first if where.second == where.first else (1.0 - where.weight) * first + where.weight * second


def quads(points):
    """Quad mesh from a structured ``(a + 1, b + 1, 3)`` point array (cell id ``i + a * j``)."""
    pv = _deps.pyvista(rendering=True)
    a, b = points.shape[0] - 1, points.shape[1] - 1
    flat = np.ascontiguousarray(points.transpose(1, 0, 2)).reshape(-1, 3)
    i, j = (x.ravel(order="F") for x in np.meshgrid(np.arange(a), np.arange(b), indexing="ij"))

    def p(u, v):
        return u + (a + 1) * v

    cells = np.column_stack([np.full(i.size, 4), p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)]).ravel()
    return pv.UnstructuredGrid(cells, np.full(i.size, meshes.VTK_QUAD, dtype=np.uint8), flat)


def slice_mesh(grid, values, plane, position):
    """Quads in the plane ``plane = position`` [m]: (along, depth) cells coloured by ``values`` ``(along, layers)``."""
    c1, c2 = meshes.corner_coordinates(grid)
    z = -meshes.layer_boundaries(grid)
    a, zz = np.meshgrid(c1 if plane == "x2" else c2, z, indexing="ij")
    if plane == "x2":
        points = np.stack([a, np.full_like(a, position), zz], axis=-1)
    else:
        points = np.stack([np.full_like(a, position), a, zz], axis=-1)
    mesh = quads(points)
    mesh.cell_data["values"] = meshes.cell_order(values)
    return mesh


def clipped_mesh(grid, values, plane, index):
    """Hexahedra of the cells from ``index`` on along the normal, coloured by ``values`` (their block of cells)."""
    mesh = meshes.hexahedron_mesh(grid)
    n1, n2 = grid.shape
    ids = np.arange(mesh.n_cells)
    along = (ids // n1) % n2 if plane == "x2" else ids % n1
    mesh = mesh.extract_cells(ids[along >= index])  # ascending ids: the cell order of the kept block
    mesh.cell_data["values"] = meshes.cell_order(values)
    return mesh
