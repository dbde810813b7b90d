"""Rigid sphere on a linear viscoelastic half-space: Lee & Radok, Ting and Graham.

* Non-decreasing contact radius: E. H. Lee and J. R. M. Radok, "The contact
  problem for viscoelastic bodies", J. Appl. Mech. 27 (1960) 438-444.
* Contact radius with one maximum (loading, then a receding contact):
  T. C. T. Ting, "The contact stresses between a rigid indenter and a
  viscoelastic half-space", J. Appl. Mech. 33 (1966) 845-854; G. A. C. Graham,
  "The contact problem in the linear theory of viscoelasticity when the time
  dependent contact area has any number of maxima and minima",
  Int. J. Eng. Sci. 5 (1967) 495-514.
* Abel-transform representation of an axisymmetric frictionless contact:
  I. N. Sneddon, Int. J. Eng. Sci. 3 (1965) 47-57.

Conventions
-----------
SI units; pressure positive compressive; constant Poisson ratio ``nu``. The
material is given by plain callables of the time [s] that accept numpy arrays:
``relaxation(t)`` -> tension relaxation modulus E(t) [Pa] and ``creep(t)`` ->
tension creep compliance J(t) [1/Pa]. Contact relaxation modulus
``E*(t) = E(t) / (1 - nu**2)``, contact creep compliance
``C*(t) = (1 - nu**2) J(t)``; they are inverse in the Stieltjes sense,
``int_0^t E*(t - s) dC*(s) = 1`` (``dC*`` including its jump ``C*(0)`` at 0).
Every history starts at t = 0 from the undeformed, unloaded state. A history
function evaluated at t = 0 gives the value just *after* a possible jump at
t = 0 (a step of height W0 is ``lambda t: W0 * np.ones_like(t)``).

Derivation of the receding phase (used by :func:`ting_contact_radius`)
-----------------------------------------------------------------------
Sneddon's representation, for a pressure p(r) on r <= a and unit contact
compliance: ``g(x) = int_x^a p(r) r dr / sqrt(r**2 - x**2)`` (zero for
x >= a), surface displacement ``u(r) = (4/pi) int_0^r g(x) dx / sqrt(r**2 - x**2)``
at *every* r, load ``W = 4 int_0^a g(x) dx``. Both transforms act on space
only, so on the viscoelastic body ``G(x, t) = int_0^t C*(t - s) d_s g(x, s)``
replaces ``g`` in the displacement. Abel inversion of ``u = delta - r**2/(2R)``
over the contact gives, for each x < a(t), ``G(x, t) = (delta(t) - x**2/R)/2``;
for x > a(t), ``g(x, t) = 0``. The problem thus separates into one history per
x: a point x < a(t) entered the contact at t_x (a(t_x) = x) and has stayed in
it, so ``g(x, t) = (1/2) int_{t_x}^{t} E*(t - s) d delta(s)``. Bounded pressure
at the edge, g(a(t)-, t) = 0, gives delta = a**2/R while a grows (Lee & Radok)
and, with a(t) rising to its maximum at t_m and then falling, and t1(t) <= t_m
the loading time at which a(t1) = a(t),

    int_{t1(t)}^{t} E*(t - s) d delta(s) = 0          (t > t_m).

Splitting the integral for g(x, t) at t1(t) then leaves
``g(x, t) = int_0^{t1(t)} E*(t - s) d_s (a(s)**2 - x**2)_+ / (2R)``:
the pressure and the load are the Lee & Radok integrals cut at t1(t),

    W(t) = (4 / (3R)) int_0^{t1(t)} E*(t - s) d[a(s)**3](s)   (Graham 1967),

and the approach follows by inverting the equation above with C*:

    delta(t) = a(t_m)**2/R + int_{t_m}^{t} C*(t - s) dH(s),
    H(s) = -(1/R) int_{t1(s)}^{t_m} E*(s - v) d[a(v)**2](v).

With constant E* these reduce to Hertz at every time. The formulas are checked
in ``tests/test_reference_viscoelastic.py`` against an independent
time-stepping solution of the contact problem (rings, Boussinesq kernels,
hereditary sum, complementarity), not only against themselves.
"""
from dataclasses import dataclass
from typing import Optional

import numpy as np
from numpy.polynomial import chebyshev as cheb
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import dawsn

from .._validation import check_non_negative, check_poisson, check_positive, check_positive_int
from ..errors import ParameterError

__all__ = ["TingSolution", "lee_radok_load_for_approach", "lee_radok_ramp_load", "lee_radok_step_approach_load",
           "lee_radok_step_load", "lee_radok_step_load_pressure", "ting_contact_radius"]


# --------------------------------------------------------------------------- small helpers

