"""The time error of the Prony recursions: estimated at every step, and the steps that keep it below a tolerance.

The recursions (:mod:`framework.history`, THEORY.md sec. 5) are exact for a pressure linear within
each step. The true pressure ``p`` is not: with ``p_h`` its piecewise-linear interpolant, the surface
displacement the recursion computes at ``t_n`` misses (integrating the hereditary integral by parts,
``p - p_h`` vanishing at the steps)

    du(t_n) = K * int_0^t_n C*'(t_n - s) (p - p_h)(s) ds,   C*'(t) = sum_k (c_k/lambda_k) exp(-t/lambda_k) (+ flow),

a sum over the steps of local defects, each fading with its term's ``exp(-(t_n - t_j)/lambda_k)``. Over a
step of length ``h`` where ``p - p_h = -DD2 (s - t_{n-1}) (t_n - s)`` (``DD2`` the second divided
difference, ``p''/2``) the defect of term ``k`` is

    d_k = c_k lambda_k^2 f(h/lambda_k) |K * DD2|,   f(H) = H - 2 + (H + 2) exp(-H)  (= H^3/6 for small H),

(``flow h^3 / 6 |K * DD2|`` for a fluid's flow term). A material without instantaneous compliance
holds the pressure within a step instead (first order): there ``p - p_h = -p' (t_n - s)`` and
``d_k = c_k lambda_k g(h/lambda_k) |K * p'|`` with ``g(H) = 1 - (1 + H) exp(-H)``. The first step
after a jump or a kink of the load has no earlier step of its stretch to take a curvature from; for a
pressure monotone within the step ``|p - p_h| <= |p_n - p_{n-1}|``, so
``d_k <= c_k (1 - exp(-h/lambda_k)) |K * (p_n - p_{n-1})|`` bounds it.

The defect ``du`` of the history moves the step's contact as a change of the approach would: the
pressure answers with ``du`` over the compliance. So the divided differences are taken of the
pressure field itself (its root mean square over the grid: a cell entering or leaving the contact
within a step is a kink there, one ring of cells, which the mean square weighs by its share), the
defects per term fade as the memory does, ``A_k <- exp(-h/lambda_k) A_k + d_k``, and the estimate is

    E_n = sum_k A_k / (C_s |p|),

``C_s`` the step's secant compliance (the largest total surface displacement over the largest
elastic displacement per unit compliance) and ``|p|`` the RMS pressure, the largest of the run so
far: a load that relaxes or is taken off, and a surface recovering without contact, are measured
against the pressure there was. It costs no solve. Measured (``tests/test_time_tolerance.py``,
README), against exact relaxation and finely stepped runs: on PMMA and a standard linear solid
with ``E(0) = 2 E(inf)`` the error is within 0.9-1.2 times the estimate from 1e-3 to 1e-6; with
``E(0) = 10 E(inf)`` and a growing contact up to 1.7 times at 1e-4 and 6 times at 1e-3 (the
errors feed back through the history more strongly there, which the estimate leaves out).

:class:`StepControl` takes steps so that the estimate stays below ``Options.time_tolerance``. A
trial is accepted when ``E_n``, or the step's own defect repeated at every step with its fading
(``U_n = sum_k d_k / (1 - exp(-h/lambda_k)) / (C_s |p|)``), meets it: an excess of earlier steps
fades, and a shorter step would not remove it. A rejected trial is solved again shorter, and
nothing of it is committed. The next step is the longest (up to :data:`GROWTH` times the last)
whose prediction, the last curvature taken as it is, meets :data:`SAFETY` times the tolerance; the
whole interval to the next station is taken when it is predicted to meet the tolerance itself, so
output times fine enough take no extra step.
"""
import math

import numpy as np

from .errors import ConvergenceError
from .history import translate

__all__ = ["GROWTH", "SAFETY", "StepControl", "curvature_weights", "slope_weights"]


