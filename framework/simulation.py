"""The time stepper: one mechanism for every schedule and material.

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
"""
import math
import sys
from dataclasses import dataclass, field, replace

import numpy as np

from . import loads, schedules
from ._validation import check_bool, check_positive_int
from .errors import FrameworkError, GridTooSmallError, LoadNotCarriedError, ParameterError
from .grid import Grid
from .indenters import Indenter
from .operators.surface import SurfaceCompliance
from .result import Result, StepRecord
from .solver import SolverOptions, solve_normal


@dataclass(frozen=True)
class Options:
    """Run options.

    Parameters
    ----------
    solver : SolverOptions
        Tolerances of the contact solver.
    check_edges : bool
        Raise :class:`GridTooSmallError` when the contact reaches the edge of a
        non-periodic grid (the DC-FFT half-space ends there).
    history : str
        ``"recursive"`` (Prony recursions, O(1) per step) or ``"hereditary"``
        (the full hereditary sum, O(n) per step: a reference for tests).
    """

    solver: SolverOptions = field(default_factory=SolverOptions)
    check_edges: bool = True
    history: str = "recursive"

    def __post_init__(self):
        if not isinstance(self.solver, SolverOptions):
            raise ParameterError(f"solver must be a SolverOptions, got {self.solver!r}")
        object.__setattr__(self, "check_edges", check_bool(self.check_edges, name="check_edges"))
        if self.history not in ("recursive", "hereditary"):
            raise ParameterError(f"history must be 'recursive' or 'hereditary', got {self.history!r}")

    @classmethod
    def from_value(cls, value):
        """Options from ``None``, an ``Options`` or a dict of solver/run keys."""
        if value is None:
            return cls()
        if isinstance(value, cls):
            return value
        if not isinstance(value, dict):
            raise ParameterError(f"options must be a dict or Options, got {type(value).__name__}")
        solver_keys = set(SolverOptions.__dataclass_fields__)
        run_keys = {"check_edges", "history"}
        unknown = set(value) - solver_keys - run_keys
        if unknown:
            raise ParameterError(f"unknown option(s) {sorted(unknown)}; expected some of "
                                 f"{sorted(solver_keys | run_keys)}")
        solver = replace(SolverOptions(), **{k: v for k, v in value.items() if k in solver_keys})
        return cls(solver=solver, **{k: v for k, v in value.items() if k in run_keys})


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

    def commit(self, time, pressure):
        state = self.state
        if len(self.coefficients) or self.series.flow:
            state.fields = self._decay[:, None, None] * state.fields \
                + self._weight[:, None, None] * (pressure - state.pressure)
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

    def commit(self, time, pressure):
        self.times.append(time)
        self.pressures.append(pressure)

    def snapshot(self):
        return {"times": np.array(self.times), "pressures": np.array(self.pressures)}

    def restore(self, snapshot):
        self.times, self.pressures = list(snapshot["times"]), list(snapshot["pressures"])


#: The most time steps a run may take: beyond it a schedule is a mistake (e.g. a 1 ms period over a year).
MAX_STATIONS = 1_000_000


