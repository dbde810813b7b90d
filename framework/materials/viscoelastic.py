"""Isotropic linear viscoelastic solids: Prony series and exact conversion.

A generalized Maxwell (Wiechert) solid has the relaxation modulus (tension)

    E(t) = e_inf + sum_i E_i exp(-t / tau_i)                       [Pa]

and its creep compliance is again a finite sum of exponentials,

    J(t) = j0 + sum_k J_k (1 - exp(-t / lambda_k))                 [1/Pa],

with ``j0 = J(0) = 1/E(0)`` and ``J(inf) = j0 + sum_k J_k = 1/e_inf``. The two
are linked by the Laplace-domain identity ``s E_bar(s) . s J_bar(s) = 1``
(Gross 1953; Tschoegl 1989, ch. 4; the reciprocal relation used by Spinu &
Cerlinca, seed 001, eq. 3), i.e. ``int_0^t E(t - s) dJ(s) = 1`` for all
``t >= 0``.

Derivation of the conversion (checked numerically in tests/test_materials.py)
-------------------------------------------------------------------------------
With rates ``r_i = 1/tau_i``, ``s E_bar(s) = e_inf + sum_i E_i s / (s + r_i)``.
``s J_bar(s) = 1 / (s E_bar(s))`` is a rational function whose poles are the
zeros of ``s E_bar(s)``; writing ``s = -rho`` they solve

    e_inf - sum_i E_i rho / (r_i - rho) = 0.

The left side decreases on every interval between poles, equals ``e_inf > 0``
at ``rho = 0``, runs from ``+inf`` to ``-inf`` between consecutive ``r_i`` and
stays above ``E(0) > 0`` beyond the largest ``r_i``: there are exactly N real
roots, interlaced as ``0 < rho_1 < r_1 < rho_2 < r_2 < ... < rho_N < r_N``.
Matching ``s J_bar(s) = J(inf) - sum_k D_k s / (s + rho_k)`` at the simple pole
``s = -rho_k`` gives ``D_k rho_k = 1 / g'(-rho_k)`` with
``g(s) = s E_bar(s)``, ``g'(s) = sum_i E_i r_i / (s + r_i)^2``, hence

    D_k = 1 / (rho_k sum_i E_i r_i / (r_i - rho_k)^2),  lambda_k = 1/rho_k,

and ``J(t) = 1/e_inf - sum_k D_k exp(-rho_k t)``, i.e. ``J_k = D_k`` in the form
above. Both formulas of THEORY.md sec. 4 (root equation and ``D_k``) agree with
this derivation; the tests confirm ``J(0) E(0) = 1``, ``J(inf) e_inf = 1`` and
the convolution identity to ~1e-14.

The converse is the same construction on ``s J_bar(s) = j0 + sum_k J_k
rho_k / (s + rho_k)``: the relaxation rates ``r`` are the zeros of

    j0 + sum_k J_k rho_k / (rho_k - r) = 0,

which increases from ``-inf`` to ``+inf`` between consecutive ``rho_k`` and from
``-inf`` towards ``j0 > 0`` beyond the largest one, so that
``rho_1 < r_1 < rho_2 < ... < rho_N < r_N``; the residues give
``E_i = 1 / (r_i sum_k J_k rho_k / (rho_k - r_i)^2)`` and ``e_inf = 1/J(inf)``.
A solid with ``j0 = 0`` (Kelvin-Voigt) sends ``r_N`` to infinity: its
relaxation modulus carries a Dirac delta (see :class:`KelvinVoigt`).

Each root is bracketed between its two poles, measured as an offset from the
nearer pole (so that the differences ``r_i - rho`` keep full relative precision
however close the root is to a pole and however many decades the times span),
solved with :func:`scipy.optimize.brentq` in the logarithm of that offset and
polished by Newton steps.

PMMA of seed 001
----------------
:data:`PMMA` is the relaxation modulus of Spinu & Cerlinca (seed 001, eq. 2),
fitted to the data of Kumar & Narasimhan (2004):
``E(t) = 1973 + 254.776 exp(-t/8.93) + 263.6628 exp(-t/117.96)`` MPa. Its exact
creep compliance (this module) is

    J(t) = 5.06842e-4 - 4.47406e-5 exp(-t/9.93630) - 6.07272e-5 exp(-t/133.870)  [1/MPa],

``J(0) = 4.01374e-4 = 1/2491.44`` 1/MPa. Seed 001 prints (its eq. 4)
``Phi(t) = 7e-4 - 6.17e-5 exp(-0.1 t) - 8.38e-5 exp(-7.47e-3 t)`` [1/MPa].
Its retardation times, 10 s and 133.9 s, agree with the exact 9.936 s and
133.870 s, but all three coefficients are about 1.38 times too large:
``Phi(t)/J(t)`` lies between 1.38098 and 1.38150 for every ``t`` (1.38150 at
``t = 0``, 1.38110 as ``t -> inf``, since ``7e-4 * 1973 = 1.3811``), so that
``Phi(0) E(0) = 1.38`` instead of 1 and ``Phi(inf) e_inf = 1.38`` instead of 1.
The printed function is therefore not used: the creep is always derived from
the relaxation modulus.
"""
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from .._validation import LIMITS, RELAXATION_TIMES, check_poisson, check_positive, check_quantity, check_real
from ..errors import ParameterError
from .base import ComplianceSeries, DynamicModuli, check_frequencies, refuse_shift
from .temperature import Shift, check_temperature

