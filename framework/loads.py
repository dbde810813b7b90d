"""Histories of load [N] or approach [m] in time [s].

A history is a right-continuous function of time, zero before it starts. Its
``jumps`` are the times where it is discontinuous and its ``kinks`` the times
where its slope changes; the time stepper puts a station at each (a jump is
applied with zero time increment), so a piecewise-linear history is followed
exactly by the piecewise-linear pressure of the Prony recursions. A smooth
curved history (a sine) says in ``resolution`` how finely it must be followed:
on a material with memory the stepper adds unrecorded stations there, so that
no step is longer than ``max_step`` whatever the output times (output times
once per period would otherwise sample a sine at one phase and treat the load
as constant in between).

Times and durations are 0 or lie between 1e-15 and 1e15 s
(``framework._validation.LIMITS``); the schedule bounds the values.

Every history can stand alone (it starts at t = 0, or at ``start``/``at``)
or be a segment of a :class:`Sequence`, which chains them: each segment starts
where and when the previous one ended.
"""
from dataclasses import dataclass

import numpy as np

from ._validation import LIMITS, check_finite_array, check_non_negative, check_positive_int, check_quantity, check_real
from .errors import ParameterError


#: Time steps per period with which the stepper follows a sine :class:`Cyclic` history.
STATIONS_PER_PERIOD = 32


class History:
    """Base class of load and approach histories.

    Subclasses define ``span`` (the segment's length [s]) and ``segment(tau, start_value)``: the value
    ``tau >= 0`` after the segment's start when it starts from ``start_value``,
    plus ``segment_jumps``/``segment_kinks`` relative to the start. A history
    alone starts from 0 at time 0.
    """

    segment_jumps = ()
    segment_kinks = ()
    segment_resolution = ()

    def segment(self, tau, start_value):  # pragma: no cover - interface
        raise NotImplementedError

    @property
    def jumps(self):
        """Times of discontinuities [s]."""
        return tuple(self.segment_jumps)

    @property
    def kinks(self):
        """Times where the slope changes [s]."""
        return tuple(self.segment_kinks)

    @property
    def resolution(self):
        """``((start, end, max_step), ...)`` [s]: over ``[start, end]`` no time step may exceed ``max_step``.

        Empty for a piecewise-linear history, which stations at its jumps and kinks follow exactly.
        """
        return tuple(self.segment_resolution)

    def __call__(self, t):
        """Value at times ``t`` [s] (right-continuous, 0 before the history starts)."""
        t = np.asarray(t, dtype=float)
        return np.where(t >= 0, self.segment(np.maximum(t, 0.0), 0.0), 0.0)

    def left(self, t):
        """Left limit of the value at ``t`` (differs from ``self(t)`` at a jump)."""
        t = np.asarray(t, dtype=float)
        eps = 1e-12 * max(1.0, float(np.max(np.abs(t))) if t.size else 1.0)
        return self(t - eps)


@dataclass(frozen=True)
class Step(History):
    """Sudden change to ``value`` at ``at`` [s] (in a sequence: at the segment's start + ``at``).

    Parameters
    ----------
    value : float
        Load [N] or approach [m] after the step.
    at : float
        Time of the step [s].
    """

    value: float
    at: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "value", check_real(self.value, name="value"))
        object.__setattr__(self, "at", check_quantity(self.at, name="at", unit="s", zero=True))

    span = property(lambda self: self.at)
    segment_jumps = property(lambda self: (self.at,))

    def segment(self, tau, start_value):
        return np.where(np.asarray(tau) >= self.at, self.value, start_value)


@dataclass(frozen=True)
class Ramp(History):
    """Linear change to ``end`` over ``duration``, starting after ``start`` [s].

    Parameters
    ----------
    end : float
        Value at the end of the ramp (load [N] or approach [m]).
    duration : float
        Rise (or fall) time [s].
    start : float
        Delay before the ramp begins [s].
    """

    end: float
    duration: float
    start: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "end", check_real(self.end, name="end"))
        object.__setattr__(self, "duration", check_quantity(self.duration, name="duration", unit="s"))
        object.__setattr__(self, "start", check_quantity(self.start, name="start", unit="s", zero=True))

    span = property(lambda self: self.start + self.duration)
    segment_kinks = property(lambda self: (self.start, self.start + self.duration))

    def segment(self, tau, start_value):
        fraction = np.clip((np.asarray(tau, dtype=float) - self.start) / self.duration, 0.0, 1.0)
        return start_value + (self.end - start_value) * fraction


