"""Off-screen pictures of one step with pyvista: pressure maps, deformed surfaces, stress slices.

Works without a display: on Linux with neither ``DISPLAY`` nor
``WAYLAND_DISPLAY`` set, VTK's EGL render window is chosen (unless
``VTK_DEFAULT_OPENGL_WINDOW`` is set already) before vtk is imported, and
``pyvista.OFF_SCREEN`` is set. Colours follow the displayed field: by default
the colour range is the field's own minimum and maximum in the picture
(:attr:`Rendering.scalar_range`), unless ``clim`` fixes it (to compare steps).
Values are shown in a readable unit (MPa, um, mm ...) named on the colour bar;
:class:`Rendering` keeps the SI values.
"""
import os
from dataclasses import dataclass

import numpy as np

from framework.errors import ParameterError

from . import _deps, meshes

#: Surface fields: name -> (label, SI unit).
SURFACE_FIELDS = {
    "pressure": ("pressure", "Pa"),
    "displacement": ("normal displacement u3", "m"),
    "gap": ("gap", "m"),
    "contact": ("contact", ""),
}

#: Subsurface fields for ``kind="slice"``: name -> (label, SI unit). Components in the z-up frame.
VOLUME_FIELDS = {
    "von_mises": ("von Mises stress", "Pa"),
    "tresca": ("Tresca stress", "Pa"),
    "principal_1": ("max principal stress", "Pa"),
    "principal_2": ("middle principal stress", "Pa"),
    "principal_3": ("min principal stress", "Pa"),
    **{name: (name.replace("_", " "), "Pa") for name in meshes.STRESS_COMPONENTS},
}

KINDS = {"map": SURFACE_FIELDS, "surface": SURFACE_FIELDS, "slice": VOLUME_FIELDS}
DEFAULT_FIELD = {"map": "pressure", "surface": "pressure", "slice": "von_mises"}

