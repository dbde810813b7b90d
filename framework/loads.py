"""Histories of load [N] or approach [m] in time [s].

A history is a right-continuous function of time, zero before it starts; its
``jumps`` are the times where it is discontinuous, which the time stepper
resolves exactly (a step at ``t`` is applied with zero time increment).
"""
from dataclasses import dataclass

import numpy as np

from ._validation import check_finite_array, check_non_negative, check_positive, check_real
from .errors import ParameterError


class History:
    """Base class of load and approach histories."""

    jumps = ()

    def __call__(self, t):
        """Value at times ``t`` [s] (right-continuous)."""
        raise NotImplementedError  # pragma: no cover - interface

    def left(self, t):
        """Left limit of the value at ``t`` (differs from ``self(t)`` at a jump)."""
        return self(np.asarray(t, dtype=float) - 1e-12 * max(1.0, abs(float(np.max(t)))))


@dataclass(frozen=True)
class Step(History):
    """Constant value applied suddenly at time ``at``.

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
        object.__setattr__(self, "at", check_non_negative(self.at, name="at", unit="s"))

    @property
    def jumps(self):
        return (self.at,) if self.value != 0 else ()

    def __call__(self, t):
        return np.where(np.asarray(t, dtype=float) >= self.at, self.value, 0.0)

    def left(self, t):
        return np.where(np.asarray(t, dtype=float) > self.at, self.value, 0.0)


@dataclass(frozen=True)
class Ramp(History):
    """Linear rise from 0 at ``start`` to ``end`` at ``start + duration``, then held.

    Parameters
    ----------
    end : float
        Final value (load [N] or approach [m]).
    duration : float
        Rise time [s].
    start : float
        Time the rise begins [s].
    """

    end: float
    duration: float
    start: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "end", check_real(self.end, name="end"))
        object.__setattr__(self, "duration", check_positive(self.duration, name="duration", unit="s"))
        object.__setattr__(self, "start", check_non_negative(self.start, name="start", unit="s"))

    def __call__(self, t):
        fraction = np.clip((np.asarray(t, dtype=float) - self.start) / self.duration, 0.0, 1.0)
        return self.end * fraction

    def left(self, t):
        return self(t)


@dataclass(frozen=True)
class Table(History):
    """Tabulated history, linear between the points, zero before the first one.

    Parameters
    ----------
    times : array_like
        Strictly increasing times [s], >= 0.
    values : array_like
        Values at those times (load [N] or approach [m]).
    """

    times: tuple
    values: tuple

    def __post_init__(self):
        times = check_finite_array(self.times, name="times", ndim=1)
        values = check_finite_array(self.values, name="values", ndim=1)
        if times.size != values.size or times.size == 0:
            raise ParameterError(f"times and values must have the same non-zero length, got {times.size} and {values.size}")
        check_increasing(times, name="times")
        object.__setattr__(self, "times", tuple(times))
        object.__setattr__(self, "values", tuple(values))

    @property
    def jumps(self):
        return (self.times[0],) if self.values[0] != 0 else ()

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        return np.where(t >= self.times[0], np.interp(t, self.times, self.values), 0.0)

    def left(self, t):
        t = np.asarray(t, dtype=float)
        return np.where(t > self.times[0], np.interp(t, self.times, self.values), 0.0)


def check_increasing(times, *, name):
    """Raise unless ``times`` are >= 0 and strictly increasing."""
    times = np.asarray(times, dtype=float)
    if np.any(times < 0):
        raise ParameterError(f"{name} must be >= 0 [s], got {float(times[times < 0][0])!r}")
    steps = np.diff(times)
    if np.any(steps <= 0):
        i = int(np.argmax(steps <= 0))
        raise ParameterError(f"{name} must be strictly increasing, got {float(times[i])!r} followed by {float(times[i + 1])!r} "
                             f"at index {i + 1}")
    return times
