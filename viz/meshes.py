"""VTK meshes of a result: the surface, the subsurface layers, the indenter.

Geometry (the ParaView convention): ``x = x1``, ``y = x2`` and ``z`` pointing UP
out of the solid, so the solid occupies ``z <= 0``, the layer centres lie at
``z = -x3`` and the deformed surface at ``z = -u3``. Lengths in metres. The
surface and volume meshes are undeformed; the surface carries the point vector
``displacement_vector`` ``(0, 0, -u3)`` for ParaView's Warp By Vector.

Ordering: points and cells are numbered like a VTK structured grid, x1 fastest,
then x2, then (for the volume) the layers from the surface down:

* surface cell ``(i, j)`` has id ``i + n1 * j``, i.e. a ``(n1, n2)`` field
  ``f`` is written as ``f.ravel(order="F")`` and read back with
  ``array.reshape((n1, n2), order="F")``;
* volume cell ``(i, j, k)`` (layer ``k``, 0 at the top) has id
  ``i + n1 * (j + n2 * k)``; :func:`cell_order` and :func:`grid_order` convert.

Stress components are given in the exported frame ``(x, y, z) = (x1, x2, -x3)``:
``xx``, ``yy``, ``zz`` and ``xy`` equal the framework's components, while
``yz = -sigma_23`` and ``xz = -sigma_13`` (the framework's x3 points down).
Invariants, principal stresses, von Mises and Tresca do not depend on this.

Frame: the grid moves with the body (a rolling run works in the body's frame,
centred on its axis), and so do the meshes built here. The exported files
are translated to the material frame by :func:`to_material_frame`, i.e. by
the body's ``result.position`` (0 at rest and for steady runs), so that in
ParaView a rolling body and its contact travel over the material; the fields
on the mesh are those of the cells under the body at that step.

Tensor order: 6-component symmetric tensors (``stress``, ``eigenstrain``) are
written in VTK's order ``XX YY ZZ XY YZ XZ`` (:data:`TENSOR_ORDER`), the order
ParaView and VTK's tensor filters read, NOT the framework's Voigt order ``xx yy
zz yz xz xy`` of :meth:`framework.Result.stress`; :func:`vtk_tensor` converts.
"""
import json

import numpy as np

from framework.errors import ParameterError
from framework.result import von_mises as _von_mises

from . import _deps

VTK_QUAD = 9
VTK_HEXAHEDRON = 12

#: Components of a 6-component symmetric tensor in the files: VTK's order (exported frame, z up).
TENSOR_ORDER = ("xx", "yy", "zz", "xy", "yz", "xz")

#: Names of the per-component stress arrays, in :data:`TENSOR_ORDER`.
STRESS_COMPONENTS = tuple("stress_" + c for c in TENSOR_ORDER)

#: Framework Voigt index (``xx yy zz yz xz xy``, x3 down) of each component of :data:`TENSOR_ORDER`.
VOIGT_INDEX = (0, 1, 2, 5, 3, 4)

#: Sign of each component of :data:`TENSOR_ORDER` going from x3 down to z up (``yz`` and ``xz`` flip).
FRAME_SIGN = np.array([1.0, 1.0, 1.0, 1.0, -1.0, -1.0])


def vtk_tensor(voigt):
    """Framework Voigt tensors to the exported ones: VTK order ``XX YY ZZ XY YZ XZ``, frame z up.

    Parameters
    ----------
    voigt : array_like
        ``(..., 6)`` components ``xx yy zz yz xz xy`` in the framework's frame
        (x3 pointing down), e.g. :meth:`framework.Result.stress` [Pa].

    Returns
    -------
    ndarray
        ``(..., 6)`` components ``xx yy zz xy yz xz`` in the frame
        ``(x1, x2, -x3)``, as written to the files (:data:`TENSOR_ORDER`).
    """
    return np.asarray(voigt, dtype=float)[..., list(VOIGT_INDEX)] * FRAME_SIGN


