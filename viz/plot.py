"""History plots: per-step series of a result against time, load, approach or distance rolled (matplotlib, Agg).

The figure is made with :class:`matplotlib.figure.Figure` directly (no pyplot,
no GUI backend, no global state), one panel per quantity. Lengths, areas and
pressures are shown in a readable unit (``contact radius $a$ [mm]``,
``peak pressure $p_\\mathrm{max}$ [MPa]``, chosen like the pictures' colour bars by
:func:`viz.scales.display_unit`), other quantities in SI units; symbols are
mathtext. A result of one step has no history to draw: its values are written
out instead, one line per quantity.
"""
import os

import numpy as np

from framework.errors import ParameterError

from . import _deps
from .scales import display_unit

#: Series that can be plotted: name -> (label, SI unit, component names or None). Symbols in mathtext.
QUANTITIES = {
    "load": ("load $W$", "N", None),
    "approach": ("approach $\\delta$", "m", None),
    "contact_area": ("contact area $A$", "m\u00b2", None),
    "contact_radius": ("contact radius $a$", "m", None),
    "max_pressure": ("peak pressure $p_\\mathrm{max}$", "Pa", None),
    "center": ("load centre", "m", ("$x_1$", "$x_2$")),
    "tilt": ("tilt", "rad", ("$x_1$", "$x_2$")),
    "half_width": ("half-width $b$", "m", None),
    "friction_coefficient": ("friction coefficient $\\mu$", "-", None),
    "torque": ("torque", "N m", None),
    "dissipated_power": ("dissipated power", "W", None),
    "position": ("position", "m", ("$x_1$", "$x_2$")),
    "iterations": ("solver iterations", "-", None),
    "residual": ("solver residual", "-", None),
}

#: Abscissae: name -> (label, SI unit).
AGAINST = {"time": ("time $t$", "s"), "load": ("load $W$", "N"), "approach": ("approach $\\delta$", "m"),
           "position": ("distance rolled", "m")}

DEFAULT = ("load", "approach", "contact_radius", "max_pressure")


def _series(result, name):
    if name == "time":
        return np.asarray(result.times, dtype=float)
    return np.asarray(getattr(result, name), dtype=float)


def _abscissa(result, name):
    """The x values: a series, or for ``position`` the distance the body has rolled."""
    if name == "position":
        return np.linalg.norm(_series(result, "position"), axis=1)
    return _series(result, name)


def plot_history(result, png, quantities=DEFAULT, *, against="time", xscale=None, title=None, dpi=120):
    """Plot per-step series of a result, one panel per quantity, into a PNG file.

    Parameters
    ----------
    result : framework.Result
        The run.
    png : str or path
        Output file (its folder must exist); the format follows the extension.
    quantities : str or sequence of str
        Any of ``load`` [N], ``approach`` [m], ``contact_area`` [m^2],
        ``contact_radius`` [m], ``max_pressure`` [Pa], ``center`` [m] (x1 and
        x2), ``tilt`` [rad] (two components), ``half_width`` [m] (line
        contacts), ``friction_coefficient`` [-], ``torque`` [N m],
        ``dissipated_power`` [W], ``position`` [m] (x1 and x2: a rolling
        body's), ``iterations``, ``residual``. Default: load, approach,
        contact radius and peak pressure.
    against : {"time", "load", "approach", "position"}
        Abscissa: time [s] (default), load [N], approach [m] or the distance
        a rolling body has travelled [m].
    xscale : {"linear", "log", "symlog"}, optional
        Abscissa scale. Default: for time, ``symlog`` (linear below the first
        positive time, so t = 0 stays visible) when the positive times span
        more than two decades, else linear; linear otherwise.
    title : str, optional
        Figure title; default: indenter, material and number of steps.
        A result of one step gets its values written out, one line per
        quantity, instead of panels of a single point.
    dpi : int
        Resolution [dots per inch].

    Returns
    -------
    str
        The path written.

    Raises
    ------
    framework.errors.ParameterError
        Unknown quantity, abscissa or scale, or a result without steps.
    ImportError
        matplotlib is missing (``pip install 'viscocontact[viz]'``).
    """
    if isinstance(quantities, str):
        quantities = [quantities]
    quantities = list(quantities)
    if not quantities:
        raise ParameterError(f"quantities must name at least one of {list(QUANTITIES)}, got an empty list")
    for name in quantities:
        if name not in QUANTITIES:
            raise ParameterError(f"unknown quantity {name!r}; choose from {list(QUANTITIES)}")
    if against not in AGAINST:
        raise ParameterError(f"against must be one of {list(AGAINST)}, got {against!r}")
    if xscale not in (None, "linear", "log", "symlog"):
        raise ParameterError(f"xscale must be 'linear', 'log', 'symlog' or None, got {xscale!r}")
    if len(result) == 0:
        raise ParameterError("the result has no steps to plot")
    figure_module = _deps.require("matplotlib.figure")
    if len(result) == 1:
        return _values(result, png, quantities, figure_module, title, dpi)
    xlabel, xunit = AGAINST[against]
    x = _abscissa(result, against)
    x_scale, xunit = display_unit(xunit, _magnitude(x))
    x = x / x_scale
    positive = x[x > 0]
    if xscale is None:
        xscale = "linear"
        if against == "time" and positive.size and positive.max() / positive.min() > 100:
            xscale = "symlog"
    figure = figure_module.Figure(figsize=(8.0, 1.2 + 2.3 * len(quantities)), dpi=dpi, layout="constrained")
    axes = figure.subplots(len(quantities), 1, sharex=True, squeeze=False)[:, 0]
    for ax, name in zip(axes, quantities):
        label, unit, components = QUANTITIES[name]
        y = _series(result, name)
        resolution = _resolution(result, name)
        y_scale, unit = display_unit(unit, max(_magnitude(y), resolution))
        y, resolution = y / y_scale, resolution / y_scale
        if components:
            for c, component in enumerate(components):
                ax.plot(x, y[:, c], "o-", markersize=3, label=component)
            ax.legend(loc="best", fontsize="small")
        else:
            ax.plot(x, y, "o-", markersize=3)
        ax.set_ylabel(f"{label} [{unit}]")
        low, high = np.nanmin(y, initial=np.inf), np.nanmax(y, initial=-np.inf)
        if high - low < resolution:  # round-off, not a change: keep it flat
            middle = (low + high) / 2 if np.isfinite(low + high) else 0.0
            ax.set_ylim(middle - resolution, middle + resolution)
        ax.grid(True, alpha=0.3)
        if name != "residual" and name != "iterations":
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4), useMathText=True)
        elif name == "residual" and np.all(y > 0):
            ax.set_yscale("log")
    bottom = axes[-1]
    if xscale == "symlog":
        bottom.set_xscale("symlog", linthresh=float(positive.min()))
    elif xscale == "log":
        if not positive.size:
            raise ParameterError(f"xscale='log' needs positive {against} values")
        bottom.set_xscale("log")
    else:
        bottom.ticklabel_format(axis="x", style="sci", scilimits=(-3, 4), useMathText=True)
    bottom.set_xlabel(f"{xlabel} [{xunit}]" + (" (symlog scale)" if xscale == "symlog" else ""))
    figure.suptitle(title if title is not None else _default_title(result))
    path = os.fspath(png)
    figure.savefig(path)
    return path