__all__ = ["KelvinVoigt", "Maxwell", "PMMA", "StandardLinearSolid", "Viscoelastic"]


# --------------------------------------------------------------------------- validation

def _check_times(t):
    """Evaluation times as a float array: finite or +inf, and >= 0 [s]."""
    try:
        t = np.asarray(t, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"t must be real times [s], got {type(t).__name__}") from exc
    bad = np.isnan(t) | (t < 0)
    if np.any(bad):
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ParameterError(f"t must be >= 0 [s] (time since loading), got {float(t[index])!r} at index {index}")
    return t


def _check_terms(terms, *, name, coefficient, unit, time):
    """Validate ``[(coefficient, time), ...]``; return them sorted by time (ascending)."""
    what = f"a sequence of ({coefficient} [{unit}], {time} [s]) pairs"
    if isinstance(terms, (str, bytes)) or not hasattr(terms, "__iter__"):
        raise ParameterError(f"{name} must be {what}, got {terms!r}")
    checked = []
    for i, term in enumerate(terms):
        try:
            value, tau = term
        except (TypeError, ValueError) as exc:
            raise ParameterError(f"{name}[{i}] must be a ({coefficient} [{unit}], {time} [s]) pair, "
                                 f"got {term!r}") from exc
        value = check_quantity(value, name=f"{name}[{i}] {coefficient}", unit=unit, lower=False)
        tau = check_quantity(tau, name=f"{name}[{i}] {time}", unit="s", limits=RELAXATION_TIMES)
        for j, (_, other) in enumerate(checked):
            if tau == other:
                raise ParameterError(
                    f"{name}[{i}] {time} must differ from the others, got {tau!r} s, the same as {name}[{j}]; "
                    f"expected distinct times (merge the two terms by adding their {coefficient}s)")
        checked.append((value, tau))
    return tuple(sorted(checked, key=lambda pair: pair[1]))


# --------------------------------------------------------------------------- root finding

def _rate(rate):
    """A rate [1/s] and its time, for messages."""
    return f"{rate!r} 1/s" + (f" (1/rate = {1 / rate:.6g} s)" if rate > 0 else "")


def _interval_root(evaluate, derivative, left, right, left_sign):
    """Root of a rational function that changes sign once in ``(left, right)``.

    ``evaluate(anchor, sign, delta)`` and ``derivative(anchor, sign, delta)``
    give the function and its derivative with respect to ``delta`` at
    ``x = anchor + sign * delta``, computing the distances to the poles from
    the exact ``anchor - p_i``. The function has the sign ``left_sign`` just
    right of ``left`` and the opposite sign just left of ``right``.

    Returns ``(anchor, sign, delta)`` of the root.
    """
    middle = math.sqrt(left * right) if left > 0 else 0.5 * right
    if not left < middle < right:  # the two poles are as close as rounding can tell: no room for a root
        raise ParameterError(
            f"a Prony term is too weak to resolve in double precision: a root lies within rounding of the rate "
            f"{_rate(right)}; drop the negligible term")
    at_middle = evaluate(left, 1.0, middle - left)
    if at_middle == 0.0:
        return left, 1.0, middle - left
    if (at_middle > 0) == (left_sign > 0):
        anchor, sign, width, end_sign = right, -1.0, right - middle, -left_sign
    else:
        anchor, sign, width, end_sign = left, 1.0, middle - left, left_sign

    def in_log(u):
        return evaluate(anchor, sign, width * math.exp(u))

    low = -40.0
    while (in_log(low) > 0) != (end_sign > 0):
        if low < -320.0:  # the next try, exp(-1280), would underflow to a zero distance
            raise ParameterError(
                f"a Prony term is too weak to resolve in double precision: a root lies within "
                f"{width * math.exp(low):.3g} 1/s of the rate {_rate(anchor)}; drop the negligible term")
        low *= 2.0
    u = brentq(in_log, low, 0.0, xtol=1e-14, rtol=4 * np.finfo(float).eps, maxiter=500)
    delta = width * math.exp(u)
    # Newton polish: the log-space bracket leaves ~1e-14 relative error in delta.
    value = evaluate(anchor, sign, delta)
    for _ in range(3):
        if value == 0.0:
            break
        step = value / derivative(anchor, sign, delta)
        trial = delta - step
        if not 0.0 < trial <= width:
            break
        trial_value = evaluate(anchor, sign, trial)
        if abs(trial_value) >= abs(value):
            break
        delta, value = trial, trial_value
    return anchor, sign, delta


