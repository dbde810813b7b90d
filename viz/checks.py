"""Checks of the arguments of :func:`viz.render` and :func:`viz.animate`, made before anything is drawn.

Each raises :class:`framework.errors.ParameterError` naming the argument, the
value received and what was expected. The window is bounded before VTK
allocates it: an off-screen window of 100000 x 100000 pixels would take 40 GB
and VTK aborts the interpreter when the allocation fails.
"""
import numbers
import os

import numpy as np

from framework.errors import ParameterError

from . import slices
from .fields import DEFAULT_FIELD, KINDS

#: Least and largest side of a picture [px], and its largest area (4096 x 4096, 64 MB of RGBA).
SMALLEST_SIDE, LARGEST_SIDE, LARGEST_AREA = 16, 8192, 4096 * 4096

#: Least and largest base font size [px].
SMALLEST_FONT, LARGEST_FONT = 4, 200


def as_result(result, name="result"):
    """``result``, or the result saved in the file it names (``result.h5``), read by :func:`framework.load_result`."""
    if not isinstance(result, (str, bytes, os.PathLike)):
        if not (hasattr(result, "grid") and hasattr(result, "times")):
            raise ParameterError(f"{name} must be a framework.Result or the path of a saved result file "
                                 f"(result.h5), got {type(result).__name__}: {result!r:.80}")
        return result
    from framework import load_result
    try:
        return load_result(result)
    except ParameterError as exc:
        text = str(exc)
        text = text[len("path: "):] if text.startswith("path: ") else text
        try:
            error = type(exc)(f"{name}: cannot load the result file: {text}")
        except TypeError:
            error = ParameterError(f"{name}: cannot load the result file: {text}")
        raise error from exc


def _whole(value):
    return (isinstance(value, numbers.Real) and not isinstance(value, bool) and np.isfinite(value)
            and float(value) == int(value))


def check_window_size(window_size, name="window_size"):
    """``window_size`` as two ints ``(width, height)`` [px], or None (sized to the field); else ParameterError."""
    if window_size is None:
        return None
    try:
        pair = tuple(window_size)
    except TypeError:
        pair = ()
    if len(pair) != 2 or not all(_whole(n) and SMALLEST_SIDE <= n <= LARGEST_SIDE for n in pair) \
            or pair[0] * pair[1] > LARGEST_AREA:
        raise ParameterError(f"{name} must be two whole numbers of pixels (width, height), each in "
                             f"[{SMALLEST_SIDE}, {LARGEST_SIDE}] and at most {LARGEST_AREA} pixels in all "
                             f"(4096 x 4096), or None to size the picture to the field; got {window_size!r}")
    return int(pair[0]), int(pair[1])


def check_font_size(font_size, name="font_size"):
    """``font_size`` as an int [px] in [:data:`SMALLEST_FONT`, :data:`LARGEST_FONT`], or ParameterError."""
    if not (isinstance(font_size, numbers.Real) and not isinstance(font_size, bool) and np.isfinite(font_size)
            and SMALLEST_FONT <= font_size <= LARGEST_FONT):
        raise ParameterError(f"{name} must be a number of pixels in [{SMALLEST_FONT}, {LARGEST_FONT}] "
                             f"(the tick labels' size; titles are scaled from it), got {font_size!r}")
    return int(round(font_size))


def check_cmap(cmap, name="cmap"):
    """``cmap`` once pyvista knows it (a matplotlib colour map name or Colormap), None kept; else ParameterError."""
    if cmap is None:
        return None
    from . import _deps
    colors = _deps.require("pyvista.plotting.colors")
    try:
        colors.get_cmap_safe(cmap)
    except (ValueError, TypeError, KeyError) as exc:
        raise ParameterError(f"{name} must be the name of a matplotlib colour map such as 'viridis', 'coolwarm' "
                             f"or 'magma' (or a matplotlib Colormap), got {cmap!r}") from exc
    return cmap


def check_clim(clim, unit):
    """``clim`` as two finite floats ``(low, high)`` [SI unit], or ParameterError naming it."""
    try:
        used = tuple(float(c) for c in clim)
    except (TypeError, ValueError):
        used = ()
    if len(used) != 2 or not all(np.isfinite(used)):
        raise ParameterError(f"clim must be two finite numbers (low, high) in {unit or 'the field unit'}, "
                             f"got {clim!r}")
    if not used[0] < used[1]:
        raise ParameterError(f"clim must be (low, high) with low < high in {unit or 'the field unit'}, got {clim!r}: "
                             f"the colour range is used as given, never silently replaced")
    return used


def check_picture(result, kind, field, *, plane="x2", origin=0.0, warp=None):
    """The field a picture shows (``field`` or the kind's default) once the picture's options are valid.

    Parameters are those of :func:`viz.render`. Raises ParameterError naming
    the first bad one: ``kind``, ``field``, ``plane``, ``origin``, ``warp``,
    or a slice of a grid without layers.
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
        slices.plane_index(result.grid, plane, origin)
    if warp is not None and not (isinstance(warp, (int, float, np.number)) and not isinstance(warp, bool)
                                 and np.isfinite(warp) and warp > 0):
        raise ParameterError(f"warp must be a positive finite exaggeration factor, got {warp!r}")
    return field


def check_options(result, kind, field, *, clim=None, cmap=None, warp=None, plane="x2", origin=0.0,
                  window_size=None, font_size=18):
    """Every option of a picture checked (see the functions above): ``(field, clim, cmap, window_size, font_size)``."""
    field = check_picture(result, kind, field, plane=plane, origin=origin, warp=warp)
    if clim is not None:
        clim = check_clim(clim, KINDS[kind][field][1])
    return field, clim, check_cmap(cmap), check_window_size(window_size), check_font_size(font_size)