def _check_callable(function, *, name):
    if not callable(function):
        raise ParameterError(f"{name} must be a callable of the time [s], got {type(function).__name__}")
    return function


def _times(t, *, name="t"):
    """Times as a float array, finite and >= 0 [s]."""
    try:
        times = np.asarray(t, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name} must be real times [s], got {type(t).__name__}") from exc
    if not np.all(np.isfinite(times)) or np.any(times < 0.0):
        raise ParameterError(f"{name} must be finite and >= 0 [s], got minimum {np.min(times)!r}")
    return times


def _scalar(function, x):
    return float(np.asarray(function(np.float64(x)), dtype=float))


def _invert_non_decreasing(function, target, upper):
    """Smallest-error s in [0, upper] with function(s) = target, function non-decreasing.

    brentq also converges to the location of a jump that spans ``target``,
    which is what a Stieltjes integral over the values needs.
    """
    low = function(0.0) - target
    if low >= 0.0:
        return 0.0
    high = function(upper) - target
    if high <= 0.0:
        return upper
    return brentq(lambda s: function(s) - target, 0.0, upper, xtol=1e-15 * upper, rtol=4.0 * np.finfo(float).eps,
                  maxiter=200)


def _stieltjes_over_values(kernel, history, t, value_at_zero):
    """int_0^t kernel(t - s) d history(s) for a non-decreasing history, jump at 0 included.

    The integral is taken over the values y of the history, s(y) found by
    inversion, so that it is an ordinary integral of a bounded function:
    int_{y(0+)}^{y(t)} kernel(t - s(y)) dy. This needs no derivative and no
    special care where history'(s) is singular (a(s) crossing r, delta**1.5
    at s = 0, ...).
    """
    jump = kernel(t) * value_at_zero
    value_at_t = history(t)
    if not value_at_t > value_at_zero or t == 0.0:
        return jump
    scale = kernel(0.0) * (value_at_t - value_at_zero)
    smooth, _ = quad(lambda y: kernel(t - _invert_non_decreasing(history, y, t)), value_at_zero, value_at_t,
                     epsabs=1e-14 * scale, epsrel=1e-12, limit=400)
    return jump + smooth


# --------------------------------------------------------------------------- Lee & Radok

def lee_radok_step_load(t, radius, load, creep, poisson):
    """Contact radius and approach of a rigid sphere under a step load (Lee & Radok 1960).

    The contact radius grows (creep), so Lee & Radok's correspondence holds:
    ``a(t)**3 = 3 R W0 C*(t) / 4``, ``delta(t) = a(t)**2 / R``.

    Parameters
    ----------
    t : array_like
        Times after the application of the load, >= 0 [s] (t = 0 gives the
        instantaneous, glassy response).
    radius : float
        Sphere radius R [m].
    load : float
        Step load W0 applied at t = 0 [N].
    creep : callable
        Tension creep compliance J(t) [1/Pa], accepting numpy arrays.
    poisson : float
        Poisson ratio nu [-], constant in time.

    Returns
    -------
    contact_radius : numpy.ndarray
        a(t) [m].
    approach : numpy.ndarray
        delta(t) [m].

    References
    ----------
    Lee & Radok (1960), J. Appl. Mech. 27, 438-444.
    """
    times = _times(t)
    radius = check_positive(radius, name="radius", unit="m")
    load = check_positive(load, name="load", unit="N")
    poisson = check_poisson(poisson)
    creep = _check_callable(creep, name="creep")
    compliance = (1.0 - poisson**2) * np.asarray(creep(times), dtype=float)
    if np.any(~np.isfinite(compliance)) or np.any(compliance <= 0.0):
        raise ParameterError(f"creep(t) must be finite and > 0 [1/Pa], got minimum {np.min(compliance)!r}")
    contact_radius = np.cbrt(0.75 * radius * load * compliance)
    return contact_radius, contact_radius**2 / radius