#: The kinds of defect model (module docstring): second divided difference, held slope, a stretch's first step.
MODELS = ("curvature", "slope", "first")
#: The next step is at most this many times the last accepted one.
GROWTH = 4.0
#: Steps are chosen to meet this fraction of the tolerance, so that few are rejected.
SAFETY = 0.5
#: A stretch between two stations is never cut into more steps than this (a tolerance the solver's own
#: round-off cannot meet would otherwise shrink the steps for ever).
MAX_STEPS_PER_INTERVAL = 100_000


def _series(values, coefficients):
    """``sum_m coefficients[m] H^m`` (``coefficients[0]`` for ``H^0``), for small ``H``."""
    out = np.zeros_like(values)
    for coefficient in coefficients[::-1]:
        out = out * values + coefficient
    return out


#: Taylor coefficients of ``f(H) = H - 2 + (H + 2) e^-H``: ``(-1)^(m+1) (m - 2) / m!`` from ``m = 3``.
_F = [0.0, 0.0, 0.0] + [(-1) ** (m + 1) * (m - 2) / math.factorial(m) for m in range(3, 16)]
#: Taylor coefficients of ``g(H) = 1 - (1 + H) e^-H``: ``(-1)^m (m - 1) / m!`` from ``m = 2``.
_G = [0.0, 0.0] + [(-1) ** m * (m - 1) / math.factorial(m) for m in range(2, 16)]


def curvature_weights(step, times):
    """``lambda_k^2 f(step / lambda_k)`` [s^2] per retardation time ``times`` [s] (see the module docstring).

    The defect of term ``k`` over a step of ``step`` [s] per unit second divided difference. A series
    below ``H = 0.5``, where the closed form loses its digits to cancellation (``f ~ H^3/6``).
    """
    times = np.asarray(times, dtype=float)
    ratio = step / times
    small = ratio < 0.5
    closed = ratio - 2.0 + (ratio + 2.0) * np.exp(-np.where(small, 1.0, ratio))
    return times**2 * np.where(small, _series(np.where(small, ratio, 0.0), _F), closed)


def slope_weights(step, times):
    """``lambda_k g(step / lambda_k)`` [s] per retardation time (held pressure, first order; module docstring)."""
    times = np.asarray(times, dtype=float)
    ratio = step / times
    small = ratio < 0.5
    closed = 1.0 - (1.0 + ratio) * np.exp(-np.where(small, 1.0, ratio))
    return times * np.where(small, _series(np.where(small, ratio, 0.0), _G), closed)


def _norm(field):
    """The root mean square of a field over the grid."""
    return float(np.sqrt(np.mean(np.square(field))))


def _per_unit_step(defects, step, times):
    """``sum_k d_k / (1 - exp(-step/lambda_k))``: the defects of equal steps summed with their fading [m]."""
    if step <= 0:
        return 0.0
    return float((defects / -np.expm1(-step / times)).sum())


