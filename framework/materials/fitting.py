"""Prony series fitted to measured relaxation, creep or dynamic (DMA) data.

Relaxation and creep: the characteristic times are fixed on a log-spaced grid
spanning the data (one or two per decade is the usual choice) and the
coefficients found by non-negative least squares (Lawson & Hanson 1974,
:func:`scipy.optimize.nnls`), which keeps every modulus or compliance >= 0 and
so gives a physically admissible (completely monotone) function; Park &
Schapery (Int. J. Solids Struct. 36, 1999) discuss this collocation approach
and the choice of times. The residual is weighted by ``1/value`` so that the
fit is uniform in relative error over data that span decades of time.

Dynamic (DMA) data ``E*(w) = E' + i E''``: the storage and loss moduli of
``e_inf + sum_i E_i (i w tau_i) / (1 + i w tau_i)`` are fitted together,
each relative to its own data (residuals ``(E'_fit - E')/E'`` and ``(E''_fit -
E'')/E''``, so that a small loss modulus weighs as much as the storage
modulus), and the relaxation times are fitted as well as the moduli, by
variable projection (Golub & Pereyra, SIAM J. Numer. Anal. 10, 1973; Kaufman's
Jacobian, BIT 15, 1975): for given times the moduli are the non-negative
least-squares solution, and a Levenberg-Marquardt iteration moves the
logarithms of the times, starting from times log-spaced over the ``1/w`` the
data cover, and from the peaks of a fine fixed-time fit. The times stay within
:data:`EDGE` decades of ``1/w_max .. 1/w_min`` (and inside
:data:`~framework._validation.RELAXATION_TIMES`): a time further out is a
guess the data cannot check. Without
``n_terms``, the count is the fewest terms within :data:`AUTO_RESIDUAL` of the
residual of one term per decade, found by bisection.
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

from .._validation import RELAXATION_TIMES, check_finite_array, check_poisson, check_positive_int, check_quantity
from ..errors import ParameterError, ShapeError
from .base import maxwell_arm
from .viscoelastic import Viscoelastic

#: Largest loss tangent E''/E' accepted in DMA data: beyond it the data are those of a liquid, or the columns
#: are swapped or in different units (solid polymers peak at tan delta ~ 0.1 to 3).
MAX_LOSS_TANGENT = 10.0
#: Automatic term count: the fewest terms whose rms (weighted) residual is within this factor of the best any Prony
#: series achieves, that of a fit with DENSE_TIMES fixed times per decade (the moduli free), and at most
#: MOST_PER_DECADE per decade of the data. The extra misfit is then at most sqrt(1.1^2 - 1) = 0.46 of the best
#: residual in quadrature, below the data's scatter: the terms left out were fitting noise. pyvisco's rule
#: (``opt.nprony``, Springer 2022) accepts 1.5 times its best residual (a misfit 1.1 times it) and starts from one
#: term per decade: too few where the spectrum is richer (a rubber's: 8 terms over 7.6 decades leave 3 % where 12
#: reach the 1 % noise). ``bench/dma.py`` compares the counts and errors on the shared DMA data.
AUTO_RESIDUAL = 1.1
DENSE_TIMES, MOST_PER_DECADE = 4, 2
#: How far (decades) beyond 1/w_max .. 1/w_min a fitted relaxation time may lie: a Maxwell arm half a decade
#: beyond still shows in the data (its loss modulus at the data's edge is 0.57 of its peak), one further out is a
#: guess they cannot check (it was 3 decades: the real master curve of the shared DMA data then put a time at
#: 1.5e15 s, outside the framework's range).
EDGE = 0.5
#: Variable projection stops when a step lowers the cost by less than this fraction and moves the log-times by less
#: than this, or after this many residual evaluations per fitted parameter. A measured curve's cost settles at its
#: scatter and its last digits take hundreds of evaluations: the search for the term count compares costs to
#: SEARCH_TOLERANCE (0.01 %), and the count found is then polished to FIT_TOLERANCE. A given count (exact data in
#: the tests) is fitted to 1e-15.
SEARCH_TOLERANCE, FIT_TOLERANCE, FIT_EVALUATIONS = 1e-4, 1e-9, 30
#: Smallest relative scatter assumed for a modulus when the two are weighted (0.1 %): exact or very smooth data
#: weigh the storage and loss moduli alike.
SCATTER_FLOOR = 1e-3
#: A storage modulus that falls with frequency by more than the range noise reaches, ``2 sqrt(2 ln n)`` times the
#: data's scatter over ``n`` points (:func:`_fall_scatter`; 6.5 at 200 points), plus FALL_MARGIN scatters, is named
#: as the cause when a dynamic fit finds no relaxed modulus (:func:`_check_rising`), rather than a fluid: E' of a
#: passive solid never falls as the frequency rises. (Data that fit are not refused: a master curve built with a
#: given shift law that does not superpose the sweeps falls by 46 %, and is fitted as asked.) The largest fall of noise
#: alone, over 100 draws of 1 % to 10 % noise on 20 to 1000 points, is 7.4 scatters (against 7.9 to 10.4 allowed);
#: the shared measured master curve (examples/data/dma/pyvisco_freq_raw.csv, 210 points interleaving 21 sweeps)
#: falls by 6.0 % (0.062 in ln E') where its scatter is 1.25 %: 4.9 scatters, against 9.5 allowed.
FALL_MARGIN = 3.0

__all__ = ["PronyFit", "fit_prony"]


@dataclass(frozen=True)
class PronyFit:
    """The outcome of :func:`fit_prony`.

    Attributes
    ----------
    material : Viscoelastic
        The fitted material (built with ``from_prony`` for relaxation and
        dynamic data and ``from_creep`` for creep data).
    kind : str
        ``"relaxation"``, ``"creep"`` or ``"dynamic"``.
    constant : float
        ``e_inf`` [Pa] (relaxation, dynamic) or ``j0`` [1/Pa] (creep).
    terms : tuple
        The retained terms ``((E_i [Pa], tau_i [s]), ...)`` or
        ``((J_k [1/Pa], lambda_k [s]), ...)``; times whose coefficient came out
        zero are dropped.
    times : numpy.ndarray
        Every time of the grid the fit was allowed to use [s] (dynamic: the
        fitted relaxation times, those of zero modulus included).
    fitted : numpy.ndarray
        The fitted function at the data times [Pa or 1/Pa] (dynamic: ``E*`` at
        the data frequencies, complex [Pa]).
    rms_error : float
        Root-mean-square of ``|fitted - values|`` [Pa or 1/Pa].
    max_relative_error : float
        ``max |fitted - values| / values`` (dynamic: the largest of
        ``|E'_fit - E'| / E'`` and ``|E''_fit - E''| / E''``).
    rms_relative_error : float
        Root-mean-square of the relative residuals the fit minimised (dynamic:
        over both moduli): about the data's relative noise for a good fit.
    """

    material: Viscoelastic
    kind: str
    constant: float
    terms: tuple
    times: np.ndarray
    fitted: np.ndarray
    rms_error: float
    max_relative_error: float
    rms_relative_error: float


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


def fit_prony(t=None, values=None, kind="relaxation", n_terms=None, times=None, *, poisson, frequencies=None,
              complex_modulus=None):
    """Fit a Prony series to relaxation, creep or dynamic (DMA) data.

    Relaxation: ``E(t) = e_inf + sum_i E_i exp(-t/tau_i)``; creep:
    ``J(t) = j0 + sum_k J_k (1 - exp(-t/lambda_k))``, with the times fixed and
    the coefficients >= 0 minimising ``sum ((model - values)/values)^2``.
    Dynamic: ``fit_prony(frequencies, complex_modulus, kind="dynamic", ...)``
    fits ``E*(w) = e_inf + sum_i E_i (i w tau_i) / (1 + i w tau_i)`` to the
    storage and loss moduli together, times and moduli both, the times within
    half a decade of ``1/w_max .. 1/w_min`` (module docstring).

    Parameters
    ----------
    t : array_like
        Sample times [s], >= 0 and strictly increasing; for ``kind="dynamic"``
        the angular frequencies ``w`` [rad/s], > 0, in any order (the points of
        several temperatures of a master curve may interleave).
    values : array_like
        Measured relaxation modulus [Pa] or creep compliance [1/Pa], > 0; for
        ``kind="dynamic"`` the complex modulus ``E' + 1j * E''`` [Pa] with both
        parts > 0 and ``E''/E' <= 10``.
    kind : {"relaxation", "creep", "dynamic"}
        What ``values`` holds.
    n_terms : int, optional
        Number of Prony times, log-spaced from the smallest positive to the
        largest sample time (dynamic: over ``1/w_max .. 1/w_min``, the starting
        times). Default: one per decade of the data (dynamic: the fewest terms
        within :data:`AUTO_RESIDUAL` of that fit's residual).
    times : array_like, optional
        The Prony times [s] to use instead of the log-spaced grid (dynamic: the
        starting times, fitted further).
    poisson : float
        Poisson ratio of the material (keyword, required), in (-1, 0.5].
    frequencies, complex_modulus : array_like, optional
        The DMA data by their own names (keywords, instead of ``t`` and
        ``values``; ``kind`` must then be ``"dynamic"``).

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
    ShapeError
        ``values`` and ``t`` of different lengths.
    """
    if kind not in ("relaxation", "creep", "dynamic"):
        raise ParameterError(f"kind must be 'relaxation', 'creep' or 'dynamic', got {kind!r}")
    if frequencies is not None or complex_modulus is not None:
        if kind != "dynamic" or t is not None or values is not None:
            raise ParameterError(f"frequencies and complex_modulus are the data of kind='dynamic' and replace t and "
                                 f"values; got kind={kind!r} with t and values "
                                 f"{'given' if t is not None or values is not None else 'absent'}")
        t, values = frequencies, complex_modulus
    if t is None or values is None:
        raise ParameterError("fit_prony needs the data: t and values (or, for kind='dynamic', frequencies and "
                             "complex_modulus)")
    check_poisson(poisson)
    if kind == "dynamic":
        return _fit_dynamic(t, values, n_terms, times, poisson)
    t, values = _check_data(t, values)
    _check_monotone(t, values, kind)
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
                    max_relative_error=float(np.max(np.abs(residual) / values)),
                    rms_relative_error=float(np.sqrt(np.mean((residual / values)**2))))


# --------------------------------------------------------------------------- dynamic (DMA) data

def check_dynamic(frequencies, complex_modulus):
    """DMA data as ``(w [rad/s], E' [Pa], E'' [Pa])`` float arrays, or a ParameterError naming the bad sample.

    ``frequencies``: one-dimensional, finite, > 0; ``complex_modulus``: complex
    ``E' + i E''`` of the same length, both parts > 0, ``E''/E' <= 10``
    (:data:`MAX_LOSS_TANGENT`).
    """
    w = check_finite_array(frequencies, name="frequencies", ndim=1)
    modulus = np.asarray(complex_modulus)
    if not np.iscomplexobj(modulus):
        raise ParameterError(f"complex_modulus must be complex, E' + 1j * E'' [Pa] (storage plus i times loss "
                             f"modulus), got a {modulus.dtype} array: real data carry no loss modulus")
    if modulus.ndim != 1:
        raise ShapeError(f"complex_modulus must have 1 dimension, got shape {modulus.shape}")
    if modulus.shape != w.shape:
        raise ShapeError(f"complex_modulus has {modulus.size} samples but frequencies has {w.size}; "
                         f"expected one complex modulus per frequency")
    if not np.all(np.isfinite(modulus)):
        i = int(np.argmax(~np.isfinite(modulus)))
        raise ParameterError(f"complex_modulus must be finite everywhere, got {modulus[i]!r} at index {i}")
    if np.any(w <= 0):
        i = int(np.argmax(w <= 0))
        raise ParameterError(f"frequencies must be positive angular frequencies [rad/s], got frequencies[{i}] = "
                             f"{float(w[i])!r}")
    storage, loss = modulus.real.astype(float), modulus.imag.astype(float)
    for part, values in (("storage modulus E' (real part)", storage), ("loss modulus E'' (imaginary part)", loss)):
        if np.any(values <= 0):
            i = int(np.argmax(values <= 0))
            raise ParameterError(f"complex_modulus[{i}]: the {part} must be positive [Pa], got {float(values[i])!r}")
    tangent = loss / storage
    if np.any(tangent > MAX_LOSS_TANGENT):
        i = int(np.argmax(tangent > MAX_LOSS_TANGENT))
        raise ParameterError(
            f"complex_modulus[{i}]: loss tangent E''/E' = {float(tangent[i]):.6g} exceeds {MAX_LOSS_TANGENT:g}, more "
            f"than a solid's DMA data show (E' = {float(storage[i])!r}, E'' = {float(loss[i])!r} Pa); expected E' + "
            f"1j * E'' with both in Pa: check that the columns are not swapped or in different units")
    return w, storage, loss


def _start_times(covered, n_terms, times):
    """Starting relaxation times [s]: ``times`` checked, or ``n_terms`` log-spaced over ``covered``."""
    if times is not None:
        return _time_grid(None, n_terms, times)
    low, high = covered
    if n_terms is None:
        n_terms = max(1, math.ceil(math.log10(high / low) - 1e-9))
    n_terms = check_positive_int(n_terms, name="n_terms")
    # the centres of n_terms equal decades-wide cells: no time starts at the data's very edge
    return np.exp(math.log(low) + (np.arange(n_terms) + 0.5) / n_terms * math.log(high / low))


def _scatter(values):
    """Relative scatter of positive data along their order: rms second difference of ``ln values`` over sqrt(6).

    For independent noise of relative size ``s`` on a curve that is smooth on
    the sampling, ``ln y[i-1] - 2 ln y[i] + ln y[i+1]`` has variance ``6 s^2``
    (the curve's own second differences add to it: an upper bound). At least
    :data:`SCATTER_FLOOR`, so that exact data weigh both moduli alike.
    """
    second = np.diff(np.log(values), 2)
    return max(math.sqrt(float(second @ second) / max(1, second.size) / 6.0), SCATTER_FLOOR)


def _fall_scatter(values):
    """Relative scatter of positive data along their order, robust to a few steps: for :func:`_check_rising`.

    As :func:`_scatter`, the rms second difference of ``ln values`` over sqrt(6), but of the second
    differences within 5 standard deviations (estimated from their median absolute value) of zero: a
    single step in the data (the fall to be found) would otherwise count as scatter, while the
    mismatch of interleaved sweeps in a master curve, spread over many points, still does.
    """
    second = np.diff(np.log(values), 2)
    if second.size == 0:
        return SCATTER_FLOOR
    deviation = max(1.4826 * float(np.median(np.abs(second))), math.sqrt(6.0) * SCATTER_FLOOR)
    kept = second[np.abs(second) <= 5.0 * deviation]
    return max(math.sqrt(float(kept @ kept) / max(1, kept.size) / 6.0), SCATTER_FLOOR)


def _check_monotone(t, values, kind):
    """Refuse a relaxation modulus that clearly rises with time, or a creep compliance that clearly falls.

    The same criterion as :func:`_check_rising` (a change beyond what the data's scatter explains over their
    length): a Prony relaxation modulus never rises and a creep compliance never falls, so the non-negative fit of
    such data is a constant, returned without a word before.
    """
    logs = np.log(values) if kind == "creep" else -np.log(values)   # should rise: the creep compliance
    fall = np.maximum.accumulate(logs) - logs
    j = int(np.argmax(fall))
    scatter = _fall_scatter(values)
    allowed = (2.0 * math.sqrt(2.0 * math.log(max(2, t.size))) + FALL_MARGIN) * scatter
    if fall[j] > allowed:
        i = int(np.argmax(logs[:j + 1]))
        what, way = (("creep compliance", "falls"), ("relaxation modulus", "rises"))[kind == "relaxation"]
        raise ParameterError(
            f"values: the {what} {way} with time, from {float(values[i]):.6g} at t = {float(t[i]):.6g} s (index {i}) "
            f"to {float(values[j]):.6g} at t = {float(t[j]):.6g} s (index {j}), by {100 * abs(values[j] / values[i] - 1):.3g} "
            f"%: more than its scatter ({100 * scatter:.2g} %) explains; a {what} never {way} (is the kind "
            f"{kind!r} right, are the columns in order?)")


def _check_repeated(w, storage, loss):
    """Refuse one frequency carrying two different moduli (a modulus is one function of the frequency)."""
    order = np.argsort(w, kind="stable")
    for i, j in zip(order[:-1], order[1:]):
        if w[i] == w[j] and not (math.isclose(storage[i], storage[j], rel_tol=1e-12)
                                 and math.isclose(loss[i], loss[j], rel_tol=1e-12)):
            i, j = sorted((int(i), int(j)))
            raise ParameterError(
                f"frequencies[{i}] and frequencies[{j}] are both {float(w[i])!r} rad/s but carry different moduli, "
                f"E' + i E'' = {float(storage[i]):.6g} + {float(loss[i]):.6g}j and {float(storage[j]):.6g} + "
                f"{float(loss[j]):.6g}j Pa; expected one complex modulus per frequency: average repeated "
                f"measurements first (or drop one)")


def _check_rising(w, storage):
    """Refuse a storage modulus that clearly falls as the frequency rises (:data:`FALL_MARGIN`).

    Neither a passive solid's E' nor a fluid's falls with frequency: data that do are misread (units,
    columns, a master curve's shift factors), and a fit to them fails in ways (a zero ``e_inf``) that
    would otherwise be blamed on the material.
    """
    order = np.argsort(w, kind="stable")
    log_storage = np.log(storage[order])
    fall = np.maximum.accumulate(log_storage) - log_storage
    j = int(np.argmax(fall))
    scatter = _fall_scatter(storage[order])
    allowed = (2.0 * math.sqrt(2.0 * math.log(max(2, w.size))) + FALL_MARGIN) * scatter
    if fall[j] > allowed:
        i = int(np.argmax(log_storage[:j + 1]))
        first, last = int(order[i]), int(order[j])
        raise ParameterError(
            f"the storage modulus E' falls with frequency, from {float(storage[first]):.6g} Pa at "
            f"{float(w[first]):.6g} rad/s (index {first}) to {float(storage[last]):.6g} Pa at {float(w[last]):.6g} "
            f"rad/s (index {last}), {100 * -math.expm1(-float(fall[j])):.3g} % lower: more than its scatter "
            f"({100 * scatter:.2g} %) explains (at most {100 * -math.expm1(-allowed):.2g} %); a passive solid's "
            f"storage modulus never falls as the frequency rises: check the frequency units, the order of the columns "
            f"and, for a master curve, its shift factors")


class _DynamicProblem:
    """Variable projection for ``E*(w) = e_inf + sum_i E_i (i w tau_i)/(1 + i w tau_i)`` in ``u_i = ln tau_i``.

    Rows: the storage moduli, then the loss moduli, each divided by its datum
    and by the modulus's scatter (:func:`_scatter`, inverse-variance weights:
    a measured loss modulus, ``E' tan delta``, scatters far more than the
    storage modulus, and would otherwise pull the storage fit off data it
    does not contradict); columns: ``e_inf``, then one Maxwell arm per time.
    For given times the moduli are the non-negative least-squares solution;
    the residual ``A(u) g(u) - b`` is what :func:`_levenberg_marquardt`
    minimises over ``u``, with Kaufman's Jacobian ``P dA/du g`` (``P`` the
    projection off the columns in use).
    """

    def __init__(self, w, storage, loss):
        self.w = w
        scatter = np.repeat([_scatter(storage), _scatter(loss)], w.size) / min(_scatter(storage), _scatter(loss))
        self.scale = 1.0 / (np.concatenate([storage, loss]) * scatter)
        self.target = 1.0 / scatter
        self._key, self._solved = None, None

    def solve(self, u):
        """``(A, dA/du, g, residual, g in unit columns)`` at the log-times ``u`` (the last call's answer kept)."""
        key = np.asarray(u, dtype=float).tobytes()
        if key != self._key:
            real, imaginary = maxwell_arm(self.w[:, None], np.exp(np.asarray(u))[None, :])
            ones, zeros = np.ones((self.w.size, 1)), np.zeros((self.w.size, 1))
            columns = np.vstack([np.hstack([ones, real]), np.hstack([zeros, imaginary])]) * self.scale[:, None]
            # d/du of s^2/(1+s^2) and s/(1+s^2), s = w exp(u), in terms of the two
            slopes = np.vstack([2.0 * real * (1.0 - real), imaginary * (1.0 - 2.0 * real)]) * self.scale[:, None]
            norms = np.linalg.norm(columns, axis=0)
            norms[norms == 0] = 1.0
            unit, _ = nnls(columns / norms, self.target, maxiter=50 * columns.shape[1])
            weights = unit / norms
            self._key = key
            self._solved = (columns, slopes, weights, columns @ weights - self.target, unit)
        return self._solved

    def residual(self, u):
        return self.solve(u)[3]

    def jacobian(self, u):
        # the projection through the normal equations of the (few) columns in use: no QR of the tall matrix
        columns, slopes, weights, _, _ = self.solve(u)
        used = columns[:, weights > 0]
        derivative = slopes * weights[1:][None, :]
        gram, right = used.T @ used, used.T @ derivative
        try:
            coefficients = np.linalg.solve(gram, right)
        except np.linalg.LinAlgError:
            coefficients = None
        if coefficients is None or not np.all(np.isfinite(coefficients)):   # two arms met: columns dependent
            coefficients = np.linalg.lstsq(gram, right, rcond=1e-13)[0]
        return derivative - used @ coefficients


def _levenberg_marquardt(problem, u, bounds, tolerance, evaluations):
    """Minimise ``|problem.residual(u)|^2 / 2`` over ``bounds[0] <= u <= bounds[1]``: ``(u, cost, evaluations)``.

    Levenberg-Marquardt (More, Lecture Notes in Math. 630, 1978: damping by
    ``lambda diag(J^T J)``, lowered after a step that lowers the cost, raised
    after one that does not), each step clipped into the bounds. Written on
    the normal equations of the few parameters (one per term): the SVD and QR
    of the tall Jacobian that :func:`scipy.optimize.least_squares` takes each
    iteration cost more than the fit itself, and far more where the BLAS
    starts threads for them. Stops when a step lowers the cost by less than
    ``tolerance`` of it and moves ``u`` by less than ``tolerance``, or after
    ``evaluations`` residuals.
    """
    u = np.clip(np.asarray(u, dtype=float), *bounds)
    residual = problem.residual(u)
    cost, damping, count = 0.5 * float(residual @ residual), 1e-3, 1
    while count < evaluations and damping < 1e12:
        jacobian = problem.jacobian(u)
        gradient, normal = jacobian.T @ residual, jacobian.T @ jacobian
        diagonal = np.maximum(np.diag(normal), 1e-12 * max(1.0, float(np.max(np.diag(normal)))))
        while count < evaluations and damping < 1e12:
            step = np.linalg.solve(normal + damping * np.diag(diagonal), -gradient)
            trial = np.clip(u + step, *bounds)
            trial_residual = problem.residual(trial)
            trial_cost = 0.5 * float(trial_residual @ trial_residual)
            count += 1
            if trial_cost < cost:
                break
            damping *= 4.0
        else:
            break
        converged = cost - trial_cost <= tolerance * cost and np.max(np.abs(trial - u)) <= tolerance * (
            1.0 + np.max(np.abs(u)))
        u, residual, cost, damping = trial, trial_residual, trial_cost, max(damping / 3.0, 1e-12)
        if converged or cost == 0.0:
            break
    problem.solve(u)
    return u, cost, count


def _spectrum_start(problem, covered, n_terms):
    """Log-times where a non-negative fit on a fine grid (4 per decade) puts its weight, as ``n_terms`` starts.

    A second start for the variable projection: the log-spaced start can leave
    two true times in one cell and a term stranded where its modulus vanishes
    (a local minimum); the fine fixed-time fit puts its moduli around every
    time the data show. Its peaks (runs of neighbouring grid times) are ranked
    by their weight in the relative residual (the solver's unit columns), the
    heaviest ``n_terms`` kept, each started at its weighted mean; with fewer
    peaks than terms the grid times are cut at their widest gaps instead. None
    when the fine fit uses fewer than ``n_terms`` times.
    """
    grid = np.log(np.geomspace(covered[0], covered[1], max(2, round(4 * math.log10(covered[1] / covered[0])) + 1)))
    weight = problem.solve(grid)[4][1:]
    used = np.flatnonzero(weight > 0)
    if used.size < n_terms:
        return None
    peaks = np.split(used, np.flatnonzero(np.diff(used) > 1) + 1)
    if len(peaks) >= n_terms:
        groups = sorted(peaks, key=lambda peak: -weight[peak].sum())[:n_terms]
    else:
        groups = np.split(used, np.sort(np.argsort(np.diff(grid[used]))[used.size - n_terms:]) + 1)
    return np.sort([np.average(grid[group], weights=weight[group]) for group in groups])


def _fit_times(problem, start, bounds, tolerance):
    """Variable projection from the log-times ``start``: ``(log-times, cost)``."""
    u, cost, _ = _levenberg_marquardt(problem, start, bounds, tolerance, FIT_EVALUATIONS * (start.size + 1))
    return u, cost


def _fit_count(problem, covered, bounds, count):
    """The dynamic fit with ``count`` terms: the better of the log-spaced and the spectrum start."""
    starts = (np.log(_start_times(covered, count, None)), _spectrum_start(problem, covered, count))
    return min((_fit_times(problem, u, bounds, SEARCH_TOLERANCE) for u in starts if u is not None),
               key=lambda solved: solved[1])


def _fewest_terms(problem, covered, bounds, most):
    """The fewest terms (bisection over 1..``most``) within :data:`AUTO_RESIDUAL` of the best residual.

    The best residual is that of the fine fixed-time fit (:data:`DENSE_TIMES` per decade, the moduli free): no
    Prony series fits the data much better, so its residual is their scatter.
    """
    grid = np.log(np.geomspace(covered[0], covered[1],
                               max(2, round(DENSE_TIMES * math.log10(covered[1] / covered[0])) + 1)))
    dense = problem.residual(grid)
    target = AUTO_RESIDUAL**2 * 0.5 * float(dense @ dense)
    fits = {}
    low, high = 0, most   # `high` terms meet the target (or are the most allowed), `low` (found so far) do not
    while high - low > 1:
        middle = (low + high) // 2
        fits[middle] = _fit_count(problem, covered, bounds, middle)
        if fits[middle][1] <= target:
            high = middle
        else:
            low = middle
    start = fits[high][0] if high in fits else _fit_count(problem, covered, bounds, high)[0]
    return _fit_times(problem, start, bounds, FIT_TOLERANCE)


def _fit_dynamic(frequencies, complex_modulus, n_terms, times, poisson):
    """:func:`fit_prony` for ``kind="dynamic"`` (see there and the module docstring)."""
    w, storage, loss = check_dynamic(frequencies, complex_modulus)
    _check_repeated(w, storage, loss)
    shortest, longest = RELAXATION_TIMES
    covered = (max(1.0 / float(w.max()), shortest), min(1.0 / float(w.min()), longest))
    if covered[0] >= covered[1]:
        raise ParameterError(f"frequencies must span a range inside {1 / longest:g} .. {1 / shortest:g} rad/s (the "
                             f"inverse of the relaxation times this framework accepts), got {float(w.min())!r} .. "
                             f"{float(w.max())!r} rad/s")
    most = max(1, math.ceil(MOST_PER_DECADE * math.log10(covered[1] / covered[0]) - 1e-9))
    start = _start_times(covered, n_terms if n_terms is not None or times is not None else 1, times)
    if w.size < start.size + 1:
        raise ParameterError(
            f"{start.size} Prony terms (a modulus and a time each) and e_inf need at least {start.size + 1} "
            f"frequencies (two moduli each), got {w.size}; lower n_terms or add data")
    u0 = np.log(start)
    edges = (max(math.log(covered[0]) - EDGE * math.log(10.0), math.log(shortest)),
             min(math.log(covered[1]) + EDGE * math.log(10.0), math.log(longest)))
    bounds = (min(edges[0], float(u0.min())), max(edges[1], float(u0.max())))
    problem = _DynamicProblem(w, storage, loss)
    if times is not None:
        solution = _fit_times(problem, u0, bounds, 1e-15)
    elif n_terms is not None:
        solution = min((_fit_times(problem, u, bounds, 1e-15)
                        for u in (u0, _spectrum_start(problem, covered, start.size)) if u is not None),
                       key=lambda solved: solved[1])
    else:
        solution = _fewest_terms(problem, covered, bounds, min(most, w.size - 1))
    _, _, weights, _, unit = problem.solve(solution[0])
    # a unit column carrying less than 1e-12 of the (unit) weighted data is round-off: drop it
    weights = np.where(unit > 1e-12 * math.sqrt(2 * w.size), weights, 0.0)
    fitted_times = [float(tau) for tau in np.exp(solution[0])]
    merged = {}
    for modulus, tau in zip(weights[1:], fitted_times):   # two times that met are one term
        key = next((other for other in merged if abs(other - tau) <= 1e-12 * tau), tau)
        merged[key] = merged.get(key, 0.0) + float(modulus)
    terms = tuple(sorted(((modulus, tau) for tau, modulus in merged.items() if modulus > 0), key=lambda p: p[1]))
    e_inf = float(weights[0])
    if e_inf <= 0:
        _check_rising(w, storage)   # data no material gives, before blaming a fluid
        raise ParameterError(f"the fitted e_inf is {e_inf!r}: the data show no relaxed (rubbery or glassy low-frequency) "
                             f"modulus, as a fluid's do: use materials.Maxwell, or extend the data to lower "
                             f"frequencies (a master curve)")
    material = Viscoelastic.from_prony(e_inf=e_inf, terms=terms, poisson=poisson)
    fitted = material.complex_modulus(w)
    relative = np.concatenate([(fitted.real - storage) / storage, (fitted.imag - loss) / loss])
    return PronyFit(material=material, kind="dynamic", constant=e_inf, terms=terms, times=np.sort(fitted_times),
                    fitted=fitted, rms_error=float(np.sqrt(np.mean(np.abs(fitted - (storage + 1j * loss))**2))),
                    max_relative_error=float(np.max(np.abs(relative))),
                    rms_relative_error=float(np.sqrt(np.mean(relative**2))))
