"""Off-screen pictures of one step with pyvista: pressure maps, deformed surfaces, stress slices.

Works without a display: on Linux with neither ``DISPLAY`` nor
``WAYLAND_DISPLAY`` set, VTK's EGL render window is chosen (unless
``VTK_DEFAULT_OPENGL_WINDOW`` is set already) before vtk is imported, and
``pyvista.OFF_SCREEN`` is set.

Colours follow the displayed field: by default the colour range is the field's
own minimum and maximum in the picture (:attr:`Rendering.scalar_range`), with
ends closer to zero than :data:`SNAP` times the range taken as zero (round-off:
a contact-free surface shows ``0``, not ``-7.6e-09``); a field taking both signs
gets limits symmetric about zero and the diverging map :data:`DIVERGING`
(white-grey at zero), a one-signed field the sequential :data:`SEQUENTIAL`.
``clim`` fixes the range instead (to compare steps). Values are shown in a
readable unit (MPa, µm, mm ...) named on the colour bar with the field's label
(``von Mises stress [MPa]``); :class:`Rendering` keeps the SI values.

Axes, tick labels and titles are drawn in window pixels over the scene: ticks
fall on round values (1, 2 or 5 times a power of ten), as many as fit the
axis's length on screen without their labels touching, with as many decimals as
the tick spacing needs; a label that would touch one of another axis (at a
shared corner) is left out. Text uses matplotlib's DejaVu Sans when matplotlib
is installed (VTK's own font otherwise).
"""
import functools
import os
from dataclasses import dataclass, field as _field

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
    **{name: (("normal" if name[-1] == name[-2] else "shear") + " stress " + name[-2:], "Pa")
       for name in meshes.STRESS_COMPONENTS},
}

KINDS = {"map": SURFACE_FIELDS, "surface": SURFACE_FIELDS, "slice": VOLUME_FIELDS}
DEFAULT_FIELD = {"map": "pressure", "surface": "pressure", "slice": "von_mises"}

#: Colour map of fields of one sign, and of fields of both signs (limits symmetric about zero).
SEQUENTIAL, DIVERGING = "viridis", "coolwarm"

#: Automatic colour limits closer to zero than this fraction of the range are round-off, shown as 0.
SNAP = 1e-6

