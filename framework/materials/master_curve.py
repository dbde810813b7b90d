"""Master curves: DMA frequency sweeps at several temperatures shifted onto one reference temperature.

A DMA instrument sweeps a few decades of frequency at each of several
temperatures. For a thermorheologically simple solid the sweep at ``T`` is the
reference curve seen at the reduced frequency ``w a_T``
(:mod:`framework.materials.temperature`), so the sweeps, shifted along
``log w`` by ``log10 a_T``, join into one master curve over many more decades
than any sweep covers.

Shift factors are found between neighbouring temperatures, by the storage
modulus: every point of each sweep whose ``log10 E'`` lies within the other's
range is placed on the other's monotone curve (its isotonic fit, interpolated
and inverted) at the same modulus, and the shift ``d`` of ``log10 w`` is the
mean horizontal distance. Matching at equal modulus keeps ``E'`` monotone
along the master curve where the sweeps' levels differ slightly (the glassy
sweeps of a real polymer do, by a few percent), which least squares at equal
frequency does not: it piled pyvisco's glassy sweeps into one frequency window
(a downward variation of ``log10 E'`` of 2.06 against 0.098 now). Where
``E'`` is flat in a sweep (it rises by less than :data:`FLAT` times its
scatter across the sweep) its place is set by noise, and the loss modulus
places the pair instead (least squares of ``log10 E''`` differences over the
overlap, each sweep a cubic spline in ``log10 w``). The neighbours' shifts are
chained, made non-increasing in temperature (a warmer solid relaxes faster)
and set to ``a_T = 1`` at the reference. Optionally a vertical (``T rho``)
factor first. :attr:`MasterCurve.glass_transition` locates the loss peak;
:meth:`MasterCurve.fit_wlf`, :meth:`MasterCurve.fit_arrhenius` and
:meth:`MasterCurve.fit_shift` give the laws through the factors, and
:meth:`MasterCurve.fit_prony` the Prony series of the master curve (at the
reference temperature). Compared with pyvisco (Springer 2022), which fits a
power law to each sweep's ``E'`` and places neighbours at three common moduli,
on its own example data: ``bench/dma.py``.
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import isotonic_regression, minimize_scalar

from .._validation import check_bool
from ..errors import FrameworkError, ParameterError
from .fitting import check_dynamic, fit_prony
from .temperature import WLF, Arrhenius, Shift, WLFArrhenius, check_temperature

__all__ = ["MasterCurve", "master_curve"]

#: Loss-modulus shifts are scanned on a grid of this fraction of the sweeps' mean point spacing (in log10 w), then
#: refined.
SCAN_STEP = 0.1
#: A sweep's storage modulus is flat when it rises by less than this many times its scatter across the sweep: its
#: horizontal place is then set by noise, and the loss modulus places it instead.
FLAT = 5.0
#: Smallest scatter [decades] assumed for a sweep: 1e-3 decades (0.23 %), about how well a DMA's moduli repeat from
#: one sweep to the next however smooth each sweep is (instruments state +-1 % accuracy). With FLAT, a storage
#: modulus rising by less than 1.2 % across a sweep is flat.
FLOOR = 1e-3
#: Samples per interval of a sweep's storage-modulus spline when it is inverted (error ~1e-6 decades).
DENSE = 64
#: A WLF law through every shift factor is kept for the whole range when it follows them within this rms [decades]
#: (a factor 1.26 in time: measured shift factors scatter that much); beyond, the glass shifts otherwise.
WLF_SCATTER = 0.1
#: Points through which a sweep's storage modulus is extended, as a power law, beyond its ends.
END_POINTS = 3


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
    vertical_factors : numpy.ndarray
        The factor each temperature's moduli were multiplied by (``T_ref / T``
        with ``vertical=True``, else ones).
    """

    reference: float
    temperatures: np.ndarray
    shift_factors: np.ndarray
    frequencies: np.ndarray
    complex_modulus: np.ndarray
    point_temperatures: np.ndarray
    vertical_factors: np.ndarray = None

    @property
    def glass_transition(self):
        """The glass transition [K] the sweeps show: the peak of the loss modulus at 1 Hz, or None.

        ASTM E1640's loss-modulus definition: each sweep's ``log E''`` at 1 Hz
        (``2 pi`` rad/s; at the geometric mean of the measured frequencies when
        a sweep does not reach 1 Hz), interpolated linearly in ``log w``, and the
        vertex of the parabola through the highest value and its two
        neighbours in temperature. None when the highest value is at the
        coldest or the warmest sweep: the transition lies outside the data.
        """
        measured = self.frequencies / self.shift_factors[np.searchsorted(self.temperatures, self.point_temperatures)]
        lows = [measured[self.point_temperatures == t].min() for t in self.temperatures]
        highs = [measured[self.point_temperatures == t].max() for t in self.temperatures]
        at = 2 * math.pi if max(lows) <= 2 * math.pi <= min(highs) else math.exp(np.mean(np.log(measured)))
        loss = []
        for temperature in self.temperatures:
            mine = self.point_temperatures == temperature
            x, y = np.log(measured[mine]), np.log(self.complex_modulus.imag[mine])
            order = np.argsort(x)
            loss.append(np.interp(math.log(at), x[order], y[order]))
        peak = int(np.argmax(loss))
        if peak in (0, len(loss) - 1):
            return None
        t, y = self.temperatures[peak - 1:peak + 2], np.array(loss[peak - 1:peak + 2])
        a, b, _ = np.polyfit(t - t[1], y, 2)
        return float(t[1] - b / (2 * a)) if a < 0 else float(t[1])

    def fit_wlf(self):
        """The :class:`~framework.materials.WLF` law through the shift factors (:meth:`WLF.fit`).

        WLF holds from the glass transition up (Ferry 1980, ch. 11). When the
        sweeps show one inside their range (:attr:`glass_transition`), the law
        is fitted to the factors at and above it and its reference is the
        sweep nearest ``T_g`` above it: its constants are those usually quoted
        (about 17 and 50-100 K for amorphous polymers). Otherwise it goes
        through every factor and its reference is :attr:`reference`. To take
        the fitted material to any temperature of the data, use
        :meth:`fit_shift`, whose reference is always :attr:`reference`.
        """
        tg = self.glass_transition
        if tg is None:
            return WLF.fit(self.temperatures, self.shift_factors, self.reference)
        above = self.temperatures >= tg
        base = self.temperatures[above][0]
        factors = self.shift_factors[above] / self.shift_factors[self.temperatures == base][0]
        return WLF.fit(self.temperatures[above], factors, base)

    def fit_arrhenius(self):
        """The :class:`~framework.materials.Arrhenius` law through the shift factors (:meth:`Arrhenius.fit`)."""
        return Arrhenius.fit(self.temperatures, self.shift_factors, self.reference)

    def fit_shift(self):
        """The shift law for the whole range of the data, ``a_T = 1`` at :attr:`reference`.

        WLF through every factor (:meth:`WLF.fit`) when it follows them within
        :data:`WLF_SCATTER` decades rms, or when the sweeps show no glass
        transition with three temperatures at or above it; otherwise the data
        say the glass shifts otherwise, and the law is
        :class:`~framework.materials.WLFArrhenius` (WLF above, Arrhenius below)
        joined at :attr:`glass_transition`.
        ``fit_prony(...).material.at(T, curve.fit_shift())`` is the solid at ``T``.
        """
        logs = np.log10(self.shift_factors)
        try:
            wlf = WLF.fit(self.temperatures, self.shift_factors, self.reference)
            scatter = math.sqrt(float(np.mean((wlf.log10_factor(self.temperatures) - logs) ** 2)))
        except ParameterError:
            wlf, scatter = None, math.inf
        tg = self.glass_transition
        if scatter <= WLF_SCATTER or tg is None or np.sum(self.temperatures >= tg) < 3:
            if wlf is None:
                return WLF.fit(self.temperatures, self.shift_factors, self.reference)   # raises, naming why
            return wlf
        return WLFArrhenius.fit(self.temperatures, self.shift_factors, self.reference, tg)

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
        temperature = check_temperature(temperature, name=f"{name}: the key")
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