@dataclass(frozen=True)
class Hold(History):
    """Constant value for ``duration`` [s]: the current one, or ``value`` (a step, then held).

    Parameters
    ----------
    duration : float
        Holding time [s].
    value : float, optional
        Value to jump to at the start of the hold; None keeps the current value.
    """

    duration: float
    value: float = None

    def __post_init__(self):
        object.__setattr__(self, "duration", check_quantity(self.duration, name="duration", unit="s", zero=True))
        if self.value is not None:
            object.__setattr__(self, "value", check_real(self.value, name="value"))

    span = property(lambda self: self.duration)
    segment_jumps = property(lambda self: (0.0,) if self.value is not None else ())

    def segment(self, tau, start_value):
        return np.full(np.shape(tau), start_value if self.value is None else self.value, dtype=float)


@dataclass(frozen=True)
class Table(History):
    """Tabulated history, linear between the points; before the first point the previous value.

    Parameters
    ----------
    times : array_like
        Strictly increasing times [s], >= 0 (relative to the segment's start in a sequence).
    values : array_like
        Values at those times (load [N] or approach [m]).
    """

    times: tuple
    values: tuple

    def __post_init__(self):
        times = check_finite_array(self.times, name="times", ndim=1)
        values = check_finite_array(self.values, name="values", ndim=1)
        if times.size != values.size or times.size == 0:
            raise ParameterError(f"times and values must have the same non-zero length, got {times.size} "
                                 f"and {values.size}")
        check_increasing(times, name="times")
        object.__setattr__(self, "times", tuple(times))
        object.__setattr__(self, "values", tuple(values))

    span = property(lambda self: self.times[-1])
    segment_jumps = property(lambda self: (self.times[0],))
    segment_kinks = property(lambda self: self.times)

    def segment(self, tau, start_value):
        tau = np.asarray(tau, dtype=float)
        return np.where(tau >= self.times[0], np.interp(tau, self.times, self.values), start_value)


@dataclass(frozen=True)
class Cyclic(History):
    """Oscillation ``mean + amplitude * wave(2 pi tau / period)`` for ``cycles`` periods, then ``mean``.

    A sine is followed with at least :data:`STATIONS_PER_PERIOD` time steps per
    period whatever the output times (its :attr:`resolution`): the stepper takes
    the value as linear between stations, which then misses the peaks by less
    than ``(pi / 32)^2 / 2 = 0.5 %`` of the amplitude, and the hereditary
    response converges as the square of the step. A triangle is piecewise
    linear: its corners are kinks and it needs nothing more.

    Parameters
    ----------
    mean : float
        Mean value (load [N] or approach [m]); the history jumps to it at the start.
    amplitude : float
        Half the peak-to-peak range, >= 0.
    period : float
        Period [s].
    cycles : int
        Number of periods.
    shape : str
        ``"sine"`` or ``"triangle"`` (piecewise linear, its corners are kinks).
    """

    mean: float
    amplitude: float
    period: float
    cycles: int = 1
    shape: str = "sine"

    def __post_init__(self):
        object.__setattr__(self, "mean", check_real(self.mean, name="mean"))
        object.__setattr__(self, "amplitude", check_non_negative(self.amplitude, name="amplitude"))
        object.__setattr__(self, "period", check_quantity(self.period, name="period", unit="s"))
        object.__setattr__(self, "cycles", check_positive_int(self.cycles, name="cycles"))
        if self.shape not in ("sine", "triangle"):
            raise ParameterError(f"shape must be 'sine' or 'triangle', got {self.shape!r}")
        # A load or an approach must be >= 0 at every time. The schedule checks the values at its stations, which
        # need not fall on a trough: the trough is checked here, where it is known.
        if self.mean - self.amplitude < 0:
            raise ParameterError(f"Cyclic dips to mean - amplitude = {self.mean!r} - {self.amplitude!r} = "
                                 f"{self.mean - self.amplitude!r} at its troughs, and a load must be >= 0 at every "
                                 f"time (an approach too); expected amplitude <= mean")

    span = property(lambda self: self.cycles * self.period)
    segment_jumps = property(lambda self: (0.0,))

    @property
    def segment_resolution(self):
        if self.shape == "sine":
            return ((0.0, self.span, self.period / STATIONS_PER_PERIOD),)
        return ()

    @property
    def segment_kinks(self):
        if self.shape == "sine":
            return (self.span,)
        return tuple(self.period * (0.25 + 0.5 * np.arange(2 * self.cycles))) + (self.span,)

    def segment(self, tau, start_value):
        tau = np.asarray(tau, dtype=float)
        phase = np.minimum(tau, self.span) / self.period
        if self.shape == "sine":
            wave = np.sin(2 * np.pi * phase)
        else:
            wave = 2 / np.pi * np.arcsin(np.sin(2 * np.pi * phase))
        return self.mean + self.amplitude * wave


