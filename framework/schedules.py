"""Motion schedules: data describing what happens to the indenter, not code."""
from dataclasses import dataclass

import numpy as np

from . import loads
from ._validation import LIMITS, check_bool, check_finite_array, check_quantity, check_real
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


def _check_range(values, name, times=None):
    """Loads [N] and approaches [m] are >= 0 and below :data:`LIMITS`; ``times`` [s] locate a bad value."""
    negative = np.flatnonzero(values < 0)
    if negative.size:
        raise ParameterError(f"{name} must be >= 0 at every time, got {float(values[negative[0]])!r}")
    unit, largest = UNITS[name], LIMITS[UNITS[name]][1]
    large = np.flatnonzero(values > largest)
    if large.size:
        k = large[0]
        at = "" if times is None else f" at t = {float(times[k]):g} s"
        raise ParameterError(f"{name} must stay below {largest:g} {unit}, the range this framework accepts, "
                             f"got {float(values[k])!r} {unit}{at}")


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
        _check_range(values, control, probe)
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


@dataclass(frozen=True)
class Rolling:
    """A rigid body rolling, or sliding without friction, at constant velocity over the half-space.

    Rolling of a rigid body and frictionless sliding are the same normal
    problem (seed 000). The run works in the body's frame: the grid moves with
    the body, centred on its axis, and the material flows through it at
    ``-velocity`` (THEORY.md sec. 7).

    * Transient (``steady=False``): the body first indents the material at rest
      (the load applied at t = 0, or the ``start`` schedule), then moves. Each
      step the material, with everything the stepper remembers of it, moves by
      exactly one cell against the motion (the time step is one cell over the
      speed); material entering the grid ahead of the body is virgin, the
      history of material leaving it behind is dropped, so the grid must hold
      the contact and its wake (the run checks it). The load (a number or a
      history of the time since the motion began) is followed at these steps.
    * Steady (``steady=True``): the steady state in the body's frame, solved
      directly (:mod:`framework.operators.rolling`, :mod:`framework.steady_solver`):
      one solve per load, no history, recorded at the times 0, 1, 2 ... (the
      load's index, like the default times of a list of loads at rest). The
      wake lies in the operator, so the grid need only hold the contact.

    Refused: oblique motion (velocity along a grid axis only), output times
    that do not fall on whole cells of motion, a distance shorter than a cell;
    steady runs of a fluid (a Maxwell material has no steady state), of a
    solid without instantaneous compliance (Kelvin-Voigt), or along a periodic
    grid axis.

    Parameters
    ----------
    load : float, sequence or loads.History
        Normal load [N]. Transient: a number or a history of the time since
        the motion began. Steady: a number or a list of loads (one steady
        state each, in order, each warm-starting the next).
    velocity : tuple of float
        ``(v1, v2)`` [m/s], the body's velocity over the material, along one
        grid axis (the other component 0), either sign.
    distance : float, optional
        Transient: the distance [m] the body rolls (rounded to whole cells).
    times : array_like, optional
        Transient: output times [s] since the motion began, each a whole
        number of cells of motion (default: every step, from the rest
        indentation at 0 to ``distance``).
    steady : bool
        Solve the steady state instead of the transient.
    start : Static, optional
        Transient: an indentation at rest under load before the motion (a
        preload history); its output times are recorded, and the motion
        begins at its last time. Default: the load applied at t = 0.
    """

    load: object
    velocity: tuple
    distance: float = None
    times: object = None
    steady: bool = False
    start: object = None

    def __post_init__(self):
        velocity = self.velocity
        if not isinstance(velocity, (tuple, list, np.ndarray)) or len(velocity) != 2:
            raise ParameterError(f"velocity must be a pair (v1, v2) [m/s], got {velocity!r}")
        velocity = tuple(check_real(v, name=f"velocity[{i}]") for i, v in enumerate(velocity))
        if velocity == (0.0, 0.0):
            raise ParameterError("velocity must not be zero, got (0.0, 0.0); a body at rest is schedules.Static")
        if velocity[0] and velocity[1]:
            raise ParameterError(f"velocity {velocity} m/s: oblique motion is not supported; the body moves along a "
                                 f"grid axis, one component zero (turn the grid instead)")
        for v in velocity:
            if v:
                check_quantity(abs(v), name="speed |velocity|", unit="m/s")
        object.__setattr__(self, "velocity", velocity)
        steady = check_bool(self.steady, name="steady")
        object.__setattr__(self, "steady", steady)
        if steady:
            for name in ("distance", "times", "start"):
                if getattr(self, name) is not None:
                    raise ParameterError(f"{name} has no meaning for a steady run (steady=True), got "
                                         f"{getattr(self, name)!r}; leave it out")
            if isinstance(self.load, loads.History):
                raise ParameterError("load of a steady run is a number or a list of loads, one steady state each; "
                                     f"got the history {self.load!r}")
            values = _values(self.load, "load")
            _check_range(values, "load")
            object.__setattr__(self, "history", None)
            object.__setattr__(self, "loads", tuple(values.tolist()))
            return
        if self.distance is None and self.times is None:
            raise ParameterError("a transient rolling run needs how far to roll: give distance [m] or times [s]")
        if self.distance is not None:
            object.__setattr__(self, "distance", check_quantity(self.distance, name="distance", unit="m"))
        if self.times is not None:
            times = check_finite_array(self.times, name="times", ndim=1)
            if times.size == 0:
                raise ParameterError("times must hold at least one time, got an empty array")
            loads.check_increasing(times, name="times")
            object.__setattr__(self, "times", times)
        if self.start is not None and (not isinstance(self.start, Static) or self.start.control != "load"
                                       or isinstance(self.start, Eccentric)):
            raise ParameterError(f"start must be a Static schedule under load (the indentation at rest before the "
                                 f"motion), got {self.start!r}")
        if isinstance(self.load, loads.History):
            history = self.load
        else:
            values = _values(self.load, "load")
            if values.size != 1:
                raise ParameterError(f"load of a transient run is a number or a loads history of the time since the "
                                     f"motion began (e.g. loads.Table(times, values)), got {values.size} values")
            history = loads.Step(float(values[0]))
        probe = np.array(history.jumps + history.kinks + (0.0,))
        _check_range(np.concatenate([history(probe), history.left(probe)]), "load", np.concatenate([probe, probe]))
        object.__setattr__(self, "history", history)
        object.__setattr__(self, "loads", None)

    control = "load"

    @property
    def axis(self):
        """The grid axis of the motion (0 or 1)."""
        return 0 if self.velocity[0] else 1

    @property
    def speed(self):
        """``|velocity|`` [m/s]."""
        return abs(self.velocity[self.axis])

    @property
    def direction(self):
        """The unit vector of the motion ``(m1, m2)``."""
        return tuple(float(np.sign(v)) for v in self.velocity)

    @property
    def motion_start(self):
        """Time [s] at which the body starts to move (the end of ``start``, else 0)."""
        return float(self.start.times[-1]) if self.start is not None else 0.0
