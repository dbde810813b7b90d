"""The memory of the half-space: what the stepper carries from one step to the next.

Each step is an elastic contact problem with the step's effective compliance
plus a known displacement from the history (THEORY.md sec. 5): with
``C*(t) = c0 + sum_k c_k (1 - exp(-t/lambda_k))`` and a pressure varying
linearly in time within a step,

    u_n = K * [ C_eff p_n - sum_k c_k (e_k q_k - w_k p_{n-1}) ],
    C_eff = c0 + sum_k c_k (1 - w_k),  e_k = exp(-dt/lambda_k),
    w_k = (lambda_k/dt)(1 - e_k)  (1 when dt = 0),
    q_k <- e_k q_k + w_k (p_n - p_{n-1}),

(a material without instantaneous compliance, ``c0 = 0``, takes the pressure
changed at the start of each step and held instead: ``w_k = e_k`` and
``C_eff = C*(dt)``, first order; see :attr:`ComplianceSeries.linear_steps`),
which costs one extra convolution per step and one surface field per term
(plus one, the time integral of the pressure, for a fluid's ``flow`` term). An
elastic material has no terms, and the steps are independent solves
warm-started from the previous pressure. ``C_eff`` is the mean of ``C*`` over
``[0, dt]``. The quadratic hereditary sum over all previous steps
(Chen et al. 2011; seed 001) is kept as :class:`HereditarySum`, the reference
the recursion is tested against (``options={"history": "hereditary"}``).

The history fields belong to the material. When it moves under the body
(rolling, THEORY.md sec. 7: the stepper works in the body's frame), ``translate``
moves them with it by whole cells, exactly; material entering the grid has no
history, and the history of material leaving it is dropped.
"""
from dataclasses import dataclass

import numpy as np


def translate(field, cells, periodic):
    """``field`` (``(..., n1, n2)``) after the material moved ``cells = (c1, c2)`` whole cells.

    The value of a material point at cell ``i`` is then at cell ``i + c``; a
    periodic axis wraps around, an open one takes zeros where material enters.
    """
    for axis, (count, wrap) in enumerate(zip(cells, periodic)):
        if count == 0:
            continue
        axis = axis - 2
        if wrap:
            field = np.roll(field, count, axis=axis)
            continue
        moved = np.zeros_like(field)
        n = field.shape[axis]
        if abs(count) < n:
            source = [slice(None)] * field.ndim
            target = [slice(None)] * field.ndim
            source[axis] = slice(max(0, -count), n - max(0, count))
            target[axis] = slice(max(0, count), n - max(0, -count))
            moved[tuple(target)] = field[tuple(source)]
        field = moved
    return field


@dataclass
class HistoryState:
    """What the recursion carries from one step to the next (all on the surface grid).

    ``pressure`` is the last pressure, ``fields`` the Prony history fields ``q_k``
    (one per compliance term) and ``integral`` the time integral of the
    pressure (for a ``flow`` term); rolling translates them with the material.
    """

    time: float
    pressure: np.ndarray
    fields: np.ndarray
    integral: np.ndarray

    @classmethod
    def at_rest(cls, shape, n_terms):
        return cls(0.0, np.zeros(shape), np.zeros((n_terms,) + tuple(shape)), np.zeros(shape))