def _relaxation_to_creep(e_inf, terms):
    """Exact creep Prony series ``(j0, ((J_k, lambda_k), ...))`` of a relaxation series."""
    e0 = math.fsum([e_inf] + [e for e, _ in terms])
    if not terms:
        return 1.0 / e0, ()
    # ascending rates r_i = 1/tau_i (terms come sorted by ascending tau)
    moduli = [e / e0 for e, _ in reversed(terms)]
    rates = [1.0 / tau for _, tau in reversed(terms)]
    c = e_inf / e0

    def distances(anchor, sign, delta):
        return [(anchor - r) + sign * delta for r in rates]   # x - r_i

    def evaluate(anchor, sign, delta):       # c + sum w_i x/(x - r_i)
        x = anchor + sign * delta
        return math.fsum([c] + [w * x / d for w, d in zip(moduli, distances(anchor, sign, delta))])

    def derivative(anchor, sign, delta):     # d/d(delta) = sign * (-sum w_i r_i/(x - r_i)^2)
        return -sign * math.fsum([w * r / d**2 for w, r, d in zip(moduli, rates, distances(anchor, sign, delta))])

    creep = []
    for k, right in enumerate(rates):
        left = rates[k - 1] if k else 0.0
        anchor, sign, delta = _interval_root(evaluate, derivative, left, right, left_sign=1.0)
        rho = anchor + sign * delta
        slope = math.fsum([w * r / d**2 for w, r, d in zip(moduli, rates, distances(anchor, sign, delta))])
        creep.append((1.0 / (e0 * rho * slope), 1.0 / rho))
    return 1.0 / e0, tuple(sorted(creep, key=lambda pair: pair[1]))


def _creep_to_relaxation(j0, terms):
    """Exact relaxation Prony series ``(e_inf, ((E_i, tau_i), ...))`` of a creep series."""
    j_inf = math.fsum([j0] + [j for j, _ in terms])
    if not terms:
        return 1.0 / j_inf, ()
    compliances = [j / j_inf for j, _ in reversed(terms)]
    rates = [1.0 / lam for _, lam in reversed(terms)]
    c = j0 / j_inf

    def distances(anchor, sign, delta):
        return [(anchor - p) + sign * delta for p in rates]   # x - rho_k

    def evaluate(anchor, sign, delta):       # c - sum w_k rho_k/(x - rho_k)
        return math.fsum([c] + [-w * p / d for w, p, d in zip(compliances, rates, distances(anchor, sign, delta))])

    def derivative(anchor, sign, delta):     # sign * sum w_k rho_k/(x - rho_k)^2
        return sign * math.fsum([w * p / d**2 for w, p, d in zip(compliances, rates, distances(anchor, sign, delta))])

    # beyond the largest rate the function climbs from -inf towards c > 0 and is
    # positive from rho_N + sum_k w_k rho_k / c on: twice that is a safe bracket end
    last = rates[-1] + 2.0 * math.fsum([w * p for w, p in zip(compliances, rates)]) / c
    relaxation = []
    for k, left in enumerate(rates):
        right = rates[k + 1] if k + 1 < len(rates) else last
        anchor, sign, delta = _interval_root(evaluate, derivative, left, right, left_sign=-1.0)
        r = anchor + sign * delta
        slope = math.fsum([w * p / d**2 for w, p, d in zip(compliances, rates, distances(anchor, sign, delta))])
        relaxation.append((1.0 / (j_inf * r * slope), 1.0 / r))
    return 1.0 / j_inf, tuple(sorted(relaxation, key=lambda pair: pair[1]))


# --------------------------------------------------------------------------- materials

#: Ends the message of an array of temperatures given to a material (a material is at one temperature).
_ONE_AT_A_TIME = "; take the material to one temperature at a time, e.g. [m.at(T, shift) for T in temperatures]"


