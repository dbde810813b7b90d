"""Master curves: DMA frequency sweeps at several temperatures shifted onto one reference temperature.

A DMA instrument sweeps a few decades of frequency at each of several
temperatures. For a thermorheologically simple solid the sweep at ``T`` is the
reference curve seen at the reduced frequency ``w a_T``
(:mod:`framework.materials.temperature`), so the sweeps, shifted along
``log w`` by ``log10 a_T``, join into one master curve over many more decades
than any sweep covers.

Shift factors are found between neighbouring temperatures: the shift ``d`` of
``log10 w`` that best lays one sweep on the other, by least squares of the
differences of ``log10 E'`` and ``log10 E''`` (both, so that a flat storage
plateau is still placed by its loss modulus) over the frequencies where they
overlap, each sweep interpolated by a cubic spline in ``log10 w``, both ways
(the points of each onto the other). The neighbours' shifts are chained and
set to ``a_T = 1`` at the reference temperature. Only horizontal shifts are
made (no vertical ``T rho`` factor). :meth:`MasterCurve.fit_wlf` and
:meth:`MasterCurve.fit_arrhenius` then give the laws through the factors, and
:meth:`MasterCurve.fit_prony` the Prony series of the master curve (at the
reference temperature).
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import minimize_scalar

from ..errors import FrameworkError, ParameterError
from .fitting import check_dynamic, fit_prony
from .temperature import WLF, Arrhenius, Shift, check_temperatures

__all__ = ["MasterCurve", "master_curve"]

#: Shifts are scanned on a grid of this fraction of the sweeps' mean point spacing (in log10 w), then refined.
SCAN_STEP = 0.1


@dataclass(frozen=True)
class MasterCurve:
    """DMA sweeps shifted onto a reference temperature (:func:`master_curve`).

    Attributes
    ----------
    reference : float
        Reference temperature [K] (``a_T = 1``).
    temperatures : numpy.ndarray
        The sweeps' temperatures [K], ascending.
    shift_factors : numpy.ndarray
        ``a_T`` of each temperature (fitted, or from the given shift).
    frequencies : numpy.ndarray
        Reduced angular frequencies ``w a_T`` [rad/s] of every point, ascending.
    complex_modulus : numpy.ndarray
        ``E' + i E''`` [Pa] of every point, in the same order.
    point_temperatures : numpy.ndarray
        The temperature [K] each point was measured at.
    """

    reference: float
    temperatures: np.ndarray
    shift_factors: np.ndarray
    frequencies: np.ndarray
    complex_modulus: np.ndarray
    point_temperatures: np.ndarray

    def fit_wlf(self):
        """The :class:`~framework.materials.WLF` law through the shift factors (:meth:`WLF.fit`)."""
        return WLF.fit(self.temperatures, self.shift_factors, self.reference)

    def fit_arrhenius(self):
        """The :class:`~framework.materials.Arrhenius` law through the shift factors (:meth:`Arrhenius.fit`)."""
        return Arrhenius.fit(self.temperatures, self.shift_factors, self.reference)

    def fit_prony(self, n_terms=None, times=None, *, poisson):
        """Prony series of the master curve at the reference temperature: ``fit_prony(..., kind="dynamic")``."""
        return fit_prony(self.frequencies, self.complex_modulus, kind="dynamic", n_terms=n_terms, times=times,
                         poisson=poisson)


def _sweeps(sweeps):
    """``[(T, log10 w, log10 [E', E''] (n, 2), w, E*), ...]`` ascending in T, each sweep sorted by frequency."""
    if not isinstance(sweeps, dict) or not sweeps:
        raise ParameterError(f"sweeps must be a non-empty dict {{temperature [K]: (frequencies [rad/s], "
                             f"complex modulus [Pa])}}, got {type(sweeps).__name__}")
    out = []
    for temperature, sweep in sweeps.items():
        name = f"sweeps[{temperature!r}]"
        temperature = float(check_temperatures(temperature, name=f"{name}: the key"))
        try:
            frequencies, modulus = sweep
            w, storage, loss = check_dynamic(frequencies, modulus)
        except (TypeError, ValueError) as exc:
            if not isinstance(exc, FrameworkError):
                exc = ParameterError(f"expected a pair (frequencies [rad/s], complex modulus [Pa]), got {sweep!r}")
            raise type(exc)(f"{name}: {exc}") from exc
        order = np.argsort(w)
        w, storage, loss = w[order], storage[order], loss[order]
        if np.any(np.diff(w) == 0):
            i = int(np.argmax(np.diff(w) == 0))
            raise ParameterError(f"{name}: the frequencies must be distinct within a sweep, got {w[i]!r} rad/s twice; "
                                 f"average repeated measurements first")
        if w.size < 2:
            raise ParameterError(f"{name}: a sweep needs at least two frequencies to be shifted, got {w.size}")
        out.append((temperature, np.log10(w), np.log10(np.column_stack([storage, loss])), w, storage + 1j * loss))
    out.sort(key=lambda sweep: sweep[0])
    for (t1, *_), (t2, *_) in zip(out, out[1:]):
        if t1 == t2:
            raise ParameterError(f"sweeps: two sweeps at {t1!r} K; expected one per temperature")
    return out


def _pair_shift(first, second):
    """``log10 a(second) - log10 a(first)``: the ``d`` with ``second(x) = first(x + d)`` in ``x = log10 w``."""
    (t_a, x_a, y_a, *_), (t_b, x_b, y_b, *_) = first, second
    spline_a, spline_b = CubicSpline(x_a, y_a, axis=0), CubicSpline(x_b, y_b, axis=0)
    smallest = max(4, math.ceil(0.5 * min(x_a.size, x_b.size)))   # points in the overlap, both ways together

    def mismatch(d):
        into_a = (x_b + d >= x_a[0]) & (x_b + d <= x_a[-1])
        into_b = (x_a - d >= x_b[0]) & (x_a - d <= x_b[-1])
        count = int(into_a.sum() + into_b.sum())
        if count < smallest:
            return np.inf
        squares = np.sum((y_b[into_a] - spline_a(x_b[into_a] + d))**2) \
            + np.sum((y_a[into_b] - spline_b(x_a[into_b] - d))**2)
        return squares / count

    step = SCAN_STEP * min(np.mean(np.diff(x_a)), np.mean(np.diff(x_b)))
    candidates = np.arange(x_a[0] - x_b[-1], x_a[-1] - x_b[0] + step, step)
    values = np.array([mismatch(d) for d in candidates])
    if not np.any(np.isfinite(values)):
        raise ParameterError(f"sweeps: the sweeps at {t_a:g} K and {t_b:g} K share too few frequencies to be "
                             f"shifted onto each other (each has {x_a.size} and {x_b.size} points); expected sweeps "
                             f"of several points each, or give the shift")
    best = candidates[int(np.argmin(values))]
    refined = minimize_scalar(mismatch, bounds=(best - step, best + step), method="bounded",
                              options={"xatol": 1e-10})
    return float(refined.x) if refined.fun <= values.min() else float(best)


def master_curve(sweeps, reference, shift=None):
    """Shift DMA sweeps at several temperatures onto ``reference`` (module docstring).

    Parameters
    ----------
    sweeps : dict
        ``{temperature [K]: (frequencies [rad/s], complex modulus E' + 1j E'' [Pa])}``,
        one frequency sweep per temperature (data checked as for
        ``fit_prony(kind="dynamic")``); neighbouring temperatures must overlap
        once shifted.
    reference : float
        Reference temperature [K]: one of the sweeps' temperatures when the
        shift factors are fitted, any temperature with ``shift``.
    shift : materials.WLF or materials.Arrhenius, optional
        Known shift law: its factors (relative to ``reference``) are used
        instead of fitted ones.

    Returns
    -------
    MasterCurve
    """
    data = _sweeps(sweeps)
    temperatures = np.array([sweep[0] for sweep in data])
    reference = float(check_temperatures(reference, name="reference"))
    if shift is not None:
        if not isinstance(shift, Shift):
            raise ParameterError(f"shift must be materials.WLF(...) or materials.Arrhenius(...), got {shift!r}")
        logs = np.asarray(shift.log10_factor(temperatures)) - shift.log10_factor(reference)
    else:
        if reference not in temperatures:
            raise ParameterError(f"reference must be one of the sweeps' temperatures {temperatures.tolist()} K when "
                                 f"the shift factors are fitted, got {reference!r}; move the fitted law to another "
                                 f"temperature with Viscoelastic.at")
        logs = np.concatenate([[0.0], np.cumsum([_pair_shift(a, b) for a, b in zip(data, data[1:])])])
        logs -= logs[int(np.argmax(temperatures == reference))]
    factors = 10.0 ** logs
    frequencies = np.concatenate([sweep[3] * factor for sweep, factor in zip(data, factors)])
    modulus = np.concatenate([sweep[4] for sweep in data])
    measured_at = np.concatenate([np.full(sweep[3].size, sweep[0]) for sweep in data])
    order = np.argsort(frequencies, kind="stable")
    return MasterCurve(reference=reference, temperatures=temperatures, shift_factors=factors,
                       frequencies=frequencies[order], complex_modulus=modulus[order],
                       point_temperatures=measured_at[order])