def _stations(schedule, refine=True):
    """``(time, value, recorded)``: the output times, the kinks and both sides of every jump.

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
    count = len(keys) + len(jumps) + sum(splits) - len(splits)
    if count > MAX_STATIONS:
        raise ParameterError(
            f"the schedule needs {count} time steps up to t = {last:g} s (a sine history is followed with "
            f"{loads.STATIONS_PER_PERIOD} steps per period), more than {MAX_STATIONS}: shorten the times or "
            f"lengthen the period")
    inner = {a + (b - a) * k / n for a, b, n in zip(keys, keys[1:], splits) for k in range(1, n)}
    every = np.array(sorted(set(keys) | inner))
    stations = []
    for t, value in zip(every.tolist(), history(every).tolist()):
        before = float(history.left(t)) if t in jumps else value
        # both sides of a jump: a step of zero duration between them (a jump to the same value is none; the
        # left limit is taken a hair before t, so a steep ramp's left limit differs from its value by rounding)
        if not math.isclose(before, value, rel_tol=1e-9):
            stations.append((t, before, False))
        stations.append((t, value, t in outputs))
    return stations


class Simulation:
    """Wires a grid, a material, an indenter and a schedule into a run.

    Parameters
    ----------
    grid : Grid
        Surface grid (and subsurface layers for stresses).
    material : materials.Elastic or another material with ``contact_compliance()``
        The half-space.
    indenter : indenters.Indenter
        The rigid body.
    schedule : schedules.Static
        What happens in time.
    inclusions : None
        Inhomogeneities (not available yet: must be None).
    options : dict or Options, optional
        Solver tolerances and run choices (see :class:`Options`).

    Raises
    ------
    ParameterError, ShapeError, LoadNotCarriedError
        At construction, before any step, for everything the parts cannot
        check alone: fewer than 3 cells along a non-periodic axis, a HeightMap
        of another shape than the grid, an offset the body cannot carry, a
        sudden change of load on a Kelvin-Voigt solid, more than
        :data:`MAX_STATIONS` time steps.
    """

    def __init__(self, grid, material, indenter, schedule, inclusions=None, options=None):
        if not isinstance(grid, Grid):
            raise ParameterError(f"grid must be a framework.Grid, got {type(grid).__name__}")
        if not hasattr(material, "contact_compliance"):
            raise ParameterError(f"material must be a framework material, got {type(material).__name__}")
        if not isinstance(indenter, Indenter):
            raise ParameterError(f"indenter must be a framework indenter, got {type(indenter).__name__}")
        if not isinstance(schedule, schedules.Static):
            raise ParameterError(f"schedule must be a framework schedule, got {type(schedule).__name__}")
        if inclusions is not None:
            raise ParameterError(f"inclusions are not supported by this version, got {inclusions!r}; pass None")
        self.grid, self.material, self.indenter, self.schedule = grid, material, indenter, schedule
        self.options = Options.from_value(options)
        self.result = None
        self._check()

    def _check(self):
        """Everything a run needs that the parts cannot check alone: found here, before any step."""
        grid, schedule = self.grid, self.schedule
        for axis, (cells, periodic) in enumerate(zip(grid.shape, grid.periodic)):
            if not periodic and cells < 3:
                raise ParameterError(
                    f"grid: shape[{axis}] must be >= 3 along the non-periodic axis x{axis + 1} (on a narrower grid "
                    f"every cell lies on the edge, where the half-space ends, so no contact can stay inside), got "
                    f"{cells}; use tens of cells to resolve a contact, or make the axis periodic")
        try:
            self._heights = self.indenter.on_grid(grid)
        except MemoryError as exc:
            raise ParameterError(f"grid: {grid.shape[0]} x {grid.shape[1]} cells do not fit in memory") from exc
        self._series = series = self.material.contact_compliance()
        offset = getattr(schedule, "offset", None)
        if offset is not None:
            _check_offset(offset, self.indenter.reach(grid), grid.coordinates())
        memory = len(series.terms) > 0 or series.flow > 0
        self._timeline = stations = _stations(schedule, refine=memory)
        if series.c0 <= 0:
            for (time, before, _), (later, after, _) in zip(stations, stations[1:]):
                if later == time and after != before:
                    raise ParameterError(
                        f"the material has no instantaneous compliance (C*(0) = {series.c0:g} 1/Pa, a Kelvin-Voigt "
                        f"solid): the {schedule.control} cannot change suddenly, as it does at t = {time:g} s "
                        f"(from {before:g} to {after:g}); use a Ramp or a Table that starts from zero")

    def steps(self, state=None):
        """Run step by step, yielding a :class:`StepRecord` at every output time.

        ``state`` (from a checkpoint) continues a run where it stopped.
        """
        grid, options = self.grid, self.options
        heights, series = self._heights, self._series
        operator = SurfaceCompliance(grid)
        integrator = (PronyRecursion if options.history == "recursive" else HereditarySum)(series, grid.shape)
        self._integrator, start, index = integrator, 0, 0
        if state is not None:
            integrator.restore({key: value for key, value in state.items() if key not in ("station", "index")})
            start, index = int(state["station"]), int(state["index"])
        load_control = self.schedule.control == "load"
        offset = getattr(self.schedule, "offset", None)
        coordinates = grid.coordinates() if offset is not None else None
        for number, (time, value, recorded) in enumerate(self._timeline):
            if number < start:
                continue
            compliance, memory = integrator.prepare(time)
            history_displacement = 0.0 if memory is None else operator.apply(memory)
            solution = solve_normal(
                lambda p: compliance * operator.apply(p), heights + history_displacement,
                cell_area=grid.cell_area, initial=integrator.pressure,
                load=value if load_control else None, approach=None if load_control else value,
                options=options.solver, window=operator.window,
                apply_window=lambda field, box: compliance * operator.apply_window(field, box),
                offset=offset, coordinates=coordinates)
            if options.check_edges:
                _check_edges(solution.pressure, grid, time, value, self.schedule.control)
            integrator.commit(time, solution.pressure)
            self._position = (number + 1, index + int(recorded))
            if recorded:
                yield StepRecord(index=index, time=time, load=solution.load, approach=solution.approach,
                                 pressure=solution.pressure,
                                 displacement=solution.displacement + history_displacement,
                                 gap=solution.gap, iterations=solution.iterations, residual=solution.residual,
                                 success=solution.success, tilt=tuple(np.arctan(solution.slopes)))
                index += 1

    def run(self, progress=False, callback=None, checkpoint=None, every=10, resume=None):
        """Run every step and return the :class:`Result`.

        Parameters
        ----------
        progress : bool
            Print one line per step (the same line on a terminal), ``step k/last``
            with the 0-based step index of ``Result`` and the exported files.
        callback : callable, optional
            ``callback(result, record)`` after each finished step (e.g. to write
            it to disk at once).
        checkpoint : str or os.PathLike, optional
            HDF5 file rewritten every ``every`` steps and at the end with the
            finished steps and the stepper's history (atomic renames). Its
            folder must exist and be writable.
        every : int
            Steps between checkpoints (an integer >= 1).
        resume : str or os.PathLike, optional
            A checkpoint of this same configuration: continue from it. The
            result equals the one of an uninterrupted run.

        Every argument is checked before the first step: a bad one raises
        :class:`ParameterError` naming it (a folder or a missing folder as
        ``checkpoint``, a missing, foreign or damaged ``resume`` file, ...).
        If a step fails, the exception carries the finished steps as
        ``exc.partial_result`` (also kept in ``self.result``).
        """
        from . import io
        progress = check_bool(progress, name="progress")
        if callback is not None and not callable(callback):
            raise ParameterError(f"callback must be callable as callback(result, record) or None, got {callback!r}")
        every = check_positive_int(every, name="every (steps between checkpoints)")
        if checkpoint is not None:
            checkpoint = io.check_target(checkpoint, name="checkpoint")
        self.result = result = Result(self.grid, self.material, self.indenter, self.schedule, self.options)
        state = None
        if resume is not None:
            state = self._resume(resume, result)
            if state is None:  # a finished run: nothing left to do
                return result
        total = len(self.schedule.times)
        end = "\r" if sys.stdout.isatty() else "\n"

        def save():
            position = self._position
            io.save(result, checkpoint, dict(self._integrator.snapshot(), station=position[0], index=position[1]),
                    name="checkpoint")

        try:
            for record in self.steps(state):
                result.append(record)
                if callback is not None:
                    callback(result, record)
                if checkpoint is not None and len(result) % every == 0:
                    save()
                if progress:
                    print(f"step {record.index}/{total - 1}  t = {record.time:.4g} s  load = {record.load:.4g} N  "
                          f"approach = {record.approach:.4g} m  iterations = {record.iterations}", end=end, flush=True)
            if checkpoint is not None and hasattr(self, "_position"):
                save()
        except FrameworkError as exc:
            exc.partial_result = result
            raise
        finally:
            if progress and end == "\r":
                print()
        return result

    def _resume(self, path, result):
        """Load the finished steps of a checkpoint into ``result``; return the stepper state (None: done)."""
        import json
        import os
        from . import io
        configuration, records, state = io.read(path, name="resume")
        path = os.fspath(path)
        mine = result.configuration()
        differing = sorted(key for key in mine if key != "framework_version"
                           and json.dumps(mine[key]) != json.dumps(configuration.get(key)))
        if differing:
            raise ParameterError(f"resume: the checkpoint {path!r} was written for another configuration "
                                 f"({', '.join(differing)} differ); run it with its own scenario or start afresh")
        outputs = len(self.schedule.times)
        if state is None and len(records) < outputs:
            raise ParameterError(f"resume: {path!r} holds {len(records)} of the {outputs} steps and no stepper "
                                 f"state: it is a saved result, not a checkpoint (run(checkpoint=...) writes one)")
        for record in records:
            result.append(record)
        if state is None or int(state["station"]) >= len(self._timeline):
            return None
        return state


def _check_edges(pressure, grid, time, value, control):
    edges = []
    if not grid.periodic[0] and (pressure[0].any() or pressure[-1].any()):
        edges.append("x1 = +/-%g m" % (grid.size[0] / 2))
    if not grid.periodic[1] and (pressure[:, 0].any() or pressure[:, -1].any()):
        edges.append("x2 = +/-%g m" % (grid.size[1] / 2))
    if edges:
        raise GridTooSmallError(
            f"the contact reaches the grid edge ({', '.join(edges)}) at t = {time:g} s under {control} = {value:g} "
            f"{'N' if control == 'load' else 'm'}; "
            f"the grid of size {grid.size} m cannot carry it: enlarge size or lower the {control}")


def _check_offset(offset, reach, coordinates):
    """The load centre must lie inside the convex hull of the cells the body can touch."""
    x1, x2 = coordinates[0][reach], coordinates[1][reach]
    for angle in np.linspace(0, 2 * np.pi, 180, endpoint=False):
        direction = np.array([np.cos(angle), np.sin(angle)])
        if direction @ np.asarray(offset) >= (x1 * direction[0] + x2 * direction[1]).max():
            raise LoadNotCarriedError(
                f"offset {tuple(offset)} m lies outside the area the indenter can touch (its face, within "
                f"{np.hypot(x1, x2).max():.4g} m of the axis): no contact can carry a load there")