_PREFIXES = {"Pa": ((1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa"), (1.0, "Pa")),
             "m": ((1.0, "m"), (1e-3, "mm"), (1e-6, "\u00b5m"), (1e-9, "nm")),
             "m\u00b2": ((1.0, "m\u00b2"), (1e-6, "mm\u00b2"))}  # contact areas read best in mm²


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
        The picture's title (lines joined by newlines).
    bar_title : str
        Title of the colour bar, the field's label and display unit.
    bar_labels : tuple of str
        Tick labels of the colour bar (values in the display unit).
    axis_labels : dict
        Axis title -> the tick labels drawn along it.
    label_boxes : list of tuple
        ``(x0, y0, x1, y1)`` window pixels of every axis tick label drawn.
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


def display_unit(unit, magnitude):
    """A readable unit for values of size ``magnitude`` [SI].

    Parameters
    ----------
    unit : str
        SI unit, ``"Pa"``, ``"m"`` or ``"m²"`` get prefixes; others are kept.
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


def colour_limits(low, high):
    """Automatic colour limits of values spanning ``[low, high]``.

    Parameters
    ----------
    low, high : float
        Minimum and maximum of the values.

    Returns
    -------
    tuple of float
        ``(low, high)`` with an end closer to zero than :data:`SNAP` times
        ``high - low`` set to zero (round-off), then, if the values still take
        both signs, ``(-m, m)`` with ``m`` the larger magnitude, so that a
        diverging colour map puts zero at its centre.
    """
    span = high - low
    low, high = (0.0 if abs(v) <= SNAP * span else float(v) for v in (low, high))
    if low < 0.0 < high:
        top = max(-low, high)
        return -top, top
    return low, high


def automatic_warp(grid, deepest):
    """Default exaggeration of a deformed surface: round (1, 2 or 5 times a power of ten), the deepest point at most 25 % of the grid side.

    Parameters
    ----------
    grid : framework.Grid
        The surface grid.
    deepest : float
        Largest absolute normal displacement shown [m].

    Returns
    -------
    float
        The factor (1 for an undeformed surface).
    """
    return float(_nice(0.25 * max(grid.size) / deepest)) if deepest > 0 else 1.0


def check_clim(clim, unit):
    """``clim`` as two finite floats ``(low, high)`` [SI unit], or ParameterError naming it."""
    try:
        used = tuple(float(c) for c in clim)
    except (TypeError, ValueError):
        used = ()
    if len(used) != 2 or not all(np.isfinite(used)):
        raise ParameterError(f"clim must be two finite numbers (low, high) in {unit or 'the field unit'}, "
                             f"got {clim!r}")
    return used


def _nice(value, up=False):
    """1, 2 or 5 times a power of ten: the largest at most ``value``, or with ``up`` the smallest at least it."""
    if not np.isfinite(value) or value <= 0:
        return 1.0
    power = 10.0 ** np.floor(np.log10(value))
    if up:
        return min(m for m in (1.0, 2.0, 5.0, 10.0) if m * power >= value * (1 - 1e-12)) * power
    return max(m for m in (1.0, 2.0, 5.0, 10.0) if m * power <= value * (1 + 1e-12)) * power


def nice_ticks(low, high, most):
    """Round tick values in ``[low, high]``: multiples of a step of 1, 2 or 5 times a power of ten.

    Parameters
    ----------
    low, high : float
        The range, ``low < high``.
    most : int
        Largest number of ticks wanted (>= 2).

    Returns
    -------
    values : ndarray
        The ticks (at most ``most``; at least one when the range holds a
        multiple of the step, which is the case unless it is very short).
    decimals : int
        Decimals that print every tick exactly (from the step: 0.2 -> 1).
    """
    rough = (high - low) / max(most - 1, 1)
    for step in (_nice(rough), _nice(rough, up=True)):  # the finer one unless it gives too many
        first, last = np.ceil(low / step - 1e-9), np.floor(high / step + 1e-9)
        if last - first + 1 <= most:
            break
    values = np.arange(first, last + 1) * step
    values[np.abs(values) < 1e-9 * step] = 0.0  # no "-0"
    return values, max(0, -int(np.floor(np.log10(step) + 1e-9)))


def _format(value, decimals):
    return f"{value + 0.0:.{decimals}f}"


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


def shown_values(result, k, kind, field, *, plane="x2", origin=0.0, clip=False):
    """The values a picture of step ``k`` colours [SI unit]: what its colour range is taken from.

    Parameters
    ----------
    result : framework.Result
        The run.
    k : int
        Step index (non-negative).
    kind, field, plane, origin, clip
        As in :func:`render` (``field`` not None).

    Returns
    -------
    ndarray
        ``kind="map"`` or ``"surface"``: the surface field ``(n1, n2)``.
        ``kind="slice"``: the layer of cells cut by the plane, ``(n1,
        layers)`` for ``plane="x2"`` (``(n2, layers)`` for ``"x1"``); with
        ``clip`` the block of cells on the far side of the plane, ``(n1, n2
        - index, layers)`` (``(n1 - index, n2, layers)``).
    """
    if kind != "slice":
        return _surface_field(result, k, field)
    values = _volume_field(result, k, field)
    index = _plane_index(result.grid, plane, origin)
    if plane == "x2":
        return values[:, index:] if clip else values[:, index]
    return values[index:] if clip else values[index]


def check_picture(result, kind, field, *, plane="x2", origin=0.0, warp=None):
    """The field a picture shows (``field`` or the kind's default) once the picture's options are valid.

    Parameters are those of :func:`render`. Raises ParameterError naming the
    first bad one: ``kind``, ``field``, ``plane``, ``origin``, ``warp``, or a
    slice of a grid without layers.
    """
    if kind not in KINDS:
        raise ParameterError(f"kind must be one of {sorted(KINDS)}, got {kind!r}")
    field = DEFAULT_FIELD[kind] if field is None else field
    if field not in KINDS[kind]:
        raise ParameterError(f"unknown field {field!r} for kind={kind!r}; choose one of {list(KINDS[kind])}")
    if plane not in ("x1", "x2"):
        raise ParameterError(f"plane must be 'x1' or 'x2' (the slice normal), got {plane!r}")
    if kind == "slice":
        if not result.grid.layers:
            raise ParameterError("kind='slice' needs subsurface layers: the grid has layers=0; "
                                 "give Grid(..., depth=..., layers=...)")
        _plane_index(result.grid, plane, origin)
    if warp is not None and not (isinstance(warp, (int, float, np.number)) and not isinstance(warp, bool)
                                 and np.isfinite(warp) and warp > 0):
        raise ParameterError(f"warp must be a positive finite exaggeration factor, got {warp!r}")
    return field


def render(result, png, field=None, step=-1, *, kind="map", clim=None, cmap=None, warp=None,
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
        ``stress_xx`` ... ``stress_xz`` (frame z up, see :mod:`viz.meshes`).
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
        A run's inhomogeneities are outlined in black where the plane cuts
        them, and in the 3-D view also drawn whole, translucent white.
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
    window_size : tuple of int
        Picture size in pixels.
    title : str, optional
        Replaces the default title (field, step, time and load).
    font_size : int
        Base font size [pixels] of the tick labels; titles are scaled from it.

    Returns
    -------
    Rendering
        The file, the colour range, colour map, units and labels used.

    Raises
    ------
    framework.errors.ParameterError
        Unknown ``kind``, ``field`` or ``plane``, bad ``step``, or a slice of
        a result without layers.
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
         plane="x2", origin=0.0, clip=False, window_size=(1200, 900), title=None, font_size=18):
    """The scene of :func:`render` in an off-screen plotter, not yet saved: one frame of a picture or an animation.

    Parameters are those of :func:`render`.

    Returns
    -------
    plotter : pyvista.Plotter
        The scene, ready for ``plotter.screenshot``; the caller closes it.
    rendering : Rendering
        What is drawn, with ``path`` None.
    """
    field = check_picture(result, kind, field, plane=plane, origin=origin, warp=warp)
    k = meshes.step_index(result, step)
    pv = _deps.pyvista(rendering=True)
    grid = result.grid
    label, unit = KINDS[kind][field]
    time = float(result.times[k])
    length_scale, length_unit = display_unit("m", max(grid.size))
    warp_factor, heading = None, ""
    values = shown_values(result, k, kind, field, plane=plane, origin=origin, clip=clip)

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
        index = _plane_index(grid, plane, origin)
        mesh = _slice_mesh(grid, values, plane, origin)  # values: the layer of cells cut by the plane
        heading = f", plane {plane} = {_length(_centres(grid, plane)[index], length_scale, length_unit)}"
    else:
        index = _plane_index(grid, plane, origin)
        mesh = meshes.hexahedron_mesh(grid)
        n1, n2 = grid.shape
        ids = np.arange(mesh.n_cells)
        along = (ids // n1) % n2 if plane == "x2" else ids % n1
        mesh = mesh.extract_cells(ids[along >= index])  # ascending ids: the cell order of the kept block
        mesh.cell_data["values"] = meshes.cell_order(values)
        heading = f", clipped at {plane} = {_length(_centres(grid, plane)[index], length_scale, length_unit)}"
    mesh.points[:] /= length_scale

    drawn = np.asarray(mesh.cell_data["values"], dtype=float)
    scalar_range = (float(drawn.min()), float(drawn.max()))
    automatic = (-0.5, 1.5) if field == "contact" else colour_limits(*scalar_range)  # 0 and 1 mid-band
    used = check_clim(clim, unit) if clim is not None else automatic
    if not used[1] > used[0]:
        used = (used[0], used[0] + (abs(used[0]) if used[0] else 1.0))
    if cmap is None:
        cmap = DIVERGING if used[0] == -used[1] else SEQUENTIAL
    scale, shown_unit = display_unit(unit, max(abs(used[0]), abs(used[1])))
    mesh.cell_data["values"] = drawn / scale
    low, high = used[0] / scale, used[1] / scale
    bar_title = f"{label} [{shown_unit}]" if shown_unit else label

    plotter = pv.Plotter(off_screen=True, window_size=tuple(int(w) for w in window_size))
    plotter.set_background("white")
    overlay = _Overlay(plotter, font_size)
    title = title or f"{label}{heading}\n{_step_line(result, k, time)}"
    below_title = overlay.title(title)
    options = dict(scalars="values", cmap=cmap, clim=(low, high), show_edges=False, show_scalar_bar=False,
                   n_colors=2 if field == "contact" else 256)
    # room at the top for the title and half a tick label, at the left and bottom for labels and axis titles
    box = (0.12, 0.13, 0.79, min(0.86, (below_title - 1.2 * font_size) / overlay.height))
    bar = (0.12, 0.84)  # bottom and top of the colour bar, fractions of the window height
    if kind == "map":
        actor = plotter.add_mesh(mesh, lighting=False, **options)
        _contact_outline(plotter, result, k, length_scale)
        plotter.view_xy()
        bar = _fit_2d(plotter, mesh, (0, 1), box)
        axes = {0: "x1", 1: "x2"}
    elif kind == "surface":
        actor = plotter.add_mesh(mesh, smooth_shading=True, **options)
        if show_indenter:
            _indenter(plotter, result, k, warp_factor, length_scale, deepest)
        _camera_3d(plotter, mesh, azimuth=-60, elevation=28, zoom=1.05)
        axes = {0: "x1", 1: "x2"}
    elif not clip:
        actor = plotter.add_mesh(mesh, lighting=False, **options)
        # view_xz looks from -x2, view_yz from +x1
        # cut through the centres of the drawn cells, the plane the title names
        _inclusions(plotter, result, k, length_scale, plane, _centres(grid, plane)[index],
                    toward=-1 if plane == "x2" else 1, surfaces=False, at=origin)
        if plane == "x2":
            plotter.view_xz()
            bar = _fit_2d(plotter, mesh, (0, 2), box)
            axes = {0: "x1", 2: "z"}
        else:
            plotter.view_yz()
            bar = _fit_2d(plotter, mesh, (1, 2), box)
            axes = {1: "x2", 2: "z"}
    else:
        actor = plotter.add_mesh(mesh, ambient=0.6, diffuse=0.45, specular=0.0, **options)
        # the camera looks at the cut face from the removed side (-x2, resp. -x1)
        _inclusions(plotter, result, k, length_scale, plane, _corners(grid, plane)[index], toward=-1, surfaces=True)
        _camera_3d(plotter, mesh, azimuth=-55 if plane == "x2" else -145, elevation=25, zoom=0.95)
        axes = {0: "x1", 1: "x2", 2: "z"}
    axis_labels = overlay.axes(mesh.bounds, {a: f"{name} [{length_unit}]" for a, name in axes.items()},
                               frame=kind == "map" or (kind == "slice" and not clip))
    bar_labels = overlay.colour_bar(actor.mapper.lookup_table, low, high, bar_title, bar,
                                    ticks=(0.0, 1.0) if field == "contact" else None)
    return plotter, Rendering(path=None, kind=kind, field=field, step=k, time=time, unit=unit,
                              scalar_range=scalar_range, clim=used, display_unit=shown_unit, display_scale=scale,
                              warp=warp_factor, cmap=cmap, title=title, bar_title=bar_title,
                              bar_labels=bar_labels, axis_labels=axis_labels,
                              label_boxes=list(overlay.label_boxes))


@functools.lru_cache(maxsize=1)
def _font_file():
    """DejaVu Sans from matplotlib (brackets, µ, ×), or None for VTK's own font when matplotlib is missing."""
    try:
        from matplotlib import font_manager
        return font_manager.findfont("DejaVu Sans", fallback_to_default=False)
    except (ImportError, ValueError):
        return None


def _boxes_touch(a, b, gap):
    """True when the boxes ``(x0, y0, x1, y1)`` come closer than ``gap`` pixels."""
    return a[0] < b[2] + gap and b[0] < a[2] + gap and a[1] < b[3] + gap and b[1] < a[3] + gap


class _Overlay:
    """Text and lines in window pixels drawn over the scene: titles, axes, colour bar.

    Sizes are measured with VTK's text renderer, so the layout (no label
    touching another) holds in the picture. ``label_boxes`` collects the
    boxes of the axis tick labels drawn.
    """

    def __init__(self, plotter, font_size):
        self.plotter = plotter
        self.renderer = plotter.renderer
        self.width, self.height = plotter.window_size
        self.font_size = int(font_size)
        self.tick = 0.4 * self.font_size  # length of the tick marks
        self.pad = 0.35 * self.font_size  # between a tick and its label
        self.label_boxes = []
        self._measure = _deps.require("vtkmodules.vtkRenderingCore").vtkTextRenderer()
        _deps.require("vtkmodules.vtkRenderingFreeType")  # the text renderer's backend

    def _property(self, size, rotation=0.0, left=False, top=False):
        vtk_core = _deps.require("vtkmodules.vtkRenderingCore")
        prop = vtk_core.vtkTextProperty()
        prop.SetFontSize(int(size))
        prop.SetColor(0.0, 0.0, 0.0)
        prop.SetOrientation(rotation)
        font = _font_file()
        if font:
            prop.SetFontFamily(vtk_core.vtkTextProperty.GetFontFamilyFromString("File"))
            prop.SetFontFile(font)
        else:
            prop.SetFontFamilyToArial()
        prop.SetJustification(0 if left else 1)  # VTK_TEXT_LEFT, VTK_TEXT_CENTERED
        prop.SetVerticalJustification(2 if top else 1)  # VTK_TEXT_TOP, VTK_TEXT_CENTERED
        return prop

    def _size(self, text, prop):
        box = [0, 0, 0, 0]
        self._measure.GetBoundingBox(prop, text, box, self.plotter.render_window.GetDPI())
        return box[1] - box[0], box[3] - box[2]

    def _text(self, text, position, prop):
        actor = _deps.require("vtkmodules.vtkRenderingCore").vtkTextActor()
        actor.SetInput(text)
        actor.SetTextProperty(prop)
        actor.SetPosition(float(position[0]), float(position[1]))
        self.renderer.AddActor(actor)

    def _lines(self, segments, width=1.2):
        """Straight lines ``[(start, end), ...]`` in window pixels."""
        vtk_core = _deps.require("vtkmodules.vtkRenderingCore")
        pv = _deps.pyvista(rendering=True)
        points = np.array([[x, y, 0.0] for segment in segments for x, y in segment])
        poly = pv.PolyData(points, lines=np.column_stack([np.full(len(segments), 2),
                                                          np.arange(0, 2 * len(segments), 2),
                                                          np.arange(1, 2 * len(segments), 2)]).ravel())
        mapper = vtk_core.vtkPolyDataMapper2D()
        mapper.SetInputData(poly)
        actor = vtk_core.vtkActor2D()
        actor.SetMapper(mapper)
        actor.GetProperty().SetColor(0.0, 0.0, 0.0)
        actor.GetProperty().SetLineWidth(width)
        self.renderer.AddActor(actor)

    def _project(self, point):
        self.renderer.SetWorldPoint(float(point[0]), float(point[1]), float(point[2]), 1.0)
        self.renderer.WorldToDisplay()
        return np.array(self.renderer.GetDisplayPoint()[:2])

    def title(self, text):
        """The picture's title at the top left; returns the window height [px] just below it."""
        prop = self._property(1.35 * self.font_size, left=True, top=True)
        top = self.height - 0.6 * self.font_size
        self._text(text, (0.015 * self.width, top), prop)
        return top - self._size(text, prop)[1]

    def _label_box(self, text, prop, anchor, outward):
        """Box of ``text`` placed just beyond ``anchor`` in the direction ``outward`` (a unit vector)."""
        w, h = self._size(text, prop)
        centre = anchor + outward * (abs(outward[0]) * w / 2 + abs(outward[1]) * h / 2)
        return (centre[0] - w / 2, centre[1] - h / 2, centre[0] + w / 2, centre[1] + h / 2)

    def axes(self, bounds, titles, frame=False):
        """Axes with round ticks along edges of the box ``bounds`` (display length unit).

        Parameters
        ----------
        bounds : sequence of float
            ``(x0, x1, y0, y1, z0, z1)`` of the mesh.
        titles : dict
            Axis index (0, 1, 2) -> title, in drawing order.
        frame : bool
            Also draw the two edges opposite the axes (a flat 2-D picture).

        Returns
        -------
        dict
            Title -> the tick labels drawn.
        """
        b = np.asarray(bounds, dtype=float).reshape(3, 2)
        centre = self._project(b.mean(axis=1))
        prop = self._property(self.font_size)
        drawn = {}
        segments = []
        for axis, title in titles.items():
            start, end, outward, upright = self._edge(b, axis, centre)
            segments.append((start, end))
            kept = self._ticks(b[axis], start, end, outward, prop)
            for value, _, _ in kept:
                point = start + (end - start) * (value - b[axis, 0]) / (b[axis, 1] - b[axis, 0])
                segments.append((point, point + outward * self.tick))
            for _, text, box in kept:
                self._text(text, ((box[0] + box[2]) / 2, (box[1] + box[3]) / 2), prop)
            self.label_boxes += [box for _, _, box in kept]
            drawn[title] = tuple(text for _, text, _ in kept)
            # the title beyond the labels, turned along an upright axis
            title_prop = self._property(1.1 * self.font_size, rotation=90.0 if upright else 0.0)
            depth = max([abs(outward[0]) * (box[2] - box[0]) + abs(outward[1]) * (box[3] - box[1])
                         for _, _, box in kept] + [0.0])
            anchor = (start + end) / 2 + outward * (self.tick + 2 * self.pad + depth)
            box = self._label_box(title, title_prop, anchor, outward)
            self._text(title, ((box[0] + box[2]) / 2, (box[1] + box[3]) / 2), title_prop)
        if frame:
            shown = list(titles)
            corners = []
            for u, v in ((0, 0), (1, 0), (1, 1), (0, 1)):
                point = b[:, 0].copy()
                point[shown[0]], point[shown[1]] = b[shown[0], u], b[shown[1], v]
                corners.append(self._project(point))
            segments += [(corners[i], corners[(i + 1) % 4]) for i in range(4)]
        self._lines(segments)
        return drawn

    def _edge(self, b, axis, centre):
        """The box edge along ``axis`` to draw it on: the lowest on screen, or the leftmost for an upright axis.

        An axis is upright when it is z in a 3-D view or within about 18 degrees
        of the vertical on screen. Returns the edge's ends in window pixels, the
        unit vector pointing away from the box and whether the axis is upright.
        """
        others = [i for i in range(3) if i != axis]
        edges = []
        for u in b[others[0]]:
            for v in b[others[1]]:
                low, high = np.empty(3), np.empty(3)
                low[others], high[others] = (u, v), (u, v)
                low[axis], high[axis] = b[axis]
                edges.append((self._project(low), self._project(high)))
        along = edges[0][1] - edges[0][0]
        upright = abs(along[1]) > 3 * abs(along[0]) or (axis == 2 and abs(along[1]) > abs(along[0]))
        start, end = min(edges, key=lambda e: (e[0][0] + e[1][0]) if upright else (e[0][1] + e[1][1]))
        along = end - start
        outward = np.array([-along[1], along[0]]) / max(np.linalg.norm(along), 1e-30)
        if np.dot(outward, (start + end) / 2 - centre) < 0:
            outward = -outward
        return start, end, outward, upright

    def _ticks(self, limits, start, end, outward, prop):
        """``(value, label, box)`` of the ticks of one axis.

        The most round ticks (at most 7) whose labels keep apart: a font size
        along a horizontal axis, a third of it along an upright one, and half
        a font size from the labels of the axes drawn before (at a shared
        corner the later axis gives way). When not even two fit, one label.
        """
        low, high = limits
        if not high > low:
            return []
        along = (end - start) / max(np.linalg.norm(end - start), 1e-30)
        gap = self.font_size * (abs(along[0]) + abs(along[1]) / 3)
        single = []
        for most in range(7, 1, -1):
            values, decimals = nice_ticks(low, high, most)
            anchors = [start + (end - start) * (v - low) / (high - low) + outward * (self.tick + self.pad)
                       for v in values]
            placed = [(v, _format(v, decimals), anchor) for v, anchor in zip(values, anchors)]
            placed = [(v, text, self._label_box(text, prop, anchor, outward)) for v, text, anchor in placed]
            placed = [item for item in placed
                      if not any(_boxes_touch(item[2], other, 0.5 * self.font_size) for other in self.label_boxes)]
            single = placed[:1] or single  # the coarsest ticks give the roundest lone label
            if len(placed) >= 2 and not any(_boxes_touch(a[2], b[2], gap) for a, b in zip(placed, placed[1:])):
                return placed
        return single

    def colour_bar(self, lookup_table, low, high, title, extent, ticks=None):
        """Vertical colour bar at the right with round ticks (display unit) and ``title`` above it.

        ``extent``: (bottom, top) of the picture as fractions of the window
        height; the bar spans it, or 45 % of the window about its middle when
        it is flatter. Returns the tick labels.
        """
        vtk_annotation = _deps.require("vtkmodules.vtkRenderingAnnotation")
        vtk_common = _deps.require("vtkmodules.vtkCommonCore")
        bar = vtk_annotation.vtkScalarBarActor()
        bar.SetLookupTable(lookup_table)
        bar.SetOrientationToVertical()
        height = max(extent[1] - extent[0], 0.45)
        left, bottom, width = 0.83, (extent[0] + extent[1] - height) / 2, 0.06
        bar.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
        bar.GetPositionCoordinate().SetValue(left, bottom)
        bar.SetWidth(width)
        bar.SetHeight(height)
        bar.SetTitle("")
        bar.UnconstrainedFontSizeOn()
        bar.SetLabelTextProperty(self._property(1.15 * self.font_size))
        bar.GetLabelTextProperty().SetJustificationToLeft()
        if ticks is None:
            values, decimals = nice_ticks(low, high, 7)
        else:
            values, decimals = np.asarray(ticks, dtype=float), 0
        custom = vtk_common.vtkDoubleArray()
        for value in values:
            custom.InsertNextValue(float(value))
        bar.SetUseCustomLabels(True)
        bar.SetCustomLabels(custom)
        bar.SetLabelFormat(f"%.{decimals}f")
        self.renderer.AddActor(bar)
        prop = self._property(1.2 * self.font_size, left=True)
        w, h = self._size(title, prop)
        x = min(left * self.width, self.width - 0.6 * self.font_size - w)
        self._text(title, (x, (bottom + height) * self.height + 0.8 * self.font_size + h / 2), prop)
        return tuple(_format(v, decimals) for v in values)


def _fit_2d(plotter, mesh, axes, box):
    """Parallel projection placing the mesh's extent along ``axes`` (horizontal, vertical) in ``box``.

    ``box`` = (left, bottom, right, top) as fractions of the window: room for
    the axes' labels, the colour bar on the right and the title on top.
    Returns the mesh's bottom and top as fractions of the window height.
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
    distance = np.linalg.norm(np.subtract(camera.position, camera.focal_point))
    camera.focal_point = tuple(focal)
    camera.position = tuple(focal + distance * direction)
    camera.parallel_scale = per_pixel * height / 2
    plotter.renderer.ResetCameraClippingRange()
    middle, half = (box[1] + box[3]) / 2, (v1 - v0) / per_pixel / height / 2
    return middle - half, middle + half


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


def _step_line(result, k, time):
    """The second title line: which step, and the state of the body (rolling: its speed or position)."""
    line = f"load {result.load[k]:.4g} N, approach {_length(result.approach[k])}"
    schedule = result.schedule
    if getattr(schedule, "velocity", None) is None:
        return f"step {k}, t = {_format_time(time)}, {line}"
    if schedule.steady:
        return (f"step {k}, steady rolling at {schedule.speed:.4g} m/s, {line}, "
                f"\u03bc = {result.friction_coefficient[k]:.3g}")
    rolled = float(np.linalg.norm(result.position[k]))
    return (f"step {k}, t = {_format_time(time)}, rolled {_length(rolled) if rolled else '0'}, {line}, "
            f"\u03bc = {result.friction_coefficient[k]:.3g}")


def _length(value, scale=None, unit=None):
    if scale is None:
        scale, unit = display_unit("m", value)
    return f"{value / scale:.4g} {unit}"


def _centres(grid, plane):
    return grid.x2 if plane == "x2" else grid.x1


def _corners(grid, plane):
    return meshes.corner_coordinates(grid)[1 if plane == "x2" else 0]


def _plane_index(grid, plane, origin):
    axis = 1 if plane == "x2" else 0
    half = grid.size[axis] / 2
    if not np.isfinite(origin) or abs(origin) > half:
        raise ParameterError(f"origin of the {plane} slice must lie in [-{half:g}, {half:g}] m, got {origin!r}")
    return int(np.clip(np.floor((origin + half) / grid.spacing[axis]), 0, grid.shape[axis] - 1))


def _slice_mesh(grid, cut, plane, origin):
    """Quads of the cells cut by the plane: (along, depth) with their exact values ``cut`` (along, layers)."""
    c1, c2 = meshes.corner_coordinates(grid)
    z = -meshes.layer_boundaries(grid)
    a, zz = np.meshgrid(c1 if plane == "x2" else c2, z, indexing="ij")
    if plane == "x2":
        points = np.stack([a, np.full_like(a, origin), zz], axis=-1)
    else:
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
    # zero padding closes the outline along the grid's open edges; a periodic axis wraps (no edge there)
    padded = contact
    for axis, periodic in enumerate(grid.periodic):
        width = [(0, 0), (0, 0)]
        width[axis] = (1, 1)
        padded = np.pad(padded, width, mode="wrap" if periodic else "constant")
    corners = meshes.corner_average(padded, (False, False))[1:-1, 1:-1]
    mesh.point_data["contact"] = corners.ravel(order="F")
    outline = mesh.contour([0.5], scalars="contact")
    if outline.n_points:
        plotter.add_mesh(outline, color="white", line_width=3, lighting=False, label="contact edge")


def _inclusions(plotter, result, k, length_scale, plane, cut, toward, surfaces, at=None):
    """The inhomogeneities of step ``k``'s slice picture: their section by the plane ``plane = cut`` [m] as black curves.

    They are material points: under a rolling body (pictures in the body's frame) they
    lie ``result.position[k]`` behind where they started.

    The curves are drawn in the plane ``plane = at`` (default ``cut``: that
    of the coloured cells) moved off it by 0.1 % of the grid side ``toward``
    the camera (+1: along +x2, resp. +x1) so that no cell hides them; with
    ``surfaces`` the ellipsoids are drawn too, translucent (the
    parts inside the drawn cells stay hidden by them).
    """
    if not getattr(result, "inclusions", None):
        return
    mesh = meshes.inclusion_mesh(result.inclusions)
    mesh.points[:, :2] -= np.asarray(result.position[k], dtype=float)
    mesh.points[:] /= length_scale
    axis = 1 if plane == "x2" else 0
    origin = np.zeros(3)
    origin[axis] = cut / length_scale
    outline = mesh.slice(normal=tuple(np.eye(3)[axis]), origin=tuple(origin))
    if surfaces:
        plotter.add_mesh(mesh, color="white", opacity=0.45, smooth_shading=True, show_scalar_bar=False)
    if outline.n_points:
        outline.points[:, axis] = (cut if at is None else at) / length_scale \
            + toward * 1e-3 * max(result.grid.size) / length_scale
        plotter.add_mesh(outline, color="black", line_width=3, lighting=False, label="inhomogeneity")


def _indenter(plotter, result, k, warp_factor, length_scale, deepest):
    """The indenter, exaggerated like the surface, shown up to a little above the undeformed plane."""
    grid = result.grid
    mesh = meshes.indenter_mesh(result, k)  # at its position, tilt included
    # lifted by 0.2 % of the grid side: in contact the indenter and the surface coincide (no z-fighting)
    mesh.points[:, 2] = warp_factor * mesh.points[:, 2] + 2e-3 * max(grid.size)
    mesh.points[:] /= length_scale
    mesh.point_data["z"] = mesh.points[:, 2].copy()
    top = max(0.3 * warp_factor * deepest, 0.02 * max(grid.size)) / length_scale
    mesh = mesh.clip_scalar(scalars="z", value=top, invert=True)
    if mesh.n_cells:
        plotter.add_mesh(mesh, color="lightgray", opacity=0.35, show_scalar_bar=False, smooth_shading=True)