def step_index(result, step):
    """Non-negative index of ``step`` (negative counts from the end) or ParameterError.

    Parameters
    ----------
    result : framework.Result
        The run.
    step : int
        Step index in ``[-len(result), len(result))``.

    Returns
    -------
    int
        The index in ``[0, len(result))``.
    """
    n = len(result)
    if not isinstance(step, (int, np.integer)) or isinstance(step, bool) or not -n <= step < n:
        raise ParameterError(f"step must be an integer index in [-{n}, {n}) (the result has {n} steps), "
                             f"got {step!r}")
    return int(step) % n


def cell_order(field, spatial=None):
    """Flatten a cell field ``(n1, n2[, layers][, components])`` to VTK cell order.

    Parameters
    ----------
    field : ndarray
        Per-cell values with the spatial axes first: ``(n1, n2)`` or
        ``(n1, n2, layers)``, optionally followed by component axes.
    spatial : int, optional
        How many leading axes are spatial (2 or 3); all of them by default.

    Returns
    -------
    ndarray
        ``(n_cells,)`` or ``(n_cells, components)``, x1 fastest.
    """
    field = np.asarray(field)
    return _cell_order(field, field.ndim if spatial is None else spatial)


def _cell_order(field, spatial):
    axes = tuple(range(spatial))[::-1] + tuple(range(spatial, field.ndim))
    out = np.transpose(field, axes)
    return out.reshape((-1,) + field.shape[spatial:])


def grid_order(array, shape):
    """Inverse of :func:`cell_order`: VTK cell order back to ``shape`` (spatial axes first).

    Parameters
    ----------
    array : array_like
        ``(n_cells,)`` or ``(n_cells, components)`` values as read from a file.
    shape : tuple of int
        Spatial shape, ``(n1, n2)`` or ``(n1, n2, layers)``.

    Returns
    -------
    ndarray
        ``shape + (components,)`` (no component axis for scalars).
    """
    array = np.asarray(array)
    rest = array.shape[1:]
    out = array.reshape(tuple(shape)[::-1] + rest)
    return np.transpose(out, tuple(range(len(shape)))[::-1] + tuple(range(len(shape), out.ndim)))


def corner_average(field, periodic=(False, False)):
    """Values at the cell corners, the mean of the (up to four) adjacent cells.

    Parameters
    ----------
    field : ndarray
        ``(n1, n2)`` cell values.
    periodic : tuple of bool
        Per axis: wrap around (the corners on the two edges then agree) or
        average only the cells that exist (edge padding).

    Returns
    -------
    ndarray
        ``(n1 + 1, n2 + 1)`` corner values.
    """
    f = np.asarray(field, dtype=float)
    f = np.pad(f, ((1, 1), (0, 0)), mode="wrap" if periodic[0] else "edge")
    f = np.pad(f, ((0, 0), (1, 1)), mode="wrap" if periodic[1] else "edge")
    return 0.25 * (f[:-1, :-1] + f[1:, :-1] + f[:-1, 1:] + f[1:, 1:])


def corner_coordinates(grid):
    """Corner coordinates ``(c1, c2)`` [m] of the surface cells: ``n1 + 1`` and ``n2 + 1`` values."""
    return (np.linspace(-grid.size[0] / 2, grid.size[0] / 2, grid.shape[0] + 1),
            np.linspace(-grid.size[1] / 2, grid.size[1] / 2, grid.shape[1] + 1))


def layer_boundaries(grid):
    """Depths [m] of the layer boundaries, ``0 .. depth`` (``layers + 1`` values)."""
    return np.linspace(0.0, grid.depth, grid.layers + 1)