def _scatter(x, y):
    """rms scatter [decades] of ``y = log10 modulus`` about a quadratic in ``x = log10 w`` (at least :data:`FLOOR`)."""
    degree = min(2, x.size - 1)
    residual = y - np.polyval(np.polyfit(x, y, degree), x)
    return max(math.sqrt(float(residual @ residual) / max(1, x.size - degree - 1)), FLOOR)


def _monotone(x, y):
    """``(log10 w at a given log10 E', the rising fit of log10 E')``: one sweep's storage modulus as a curve.

    The isotonic (least-squares non-decreasing, :func:`scipy.optimize.isotonic_regression`) fit of ``y``,
    interpolated by a cubic spline sampled :data:`DENSE` times per interval and made non-decreasing (running
    maximum), then inverted; beyond its ends, the straight line through the last :data:`END_POINTS` points (a power
    law), so that sweeps whose moduli do not overlap are placed across the gap.
    """
    rising = isotonic_regression(y).x
    dense = np.linspace(x[0], x[-1], DENSE * (x.size - 1) + 1)
    values = np.maximum.accumulate(CubicSpline(x, rising)(dense))
    values = values + np.arange(values.size) * 1e-12 * max(1e-9, float(np.ptp(values)))   # ties: strictly rising
    ends = min(END_POINTS, x.size)
    low = max(np.polyfit(x[:ends], rising[:ends], 1)[0], 1e-9)
    high = max(np.polyfit(x[-ends:], rising[-ends:], 1)[0], 1e-9)

    def frequency(level):
        level = np.asarray(level, dtype=float)
        inside = np.interp(level, values, dense)
        return np.where(level < values[0], x[0] + (level - values[0]) / low,
                        np.where(level > values[-1], x[-1] + (level - values[-1]) / high, inside))
    return frequency, values[[0, -1]]


