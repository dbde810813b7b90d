"""Viscoelastic indentation: the stepper against Lee & Radok and against its own hereditary sum.

Material: a two-term Prony solid, E(t) = 1 + 1.5 exp(-t/1 s) + 1 exp(-t/30 s) GPa,
nu = 0.4; rigid sphere R = 10 mm. Grids: odd, about 36 cells per final contact radius.
"""
import numpy as np
import pytest

import framework as fw
from framework import indenters, loads, materials, reference, schedules
from framework.history import HereditarySum, PronyRecursion

MATERIAL = materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(1.5e9, 1.0), (1e9, 30.0)], poisson=0.4)
RADIUS = 10e-3
LOAD = 2.0  # N


def grid_for(final_radius, cells):
    dx = final_radius / cells
    n = 2 * int(1.6 * cells) + 1
    return fw.Grid(shape=(n, n), size=(n * dx, n * dx))


def lee_radok_step(t):
    """Lee & Radok: a^3 = 3 R W C*(t) / 4, delta = a^2 / R."""
    a = (0.75 * RADIUS * LOAD * MATERIAL.contact_compliance()(t)) ** (1 / 3)
    return a, a**2 / RADIUS


@pytest.fixture(scope="module")
def creep_run():
    times = np.concatenate([[0.0], np.geomspace(0.01, 200.0, 40)])
    final_radius = lee_radok_step(np.inf)[0]
    sim = fw.Simulation(grid=grid_for(final_radius, 36), material=MATERIAL, indenter=indenters.Sphere(radius=RADIUS),
                        schedule=schedules.Static(load=loads.Step(LOAD), times=times))
    return sim.run()


def test_step_load_follows_lee_radok(creep_run):
    a, delta = lee_radok_step(creep_run.times)
    assert np.abs(creep_run.contact_radius / a - 1).max() < 1e-2
    assert np.abs(creep_run.approach / delta - 1).max() < 1e-2
    assert np.all(np.diff(creep_run.contact_radius) >= 0) and np.all(np.diff(creep_run.approach) > 0)
    assert np.allclose(creep_run.load, LOAD, rtol=1e-12)


def test_recursion_equals_hereditary_sum_for_any_pressure_history():
    """Given the same pressures, the O(1) recursion and the O(n) sum give the same history fields."""
    rng = np.random.default_rng(1)
    series = materials.Maxwell(young=2e9, relaxation_time=3.0, poisson=0.3).contact_compliance()
    held = materials.KelvinVoigt(young=2e9, viscosity=4e9, poisson=0.3).contact_compliance()  # held pressure
    for series in (MATERIAL.contact_compliance(), series, held):
        recursion, direct = PronyRecursion(series, (6, 5)), HereditarySum(series, (6, 5))
        for time in [0.0, 0.0, 0.3, 0.31, 2.0, 2.0, 7.5, 40.0, 41.0]:
            c1, f1 = recursion.prepare(time)
            c2, f2 = direct.prepare(time)
            assert c1 == pytest.approx(c2, rel=1e-14)
            if f1 is not None:
                assert np.abs(f1 - f2).max() <= 1e-12 * float(series(1.0)) * 1e9  # pressures ~1e9 Pa
            pressure = rng.random((6, 5)) * 1e9
            recursion.commit(time, pressure)
            direct.commit(time, pressure)


def test_recursion_equals_hereditary_sum_in_a_full_run():
    history = loads.Sequence([loads.Ramp(LOAD, 1.0), loads.Hold(3.0), loads.Ramp(0.3 * LOAD, 1.0), loads.Hold(10.0)])
    times = np.linspace(0.25, 15.0, 24)
    grid = grid_for(lee_radok_step(np.inf)[0], 12)
    options = {"tolerance": 1e-13, "residual_tolerance": 1e-11}
    runs = [fw.Simulation(grid=grid, material=MATERIAL, indenter=indenters.Sphere(radius=RADIUS),
                          schedule=schedules.Static(load=history, times=times),
                          options=dict(options, history=kind)).run() for kind in ("recursive", "hereditary")]
    peak = runs[1].max_pressure.max()
    for step in range(len(times)):
        assert np.abs(runs[0].pressure(step) - runs[1].pressure(step)).max() <= 1e-10 * peak
    assert np.allclose(runs[0].approach, runs[1].approach, rtol=1e-10)