def _scaled(terms, factor):
    """Prony terms ``((coefficient, time), ...)`` with every time multiplied by ``factor`` (exact for 1)."""
    return tuple((value, time * factor) for value, time in terms)


def _check_shift(shift):
    if not isinstance(shift, Shift):
        raise ParameterError(f"shift must be a time-temperature shift, materials.WLF(c1, c2, reference) or "
                             f"materials.Arrhenius(activation_energy, reference), got {shift!r}")
    return shift


@dataclass(frozen=True)
class Viscoelastic(DynamicModuli):
    """Isotropic linear viscoelastic solid (generalized Maxwell / Wiechert) with constant Poisson ratio.

    Relaxation modulus (tension) ``E(t) = e_inf + sum_i E_i exp(-t/tau_i)`` and
    its exact creep compliance ``J(t) = j0 + sum_k J_k (1 - exp(-t/lambda_k))``,
    ``j0 = 1/E(0)``, ``J(inf) = 1/e_inf`` (conversion in the module docstring;
    Gross 1953, Tschoegl 1989; the Prony form used by Chen et al., J. Tribol.
    2011, and Spinu & Cerlinca, seed 001). Build it with :meth:`from_prony`
    (relaxation data) or :meth:`from_creep` (creep data); ``Viscoelastic(e_inf,
    terms, poisson)`` is the same as :meth:`from_prony`.

    Parameters
    ----------
    e_inf : float
        Relaxed (long-time) modulus ``E(inf)`` [Pa], > 0. A material without one
        is a fluid: use :class:`Maxwell`.
    terms : sequence of (float, float)
        ``[(E_i [Pa], tau_i [s]), ...]``, moduli and relaxation times > 0, times
        distinct. Stored sorted by ascending ``tau_i``. May be empty (elastic).
    poisson : float
        Constant Poisson ratio in (-1, 0.5].
    temperature : float, optional
        The material's temperature [K]; needs ``shift``. Default: the shift's
        reference temperature (None without a shift).
    shift : materials.WLF or materials.Arrhenius, optional
        Time-temperature shift. With one, ``e_inf`` and ``terms`` describe the
        solid at ``shift.reference`` (its master curve) and the solid itself,
        at ``temperature``, has every relaxation time multiplied by
        ``a_T = shift.factor(temperature)``, moduli unchanged
        (:mod:`framework.materials.temperature`): :attr:`relaxation_terms`,
        :attr:`creep_terms`, :meth:`relaxation`, :meth:`creep`,
        :meth:`complex_modulus` and the contact all use the shifted times.
        Build it with :meth:`at`.

    Moduli lie between 1e-3 and 1e15 Pa (a term's modulus may be smaller: a term
    too weak to resolve in double precision is refused by name) and times
    between 1e-40 and 1e40 s (``framework._validation.RELAXATION_TIMES``: a
    master curve's), shifted or not.
    """

    e_inf: float
    terms: tuple
    poisson: float
    temperature: float = None
    shift: object = None
    _j0: float = field(init=False, repr=False, compare=False)
    _creep: tuple = field(init=False, repr=False, compare=False)   # of ``terms``: unshifted
    _factor: float = field(init=False, repr=False, compare=False)  # a_T at ``temperature``

    def __post_init__(self):
        e_inf = check_real(self.e_inf, name="e_inf")
        if e_inf <= 0.0:
            raise ParameterError(
                f"e_inf must be positive [Pa], got {e_inf!r}; a material without a relaxed modulus is a "
                f"fluid: use materials.Maxwell")
        object.__setattr__(self, "e_inf", check_quantity(e_inf, name="e_inf", unit="Pa"))
        object.__setattr__(self, "terms",
                           _check_terms(self.terms, name="terms", coefficient="modulus", unit="Pa",
                                        time="relaxation time"))
        object.__setattr__(self, "poisson", check_poisson(self.poisson))
        object.__setattr__(self, "_factor", self._shift_factor())
        j0, creep = _relaxation_to_creep(self.e_inf, self.terms)
        object.__setattr__(self, "_j0", j0)
        object.__setattr__(self, "_creep", creep)

    def _shift_factor(self):
        """Check ``temperature`` and ``shift`` (the temperature defaults to the reference); return ``a_T``."""
        if self.shift is None:
            if self.temperature is not None:
                raise ParameterError(
                    f"temperature needs a shift: give shift = materials.WLF(c1, c2, reference) or "
                    f"materials.Arrhenius(activation_energy, reference), which says how the times change with "
                    f"temperature, got temperature = {self.temperature!r} and no shift")
            return 1.0
        _check_shift(self.shift)
        if self.temperature is None:
            object.__setattr__(self, "temperature", self.shift.reference)
        object.__setattr__(self, "temperature", check_temperature(self.temperature, hint=_ONE_AT_A_TIME))
        factor = self.shift.factor(self.temperature)
        low, high = RELAXATION_TIMES
        for i, (_, tau) in enumerate(self.terms):
            if not low <= tau * factor <= high:
                raise ParameterError(
                    f"temperature: at {self.temperature:g} K the shift factor a_T = {factor:.6g} takes the relaxation "
                    f"time terms[{i}] = {tau:g} s to {tau * factor:.6g} s, outside the {low:g} to {high:g} s this "
                    f"framework accepts; expected a temperature nearer the shift's reference {self.shift.reference:g} K")
        return factor

    @classmethod
    def from_prony(cls, e_inf, terms, poisson):
        """Material from its relaxation modulus ``E(t) = e_inf + sum_i E_i exp(-t/tau_i)``.

        Parameters
        ----------
        e_inf : float
            Relaxed modulus [Pa], > 0.
        terms : sequence of (float, float)
            ``[(E_i [Pa], tau_i [s]), ...]``.
        poisson : float
            Poisson ratio in (-1, 0.5].
        """
        return cls(e_inf=e_inf, terms=terms, poisson=poisson)

    @classmethod
    def from_creep(cls, j0, terms, poisson):
        """Material from its creep compliance ``J(t) = j0 + sum_k J_k (1 - exp(-t/lambda_k))``.

        The relaxation modulus is obtained exactly (module docstring); the
        creep series is kept as given.

        Parameters
        ----------
        j0 : float
            Instantaneous compliance ``J(0) = 1/E(0)`` [1/Pa], > 0. A solid
            without one is a :class:`KelvinVoigt` solid.
        terms : sequence of (float, float)
            ``[(J_k [1/Pa], lambda_k [s]), ...]``, compliances and retardation
            times > 0, times distinct.
        poisson : float
            Poisson ratio in (-1, 0.5].
        """
        j0 = check_real(j0, name="j0")
        if j0 <= 0.0:
            raise ParameterError(
                f"j0 must be positive [1/Pa], got {j0!r}; a solid without instantaneous compliance has a "
                f"relaxation modulus with a Dirac delta: use materials.KelvinVoigt")
        j0 = check_quantity(j0, name="j0", unit="1/Pa")
        terms = _check_terms(terms, name="terms", coefficient="compliance", unit="1/Pa",
                             time="retardation time")
        check_poisson(poisson)
        relaxed, largest = math.fsum([j0] + [j for j, _ in terms]), LIMITS["1/Pa"][1]
        if relaxed > largest:
            raise ParameterError(f"j0 plus the terms' compliances, J(inf) = 1/e_inf, must stay below {largest:g} 1/Pa, "
                                 f"the range this framework accepts, got {relaxed!r}")
        e_inf, relaxation = _creep_to_relaxation(j0, terms)
        material = cls(e_inf=e_inf, terms=relaxation, poisson=poisson)
        object.__setattr__(material, "_j0", j0)
        object.__setattr__(material, "_creep", terms)
        return material

    def at(self, temperature, shift=None):
        """The same solid at ``temperature`` [K]: every time multiplied by the shift factor, moduli unchanged.

        The relaxation times become ``tau_i a_T(temperature) / a_T(self.temperature)``
        (the retardation times likewise: the creep series scales exactly), so
        that ``m.at(T1, s).at(T2, s) == m.at(T2, s)``. A material without a
        temperature is taken to be at the shift's reference. No vertical shift
        of the moduli is applied (:mod:`framework.materials.temperature`).

        Parameters
        ----------
        temperature : float
            Temperature [K].
        shift : materials.WLF or materials.Arrhenius, optional
            The shift function; default: the material's own. A new one takes
            the solid from its present temperature with the new law.

        Returns
        -------
        Viscoelastic
            With ``temperature`` and ``shift`` set; its ``terms`` stay those at
            ``shift.reference``, :attr:`relaxation_terms` gives the shifted ones.
        """
        if temperature is not None:
            temperature = check_temperature(temperature, hint=_ONE_AT_A_TIME)
        shift = self.shift if shift is None else _check_shift(shift)
        if shift is None:
            raise ParameterError("shift: this material carries no time-temperature shift; pass one, "
                                 "materials.WLF(c1, c2, reference) or materials.Arrhenius(activation_energy, "
                                 "reference)")
        terms, creep = self.terms, self._creep
        if self.shift is not None and shift != self.shift:
            # the series at the material's temperature, expressed at the new law's reference
            ratio = self._factor / shift.factor(self.temperature)
            terms, creep = _scaled(terms, ratio), _scaled(creep, ratio)
        material = Viscoelastic(e_inf=self.e_inf, terms=terms, poisson=self.poisson, temperature=temperature,
                                shift=shift)
        object.__setattr__(material, "_j0", self._j0)   # keep a creep series given as such (from_creep)
        object.__setattr__(material, "_creep", creep)
        return material

    @property
    def shift_factor(self):
        """``a_T`` at the material's temperature (1 without a shift): the factor on every time of ``terms``."""
        return self._factor

    @property
    def relaxation_terms(self):
        """``(e_inf [Pa], ((E_i [Pa], tau_i [s]), ...))`` at the material's temperature, ascending ``tau_i``."""
        return self.e_inf, _scaled(self.terms, self._factor)

    @property
    def creep_terms(self):
        """``(j0 [1/Pa], ((J_k [1/Pa], lambda_k [s]), ...))`` at the material's temperature, ascending ``lambda_k``."""
        return self._j0, _scaled(self._creep, self._factor)

    @property
    def relaxation_times(self):
        """The ``tau_i`` [s] at the material's temperature, as an array."""
        return np.array([tau for _, tau in self.relaxation_terms[1]], dtype=float)

    @property
    def retardation_times(self):
        """The ``lambda_k`` [s] at the material's temperature, as an array."""
        return np.array([lam for _, lam in self.creep_terms[1]], dtype=float)

    @property
    def instantaneous_modulus(self):
        """Glassy modulus ``E(0) = e_inf + sum_i E_i`` [Pa]."""
        return math.fsum([self.e_inf] + [e for e, _ in self.terms])

    @property
    def relaxed_modulus(self):
        """Rubbery modulus ``E(inf) = e_inf`` [Pa]."""
        return self.e_inf

    @property
    def contact_modulus(self):
        """Instantaneous plane-strain modulus ``E*(0) = E(0) / (1 - nu^2)`` [Pa].

        The response to a sudden load or indentation; the relaxed one is
        ``relaxed_modulus / (1 - poisson**2)``.
        """
        return self.instantaneous_modulus / (1.0 - self.poisson**2)

    def relaxation(self, t):
        """Relaxation modulus ``E(t)`` [Pa] at times ``t >= 0`` [s] (any shape)."""
        t = _check_times(t)
        value = np.full(t.shape, self.e_inf)
        for modulus, tau in self.relaxation_terms[1]:
            value = value + modulus * np.exp(-t / tau)
        return value

    def creep(self, t):
        """Creep compliance ``J(t)`` [1/Pa] at times ``t >= 0`` [s] (any shape; ``inf`` allowed)."""
        t = _check_times(t)
        j0, creep = self.creep_terms
        value = np.full(t.shape, j0)
        for compliance, lam in creep:
            value = value + compliance * -np.expm1(-t / lam)
        return value

    def contact_compliance(self):
        """``C*(t) = (1 - nu^2) J(t)`` as a :class:`ComplianceSeries` [1/Pa]."""
        factor = 1.0 - self.poisson**2
        j0, creep = self.creep_terms
        return ComplianceSeries(c0=factor * j0, terms=tuple((factor * j, lam) for j, lam in creep))