@dataclass(frozen=True)
class Sequence(History):
    """Segments one after the other, each starting where and when the previous one ended.

    Example: ``Sequence([Ramp(100.0, 10.0), Hold(100.0), Ramp(0.0, 10.0), Hold(300.0)])``
    loads to 100 N in 10 s, holds, unloads in 10 s and watches the recovery.

    Parameters
    ----------
    segments : sequence of History
        The segments.
    """

    segments: tuple

    def __post_init__(self):
        segments = tuple(self.segments)
        if not segments or not all(isinstance(s, History) and not isinstance(s, Sequence) for s in segments):
            raise ParameterError(f"segments must be a non-empty list of Step, Ramp, Hold, Table or Cyclic, "
                                 f"got {self.segments!r}")
        object.__setattr__(self, "segments", segments)

    def _starts(self):
        starts, values, time, value = [], [], 0.0, 0.0
        for segment in self.segments:
            starts.append(time)
            values.append(value)
            value = float(segment.segment(segment.span, value))
            time += segment.span
        return np.array(starts), values

    span = property(lambda self: float(sum(s.span for s in self.segments)))

    @property
    def segment_jumps(self):
        starts, _ = self._starts()
        return tuple(float(t0 + j) for t0, s in zip(starts, self.segments) for j in s.segment_jumps)

    @property
    def segment_kinks(self):
        starts, _ = self._starts()
        return tuple(float(t0 + k) for t0, s in zip(starts, self.segments) for k in s.segment_kinks)

    @property
    def segment_resolution(self):
        starts, _ = self._starts()
        return tuple((float(t0 + a), float(t0 + b), h) for t0, s in zip(starts, self.segments)
                     for a, b, h in s.segment_resolution)

    def segment(self, tau, start_value):  # a sequence always starts from 0 (sequences do not nest)
        tau = np.asarray(tau, dtype=float)
        starts, values = self._starts()
        # the last segment that has started; zero-duration segments (steps) apply at once
        index = np.searchsorted(starts, tau, side="right") - 1
        out = np.empty(tau.shape)
        for k, segment in enumerate(self.segments):
            chosen = index == k
            if chosen.any():
                out[chosen] = segment.segment(tau[chosen] - starts[k], values[k])
        return out


def check_increasing(times, *, name):
    """Raise unless ``times`` are >= 0, strictly increasing and, unless 0, within the ``LIMITS`` of times."""
    times = np.asarray(times, dtype=float)
    if np.any(times < 0):
        raise ParameterError(f"{name} must be >= 0 [s], got {float(times[times < 0][0])!r}")
    low, high = LIMITS["s"]
    outside = (times != 0) & ((times < low) | (times > high))
    if np.any(outside):
        raise ParameterError(f"{name} must be 0 or lie between {low:g} and {high:g} s, the range this framework "
                             f"accepts, got {float(times[outside][0])!r}")
    steps = np.diff(times)
    if np.any(steps <= 0):
        i = int(np.argmax(steps <= 0))
        raise ParameterError(f"{name} must be strictly increasing, got {float(times[i])!r} followed by "
                             f"{float(times[i + 1])!r} at index {i + 1}")
    return times