def stress_measures(stress):
    """Derived stress measures of Voigt stresses ``(..., 6)`` [Pa].

    Parameters
    ----------
    stress : ndarray
        Voigt ``xx yy zz yz xz xy`` [Pa], the framework's order (either
        frame: the measures do not change when ``yz`` and ``xz`` flip sign).

    Returns
    -------
    dict
        ``von_mises`` (...), ``tresca`` (...) the largest principal
        difference, ``principal_stress`` (..., 3) sorted descending (from
        :func:`numpy.linalg.eigvalsh` on the 3x3 tensors) [Pa].
    """
    s = np.asarray(stress, dtype=float)
    tensor = np.empty(s.shape[:-1] + (3, 3))
    for (a, b), c in zip(((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)), range(6)):
        tensor[..., a, b] = tensor[..., b, a] = s[..., c]
    principal = np.linalg.eigvalsh(tensor)[..., ::-1]
    return {"von_mises": _von_mises(s), "tresca": principal[..., 0] - principal[..., 2],
            "principal_stress": np.ascontiguousarray(principal)}


def encode_text(text):
    """UTF-8 bytes of ``text`` as a uint8 array: field data meshio can read (ParaView shows it as numbers)."""
    return np.frombuffer(text.encode("utf-8"), dtype=np.uint8).copy()


def decode_text(array):
    """Text stored by :func:`add_text` or :func:`encode_text` (a VTK string array as read by pyvista, or uint8)."""
    array = np.asarray(array)
    if array.dtype.kind in "US" or array.dtype == object:
        return str(array.ravel()[0]) if array.size == 1 else "".join(str(a) for a in array.ravel())
    return bytes(array.astype(np.uint8).ravel()).decode("utf-8")


def add_text(mesh, name, text, strings=True):
    """Store ``text`` as the field data ``name`` of ``mesh``.

    Parameters
    ----------
    mesh : pyvista.DataSet
        The mesh to write.
    name, text : str
        Array name and its text (UTF-8).
    strings : bool
        True: a one-value ``vtkStringArray``, written as ``<Array
        type="String">``, which ParaView's spreadsheet and information panel
        show as text. False: the UTF-8 bytes as a uint8 array
        (:func:`encode_text`), for readers that refuse string arrays (meshio
        5.3 refuses the whole file).
    """
    if not strings:
        mesh.field_data[name] = encode_text(text)
        return mesh
    array = _deps.require("vtkmodules.vtkCommonCore").vtkStringArray()
    array.SetName(name)
    array.InsertNextValue(text)
    mesh.GetFieldData().RemoveArray(name)
    mesh.GetFieldData().AddArray(array)
    return mesh


def configuration_json(result):
    """``result.configuration()`` as a JSON string (non-finite numbers written as NaN/Infinity)."""
    return json.dumps(result.configuration(), default=_plain)


def _plain(obj):
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    return repr(obj)


def attach_metadata(mesh, result, step, configuration=None, strings=True):
    """Add the field data every exported file carries.

    ``framework_version`` and ``configuration`` (JSON of
    ``result.configuration()``) as text (:func:`add_text`: VTK string arrays,
    or with ``strings=False`` UTF-8 uint8 arrays; :func:`decode_text` reads
    both), ``time`` [s] and ``TimeValue`` [s] (the name ParaView looks for),
    ``step`` (index into the result).
    """
    k = step_index(result, step)
    add_text(mesh, "framework_version", str(result.version), strings)
    add_text(mesh, "configuration", configuration or configuration_json(result), strings)
    mesh.field_data["time"] = np.array([result.times[k]], dtype=float)
    mesh.field_data["TimeValue"] = np.array([result.times[k]], dtype=float)
    mesh.field_data["step"] = np.array([k], dtype=np.int64)
    return mesh


def _unstructured(points, connectivity, cell_type):
    pv = _deps.pyvista()
    n, per = connectivity.shape
    cells = np.hstack([np.full((n, 1), per, dtype=np.int64), connectivity.astype(np.int64)]).ravel()
    return pv.UnstructuredGrid(cells, np.full(n, cell_type, dtype=np.uint8), np.asarray(points, dtype=float))