def StandardLinearSolid(e_inf, e_1, tau, poisson, temperature=None, shift=None):  # noqa: N802 - a named material
    """Standard linear solid (Zener): a spring ``e_inf`` parallel to a Maxwell arm ``(e_1, tau)``.

    ``E(t) = e_inf + e_1 exp(-t/tau)`` and
    ``J(t) = 1/e_inf - e_1 / (e_inf (e_inf + e_1)) exp(-t / lambda)`` with the
    retardation time ``lambda = tau (e_inf + e_1) / e_inf`` (Zener 1948;
    Findley, Lai & Onaran 1976, ch. 5).

    Parameters
    ----------
    e_inf : float
        Relaxed modulus [Pa], > 0.
    e_1 : float
        Modulus of the Maxwell arm [Pa], > 0; ``E(0) = e_inf + e_1``.
    tau : float
        Relaxation time of the arm [s], > 0.
    poisson : float
        Poisson ratio in (-1, 0.5].
    temperature, shift : optional
        As for :class:`Viscoelastic`: ``tau`` is then the time at ``shift.reference``.

    Its dynamic modulus peaks in loss at ``w = 1 / sqrt(tau lambda)``, where
    ``tan delta = e_1 / (2 sqrt(e_inf (e_inf + e_1)))``.

    Returns
    -------
    Viscoelastic
        The one-term material.
    """
    e_1 = check_quantity(e_1, name="e_1", unit="Pa")
    tau = check_quantity(tau, name="tau", unit="s")
    return Viscoelastic(e_inf=e_inf, terms=[(e_1, tau)], poisson=poisson, temperature=temperature, shift=shift)


