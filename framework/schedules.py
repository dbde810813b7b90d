"""Motion schedules: data describing what happens to the indenter, not code."""
from dataclasses import dataclass

import numpy as np

from . import loads
from ._validation import LIMITS, check_finite_array
from .errors import ParameterError

UNITS = {"load": "N", "approach": "m"}


def _values(value, name):
    """The numbers of a load or approach given as a number or a sequence, checked."""
    expected = f"{name} must be a number, a sequence of numbers or a loads history"
    if isinstance(value, (bool, np.bool_, str, bytes, dict)):
        raise ParameterError(f"{expected}, got {value!r}")
    try:
        array = np.atleast_1d(np.asarray(value, dtype=float))
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{expected}, got {value!r}") from exc
    if array.ndim != 1:
        raise ParameterError(f"{expected}, got {value!r}")
    if array.size == 0:
        raise ParameterError(f"{name} is empty: give a number, one value per time or a loads history")
    return check_finite_array(array, name=name)


def _as_history(values, times, name):
    if values.size == 1:
        return loads.Step(float(values[0]))
    if len(times) != values.size:
        raise ParameterError(f"{name} has {values.size} values but times has {len(times)} entries; "
                             f"give one time per value")
    return loads.Table(times=times, values=values)


@dataclass(frozen=True)
class Static:
    """Indentation along the surface normal under a load or an approach history.

    Parameters
    ----------
    load : float, sequence or loads.History, optional
        Total normal load [N]: a constant (applied at t = 0), one value per
        time, or a history.
    approach : float, sequence or loads.History, optional
        Rigid approach [m], the same forms; give ``load`` or ``approach``.
    times : array_like, optional
        Output times [s], strictly increasing, >= 0. Default: ``0, 1, 2, ...``
        one per value of a sequence, or ``[0]`` for a constant.

    Times lie within ``framework._validation.LIMITS`` (0 or 1e-15 to 1e15 s),
    the load below 1e12 N and the approach below 1e6 m.
    """

    load: object = None
    approach: object = None
    times: object = None

    def __post_init__(self):
        if (self.load is None) == (self.approach is None):
            raise ParameterError(f"give exactly one of load and approach, got load={self.load!r}, "
                                 f"approach={self.approach!r}")
        control = self.control
        value = self.load if self.load is not None else self.approach
        values = None if isinstance(value, loads.History) else _values(value, control)
        times = self.times
        if times is None:
            times = np.arange(1 if values is None else values.size, dtype=float)
        times = check_finite_array(times, name="times", ndim=1)
        if times.size == 0:
            raise ParameterError("times must hold at least one time, got an empty array")
        loads.check_increasing(times, name="times")
        history = value if values is None else _as_history(values, times, control)
        probe = np.concatenate([times, np.asarray(history.jumps + history.kinks, dtype=float)])
        values = np.concatenate([history(probe), history.left(probe)])  # each value and its left limit
        probe = np.concatenate([probe, probe])
        if np.any(values < 0):
            raise ParameterError(f"{control} must be >= 0 at every time, got {float(values[values < 0][0])!r}")
        unit, largest = UNITS[control], LIMITS[UNITS[control]][1]
        if np.any(values > largest):
            k = int(np.argmax(values > largest))
            raise ParameterError(f"{control} must stay below {largest:g} {unit}, the range this framework accepts, "
                                 f"got {float(values[k])!r} {unit} at t = {float(probe[k]):g} s")
        object.__setattr__(self, "times", times)
        object.__setattr__(self, "history", history)

    @property
    def control(self):
        """``"load"`` or ``"approach"``."""
        return "load" if self.load is not None else "approach"


@dataclass(frozen=True)
class Eccentric(Static):
    """Indentation under a load applied off the indenter's axis: the indenter tilts.

    The approach and both tilts are unknowns fixed by the force and the two
    moments at every step (THEORY.md sec. 6); ``Result.tilt`` holds the tilt
    angles ``atan(alpha1), atan(alpha2)`` [rad] of the rigid motion
    ``w = delta + alpha1 x1 + alpha2 x2`` (``tilt[:, 0]`` is the slope along x1,
    a rotation about the x2 axis).

    Parameters
    ----------
    load : float, sequence or loads.History
        Total normal load [N].
    offset : tuple of float
        Point ``(e1, e2)`` [m] where the load acts, from the indenter's axis.
    times : array_like, optional
        Output times [s].
    """

    offset: tuple = (0.0, 0.0)

    def __init__(self, load, offset=(0.0, 0.0), times=None):
        if load is None:
            raise ParameterError("Eccentric needs a load (N); an approach cannot be applied off the axis")
        if not isinstance(offset, (tuple, list, np.ndarray)) or len(offset) != 2:
            raise ParameterError(f"offset must be a pair (e1, e2) [m], got {offset!r}")
        offset = tuple(check_finite_array(offset, name="offset", ndim=1).tolist())
        object.__setattr__(self, "offset", offset)
        Static.__init__(self, load=load, approach=None, times=times)