def _storage_shift(first, second):
    """``d`` laying the storage moduli of two sweeps on each other: horizontal distances at equal modulus.

    Every point of each sweep whose ``log10 E'`` lies in the other's range is placed on the other's rising curve
    (:func:`_monotone`) at the same modulus; ``d`` is the mean of the frequency differences. Where the two ranges do
    not overlap, the curves are compared across the gap (five levels, extended as power laws) if it is narrower than
    either sweep's own rise; a wider gap is refused (it returned a shift of ~0 before).
    """
    (_, x_a, y_a, *_), (_, x_b, y_b, *_) = first, second
    (at_a, rising_a), (at_b, rising_b) = _monotone(x_a, y_a[:, 0]), _monotone(x_b, y_b[:, 0])
    low, high = max(rising_a[0], rising_b[0]), min(rising_a[-1], rising_b[-1])
    if low > high:
        rise = min(rising_a[-1] - rising_a[0], rising_b[-1] - rising_b[0])
        if low - high > rise:
            raise ParameterError(
                f"sweeps: the sweeps at {first[0]:g} K and {second[0]:g} K do not overlap: their storage moduli "
                f"(10^{rising_a[0]:.4g} .. 10^{rising_a[-1]:.4g} and 10^{rising_b[0]:.4g} .. 10^{rising_b[-1]:.4g} Pa) "
                f"lie {low - high:.3g} decades apart, more than either sweep spans ({rise:.3g}); expected "
                f"temperatures close enough for neighbouring sweeps to share moduli, or give the shift")
        levels = np.linspace(high, low, 5)
        return float(np.mean(at_a(levels) - at_b(levels)))
    in_a = (y_b[:, 0] >= low) & (y_b[:, 0] <= high)
    in_b = (y_a[:, 0] >= low) & (y_a[:, 0] <= high)
    return float(np.mean(np.concatenate([at_a(y_b[in_a, 0]) - x_b[in_a], x_a[in_b] - at_b(y_a[in_b, 0])])))