def quad_mesh(grid, z_corners):
    """Quad mesh of the surface cells with the corners at heights ``z_corners`` ``(n1 + 1, n2 + 1)`` [m].

    Quads are counter-clockwise seen from above (normals point up, +z).
    """
    n1, n2 = grid.shape
    c1, c2 = corner_coordinates(grid)
    x, y = np.meshgrid(c1, c2, indexing="ij")
    points = np.column_stack([x.ravel(order="F"), y.ravel(order="F"), np.asarray(z_corners).ravel(order="F")])
    i, j = (a.ravel(order="F") for a in np.meshgrid(np.arange(n1), np.arange(n2), indexing="ij"))

    def p(a, b):
        return a + (n1 + 1) * b

    connectivity = np.column_stack([p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)])
    return _unstructured(points, connectivity, VTK_QUAD)


def hexahedron_mesh(grid):
    """Hexahedra (VTK_HEXAHEDRON) of the surface cells times the layers, ``z`` from 0 down to ``-depth``."""
    if not grid.layers:
        raise ParameterError("the volume mesh needs subsurface layers: the grid has layers=0; "
                             "give Grid(..., depth=..., layers=...)")
    n1, n2, n3 = grid.shape + (grid.layers,)
    c1, c2 = corner_coordinates(grid)
    z = -layer_boundaries(grid)
    x, y, zz = np.meshgrid(c1, c2, z, indexing="ij")
    points = np.column_stack([a.ravel(order="F") for a in (x, y, zz)])
    i, j, k = (a.ravel(order="F") for a in np.meshgrid(np.arange(n1), np.arange(n2), np.arange(n3), indexing="ij"))

    def q(a, b, m):
        return a + (n1 + 1) * (b + (n2 + 1) * m)

    # VTK: the base (0-3) is counter-clockwise about the normal pointing to the opposite face (4-7):
    # base = the lower boundary of layer k (m = k + 1), top = its upper boundary (m = k).
    connectivity = np.column_stack([q(i, j, k + 1), q(i + 1, j, k + 1), q(i + 1, j + 1, k + 1), q(i, j + 1, k + 1),
                                    q(i, j, k), q(i + 1, j, k), q(i + 1, j + 1, k), q(i, j + 1, k)])
    return _unstructured(points, connectivity, VTK_HEXAHEDRON)


def to_material_frame(mesh, result, step):
    """Translate a mesh built in the body's frame to the material frame: by ``result.position[step]``.

    The exported files are drawn there (:class:`viz.Exporter`); the meshes
    of this module and the pictures stay in the body's frame.
    """
    k = step_index(result, step)
    shift = np.asarray(result.position[k], dtype=float)
    if np.any(shift):
        mesh.points[:, :2] += shift
    return mesh


def surface_mesh(result, step):
    """The surface of one step: the undeformed plane with the displacement as a point vector.

    Points: the ``(n1 + 1) x (n2 + 1)`` cell corners on the undeformed
    surface ``z = 0``.

    Point data: ``displacement_vector`` [m], the active vectors, ``(0, 0,
    -u3)`` (z up) with ``u3`` averaged over the cells around each corner
    (:func:`corner_average`, wrapping on periodic axes). ParaView's Warp By
    Vector with scale factor 1 moves the points to the deformed surface
    ``z = -u3``, where it meets the indenter in the contact (see
    :func:`indenter_mesh`); scale factor ``s`` exaggerates the deformation
    ``s`` times.

    Cell data: ``pressure`` [Pa], ``displacement`` (the scalar u3 [m],
    positive into the solid), ``gap`` [m], ``contact`` (int32, 1 where the
    pressure is > 0).

    Parameters
    ----------
    result : framework.Result
        The run.
    step : int
        Step index (negative counts from the end).

    Returns
    -------
    pyvista.UnstructuredGrid
        Quads (VTK_QUAD), no field data (see :func:`attach_metadata`).
    """
    k = step_index(result, step)
    grid = result.grid
    u3 = np.asarray(result.displacement(k), dtype=float)
    u3_corner = corner_average(u3, grid.periodic)
    mesh = quad_mesh(grid, np.zeros_like(u3_corner))
    vector = np.zeros((u3_corner.size, 3))
    vector[:, 2] = -u3_corner.ravel(order="F")
    mesh.point_data["displacement_vector"] = vector
    mesh.set_active_vectors("displacement_vector", preference="point")
    mesh.GetPointData().SetActiveScalars(None)  # else ParaView colours by the vector's magnitude, not the pressure
    pressure = np.asarray(result.pressure(k), dtype=float)
    mesh.cell_data["pressure"] = cell_order(pressure)
    mesh.cell_data["displacement"] = cell_order(u3)
    mesh.cell_data["gap"] = cell_order(np.asarray(result.gap(k), dtype=float))
    mesh.cell_data["contact"] = cell_order((pressure > 0).astype(np.int32))
    mesh.set_active_scalars("pressure", preference="cell")
    return mesh


