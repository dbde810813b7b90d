"""Checks of framework.reference.viscoelastic (Lee & Radok, Ting, Graham).

Independent evidence, not re-typed formulas:

* elastic limits (constant modulus) against framework.reference.hertz;
* the step-load pressure integrated over the contact (load) and its Abel
  moment 2 int p dr, which is the Boussinesq displacement at the centre,
  against the relaxation form of delta = a**2/R computed by a time quadrature;
* closed forms (standard linear solid) for the loading phase and for the time
  of the maximum contact radius;
* a separate time-stepping solution of the contact problem: rings of uniform
  pressure with Johnson's disc displacements, hereditary sum of the creep
  compliance (pressure linear in time within a step), contact set found by
  complementarity at every step. It assumes nothing of Lee & Radok or Ting,
  so it checks the receding-contact formulas themselves.
"""
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import solve_triangular
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from framework.errors import ParameterError
from framework.reference.hertz import HertzSphere
from framework.reference.viscoelastic import (lee_radok_load_for_approach, lee_radok_ramp_load,
                                              lee_radok_step_approach_load, lee_radok_step_load,
                                              lee_radok_step_load_pressure, ting_contact_radius)

RADIUS = 0.01          # [m]
POISSON = 0.3
FACTOR = 1.0 - POISSON**2
# standard linear solid E(t) = E_inf + E_1 exp(-t/tau): strong creep (J(inf)/J(0) = 10)
E_INF, E_1, TAU = 1.0e9, 9.0e9, 0.2
RETARDATION = TAU * (E_INF + E_1) / E_INF
CREEP_AMPLITUDE = E_1 / (E_INF * (E_INF + E_1))


def relaxation(t):
    return E_INF + E_1 * np.exp(-np.asarray(t, dtype=float) / TAU)


def creep(t):
    """Closed-form creep compliance of the standard linear solid [1/Pa]."""
    return 1.0 / E_INF - CREEP_AMPLITUDE * np.exp(-np.asarray(t, dtype=float) / RETARDATION)


def creep_rate(t):
    return CREEP_AMPLITUDE / RETARDATION * np.exp(-np.asarray(t, dtype=float) / RETARDATION)


def creep_integral(t):
    """int_0^t J(x) dx."""
    t = np.asarray(t, dtype=float)
    return t / E_INF - CREEP_AMPLITUDE * RETARDATION * (1.0 - np.exp(-t / RETARDATION))


def mean_contact_compliance(start, end):
    """Mean of C* = (1 - nu**2) J over [start, end]."""
    return FACTOR * (creep_integral(end) - creep_integral(start)) / (end - start)


def constant(value):
    return lambda t: np.full(np.shape(t), value, dtype=float)


def triangle(peak_time, peak_load):
    def load(t):
        t = np.asarray(t, dtype=float)
        return peak_load * np.minimum(t / peak_time, np.maximum(2.0 - t / peak_time, 0.0))
    return load


def hold_then_unload(load_value):
    """W0 from t = 0 (a step), held until 1 s, then down to zero at 2 s."""
    return lambda t: load_value * np.clip(2.0 - np.asarray(t, dtype=float), 0.0, 1.0)


# --------------------------------------------------------------------------- independent solver

def disc_displacement(r, c):
    """Surface displacement at r of unit pressure on a disc of radius c, unit compliance.

    Johnson, Contact Mechanics (1985), section 3.4: (4c/pi) E(r/c) inside,
    (4r/pi) [E(c/r) - (1 - c**2/r**2) K(c/r)] outside (scipy takes m = k**2).
    """
    r, c = np.broadcast_arrays(np.asarray(r, dtype=float), np.asarray(c, dtype=float))
    out = np.zeros(r.shape)
    inside = (r < c) & (c > 0.0)
    out[inside] = 4.0 * c[inside] / np.pi * ellipe((r[inside] / c[inside]) ** 2)
    outside = (r > c) & (c > 0.0)
    m = (c[outside] / r[outside]) ** 2
    out[outside] = 4.0 * r[outside] / np.pi * (ellipe(m) - (1.0 - m) * ellipk(m))
    return out