def _magnitude(values):
    """Largest finite absolute value (0 when there is none): picks the display unit."""
    values = np.abs(np.asarray(values, dtype=float))
    return float(np.max(values[np.isfinite(values)], initial=0.0))


def _resolution(result, name):
    """Smallest change of a series that is not round-off, in its SI unit (0: any change counts).

    The load centre of a symmetric contact wanders by 1e-14 m of round-off;
    plotted on its own scale that looks like motion. Its axis spans at least
    half a cell either side.
    """
    return 0.5 * min(result.grid.spacing) if name == "center" else 0.0


def _default_title(result):
    indenter, material = type(result.indenter).__name__, type(result.material).__name__
    n1, n2 = result.grid.shape
    steps = len(result)
    return f"{indenter} on {material}, {n1} \u00d7 {n2} cells, {steps} step{'' if steps == 1 else 's'}"


def value_text(result, name, k=0):
    """``contact radius $a$ = 149.3 µm``: one quantity of step ``k`` in its readable unit."""
    label, unit, components = QUANTITIES[name]
    y = np.asarray(_series(result, name), dtype=float)[k]
    scale, unit = display_unit(unit, max(_magnitude(y), _resolution(result, name)))
    shown = np.atleast_1d(y / scale)
    shown = np.where(np.abs(shown) < 1e-9 * max(np.max(np.abs(shown)), 1e-300), 0.0, shown) + 0.0
    numbers = ", ".join(f"{v:.4g}" for v in shown)
    if components:
        numbers = f"({numbers})"
        label = f"{label} ({', '.join(components)})"
    return f"{label} = {numbers}" + (f" {unit}" if unit and unit != "-" else "")


def _values(result, png, quantities, figure_module, title, dpi):
    """The one step of a result as text: a line per quantity (a plot of one point would show nothing)."""
    lines = [value_text(result, name) for name in quantities]
    figure = figure_module.Figure(figsize=(8.0, 1.3 + 0.42 * len(lines)), dpi=dpi)
    head = title if title is not None else _default_title(result)
    figure.text(0.5, 1.0 - 0.35 / figure.get_figheight(), head, ha="center", va="top", fontsize="large")
    figure.text(0.06, 1.0 - 0.8 / figure.get_figheight(), f"the values at t = {float(result.times[0]):.4g} s "
                "(one step: no history to plot)", ha="left", va="top", color="0.35")
    for i, line in enumerate(lines):
        figure.text(0.06, 1.0 - (1.25 + 0.42 * i) / figure.get_figheight(), line, ha="left", va="top",
                    fontsize="large")
    path = os.fspath(png)
    figure.savefig(path)
    return path
