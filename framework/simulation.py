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

The stations of a run (:mod:`framework.stations`) are its output times, every
jump and kink of the load history, the finer steps a periodic history needs
and, for a transient rolling run, one step per cell of motion. Its options are
:class:`framework.options.Options`; a warm-started solve on an open grid runs
on a box around the contact (:mod:`framework.boxed_solve`).
"""
import sys

import numpy as np

from . import boxed_solve, resolution, schedules
from . import stations as stations_module
from ._validation import check_bool, check_positive_int
from .errors import FrameworkError, GridTooSmallError, LoadNotCarriedError, ParameterError
from .grid import Grid
from .history import HereditarySum, PronyRecursion, SteadyMemory
from .materials import ComplianceSeries
from .indenters import Indenter
from .operators.rolling import SteadyRollingCompliance, check_steady
from .operators.stiffness import SurfaceStiffness
from .operators.surface import SurfaceCompliance
from .options import Options
from .resolution import MIN_CELLS_PER_RADIUS  # noqa: F401 (kept importable from here)
from .result import Result, StepRecord
from .stations import MAX_STATIONS, Station  # noqa: F401 (MAX_STATIONS: named in the docstrings, kept importable)
from .solver import SolverOptions, solve_normal
from .steady_solver import solve_steady
from .time_error import StepControl


#: How many wake lengths ``|V| lambda`` a transient rolling grid must hold behind the contact: the history of
#: material that leaves the grid is dropped, and what it would still displace decays like ``exp(-d/(V lambda))``.
WAKE_LENGTHS = 3.0


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
        geometry = self.options.inclusion_geometry
        if geometry == "laminate" and not isinstance(self.material, Elastic):
            raise ParameterError(f"options.inclusion_geometry = 'laminate' needs an elastic matrix (its cut cuboids mix "
                                 f"the matrix's stiffness with the body's, and a viscoelastic one's relaxes), got "
                                 f"{type(self.material).__name__}; use 'staircase'")
        if self.options.inclusion_operator == "particle_mesh":     # on the bodies' cuboids alone
            from .inclusions.dispersed import BodiesInclusionProblem
            self._inclusion_problem = BodiesInclusionProblem(self.grid, self.material, inclusions,
                                                             margin=self.options.inclusion_margin, travel=travel)
        else:
            self._inclusion_problem = InclusionProblem(self.grid, self.material, inclusions, geometry=geometry,
                                                       margin=self.options.inclusion_margin, travel=travel)
        resolution.check_bodies(self.grid, inclusions, stacklevel=3)    # after the problem's own checks
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
        stations = stations_module.rolling_stations(schedule, grid, memory) if rolling else stations_module.static_stations(schedule, refine=memory)
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

        Between two stations a material with memory may take shorter steps, as
        many as ``options.time_tolerance`` needs (:mod:`framework.time_error`);
        a trial step whose estimated error exceeds it is solved again shorter,
        and nothing of it is committed. Only the stations' output times are
        recorded. ``steps_taken`` and ``steps_rejected`` count the solves.
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
        control = StepControl(series if not steady else ComplianceSeries(c0=1.0), options.time_tolerance,
                              self._timeline[-1].time)
        control.points = [(0.0, np.zeros(grid.shape))]      # the material at rest, no pressure
        if state is not None:
            integrator.restore({key: value for key, value in state.items() if key not in ("station", "index")
                                and not key.startswith(("inclusion_", "predictor_", "time_"))})
            start, index = int(state["station"]), int(state["index"])
            control.restore(state)
        self._control = control
        load_control = schedule.control == "load"
        coupling = None
        if self._inclusion_problem is not None:
            from .inclusions.coupling import ContactCoupling
            coupling = ContactCoupling(self._inclusion_problem, tolerance=options.coupling_tolerance,
                                       history=options.history,
                                       **({} if options.max_couplings is None else
                                          {"max_couplings": options.max_couplings}))
            if state is not None and "inclusion_eigenstrain" in state:
                coupling.restore(state)
        self._coupling = coupling
        offset = getattr(schedule, "offset", None)
        coordinates = grid.coordinates() if offset is not None else None
        self._predictor = predictor = _Predictor()
        if state is not None:
            predictor.restore(state)
        history_at, breaks, still = self._stretches()
        self.steps_taken = self.steps_rejected = 0
        for number, station in enumerate(self._timeline):
            if number < start:
                continue
            integrator.translate(station.shift, grid.periodic)
            control.translate(station.shift, grid.periodic)
            if coupling is not None:
                coupling.move(station.shift, grid.periodic)     # the inhomogeneities ride with the material
            adaptive = not steady and station.time <= still
            now, trials = integrator.time, 0
            while True:
                time = control.next_time(now, station.time) if adaptive else station.time
                value = station.value if time == station.time else float(history_at(time))
                compliance, memory = integrator.prepare(time)
                history_displacement = 0.0 if memory is None else operator.apply(memory)
                initial = integrator.pressure if steady else predictor.guess(time, integrator.pressure)
                arguments = dict(cell_area=grid.cell_area, initial=initial, options=options.solver,
                                 window=operator.window,
                                 apply_window=lambda field, box: operator.apply_window(field, box, compliance,
                                                                                       copy=False))
                if steady:
                    solution = solve_steady(operator.apply, heights, load=value, symmetric=symmetric,
                                            precondition=stiffness, **arguments)
                else:
                    def solve(extra=0.0):
                        base = heights + history_displacement + extra
                        control_value = dict(load=value if load_control else None,
                                             approach=None if load_control else value)
                        if offset is None and not any(grid.periodic):
                            return boxed_solve.solve_boxed(operator, compliance, base, stiffness=stiffness,
                                                           options=options.solver, initial=arguments["initial"],
                                                           cell_area=grid.cell_area, **control_value)
                        return solve_normal(
                            lambda p: operator.apply(p, compliance, copy=False), base, offset=offset,
                            coordinates=coordinates, diagonal=compliance * operator.diagonal,
                            precondition=stiffness, **control_value, **arguments)
                    if coupling is None:
                        solution = solve()
                    else:
                        warm = (coupling.eigenstrain, coupling.disturbance, coupling.displacement)
                        coupling.prepare(time)
                        coupled = coupling.solve(solve)
                        solution = coupled.contact
                        history_displacement = history_displacement + coupled.displacement
                displacement = solution.displacement + history_displacement
                if not steady:
                    elastic = float(np.abs(solution.displacement).max())
                    secant = compliance * float(np.abs(displacement).max()) / elastic if elastic > 0 else compliance
                    control.judge(time, solution.pressure, secant)
                if adaptive and not control.acceptable():   # rejected: nothing of it is kept, not even its warm start
                    self.steps_rejected += 1
                    control.reject(now)
                    if coupling is not None:
                        coupling.eigenstrain, coupling.disturbance, coupling.displacement = warm
                    trials += 1
                    control.check_count(trials, now, station.time)
                    continue
                self.steps_taken += 1
                if options.check_edges:
                    _check_edges(solution.pressure, grid, time, value, schedule.control)
                if coupling is not None:
                    coupling.commit(coupled)
                integrator.commit(time, solution.pressure)
                if not steady:
                    predictor.commit(time, solution.pressure)
                    control.accept()
                now = time
                if time == station.time:
                    break
                trials += 1
                control.check_count(trials, now, station.time)
            if station.time in breaks or (number and self._timeline[number - 1].time == station.time):
                control.new_stretch()
            self._position = (number + 1, index + int(station.recorded))
            if station.recorded:
                yield StepRecord(index=index, time=station.time, load=solution.load, approach=solution.approach,
                                 pressure=solution.pressure, displacement=displacement,
                                 gap=solution.gap, iterations=solution.iterations, residual=solution.residual,
                                 success=solution.success, tilt=tuple(np.arctan(solution.slopes)),
                                 time_error=control.error,
                                 **({} if coupling is None else dict(
                                     eigenstrain=coupled.eigenstrain, inclusion_stress=coupled.stress,
                                     relaxed_eigenstrain=coupled.relaxed,
                                     couplings=coupled.couplings, inclusion_start=coupling.problem.start)))
                index += 1

    def _stretches(self):
        """``(history, breaks, still)``: the load or approach at any time [s], the times [s] after which the
        pressure's curvature starts afresh (jumps and kinks of the history, the start of a motion), and the
        last time [s] at which the body is at rest (a transient roll takes one step per cell after it)."""
        schedule = self.schedule
        if isinstance(schedule, schedules.Rolling):
            if schedule.steady:
                return (lambda t: 0.0), set(), -np.inf
            begin = schedule.motion_start
            breaks = {begin} | {begin + float(t) for t in schedule.history.jumps + schedule.history.kinks}
            if schedule.start is None:
                return schedule.history, breaks, begin
            start = schedule.start.history
            return start, breaks | {float(t) for t in start.jumps + start.kinks}, begin
        history = schedule.history
        return history, {float(t) for t in history.jumps + history.kinks}, np.inf

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
        # a result reads its fields on the box (records, stress): the bodies' problem has none, the result makes
        # the box's operators only where asked (stress_at)
        boxed = self._inclusion_problem if self.options.inclusion_operator == "box" else None
        self.result = result = Result(self.grid, self.material, self.indenter, self.schedule, self.options,
                                      inclusions=self.inclusions, inclusion_problem=boxed)
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
                                             **self._predictor.snapshot(), **self._control.snapshot(), **extra),
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
        resolution.check_result(result, stacklevel=2)
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
                                 f"({_differences(mine, configuration, differing)}); run it with its own scenario "
                                 f"or start afresh")
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


#: Options an earlier version did not have, and the value that behaves as it did (a checkpoint without them).
EARLIER_OPTIONS = {"time_tolerance": None}


def _differences(mine, theirs, keys):
    """What differs between two configurations, for a message: the keys, and within ``options`` which option
    with both values (an option the checkpoint predates: the value to give to resume it)."""
    import json
    plain, options = [], []
    for key in keys:
        if key == "options" and isinstance(mine.get(key), dict) and isinstance(theirs.get(key), dict):
            ours, its = mine[key], theirs[key]
            for name in sorted(set(ours) | set(its)):
                if json.dumps(ours.get(name)) == json.dumps(its.get(name)):
                    continue
                if name not in its and name in EARLIER_OPTIONS:
                    options.append(f"options.{name}: the checkpoint predates it; give {name}="
                                   f"{EARLIER_OPTIONS[name]!r} to resume it")
                else:
                    options.append(f"options.{name}: {ours.get(name)!r} here, {its.get(name)!r} in the checkpoint")
        else:
            plain.append(key)
    return "; ".join(([f"{', '.join(plain)} differ"] if plain else []) + options)


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
