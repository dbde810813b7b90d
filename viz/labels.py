"""The words of a picture: axis titles, the title's lines, lengths and times, typeset with mathtext.

Symbols are written as matplotlib mathtext (``$x_1$``, ``$\\mu$``), which VTK
draws through matplotlib (``vtkRenderingMatplotlib``) and matplotlib's own
figures draw natively. Lengths are written in one style everywhere: the SI
prefix that gives the value 1 to 999 (:func:`length`: ``12.5 µm``,
``1.44 mm``), the µ sign, four significant digits. Without matplotlib,
:func:`plain` turns mathtext into plain Unicode (``x₁``, ``μ``).
"""
import functools
import importlib
import re

import numpy as np

from .scales import display_unit

#: Name of each axis of the scene (x1, x2 and z up, see :mod:`viz.meshes`).
AXES = {0: "$x_1$", 1: "$x_2$", 2: "$z$"}

#: Slice normal name -> its mathtext.
PLANES = {"x1": "$x_1$", "x2": "$x_2$"}

_SUBSCRIPTS = str.maketrans("0123456789", "\u2080\u2081\u2082\u2083\u2084\u2085\u2086\u2087\u2088\u2089")
_SYMBOLS = {"\\mu": "\u03bc", "\\sigma": "\u03c3", "\\omega": "\u03c9", "\\delta": "\u03b4", "\\times": "\u00d7"}


def axis_title(axis, unit):
    """``$x_1$ [mm]``: the title of axis 0, 1 or 2 with its display unit."""
    return f"{AXES[axis]} [{unit}]"


def length(value, scale=None, unit=None):
    """A length [m] as text: ``12.5 µm``, ``0`` (the unit from its size unless ``scale`` and ``unit`` are given)."""
    if value == 0:
        return "0"
    if scale is None:
        scale, unit = display_unit("m", value)
    return f"{value / scale + 0.0:.4g} {unit}"


def duration(t):
    """A time [s] as text, ``0.25 s``."""
    return f"{t:.4g} s"


def step_line(result, k, time):
    """The title's second line: which step, and the state of the body (rolling: how far it rolled)."""
    line = f"load {result.load[k]:.4g} N, approach {length(result.approach[k])}"
    schedule = result.schedule
    if getattr(schedule, "velocity", None) is None:
        return f"step {k}, t = {duration(time)}, {line}"
    friction = f"$\\mu$ = {result.friction_coefficient[k]:.3g}"
    if schedule.steady:
        return f"step {k}, steady rolling at {schedule.speed:.4g} m/s, {line}, {friction}"
    rolled = float(np.linalg.norm(result.position[k]))
    return f"step {k}, t = {duration(time)}, rolled {length(rolled)}, {line}, {friction}"


def with_unit(label, unit):
    """``label [unit]``, or the label alone for a dimensionless field."""
    return f"{label} [{unit}]" if unit else label


@functools.lru_cache(maxsize=1)
def mathtext_available():
    """True when VTK can draw mathtext: its matplotlib module imports (matplotlib installed)."""
    try:
        importlib.import_module("matplotlib")
        importlib.import_module("vtkmodules.vtkRenderingMatplotlib")  # registers VTK's MathText backend
    except ImportError:
        return False
    return True


def plain(text):
    """Mathtext as plain Unicode: ``$x_1$`` -> ``x₁``, ``$\\sigma_{xz}$`` -> ``σxz``, ``$\\mu$`` -> ``μ``."""
    def convert(match):
        inner = match.group(1)
        for command, symbol in _SYMBOLS.items():
            inner = inner.replace(command, symbol)
        inner = re.sub(r"_\{?(\d+)\}?", lambda m: m.group(1).translate(_SUBSCRIPTS), inner)
        return re.sub(r"[_{}\\]", "", inner)
    return re.sub(r"\$([^$]*)\$", convert, text)