def volume_mesh(result, step, stress=None):
    """Subsurface stresses of one step on hexahedra spanning the cells and layers (undeformed).

    Cell data (each cell holds the value at its centre, ``z = -x3``), in the
    exported frame (see the module docstring for the shear signs):

    * ``stress_xx``, ``stress_yy``, ``stress_zz``, ``stress_xy``,
      ``stress_yz``, ``stress_xz`` [Pa], and ``stress`` the same six as one
      6-component symmetric tensor in VTK's order ``XX YY ZZ XY YZ XZ``
      (:data:`TENSOR_ORDER`; not the framework's Voigt order), so that
      ParaView's tensor filters read it right;
    * ``von_mises`` [Pa]; ``tresca`` [Pa], the largest principal difference;
    * ``principal_stress`` [Pa], 3 components sorted descending.

    For a run with inhomogeneities (``result.inclusions`` not empty), from
    ``result.eigenstrain(step)`` (``(n1, n2, layers, 6)`` strains in the
    framework's Voigt order with tensor shears ``eps_23``, not engineering
    shears ``2 eps_23``: ParaView reads a tensor) and
    ``result.inhomogeneity(step)`` (0 in the matrix, ``k + 1`` in the
    ``k``-th inhomogeneity): ``eigenstrain`` (6 tensor components, converted
    like the stress: same frame and VTK order as ``stress``) and
    ``inhomogeneity`` (int32). The ``stress`` there includes the
    eigenstrains' field (:meth:`framework.Result.stress`).

    Parameters
    ----------
    result : framework.Result
        The run (its grid must have layers).
    step : int
        Step index.
    stress : ndarray, optional
        ``result.stress(step)`` when already computed.

    Returns
    -------
    pyvista.UnstructuredGrid
        Hexahedra (VTK_HEXAHEDRON).
    """
    k = step_index(result, step)
    mesh = hexahedron_mesh(result.grid)
    voigt = _cell_order(np.asarray(result.stress(k) if stress is None else stress, dtype=float), 3)
    tensor = vtk_tensor(voigt)
    for c, name in enumerate(STRESS_COMPONENTS):
        mesh.cell_data[name] = np.ascontiguousarray(tensor[:, c])
    mesh.cell_data["stress"] = np.ascontiguousarray(tensor)
    for name, value in stress_measures(voigt).items():
        mesh.cell_data[name] = value
    if getattr(result, "inclusions", None):
        mesh.cell_data["eigenstrain"] = vtk_tensor(_cell_order(np.asarray(result.eigenstrain(k), dtype=float), 3))
        mesh.cell_data["inhomogeneity"] = _cell_order(np.asarray(result.inhomogeneity(k)).astype(np.int32), 3)
    mesh.set_active_scalars("von_mises", preference="cell")
    return mesh