def ring_simulation(times, load, rings, outer):
    """Load-controlled contact of a rigid sphere on the standard linear solid.

    Returns the outer edge of the last loaded ring (the contact radius to
    within one ring width), the approach and the ring pressures at each time.
    The contact set is always the first k rings (a disc), so one LU
    factorisation without pivoting of the influence matrix serves every
    contact set: its leading k x k blocks factorise the leading blocks.
    """
    edges = np.linspace(0.0, outer, rings + 1)
    middle = 0.5 * (edges[1:] + edges[:-1])
    area = np.pi * (edges[1:] ** 2 - edges[:-1] ** 2)
    influence = disc_displacement(middle[:, None], edges[None, 1:]) - disc_displacement(middle[:, None],
                                                                                        edges[None, :-1])
    profile = middle**2 / (2.0 * RADIUS)
    lower, upper = np.eye(rings), influence.copy()
    for j in range(rings - 1):
        lower[j + 1:, j] = upper[j + 1:, j] / upper[j, j]
        upper[j + 1:, j:] -= np.outer(lower[j + 1:, j], upper[j, j:])
    upper = np.triu(upper)

    def block_solve(count, right):
        half = solve_triangular(lower[:count, :count], right, lower=True, unit_diagonal=True, check_finite=False)
        return solve_triangular(upper[:count, :count], half, check_finite=False)

    def solve(compliance, history, total, count):
        """Contact set = first `count` rings, adjusted until p >= 0 inside and gap >= 0 outside.

        c K p - delta = -profile - history on the contact set, sum(area p) = W.
        """
        for _ in range(4 * rings):
            particular = block_solve(count, -profile[:count] - history[:count]) / compliance
            unit = block_solve(count, np.ones(count)) / compliance
            approach = (total - area[:count] @ particular) / (area[:count] @ unit)
            pressure = particular + approach * unit
            gap = profile - approach + compliance * influence[:, :count] @ pressure + history
            if pressure[-1] < 0.0 and count > 1:
                count -= 1
            elif count < rings and gap[count] < 0.0:
                count += 1
            else:
                break
        full = np.zeros(rings)
        full[:count] = pressure
        return full, approach, count

    steps = len(times)
    increments = np.zeros((steps, rings))
    pressures = np.zeros((steps, rings))
    edge = np.zeros(steps)
    approach = np.full(steps, np.nan)
    count = rings // 2
    first = float(load(times[0]))
    jump = np.zeros(rings)
    if first > 0.0:                                  # step at t = 0: glassy elastic contact
        jump, approach[0], count = solve(FACTOR * creep(0.0), np.zeros(rings), first, count)
        edge[0], pressures[0] = edges[count], jump
    previous = jump.copy()
    for n in range(1, steps):
        now = times[n]
        weights = mean_contact_compliance(now - times[1:n + 1], now - times[:n])
        history = weights[:-1] @ increments[1:n] - weights[-1] * previous + FACTOR * creep(now - times[0]) * jump
        total = float(load(now))
        if total <= 0.0:
            current, count = np.zeros(rings), 1
        else:
            current, approach[n], count = solve(weights[-1], influence @ history, total, count)
            edge[n] = edges[count]
        increments[n] = current - previous
        previous = pressures[n] = current
    return edge, approach, middle, pressures


# --------------------------------------------------------------------------- Lee & Radok, step load

def test_step_load_elastic_limit_is_hertz():
    young = 2.0e9
    times = np.array([0.0, 0.3, 5.0])
    contact_radius, approach = lee_radok_step_load(times, RADIUS, 10.0, constant(1.0 / young), POISSON)
    hertz = HertzSphere(radius=RADIUS, load=10.0, contact_modulus=young / FACTOR)
    np.testing.assert_allclose(contact_radius, hertz.contact_radius, rtol=1e-14)
    np.testing.assert_allclose(approach, hertz.approach, rtol=1e-14)
    r = np.linspace(0.0, 1.2, 12) * hertz.contact_radius  # not exactly a
    pressure = lee_radok_step_load_pressure(r, 0.7, RADIUS, 10.0, constant(young), constant(1.0 / young), POISSON)
    np.testing.assert_allclose(pressure, hertz.pressure(r), rtol=1e-12, atol=1e-12 * hertz.max_pressure)


