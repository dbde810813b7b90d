"""The stations of a run: its time steps, one loop's worth, computed from the schedule before the first step.

A station (:class:`Station`) is a time, the load or approach imposed then,
whether it is recorded, and the cells the material moved under a rolling body
since the previous station. They are the output times, every jump and kink of
the load history, the finer steps a periodic history needs and, for a
transient rolling run, one step per cell of motion.
"""
import math
from dataclasses import dataclass, replace

import numpy as np

from . import loads
from .errors import ParameterError

__all__ = ["MAX_STATIONS", "Station", "rolling_stations", "static_stations"]


#: The most time steps a run may take: beyond it a schedule is a mistake (e.g. a 1 ms period over a year).
MAX_STATIONS = 1_000_000

@dataclass(frozen=True)
class Station:
    """One step of a run: its time [s], the load [N] or approach [m] it imposes, whether it is recorded,
    and the whole cells ``(c1, c2)`` the material moved under the body since the previous station."""

    time: float
    value: float
    recorded: bool
    shift: tuple = (0, 0)


def static_stations(schedule, refine=True):
    """The stations of an indentation at rest: the output times, the kinks and both sides of every jump.

    With ``refine`` (a material with memory), every gap between them that lies
    in an interval of the history's ``resolution`` is split into equal steps
    no longer than its ``max_step`` (unrecorded stations).
    """
    history, times = schedule.history, schedule.times
    last = times[-1]
    jumps = {float(t) for t in history.jumps if t <= last}
    kinks = {float(t) for t in history.kinks if 0 < t <= last}
    outputs = {float(t) for t in times}
    limits = [(start, min(end, last), step) for start, end, step in history.resolution
              if start < min(end, last)] if refine else []
    keys = sorted(outputs | jumps | kinks | {t for start, end, _ in limits for t in (start, end)})

    def pieces(a, b):  # equal steps no longer than the finest max_step of the intervals holding [a, b]
        step = min((h for start, end, h in limits if start <= a and b <= end), default=None)
        return 1 if step is None else math.ceil((b - a) / step)

    splits = [pieces(a, b) for a, b in zip(keys, keys[1:])]
    _check_count(len(keys) + len(jumps) + sum(splits) - len(splits), last)
    inner = {a + (b - a) * k / n for a, b, n in zip(keys, keys[1:], splits) for k in range(1, n)}
    every = np.array(sorted(set(keys) | inner))
    stations = []
    for t, value in zip(every.tolist(), history(every).tolist()):
        before = float(history.left(t)) if t in jumps else value
        # both sides of a jump: a step of zero duration between them (a jump to the same value is none; the
        # left limit is taken a hair before t, so a steep ramp's left limit differs from its value by rounding)
        if not math.isclose(before, value, rel_tol=1e-9):
            stations.append(Station(t, before, False))
        stations.append(Station(t, value, t in outputs))
    return stations


def _check_count(count, last):
    if count > MAX_STATIONS:
        raise ParameterError(
            f"the schedule needs {count} time steps up to t = {last:g} s (a sine history is followed with "
            f"{loads.STATIONS_PER_PERIOD} steps per period, rolling with one per cell), more than {MAX_STATIONS}: "
            f"shorten the times or the distance, or lengthen the period")


def rolling_stations(schedule, grid, refine=True):
    """The stations of a rolling run: the rest indentation, then one per cell of motion (transient),
    or one per load (steady, at the times 0, 1, 2 ..., like the default times of a list of loads)."""
    if schedule.steady:
        if len(schedule.loads) > MAX_STATIONS:
            raise ParameterError(f"load: a steady run solves one steady state per load, got {len(schedule.loads)} "
                                 f"loads, more than {MAX_STATIONS}: sample the loads more coarsely")
        return [Station(float(k), value, True) for k, value in enumerate(schedule.loads)]
    axis, speed = schedule.axis, schedule.speed
    cell, step = grid.spacing[axis], grid.spacing[axis] / speed        # [m], [s]
    if schedule.times is not None:
        cells = schedule.times / step
        whole = np.round(cells)
        bad = np.abs(cells - whole) > 1e-6 * np.maximum(1.0, whole)
        if bad.any():
            t = float(schedule.times[np.argmax(bad)])
            raise ParameterError(
                f"times: the body moves one cell ({cell:g} m) every {step:g} s and the material under it by whole "
                f"cells only; {t:g} s is {t / step:.4g} cells of motion, not a whole number of cells: use multiples "
                f"of {step:g} s (nearest {round(t / step) * step:g} s)")
        outputs = {int(k) for k in whole}
    if schedule.distance is not None:
        count = int(round(schedule.distance / cell))
        if count < 1:
            raise ParameterError(f"distance {schedule.distance:g} m is shorter than one cell ({cell:g} m along the "
                                 f"motion): the material moves by whole cells; roll at least {cell:g} m")
        if schedule.times is not None and max(outputs) > count:
            raise ParameterError(f"times: {float(schedule.times[-1]):g} s lies beyond the end of the motion "
                                 f"(distance {count * cell:g} m at {speed:g} m/s: {count * step:g} s)")
    else:
        count = max(outputs)
    if schedule.times is None:
        outputs = set(range(count + 1))
    stations = static_stations(schedule.start, refine) if schedule.start is not None else []
    begin = schedule.motion_start
    _check_count(len(stations) + count + 1, begin + count * step)
    value = float(schedule.history(0.0))
    if stations and math.isclose(stations[-1].value, value, rel_tol=1e-9):
        if 0 in outputs and not stations[-1].recorded:   # the start's last station is the rest at the motion's start
            stations[-1] = replace(stations[-1], recorded=True)
    else:  # (a start's last station is recorded already: one record per time)
        stations.append(Station(begin, value, 0 in outputs and not (stations and stations[-1].recorded)))
    shift = [0, 0]
    shift[axis] = -int(np.sign(schedule.velocity[axis]))  # the material moves against the body, a cell a step
    loads_at = schedule.history(np.arange(1, count + 1) * step)
    stations += [Station(begin + k * step, float(loads_at[k - 1]), k in outputs, tuple(shift))
                 for k in range(1, count + 1)]
    return stations
