"""The time stepper: one loop for every schedule and material.

Each step prepares the history (the material moved under a rolling body is
translated with everything it remembers, :mod:`framework.history`), solves
the contact of the step, and commits the new pressure. The step's contact is
elastic with the step's effective compliance plus the displacement the
history leaves (THEORY.md sec. 5): conjugate gradients with the symmetric
half-space operator (:func:`framework.solver.solve_normal`). The steady state
of a rolling body has its history folded into a non-symmetric operator
(:mod:`framework.operators.rolling`) and its own solver
(:func:`framework.steady_solver.solve_steady`), with no history to carry.

The stations of a run (:class:`Station`) are its output times, every jump
and kink of the load history, the finer steps a periodic history needs and,
for a transient rolling run, one step per cell of motion.
"""
import math
import sys
from dataclasses import dataclass, field, replace

import numpy as np

from . import loads, schedules
from ._validation import check_bool, check_positive_int, check_quantity, check_real
from .errors import FrameworkError, GridTooSmallError, LoadNotCarriedError, ParameterError
from .grid import Grid
from .history import HereditarySum, PronyRecursion, SteadyMemory
from .indenters import Indenter
from .operators.rolling import SteadyRollingCompliance, check_steady
from .operators.stiffness import SurfaceStiffness
from .operators.surface import SurfaceCompliance
from .result import Result, StepRecord
from .solver import SolverOptions, solve_normal
from .steady_solver import solve_steady


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
    inclusion_margin : float or None
        Distance [m] around the inhomogeneities where the stress includes their
        eigenstrains' fields (the eigenstrain operators' box); None: half the
        largest semi-axis.
    coupling_tolerance : float
        Relative change of the inhomogeneities' surface displacement at which a
        step's contact and eigenstrains count as converged together.
    """

    solver: SolverOptions = field(default_factory=SolverOptions)
    check_edges: bool = True
    history: str = "recursive"
    inclusion_margin: float = None
    coupling_tolerance: float = 1e-8

    def __post_init__(self):
        if not isinstance(self.solver, SolverOptions):
            raise ParameterError(f"solver must be a SolverOptions, got {self.solver!r}")
        object.__setattr__(self, "check_edges", check_bool(self.check_edges, name="check_edges"))
        if self.history not in ("recursive", "hereditary"):
            raise ParameterError(f"history must be 'recursive' or 'hereditary', got {self.history!r}")
        if self.inclusion_margin is not None:
            object.__setattr__(self, "inclusion_margin",
                               check_quantity(self.inclusion_margin, name="inclusion_margin", unit="m", zero=True))
        tolerance = check_real(self.coupling_tolerance, name="coupling_tolerance")
        if not 1e-14 <= tolerance < 1:
            raise ParameterError(f"coupling_tolerance must lie in [1e-14, 1) (a relative change), got {tolerance!r}")
        object.__setattr__(self, "coupling_tolerance", tolerance)

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
        run_keys = {"check_edges", "history", "inclusion_margin", "coupling_tolerance"}
        unknown = set(value) - solver_keys - run_keys
        if unknown:
            raise ParameterError(f"unknown option(s) {sorted(unknown)}; expected some of "
                                 f"{sorted(solver_keys | run_keys)}")
        solver = replace(SolverOptions(), **{k: v for k, v in value.items() if k in solver_keys})
        return cls(solver=solver, **{k: v for k, v in value.items() if k in run_keys})


#: The most time steps a run may take: beyond it a schedule is a mistake (e.g. a 1 ms period over a year).
MAX_STATIONS = 1_000_000

#: How many wake lengths ``|V| lambda`` a transient rolling grid must hold behind the contact: the history of
#: material that leaves the grid is dropped, and what it would still displace decays like ``exp(-d/(V lambda))``.
WAKE_LENGTHS = 3.0


@dataclass(frozen=True)
class Station:
    """One step of a run: its time [s], the load [N] or approach [m] it imposes, whether it is recorded,
    and the whole cells ``(c1, c2)`` the material moved under the body since the previous station."""

    time: float
    value: float
    recorded: bool
    shift: tuple = (0, 0)


def _stations(schedule, refine=True):
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


def _rolling_stations(schedule, grid, refine=True):
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
    stations = _stations(schedule.start, refine) if schedule.start is not None else []
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
    schedule : schedules.Static, schedules.Eccentric or schedules.Rolling
        What happens in time.
    inclusions : inclusions.InclusionSet or list of inclusions.Ellipsoid, optional
        Elastic inhomogeneities in the half-space (an elastic matrix, ``Static``
        or ``Eccentric`` schedules): each step converges the contact and the
        equivalent eigenstrains together (:class:`framework.inclusions.coupling.ContactCoupling`).
    options : dict or Options, optional
        Solver tolerances and run choices (see :class:`Options`).

    Raises
    ------
    ParameterError, ShapeError, LoadNotCarriedError
        At construction, before any step, for everything the parts cannot
        check alone: fewer than 3 cells along a non-periodic axis, a HeightMap
        of another shape than the grid, an offset the body cannot carry, a
        sudden change of load on a Kelvin-Voigt solid, more than
        :data:`MAX_STATIONS` time steps, inclusions in an incompressible
        matrix (``poisson = 0.5``) or too soft for the equivalent-inclusion method.
    """

    def __init__(self, grid, material, indenter, schedule, inclusions=None, options=None):
        if not isinstance(grid, Grid):
            raise ParameterError(f"grid must be a framework.Grid, got {type(grid).__name__}")
        if not hasattr(material, "contact_compliance"):
            raise ParameterError(f"material must be a framework material, got {type(material).__name__}")
        if not isinstance(indenter, Indenter):
            raise ParameterError(f"indenter must be a framework indenter, got {type(indenter).__name__}")
        if not isinstance(schedule, (schedules.Static, schedules.Rolling)):
            raise ParameterError(f"schedule must be a framework schedule (Static, Eccentric, Rolling), got "
                                 f"{type(schedule).__name__}")
        self.grid, self.material, self.indenter, self.schedule = grid, material, indenter, schedule
        self.options = Options.from_value(options)
        self.result = None
        self._check()
        self.inclusions = self._check_inclusions(inclusions)

    def _check_inclusions(self, inclusions):
        """The inhomogeneities as an InclusionSet with their operators built (None without any)."""
        if inclusions is None:
            self._inclusion_problem = None
            return None
        from .inclusions import InclusionSet
        from .inclusions.field import InclusionProblem
        from .materials import Elastic, Viscoelastic
        if not isinstance(inclusions, InclusionSet):
            inclusions = InclusionSet(inclusions)
        if len(inclusions) == 0:
            self._inclusion_problem = None
            return inclusions
        if not isinstance(self.material, (Elastic, Viscoelastic)):
            raise ParameterError(f"inclusions need an elastic matrix or a viscoelastic solid with an instantaneous "
                                 f"modulus (materials.Elastic or materials.Viscoelastic, e.g. StandardLinearSolid, "
                                 f"PMMA), got {type(self.material).__name__}")
        travel = None
        if isinstance(self.schedule, schedules.Rolling):
            if self.schedule.steady:
                raise ParameterError("inclusions: a steady rolling state does not exist over a single inhomogeneity "
                                     "(the contact changes as the body passes it); roll over it in a transient run "
                                     "(steady=False, with a distance)")
            travel = [station.shift for station in self._timeline]
        self._inclusion_problem = InclusionProblem(self.grid, self.material, inclusions,
                                                   margin=self.options.inclusion_margin, travel=travel)
        return inclusions

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
        if isinstance(schedule, schedules.Rolling) and schedule.steady and self.options.history != "recursive":
            raise ParameterError(f"options.history = {self.options.history!r} has no meaning for a steady run "
                                 f"(steady=True): the steady state is solved in the body's frame, with no history to "
                                 f"carry; leave the option out, or roll a transient run")
        memory = len(series.terms) > 0 or series.flow > 0
        rolling = isinstance(schedule, schedules.Rolling)
        stations = _rolling_stations(schedule, grid, memory) if rolling else _stations(schedule, refine=memory)
        self._timeline = stations
        self.output_times = np.array([station.time for station in stations if station.recorded])
        if series.c0 <= 0:
            where = " (a rolling run: as its load, or as start=schedules.Static(load=loads.Ramp(...)))"
            for before, after in zip([Station(0.0, 0.0, False)] + stations, stations):
                if after.time == before.time and after.value != before.value:
                    raise ParameterError(
                        f"the material has no instantaneous compliance (C*(0) = {series.c0:g} 1/Pa, a Kelvin-Voigt "
                        f"solid): the {schedule.control} cannot change suddenly, as it does at t = {after.time:g} s "
                        f"(from {before.value:g} to {after.value:g}); use a Ramp or a Table that starts from zero"
                        f"{where if rolling else ''}")
        if rolling:
            self._check_rolling()

    def _check_rolling(self):
        """What a rolling body needs of the material and the grid."""
        grid, schedule, series = self.grid, self.schedule, self._series
        axis = schedule.axis
        if schedule.steady:
            check_steady(grid, series, schedule.velocity)
            return
        if grid.periodic[axis] or series.flow:
            return  # the material comes round again; a fluid's groove never ends: no wake fits either
        # The grid must hold the contact and its wake behind the body's axis. The largest contact the run can
        # have is the one at rest with the compliance reached at its end: solve it once, now.
        stations = self._timeline
        duration = stations[-1].time
        compliance = float(series(duration))
        load = max(station.value for station in stations)
        self._surface = operator = SurfaceCompliance(grid)     # the stepper's own, reused
        self._stiffness = SurfaceStiffness(grid)                # its preconditioner, reused too
        contact = solve_normal(lambda p: operator.apply(p, compliance, copy=False), self._heights,
                               cell_area=grid.cell_area,
                               load=load, options=SolverOptions(tolerance=1e-6, residual_tolerance=1e-4,
                                                                raise_on_failure=False),
                               window=operator.window,
                               apply_window=lambda f, box: operator.apply_window(f, box, compliance, copy=False),
                               precondition=self._stiffness).pressure > 0
        along = (grid.x1, grid.x2)[axis]
        touched = along[contact.any(axis=1 - axis)]
        sign = np.sign(schedule.velocity[axis])
        trailing = float((-sign * touched).max()) if touched.size else 0.0   # how far the contact reaches behind
        significant = [lam for c, lam in series.terms if c >= 0.01 * series.coefficients.sum()]
        wake = WAKE_LENGTHS * schedule.speed * max(significant, default=0.0)
        behind = grid.size[axis] / 2
        if trailing + wake > behind:
            raise GridTooSmallError(
                f"the grid is too short for the contact and its wake: a transient rolling run drops the history of "
                f"the material that leaves the grid, so behind the body's axis the grid must extend at least "
                f"{trailing + wake:.4g} m (the contact at rest reaches {trailing:.4g} m behind it, plus "
                f"{WAKE_LENGTHS:g} wake lengths |V| lambda = {wake:.4g} m); it extends {behind:.4g} m (size[{axis}] "
                f"= {grid.size[axis]:g} m). Lengthen the grid along x{axis + 1} to at least "
                f"{2 * (trailing + wake):.4g} m, or solve the steady state (steady=True), which needs no wake")

    def steps(self, state=None):
        """Run step by step, yielding a :class:`StepRecord` at every output time.

        ``state`` (from a checkpoint) continues a run where it stopped.
        """
        grid, options, schedule = self.grid, self.options, self.schedule
        heights, series = self._heights, self._series
        steady = getattr(schedule, "steady", False)
        if steady:
            operator = SteadyRollingCompliance(grid, series, schedule.velocity)
            symmetric = operator.symmetric()
            integrator = SteadyMemory(grid.shape)
        else:
            operator = getattr(self, "_surface", None) or SurfaceCompliance(grid)
            integrator = (PronyRecursion if options.history == "recursive" else HereditarySum)(series, grid.shape)
        stiffness = getattr(self, "_stiffness", None) or SurfaceStiffness(grid)   # the solves' preconditioner
        self._integrator, start, index = integrator, 0, 0
        if state is not None:
            integrator.restore({key: value for key, value in state.items() if key not in ("station", "index")
                                and not key.startswith(("inclusion_", "predictor_"))})
            start, index = int(state["station"]), int(state["index"])
        load_control = schedule.control == "load"
        coupling = None
        if self._inclusion_problem is not None:
            from .inclusions.coupling import ContactCoupling
            coupling = ContactCoupling(self._inclusion_problem, tolerance=options.coupling_tolerance,
                                       history=options.history)
            if state is not None and "inclusion_eigenstrain" in state:
                coupling.restore(state)
        self._coupling = coupling
        offset = getattr(schedule, "offset", None)
        coordinates = grid.coordinates() if offset is not None else None
        self._predictor = predictor = _Predictor()
        if state is not None:
            predictor.restore(state)
        for number, station in enumerate(self._timeline):
            if number < start:
                continue
            integrator.translate(station.shift, grid.periodic)
            if coupling is not None:
                coupling.move(station.shift, grid.periodic)     # the inhomogeneities ride with the material
            compliance, memory = integrator.prepare(station.time)
            history_displacement = 0.0 if memory is None else operator.apply(memory)
            initial = integrator.pressure if steady else predictor.guess(station.time, integrator.pressure)
            arguments = dict(cell_area=grid.cell_area, initial=initial, options=options.solver,
                             window=operator.window,
                             apply_window=lambda field, box: operator.apply_window(field, box, compliance, copy=False))
            if steady:
                solution = solve_steady(operator.apply, heights, load=station.value, symmetric=symmetric,
                                        precondition=stiffness, **arguments)
            else:
                def solve(extra=0.0):
                    base = heights + history_displacement + extra
                    control = dict(load=station.value if load_control else None,
                                   approach=None if load_control else station.value)
                    if offset is None and not any(grid.periodic):
                        return _solve_boxed(operator, compliance, base, stiffness=stiffness, options=options.solver,
                                            initial=arguments["initial"], cell_area=grid.cell_area, **control)
                    return solve_normal(
                        lambda p: operator.apply(p, compliance, copy=False), base, offset=offset,
                        coordinates=coordinates, diagonal=compliance * operator.diagonal, precondition=stiffness,
                        **control, **arguments)
                if coupling is None:
                    solution = solve()
                else:
                    coupling.prepare(station.time)
                    coupled = coupling.solve(solve)
                    coupling.commit(coupled)
                    solution = coupled.contact
                    history_displacement = history_displacement + coupled.displacement
            if options.check_edges:
                _check_edges(solution.pressure, grid, station.time, station.value, schedule.control)
            integrator.commit(station.time, solution.pressure)
            if not steady:
                predictor.commit(station.time, solution.pressure)
            self._position = (number + 1, index + int(station.recorded))
            if station.recorded:
                yield StepRecord(index=index, time=station.time, load=solution.load, approach=solution.approach,
                                 pressure=solution.pressure,
                                 displacement=solution.displacement + history_displacement,
                                 gap=solution.gap, iterations=solution.iterations, residual=solution.residual,
                                 success=solution.success, tilt=tuple(np.arctan(solution.slopes)),
                                 **({} if coupling is None else dict(
                                     eigenstrain=coupled.eigenstrain, inclusion_stress=coupled.stress,
                                     couplings=coupled.couplings, inclusion_start=coupling.problem.start)))
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
        self.result = result = Result(self.grid, self.material, self.indenter, self.schedule, self.options,
                                      inclusions=self.inclusions, inclusion_problem=self._inclusion_problem)
        state = None
        if resume is not None:
            state = self._resume(resume, result)
            if state is None:  # a finished run: nothing left to do
                return result
        total = len(self.output_times)
        end = "\r" if sys.stdout.isatty() else "\n"

        def save():
            position = self._position
            extra = {} if self._coupling is None else self._coupling.snapshot()
            io.save(result, checkpoint, dict(self._integrator.snapshot(), station=position[0], index=position[1],
                                             **self._predictor.snapshot(), **extra),
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
        differing = sorted(key for key in set(mine) | set(configuration) if key != "framework_version"
                           and json.dumps(mine.get(key)) != json.dumps(configuration.get(key)))
        if differing:
            raise ParameterError(f"resume: the checkpoint {path!r} was written for another configuration "
                                 f"({', '.join(differing)} differ); run it with its own scenario or start afresh")
        io.check_records(records, self.grid, self.inclusions, self.options, path=path, name="resume")
        io.check_state(state, path=path, name="resume")
        outputs = len(self.output_times)
        if state is None and len(records) < outputs:
            raise ParameterError(f"resume: {path!r} holds {len(records)} of the {outputs} steps and no stepper "
                                 f"state: it is a saved result, not a checkpoint (run(checkpoint=...) writes one)")
        for record in records:
            result.append(record)
        if state is None or int(state["station"]) >= len(self._timeline):
            return None
        return state


#: The box a warm-started solve iterates on holds the start's contact grown by this fraction of its extent
#: (and :data:`BOX_CELLS` cells at least) on every side.
BOX_MARGIN = 0.25
BOX_CELLS = 4


def _solve_boxed(operator, compliance, base, *, stiffness, options, initial, cell_area, load=None, approach=None):
    """A contact solve on an open grid that iterates on a box around the cells the contact can reach.

    The box holds the start's contact (the last step's, for a warm start) grown by :data:`BOX_MARGIN`
    of its extent on every side; the conjugate gradients run on it alone, each product an FFT of twice
    the box instead of twice the grid (a transient roll over a 512 x 256 grid: 128^2 instead of
    1024 x 512). The pressure outside the box is zero, which is the solution wherever the gap there
    stays open: the whole grid's displacement is computed once at the end, and a cell outside the box
    that interpenetrates (beyond the solver's residual tolerance) sends the solve to the whole grid,
    started from the box's pressure. Without a start, or when the box would cover most of the grid,
    the whole grid from the beginning.
    """
    def apply(pressure):
        return operator.apply(pressure, compliance, copy=False)

    def within(field, window):       # a window of the box (the box itself when the window is all of it)
        return operator.apply_window(field, box if window == (slice(None), slice(None)) else window, compliance,
                                     copy=False)

    common = dict(window=operator.window, diagonal=compliance * operator.diagonal, precondition=stiffness,
                  cell_area=cell_area, load=load, approach=approach, options=options)
    whole = dict(common, apply_window=lambda field, window: operator.apply_window(field, window, compliance,
                                                                                   copy=False))
    support = None if initial is None else np.asarray(initial) > 0
    if support is None or not support.any():
        return solve_normal(apply, base, initial=initial, **whole)
    box = []
    for axis, n in enumerate(base.shape):
        cells = np.flatnonzero(support.any(axis=1 - axis))
        grow = max(BOX_CELLS, int(np.ceil(BOX_MARGIN * (cells[-1] - cells[0] + 1))))
        first, last = cells[0] - grow, cells[-1] + 1 + grow
        # sides of whole multiples of 32 cells: a run meets few box shapes, each planned once
        size = min(n, -(-(last - first) // 32) * 32)
        first = min(max(0, first - (size - (last - first)) // 2), n - size)
        box.append(slice(first, first + size))
    box = tuple(box)
    if (box[0].stop - box[0].start) * (box[1].stop - box[1].start) > 0.5 * base.size:
        return solve_normal(apply, base, initial=initial, **whole)
    boxed = solve_normal(lambda p: within(p, box), base[box], initial=np.asarray(initial)[box],
                         apply_window=within, **common)
    pressure = np.zeros(base.shape)
    pressure[box] = boxed.pressure
    displacement = operator.apply(pressure, compliance)
    gap = base + displacement - boxed.approach
    outside = np.ones(base.shape, dtype=bool)
    outside[box] = False
    scale = max(np.abs(displacement).max(), np.finfo(float).tiny)
    if -gap[outside].min(initial=0.0) > options.residual_tolerance * scale:    # the contact left the box
        return solve_normal(apply, base, initial=pressure, **whole)
    return replace(boxed, pressure=pressure, displacement=displacement, gap=gap)


class _Predictor:
    """The warm start of a step: the pressure extrapolated linearly in time from the last two steps.

    Between two steps of one smooth stretch of the load history the pressure
    field changes smoothly (a creeping contact grows, a rolling one settles):
    ``p(t) = p1 + (t - t1) (p1 - p0) / (t1 - t0)``, clipped to non-negative
    values, is a closer start than ``p1`` (the solver scales it to the step's
    load). A step of no duration (both sides of a jump of the load) starts a
    new stretch. Measured on a ball creeping into a viscoelastic solid
    (bench/contact_loop.py): 10-20 % fewer iterations per step than ``p1``;
    extrapolating with more steps, in log-time or of the gap too gains no more,
    as cells entering the contact each step are beyond any extrapolation.

    Its memory is in the body's frame (the contact's), and part of a checkpoint.
    """

    def __init__(self):
        self.times, self.pressures = [], []

    def guess(self, time, fallback):
        """The predicted pressure [Pa] at ``time`` [s] (``fallback`` before two steps of a stretch)."""
        if len(self.times) < 2 or time <= self.times[-1]:
            return fallback
        (t0, t1), (p0, p1) = self.times, self.pressures
        return np.maximum(p1 + (time - t1) / (t1 - t0) * (p1 - p0), 0.0)

    def commit(self, time, pressure):
        """Remember a step's pressure [Pa] at ``time`` [s]."""
        if self.times and time <= self.times[-1]:
            self.times, self.pressures = [], []   # a jump: the stretch before it says nothing of the one after
        self.times = self.times[-1:] + [time]
        self.pressures = self.pressures[-1:] + [pressure]

    def snapshot(self):
        """The memory as arrays (for a checkpoint)."""
        return {"predictor_times": np.array(self.times, dtype=float), "predictor_pressures": np.array(self.pressures)}

    def restore(self, state):
        """Take the memory back from a checkpoint's state (one without it: start afresh)."""
        if "predictor_times" in state:
            self.times, self.pressures = list(state["predictor_times"]), list(state["predictor_pressures"])


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