def test_step_load_goes_from_glassy_to_relaxed_hertz():
    contact_radius, _ = lee_radok_step_load([0.0, 1e3 * RETARDATION], RADIUS, 10.0, creep, POISSON)
    glassy = HertzSphere(radius=RADIUS, load=10.0, contact_modulus=(E_INF + E_1) / FACTOR)
    relaxed = HertzSphere(radius=RADIUS, load=10.0, contact_modulus=E_INF / FACTOR)
    assert contact_radius[0] == pytest.approx(glassy.contact_radius, rel=1e-13)
    assert contact_radius[1] == pytest.approx(relaxed.contact_radius, rel=1e-13)


@pytest.mark.parametrize("time", [0.5, 2.0])
def test_step_load_pressure_carries_load_and_centre_displacement(time):
    load = 10.0
    initial = lee_radok_step_load(0.0, RADIUS, load, creep, POISSON)[0]
    current = lee_radok_step_load(time, RADIUS, load, creep, POISSON)[0]
    x, w = np.polynomial.legendre.leggauss(48)
    theta = 0.5 * np.pi * (x + 1.0)
    total = moment = 0.0
    for low, high in [(0.0, initial), (initial, current)]:
        r = low + (high - low) * 0.5 * (1.0 - np.cos(theta))
        weights = 0.5 * np.pi * w * (high - low) * 0.5 * np.sin(theta)
        pressure = lee_radok_step_load_pressure(r, time, RADIUS, load, relaxation, creep, POISSON)
        total += np.sum(weights * 2.0 * np.pi * r * pressure)
        moment += np.sum(weights * 2.0 * pressure)
    assert total == pytest.approx(load, rel=1e-10)
    # 2 int p dr is the centre displacement per unit compliance; in relaxation form
    # it equals int_0^t E*(t - s) d[a(s)**2 / R](s) because delta = a**2/R at the centre.
    square = (0.75 * RADIUS * load) ** (2.0 / 3.0) / RADIUS       # a**2/R = square * C*(s)**(2/3)

    def integrand(s):
        return relaxation(time - s) / FACTOR * square * 2.0 / 3.0 * (FACTOR * creep(s)) ** (-1.0 / 3.0) \
            * FACTOR * creep_rate(s)

    expected = relaxation(time) / FACTOR * initial**2 / RADIUS + quad(integrand, 0.0, time, epsabs=0.0,
                                                                       epsrel=1e-13, limit=200)[0]
    assert moment == pytest.approx(expected, rel=1e-10)


def test_step_load_pressure_is_not_the_hertz_profile_of_the_current_radius():
    time, load = 0.5, 10.0
    current = lee_radok_step_load(time, RADIUS, load, creep, POISSON)[0]
    r = np.array([0.0, 0.9]) * current
    pressure = lee_radok_step_load_pressure(r, time, RADIUS, load, relaxation, creep, POISSON)
    hertz_shape = 3.0 * load / (2.0 * np.pi * current**2) * np.sqrt(1.0 - (r / current) ** 2)
    ratio = pressure / hertz_shape
    assert ratio[0] < 0.8 and ratio[1] > 1.5      # measured 0.704 and 1.649