def lee_radok_step_load_pressure(r, t, radius, load, relaxation, creep, poisson):
    """Contact pressure under a step load, by Lee & Radok's hereditary integral.

    ``p(r, t) = (2 / (pi R)) int_0^t E*(t - s) d/ds sqrt(a(s)**2 - r**2)_+ ds``
    with ``a(s)**3 = 3 R W0 C*(s) / 4``. The Stieltjes integral holds the jump
    ``E*(t) sqrt(a(0+)**2 - r**2)_+`` and is evaluated over the values
    ``y = sqrt(a(s)**2 - r**2)`` (``s(y)`` from the creep compliance by root
    finding), which removes the inverse-square-root singularity of d/ds where
    a(s) crosses r. The profile is *not* the Hertz profile of the current
    contact radius: points that entered the contact late carry less relaxed
    pressure.

    Parameters
    ----------
    r : array_like
        Radial distance from the axis, >= 0 [m].
    t : float
        Time after the application of the load, >= 0 [s] (t = 0: glassy Hertz).
    radius : float
        Sphere radius R [m].
    load : float
        Step load W0 [N].
    relaxation : callable
        Tension relaxation modulus E(t) [Pa].
    creep : callable
        Tension creep compliance J(t) [1/Pa] of the same material.
    poisson : float
        Poisson ratio nu [-].

    Returns
    -------
    numpy.ndarray
        Pressure p(r, t) [Pa], zero for r >= a(t); same shape as ``r``.

    References
    ----------
    Lee & Radok (1960).
    """
    radii = np.asarray(r, dtype=float)
    if not np.all(np.isfinite(radii)) or np.any(radii < 0.0):
        raise ParameterError(f"r must be finite and >= 0 [m], got minimum {np.min(radii)!r}")
    t = check_non_negative(t, name="t", unit="s")
    radius = check_positive(radius, name="radius", unit="m")
    load = check_positive(load, name="load", unit="N")
    poisson = check_poisson(poisson)
    relaxation = _check_callable(relaxation, name="relaxation")
    creep = _check_callable(creep, name="creep")
    factor = 1.0 - poisson**2
    cube_per_compliance = 0.75 * radius * load * factor  # a**3 = this * J(s)

    def contact_radius(s):
        return np.cbrt(cube_per_compliance * _scalar(creep, s))

    def kernel(lag):
        return _scalar(relaxation, max(lag, 0.0))

    pressure = np.zeros(radii.shape)
    for index, radial in np.ndenumerate(radii):
        radial_squared = radial * radial

        def history(s, radial_squared=radial_squared):
            return np.sqrt(max(contact_radius(s) ** 2 - radial_squared, 0.0))

        pressure[index] = _stieltjes_over_values(kernel, history, t, history(0.0))
    return 2.0 / (np.pi * radius * factor) * pressure


def lee_radok_step_approach_load(t, radius, approach, relaxation, poisson):
    """Load needed to hold a step approach delta0 applied at t = 0 (relaxation test).

    ``W(t) = (4 sqrt(R) / 3) E*(t) delta0**1.5``: the contact radius stays
    ``sqrt(R delta0)`` and the load relaxes with the material.

    Parameters
    ----------
    t : array_like
        Times >= 0 [s].
    radius : float
        Sphere radius R [m].
    approach : float
        Step approach delta0 [m].
    relaxation : callable
        Tension relaxation modulus E(t) [Pa].
    poisson : float
        Poisson ratio nu [-].

    Returns
    -------
    numpy.ndarray
        Load W(t) [N].

    References
    ----------
    Lee & Radok (1960).
    """
    times = _times(t)
    radius = check_positive(radius, name="radius", unit="m")
    approach = check_positive(approach, name="approach", unit="m")
    poisson = check_poisson(poisson)
    relaxation = _check_callable(relaxation, name="relaxation")
    modulus = np.asarray(relaxation(times), dtype=float) / (1.0 - poisson**2)
    return 4.0 * np.sqrt(radius) / 3.0 * modulus * approach**1.5


def lee_radok_load_for_approach(t, approach_function, radius, relaxation, poisson):
    """Load history for a prescribed non-decreasing approach (Lee & Radok 1960).

    ``W(t) = (4 sqrt(R) / 3) int_0^t E*(t - s) d[delta**1.5](s)``, a Stieltjes
    integral that holds a jump of delta at t = 0 (``approach_function(0)`` is
    delta(0+)) and any later jump. It is computed over the values
    ``y = delta**1.5`` by adaptive quadrature, ``s(y)`` by root finding, so
    that no derivative of delta is needed (relative accuracy about 1e-11).

    Parameters
    ----------
    t : array_like
        Times >= 0 [s].
    approach_function : callable
        delta(s) [m], non-decreasing, >= 0, of a scalar time [s].
    radius : float
        Sphere radius R [m].
    relaxation : callable
        Tension relaxation modulus E(t) [Pa].
    poisson : float
        Poisson ratio nu [-].

    Returns
    -------
    numpy.ndarray
        Load W(t) [N], same shape as ``t``.

    Raises
    ------
    ParameterError
        If the approach decreases (the contact would recede: see
        :func:`ting_contact_radius`) or is negative.

    References
    ----------
    Lee & Radok (1960).
    """
    times = _times(t)
    radius = check_positive(radius, name="radius", unit="m")
    poisson = check_poisson(poisson)
    relaxation = _check_callable(relaxation, name="relaxation")
    approach_function = _check_callable(approach_function, name="approach_function")
    if times.size:
        probe = np.linspace(0.0, float(np.max(times)), 257)
        sampled = np.array([_scalar(approach_function, s) for s in probe])
        if np.any(~np.isfinite(sampled)) or np.any(sampled < 0.0):
            raise ParameterError(f"approach_function must be finite and >= 0 [m], got {np.min(sampled)!r}")
        decrease = np.nonzero(np.diff(sampled) < -1e-12 * np.max(np.abs(sampled)))[0]
        if decrease.size:
            raise ParameterError(
                f"approach_function must be non-decreasing (Lee & Radok), but it decreases after "
                f"t = {probe[decrease[0]]!r} s; a receding contact needs ting_contact_radius")

    def history(s):
        return _scalar(approach_function, s) ** 1.5

    def kernel(lag):
        return _scalar(relaxation, max(lag, 0.0))

    start = history(0.0)
    load = np.array([_stieltjes_over_values(kernel, history, float(time), start) for time in times.ravel()])
    return (4.0 * np.sqrt(radius) / (3.0 * (1.0 - poisson**2)) * load).reshape(times.shape)


