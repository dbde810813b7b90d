"""Time-temperature superposition: the shift functions of thermorheologically simple solids.

A thermorheologically simple solid has at the temperature ``T`` the response
it has at a reference temperature ``T_ref`` with every time multiplied by the
shift factor ``a_T`` (Ferry, *Viscoelastic Properties of Polymers*, 3rd ed.
1980, ch. 11; Tschoegl 1989, ch. 6)::

    E(t; T) = E(t / a_T; T_ref),        E*(w; T) = E*(w a_T; T_ref),

so that a Prony series keeps its moduli and takes the relaxation (and
retardation) times ``tau_i(T) = a_T tau_i(T_ref)``: ``a_T < 1`` above
``T_ref`` (the material relaxes faster), ``a_T > 1`` below it. Temperatures
are in kelvin.

The moduli are NOT shifted. The entropy-elasticity correction (Ferry's
vertical shift: moduli scaled by ``T rho / (T_ref rho_ref)``, a few percent over
tens of kelvin) is not applied anywhere; scale the moduli yourself when your
data call for it.

WLF (Williams, Landel & Ferry, J. Am. Chem. Soc. 77, 3701, 1955), from about
the glass transition up::

    log10 a_T = -c1 (T - T_ref) / (c2 + T - T_ref)

(decimal logarithm), singular at ``T - T_ref = -c2``: temperatures at or below
``T_ref - c2`` are refused. Arrhenius, below the glass transition or for a
secondary relaxation::

    ln a_T = (E_a / R) (1/T - 1/T_ref)

(natural logarithm), ``E_a`` [J/mol], ``R`` = :data:`GAS_CONSTANT` =
8.314462618 J/(mol K) (CODATA 2018, exact).
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from .._validation import LIMITS, check_finite_array, check_positive, check_quantity
from ..errors import ParameterError, ShapeError

__all__ = ["Arrhenius", "GAS_CONSTANT", "Shift", "WLF", "WLFArrhenius", "check_temperature", "check_temperatures"]

#: Molar gas constant R [J/(mol K)] (CODATA 2018: exact, from the Boltzmann and Avogadro constants).
GAS_CONSTANT = 8.314462618


#: [K] Coldest temperature accepted: -200 degC, below where DMA instruments' liquid-nitrogen cooling stops (77 K)
#: and far below any polymer's use. A colder value is almost surely degrees Celsius given for kelvin (23 for room
#: temperature): it is refused with the kelvin value it likely meant.
COLDEST = 73.15


def check_temperatures(temperature, *, name="temperature"):
    """``temperature`` [K] as a float array (any shape), finite, within ``LIMITS["K"]`` and above :data:`COLDEST`."""
    try:
        raw = np.asarray(temperature)
    except (TypeError, ValueError):   # ragged nested sequences
        raw = np.asarray(None)
    if raw.dtype.kind not in "iuf":   # booleans, strings, None, objects, complex
        raise ParameterError(f"{name} must be a temperature in kelvin, got {temperature!r}")
    values = raw.astype(float)
    low, high = LIMITS["K"]
    bad = ~np.isfinite(values) | (values < low) | (values > high)
    if np.any(bad):
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        where = f" at index {index}" if values.ndim else ""
        raise ParameterError(f"{name} must be a temperature in kelvin between {low:g} and {high:g} K, "
                             f"got {float(values[index])!r}{where}")
    cold = values < COLDEST
    if np.any(cold):
        index = tuple(int(i) for i in np.argwhere(cold)[0])
        where = f" at index {index}" if values.ndim else ""
        value = float(values[index])
        meant = f": it looks like degrees Celsius, {value:g} degC is {value + 273.15:g} K" if value + 273.15 > COLDEST \
            else ""
        raise ParameterError(f"{name} must be a temperature in kelvin above {COLDEST:g} K (-200 degC, colder than any "
                             f"DMA or contact of a polymer), got {value!r}{where}{meant}")
    return values


def check_temperature(temperature, *, name="temperature", hint=""):
    """One temperature [K] as a float, finite and within ``LIMITS["K"]``; ``hint`` ends the message of an array."""
    try:
        shape = np.shape(temperature)
    except (TypeError, ValueError):   # ragged nested sequences: check_temperatures names them
        shape = ()
    if shape != ():
        raise ParameterError(f"{name} must be one temperature in kelvin (a float), got an array of shape {shape}"
                             f"{hint}")
    return float(check_temperatures(temperature, name=name)[()])


def _scalar_or_array(values, like):
    return float(values) if np.ndim(like) == 0 else values


#: Largest WLF constant accepted, c1 and c2 [K]: log10 a_T never exceeds c1 in magnitude above T_ref - c2, and beyond
#: a few hundred decades no time of a run or a material is representable (relaxation times span 1e-40..1e40 s);
#: measured constants are 5-50 and 20-200 K at T_g, larger only referred near the singularity.
LARGEST_CONSTANT = 1e4


def _check_constant(value, *, name, unit=""):
    value = check_positive(value, name=name, unit=unit)
    if value > LARGEST_CONSTANT:
        raise ParameterError(f"{name} must be at most {LARGEST_CONSTANT:g}{' ' + unit if unit else ''} (measured WLF "
                             f"constants are 5-50 and 20-200 K at the glass transition), got {value!r}")
    return value


class Shift:
    """A shift function ``a_T(T)`` with ``a_T(reference) = 1``: the base of :class:`WLF` and :class:`Arrhenius`."""

    reference: float

    def log10_factor(self, temperature):
        """``log10 a_T`` at ``temperature`` [K] (a float, or an array for an array)."""
        raise NotImplementedError

    def factor(self, temperature):
        """The shift factor ``a_T`` at ``temperature`` [K]: every time of the material is multiplied by it.

        Raises a ParameterError where ``a_T`` leaves double precision (beyond
        1e+-300: near a WLF law's singularity), naming the temperature.
        """
        logs = np.asarray(self.log10_factor(temperature), dtype=float)
        outside = np.abs(logs) > 300.0
        if np.any(outside):
            index = tuple(int(i) for i in np.argwhere(outside)[0])
            value = float(np.asarray(temperature, dtype=float)[index]) if logs.ndim else float(temperature)
            raise ParameterError(f"temperature {value!r} K gives log10 a_T = {float(logs[index]):.6g} under {self!r}: "
                                 f"a shift factor beyond 1e+-300, outside double precision (too near the law's "
                                 f"singularity or too far from its reference); expected a temperature nearer "
                                 f"{self.reference:g} K")
        return _scalar_or_array(10.0 ** logs, temperature)


def _check_factors(temperatures, factors, reference):
    """Data of the ``fit`` classmethods: temperatures [K], shift factors > 0, and the reference."""
    temperatures = check_temperatures(check_finite_array(temperatures, name="temperatures", ndim=1),
                                      name="temperatures")
    factors = check_finite_array(factors, name="factors", ndim=1)
    if factors.shape != temperatures.shape:
        raise ShapeError(f"factors has {factors.size} values but temperatures has {temperatures.size}; "
                         f"expected one shift factor per temperature")
    if np.any(factors <= 0):
        i = int(np.argmax(factors <= 0))
        raise ParameterError(f"factors must be positive shift factors a_T, got factors[{i}] = {float(factors[i])!r}")
    reference = check_temperature(reference, name="reference")
    informative = temperatures != reference   # a_T(T_ref) = 1 says nothing about the constants
    return temperatures[informative] - reference, np.log10(factors[informative]), reference


@dataclass(frozen=True)
class WLF(Shift):
    """Williams-Landel-Ferry shift: ``log10 a_T = -c1 (T - T_ref) / (c2 + T - T_ref)``.

    Parameters
    ----------
    c1 : float
        Dimensionless constant, > 0 (17.44 for many polymers with ``T_ref = Tg``).
    c2 : float
        Temperature constant [K], > 0 (51.6 K for many polymers with ``T_ref = Tg``).
    reference : float
        Reference temperature ``T_ref`` [K], where ``a_T = 1``.

    Williams, Landel & Ferry, J. Am. Chem. Soc. 77, 3701 (1955). Temperatures
    with ``T - T_ref <= -c2`` (where the law is singular) are refused; the law
    holds from about the glass transition up (below it use :class:`Arrhenius`).
    """

    c1: float
    c2: float
    reference: float

    def __post_init__(self):
        object.__setattr__(self, "c1", _check_constant(self.c1, name="c1"))
        object.__setattr__(self, "c2", _check_constant(self.c2, name="c2", unit="K"))
        object.__setattr__(self, "reference", check_temperature(self.reference, name="reference"))

    def log10_factor(self, temperature):
        """``log10 a_T = -c1 (T - T_ref) / (c2 + T - T_ref)`` at ``temperature`` [K]."""
        values = check_temperatures(temperature)
        difference = values - self.reference
        singular = difference <= -self.c2
        if np.any(singular):
            index = tuple(int(i) for i in np.argwhere(singular)[0])
            raise ParameterError(
                f"temperature must lie above T_ref - c2 = {self.reference - self.c2:.6g} K, where the WLF shift "
                f"log10 a_T = -c1 (T - T_ref) / (c2 + T - T_ref) is singular (T - T_ref <= -c2, with "
                f"c2 = {self.c2:g} K and T_ref = {self.reference:g} K), got {float(values[index])!r} K; below the "
                f"glass transition use materials.Arrhenius")
        return _scalar_or_array(-self.c1 * difference / (self.c2 + difference), temperature)

    @classmethod
    def fit(cls, temperatures, factors, reference):
        """The WLF law through measured shift factors, by least squares in ``log10 a_T``.

        The linear form ``c2 y + c1 x = -x y`` (``x = T - T_ref``, ``y = log10
        a_T``) gives the start, exact for exact data; ``scipy.optimize.
        least_squares`` then minimises ``sum (log10 a_model - y)^2`` with
        ``c1 > 0`` and ``c2 > max(T_ref - T)`` (the singularity below every
        temperature).

        Parameters
        ----------
        temperatures : array_like
            Temperatures [K].
        factors : array_like
            Shift factors ``a_T`` (not their logarithms) at those temperatures, > 0.
        reference : float
            ``T_ref`` [K] of the factors (where ``a_T = 1``).

        Returns
        -------
        WLF
        """
        x, y, reference = _check_factors(temperatures, factors, reference)
        if x.size < 2:
            raise ParameterError(f"temperatures must hold at least two temperatures besides the reference "
                                 f"{reference:g} K to fit c1 and c2, got {x.size}")
        floor = max(0.0, float(np.max(-x)))   # c2 must exceed it: the singularity below every temperature
        (c1, c2), *_ = np.linalg.lstsq(np.column_stack([x, y]), -x * y, rcond=None)
        start = [max(c1, 1e-3), max(c2, floor * 1.01 + 1e-3)]

        def residual(p):
            return -p[0] * x / (p[1] + x) - y
        solution = least_squares(residual, start, bounds=([1e-12, floor * (1 + 1e-9) + 1e-12], [np.inf, np.inf]),
                                 xtol=1e-15, ftol=1e-15, gtol=1e-15)
        c1, c2 = (float(v) for v in solution.x)
        if c1 <= 1e-9:
            raise ParameterError(f"factors must fall as the temperature rises for a WLF law (a_T > 1 below the "
                                 f"reference, < 1 above), got factors {np.round(10.0 ** y, 6).tolist()} at "
                                 f"{(x + reference).tolist()} K: the fitted c1 sits at its bound 0")
        if c1 > LARGEST_CONSTANT or c2 > LARGEST_CONSTANT:
            raise ParameterError(f"factors do not follow a WLF law: the fitted c1 = {c1:.6g}, c2 = {c2:.6g} K exceed "
                                 f"{LARGEST_CONSTANT:g} (the factors are straight in T: use Arrhenius.fit, or fit from "
                                 f"the glass transition up, MasterCurve.fit_wlf)")
        return cls(c1=c1, c2=c2, reference=reference)


@dataclass(frozen=True)
class Arrhenius(Shift):
    """Arrhenius shift: ``ln a_T = (E_a / R) (1/T - 1/T_ref)`` (natural logarithm).

    Parameters
    ----------
    activation_energy : float
        ``E_a`` [J/mol], > 0.
    reference : float
        Reference temperature ``T_ref`` [K], where ``a_T = 1``.

    ``R`` is :data:`GAS_CONSTANT` = 8.314462618 J/(mol K).
    """

    activation_energy: float
    reference: float

    def __post_init__(self):
        object.__setattr__(self, "activation_energy",
                           check_quantity(self.activation_energy, name="activation_energy", unit="J/mol"))
        object.__setattr__(self, "reference", check_temperature(self.reference, name="reference"))

    def log10_factor(self, temperature):
        """``log10 a_T = (E_a / (R ln 10)) (1/T - 1/T_ref)`` at ``temperature`` [K]."""
        values = check_temperatures(temperature)
        natural = self.activation_energy / GAS_CONSTANT * (1.0 / values - 1.0 / self.reference)
        return _scalar_or_array(natural / math.log(10.0), temperature)

    @classmethod
    def fit(cls, temperatures, factors, reference):
        """The Arrhenius law through measured shift factors: ``E_a`` by least squares in ``ln a_T`` (exact: linear).

        Parameters as :meth:`WLF.fit`. Returns :class:`Arrhenius`.
        """
        x, y, reference = _check_factors(temperatures, factors, reference)
        if x.size < 1:
            raise ParameterError(f"temperatures must hold a temperature besides the reference {reference:g} K "
                                 f"to fit the activation energy, got none")
        slope_variable = 1.0 / (x + reference) - 1.0 / reference
        energy = GAS_CONSTANT * math.log(10.0) * float(slope_variable @ y) / float(slope_variable @ slope_variable)
        if energy <= 0:
            raise ParameterError(f"factors must fall as the temperature rises (a_T > 1 below the reference, < 1 "
                                 f"above) for an Arrhenius law, got a fitted activation energy of {energy:.6g} J/mol")
        return cls(activation_energy=energy, reference=reference)


@dataclass(frozen=True)
class WLFArrhenius(Shift):
    """WLF above the glass transition, Arrhenius below it, joined at ``glass_transition``; ``a_T = 1`` at ``reference``.

    ``log10 a_T = L(T) - L(T_ref)`` with, about ``T_g`` = ``glass_transition``::

        L(T) = -c1 (T - T_g) / (c2 + T - T_g)                 T >= T_g   (WLF, constants at T_g)
        L(T) = E_a / (R ln 10) (1/T - 1/T_g)                  T <  T_g   (Arrhenius)

    The usual description of an amorphous polymer over its whole DMA range
    (Ferry 1980, ch. 11 and 17: free volume above ``T_g``, an activated process
    in the glass): continuous at ``T_g``, never singular (the WLF branch is used
    only above ``T_g``). Unlike :class:`WLF`, the reference may lie on either
    side of ``T_g``, so the law of a master curve at a glassy reference is one
    object (:meth:`MasterCurve.fit_shift <framework.materials.MasterCurve.fit_shift>`).

    Parameters
    ----------
    c1 : float
        WLF constant at ``T_g``, > 0 (17.44 "universal").
    c2 : float
        WLF constant at ``T_g`` [K], > 0 (51.6 K "universal").
    glass_transition : float
        ``T_g`` [K], where the branches join.
    activation_energy : float
        ``E_a`` of the glassy branch [J/mol], > 0.
    reference : float
        ``T_ref`` [K], where ``a_T = 1``.
    """

    c1: float
    c2: float
    glass_transition: float
    activation_energy: float
    reference: float

    def __post_init__(self):
        object.__setattr__(self, "c1", _check_constant(self.c1, name="c1"))
        object.__setattr__(self, "c2", _check_constant(self.c2, name="c2", unit="K"))
        object.__setattr__(self, "glass_transition",
                           check_temperature(self.glass_transition, name="glass_transition"))
        object.__setattr__(self, "activation_energy",
                           check_quantity(self.activation_energy, name="activation_energy", unit="J/mol"))
        object.__setattr__(self, "reference", check_temperature(self.reference, name="reference"))

    @staticmethod
    def _branches(values, c1, c2, tg, energy):
        above = values - tg
        with np.errstate(divide="ignore", invalid="ignore"):
            wlf = -c1 * above / (c2 + np.maximum(above, 0.0))
        arrhenius = energy / (GAS_CONSTANT * math.log(10.0)) * (1.0 / values - 1.0 / tg)
        return np.where(above >= 0.0, wlf, arrhenius)

    def log10_factor(self, temperature):
        """``log10 a_T = L(T) - L(T_ref)`` at ``temperature`` [K] (class docstring)."""
        values = check_temperatures(temperature)
        law = (self.c1, self.c2, self.glass_transition, self.activation_energy)
        return _scalar_or_array(self._branches(values, *law) - self._branches(np.asarray(self.reference), *law),
                                temperature)

    @classmethod
    def fit(cls, temperatures, factors, reference, glass_transition):
        """The law through measured shift factors, ``T_g`` given.

        The WLF branch first, from the factors at and above ``T_g`` alone
        (``c1``, ``c2`` and the branch's offset by least squares in ``log10
        a_T``): so that its constants stay those of the rubbery and transition
        range, whatever the glass does. Then ``E_a``: with the reference below
        ``T_g``, the Arrhenius line through ``T_g`` and ``a_T(T_ref) = 1`` (so the
        law is exact at the reference and follows the WLF range); with the
        reference above, by least squares over the factors below ``T_g``.

        Parameters
        ----------
        temperatures, factors : array_like
            Temperatures [K] and shift factors ``a_T`` (not their logarithms), > 0.
        reference : float
            ``T_ref`` [K] of the factors (where ``a_T = 1``).
        glass_transition : float
            ``T_g`` [K]: at least three temperatures must lie at or above it, one below.

        Returns
        -------
        WLFArrhenius
        """
        x, y, reference = _check_factors(temperatures, factors, reference)
        temperatures, y = np.append(x + reference, reference), np.append(y, 0.0)   # a_T(T_ref) = 1 is a factor too
        tg = check_temperature(glass_transition, name="glass_transition")
        above, below = temperatures >= tg, temperatures < tg
        if above.sum() < 3 or below.sum() < 1:
            raise ParameterError(f"glass_transition {tg:g} K must leave at least three temperatures at or above it and "
                                 f"one below to fit both branches, got {int(above.sum())} above and "
                                 f"{int(below.sum())} below")
        t_above, y_above = temperatures[above] - tg, y[above]

        def branch(p):   # c1, c2, offset
            return -p[0] * t_above / (p[1] + t_above) + p[2] - y_above

        c1, c2, offset = least_squares(branch, [17.44, 51.6, float(np.mean(y_above))], x_scale=[10.0, 50.0, 1.0],
                                       bounds=([1e-9, 1e-9, -np.inf], np.inf), xtol=1e-14, ftol=1e-14, gtol=1e-14).x
        inverse = 1.0 / temperatures[below] - 1.0 / tg
        if reference < tg:
            # the glassy branch through (T_g, offset) and (T_ref, 0): the WLF range and the reference stay exact
            energy = -offset * GAS_CONSTANT * math.log(10.0) / (1.0 / reference - 1.0 / tg)
        else:
            # offset at T_g fixed by the WLF branch: E_a by least squares below T_g (linear)
            energy = GAS_CONSTANT * math.log(10.0) * float(inverse @ (y[below] - offset)) / float(inverse @ inverse)
        if not energy > 0:
            raise ParameterError(f"factors must fall as the temperature rises below glass_transition {tg:g} K for an "
                                 f"Arrhenius branch, got a fitted activation energy of {energy:.6g} J/mol")
        return cls(c1=float(c1), c2=float(c2), glass_transition=tg, activation_energy=float(energy),
                   reference=reference)
