"""History plots: per-step series of a result against time, load, approach or distance rolled (matplotlib, Agg).

The figure is made with :class:`matplotlib.figure.Figure` directly (no pyplot,
no GUI backend, no global state), one panel per quantity. Lengths, areas and
pressures are shown in a readable unit (``contact radius [mm]``,
``max pressure [MPa]``, chosen like the pictures' colour bars by
:func:`viz.render.display_unit`), other quantities in SI units.
"""
import os

import numpy as np

from framework.errors import ParameterError

from . import _deps
from .render import display_unit

#: Series that can be plotted: name -> (label, SI unit, component names or None).
QUANTITIES = {
    "load": ("load", "N", None),
    "approach": ("approach", "m", None),
    "contact_area": ("contact area", "m\u00b2", None),
    "contact_radius": ("contact radius", "m", None),
    "max_pressure": ("max pressure", "Pa", None),
    "center": ("load centre", "m", ("x1", "x2")),
    "tilt": ("tilt", "rad", ("x1", "x2")),
    "half_width": ("half-width", "m", None),
    "friction_coefficient": ("friction coefficient", "-", None),
    "torque": ("torque", "N m", None),
    "dissipated_power": ("dissipated power", "W", None),
    "position": ("position", "m", ("x1", "x2")),
    "iterations": ("solver iterations", "-", None),
    "residual": ("solver residual", "-", None),
}

#: Abscissae: name -> (label, SI unit).
AGAINST = {"time": ("time", "s"), "load": ("load", "N"), "approach": ("approach", "m"),
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
    return f"{indenter} on {material}, {n1} x {n2} cells, {len(result)} steps"
