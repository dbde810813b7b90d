"""Colour scales, display units and round ticks: the numbers a picture shows, from the SI values.

By default a picture's colour range is the field's own minimum and maximum,
with ends closer to zero than :data:`SNAP` times the range taken as zero
(round-off: a contact-free surface shows ``0``, not ``-7.6e-09``); a field
taking both signs gets limits symmetric about zero and the diverging map
:data:`DIVERGING` (white-grey at zero), a one-signed field the sequential
:data:`SEQUENTIAL`. Values are shown in a readable unit (:func:`display_unit`:
MPa, µm, mm ...); ticks fall on round values, 1, 2 or 5 times a power of ten
(:func:`nice_ticks`).
"""
import numpy as np

#: Colour map of fields of one sign, and of fields of both signs (limits symmetric about zero).
SEQUENTIAL, DIVERGING = "viridis", "coolwarm"

#: Automatic colour limits closer to zero than this fraction of the range are round-off, shown as 0.
SNAP = 1e-6

#: SI unit -> the (scale, name) it may be shown in, largest first.
PREFIXES = {"Pa": ((1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa"), (1.0, "Pa")),
            "m": ((1.0, "m"), (1e-3, "mm"), (1e-6, "\u00b5m"), (1e-9, "nm")),
            "m\u00b2": ((1.0, "m\u00b2"), (1e-6, "mm\u00b2"))}  # contact areas read best in mm²


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
    choices = PREFIXES.get(unit)
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
    return float(nice(0.25 * max(grid.size) / deepest)) if deepest > 0 else 1.0


def nice(value, up=False):
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
    for step in (nice(rough), nice(rough, up=True)):  # the finer one unless it gives too many
        first, last = np.ceil(low / step - 1e-9), np.floor(high / step + 1e-9)
        if last - first + 1 <= most:
            break
    values = np.arange(first, last + 1) * step
    values[np.abs(values) < 1e-9 * step] = 0.0  # no "-0"
    return values, max(0, -int(np.floor(np.log10(step) + 1e-9)))


def format_tick(value, decimals):
    """``value`` with ``decimals`` decimals, never ``-0``."""
    return f"{value + 0.0:.{decimals}f}"
