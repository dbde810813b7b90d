"""The time stepper: one mechanism for every schedule and material.

Each step is an elastic contact problem with the step's effective compliance
plus a known displacement from the history (THEORY.md sec. 5): with
``C*(t) = c0 + sum_k c_k (1 - exp(-t/lambda_k))`` and a pressure varying
linearly in time within a step,

    u_n = K * [ C_eff p_n - sum_k c_k (e_k q_k - w_k p_{n-1}) ],
    C_eff = c0 + sum_k c_k (1 - w_k),  e_k = exp(-dt/lambda_k),
    w_k = (lambda_k/dt)(1 - e_k)  (1 when dt = 0),
    q_k <- e_k q_k + w_k (p_n - p_{n-1}),

which costs one extra convolution per step and one surface field per term. An
elastic material has no terms, and the steps are independent solves
warm-started from the previous pressure.
"""
from dataclasses import dataclass, field, replace

import numpy as np

from . import schedules
from .errors import FrameworkError, GridTooSmallError, ParameterError
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
    """

    solver: SolverOptions = field(default_factory=SolverOptions)
    check_edges: bool = True

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
        unknown = set(value) - solver_keys - {"check_edges"}
        if unknown:
            raise ParameterError(f"unknown option(s) {sorted(unknown)}; expected some of "
                                 f"{sorted(solver_keys | {'check_edges'})}")
        solver = replace(SolverOptions(), **{k: v for k, v in value.items() if k in solver_keys})
        return cls(solver=solver, check_edges=value.get("check_edges", True))


@dataclass
class HistoryState:
    """What the stepper carries from one step to the next (all on the surface grid).

    ``pressure`` is the last pressure, ``fields`` the Prony history fields ``q_k``
    (one per compliance term); rolling translates both with the material.
    """

    time: float
    pressure: np.ndarray
    fields: np.ndarray

    @classmethod
    def at_rest(cls, shape, n_terms):
        return cls(0.0, np.zeros(shape), np.zeros((n_terms,) + tuple(shape)))


def _stations(schedule):
    """``(time, value, recorded)``: the output times and both sides of every jump."""
    history, times = schedule.history, schedule.times
    jumps = {float(t) for t in history.jumps if t <= times[-1]}
    outputs = {float(t) for t in times}
    stations = []
    for t in sorted(outputs | jumps):
        if t in jumps:
            stations.append((t, float(history.left(t)), False))
        stations.append((t, float(history(t)), t in outputs))
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

    def steps(self):
        """Run step by step, yielding a :class:`StepRecord` at every output time."""
        grid, options = self.grid, self.options
        heights = self.indenter.on_grid(grid)
        operator = SurfaceCompliance(grid)
        series = self.material.contact_compliance()
        coefficients, retardation = series.coefficients, series.times
        state = HistoryState.at_rest(grid.shape, len(series.terms))
        load_control = self.schedule.control == "load"
        index = 0
        for time, value, recorded in _stations(self.schedule):
            dt = time - state.time
            decay = np.exp(-dt / retardation)
            weight = np.where(dt > 0, retardation / max(dt, 1e-300) * -np.expm1(-dt / retardation), 1.0)
            compliance = series.c0 + float(np.sum(coefficients * (1 - weight)))
            if len(coefficients):
                memory = np.tensordot(coefficients * decay, state.fields, axes=1) \
                    - np.sum(coefficients * weight) * state.pressure
                history_displacement = -operator.apply(memory)
            else:
                history_displacement = 0.0
            solution = solve_normal(
                lambda p: compliance * operator.apply(p), heights + history_displacement,
                cell_area=grid.cell_area, initial=state.pressure,
                load=value if load_control else None, approach=None if load_control else value,
                options=options.solver, window=operator.window,
                apply_window=lambda field, box: compliance * operator.apply_window(field, box))
            if options.check_edges:
                _check_edges(solution.pressure, grid, time, value, self.schedule.control)
            pressure = solution.pressure
            state.fields = decay[:, None, None] * state.fields + weight[:, None, None] * (pressure - state.pressure)
            state.pressure, state.time = pressure, time
            if recorded:
                yield StepRecord(index=index, time=time, load=solution.load, approach=solution.approach,
                                 pressure=pressure, displacement=solution.displacement + history_displacement,
                                 gap=solution.gap, iterations=solution.iterations, residual=solution.residual,
                                 success=solution.success)
                index += 1

    def run(self, progress=False):
        """Run every step and return the :class:`Result`.

        If a step fails, the exception carries the finished steps as
        ``exc.partial_result`` (also kept in ``self.result``).
        """
        self.result = result = Result(self.grid, self.material, self.indenter, self.schedule, self.options)
        total = len(self.schedule.times)
        try:
            for record in self.steps():
                result.append(record)
                if progress:
                    print(f"\rstep {record.index + 1}/{total}  t = {record.time:.4g} s  "
                          f"load = {record.load:.4g} N  iterations = {record.iterations}", end="", flush=True)
        except FrameworkError as exc:
            exc.partial_result = result
            raise
        finally:
            if progress:
                print()
        return result


def _check_edges(pressure, grid, time, value, control):
    n1, n2 = grid.shape
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