def lee_radok_ramp_load(t, radius, rate, e_inf, terms, poisson):
    """Load for a constant indentation rate delta = v t on a Prony (Wiechert) material.

    With ``E(t) = E_inf + sum_i E_i exp(-t/tau_i)`` the Lee & Radok integral
    ``W = 2 sqrt(R) v**1.5 / (1 - nu**2) int_0^t E(t - s) sqrt(s) ds`` is, term
    by term (substitute s = tau y**2, integrate by parts),

        W(t) = 2 sqrt(R) v**1.5 / (1 - nu**2) [ (2/3) E_inf t**1.5
               + sum_i E_i tau_i**1.5 (x_i - F(x_i)) ],   x_i = sqrt(t / tau_i),

    F the Dawson function ``F(x) = exp(-x**2) int_0^x exp(y**2) dy``
    (Abramowitz & Stegun 7.1.17). This is the form of THEORY.md; it agrees with
    :func:`lee_radok_load_for_approach` to 1e-11.

    Parameters
    ----------
    t : array_like
        Times >= 0 [s].
    radius : float
        Sphere radius R [m].
    rate : float
        Indentation rate v [m/s].
    e_inf : float
        Long-time modulus E_inf [Pa].
    terms : sequence of (float, float)
        Prony terms (E_i [Pa], tau_i [s]).
    poisson : float
        Poisson ratio nu [-].

    Returns
    -------
    numpy.ndarray
        Load W(t) [N].

    References
    ----------
    Lee & Radok (1960).
    """
    times = _times(t)
    radius = check_positive(radius, name="radius", unit="m")
    rate = check_positive(rate, name="rate", unit="m/s")
    e_inf = check_non_negative(e_inf, name="e_inf", unit="Pa")
    poisson = check_poisson(poisson)
    bracket = 2.0 / 3.0 * e_inf * times**1.5
    for number, term in enumerate(terms):
        try:
            modulus, tau = term
        except (TypeError, ValueError) as exc:
            raise ParameterError(f"terms[{number}] must be a pair (E_i [Pa], tau_i [s]), got {term!r}") from exc
        modulus = check_non_negative(modulus, name=f"terms[{number}] modulus", unit="Pa")
        tau = check_positive(tau, name=f"terms[{number}] tau", unit="s")
        x = np.sqrt(times / tau)
        bracket = bracket + modulus * tau**1.5 * (x - dawsn(x))
    return 2.0 * np.sqrt(radius) * rate**1.5 / (1.0 - poisson**2) * bracket


# --------------------------------------------------------------------------- spectral panels (Ting)
#
# Histories are represented on the intervals ("panels") of the time grid by
# Chebyshev interpolation at NODES + 1 Lobatto points in a panel variable u in
# [-1, 1]. Stieltjes integrals int f dG over a panel are int f (dG/du) du, with
# dG/du from differentiating the interpolant and the integral by Clenshaw-Curtis
# weights: spectrally accurate when the histories are smooth inside each panel.
# The first panel, and a panel at whose end the load vanishes, use a cubic map
# s = lo + h ((u+1)/2)**3 (resp. s = hi - h ((1-u)/2)**3): a**2 ~ A**(2/3) with
# A ~ s there, which the cubic map makes analytic in u.

_NODES = 16
_LINEAR, _CLUSTER_LEFT, _CLUSTER_RIGHT = 0, 1, 2