_PREFIXES = {"Pa": ((1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa"), (1.0, "Pa")),
             "m": ((1.0, "m"), (1e-3, "mm"), (1e-6, "\u00b5m"), (1e-9, "nm"))}


@dataclass
class Rendering:
    """What :func:`render` drew.

    Attributes
    ----------
    path : str
        The PNG file.
    kind, field : str
        Picture kind and field name.
    step : int
        Step index (non-negative).
    time : float
        Physical time of the step [s].
    unit : str
        SI unit of the field ("" when dimensionless).
    scalar_range : tuple of float
        Minimum and maximum of the drawn values [SI unit].
    clim : tuple of float
        Colour range used [SI unit] (``scalar_range`` unless given, or widened
        when the field is constant).
    display_unit : str
        Unit on the colour bar; ``display_scale`` [SI unit per display unit].
    display_scale : float
        Displayed value = SI value / display_scale.
    warp : float or None
        Exaggeration of the deformation (``kind="surface"``), else None.
    """

    path: str
    kind: str
    field: str
    step: int
    time: float
    unit: str
    scalar_range: tuple
    clim: tuple
    display_unit: str
    display_scale: float
    warp: float = None


def display_unit(unit, magnitude):
    """A readable unit for values of size ``magnitude`` [SI].

    Parameters
    ----------
    unit : str
        SI unit, ``"Pa"`` or ``"m"`` get prefixes; others are kept.
    magnitude : float
        Typical absolute value [SI].

    Returns
    -------
    tuple
        ``(scale, name)``: display value = SI value / scale.
    """
    choices = _PREFIXES.get(unit)
    if not choices:
        return 1.0, unit
    magnitude = abs(float(magnitude))
    if not np.isfinite(magnitude) or magnitude == 0.0:
        return next((s, n) for s, n in choices if s == 1.0)
    for scale, name in choices:
        if magnitude >= scale:
            return scale, name
    return choices[-1]


def _nice(value):
    """1, 2 or 5 times a power of ten, at most ``value``."""
    if not np.isfinite(value) or value <= 0:
        return 1.0
    power = 10.0 ** np.floor(np.log10(value))
    return max(m for m in (1.0, 2.0, 5.0, 10.0) if m * power <= value * (1 + 1e-12)) * power


def _format_time(t):
    return f"{t:.4g} s"


def _quads(points):
    """Quad mesh from a structured ``(a + 1, b + 1, 3)`` point array (cell id ``i + a * j``)."""
    pv = _deps.pyvista(rendering=True)
    a, b = points.shape[0] - 1, points.shape[1] - 1
    flat = np.ascontiguousarray(points.transpose(1, 0, 2)).reshape(-1, 3)
    i, j = (x.ravel(order="F") for x in np.meshgrid(np.arange(a), np.arange(b), indexing="ij"))

    def p(u, v):
        return u + (a + 1) * v

    cells = np.column_stack([np.full(i.size, 4), p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)]).ravel()
    return pv.UnstructuredGrid(cells, np.full(i.size, meshes.VTK_QUAD, dtype=np.uint8), flat)


def _surface_field(result, k, field):
    if field == "pressure":
        return np.asarray(result.pressure(k), dtype=float)
    if field == "displacement":
        return np.asarray(result.displacement(k), dtype=float)
    if field == "gap":
        return np.asarray(result.gap(k), dtype=float)
    return (np.asarray(result.pressure(k)) > 0).astype(float)


def _volume_field(result, k, field):
    stress = np.asarray(result.stress(k), dtype=float)
    if field in meshes.STRESS_COMPONENTS:
        return meshes.vtk_tensor(stress)[..., meshes.STRESS_COMPONENTS.index(field)]
    measures = meshes.stress_measures(stress)
    if field.startswith("principal_"):
        return measures["principal_stress"][..., int(field[-1]) - 1]
    return measures[field]


def _check(kind, field):
    if kind not in KINDS:
        raise ParameterError(f"kind must be one of {sorted(KINDS)}, got {kind!r}")
    field = DEFAULT_FIELD[kind] if field is None else field
    if field not in KINDS[kind]:
        raise ParameterError(f"unknown field {field!r} for kind={kind!r}; choose one of {list(KINDS[kind])}")
    return field


def render(result, png, field=None, step=-1, *, kind="map", clim=None, cmap="viridis", warp=None,
           show_indenter=False, plane="x2", origin=0.0, clip=False, window_size=(1200, 900), title=None,
           font_size=18):
    """Draw one step of a result into a PNG file, off screen.

    Parameters
    ----------
    result : framework.Result
        The run.
    png : str or path
        Output file (``.png``); its folder must exist.
    field : str, optional
        What colours the picture. ``kind="map"`` or ``"surface"``:
        ``pressure`` [Pa] (default), ``displacement`` [m], ``gap`` [m],
        ``contact``. ``kind="slice"``: ``von_mises`` [Pa] (default),
        ``tresca``, ``principal_1`` / ``_2`` / ``_3`` (descending),
        ``stress_xx`` ... ``stress_xy`` (frame z up, see :mod:`viz.meshes`).
    step : int
        Step index (default -1, the last).
    kind : {"map", "surface", "slice"}
        ``map``: top view of the surface cells, with the contact outline.
        ``surface``: 3-D view of the deformed surface, the deformation
        exaggerated ``warp`` times (written in the title), with the indenter
        (translucent) when ``show_indenter``.
        ``slice``: the subsurface stresses in the plane ``plane = origin``
        (the layer of cells containing it, exact cell values); with
        ``clip=True`` a 3-D view of the layers on the far side of the plane.
    clim : tuple of float, optional
        Colour range [SI unit]; default: the field's minimum and maximum.
    cmap : str
        Matplotlib colour map name.
    warp : float, optional
        Exaggeration of the deformation for ``kind="surface"``; default: a
        round number (1, 2 or 5 times a power of ten) making the deepest
        point at most 25 % of the grid side.
    show_indenter : bool
        Draw the indenter with ``kind="surface"``.
    plane : {"x2", "x1"}
        Slice normal for ``kind="slice"``: ``"x2"`` the plane x2 = origin.
    origin : float
        Position of the slice plane [m].
    clip : bool
        ``kind="slice"``: 3-D view of the clipped volume instead of the plane.
    window_size : tuple of int
        Picture size in pixels.
    title : str, optional
        Replaces the default title (field, step, time and load).
    font_size : int
        Base font size [pt]; titles and labels are scaled from it.

    Returns
    -------
    Rendering
        The file, the colour range and the units used.

    Raises
    ------
    framework.errors.ParameterError
        Unknown ``kind``, ``field`` or ``plane``, bad ``step``, or a slice of
        a result without layers.
    ImportError
        pyvista is missing (``pip install 'viscocontact[viz]'``).
    """
    field = _check(kind, field)
    k = meshes.step_index(result, step)
    if plane not in ("x1", "x2"):
        raise ParameterError(f"plane must be 'x1' or 'x2' (the slice normal), got {plane!r}")
    if kind == "slice" and not result.grid.layers:
        raise ParameterError("kind='slice' needs subsurface layers: the grid has layers=0; "
                             "give Grid(..., depth=..., layers=...)")
    pv = _deps.pyvista(rendering=True)
    grid = result.grid
    label, unit = KINDS[kind][field]
    time = float(result.times[k])
    length_scale, length_unit = display_unit("m", max(grid.size))
    warp_factor, heading = None, ""
    values = (_volume_field if kind == "slice" else _surface_field)(result, k, field)

    # the mesh to colour, its cell data "values" in SI units, coordinates in the display length unit
    if kind == "map":
        mesh = meshes.quad_mesh(grid, np.zeros(tuple(n + 1 for n in grid.shape)))
        mesh.cell_data["values"] = meshes.cell_order(values)
    elif kind == "surface":
        u3 = np.asarray(result.displacement(k), dtype=float)
        deepest = float(np.max(np.abs(u3)))
        if warp is not None:
            if not (isinstance(warp, (int, float, np.number)) and np.isfinite(warp) and warp > 0):
                raise ParameterError(f"warp must be a positive finite exaggeration factor, got {warp!r}")
            warp_factor = float(warp)
        else:
            warp_factor = float(_nice(0.25 * max(grid.size) / deepest)) if deepest > 0 else 1.0
        mesh = meshes.quad_mesh(grid, -warp_factor * meshes.corner_average(u3, grid.periodic))
        mesh.cell_data["values"] = meshes.cell_order(values)
        heading = f", deformation \u00d7{warp_factor:g}"
    elif not clip:
        index = _plane_index(grid, plane, origin)
        mesh = _slice_mesh(grid, values, plane, origin)
        heading = f", plane {plane} = {_length(_centres(grid, plane)[index], length_scale, length_unit)}"
    else:
        index = _plane_index(grid, plane, origin)
        mesh = meshes.hexahedron_mesh(grid)
        mesh.cell_data["values"] = meshes.cell_order(values)
        n1, n2 = grid.shape
        ids = np.arange(mesh.n_cells)
        along = (ids // n1) % n2 if plane == "x2" else ids % n1
        mesh = mesh.extract_cells(ids[along >= index])
        heading = f", clipped at {plane} = {_length(_centres(grid, plane)[index], length_scale, length_unit)}"
    mesh.points[:] /= length_scale

    drawn = np.asarray(mesh.cell_data["values"], dtype=float)
    scalar_range = (float(drawn.min()), float(drawn.max()))
    try:
        used = tuple(float(c) for c in clim) if clim is not None else scalar_range
    except (TypeError, ValueError):
        used = ()
    if len(used) != 2 or not all(np.isfinite(used)):
        raise ParameterError(f"clim must be two finite numbers (low, high) in {unit or 'the field unit'}, "
                             f"got {clim!r}")
    if not used[1] > used[0]:
        used = (used[0], used[0] + (abs(used[0]) if used[0] else 1.0))
    scale, shown_unit = display_unit(unit, max(abs(used[0]), abs(used[1])))
    mesh.cell_data["values"] = drawn / scale

    plotter = pv.Plotter(off_screen=True, window_size=tuple(int(w) for w in window_size))
    plotter.set_background("white")
    bar = dict(title=f"{field} [{shown_unit}]" if shown_unit else field, vertical=True, position_x=0.83,
               position_y=0.12, width=0.06, height=0.72, title_font_size=int(font_size * 1.3),
               label_font_size=int(font_size * 1.2), fmt="%.3g", color="black", n_labels=2 if field == "contact" else 6)
    options = dict(scalars="values", cmap=cmap, clim=(used[0] / scale, used[1] / scale), scalar_bar_args=bar,
                   show_edges=False)
    if kind == "map":
        plotter.add_mesh(mesh, lighting=False, **options)
        _contact_outline(plotter, result, k, length_scale)
        plotter.view_xy()
        _bounds(plotter, mesh, font_size, ("x1", "x2", ""), length_unit, flat="z")
        _fit_2d(plotter, mesh, (0, 1))
    elif kind == "surface":
        plotter.add_mesh(mesh, smooth_shading=True, **options)
        if show_indenter:
            _indenter(plotter, result, k, warp_factor, length_scale, deepest)
        _bounds(plotter, mesh, font_size, ("x1", "x2", ""), length_unit, flat="z")
        _camera_3d(plotter, mesh, azimuth=-60, elevation=28, zoom=1.05)
    elif not clip:
        plotter.add_mesh(mesh, lighting=False, **options)
        if plane == "x2":
            plotter.view_xz()
            _bounds(plotter, mesh, font_size, ("x1", "", "z"), length_unit, flat="y")
            _fit_2d(plotter, mesh, (0, 2))
        else:
            plotter.view_yz()
            _bounds(plotter, mesh, font_size, ("", "x2", "z"), length_unit, flat="x")
            _fit_2d(plotter, mesh, (1, 2))
    else:
        plotter.add_mesh(mesh, ambient=0.6, diffuse=0.45, specular=0.0, **options)
        _bounds(plotter, mesh, font_size, ("x1", "x2", "z"), length_unit)
        _camera_3d(plotter, mesh, azimuth=-55 if plane == "x2" else -145, elevation=25, zoom=0.95)

    lines = [title] if title else [f"{label}{heading}",
                                   f"step {k}, t = {_format_time(time)}, load {result.load[k]:.4g} N, "
                                   f"approach {_length(result.approach[k])}"]
    text_size = int(font_size)
    plotter.add_text("\n".join(lines), position=(int(0.015 * plotter.window_size[0]),
                                                 int(plotter.window_size[1] - 2.2 * text_size * len(lines) - 20)),
                     font_size=text_size, color="black")
    path = os.fspath(png)
    try:
        plotter.screenshot(path)
    finally:
        plotter.close()
    return Rendering(path=path, kind=kind, field=field, step=k, time=time, unit=unit, scalar_range=scalar_range,
                     clim=used, display_unit=shown_unit, display_scale=scale, warp=warp_factor)


def _fit_2d(plotter, mesh, axes, box=(0.11, 0.12, 0.79, 0.86)):
    """Parallel projection placing the mesh's extent along ``axes`` (horizontal, vertical) in ``box``.

    ``box`` = (left, bottom, right, top) as fractions of the window: room for
    the axes' labels, the colour bar on the right and the title on top.
    """
    plotter.enable_parallel_projection()
    width, height = plotter.window_size
    b = np.asarray(mesh.bounds).reshape(3, 2)
    (h0, h1), (v0, v1) = b[axes[0]], b[axes[1]]
    per_pixel = max((h1 - h0) / ((box[2] - box[0]) * width), (v1 - v0) / ((box[3] - box[1]) * height), 1e-30)
    camera = plotter.camera
    direction = np.subtract(camera.position, camera.focal_point)
    direction = direction / np.linalg.norm(direction)
    centre = b.mean(axis=1)
    # the mesh centre must land at the box centre: shift the focal point the other way
    shift_h = ((box[0] + box[2]) / 2 - 0.5) * width * per_pixel
    shift_v = ((box[1] + box[3]) / 2 - 0.5) * height * per_pixel
    focal = centre.copy()
    focal[axes[0]] -= shift_h
    focal[axes[1]] -= shift_v
    distance = np.linalg.norm(np.subtract(camera.position, camera.focal_point))  # keeps the axes' label size
    camera.focal_point = tuple(focal)
    camera.position = tuple(focal + distance * direction)
    camera.parallel_scale = per_pixel * height / 2
    plotter.renderer.ResetCameraClippingRange()


def _camera_3d(plotter, mesh, azimuth, elevation, zoom, shift=0.07):
    """Perspective view from ``azimuth`` / ``elevation`` [deg] (z up), the scene shifted left of the colour bar."""
    az, el = np.radians(azimuth), np.radians(elevation)
    direction = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    centre = np.asarray(mesh.center)
    camera = plotter.camera
    camera.focal_point = tuple(centre)
    camera.position = tuple(centre + direction)
    camera.up = (0.0, 0.0, 1.0)
    plotter.reset_camera()
    camera.zoom(zoom)
    distance = np.linalg.norm(np.subtract(camera.position, camera.focal_point))
    width, height = plotter.window_size
    visible = 2 * distance * np.tan(np.radians(camera.view_angle) / 2) * width / height
    right = np.cross(-direction, (0.0, 0.0, 1.0))
    right /= np.linalg.norm(right)
    move = right * shift * visible
    camera.focal_point = tuple(np.add(camera.focal_point, move))
    camera.position = tuple(np.add(camera.position, move))
    plotter.renderer.ResetCameraClippingRange()


def _length(value, scale=None, unit=None):
    if scale is None:
        scale, unit = display_unit("m", value)
    return f"{value / scale:.4g} {unit}"


def _centres(grid, plane):
    return grid.x2 if plane == "x2" else grid.x1


def _plane_index(grid, plane, origin):
    axis = 1 if plane == "x2" else 0
    half = grid.size[axis] / 2
    if not np.isfinite(origin) or abs(origin) > half:
        raise ParameterError(f"origin of the {plane} slice must lie in [-{half:g}, {half:g}] m, got {origin!r}")
    return int(np.clip(np.floor((origin + half) / grid.spacing[axis]), 0, grid.shape[axis] - 1))


def _slice_mesh(grid, values, plane, origin):
    """Quads of the cells cut by the plane: (along, depth) with the exact cell values."""
    index = _plane_index(grid, plane, origin)
    c1, c2 = meshes.corner_coordinates(grid)
    z = -meshes.layer_boundaries(grid)
    if plane == "x2":
        along, cut = c1, values[:, index, :]
        a, zz = np.meshgrid(along, z, indexing="ij")
        points = np.stack([a, np.full_like(a, origin), zz], axis=-1)
    else:
        along, cut = c2, values[index, :, :]
        a, zz = np.meshgrid(along, z, indexing="ij")
        points = np.stack([np.full_like(a, origin), a, zz], axis=-1)
    mesh = _quads(points)
    mesh.cell_data["values"] = meshes.cell_order(cut)
    return mesh


def _contact_outline(plotter, result, k, length_scale):
    """Black line around the cells in contact (the 0.5 contour of the corner-averaged indicator)."""
    grid = result.grid
    contact = (np.asarray(result.pressure(k)) > 0).astype(float)
    if not contact.any() or contact.all():
        return
    mesh = meshes.quad_mesh(grid, np.full(tuple(n + 1 for n in grid.shape), 1e-6 * max(grid.size)))
    mesh.points[:] /= length_scale
    # zero padding closes the outline along the grid's edges
    corners = meshes.corner_average(np.pad(contact, 1), (False, False))[1:-1, 1:-1]
    mesh.point_data["contact"] = corners.ravel(order="F")
    outline = mesh.contour([0.5], scalars="contact")
    if outline.n_points:
        plotter.add_mesh(outline, color="white", line_width=3, lighting=False, label="contact edge")


def _indenter(plotter, result, k, warp_factor, length_scale, deepest):
    """The indenter, exaggerated like the surface, shown up to a little above the undeformed plane."""
    grid = result.grid
    heights = np.asarray(result.indenter.on_grid(grid), dtype=float)
    z = warp_factor * (meshes.corner_average(heights, grid.periodic) - float(result.approach[k]))
    # lifted by 0.2 % of the grid side: in contact the indenter and the surface coincide (no z-fighting)
    mesh = meshes.quad_mesh(grid, z + 2e-3 * max(grid.size))
    mesh.points[:] /= length_scale
    mesh.point_data["z"] = mesh.points[:, 2].copy()
    top = max(0.3 * warp_factor * deepest, 0.02 * max(grid.size)) / length_scale
    mesh = mesh.clip_scalar(scalars="z", value=top, invert=True)
    if mesh.n_cells:
        plotter.add_mesh(mesh, color="lightgray", opacity=0.35, show_scalar_bar=False, smooth_shading=True)


def _bounds(plotter, mesh, font_size, titles, length_unit, flat=None):
    """Axes with ticks in the display length unit."""
    unit = length_unit.replace("\u00b5", "u")  # the axes' vector font has no micro sign
    x, y, z = (f"{t} [{unit}]" if t else " " for t in titles)
    plotter.show_bounds(mesh=mesh, xtitle=x, ytitle=y, ztitle=z, font_size=int(font_size),
                        color="black", location="outer", ticks="outside", fmt="%.2f",
                        show_xaxis=flat != "x", show_yaxis=flat != "y", show_zaxis=flat != "z",
                        show_xlabels=flat != "x", show_ylabels=flat != "y", show_zlabels=flat != "z")