@dataclass(frozen=True)
class Maxwell(DynamicModuli):
    """Maxwell fluid: a spring ``young`` in series with a dashpot ``young * relaxation_time``.

    ``E(t) = E exp(-t/tau)`` and ``J(t) = 1/E + t / (E tau)``: the creep grows
    without bound, so it is no bounded Prony series; :meth:`contact_compliance`
    returns a :class:`ComplianceSeries` with the linear ``flow`` term. Dynamic
    modulus ``E*(w) = E (i w tau) / (1 + i w tau)``: ``tan delta = 1 / (w tau)``.

    Parameters
    ----------
    young : float
        Instantaneous modulus ``E`` [Pa], > 0.
    relaxation_time : float
        ``tau = eta / E`` [s], > 0.
    poisson : float
        Poisson ratio in (-1, 0.5].
    """

    young: float
    relaxation_time: float
    poisson: float

    def __post_init__(self):
        object.__setattr__(self, "young", check_quantity(self.young, name="young", unit="Pa"))
        object.__setattr__(self, "relaxation_time",
                           check_quantity(self.relaxation_time, name="relaxation_time", unit="s"))
        object.__setattr__(self, "poisson", check_poisson(self.poisson))

    def at(self, temperature, shift=None):
        """Refused: a Maxwell fluid carries no temperature or shift (its ``relaxation_time`` is at one temperature).

        Time-temperature superposition scales the relaxation time, ``tau(T) = a_T(T) tau(T_ref)``;
        for a fluid whose ``relaxation_time`` is at ``shift.reference`` that is
        ``Maxwell(young, relaxation_time * shift.factor(T), poisson)``. A shifted copy that
        forgot its temperature would be shifted twice by a second ``at``, so none is returned.

        Raises
        ------
        ParameterError
            Always, naming the temperature received and the construction above.
        """
        refuse_shift(self, temperature, shift, "a Maxwell fluid carries no temperature or shift to shift from; for "
                     "the fluid at T from one whose relaxation_time is at shift.reference, build Maxwell(young, "
                     "relaxation_time * shift.factor(T), poisson)")

    @property
    def viscosity(self):
        """Dashpot viscosity in tension ``eta = E tau`` [Pa s]."""
        return self.young * self.relaxation_time

    @property
    def relaxation_terms(self):
        """``(0, ((E, tau),))``: no relaxed modulus."""
        return 0.0, ((self.young, self.relaxation_time),)

    @property
    def creep_terms(self):
        """``(1/E, ())``: the bounded part of the creep; the rest is :attr:`flow`."""
        return 1.0 / self.young, ()

    @property
    def flow(self):
        """Creep rate per unit stress ``1/eta`` [1/(Pa s)]."""
        return 1.0 / self.viscosity

    @property
    def instantaneous_modulus(self):
        """``E(0) = E`` [Pa]."""
        return self.young

    @property
    def relaxed_modulus(self):
        """``E(inf) = 0`` [Pa]: a fluid."""
        return 0.0

    @property
    def contact_modulus(self):
        """Instantaneous plane-strain modulus ``E / (1 - nu^2)`` [Pa]."""
        return self.young / (1.0 - self.poisson**2)

    def relaxation(self, t):
        """Relaxation modulus ``E exp(-t/tau)`` [Pa] at times ``t >= 0`` [s]."""
        return self.young * np.exp(-_check_times(t) / self.relaxation_time)

    def creep(self, t):
        """Creep compliance ``1/E + t/(E tau)`` [1/Pa] at times ``t >= 0`` [s]."""
        return (1.0 + _check_times(t) / self.relaxation_time) / self.young

    def contact_compliance(self):
        """``C*(t) = (1 - nu^2)(1/E + t/eta)`` as a :class:`ComplianceSeries` [1/Pa]."""
        factor = 1.0 - self.poisson**2
        return ComplianceSeries(c0=factor / self.young, terms=(), flow=factor / self.viscosity)