def test_step_load_matches_ring_simulation():
    load, rings = 10.0, 200
    times = np.linspace(0.0, 2.0, 201)
    contact_radius, approach = lee_radok_step_load(times, RADIUS, load, creep, POISSON)
    outer = 1.2 * contact_radius[-1]
    edge, ring_approach, middle, pressures = ring_simulation(times, constant(load), rings, outer)
    assert np.max(np.abs(edge - contact_radius)) < outer / rings                      # measured 0.66 ring
    assert np.max(np.abs(ring_approach - approach)) < 2e-5 * approach[-1]            # measured 4.5e-6
    index = 50                                                                        # t = 0.5 s
    inside = middle < 0.9 * contact_radius[index]
    pressure = lee_radok_step_load_pressure(middle[inside], times[index], RADIUS, load, relaxation, creep, POISSON)
    assert np.max(np.abs(pressures[index][inside] - pressure)) < 2e-3 * pressure.max()  # measured 4.6e-4


# --------------------------------------------------------------------------- Lee & Radok, prescribed approach

PRONY_INF = 1.0e9
PRONY_TERMS = [(2.0e9, 0.1), (3.0e9, 1.0), (1.0e9, 10.0)]


def prony_relaxation(t):
    t = np.asarray(t, dtype=float)
    return PRONY_INF + sum(modulus * np.exp(-t / tau) for modulus, tau in PRONY_TERMS)


def test_ramp_closed_form_equals_quadrature():
    rate = 1e-6
    times = np.array([0.0, 0.01, 0.3, 1.0, 5.0, 30.0])
    closed = lee_radok_ramp_load(times, RADIUS, rate, PRONY_INF, PRONY_TERMS, POISSON)
    numerical = lee_radok_load_for_approach(times, lambda s: rate * s, RADIUS, prony_relaxation, POISSON)
    np.testing.assert_allclose(numerical, closed, rtol=1e-8, atol=0.0)    # measured 1e-12
    assert closed[0] == 0.0


def test_ramp_elastic_limit_is_hertz():
    rate, times = 2e-6, np.array([0.5, 3.0])
    load = lee_radok_ramp_load(times, RADIUS, rate, 2.0e9, [], POISSON)
    for time, value in zip(times, load):
        hertz = HertzSphere.from_contact_radius(RADIUS, np.sqrt(RADIUS * rate * time), 2.0e9 / FACTOR)
        assert value == pytest.approx(hertz.load, rel=1e-13)


def test_step_approach_relaxes_from_glassy_to_relaxed_hertz():
    depth = 2e-6
    times = np.array([0.0, 0.5, 2.0, 400.0])
    closed = lee_radok_step_approach_load(times, RADIUS, depth, prony_relaxation, POISSON)
    numerical = lee_radok_load_for_approach(times, constant(depth), RADIUS, prony_relaxation, POISSON)
    np.testing.assert_allclose(numerical, closed, rtol=1e-13)
    contact_radius = np.sqrt(RADIUS * depth)
    glassy = HertzSphere.from_contact_radius(RADIUS, contact_radius, prony_relaxation(0.0) / FACTOR)
    relaxed = HertzSphere.from_contact_radius(RADIUS, contact_radius, PRONY_INF / FACTOR)
    assert closed[0] == pytest.approx(glassy.load, rel=1e-13)
    assert closed[-1] == pytest.approx(relaxed.load, rel=1e-13)
    assert np.all(np.diff(closed) < 0.0)


def test_load_for_approach_rejects_a_receding_approach():
    with pytest.raises(ParameterError, match="non-decreasing"):
        lee_radok_load_for_approach([1.0, 2.0], lambda s: 1e-6 * (1.0 - 0.3 * s), RADIUS, prony_relaxation, POISSON)


# --------------------------------------------------------------------------- Ting / Graham

def hertz_history(load, young):
    contact_radius = np.cbrt(0.75 * load * RADIUS * FACTOR / young)
    return contact_radius, contact_radius**2 / RADIUS


