"""Hertz contact of elastic bodies: sphere on a flat and cylinder on a flat.

Closed-form results of H. Hertz, "Ueber die Beruehrung fester elastischer
Koerper", J. reine angew. Math. 92 (1882) 156-171, in the form given by
K. L. Johnson, *Contact Mechanics*, Cambridge University Press (1985),
sections 3.4 (Hertz pressure and the stresses on the axis), 4.2 (sphere)
and 4.3 (cylinder, plane strain).

Conventions: SI units, contact modulus ``E* = E / (1 - nu**2)`` (combined
modulus of both bodies), pressure positive when compressive, stresses positive
in tension, depth ``x3 >= 0`` measured into the solid.
"""
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from .._validation import check_poisson, check_positive
from ..errors import ParameterError
from .plane_strain import hertz_line_stress


@dataclass(frozen=True)
class HertzSphere:
    """Frictionless contact of a sphere with an elastic half-space.

    Parameters
    ----------
    radius : float
        Radius of the sphere (or combined radius of curvature) R [m].
    load : float
        Normal load W [N].
    contact_modulus : float
        Contact modulus E* = E / (1 - nu**2) [Pa].

    References
    ----------
    Johnson, K. L. *Contact Mechanics* (1985), sections 3.4 and 4.2.
    """

    radius: float
    load: float
    contact_modulus: float

    def __post_init__(self):
        object.__setattr__(self, "radius", check_positive(self.radius, name="radius", unit="m"))
        object.__setattr__(self, "load", check_positive(self.load, name="load", unit="N"))
        object.__setattr__(self, "contact_modulus",
                           check_positive(self.contact_modulus, name="contact_modulus", unit="Pa"))

    @classmethod
    def from_contact_radius(cls, radius, contact_radius, contact_modulus):
        """Hertz contact that has the given contact radius.

        Parameters
        ----------
        radius : float
            Radius of the sphere R [m].
        contact_radius : float
            Contact radius a [m].
        contact_modulus : float
            Contact modulus E* [Pa].

        Returns
        -------
        HertzSphere
            The contact under the load W = 4 E* a**3 / (3 R) [N].
        """
        contact_radius = check_positive(contact_radius, name="contact_radius", unit="m")
        load = 4.0 * contact_modulus * contact_radius**3 / (3.0 * radius)
        return cls(radius=radius, load=load, contact_modulus=contact_modulus)

    @property
    def contact_radius(self):
        """Contact radius a = (3 W R / (4 E*))**(1/3) [m]."""
        return (3.0 * self.load * self.radius / (4.0 * self.contact_modulus)) ** (1.0 / 3.0)

    @property
    def max_pressure(self):
        """Peak pressure p0 = 3 W / (2 pi a**2) [Pa], at the centre."""
        return 3.0 * self.load / (2.0 * np.pi * self.contact_radius**2)

    @property
    def mean_pressure(self):
        """Mean pressure W / (pi a**2) = 2 p0 / 3 [Pa]."""
        return self.load / (np.pi * self.contact_radius**2)

    @property
    def approach(self):
        """Approach of distant points (rigid-body indentation) delta = a**2 / R [m]."""
        return self.contact_radius**2 / self.radius

    def pressure(self, r):
        """Contact pressure p(r) = p0 sqrt(1 - r**2/a**2), zero outside the contact.

        Parameters
        ----------
        r : array_like
            Radial distance from the axis [m].

        Returns
        -------
        numpy.ndarray
            Pressure [Pa], positive compressive.
        """
        ratio_squared = (np.asarray(r, dtype=float) / self.contact_radius) ** 2
        return self.max_pressure * np.sqrt(np.clip(1.0 - ratio_squared, 0.0, None))

    def axis_stress(self, depth, poisson):
        """Stresses on the axis of symmetry below the centre of the contact.

        Parameters
        ----------
        depth : array_like
            Depth x3 >= 0 below the surface [m].
        poisson : float
            Poisson ratio nu of the half-space [-].

        Returns
        -------
        radial_stress : numpy.ndarray
            s_rr = s11 = s22 [Pa], tension positive:
            s_rr / p0 = -(1 + nu) (1 - zeta atan(1/zeta)) + 1 / (2 (1 + zeta**2)),
            zeta = x3 / a.
        axial_stress : numpy.ndarray
            s_zz = s33 [Pa]: s_zz / p0 = -1 / (1 + zeta**2).

        References
        ----------
        Johnson (1985), section 3.4.
        """
        poisson = check_poisson(poisson)
        zeta = np.asarray(depth, dtype=float) / self.contact_radius
        if np.any(zeta < 0.0):
            raise ParameterError(f"depth must be >= 0 [m], got minimum {zeta.min() * self.contact_radius!r}")
        # atan(1/zeta) written as arctan2(1, zeta): pi/2 at zeta = 0, no division.
        radial = -(1.0 + poisson) * (1.0 - zeta * np.arctan2(1.0, zeta)) + 0.5 / (1.0 + zeta**2)
        axial = -1.0 / (1.0 + zeta**2)
        return self.max_pressure * radial, self.max_pressure * axial

    def max_shear_on_axis(self, poisson):
        """Largest principal shear stress |s_zz - s_rr| / 2 on the axis.

        Found by a bounded scalar minimisation in zeta = x3/a on [0, 3];
        for nu = 0.3 it is 0.31002 p0 at x3 = 0.48086 a.

        Parameters
        ----------
        poisson : float
            Poisson ratio nu [-].

        Returns
        -------
        max_shear : float
            Maximum shear stress tau_max [Pa].
        depth : float
            Depth at which it occurs [m].
        """
        radius = self.contact_radius

        def negative_shear(zeta):
            radial, axial = self.axis_stress(zeta * radius, poisson)
            return -0.5 * abs(float(axial - radial))

        result = minimize_scalar(negative_shear, bounds=(0.0, 3.0), method="bounded",
                                 options={"xatol": 1e-12})
        return -float(result.fun), float(result.x) * radius


