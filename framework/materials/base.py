"""What every material gives the time stepper."""
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ComplianceSeries:
    """Contact compliance ``C*(t) = c0 + sum_k c_k (1 - exp(-t / lambda_k))`` [1/Pa].

    ``c0 = C*(0)`` is the instantaneous (glassy) compliance; each term
    ``(c_k, lambda_k)`` is one retardation mode (lambda_k [s]). An elastic
    solid has no terms. This is the form the Prony recursions of the time
    stepper use (THEORY.md sec. 5).
    """

    c0: float
    terms: tuple = ()

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
        """Long-time compliance ``C*(inf)`` [1/Pa]."""
        return self.c0 + self.coefficients.sum()

    def __call__(self, t):
        """``C*(t)`` [1/Pa] for times ``t >= 0`` [s]."""
        t = np.asarray(t, dtype=float)
        value = np.full(t.shape, self.c0)
        for c, lam in self.terms:
            value = value + c * -np.expm1(-t / lam)
        return value
