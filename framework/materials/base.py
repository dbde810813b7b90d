"""What every material gives the time stepper, and the dynamic moduli they share."""
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError


def check_frequencies(w, *, name="w"):
    """Angular frequencies as a float array (any shape): finite and > 0 [rad/s]."""
    try:
        w = np.asarray(w, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name} must be real angular frequencies [rad/s], got {type(w).__name__}") from exc
    bad = ~np.isfinite(w) | (w <= 0)
    if np.any(bad):
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ParameterError(f"{name} must be positive finite angular frequencies [rad/s] (2 pi times the "
                             f"frequency in Hz), got {float(w[index])!r} at index {index}")
    return w


def refuse_shift(material, temperature, shift, reason):
    """Raise the ParameterError of ``material.at(temperature, shift)`` on a material that cannot be shifted."""
    name = type(material).__name__
    raise ParameterError(f"{name}.at: got temperature = {temperature!r} K and shift = {shift!r}, but {reason}; "
                         f"expected a materials.Viscoelastic (a Prony series, e.g. fit_prony(...).material or "
                         f"StandardLinearSolid) for a time-temperature shift")


def maxwell_arm(w, tau):
    """Storage and loss parts ``((w tau)^2, w tau) / (1 + (w tau)^2)`` of a Maxwell arm of unit modulus.

    Written as ``1 / (1 + 1/s^2)`` and ``1 / (s + 1/s)`` with ``s = w tau`` so
    that neither overflows however many decades ``s`` spans.
    """
    s = np.asarray(w, dtype=float) * tau
    with np.errstate(over="ignore", divide="ignore"):
        return 1.0 / (1.0 + 1.0 / s**2), 1.0 / (s + 1.0 / s)


class DynamicModuli:
    """Dynamic moduli under a harmonic strain ``eps0 exp(i w t)`` (what DMA measures), in tension.

    ``E*(w) = E' + i E'' = e_inf + sum_i E_i (i w tau_i) / (1 + i w tau_i)`` for a
    generalized Maxwell solid (Ferry 1980, ch. 3; Tschoegl 1989, ch. 4): the
    Fourier transform ``i w int_0^inf E(t) exp(-i w t) dt`` of its relaxation
    modulus. Subclasses give ``relaxation_terms`` or override
    :meth:`complex_modulus`.
    """

    def complex_modulus(self, w):
        """``E*(w) = E'(w) + i E''(w)`` [Pa] at angular frequencies ``w > 0`` [rad/s] (any shape)."""
        w = check_frequencies(w)
        e_inf, terms = self.relaxation_terms
        storage, loss = np.full(w.shape, float(e_inf)), np.zeros(w.shape)
        for modulus, tau in terms:
            real, imaginary = maxwell_arm(w, tau)
            storage, loss = storage + modulus * real, loss + modulus * imaginary
        return storage + 1j * loss

    def storage_modulus(self, w):
        """``E'(w)`` [Pa]: the part of the stress in phase with the strain (energy stored)."""
        return self.complex_modulus(w).real

    def loss_modulus(self, w):
        """``E''(w)`` [Pa]: the part in quadrature (energy dissipated, ``pi E'' eps0^2`` per cycle and volume)."""
        return self.complex_modulus(w).imag

    def loss_tangent(self, w):
        """``tan delta = E''/E'``: the phase lag of the strain behind the stress."""
        modulus = self.complex_modulus(w)
        return modulus.imag / modulus.real


@dataclass(frozen=True)
class ComplianceSeries:
    """Contact compliance ``C*(t) = c0 + flow t + sum_k c_k (1 - exp(-t / lambda_k))`` [1/Pa].

    ``c0 = C*(0)`` is the instantaneous (glassy) compliance; each term
    ``(c_k, lambda_k)`` is one retardation mode (lambda_k [s]); ``flow``
    [1/(Pa s)] is the steady creep of a fluid (Maxwell), the limit
    ``lambda -> inf`` of a mode with ``c/lambda = flow``. An elastic solid has
    no terms. This is the form the Prony recursions of the time stepper use
    (THEORY.md sec. 5).
    """

    c0: float
    terms: tuple = ()
    flow: float = 0.0

    @property
    def coefficients(self):
        """The ``c_k`` as an array [1/Pa]."""
        return np.array([c for c, _ in self.terms], dtype=float)

    @property
    def times(self):
        """The retardation times ``lambda_k`` as an array [s]."""
        return np.array([lam for _, lam in self.terms], dtype=float)

    @property
    def relaxed(self):
        """Long-time compliance ``C*(inf)`` [1/Pa] (infinite for a fluid)."""
        return np.inf if self.flow > 0 else self.c0 + self.coefficients.sum()

    def __call__(self, t):
        """``C*(t)`` [1/Pa] for times ``t >= 0`` [s]."""
        t = np.asarray(t, dtype=float)
        value = self.c0 + (self.flow * t if self.flow else np.zeros(t.shape))
        for c, lam in self.terms:
            value = value + c * -np.expm1(-t / lam)
        return value

    def mean(self, start, end):
        """Mean of ``C*`` over ``[start, end]`` [1/Pa] (``C*(start)`` when they coincide), elementwise."""
        start, end = np.broadcast_arrays(np.asarray(start, dtype=float), np.asarray(end, dtype=float))
        width = end - start
        safe = np.where(width > 0, width, 1.0)
        value = self.c0 + (self.flow * (start + end) / 2 if self.flow else np.zeros(start.shape))
        for c, lam in self.terms:
            # (1/w) int_a^b (1 - e^{-s/lam}) ds = 1 - (lam/w) e^{-a/lam} (1 - e^{-w/lam})
            averaged = np.where(width > 0, lam / safe * np.exp(-start / lam) * -np.expm1(-safe / lam),
                                np.exp(-start / lam))
            value = value + c * (1 - averaged)
        return value

    @property
    def linear_steps(self):
        """True when the time stepper takes the pressure linear within a step (second order).

        A material without an instantaneous compliance (``c0 = 0``, Kelvin-Voigt)
        takes it constant instead, changed at the start of the step and held
        (backward Euler, first order): there the linear scheme's error
        amplification per step tends to -1 as the step shrinks, so the contact
        rings from step to step instead of settling.
        """
        return self.c0 > 0

    def step_response(self, start, end):
        """Compliance [1/Pa] felt now per unit pressure change made during a step from ``end`` to ``start`` ago.

        The mean of ``C*`` over ``[start, end]`` for a pressure linear within the
        step, ``C*(end)`` for one changed at the step's start (see :attr:`linear_steps`).
        """
        return self.mean(start, end) if self.linear_steps else self(end)

    def step_weights(self, dt):
        """Per term, how much of a step's change of pressure a history field takes up (``step_response``'s weight).

        ``(lambda_k/dt)(1 - exp(-dt/lambda_k))`` (1 when ``dt = 0``) for linear
        steps, ``exp(-dt/lambda_k)`` otherwise, so that
        ``step_response(0, dt) = c0 + sum_k c_k (1 - weight_k)`` (+ the flow term).
        """
        times = self.times
        if not self.linear_steps:
            return np.exp(-dt / times)
        if dt <= 0:  # the limit; lambda / dt itself would overflow
            return np.ones_like(times)
        return times / dt * -np.expm1(-dt / times)

