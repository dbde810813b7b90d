"""Isotropic linear elastic solid."""
from dataclasses import dataclass

import numpy as np

from .._validation import check_poisson, check_quantity
from .anisotropic import isotropic_tensor
from .base import ComplianceSeries, DynamicModuli, check_frequencies, refuse_shift


@dataclass(frozen=True)
class Elastic(DynamicModuli):
    """Isotropic linear elastic material.

    Parameters
    ----------
    young : float
        Young's modulus [Pa], between 1e-3 and 1e15 (``framework._validation.LIMITS``).
    poisson : float
        Poisson ratio, in (-1, 0.5].
    """

    young: float
    poisson: float

    def __post_init__(self):
        object.__setattr__(self, "young", check_quantity(self.young, name="young", unit="Pa"))
        object.__setattr__(self, "poisson", check_poisson(self.poisson))

    def at(self, temperature, shift=None):
        """Refused: an elastic solid has no relaxation times for a time-temperature shift to scale.

        Raises
        ------
        ParameterError
            Always, naming the temperature received: give the ``young`` and ``poisson`` of
            the solid at that temperature instead.
        """
        refuse_shift(self, temperature, shift, "an elastic solid has no relaxation times to shift; for the solid "
                     "at another temperature give its young and poisson at that temperature")

    @property
    def contact_modulus(self):
        """Plane-strain modulus ``E* = E / (1 - nu^2)`` against a rigid body [Pa]."""
        return self.young / (1.0 - self.poisson**2)

    @property
    def stiffness_tensor(self):
        """Fourth-order stiffness tensor ``C_ijkl`` [Pa], shape (3, 3, 3, 3) (none for ``poisson = 0.5``)."""
        return isotropic_tensor(self.young, self.poisson)

    def relaxation(self, t):
        """Relaxation modulus ``E(t) = E`` [Pa]."""
        return np.full(np.shape(t), self.young)

    def creep(self, t):
        """Creep compliance ``J(t) = 1/E`` [1/Pa]."""
        return np.full(np.shape(t), 1.0 / self.young)

    def complex_modulus(self, w):
        """``E*(w) = E`` [Pa] at ``w > 0`` [rad/s]: no loss."""
        return np.full(check_frequencies(w).shape, self.young + 0j)

    def contact_compliance(self):
        """The contact compliance ``C* = (1 - nu^2)/E`` as a series without terms."""
        return ComplianceSeries(c0=1.0 / self.contact_modulus)