def test_step_approach_relaxes_the_load():
    """Step approach delta0: W(t) = (4 sqrt(R)/3) E*(t) delta0^(3/2), contact radius sqrt(R delta0)."""
    delta0 = 2e-6
    times = np.concatenate([[0.0], np.geomspace(0.01, 200.0, 25)])
    grid = grid_for(np.sqrt(RADIUS * delta0), 36)
    result = fw.Simulation(grid=grid, material=MATERIAL, indenter=indenters.Sphere(radius=RADIUS),
                           schedule=schedules.Static(approach=loads.Step(delta0), times=times)).run()
    expected = 4 * np.sqrt(RADIUS) / 3 * MATERIAL.relaxation(times) / (1 - MATERIAL.poisson**2) * delta0**1.5
    assert np.abs(result.load / expected - 1).max() < 1e-2
    assert np.abs(result.contact_radius / np.sqrt(RADIUS * delta0) - 1).max() < 1e-2
    assert np.all(np.diff(result.load) < 0)


def test_unloading_with_a_receding_contact():
    """Load, hold, unload to zero, recover (Ting 1966): p >= 0, the area recedes, the approach recovers."""
    history = loads.Sequence([loads.Ramp(LOAD, 2.0), loads.Hold(5.0), loads.Ramp(0.0, 2.0), loads.Hold(100.0)])
    times = np.concatenate([np.linspace(0.2, 9.0, 45), np.geomspace(9.5, 109.0, 20)])
    grid = grid_for(lee_radok_step(np.inf)[0], 16)
    result = fw.Simulation(grid=grid, material=MATERIAL, indenter=indenters.Sphere(radius=RADIUS),
                           schedule=schedules.Static(load=history, times=times)).run()
    assert all(np.all(result.pressure(k) >= 0) for k in range(len(times)))
    unloading = (times >= 7.0) & (times <= 9.0)
    assert np.all(np.diff(result.contact_area[unloading]) <= 0)
    assert result.contact_area[times >= 9.0].max() == 0.0
    recovery = times > 9.0
    # after unloading the surface creeps back: the approach (depth of the imprint) falls towards zero
    assert np.all(np.diff(result.approach[recovery]) <= 1e-15)
    assert result.approach[-1] < 0.05 * result.approach.max()
    # the cycle dissipates energy: int W d(delta) > 0 along the history
    work = np.trapezoid(result.load, result.approach)
    assert work > 0.02 * LOAD * result.approach.max()


def test_step_load_pressure_profile_follows_lee_radok(creep_run):
    """The pressure keeps the memory of the earlier, smaller contacts (Lee & Radok), not Hertz's shape."""
    grid = creep_run.grid
    r = np.hypot(*grid.coordinates())
    peak = creep_run.max_pressure[0]
    for step in (10, 25, 40):
        t = creep_run.times[step]
        inside = r < 0.9 * creep_run.contact_radius[step]
        rings = np.unique(np.round(r[inside] / grid.spacing[0], 6))[::7] * grid.spacing[0]
        expected = reference.lee_radok_step_load_pressure(rings, t, RADIUS, LOAD, MATERIAL.relaxation,
                                                          MATERIAL.creep, MATERIAL.poisson)
        simulated = np.array([creep_run.pressure(step)[np.isclose(r, ring)].mean() for ring in rings])
        assert np.abs(simulated - expected).max() < 1e-2 * peak


def ramp_run(steps, cells=16, end=20.0):
    rate = 1e-7  # m/s
    times = np.linspace(end / steps, end, steps)
    grid = grid_for(np.sqrt(RADIUS * rate * end), cells)
    sim = fw.Simulation(grid=grid, material=MATERIAL, indenter=indenters.Sphere(radius=RADIUS),
                        schedule=schedules.Static(approach=loads.Ramp(rate * end, end), times=times),
                        options={"tolerance": 1e-12, "residual_tolerance": 1e-10, "time_tolerance": None})
    return sim.run(), rate      # (one step per output time: the order study halves them)