class PronyRecursion:
    """History by Prony recursions: O(1) convolutions and fields per step (THEORY.md sec. 5)."""

    def __init__(self, series, shape):
        self.series = series
        self.coefficients, self.retardation = series.coefficients, series.times
        self.state = HistoryState.at_rest(shape, len(series.terms))

    @property
    def time(self):
        return self.state.time

    @property
    def pressure(self):
        return self.state.pressure

    def prepare(self, time):
        """Effective compliance of the step to ``time`` and the pressure-like field of the history."""
        state, c = self.state, self.coefficients
        dt = time - state.time
        compliance = float(self.series.step_response(0.0, dt))
        if not len(c) and not self.series.flow:
            return compliance, None
        self._decay = np.exp(-dt / self.retardation)
        self._weight = self.series.step_weights(dt)
        self._dt = dt
        field = np.sum(c * self._weight) * state.pressure - np.tensordot(c * self._decay, state.fields, axes=1)
        if self.series.flow:
            field = field + self.series.flow * (state.integral + 0.5 * dt * state.pressure)
        return compliance, field

    def snapshot(self):
        """The history as arrays (for a checkpoint)."""
        state = self.state
        return {"time": state.time, "pressure": state.pressure, "fields": state.fields, "integral": state.integral}

    def restore(self, snapshot):
        self.state = HistoryState(float(snapshot["time"]), snapshot["pressure"], snapshot["fields"],
                                  snapshot["integral"])

    def translate(self, cells, periodic):
        """Move the history with the material by ``cells = (c1, c2)`` whole cells (see :func:`translate`)."""
        if any(cells):
            state = self.state
            state.pressure = translate(state.pressure, cells, periodic)
            state.fields = translate(state.fields, cells, periodic)
            state.integral = translate(state.integral, cells, periodic)

    def commit(self, time, pressure):
        state = self.state
        if len(self.coefficients) or self.series.flow:
            expand = (slice(None),) + (None,) * np.ndim(pressure)    # one factor per term, any field shape
            state.fields = self._decay[expand] * state.fields + self._weight[expand] * (pressure - state.pressure)
            state.integral = state.integral + 0.5 * self._dt * (state.pressure + pressure)
        state.pressure, state.time = pressure, time


class HereditarySum:
    """History by the full hereditary sum over every previous step: O(n) per step.

    ``u_n = K * sum_j (p_j - p_{j-1}) mean_{[t_{j-1}, t_j]} C*(t_n - s)`` for a
    pressure linear in each step (``C*(t_n - t_{j-1})`` for one held, see
    :meth:`ComplianceSeries.step_response`); the reference the recursion must reproduce.
    """

    def __init__(self, series, shape):
        self.series = series
        self.times, self.pressures = [0.0], [np.zeros(shape)]

    time = property(lambda self: self.times[-1])
    pressure = property(lambda self: self.pressures[-1])

    def prepare(self, time):
        compliance = float(self.series.step_response(0.0, time - self.times[-1]))
        field = -compliance * self.pressures[-1]
        for j in range(1, len(self.times)):
            felt = float(self.series.step_response(time - self.times[j], time - self.times[j - 1]))
            field = field + felt * (self.pressures[j] - self.pressures[j - 1])
        return compliance, field

    def translate(self, cells, periodic):
        """Move every stored pressure with the material (see :func:`translate`)."""
        if any(cells):
            self.pressures = [translate(p, cells, periodic) for p in self.pressures]

    def commit(self, time, pressure):
        self.times.append(time)
        self.pressures.append(pressure)

    def snapshot(self):
        return {"times": np.array(self.times), "pressures": np.array(self.pressures)}

    def restore(self, snapshot):
        self.times, self.pressures = list(snapshot["times"]), list(snapshot["pressures"])


class SteadyMemory:
    """The steady state in the body's frame: the history lies in the operator, none is carried.

    Only the last pressure is kept, to warm-start the next solve (the next
    load of a list); the operator returns displacements itself (compliance 1).
    """

    def __init__(self, shape):
        self.time, self.pressure = 0.0, np.zeros(shape)

    def prepare(self, time):
        return 1.0, None

    def translate(self, cells, periodic):
        """Nothing to move: in the steady state the material's history is the same at every step."""

    def commit(self, time, pressure):
        self.time, self.pressure = time, pressure

    def snapshot(self):
        return {"time": self.time, "pressure": self.pressure}

    def restore(self, snapshot):
        self.time, self.pressure = float(snapshot["time"]), snapshot["pressure"]