def _loss_shift(first, second):
    """``d`` laying the loss moduli on each other: least squares of ``log10 E''`` differences over the overlap.

    Each sweep interpolated by a cubic spline in ``log10 w``, both ways (the points of each onto the other); the
    shift scanned on a grid of :data:`SCAN_STEP` of the mean point spacing, then refined.
    """
    (t_a, x_a, y_a, *_), (t_b, x_b, y_b, *_) = first, second
    spline_a, spline_b = CubicSpline(x_a, y_a[:, 1]), CubicSpline(x_b, y_b[:, 1])
    smallest = max(4, math.ceil(0.5 * min(x_a.size, x_b.size)))   # points in the overlap, both ways together

    def mismatch(d):
        into_a = (x_b + d >= x_a[0]) & (x_b + d <= x_a[-1])
        into_b = (x_a - d >= x_b[0]) & (x_a - d <= x_b[-1])
        count = int(into_a.sum() + into_b.sum())
        if count < smallest:
            return np.inf
        squares = np.sum((y_b[into_a, 1] - spline_a(x_b[into_a] + d))**2) \
            + np.sum((y_a[into_b, 1] - spline_b(x_a[into_b] - d))**2)
        return squares / count

    step = SCAN_STEP * min(np.mean(np.diff(x_a)), np.mean(np.diff(x_b)))
    candidates = np.arange(x_a[0] - x_b[-1], x_a[-1] - x_b[0] + step, step)
    values = np.array([mismatch(d) for d in candidates])
    if not np.any(np.isfinite(values)):
        raise ParameterError(f"sweeps: the sweeps at {t_a:g} K and {t_b:g} K have flat storage moduli and share "
                             f"too few frequencies for their loss moduli to be shifted onto each other (each has "
                             f"{x_a.size} and {x_b.size} points); expected sweeps of several points each, or give "
                             f"the shift")
    best = candidates[int(np.argmin(values))]
    refined = minimize_scalar(mismatch, bounds=(best - step, best + step), method="bounded",
                              options={"xatol": 1e-10})
    return float(refined.x) if refined.fun <= values.min() else float(best)


def _pair_shift(first, second):
    """``log10 a(second) - log10 a(first)``: the ``d`` with ``second(x) = first(x + d)`` in ``x = log10 w``.

    The storage modulus places the pair unless it is flat in either sweep (it rises by less than :data:`FLAT`
    times its scatter across the sweep); then the loss modulus does.
    """
    flat = any(np.ptp(isotonic_regression(y[:, 0]).x) < FLAT * _scatter(x, y[:, 0])
               for _, x, y, *_ in (first, second))
    return _loss_shift(first, second) if flat else _storage_shift(first, second)


def master_curve(sweeps, reference, shift=None, vertical=False):
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
    vertical : bool
        Ferry's vertical shift first (the entropy-elasticity correction of
        rubbery moduli, Ferry 1980, ch. 11): every modulus at ``T`` multiplied
        by ``T_ref / T`` (constant density), before the horizontal shift. The
        fitted solid is then the one at ``reference``; ``Viscoelastic.at``
        does not scale moduli back.

    Returns
    -------
    MasterCurve
    """
    data = _sweeps(sweeps)
    temperatures = np.array([sweep[0] for sweep in data])
    reference = check_temperature(reference, name="reference")
    vertical = check_bool(vertical, name="vertical")
    scale = reference / temperatures if vertical else np.ones(temperatures.size)
    data = [(t, x, y + math.log10(b), w, modulus * b) for (t, x, y, w, modulus), b in zip(data, scale)]
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
        # a solid relaxes faster when warmer: a neighbour shifted the other way is noise, and the factors are the
        # nearest non-increasing sequence (least squares, pool-adjacent-violators)
        logs = isotonic_regression(logs, increasing=False).x
        logs -= logs[int(np.argmax(temperatures == reference))]
    factors = 10.0 ** logs
    frequencies = np.concatenate([sweep[3] * factor for sweep, factor in zip(data, factors)])
    modulus = np.concatenate([sweep[4] for sweep in data])
    measured_at = np.concatenate([np.full(sweep[3].size, sweep[0]) for sweep in data])
    order = np.argsort(frequencies, kind="stable")
    return MasterCurve(reference=reference, temperatures=temperatures, shift_factors=factors,
                       frequencies=frequencies[order], complex_modulus=modulus[order],
                       point_temperatures=measured_at[order], vertical_factors=scale)