def test_ramp_approach_against_the_closed_form():
    """delta = v t: W(t) from Lee & Radok with the Dawson function, within 1 % (36 cells per final radius)."""
    result, rate = ramp_run(40, cells=36)
    expected = reference.lee_radok_ramp_load(result.times, RADIUS, rate, 1e9, [(1.5e9, 1.0), (1e9, 30.0)],
                                             MATERIAL.poisson)
    late = result.times >= 2.0  # before, the contact spans only a few cells
    assert np.abs(result.load[late] / expected[late] - 1).max() < 1e-2


@pytest.mark.slow
def test_ramp_approach_is_second_order_in_the_time_step():
    """Self-convergence on one grid against 640 steps: fitted order ~2 (measured 2.0-2.1).

    Single halvings scatter (1.6, 2.5): cells join the contact with a square-root
    onset in time as the front passes them, so the error is not smooth in dt;
    the least-squares order over 20..160 steps is the stable measure.
    """
    finest, _ = ramp_run(640)
    steps = np.array([20, 40, 80, 160])
    errors = [abs(ramp_run(int(n))[0].load[-1] / finest.load[-1] - 1) for n in steps]
    order = -np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert order > 1.8, (errors, order)


def test_unloading_follows_ting():
    """Triangular load on the two-term solid: contact radius and approach against Ting/Graham, unloading included."""
    history = loads.Table(times=[0.0, 4.0, 8.0], values=[0.0, LOAD, 0.0])
    times = np.linspace(0.2, 7.8, 39)
    exact = reference.ting_contact_radius(np.linspace(0.0, 8.0, 161), history, RADIUS, MATERIAL.creep,
                                          MATERIAL.relaxation, MATERIAL.poisson)
    grid = grid_for(exact.max_contact_radius, 30)
    result = fw.Simulation(grid=grid, material=MATERIAL, indenter=indenters.Sphere(radius=RADIUS),
                           schedule=schedules.Static(load=history, times=times)).run()
    a = np.interp(times, exact.time, exact.contact_radius)
    delta = np.interp(times, exact.time, exact.approach)
    receding = times > exact.max_time
    assert receding.sum() > 10
    dx = grid.spacing[0]
    assert np.abs(result.contact_radius - a)[a > 8 * dx].max() < 0.6 * dx + 0.01 * a.max()
    assert np.abs(result.approach - delta).max() < 1e-2 * delta.max()


def test_kelvin_voigt_ramp_follows_lee_radok_at_first_order_and_never_rings():
    """A solid without instantaneous compliance: pressure held within a step (backward Euler).

    Lee & Radok for a load ramp W = k t: a^3 = (3R/4) k int_0^t C*(s) ds, with
    C*(t) = (1 - nu^2)/E (1 - exp(-t/tau)), so int = (1 - nu^2)/E (t - tau (1 - exp(-t/tau))).
    The piecewise-linear scheme rang here (the area jumped up and down from step to step,
    more so on finer steps); the held pressure converges at first order and monotonically.
    Grid 65 x 65 over 1.2 mm: about 10 cells per final contact radius.
    """
    young, tau, nu, rate = 2e9, 1.0, 0.4, 5.0
    solid = materials.KelvinVoigt(young=young, viscosity=young * tau, poisson=nu)
    grid = fw.Grid(shape=(65, 65), size=(1.2e-3, 1.2e-3))
    errors = []
    for steps in (12, 48):
        times = np.linspace(1.0 / steps, 1.0, steps)
        result = fw.Simulation(grid=grid, material=solid, indenter=indenters.Sphere(radius=RADIUS),
                               schedule=schedules.Static(load=loads.Ramp(end=rate, duration=1.0), times=times),
                               options={"time_tolerance": None}).run()     # the scheme's order: fixed steps
        a = (0.75 * RADIUS * rate * (1 - nu**2) / young * (times - tau * -np.expm1(-times / tau))) ** (1 / 3)
        assert np.all(np.diff(result.contact_area) >= 0)
        assert np.all(np.diff(result.approach) > 0)
        errors.append(abs(result.approach[-1] / (a[-1] ** 2 / RADIUS) - 1))
    assert errors[1] < 0.015
    assert 3.0 < errors[0] / errors[1] < 5.0  # first order: four times the steps, a quarter of the error
