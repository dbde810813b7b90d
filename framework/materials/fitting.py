"""Prony series fitted to measured relaxation or creep data.

The characteristic times are fixed on a log-spaced grid spanning the data
(one or two per decade is the usual choice) and the coefficients found by
non-negative least squares (Lawson & Hanson 1974, :func:`scipy.optimize.nnls`),
which keeps every modulus or compliance >= 0 and so gives a physically
admissible (completely monotone) function; Park & Schapery (Int. J. Solids
Struct. 36, 1999) discuss this collocation approach and the choice of times.
The residual is weighted by ``1/value`` so that the fit is uniform in relative
error over data that span decades of time.
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

from .._validation import check_finite_array, check_poisson, check_positive_int, check_quantity
from ..errors import ParameterError, ShapeError
from .viscoelastic import Viscoelastic

__all__ = ["PronyFit", "fit_prony"]


@dataclass(frozen=True)
class PronyFit:
    """The outcome of :func:`fit_prony`.

    Attributes
    ----------
    material : Viscoelastic
        The fitted material (built with ``from_prony`` for relaxation data and
        ``from_creep`` for creep data).
    kind : str
        ``"relaxation"`` or ``"creep"``.
    constant : float
        ``e_inf`` [Pa] (relaxation) or ``j0`` [1/Pa] (creep).
    terms : tuple
        The retained terms ``((E_i [Pa], tau_i [s]), ...)`` or
        ``((J_k [1/Pa], lambda_k [s]), ...)``; times whose coefficient came out
        zero are dropped.
    times : numpy.ndarray
        Every time of the grid the fit was allowed to use [s].
    fitted : numpy.ndarray
        The fitted function at the data times [Pa or 1/Pa].
    rms_error : float
        Root-mean-square of ``fitted - values`` [Pa or 1/Pa].
    max_relative_error : float
        ``max |fitted - values| / values``.
    """

    material: Viscoelastic
    kind: str
    constant: float
    terms: tuple
    times: np.ndarray
    fitted: np.ndarray
    rms_error: float
    max_relative_error: float


def _check_data(t, values):
    t = check_finite_array(t, name="t", ndim=1)
    values = check_finite_array(values, name="values", ndim=1)
    if values.shape != t.shape:
        raise ShapeError(f"values has {values.size} samples but t has {t.size}; expected one value per time")
    if t.size and t[0] < 0:
        raise ParameterError(f"t must be >= 0 [s], got t[0] = {float(t[0])!r}")
    steps = np.diff(t)
    if np.any(steps <= 0):
        i = int(np.argmax(steps <= 0)) + 1
        raise ParameterError(
            f"t must be strictly increasing, got t[{i}] = {float(t[i])!r} after t[{i - 1}] = {float(t[i - 1])!r}; "
            f"sort the samples and merge repeated times")
    if np.any(values <= 0):
        i = int(np.argmax(values <= 0))
        raise ParameterError(
            f"values must be positive (moduli or compliances), got values[{i}] = {float(values[i])!r}")
    return t, values


def _time_grid(t, n_terms, times):
    if times is not None:
        times = check_finite_array(times, name="times", ndim=1)
        if times.size == 0:
            raise ParameterError("times must hold at least one time [s], got an empty array")
        for i, value in enumerate(times):
            check_quantity(float(value), name=f"times[{i}]", unit="s")
        if np.unique(times).size != times.size:
            raise ParameterError(f"times must be distinct, got {times.tolist()!r}")
        if n_terms is not None and check_positive_int(n_terms, name="n_terms") != times.size:
            raise ParameterError(f"n_terms must equal len(times) = {times.size} when times are given, "
                                 f"got {n_terms!r}; pass one of the two")
        return np.sort(times)
    positive = t[t > 0]
    if positive.size < 2:
        raise ParameterError(f"t must hold at least two positive times to place the Prony times, "
                             f"got {positive.size}")
    low, high = positive[0], positive[-1]
    if n_terms is None:
        n_terms = max(1, math.ceil(math.log10(high / low)))
    n_terms = check_positive_int(n_terms, name="n_terms")
    if n_terms == 1:
        return np.array([math.sqrt(low * high)])
    return np.geomspace(low, high, n_terms)


def fit_prony(t, values, kind="relaxation", n_terms=None, times=None, *, poisson):
    """Fit a Prony series to relaxation or creep data by non-negative least squares.

    Relaxation: ``E(t) = e_inf + sum_i E_i exp(-t/tau_i)``; creep:
    ``J(t) = j0 + sum_k J_k (1 - exp(-t/lambda_k))``, with the times fixed and
    the coefficients >= 0 minimising ``sum ((model - values)/values)^2``.

    Parameters
    ----------
    t : array_like
        Sample times [s], >= 0 and strictly increasing.
    values : array_like
        Measured relaxation modulus [Pa] or creep compliance [1/Pa], > 0.
    kind : {"relaxation", "creep"}
        What ``values`` holds.
    n_terms : int, optional
        Number of Prony times, log-spaced from the smallest positive to the
        largest sample time. Default: one per decade of the data.
    times : array_like, optional
        The Prony times [s] to use instead of the log-spaced grid.
    poisson : float
        Poisson ratio of the material (keyword, required), in (-1, 0.5].

    Returns
    -------
    PronyFit
        The material, its terms and the fit error.

    Raises
    ------
    ParameterError
        Bad data or settings, or a fit with zero ``e_inf`` (data of a fluid:
        see :class:`~framework.materials.Maxwell`) or zero ``j0`` (see
        :class:`~framework.materials.KelvinVoigt`).
    """
    if kind not in ("relaxation", "creep"):
        raise ParameterError(f"kind must be 'relaxation' or 'creep', got {kind!r}")
    check_poisson(poisson)
    t, values = _check_data(t, values)
    grid = _time_grid(t, n_terms, times)
    if t.size < grid.size + 1:
        raise ParameterError(f"{grid.size} Prony times and a constant need at least {grid.size + 1} samples, "
                             f"got {t.size}; lower n_terms or add data")
    scaled = t[:, None] / grid[None, :]
    modes = np.exp(-scaled) if kind == "relaxation" else -np.expm1(-scaled)
    columns = np.hstack([np.ones((t.size, 1)), modes])
    weighted = columns / values[:, None]
    norms = np.linalg.norm(weighted, axis=0)
    norms[norms == 0] = 1.0   # a creep column vanishes when every t = 0 < ...: keep it inert
    solution, _ = nnls(weighted / norms, np.ones(t.size), maxiter=50 * columns.shape[1])
    # a unit column carrying less than 1e-12 of the (unit) weighted data is round-off: drop it
    solution[solution <= 1e-12 * math.sqrt(t.size)] = 0.0
    coefficients = solution / norms
    fitted = columns @ coefficients
    constant = float(coefficients[0])
    terms = tuple((float(c), float(tau)) for c, tau in zip(coefficients[1:], grid) if c > 0)
    if constant <= 0:
        hint = ("the data look like a fluid: use materials.Maxwell, or extend the data to longer times"
                if kind == "relaxation" else
                "the data have no instantaneous compliance: use materials.KelvinVoigt, or add earlier samples")
        raise ParameterError(f"the fitted {'e_inf' if kind == 'relaxation' else 'j0'} is {constant!r}; {hint}")
    if kind == "relaxation":
        material = Viscoelastic.from_prony(e_inf=constant, terms=terms, poisson=poisson)
    else:
        material = Viscoelastic.from_creep(j0=constant, terms=terms, poisson=poisson)
    residual = fitted - values
    return PronyFit(material=material, kind=kind, constant=constant, terms=terms, times=grid, fitted=fitted,
                    rms_error=float(np.sqrt(np.mean(residual**2))),
                    max_relative_error=float(np.max(np.abs(residual) / values)))
