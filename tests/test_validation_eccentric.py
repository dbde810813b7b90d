"""Eccentric loading: the tilting indenter (THEORY.md sec. 6).

Flat punch radius a = 1 mm on grids of 3a side, 40 cells per radius (121 x 121).
"""
import numpy as np
import pytest

import framework as fw
from framework import errors, indenters, loads, materials, reference, schedules

A = 1e-3
ELASTIC = materials.Elastic(young=1e9, poisson=0.3)
VISCO = materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(1.5e9, 1.0), (1e9, 30.0)], poisson=0.3)
GRID = fw.Grid(shape=(121, 121), size=(3 * A, 3 * A))
LOAD = 10.0


def punch_run(schedule, material=ELASTIC, indenter=None, options=None):
    return fw.Simulation(grid=GRID, material=material, indenter=indenter or indenters.FlatPunch(radius=A),
                         schedule=schedule, options=options).run()


def balance_errors(result, offset):
    x1, x2 = result.grid.coordinates()
    area = result.grid.cell_area
    worst = 0.0
    for k, load in enumerate(result.load):
        p = result.pressure(k)
        worst = max(worst, abs(p.sum() * area - load) / load,
                    abs((p * x1).sum() * area - load * offset[0]) / (load * A),
                    abs((p * x2).sum() * area - load * offset[1]) / (load * A))
    return worst


def test_zero_offset_reproduces_the_static_result():
    """The same discrete problem: equal to the solver tolerance (here 1e-12)."""
    tight = {"tolerance": 1e-12, "residual_tolerance": 1e-10}
    centric = punch_run(schedules.Static(load=LOAD), options=tight)
    eccentric = punch_run(schedules.Eccentric(load=LOAD, offset=(0.0, 0.0)), options=tight)
    assert np.abs(eccentric.pressure(0) - centric.pressure(0)).max() <= 1e-9 * centric.max_pressure[0]
    assert eccentric.approach[0] == pytest.approx(centric.approach[0], rel=1e-10)
    assert np.abs(eccentric.tilt).max() < 1e-12


def test_elastic_flat_punch_tilt_under_a_moment():
    """Full contact (e < a/3): alpha = 3 M / (4 E* a^3) within 1 %, no tilt about x1, balance to 1e-10."""
    offset = (0.25 * A, 0.0)
    result = punch_run(schedules.Eccentric(load=LOAD, offset=offset))
    expected = reference.FlatPunch(radius=A, contact_modulus=ELASTIC.contact_modulus).tilt(LOAD * offset[0])
    assert np.tan(result.tilt[0, 0]) == pytest.approx(expected, rel=1e-2)
    assert abs(result.tilt[0, 1]) < 1e-12
    assert balance_errors(result, offset) < 1e-10
    assert np.allclose(result.center[0], offset, atol=1e-12)


def test_offset_along_x2_tilts_about_x1_only():
    result = punch_run(schedules.Eccentric(load=LOAD, offset=(0.0, -0.2 * A)))
    assert abs(result.tilt[0, 0]) < 1e-12 and result.tilt[0, 1] < 0


def test_viscoelastic_tilt_follows_the_contact_compliance():
    """Step moment, contact area fixed by the punch face: alpha(t) = 3 M C*(t) / (4 a^3) within 1 %."""
    offset = (0.2 * A, 0.1 * A)
    times = np.concatenate([[0.0], np.geomspace(0.05, 200.0, 20)])
    result = punch_run(schedules.Eccentric(load=loads.Step(LOAD), offset=offset, times=times), material=VISCO)
    compliance = VISCO.contact_compliance()(times)
    elastic = reference.FlatPunch(radius=A, contact_modulus=1.0)
    for axis in (0, 1):
        expected = elastic.tilt(LOAD * offset[axis]) * compliance
        assert np.abs(np.tan(result.tilt[:, axis]) / expected - 1).max() < 1e-2
    assert balance_errors(result, offset) < 1e-10


def test_partial_lift_off_converges_and_reports():
    """e = 0.5 a > a/3: part of the face lifts off; the solve converges with the contact reduced."""
    offset = (0.5 * A, 0.0)
    result = punch_run(schedules.Eccentric(load=LOAD, offset=offset))
    full = np.count_nonzero(np.hypot(*GRID.coordinates()) <= A) * GRID.cell_area
    assert result.records[0].success
    assert 0.3 * full < result.contact_area[0] < 0.95 * full
    contact_x1 = GRID.coordinates()[0][result.pressure(0) > 0]
    assert contact_x1.min() > -0.9 * A  # the side opposite the load has lifted off
    assert balance_errors(result, offset) < 1e-10
    assert result.tilt[0, 0] > 0


def test_offset_the_body_cannot_carry():
    with pytest.raises(errors.LoadNotCarriedError, match=r"offset \(0.0012, 0.0\) m lies outside the area"):
        punch_run(schedules.Eccentric(load=LOAD, offset=(1.2 * A, 0.0)))


def test_tilt_grows_and_peak_pressure_falls_under_creep():
    """Seed 001: rounded punch on a creeping solid, eccentric load held: tilt grows, peak pressure falls."""
    punch = indenters.RoundedFlatPunch(flat_radius=0.5 * A, edge_radius=0.5 * A)
    load = reference.RoundedFlatPunch(flat_radius=0.5 * A, edge_radius=0.5 * A,
                                      contact_modulus=VISCO.contact_modulus).load(A)
    times = np.concatenate([[0.0], np.geomspace(0.1, 100.0, 10)])
    grid = fw.Grid(shape=(91, 91), size=(3 * A, 3 * A))
    result = fw.Simulation(grid=grid, material=VISCO, indenter=punch,
                           schedule=schedules.Eccentric(load=load, offset=(0.15 * A, 0.0), times=times)).run()
    assert np.all(np.diff(result.tilt[:, 0]) > 0)
    assert np.all(np.diff(result.max_pressure) < 0)


def test_eccentric_needs_a_load():
    with pytest.raises(errors.ParameterError, match="Eccentric needs a load"):
        schedules.Eccentric(load=None, offset=(0.0, 0.0))
    with pytest.raises(errors.ParameterError, match=r"offset must be a pair"):
        schedules.Eccentric(load=1.0, offset=(0.0,))
