"""Run options of a :class:`~framework.Simulation`: solver tolerances and what a run checks and keeps."""
from dataclasses import dataclass, field, replace

from ._validation import check_bool, check_quantity, check_real
from .errors import ParameterError
from .solver import SolverOptions

__all__ = ["Options"]


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
