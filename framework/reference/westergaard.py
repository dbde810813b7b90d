"""Contact of a one-dimensional wavy surface with an elastic half-space.

H. M. Westergaard, "Bearing pressures and cracks", J. Appl. Mech. 6 (1939)
A49-A53; K. L. Johnson, *Contact Mechanics* (1985), section 13.2, plane strain.

The rigid surface h(x) = g (1 - cos(2 pi x / lambda)) has its lowest points
(the crests pressed first into the solid) at x = 0 (mod lambda), so the
pressure is largest there:

* full contact (pbar >= p*): p(x) = pbar + p* cos(2 pi x / lambda), whose
  Fourier harmonic gives the surface displacement u3 = 2 p_hat / (E* |k|)
  = g cos(2 pi x / lambda) = const - h(x);
* partial contact (pbar < p*), contact on |x| < a (mod lambda) with
  sin(pi a / lambda)**2 = pbar / p*:
  p(x) = 2 pbar cos(pi x / lambda) sqrt(sin(pi a/lambda)**2 - sin(pi x/lambda)**2)
  / sin(pi a / lambda)**2.

Conventions: SI units, contact modulus ``E* = E / (1 - nu**2)``, pressure
positive compressive.
"""
from dataclasses import dataclass

import numpy as np

from .._validation import check_non_negative, check_positive


@dataclass(frozen=True)
class Westergaard:
    """Periodic sinusoidal (wavy) surface pressed onto an elastic half-space.

    Parameters
    ----------
    amplitude : float
        Amplitude g of the profile h(x) = g (1 - cos(2 pi x / lambda)) [m]
        (peak-to-valley height 2 g).
    wavelength : float
        Wavelength lambda [m].
    contact_modulus : float
        Contact modulus E* = E / (1 - nu**2) [Pa].

    References
    ----------
    Westergaard (1939); Johnson (1985), section 13.2.
    """

    amplitude: float
    wavelength: float
    contact_modulus: float

    def __post_init__(self):
        object.__setattr__(self, "amplitude", check_positive(self.amplitude, name="amplitude", unit="m"))
        object.__setattr__(self, "wavelength", check_positive(self.wavelength, name="wavelength", unit="m"))
        object.__setattr__(self, "contact_modulus",
                           check_positive(self.contact_modulus, name="contact_modulus", unit="Pa"))

    @property
    def full_contact_pressure(self):
        """Mean pressure p* = pi E* g / lambda [Pa] above which contact is complete."""
        return np.pi * self.contact_modulus * self.amplitude / self.wavelength

    def profile(self, x):
        """Surface height h(x) = g (1 - cos(2 pi x / lambda)) [m]."""
        return self.amplitude * (1.0 - np.cos(2.0 * np.pi * np.asarray(x, dtype=float) / self.wavelength))

    def contact_half_width(self, mean_pressure):
        """Half-width a of each contact strip [m].

        a = (lambda / pi) asin(sqrt(pbar / p*)) for pbar < p*, else lambda / 2.

        Parameters
        ----------
        mean_pressure : float
            Mean pressure pbar over a wavelength [Pa].
        """
        mean_pressure = check_non_negative(mean_pressure, name="mean_pressure", unit="Pa")
        ratio = mean_pressure / self.full_contact_pressure
        if ratio >= 1.0:
            return 0.5 * self.wavelength
        return self.wavelength / np.pi * np.arcsin(np.sqrt(ratio))

    def pressure(self, x, mean_pressure):
        """Contact pressure p(x) [Pa], periodic in x, largest at x = 0.

        Parameters
        ----------
        x : array_like
            Position along the wave [m].
        mean_pressure : float
            Mean pressure pbar over a wavelength [Pa].

        Returns
        -------
        numpy.ndarray
            Pressure [Pa]: pbar + p* cos(2 pi x / lambda) in full contact,
            Westergaard's partial-contact distribution otherwise (zero in the gaps).
        """
        mean_pressure = check_non_negative(mean_pressure, name="mean_pressure", unit="Pa")
        phase = np.pi * np.asarray(x, dtype=float) / self.wavelength
        full = self.full_contact_pressure
        if mean_pressure >= full:
            return mean_pressure + full * np.cos(2.0 * phase)
        sin_squared_edge = mean_pressure / full
        if sin_squared_edge == 0.0:
            return np.zeros_like(phase)
        # |cos(phase)| keeps the period lambda (cos(phase) alone has period 2 lambda).
        root = np.sqrt(np.clip(sin_squared_edge - np.sin(phase)**2, 0.0, None))
        return 2.0 * mean_pressure * np.abs(np.cos(phase)) * root / sin_squared_edge