@dataclass(frozen=True)
class KelvinVoigt(DynamicModuli):
    """Kelvin-Voigt solid: a spring ``young`` parallel to a dashpot ``viscosity``.

    ``J(t) = (1/E)(1 - exp(-t/lambda))`` with ``lambda = eta/E``: no
    instantaneous compliance (``J(0) = 0``). Its relaxation modulus is
    ``E(t) = E + eta delta(t)``; :meth:`relaxation` returns the regular part
    ``E`` and the Dirac delta (an infinite force for a sudden strain) is left
    out. :meth:`contact_compliance` has ``c0 = 0``: a sudden jump in load or
    approach has no finite response, and time steppers must reject it.

    Parameters
    ----------
    young : float
        Spring modulus ``E = E(inf)`` [Pa], > 0.
    viscosity : float
        Dashpot viscosity in tension ``eta`` [Pa s], > 0.
    poisson : float
        Poisson ratio in (-1, 0.5].
    """

    young: float
    viscosity: float
    poisson: float

    def __post_init__(self):
        object.__setattr__(self, "young", check_quantity(self.young, name="young", unit="Pa"))
        viscosity = check_positive(self.viscosity, name="viscosity", unit="Pa s")
        low, high = (self.young * limit for limit in LIMITS["s"])  # a retardation time within the time limits
        if not low <= viscosity <= high:
            raise ParameterError(f"viscosity must lie between {low:g} and {high:g} Pa s (young times the times "
                                 f"{LIMITS['s'][0]:g} to {LIMITS['s'][1]:g} s), got {viscosity!r}")
        object.__setattr__(self, "viscosity", viscosity)
        object.__setattr__(self, "poisson", check_poisson(self.poisson))

    def at(self, temperature, shift=None):
        """Refused: a Kelvin-Voigt solid carries no temperature or shift (see :meth:`Maxwell.at`).

        Its retardation time ``eta/E`` scales with ``a_T``: the solid at ``T`` from one at
        ``shift.reference`` is ``KelvinVoigt(young, viscosity * shift.factor(T), poisson)``.

        Raises
        ------
        ParameterError
            Always, naming the temperature received and the construction above.
        """
        refuse_shift(self, temperature, shift, "a Kelvin-Voigt solid carries no temperature or shift to shift from; "
                     "for the solid at T from one whose viscosity is at shift.reference, build KelvinVoigt(young, "
                     "viscosity * shift.factor(T), poisson)")

    @property
    def retardation_time(self):
        """``lambda = eta / E`` [s]."""
        return self.viscosity / self.young

    @property
    def relaxation_terms(self):
        """``(E, ())``: the regular part; the ``eta delta(t)`` term is :attr:`viscosity`."""
        return self.young, ()

    @property
    def creep_terms(self):
        """``(0, ((1/E, lambda),))``."""
        return 0.0, ((1.0 / self.young, self.retardation_time),)

    @property
    def instantaneous_modulus(self):
        """``E(0+)`` is infinite (the Dirac delta) [Pa]."""
        return math.inf

    @property
    def relaxed_modulus(self):
        """``E(inf) = E`` [Pa]."""
        return self.young

    @property
    def contact_modulus(self):
        """Instantaneous plane-strain modulus: infinite (no instantaneous compliance) [Pa]."""
        return math.inf

    def relaxation(self, t):
        """Regular part ``E`` of the relaxation modulus [Pa] at ``t >= 0`` [s] (the ``eta delta(t)`` is left out)."""
        return np.full(_check_times(t).shape, self.young)

    def creep(self, t):
        """Creep compliance ``(1/E)(1 - exp(-t/lambda))`` [1/Pa] at ``t >= 0`` [s]."""
        return -np.expm1(-_check_times(t) / self.retardation_time) / self.young

    def contact_compliance(self):
        """``C*(t) = (1 - nu^2) J(t)`` as a :class:`ComplianceSeries` with ``c0 = 0`` [1/Pa]."""
        factor = 1.0 - self.poisson**2
        return ComplianceSeries(c0=0.0, terms=((factor / self.young, self.retardation_time),))

    def complex_modulus(self, w):
        """``E*(w) = E + i w eta`` [Pa] at ``w > 0`` [rad/s]: the dashpot's delta gives the loss."""
        w = check_frequencies(w)
        return self.young + 1j * (w * self.viscosity)


#: Polymethyl methacrylate of Spinu & Cerlinca (seed 001, eq. 2): a two-term
#: Prony fit of the uniaxial-compression relaxation data of Kumar & Narasimhan
#: (Current Science 87, 2004; ref. [10] of seed 001),
#: ``E(t) = 1973 + 254.776 exp(-t/8.93) + 263.6628 exp(-t/117.96)`` MPa, with
#: ``nu = 0.35``. See "PMMA of seed 001" in the module docstring for its creep.
PMMA = Viscoelastic.from_prony(e_inf=1973e6, terms=[(254.776e6, 8.93), (263.6628e6, 117.96)], poisson=0.35)
