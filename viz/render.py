"""Off-screen pictures of one step with pyvista: pressure maps, deformed surfaces, stress slices.

Works without a display: on Linux with neither ``DISPLAY`` nor
``WAYLAND_DISPLAY`` set, VTK's EGL render window is chosen (unless
``VTK_DEFAULT_OPENGL_WINDOW`` is set already) before vtk is imported, and
``pyvista.OFF_SCREEN`` is set.

This module assembles a picture (:func:`draw`) and saves it (:func:`render`);
each part lives in its own module:

* :mod:`viz.fields`: the fields a picture can colour, their labels and units,
  the values drawn;
* :mod:`viz.slices`: the plane a subsurface slice shows (interpolated to the
  plane asked for) and its mesh;
* :mod:`viz.scales`: colour ranges and maps, display units (MPa, µm),
  round ticks;
* :mod:`viz.labels`: titles, axis names and lengths, typeset with mathtext;
* :mod:`viz.layout`: the window's size (a flat picture sized to its field's
  aspect) and the cameras;
* :mod:`viz.overlay`: title, axes and colour bar drawn in window pixels;
* :mod:`viz.outlines`: the contact's edge, the inhomogeneities, the indenter;
* :mod:`viz.checks`: the checks of the arguments, before anything is drawn.

Colours follow the displayed field: by default the colour range is the field's
own minimum and maximum in the picture (:attr:`Rendering.scalar_range`),
cleaned by :func:`viz.scales.colour_limits`; ``clim`` fixes the range instead
(to compare steps). Values are shown in a readable unit named on the colour
bar with the field's label (``von Mises stress [MPa]``); :class:`Rendering`
keeps the SI values.
"""
import os
from dataclasses import dataclass, field as _field

import numpy as np

from . import _deps, labels, layout, meshes, outlines, slices
from .checks import as_result, check_clim, check_options, check_picture
from .fields import DEFAULT_FIELD, KINDS, SURFACE_FIELDS, VOLUME_FIELDS, shown_values
from .overlay import BAR_GAP, BAR_WIDTH, Overlay
from .scales import DIVERGING, SEQUENTIAL, SNAP, automatic_warp, colour_limits, display_unit, nice_ticks

# the picture's pieces live in their own modules; these names stay importable from here as before
__all__ = ["render", "draw", "Rendering", "KINDS", "SURFACE_FIELDS", "VOLUME_FIELDS", "DEFAULT_FIELD",
           "SEQUENTIAL", "DIVERGING", "SNAP", "display_unit", "colour_limits", "nice_ticks", "automatic_warp",
           "check_clim", "check_picture", "shown_values"]


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
        Colour range used [SI unit]: ``clim`` when given, else
        ``scalar_range`` with round-off ends set to zero, made symmetric about
        zero when the field takes both signs (widened when it is constant);
        ``(-0.5, 1.5)`` for ``contact``, its two colours centred on 0 and 1.
    display_unit : str
        Unit on the colour bar; ``display_scale`` [SI unit per display unit].
    display_scale : float
        Displayed value = SI value / display_scale.
    warp : float or None
        Exaggeration of the deformation (``kind="surface"``), else None.
    cmap : str
        Colour map used.
    title : str
        The picture's title (lines joined by newlines; mathtext between ``$``).
    bar_title : str
        Title of the colour bar, the field's label and display unit.
    bar_labels : tuple of str
        Tick labels of the colour bar (values in the display unit).
    axis_labels : dict
        Axis title -> the tick labels drawn along it.
    label_boxes : list of tuple
        ``(x0, y0, x1, y1)`` window pixels of every axis tick label drawn.
    window_size : tuple of int
        Width and height of the picture [px].
    plane_position : float or None
        ``kind="slice"``: the plane the values belong to [m] (``origin``
        unless it lies beyond the outermost cell centres; the clipped view:
        the centres of the first cells shown), else None.
    field_box : tuple of float or None
        A flat picture's field ``(left, bottom, right, top)`` in window
        pixels (y up), else None.
    bar_box : tuple of float or None
        The colour bar's strip ``(left, bottom, right, top)`` [px, y up].
    colours : ndarray
        The colour map as drawn: ``(n_colors, 3)`` uint8 RGB, lowest first.
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
    cmap: str = SEQUENTIAL
    title: str = ""
    bar_title: str = ""
    bar_labels: tuple = ()
    axis_labels: dict = _field(default_factory=dict)
    label_boxes: list = _field(default_factory=list)
    window_size: tuple = ()
    plane_position: float = None
    field_box: tuple = None
    bar_box: tuple = None
    colours: np.ndarray = _field(default=None, repr=False)