@pytest.mark.parametrize("history", [triangle(2.0, 10.0), lambda t: 10.0 * np.sin(np.pi * np.asarray(t) / 4.0)])
def test_ting_elastic_limit_is_hertz_at_every_time(history):
    young = 2.0e9
    times = np.linspace(0.0, 4.0, 41)
    solution = ting_contact_radius(times, history, RADIUS, constant(1.0 / young), constant(young), POISSON)
    contact_radius, approach = hertz_history(history(times), young)
    np.testing.assert_allclose(solution.contact_radius**3, contact_radius**3, rtol=0.0,
                               atol=1e-12 * contact_radius.max() ** 3)
    # a ~ W**(1/3) is ill-conditioned where W(4 s) = 0 up to rounding: compare a and delta before
    np.testing.assert_allclose(solution.contact_radius[:-1], contact_radius[:-1], rtol=1e-12)
    np.testing.assert_allclose(solution.approach[:-1], approach[:-1], rtol=1e-12)
    assert solution.max_time == pytest.approx(2.0, abs=1e-9)


def test_ting_constant_load_is_lee_radok_step_load():
    times = np.linspace(0.0, 5.0, 26)
    solution = ting_contact_radius(times, constant(10.0), RADIUS, creep, relaxation, POISSON)
    contact_radius, approach = lee_radok_step_load(times, RADIUS, 10.0, creep, POISSON)
    assert solution.max_time is None
    np.testing.assert_allclose(solution.contact_radius, contact_radius, rtol=1e-13)
    np.testing.assert_allclose(solution.approach, approach, rtol=1e-13)


PEAK_TIME, PEAK_LOAD = 2.0, 10.0


@pytest.fixture(scope="module")
def triangular():
    times = np.linspace(0.0, 2.0 * PEAK_TIME, 81)
    return ting_contact_radius(times, triangle(PEAK_TIME, PEAK_LOAD), RADIUS, creep, relaxation, POISSON)


def lee_radok_cube(t):
    """4 a**3 / (3R) = int_0^t C*(t - s) dW(s) for the triangle, closed form."""
    rate = PEAK_LOAD / PEAK_TIME
    t = np.asarray(t, dtype=float)
    return FACTOR * rate * (creep_integral(t) - 2.0 * creep_integral(np.maximum(t - PEAK_TIME, 0.0)))


def test_ting_loading_phase_and_maximum_in_closed_form(triangular):
    # maximum where d/dt (C* o dW) = 0: C*(t) = 2 C*(t - t_peak) (after the load peak: creep)
    expected = brentq(lambda t: creep(t) - 2.0 * creep(t - PEAK_TIME), PEAK_TIME, 2.0 * PEAK_TIME, xtol=1e-14)
    assert triangular.max_time == pytest.approx(expected, abs=1e-9)
    assert triangular.max_time > PEAK_TIME + 0.5
    loading = triangular.time <= triangular.max_time
    closed = np.cbrt(0.75 * RADIUS * lee_radok_cube(triangular.time[loading]))
    np.testing.assert_allclose(triangular.contact_radius[loading], closed, rtol=0.0, atol=1e-13 * closed.max())
    assert triangular.max_contact_radius == pytest.approx(np.cbrt(0.75 * RADIUS * lee_radok_cube(expected)),
                                                          rel=1e-13)


def test_ting_receding_phase_satisfies_graham_equation(triangular):
    rate = PEAK_LOAD / PEAK_TIME
    for index in np.nonzero((triangular.time > triangular.max_time) & (triangular.load > 0.0))[0][::4]:
        time, loading_time = triangular.time[index], triangular.loading_time[index]

        def integrand(s, time=time):
            cube_rate = FACTOR * rate * (creep(s) - (2.0 * creep(s - PEAK_TIME) if s > PEAK_TIME else 0.0))
            return relaxation(time - s) / FACTOR * cube_rate

        breaks = [PEAK_TIME] if loading_time > PEAK_TIME else None
        load = quad(integrand, 0.0, loading_time, points=breaks, epsabs=0.0, epsrel=1e-13, limit=200)[0]
        assert load == pytest.approx(triangular.load[index], rel=1e-10)
        assert triangular.contact_radius[index] == pytest.approx(
            np.cbrt(0.75 * RADIUS * lee_radok_cube(loading_time)), rel=1e-12)


