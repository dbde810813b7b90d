"""Rigid axisymmetric punches on an elastic half-space.

* Flat-ended cylindrical punch: J. Boussinesq, *Application des potentiels*
  (1885); I. N. Sneddon, Int. J. Eng. Sci. 3 (1965) 47-57; K. L. Johnson,
  *Contact Mechanics* (1985), chapter 3 (axial load and tilt).
* Flat punch with rounded edges: M. Ciavarella, D. A. Hills, G. Monno,
  "The influence of rounded edges on indentation by a flat punch",
  Proc. IMechE C 212 (1998) 319-328, and M. Ciavarella, "Indentation by
  nominally flat or conical indenters with rounded corners", Int. J. Solids
  Struct. 36 (1999) 4149-4181.

The rounded-punch formulas (load, approach, pressure) were re-derived here
from Sneddon's general solution for an axisymmetric frictionless punch of
profile h(r),

    delta = a int_0^a h'(t) / sqrt(a^2 - t^2) dt,
    W     = 2 E* int_0^a t^2 h'(t) / sqrt(a^2 - t^2) dt,
    p(r)  = -(1/pi) int_r^a F'(t) / sqrt(t^2 - r^2) dt,
    F(t)  = E* [delta - t int_0^t h'(s) / sqrt(t^2 - s^2) ds],

(the pressure formula holds with the delta above, which makes F(a) = 0 and
removes the edge singularity),

and all three agree with the expressions of THEORY.md; they are also checked
numerically in ``tests/test_reference.py`` (load = integral of the pressure,
approach = Boussinesq displacement at the centre, surface displacement
= delta - h(r) inside the contact).

Conventions: SI units, contact modulus ``E* = E / (1 - nu**2)``, pressure
positive compressive.
"""
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from .._validation import check_non_negative, check_positive
from ..errors import ParameterError


@dataclass(frozen=True)
class FlatPunch:
    """Rigid flat-ended cylindrical punch in full contact with a half-space.

    Parameters
    ----------
    radius : float
        Punch radius a [m].
    contact_modulus : float
        Contact modulus E* = E / (1 - nu**2) [Pa].

    References
    ----------
    Johnson (1985), chapter 3; Sneddon (1965).
    """

    radius: float
    contact_modulus: float

    def __post_init__(self):
        object.__setattr__(self, "radius", check_positive(self.radius, name="radius", unit="m"))
        object.__setattr__(self, "contact_modulus",
                           check_positive(self.contact_modulus, name="contact_modulus", unit="Pa"))

    def approach(self, load):
        """Indentation depth delta = W / (2 a E*) [m] under the load W [N]."""
        return load / (2.0 * self.radius * self.contact_modulus)

    def pressure(self, r, load):
        """Contact pressure p(r) = W / (2 pi a sqrt(a**2 - r**2)), zero for r >= a.

        Parameters
        ----------
        r : array_like
            Radial distance [m]; the pressure is infinite at r = a.
        load : float
            Normal load W [N].

        Returns
        -------
        numpy.ndarray
            Pressure [Pa].
        """
        r = np.asarray(r, dtype=float)
        inside = np.abs(r) < self.radius
        gap = np.where(inside, self.radius**2 - r**2, 1.0)
        return np.where(inside, load / (2.0 * np.pi * self.radius * np.sqrt(gap)), 0.0)

    def tilt(self, moment):
        """Rotation of the punch under a tilting moment, theta = 3 M / (4 E* a**3) [rad].

        Valid while the whole face stays in contact. The pressure that goes
        with it is p = (3 M / (2 pi a**3)) r cos(phi) / sqrt(a**2 - r**2).

        Parameters
        ----------
        moment : float
            Tilting moment M [N m].
        """
        return 3.0 * moment / (4.0 * self.contact_modulus * self.radius**3)