def indenter_mesh(result, step):
    """The indenter's surface over the grid at its position in one step.

    Points: the cell corners at ``z = h - approach`` (``h`` from
    ``indenter.on_grid`` averaged to the corners like the surface), so that
    the indenter and the deformed surface coincide where every adjacent cell
    is in contact (the surface warped by its ``displacement_vector`` with
    scale factor 1). Heights are written as given: the vertical walls of flat
    punches (:data:`framework.indenters.WALL` times the grid side) show up as
    steep one-cell ramps. The tilt of an eccentrically loaded indenter is
    drawn: ``z = h - (approach + alpha1 x1 + alpha2 x2)`` with ``alpha = tan(tilt)``.

    Cell data: ``height`` [m] (``h`` at the cell centres).

    Parameters
    ----------
    result : framework.Result
        The run.
    step : int
        Step index.

    Returns
    -------
    pyvista.UnstructuredGrid
        Quads (VTK_QUAD).
    """
    k = step_index(result, step)
    grid = result.grid
    heights = np.asarray(result.indenter.on_grid(grid), dtype=float)
    slope1, slope2 = np.tan(np.asarray(result.tilt[k], dtype=float))
    corners1, corners2 = corner_coordinates(grid)
    rigid = float(result.approach[k]) + slope1 * corners1[:, None] + slope2 * corners2[None, :]
    mesh = quad_mesh(grid, corner_average(heights, grid.periodic) - rigid)
    mesh.cell_data["height"] = cell_order(heights)
    return mesh


def inclusion_mesh(inclusions, resolution=48):
    """The surfaces of ellipsoidal inhomogeneities, triangulated, in the exported frame (z up).

    Each ellipsoid is the image of a unit sphere triangulated by latitude and
    longitude (``resolution`` meridians, ``resolution // 2`` parallels, poles
    included) under ``x = c + R diag(a) p``, then ``z = -x3``; every vertex
    lies on the ellipsoid (to rounding), so the polyhedron is inscribed and
    its volume falls short of ``4/3 pi a1 a2 a3`` by a relative ``O(resolution^-2)``
    (0.75 % at 48). Triangles are counter-clockwise seen from outside (normals
    point out of the inhomogeneity). The inhomogeneities are material points:
    the same in the material frame at every step (where the files are drawn);
    a rolling run's pictures, in the body's frame, move them by ``-position``.

    Cell data: ``inhomogeneity`` (int32), ``k + 1`` on the ``k``-th ellipsoid
    (the indicator of :func:`volume_mesh`); ``young`` [Pa] and ``poisson``
    of an isotropic inhomogeneity (NaN for an anisotropic one).

    Parameters
    ----------
    inclusions : sequence of framework.inclusions.Ellipsoid
        The inhomogeneities (``result.inclusions``).
    resolution : int
        Meridians per ellipsoid (>= 8).

    Returns
    -------
    pyvista.PolyData
        Triangles, the ellipsoids one after another.
    """
    pv = _deps.pyvista()
    if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)) or resolution < 8:
        raise ParameterError(f"resolution must be an integer >= 8 (meridians per ellipsoid), got {resolution!r}")
    sphere = pv.Sphere(radius=1.0, theta_resolution=int(resolution), phi_resolution=int(resolution) // 2)
    sphere = sphere.triangulate()
    unit = np.asarray(sphere.points, dtype=float)
    unit /= np.linalg.norm(unit, axis=1)[:, None]   # vtk stores float32 points: back onto the sphere
    triangles = sphere.faces.reshape(-1, 4)[:, 1:]
    # the flip z = -x3 is a reflection: reverse each triangle so that its normal still points outwards
    triangles = triangles[:, ::-1]
    points, faces, index, young, poisson = [], [], [], [], []
    for k, body in enumerate(inclusions):
        x = np.asarray(body.center) + (unit * np.asarray(body.semi_axes)) @ np.asarray(body.orientation).T
        x[:, 2] = -x[:, 2]
        faces.append(triangles + len(unit) * k)
        points.append(x)
        index.append(np.full(len(triangles), k + 1, dtype=np.int32))
        for values, name in ((young, "young"), (poisson, "poisson")):
            values.append(np.full(len(triangles), float(getattr(body.material, name, np.nan))))
    if not points:
        return pv.PolyData()
    faces = np.concatenate(faces)
    mesh = pv.PolyData(np.concatenate(points),
                       np.column_stack([np.full(len(faces), 3), faces]).ravel().astype(np.int64))
    mesh.cell_data["inhomogeneity"] = np.concatenate(index)
    mesh.cell_data["young"] = np.concatenate(young)
    mesh.cell_data["poisson"] = np.concatenate(poisson)
    return mesh