def render(result, png, field=None, step=-1, *, kind="map", clim=None, cmap=None, warp=None,
           show_indenter=False, plane="x2", origin=0.0, clip=False, window_size=None, title=None,
           font_size=18):
    """Draw one step of a result into a PNG file, off screen.

    Parameters
    ----------
    result : framework.Result or str or path
        The run, or a saved result file (``result.h5``) to load.
    png : str or path
        Output file (``.png``); its folder must exist.
    field : str, optional
        What colours the picture. ``kind="map"`` or ``"surface"``:
        ``pressure`` [Pa] (default), ``displacement`` [m], ``gap`` [m],
        ``contact``. ``kind="slice"``: ``von_mises`` [Pa] (default),
        ``tresca``, ``principal_1`` / ``_2`` / ``_3`` (descending),
        ``stress_xx`` ... ``stress_xz`` (frame z up, see :mod:`viz.meshes`).
    step : int
        Step index (default -1, the last).
    kind : {"map", "surface", "slice"}
        ``map``: top view of the surface cells, with the contact outline.
        ``surface``: 3-D view of the deformed surface, the deformation
        exaggerated ``warp`` times (written in the title), with the indenter
        (translucent) when ``show_indenter``.
        ``slice``: the subsurface stresses in the plane ``plane = origin``,
        interpolated between the cell centres either side of it (exact on a
        plane of centres; see :mod:`viz.slices`), the plane named in the
        title; with ``clip=True`` a 3-D view of the cells from the one
        holding the plane on. A run's inhomogeneities are outlined in black
        where the plane cuts them, and in the 3-D view also drawn whole,
        translucent white.
    clim : tuple of float, optional
        Colour range [SI unit]; default: the field's minimum and maximum,
        cleaned by :func:`colour_limits` (round-off ends -> 0, symmetric
        about zero for a field of both signs).
    cmap : str, optional
        Matplotlib colour map name; default: :data:`DIVERGING` when the
        colour range is symmetric about zero, else :data:`SEQUENTIAL`.
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
    window_size : tuple of int, optional
        Picture size in pixels, each side in [16, 8192] and at most 4096 x
        4096 in all. Default: a map or a slice is sized to the field's
        aspect (:func:`viz.layout.flat_layout`: 1200 pixels wide, a wide thin
        field gets a wide short picture that it fills), a 3-D view is 1200 x
        900.
    title : str, optional
        Replaces the default title (field, step, time and load).
    font_size : int
        Base font size [pixels] of the tick labels, in [4, 200]; titles are
        scaled from it.

    Returns
    -------
    Rendering
        The file, the colour range, colour map, units and labels used.

    Raises
    ------
    framework.errors.ParameterError
        Unknown ``kind``, ``field``, ``plane`` or ``cmap``, bad ``step``,
        ``clim``, ``window_size`` or ``font_size``, a slice of a result
        without layers, or a result file that cannot be loaded.
    ImportError
        pyvista is missing (``pip install 'viscocontact[viz]'``).
    """
    plotter, rendering = draw(result, field, step, kind=kind, clim=clim, cmap=cmap, warp=warp,
                              show_indenter=show_indenter, plane=plane, origin=origin, clip=clip,
                              window_size=window_size, title=title, font_size=font_size)
    rendering.path = os.fspath(png)
    try:
        plotter.screenshot(rendering.path)
    finally:
        plotter.close()
    return rendering