def test_ting_physical_behaviour(triangular):
    a = triangular.contact_radius
    loading = triangular.time <= triangular.max_time
    assert np.all(np.diff(a[loading]) > 0.0) and np.all(np.diff(a[~loading]) < 0.0)
    assert a[-1] == 0.0 and a.max() <= triangular.max_contact_radius
    assert np.all(triangular.loading_time[~loading][:-1] < triangular.max_time)
    # the surface has not recovered when the contact is lost: the sphere still sits below it
    assert triangular.approach[-1] > 0.5 * triangular.approach[loading][-1]
    # the receding contact is not Lee & Radok's formula continued past t_m
    continued = np.cbrt(0.75 * RADIUS * lee_radok_cube(triangular.time[~loading]))
    assert np.max(np.abs(continued - a[~loading])) > 0.1 * triangular.max_contact_radius


def test_ting_converges_spectrally(triangular):
    fine = ting_contact_radius(np.linspace(0.0, 2.0 * PEAK_TIME, 161), triangle(PEAK_TIME, PEAK_LOAD), RADIUS,
                               creep, relaxation, POISSON, subdivisions=2)
    np.testing.assert_allclose(fine.contact_radius[::2], triangular.contact_radius, rtol=0.0,
                               atol=1e-11 * triangular.max_contact_radius)
    np.testing.assert_allclose(fine.approach[::2], triangular.approach, rtol=0.0,
                               atol=1e-11 * np.nanmax(triangular.approach))


def step_then_fast_unload(t):
    """10 N at t = 0, down to zero at 0.1 s: the contact radius is largest at t = 0+."""
    return 10.0 * np.clip(1.0 - 10.0 * np.asarray(t, dtype=float), 0.0, None)


@pytest.mark.parametrize("history, end, max_time", [(triangle(PEAK_TIME, PEAK_LOAD), 4.0, 2.769),
                                                    (hold_then_unload(10.0), 2.0, 1.319),
                                                    (step_then_fast_unload, 0.1, 0.0)])
def test_ting_matches_ring_simulation(history, end, max_time):
    rings = 200
    times = np.linspace(0.0, end, 401)
    solution = ting_contact_radius(times, history, RADIUS, creep, relaxation, POISSON)
    assert solution.max_time == pytest.approx(max_time, abs=1e-3)
    outer = 1.3 * solution.max_contact_radius
    edge, approach, _, _ = ring_simulation(times, history, rings, outer)
    contact = solution.contact_radius > 0.3 * solution.max_contact_radius
    assert np.any(contact & (times > max_time + 0.5 * (end - max_time)))
    assert np.max(np.abs(edge - solution.contact_radius)[contact]) < outer / rings            # measured 0.67
    error = np.max(np.abs(approach - solution.approach)[contact]) / np.nanmax(solution.approach)
    assert error < 2e-5                                                                        # measured 7e-6


def test_ting_rejects_a_second_maximum():
    def partial_unload_then_hold(t):
        t = np.asarray(t, dtype=float)
        return 10.0 * np.minimum(t, np.maximum(2.0 - t, 0.5))

    with pytest.raises(ParameterError, match="grows again"):
        ting_contact_radius(np.linspace(0.0, 6.0, 61), partial_unload_then_hold, RADIUS, creep, relaxation, POISSON)


def test_ting_contact_is_lost_where_the_load_crosses_zero():
    def load(t):
        t = np.asarray(t, dtype=float)
        return 10.0 * np.minimum(t, 2.05 - t)            # zero at 2.05 s, between grid times

    solution = ting_contact_radius(np.linspace(0.0, 3.0, 31), load, RADIUS, creep, relaxation, POISSON)
    after = solution.time > 2.05
    assert np.all(solution.contact_radius[after] == 0.0) and np.all(np.isnan(solution.approach[after]))
    before = ~after & (solution.time > 0.0)
    assert np.all(solution.contact_radius[before] > 0.0) and np.all(np.isfinite(solution.approach[before]))
