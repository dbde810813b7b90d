"""Run options of a :class:`~framework.Simulation`: solver tolerances and what a run checks and keeps."""
from dataclasses import dataclass, field, replace

from ._validation import check_bool, check_positive_int, check_quantity, check_real
from .errors import ParameterError
from .solver import SolverOptions

__all__ = ["DEFAULT_TIME_TOLERANCE", "Options"]

#: The default ``Options.time_tolerance``.
DEFAULT_TIME_TOLERANCE = 1e-3
#: The range of ``Options.time_tolerance``: tighter than 1e-8 the contact solver's own tolerance is the error.
TIME_TOLERANCES = (1e-8, 0.1)
#: The inhomogeneities' eigenstrain operators (``Options.inclusion_operator``).
OPERATORS = ("box", "particle_mesh")


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
        Relative distance of the inhomogeneities' surface displacement from the
        step's fixed point (its last change, or that change times the iteration's
        contraction) at which a step's contact and eigenstrains count as
        converged together.
    max_couplings : int or None
        Coupling iterations (one eigenstrain-operator product each) a step over
        inhomogeneities may take before it raises ConvergenceError; None: 100.
    inclusion_geometry : str
        How the cuboids hold an inhomogeneity: ``"staircase"`` (whole cuboids whose
        centre it contains) or ``"laminate"`` (also the cuboids its boundary cuts, each
        with the body's share of its volume and a body/matrix laminate's stiffness:
        :mod:`framework.inclusions.subcell`; an elastic matrix only).
    inclusion_operator : str
        The eigenstrain operator of the inhomogeneities: ``"box"`` (the box around them, exact) or
        ``"particle_mesh"`` (their cuboids alone, a coarse box and exact near tables:
        :class:`~framework.operators.particle_mesh.ParticleMeshEigenstrain`; memory follows the bodies, not
        the box, at an error of about 1e-3 of the operator; staircase geometry only; 100 glass spheres of 8 cuboids
        per radius rolled over in 23 s a step and 1.76 GiB against the box's 33 s and 3.13 GiB, see the README).
    time_tolerance : float or None
        Largest estimated time-stepping error of a material with memory,
        relative to the run's pressure and approach scale, in [1e-8, 0.1]: between two output times the run
        takes as many steps as it needs (:mod:`framework.time_error`), and
        records only the output times. None: one step per output time (and
        per jump, kink and ``resolution`` step of the load history), as
        before; the error is estimated all the same (``Result.time_error``).
        A transient rolling run moves one cell per step whatever it is, and a
        solid without instantaneous compliance (Kelvin-Voigt, first order)
        keeps the stations as its steps.
    """

    solver: SolverOptions = field(default_factory=SolverOptions)
    check_edges: bool = True
    history: str = "recursive"
    inclusion_margin: float = None
    coupling_tolerance: float = 1e-8
    max_couplings: int = None
    time_tolerance: float = DEFAULT_TIME_TOLERANCE
    inclusion_geometry: str = "staircase"
    inclusion_operator: str = "box"

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
        if self.max_couplings is not None:
            object.__setattr__(self, "max_couplings", check_positive_int(self.max_couplings, name="max_couplings"))
        from .inclusions.subcell import GEOMETRIES
        if not isinstance(self.inclusion_geometry, str) or self.inclusion_geometry not in GEOMETRIES:
            raise ParameterError(f"inclusion_geometry must be one of {', '.join(map(repr, GEOMETRIES))}, got "
                                 f"{self.inclusion_geometry!r}")
        if not isinstance(self.inclusion_operator, str) or self.inclusion_operator not in OPERATORS:
            raise ParameterError(f"inclusion_operator must be one of {', '.join(map(repr, OPERATORS))}, got "
                                 f"{self.inclusion_operator!r}")
        if self.inclusion_operator == "particle_mesh" and self.inclusion_geometry != "staircase":
            raise ParameterError(f"inclusion_operator = 'particle_mesh' takes whole cuboids only: inclusion_geometry "
                                 f"must be 'staircase', got {self.inclusion_geometry!r}")
        if self.time_tolerance is not None:
            value = check_real(self.time_tolerance, name="time_tolerance")
            low, high = TIME_TOLERANCES
            if not low <= value <= high:
                raise ParameterError(f"time_tolerance must lie in [{low:g}, {high:g}] (the time-stepping error "
                                     f"relative to the pressure and approach scale), or be None (one step per "
                                     f"output time), got {value!r}")
            object.__setattr__(self, "time_tolerance", value)

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
        run_keys = {"check_edges", "history", "inclusion_margin", "coupling_tolerance", "max_couplings",
                    "time_tolerance", "inclusion_geometry", "inclusion_operator"}
        unknown = set(value) - solver_keys - run_keys
        if unknown:
            raise ParameterError(f"unknown option(s) {sorted(unknown)}; expected some of "
                                 f"{sorted(solver_keys | run_keys)}")
        solver = replace(SolverOptions(), **{k: v for k, v in value.items() if k in solver_keys})
        return cls(solver=solver, **{k: v for k, v in value.items() if k in run_keys})