@dataclass(frozen=True)
class HertzCylinder:
    """Frictionless line contact of a cylinder with an elastic half-space (plane strain).

    Parameters
    ----------
    radius : float
        Radius of the cylinder (or combined radius of curvature) R [m].
    load_per_length : float
        Normal load per unit length W' [N/m].
    contact_modulus : float
        Contact modulus E* = E / (1 - nu**2) [Pa].

    References
    ----------
    Johnson, K. L. *Contact Mechanics* (1985), section 4.3.
    """

    radius: float
    load_per_length: float
    contact_modulus: float

    def __post_init__(self):
        object.__setattr__(self, "radius", check_positive(self.radius, name="radius", unit="m"))
        object.__setattr__(self, "load_per_length",
                           check_positive(self.load_per_length, name="load_per_length", unit="N/m"))
        object.__setattr__(self, "contact_modulus",
                           check_positive(self.contact_modulus, name="contact_modulus", unit="Pa"))

    @property
    def half_width(self):
        """Semi-width of the contact strip b = sqrt(4 W' R / (pi E*)) [m]."""
        return np.sqrt(4.0 * self.load_per_length * self.radius / (np.pi * self.contact_modulus))

    @property
    def max_pressure(self):
        """Peak pressure p0 = 2 W' / (pi b) [Pa]."""
        return 2.0 * self.load_per_length / (np.pi * self.half_width)

    def pressure(self, x):
        """Contact pressure p(x) = p0 sqrt(1 - x**2/b**2), zero outside the strip.

        Parameters
        ----------
        x : array_like
            Distance from the centre line [m].

        Returns
        -------
        numpy.ndarray
            Pressure [Pa], positive compressive.
        """
        ratio_squared = (np.asarray(x, dtype=float) / self.half_width) ** 2
        return self.max_pressure * np.sqrt(np.clip(1.0 - ratio_squared, 0.0, None))

    def stress(self, x, depth, poisson):
        """Subsurface stresses (McEwen 1949), see :func:`framework.reference.plane_strain.hertz_line_stress`.

        Parameters
        ----------
        x : array_like
            Distance from the centre line [m], across the contact.
        depth : array_like
            Depth x3 >= 0 [m]; broadcast with ``x``.
        poisson : float
            Poisson ratio nu [-].

        Returns
        -------
        numpy.ndarray
            Stress [Pa], shape ``broadcast(x, depth).shape + (6,)``, Voigt order
            xx yy zz yz xz xy with x across the contact and y along it.
        """
        return hertz_line_stress(x, depth, half_width=self.half_width, max_pressure=self.max_pressure,
                                 poisson=poisson)