class StepControl:
    """The time error of a run's steps, and the steps that keep it below ``tolerance``.

    Parameters
    ----------
    series : framework.materials.ComplianceSeries
        The contact compliance whose recursions are stepped.
    tolerance : float or None
        Largest estimated error [-], relative to the run's pressure and approach scale; None: the
        steps are the schedule's stations, and the error is estimated only.
    duration : float
        Last time of the run [s]: a fluid's flow term remembers every step, fading over no time
        shorter than this.

    The stepper asks :meth:`next_time` for each trial, reports each solve with :meth:`judge`, and
    :meth:`accept` or :meth:`reject` the trial. Its memory (the last two pressures of the stretch,
    the faded defects, the scale, the next step and its model) is part of a checkpoint
    (:meth:`snapshot`).
    """

    def __init__(self, series, tolerance, duration):
        self.tolerance = tolerance
        self.linear = series.linear_steps
        self.coefficients = series.coefficients
        times = series.times
        if series.flow:     # the flow term: a retardation time as long as the run
            self.coefficients = np.append(self.coefficients, series.flow * max(duration, 1e-300))
            times = np.append(times, max(duration, 1e-300))
        self.times = times
        self.active = len(self.coefficients) > 0
        self.defects = np.zeros(len(self.coefficients))    # A_k [m]
        self.points = []        # (time [s], pressure [Pa]) of the stretch's last two accepted steps
        self.step = None        # the next step's length [s] (None: the whole interval)
        self.peak = 0.0         # the largest scale so far [-]
        self.error = self._unit = 0.0
        self._from_rest = False
        self._trial = None
        self._model = (0.0, None)       # (scale, (kind, value)) of the last judged step: the next one's prediction

    # -- the stepper's questions -------------------------------------------------------------------------

    def adaptive(self):
        """Whether steps are chosen: a material with memory, a tolerance, and steps linear in the pressure.

        A material without instantaneous compliance (Kelvin-Voigt) holds the pressure within a step,
        first order: early in a load from rest its estimate per unit step does not fall below a
        percent for any step, and its steps stay the stations (the estimate is reported all the same).
        """
        return self.active and self.tolerance is not None and self.linear

    def next_time(self, now, target):
        """The next trial's time [s] on the way from ``now`` to the station at ``target``.

        The station itself when the step to it is predicted to meet the tolerance (output times fine
        enough take no more steps), else the step chosen after the last accepted one.
        """
        if not self.adaptive() or target <= now:
            return target
        left = target - now
        if self.step is None or left <= 1.05 * self.step or self._predicted(left) <= self.tolerance:
            return target
        if left < 2.0 * self.step:      # no sliver of a step before the station
            return now + 0.5 * left
        return now + self.step

    def new_stretch(self):
        """A jump or a kink of the load: the curvature before it says nothing of the steps after it."""
        self.points = self.points[-1:]

    def translate(self, cells, periodic):
        """The material moved (rolling): the remembered pressures move with it (a material point's history)."""
        if any(cells):
            self.points = [(t, translate(field, cells, periodic)) for t, field in self.points]

    def judge(self, time, pressure, compliance):
        """The estimate ``E_n`` [-] of a trial step to ``time`` [s] that gave ``pressure`` [Pa].

        ``compliance`` [1/Pa] is the secant compliance of the step, the total surface displacement over
        the elastic displacement of the pressure per unit compliance (largest values): with it a defect
        of the displacement becomes one of the pressure. The scale is the largest of the run so far:
        a pressure that relaxes or is unloaded, and a surface that recovers without contact, are
        measured against the pressure that was.
        """
        if not self.active or not self.points:
            self._trial = (time, pressure, np.zeros_like(self.defects), 0.0, None)
            self.error = self._unit = 0.0
            return 0.0
        then, before = self.points[-1]
        step = time - then
        decay = np.exp(-step / self.times) if step > 0 else np.ones_like(self.times)
        model = None
        if step <= 0:
            local = np.zeros_like(self.defects)
        elif not self.linear:
            slope = _norm(pressure - before) / step
            local = self.coefficients * slope_weights(step, self.times) * slope
            model = ("slope", slope)
        elif len(self.points) >= 2:
            earlier, oldest = self.points[-2]
            curvature = _norm((pressure - before) / step - (before - oldest) / (then - earlier)) / (time - earlier)
            local = self.coefficients * curvature_weights(step, self.times) * curvature
            model = ("curvature", curvature)
        else:
            rate = _norm(pressure - before) / step
            local = self.coefficients * -np.expm1(-step / self.times) * rate * step
            model = ("first", rate)
        # out of a state without pressure, a pressure growing as a power of time is as far off (relatively)
        # over a step of any length: such a step is taken as it is (its defect is counted all the same)
        self._from_rest = _norm(before) == 0.0
        scale = max(compliance * _norm(pressure), self.peak)
        defects = decay * self.defects + local
        self.error = float(defects.sum()) / scale if scale > 0 else 0.0
        self._unit = _per_unit_step(local, step, self.times) / scale if scale > 0 else 0.0
        self._trial = (time, pressure, defects, scale, model)
        return self.error

    def acceptable(self):
        """Whether the judged trial meets the tolerance (always, without one).

        Met when the estimate ``E_n`` is within it, or when the step's own defect, repeated at every
        step, would be (``sum_k d_k / (1 - exp(-h/lambda_k))``): the excess of an earlier step then fades
        and a shorter step would not remove it. A step out of a state without pressure is always met:
        a pressure growing from nothing as a power of time is as far off, relatively, over a step of
        any length.
        """
        return not self.adaptive() or self._from_rest or min(self.error, self._unit) <= self.tolerance

    def accept(self):
        """Commit the judged trial and choose the next step."""
        time, field, defects, scale, model = self._trial
        previous = self.points[-1][0] if self.points else None
        self.defects, self.peak = defects, max(self.peak, scale)
        self.points = (self.points + [(time, field)])[-2:]
        self._model = (scale, model)
        if self.adaptive() and previous is not None and time > previous:
            self.step = self._longest(GROWTH * (time - previous))

    def reject(self, now):
        """Forget the judged trial from ``now`` [s] and shorten the next one."""
        time, _, _, scale, model = self._trial
        self._model = (scale, model)
        self.step = max(self._longest(0.5 * (time - now)), 0.05 * (time - now))

    def _predicted(self, step):
        """The estimate of a step of ``step`` [s] from the last accepted one: ``min(E, U)`` of :meth:`acceptable`.

        The step's defect is that of the last model (the last curvature, slope or rate, taken as it is)
        for a step of that length; the earlier defects fade over it.
        """
        scale, model = self._model
        if model is None or scale <= 0:
            return 0.0
        kind, value = model
        if kind == "curvature":
            local = self.coefficients * curvature_weights(step, self.times) * value
        elif kind == "slope":
            local = self.coefficients * slope_weights(step, self.times) * value
        else:
            local = self.coefficients * -np.expm1(-step / self.times) * value * step
        faded = float((np.exp(-step / self.times) * self.defects + local).sum())
        return min(faded, _per_unit_step(local, step, self.times)) / scale

    def _longest(self, limit):
        """The longest step up to ``limit`` [s] predicted to meet ``SAFETY`` times the tolerance."""
        candidates = limit * 2.0 ** (-np.arange(0, 60) / 4.0)
        for step in candidates:
            if self._predicted(step) <= SAFETY * self.tolerance:
                return float(step)
        return float(candidates[-1])

    def check_count(self, count, now, target, name="time_tolerance"):
        if count > MAX_STEPS_PER_INTERVAL:
            raise ConvergenceError(
                f"{name} = {self.tolerance!r}: more than {MAX_STEPS_PER_INTERVAL} steps between t = {now:g} s "
                f"and the station at {target:g} s without meeting it (the estimated error is {self.error:.3g}); the "
                f"contact solver's own tolerance may be the limit: loosen {name} or tighten the solver's")

    # -- checkpoints ---------------------------------------------------------------------------------------

    def snapshot(self):
        """The memory as four arrays (for a checkpoint), keys prefixed ``time_``."""
        scale, model = self._model
        return {"time_defects": self.defects, "time_points": np.array([t for t, _ in self.points], dtype=float),
                "time_fields": np.array([field for _, field in self.points], dtype=float),
                "time_scalars": np.array([np.nan if self.step is None else self.step, self.peak, scale,
                                          MODELS.index(model[0]) if model else -1, model[1] if model else 0.0])}

    def restore(self, state):
        """Continue from :meth:`snapshot`'s arrays (a checkpoint without them: afresh)."""
        if "time_defects" not in state:
            return
        self.defects = np.asarray(state["time_defects"], dtype=float)
        times = np.atleast_1d(np.asarray(state["time_points"], dtype=float))
        self.points = [(float(t), field) for t, field in zip(times, state["time_fields"])]
        step, self.peak, scale, kind, value = (float(v) for v in state["time_scalars"])
        self.step = None if math.isnan(step) else step
        self._model = (scale, None if kind < 0 else (MODELS[int(kind)], value))