@dataclass(frozen=True)
class RoundedFlatPunch:
    """Rigid flat punch whose edges are rounded (Ciavarella 1999).

    Profile h(r) = 0 for r <= b and (r - b)**2 / (2 Rc) for r > b. With the
    contact radius a > b, the angle phi is defined by cos(phi) = b / a.

    Parameters
    ----------
    flat_radius : float
        Radius b of the flat part [m] (b = 0 gives a sphere of radius Rc).
    edge_radius : float
        Radius Rc of the rounded edge [m].
    contact_modulus : float
        Contact modulus E* = E / (1 - nu**2) [Pa].

    References
    ----------
    Ciavarella, Int. J. Solids Struct. 36 (1999) 4149-4181;
    Ciavarella, Hills & Monno, Proc. IMechE C 212 (1998) 319-328.
    """

    flat_radius: float
    edge_radius: float
    contact_modulus: float

    def __post_init__(self):
        object.__setattr__(self, "flat_radius",
                           check_non_negative(self.flat_radius, name="flat_radius", unit="m"))
        object.__setattr__(self, "edge_radius",
                           check_positive(self.edge_radius, name="edge_radius", unit="m"))
        object.__setattr__(self, "contact_modulus",
                           check_positive(self.contact_modulus, name="contact_modulus", unit="Pa"))

    def profile(self, r):
        """Punch profile h(r) [m]: 0 on the flat, (r - b)**2 / (2 Rc) beyond."""
        beyond = np.clip(np.abs(np.asarray(r, dtype=float)) - self.flat_radius, 0.0, None)
        return beyond**2 / (2.0 * self.edge_radius)

    def _angle(self, contact_radius):
        contact_radius = check_positive(contact_radius, name="contact_radius", unit="m")
        if contact_radius < self.flat_radius:
            raise ParameterError(f"contact_radius must be >= flat_radius = {self.flat_radius!r} [m], "
                                 f"got {contact_radius!r}")
        return np.arccos(self.flat_radius / contact_radius)

    def load(self, contact_radius):
        """Load for a contact radius a >= b [N].

        W = (E* a**3 / (3 Rc)) (3 sin(phi) + sin(phi)**3 - 3 phi cos(phi)).
        """
        phi = self._angle(contact_radius)
        return (self.contact_modulus * contact_radius**3 / (3.0 * self.edge_radius)
                * (3.0 * np.sin(phi) + np.sin(phi)**3 - 3.0 * phi * np.cos(phi)))

    def approach(self, contact_radius):
        """Indentation depth delta = (a**2 / Rc) (sin(phi) - phi cos(phi)) [m]."""
        phi = self._angle(contact_radius)
        return contact_radius**2 / self.edge_radius * (np.sin(phi) - phi * np.cos(phi))

    def contact_radius(self, load):
        """Contact radius a >= b under the load W [N], by root finding on ``load``.

        Returns b for a zero load.
        """
        load = check_non_negative(load, name="load", unit="N")
        if load == 0.0:
            return self.flat_radius
        # Start from b plus the Hertz radius and double until the load is bracketed.
        hertz_radius = (3.0 * load * self.edge_radius / (4.0 * self.contact_modulus)) ** (1.0 / 3.0)
        upper = self.flat_radius + hertz_radius
        while self.load(upper) < load:
            upper *= 2.0
        lower = max(self.flat_radius, np.finfo(float).tiny)
        return brentq(lambda radius: self.load(radius) - load, lower, upper, xtol=1e-15 * upper, rtol=1e-15)

    def pressure(self, r, contact_radius):
        """Contact pressure [Pa] for the contact radius a.

        p(r) = (E* / (pi Rc)) int_{max(r, b)}^a [2 sqrt(t**2 - b**2) - b arccos(b/t)]
        / sqrt(t**2 - r**2) dt, zero for r >= a. It is finite everywhere and
        vanishes like sqrt(a - r) at the edge.

        The integral is evaluated by adaptive quadrature after a change of
        variable that makes the integrand smooth: for r >= b,
        t**2 = r**2 + u**2 (dt / sqrt(t**2 - r**2) = du / t) removes the
        inverse square root at t = r; for r < b, t**2 = b**2 + v**2 removes
        the square-root behaviour of sqrt(t**2 - b**2) at t = b, leaving
        (2 v - b arccos(b/t)) v / (t sqrt(b**2 - r**2 + v**2)) dv.

        Parameters
        ----------
        r : array_like
            Radial distance [m].
        contact_radius : float
            Contact radius a >= b [m].

        Returns
        -------
        numpy.ndarray
            Pressure [Pa], positive compressive.
        """
        self._angle(contact_radius)
        flat, radius = self.flat_radius, contact_radius

        def kernel(root):
            """2 sqrt(t**2 - b**2) - b arccos(b/t) as a function of root = sqrt(t**2 - b**2)."""
            return 2.0 * root - flat * np.arctan2(root, flat)

        def outside_flat(position):
            def integrand(u):
                return kernel(np.sqrt(position**2 - flat**2 + u**2)) / np.sqrt(position**2 + u**2)

            return quad(integrand, 0.0, np.sqrt(radius**2 - position**2), epsabs=0.0, epsrel=1e-12,
                        limit=200)[0]

        def on_flat(position):
            def integrand(v):
                t = np.sqrt(flat**2 + v**2)
                return kernel(v) * v / (t * np.sqrt(flat**2 - position**2 + v**2))

            return quad(integrand, 0.0, np.sqrt(radius**2 - flat**2), epsabs=0.0, epsrel=1e-12,
                        limit=200)[0]

        def one_point(position):
            position = abs(position)
            if position >= radius:
                return 0.0
            return on_flat(position) if position < flat else outside_flat(position)

        values = np.vectorize(one_point, otypes=[float])(np.asarray(r, dtype=float))
        return self.contact_modulus / (np.pi * self.edge_radius) * values