class _Spectral:
    """Lobatto nodes and the matrices that act on values at them."""

    def __init__(self, order):
        self.order = order
        self.u = -np.cos(np.pi * np.arange(order + 1) / order)
        self.u[0], self.u[-1] = -1.0, 1.0
        self.to_coefficients = np.linalg.inv(cheb.chebvander(self.u, order))
        self.derivative = cheb.chebvander(self.u, order - 1) @ cheb.chebder(self.to_coefficients, axis=0)
        antiderivative = cheb.chebvander(self.u, order + 1) @ cheb.chebint(self.to_coefficients, lbnd=-1, axis=0)
        self.weights = antiderivative[-1].copy()
        # nodes of [-1, u_i], for the integral from the start of a panel to its i-th node
        self.sub = -1.0 + np.outer(self.u + 1.0, self.u + 1.0) / 2.0
        self.sub_interpolation = np.stack([cheb.chebvander(row, order) @ self.to_coefficients
                                           for row in self.sub])


_SPECTRAL = _Spectral(_NODES)


def _panel_map(lo, hi, kind, u):
    x = 0.5 * (u + 1.0)
    length = hi - lo
    return np.where(kind == _CLUSTER_LEFT, lo + length * x**3,
                    np.where(kind == _CLUSTER_RIGHT, hi - length * (1.0 - x) ** 3, lo + length * x))