def draw(result, field=None, step=-1, *, kind="map", clim=None, cmap=None, warp=None, show_indenter=False,
         plane="x2", origin=0.0, clip=False, window_size=None, title=None, font_size=18, n_colors=256):
    """The scene of :func:`render` in an off-screen plotter, not yet saved: one frame of a picture or an animation.

    Parameters are those of :func:`render`, and ``n_colors``: the number of
    colours of the colour map (an animation's GIF frames keep room in their
    256-colour palette for the text).

    Returns
    -------
    plotter : pyvista.Plotter
        The scene, ready for ``plotter.screenshot``; the caller closes it.
    rendering : Rendering
        What is drawn, with ``path`` None.
    """
    result = as_result(result)
    field, clim, cmap, window_size, font_size = check_options(
        result, kind, field, clim=clim, cmap=cmap, warp=warp, plane=plane, origin=origin,
        window_size=window_size, font_size=font_size)
    k = meshes.step_index(result, step)
    pv = _deps.pyvista(rendering=True)
    grid = result.grid
    label, unit = KINDS[kind][field]
    time = float(result.times[k])
    length_scale, length_unit = display_unit("m", max(grid.size))
    warp_factor, heading, position = None, "", None
    values = shown_values(result, k, kind, field, plane=plane, origin=origin, clip=clip)
    flat = kind == "map" or (kind == "slice" and not clip)

    # the mesh to colour, its cell data "values" in SI units, coordinates in the display length unit
    if kind == "map":
        mesh = meshes.quad_mesh(grid, np.zeros(tuple(n + 1 for n in grid.shape)))
        mesh.cell_data["values"] = meshes.cell_order(values)
    elif kind == "surface":
        u3 = np.asarray(result.displacement(k), dtype=float)
        deepest = float(np.max(np.abs(u3)))
        warp_factor = automatic_warp(grid, deepest) if warp is None else float(warp)
        mesh = meshes.quad_mesh(grid, -warp_factor * meshes.corner_average(u3, grid.periodic))
        mesh.cell_data["values"] = meshes.cell_order(values)
        heading = f", deformation \u00d7{warp_factor:g}"
    elif not clip:
        position = slices.locate(grid, plane, origin).position
        mesh = slices.slice_mesh(grid, values, plane, position)  # values: the field in the plane
        heading = f", plane {labels.PLANES[plane]} = {labels.length(position)}"
    else:
        index = slices.plane_index(grid, plane, origin)
        position = float(slices.centres(grid, plane)[index])
        mesh = slices.clipped_mesh(grid, values, plane, index)
        heading = f", cells from {labels.PLANES[plane]} = {labels.length(slices.corners(grid, plane)[index])} on"
    mesh.points[:] /= length_scale

    drawn = np.asarray(mesh.cell_data["values"], dtype=float)
    scalar_range = (float(drawn.min()), float(drawn.max()))
    used = clim if clim is not None else ((-0.5, 1.5) if field == "contact" else colour_limits(*scalar_range))
    if not used[1] > used[0]:
        used = (used[0], used[0] + (abs(used[0]) if used[0] else 1.0))
    if cmap is None:
        cmap = DIVERGING if used[0] == -used[1] else SEQUENTIAL
    scale, shown_unit = display_unit(unit, max(abs(used[0]), abs(used[1])))
    mesh.cell_data["values"] = drawn / scale
    low, high = used[0] / scale, used[1] / scale
    bar_title = labels.with_unit(label, shown_unit)
    bar_ticks = (0.0, 1.0) if field == "contact" else None
    title = title or f"{label}{heading}\n{labels.step_line(result, k, time)}"

    if kind == "map":
        axes = (0, 1)
    elif kind == "slice" and not clip:
        axes = (0, 2) if plane == "x2" else (1, 2)
    else:
        axes = (0, 1, 2) if kind == "slice" else (0, 1)
    plotter = pv.Plotter(off_screen=True, window_size=window_size or layout.VIEW_SIZE)
    plotter.set_background("white")
    overlay = Overlay(plotter, font_size)
    box = None
    if flat:
        extent = np.ptp(np.asarray(mesh.bounds).reshape(3, 2)[list(axes)], axis=1)
        arranged = layout.flat_layout(extent, font_size, title.count("\n") + 1,
                                      overlay.bar_room(low, high, bar_ticks), window_size)
        overlay.resize(*arranged.size)
        box = arranged.box
    overlay.title(title)
    options = dict(scalars="values", cmap=cmap, clim=(low, high), show_edges=False, show_scalar_bar=False,
                   n_colors=2 if field == "contact" else int(n_colors))
    if kind == "map":
        actor = plotter.add_mesh(mesh, lighting=False, **options)
        outlines.contact_outline(plotter, result, k, length_scale)
        plotter.view_xy()
    elif kind == "surface":
        actor = plotter.add_mesh(mesh, smooth_shading=True, **options)
        if show_indenter:
            outlines.indenter(plotter, result, k, warp_factor, length_scale, deepest)
        layout.camera_3d(plotter, mesh, azimuth=-60, elevation=28, zoom=1.05)
    elif not clip:
        actor = plotter.add_mesh(mesh, lighting=False, **options)
        # view_xz looks from -x2, view_yz from +x1: the outlines are moved towards the camera
        outlines.inclusions(plotter, result, k, length_scale, plane, position,
                            toward=-1 if plane == "x2" else 1, surfaces=False)
        if plane == "x2":
            plotter.view_xz()
        else:
            plotter.view_yz()
    else:
        actor = plotter.add_mesh(mesh, ambient=0.6, diffuse=0.45, specular=0.0, **options)
        # the camera looks at the cut face from the removed side (-x2, resp. -x1)
        outlines.inclusions(plotter, result, k, length_scale, plane, slices.corners(grid, plane)[index],
                            toward=-1, surfaces=True)
        layout.camera_3d(plotter, mesh, azimuth=-55 if plane == "x2" else -145, elevation=25, zoom=0.95)
    field_box = layout.fit_2d(plotter, mesh, axes, box) if flat else None
    axis_labels = overlay.axes(mesh.bounds, {a: labels.axis_title(a, length_unit) for a in axes}, frame=flat)
    if flat:
        left, bottom, top = field_box[2] + BAR_GAP * font_size, field_box[1], field_box[3]
        if top - bottom < 6 * font_size:  # a field thinner than a readable bar: the bar about its middle
            middle = (top + bottom) / 2
            bottom, top = middle - 3 * font_size, middle + 3 * font_size
    else:  # a 3-D view: the bar spans the scene's height on screen, at least 12 font sizes
        width, height = plotter.window_size
        b = np.asarray(mesh.bounds).reshape(3, 2)
        heights = [overlay.project((x, y, z))[1] for x in b[0] for y in b[1] for z in b[2]]
        bottom, top = max(min(heights), 0.12 * height), min(max(heights), 0.84 * height)
        if top - bottom < 12 * font_size:
            middle = (top + bottom) / 2
            bottom, top = middle - 6 * font_size, middle + 6 * font_size
        left = 0.83 * width
    bar_labels = overlay.colour_bar(actor.mapper.lookup_table, low, high, bar_title, left, bottom, top,
                                    ticks=bar_ticks)
    return plotter, Rendering(path=None, kind=kind, field=field, step=k, time=time, unit=unit,
                              scalar_range=scalar_range, clim=used, display_unit=shown_unit, display_scale=scale,
                              warp=warp_factor, cmap=cmap, title=title, bar_title=bar_title,
                              bar_labels=bar_labels, axis_labels=axis_labels,
                              label_boxes=list(overlay.label_boxes), window_size=tuple(plotter.window_size),
                              plane_position=position, field_box=field_box,
                              bar_box=(left, bottom, left + BAR_WIDTH * font_size, top),
                              colours=np.asarray(actor.mapper.lookup_table.values)[:, :3].astype(np.uint8))

