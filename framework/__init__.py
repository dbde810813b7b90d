"""Semi-analytical contact mechanics of (visco)elastic half-spaces.

Influence coefficients and DC-FFT convolutions for the half-space, the
Polonsky-Keer conjugate-gradient contact solver and a time stepper with Prony
recursions. See README.md for the two commands and a scripting example.
"""
from . import errors, fft, inclusions, indenters, loads, materials, reference, schedules
from ._version import __version__
from .grid import Grid
from .inclusions import solve_inclusions
from .io import load_result
from .result import Result, StepRecord
from .simulation import Options, Simulation
from .solver import ContactSolution, SolverOptions, solve_normal
from .sweep import ScenarioBuilder, read_sweep, sweep

__all__ = ["load_result", "solve_inclusions", "sweep", "ScenarioBuilder", "read_sweep", "Grid", "Options", "Result", "Simulation", "SolverOptions", "ContactSolution", "StepRecord",
           "solve_normal", "errors", "fft", "inclusions", "indenters", "loads", "materials", "reference", "schedules",
           "__version__"]