class _Panels:
    """Intervals [lo, hi] of a time grid, each with a map and its Lobatto nodes."""

    def __init__(self, breaks, kinds):
        self.breaks = np.asarray(breaks, dtype=float)
        self.lo, self.hi = self.breaks[:-1], self.breaks[1:]
        self.kinds = np.asarray(kinds, dtype=int)
        self.nodes = _panel_map(self.lo[:, None], self.hi[:, None], self.kinds[:, None], _SPECTRAL.u[None, :])
        self.nodes[:, 0], self.nodes[:, -1] = self.lo, self.hi

    def __len__(self):
        return self.lo.size

    def derivative(self, values):
        """d/du of the interpolant, at the nodes; values of shape (panels, nodes)."""
        return values @ _SPECTRAL.derivative.T

    def hereditary(self, kernel, rate):
        """int_{0+}^{s} kernel(s - v) dG(v) at every node s; ``rate`` = dG/du at the nodes.

        Whole panels before the node's panel by Clenshaw-Curtis, the part of
        its own panel up to the node on mapped sub-nodes (the kernel is never
        evaluated at a negative time).
        """
        count, size = rate.shape
        spectral = _SPECTRAL
        sub_times = _panel_map(self.lo[:, None, None], self.hi[:, None, None], self.kinds[:, None, None],
                               spectral.sub[None, :, :])
        sub_rate = np.einsum("ilj,kj->kil", spectral.sub_interpolation, rate)
        lag = np.maximum(self.nodes[:, :, None] - sub_times, 0.0)
        partial = 0.5 * (spectral.u + 1.0)[None, :] * np.einsum(
            "kil,l->ki", np.asarray(kernel(lag), dtype=float) * sub_rate, spectral.weights)

        flat_nodes = self.nodes.ravel()
        weighted = (rate * spectral.weights[None, :]).ravel()
        column_panel = np.repeat(np.arange(count), size)
        whole = np.empty(count * size)
        chunk = max(1, 4_000_000 // max(1, count * size))
        for start in range(0, count * size, chunk):
            stop = min(start + chunk, count * size)
            row_panel = (np.arange(start, stop) // size)[:, None]
            mask = column_panel[None, :] < row_panel
            lag = np.where(mask, flat_nodes[start:stop, None] - flat_nodes[None, :], 0.0)
            values = np.where(mask, np.asarray(kernel(lag), dtype=float), 0.0)
            whole[start:stop] = values @ weighted
        return whole.reshape(count, size) + partial


@dataclass(frozen=True)
class TingSolution:
    """Contact radius and approach of a rigid sphere whose contact radius has one maximum.

    Attributes
    ----------
    time : numpy.ndarray
        Times t [s], as given.
    load : numpy.ndarray
        Load W(t) [N].
    contact_radius : numpy.ndarray
        Contact radius a(t) [m]; 0 once the load has fallen to zero.
    approach : numpy.ndarray
        Approach delta(t) [m]; NaN after the contact is lost.
    loading_time : numpy.ndarray
        t1(t) [s]: the time <= t_m of the loading phase at which the contact
        radius had the value a(t) (t1 = t while the contact grows; 0 when
        a(t) <= a(0+)); NaN after the contact is lost.
    max_time : float or None
        t_m [s], time of the maximum contact radius; None if the contact
        radius does not decrease within the time span.
    max_contact_radius : float
        a(t_m) [m] (the last contact radius if it never decreases).
    """

    time: np.ndarray
    load: np.ndarray
    contact_radius: np.ndarray
    approach: np.ndarray
    loading_time: np.ndarray
    max_time: Optional[float]
    max_contact_radius: float


def _first_maximum(panels, values):
    """Time and value of the first maximum of a history given at the panel nodes, or None."""
    flat = np.concatenate([values[0], values[1:, 1:].ravel()])
    scale = np.max(np.abs(flat))
    if scale == 0.0:
        return None
    peak = np.maximum.accumulate(flat)
    drops = np.nonzero(flat < peak - 1e-10 * scale)[0]
    if drops.size == 0:
        return None
    best = peak[drops[0] - 1]
    top = np.nonzero(flat[:drops[0]] >= best - 1e-13 * scale)[0][-1]
    size = _NODES
    if top == 0:
        places = [(0, 0)]
    else:
        panel, node = (top - 1) // size, (top - 1) % size + 1
        places = [(panel, node)] + ([(panel + 1, 0)] if node == size and panel + 1 < len(panels) else [])
    time, value = float(panels.nodes[places[0]]), float(flat[top])
    for panel, node in places:
        coefficients = _SPECTRAL.to_coefficients @ values[panel]
        low = _SPECTRAL.u[max(node - 1, 0)]
        high = _SPECTRAL.u[min(node + 1, size)]
        for root in cheb.chebroots(cheb.chebder(coefficients)):
            if abs(root.imag) < 1e-12 and low <= root.real <= high:
                candidate = float(cheb.chebval(root.real, coefficients))
                if candidate > value:
                    value = candidate
                    time = float(_panel_map(panels.lo[panel], panels.hi[panel], panels.kinds[panel], root.real))
    return time, value


def ting_contact_radius(t, load_function, radius, creep, relaxation, poisson, *, subdivisions=1):
    """Contact radius (and approach) of a rigid sphere under a load that rises, then falls.

    Loading (a(t) non-decreasing, Lee & Radok 1960):
    ``a(t)**3 = (3R/4) int_0^t C*(t - s) dW(s)``, ``delta = a**2 / R``; its
    first maximum is t_m. Receding contact, t > t_m (Ting 1966, Graham 1967):
    a(t) = a(t1) where t1 <= t_m solves

        W(t) = (4 / (3R)) int_0^{t1} E*(t - s) d[a(s)**3](s),

    (the right-hand side grows with t1; below the jump at s = 0 it is
    ``E*(t) 4 a**3 / (3R)``, which gives a -> 0 as W -> 0), and

        delta(t) = a(t_m)**2 / R + int_{t_m}^{t} C*(t - s) dH(s),
        H(s) = -(1/R) int_{t1(s)}^{t_m} E*(s - v) d[a(v)**2](v),

    derived in the module docstring. Numerically: Chebyshev interpolation on
    the intervals of ``t`` (17 nodes each, first interval graded), t_m by the
    roots of the interpolant's derivative and inserted as a grid point, t1(t)
    by root finding on the cumulative integral; spectrally accurate (1e-10
    and better) for histories that are smooth between consecutive times of
    ``t`` on a grid that resolves the retardation and relaxation times.

    Parameters
    ----------
    t : array_like
        Increasing times >= 0 [s]. Kinks of the load history must lie on them;
        a step may only occur at t = 0.
    load_function : callable
        W(s) [N] accepting numpy arrays; W(0) is the load just after t = 0.
        The contact radius it produces must have a single maximum; once the
        load has fallen to zero it must stay <= 0 (the contact is lost).
    radius : float
        Sphere radius R [m].
    creep : callable
        Tension creep compliance J(t) [1/Pa], accepting numpy arrays.
    relaxation : callable
        Tension relaxation modulus E(t) [Pa] of the same material.
    poisson : float
        Poisson ratio nu [-].
    subdivisions : int, optional
        Number of panels per interval of ``t`` (default 1). Raise it when the
        intervals are much longer than the shortest relaxation or retardation
        time; the result is unchanged (to ~1e-12) once the grid is fine enough.

    Returns
    -------
    TingSolution
        a(t), delta(t), t1(t), t_m at the times ``t``.

    Raises
    ------
    ParameterError
        If the contact radius would grow again after its maximum (more than
        one maximum: Graham 1967's general case, not implemented), or if the
        load becomes positive again after the contact was lost.

    References
    ----------
    Lee & Radok (1960); Ting (1966); Graham (1967).
    """
    times = _times(t)
    if times.ndim != 1 or times.size < 2 or np.any(np.diff(times) <= 0.0):
        raise ParameterError(f"t must be a 1-D increasing array of at least 2 times [s], got shape {times.shape}")
    radius = check_positive(radius, name="radius", unit="m")
    poisson = check_poisson(poisson)
    load_function = _check_callable(load_function, name="load_function")
    creep = _check_callable(creep, name="creep")
    relaxation = _check_callable(relaxation, name="relaxation")
    factor = 1.0 - poisson**2

    def compliance(s):
        return factor * np.asarray(creep(s), dtype=float)

    def modulus(s):
        return np.asarray(relaxation(s), dtype=float) / factor

    def load(s):
        return np.asarray(load_function(np.asarray(s, dtype=float)), dtype=float) * np.ones(np.shape(s))

    initial_load = check_non_negative(float(load(0.0)), name="load_function(0)", unit="N")
    glassy_compliance = float(compliance(0.0))

    def loading_history(breaks):
        """A(s) = int_0^s C*(s - v) dW(v) (= 4 a**3 / (3R) while a grows) at the nodes."""
        kinds = np.full(len(breaks) - 1, _LINEAR)
        kinds[0] = _CLUSTER_LEFT
        panels = _Panels(breaks, kinds)
        load_values = load(panels.nodes)
        if not np.all(np.isfinite(load_values)):
            raise ParameterError("load_function must be finite on [0, max(t)]")
        values = compliance(panels.nodes) * initial_load + panels.hereditary(compliance,
                                                                              panels.derivative(load_values))
        return panels, values

    subdivisions = check_positive_int(subdivisions, name="subdivisions")
    breaks = np.unique(np.concatenate([[0.0], times]))
    if subdivisions > 1:
        fractions = np.arange(subdivisions) / subdivisions
        breaks = np.concatenate([(breaks[:-1, None] + np.diff(breaks)[:, None] * fractions[None, :]).ravel(),
                                 breaks[-1:]])
    panels, cube_values = loading_history(breaks)
    maximum = _first_maximum(panels, cube_values)

    def radius_of(cube):
        return np.cbrt(0.75 * radius * np.maximum(cube, 0.0))

    if maximum is None:
        index = np.searchsorted(breaks, times)
        ends = np.concatenate([cube_values[:1, 0], cube_values[:, -1]])
        contact_radius = radius_of(ends[index])
        return TingSolution(time=times, load=load(times), contact_radius=contact_radius,
                            approach=contact_radius**2 / radius, loading_time=times.copy(), max_time=None,
                            max_contact_radius=float(contact_radius[-1]))

    max_time, _ = maximum
    # snap t_m to a grid time when it is one (kinked load at the maximum)
    nearest = breaks[np.argmin(np.abs(breaks - max_time))]
    if abs(nearest - max_time) <= 1e-9 * max(np.max(np.diff(breaks)), 1e-300):
        max_time = float(nearest)

    # loading phase, recomputed on [0, t_m] with t_m a grid point
    first_breaks = np.concatenate([breaks[breaks < max_time], [max_time]])
    if first_breaks.size >= 2:
        first, cube = loading_history(first_breaks)
        cube_rate = first.derivative(cube)
        square = radius_of(cube) ** 2 / radius            # a(s)**2 / R
        square_rate = first.derivative(square)
        max_cube = float(cube[-1, -1])
    else:                                                  # maximum at t = 0+
        first = None
        max_cube = glassy_compliance * initial_load
    initial_cube = glassy_compliance * initial_load        # A(0+)
    initial_square = radius_of(initial_cube) ** 2 / radius
    max_square = radius_of(max_cube) ** 2 / radius

    # receding phase: grid [t_m, later times], cut where the load reaches zero
    later = breaks[breaks > max_time]
    second_breaks = np.concatenate([[max_time], later])
    load_at_breaks = load(second_breaks)
    lost = np.nonzero(load_at_breaks <= 0.0)[0]
    if lost.size:
        end = lost[0]
        if np.any(load_at_breaks[end:] > 0.0):
            raise ParameterError("the load becomes positive again after the contact was lost; "
                                 "re-loading of a recovering surface is not supported")
        if end == 0:                                       # no load left at t_m itself
            contact_breaks = second_breaks[:1]
        elif load_at_breaks[end] < 0.0:                    # insert the zero crossing as a grid point
            crossing = brentq(lambda s: float(load(s)), second_breaks[end - 1], second_breaks[end], xtol=1e-15)
            contact_breaks = np.concatenate([second_breaks[:end], [crossing]])
        else:
            contact_breaks = second_breaks[:end + 1]
        loss_time = contact_breaks[-1]
    else:
        contact_breaks = second_breaks
        loss_time = np.inf
    kinds = np.full(contact_breaks.size - 1, _LINEAR)
    if np.isfinite(loss_time) and kinds.size:
        kinds[-1] = _CLUSTER_RIGHT
    second = _Panels(contact_breaks, kinds) if kinds.size else None

    def receding_state(s, w):
        """(A(s) = 4 a**3/(3R), t1, H(s)) from W(s) = int_0^{t1} E*(s - v) dA(v)."""
        relaxed = float(modulus(s))
        if first is None or w <= relaxed * initial_cube:   # inside the jump at v = 0
            cube_now = max(w, 0.0) / relaxed
            total = relaxed * initial_square
            if first is not None:
                total += float(np.sum(modulus(s - first.nodes) * square_rate * _SPECTRAL.weights))
            return cube_now, 0.0, relaxed * radius_of(cube_now) ** 2 / radius - total
        kernel = modulus(s - first.nodes)
        load_parts = (kernel * cube_rate) @ _SPECTRAL.weights
        square_parts = (kernel * square_rate) @ _SPECTRAL.weights
        cumulative = relaxed * initial_cube + np.cumsum(load_parts)
        if w > cumulative[-1] * (1.0 + 1e-9):
            raise ParameterError(
                f"the contact radius grows again after its maximum at t_m = {max_time!r} s (at t = {s!r} s); "
                f"only histories with a single maximum of the contact radius are supported")
        panel = min(int(np.searchsorted(cumulative, w)), len(first) - 1)
        before = cumulative[panel - 1] if panel else relaxed * initial_cube
        integral = cheb.chebint(_SPECTRAL.to_coefficients @ (kernel[panel] * cube_rate[panel]), lbnd=-1)
        target = w - before
        if target >= cheb.chebval(1.0, integral):
            u = 1.0
        else:
            u = brentq(lambda x: cheb.chebval(x, integral) - target, -1.0, 1.0, xtol=1e-15)
        cube_now = float(cheb.chebval(u, _SPECTRAL.to_coefficients @ cube[panel]))
        loading_time = float(_panel_map(first.lo[panel], first.hi[panel], first.kinds[panel], u))
        square_integral = cheb.chebint(_SPECTRAL.to_coefficients @ (kernel[panel] * square_rate[panel]), lbnd=-1)
        rest = (cheb.chebval(1.0, square_integral) - cheb.chebval(u, square_integral)
                + np.sum(square_parts[panel + 1:]))
        return cube_now, loading_time, -float(rest)

    if second is not None:
        second_load = load(second.nodes)
        # the load may vanish only at the very end of the contact (the last node)
        if np.any(second_load.ravel()[:-1] <= 0.0) or (not np.isfinite(loss_time) and second_load[-1, -1] <= 0.0):
            raise ParameterError("the load falls to zero inside an interval of t; put that time on the grid")
        cube2 = np.empty(second.nodes.shape)
        loading2 = np.empty(second.nodes.shape)
        history2 = np.empty(second.nodes.shape)
        for index in np.ndindex(second.nodes.shape):
            cube2[index], loading2[index], history2[index] = receding_state(float(second.nodes[index]),
                                                                             float(second_load[index]))
        flat = np.concatenate([cube2[0], cube2[1:, 1:].ravel()])
        if np.any(np.diff(radius_of(flat)) > 1e-9 * radius_of(max_cube)):
            rise = np.nonzero(np.diff(radius_of(flat)) > 1e-9 * radius_of(max_cube))[0][0]
            raise ParameterError(
                f"the contact radius grows again after its maximum at t_m = {max_time!r} s "
                f"(near t = {np.concatenate([second.nodes[0], second.nodes[1:, 1:].ravel()])[rise]!r} s); "
                f"only histories with a single maximum of the contact radius are supported")
        history_rate = second.derivative(history2)

    contact_radius = np.empty(times.shape)
    approach = np.empty(times.shape)
    loading_time = np.empty(times.shape)
    for number, time in enumerate(times):
        if time <= max_time:
            if first is None:
                cube_now = initial_cube
            elif time == 0.0:
                cube_now = float(cube[0, 0])
            else:
                panel = int(np.searchsorted(first.hi, time))
                cube_now = float(cube[panel, -1])
            contact_radius[number] = radius_of(cube_now)
            approach[number] = contact_radius[number] ** 2 / radius
            loading_time[number] = time
        elif time > loss_time:
            contact_radius[number], approach[number], loading_time[number] = 0.0, np.nan, np.nan
        else:
            panel = int(np.searchsorted(second.hi, time))
            contact_radius[number] = radius_of(cube2[panel, -1])
            loading_time[number] = loading2[panel, -1]
            done = slice(0, panel + 1)
            approach[number] = max_square + float(np.sum(
                compliance(np.maximum(time - second.nodes[done], 0.0)) * history_rate[done] * _SPECTRAL.weights))
    return TingSolution(time=times, load=load(times), contact_radius=contact_radius, approach=approach,
                        loading_time=loading_time, max_time=float(max_time),
                        max_contact_radius=float(radius_of(max_cube)))
