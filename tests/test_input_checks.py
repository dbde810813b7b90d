"""Every bad input to the Python API is one ParameterError (or ShapeError) naming it, raised before any step."""
import re

import numpy as np
import pytest

import framework as fw
from framework import errors, indenters, loads, materials, schedules
from framework.simulation import Options
from framework.solver import SolverOptions

ELASTIC = materials.Elastic(young=1e9, poisson=0.3)
GRID = fw.Grid(shape=(16, 16), size=(1e-3, 1e-3))


def simulation(grid=GRID, material=ELASTIC, indenter=None, schedule=None, **kwargs):
    return fw.Simulation(grid=grid, material=material, indenter=indenter or indenters.Sphere(radius=5e-3),
                         schedule=schedule or schedules.Static(load=1.0), **kwargs)


# --------------------------------------------------------------------------- solver and run options

@pytest.mark.parametrize("options, message", [
    ({"max_iterations": -1}, r"max_iterations must be an integer >= 1, got -1"),
    ({"max_iterations": 0}, r"max_iterations must be an integer >= 1, got 0"),
    ({"max_iterations": 2.5}, r"max_iterations must be an integer >= 1, got 2.5"),
    ({"max_iterations": True}, r"max_iterations must be an integer >= 1, got True"),
    ({"tolerance": 0.0}, r"tolerance must lie in \[1e-15, 1\) .*got 0.0"),
    ({"tolerance": -1e-8}, r"tolerance must lie in \[1e-15, 1\) .*got -1e-08"),
    ({"tolerance": 1e-300}, r"tolerance must lie in \[1e-15, 1\) .*round-off.*got 1e-300"),
    ({"tolerance": 1.0}, r"tolerance must lie in \[1e-15, 1\) .*got 1.0"),
    ({"tolerance": float("nan")}, r"tolerance must be a finite real number, got nan"),
    ({"tolerance": "tight"}, r"tolerance must be a finite real number, got 'tight'"),
    ({"residual_tolerance": 0.0}, r"residual_tolerance must lie in \[1e-15, 1\) .*got 0.0"),
    ({"residual_tolerance": float("inf")}, r"residual_tolerance must be a finite real number, got inf"),
    ({"raise_on_failure": "no"}, r"raise_on_failure must be a boolean, true or false, got 'no'"),
    ({"raise_on_failure": 0}, r"raise_on_failure must be a boolean, true or false, got 0"),
    ({"check_edges": "no"}, r"check_edges must be a boolean, true or false, got 'no'"),
    ({"check_edges": None}, r"check_edges must be a boolean, true or false, got None"),
    ({"history": "recursve"}, r"history must be 'recursive' or 'hereditary', got 'recursve'"),
])
def test_bad_options_are_refused_when_the_simulation_is_built(options, message):
    with pytest.raises(errors.ParameterError, match=message):
        simulation(options=options)


def test_options_objects_check_themselves():
    with pytest.raises(errors.ParameterError, match=r"max_iterations must be an integer >= 1, got -5"):
        SolverOptions(max_iterations=-5)
    with pytest.raises(errors.ParameterError, match=r"solver must be a SolverOptions, got 'fast'"):
        Options(solver="fast")
    assert SolverOptions(tolerance=1e-15, raise_on_failure=np.bool_(False)).raise_on_failure is False


@pytest.mark.parametrize("kwargs, message", [
    (dict(every=0), r"every \(steps between checkpoints\) must be an integer >= 1, got 0"),
    (dict(every=-3), r"every \(steps between checkpoints\) must be an integer >= 1, got -3"),
    (dict(progress="no"), r"progress must be a boolean, true or false, got 'no'"),
    (dict(callback="print"), r"callback must be callable as callback\(result, record\) or None, got 'print'"),
    (dict(checkpoint=123), r"checkpoint must be a file path \(a non-empty str or os.PathLike\), got 123"),
    (dict(checkpoint="/no/such/folder/c.h5"), r"checkpoint: cannot write '/no/such/folder/c.h5': the folder "
                                              r"'/no/such/folder' does not exist"),
    (dict(resume="/no/such/run.h5"), r"resume: .*no result file at '/no/such/run.h5'"),
])
def test_bad_run_arguments(kwargs, message, tmp_path):
    sim = simulation()
    kwargs.setdefault("checkpoint", str(tmp_path / "c.h5"))
    with pytest.raises(errors.ParameterError, match=message):
        sim.run(**kwargs)
    assert not (tmp_path / "c.h5").exists()
    assert sim.result is None or len(sim.result) == 0


def test_bad_result_queries():
    result = fw.Simulation(grid=fw.Grid(shape=(8, 8), size=(1e-3, 1e-3), depth=1e-3, layers=2), material=ELASTIC,
                           indenter=indenters.Sphere(radius=5e-3), schedule=schedules.Static(load=[1.0, 2.0])).run()
    with pytest.raises(errors.ParameterError, match=r"step must be an integer index in \[-2, 2\), got True"):
        result.pressure(True)
    with pytest.raises(errors.ParameterError, match=r"points must be finite everywhere, got nan at index \(0, 0\)"):
        result.stress_at(0, [[np.nan, 0.0, 1e-4]])
    with pytest.raises(errors.ParameterError, match=r"points must be an array of real numbers, got str"):
        result.stress_at(0, "centre")


def test_a_grid_beyond_any_memory():
    with pytest.raises(errors.ParameterError, match=r"grid: 10000000 x 10000000 cells do not fit in memory"):
        simulation(grid=fw.Grid(shape=(10**7, 10**7), size=(1e-3, 1e-3)))


# --------------------------------------------------------------------------- booleans, loads, grids

@pytest.mark.parametrize("factory, message", [
    (lambda: indenters.Sphere(radius=1e-3, exact="no"), r"exact must be a boolean, true or false, got 'no'"),
    (lambda: indenters.Sphere(radius=1e-3, exact=1), r"exact must be a boolean, true or false, got 1"),
    (lambda: fw.Grid(shape=(4, 4), size=(1.0, 1.0), periodic=("yes", False)),
     r"periodic\[0\] must be a boolean, true or false, got 'yes'"),
    (lambda: indenters.Cylinder(radius=1.0, axis=True), r"axis must be 0 \(along x1\) or 1 \(along x2\), got True"),
    (lambda: indenters.Cylinder(radius=1.0, axis=1.0), r"axis must be 0 \(along x1\) or 1 \(along x2\), got 1.0"),
])
def test_flags_and_axes_must_be_what_they_say(factory, message):
    with pytest.raises(errors.ParameterError, match=message):
        factory()


@pytest.mark.parametrize("kwargs, message", [
    (dict(load={"value": 1.0}), r"load must be a number, a sequence of numbers or a loads history, got \{'value': 1.0\}"),
    (dict(load=[1, "a"]), r"load must be a number, a sequence of numbers or a loads history, got \[1, 'a'\]"),
    (dict(approach={}), r"approach must be a number, a sequence of numbers or a loads history, got \{\}"),
    (dict(load="5"), r"load must be a number, .*got '5'"),
    (dict(load=True), r"load must be a number, .*got True"),
    (dict(load={1.0, 2.0}), r"load must be a number, .*got \{1.0, 2.0\}"),
    (dict(load=[[1.0, 2.0]]), r"load must be a number, .*got \[\[1.0, 2.0\]\]"),
    (dict(load=[]), r"load is empty: give a number, one value per time or a loads history"),
    (dict(approach=np.array([])), r"approach is empty"),
    (dict(load=[]), r"^load is empty"),  # not blamed on times
    (dict(load=float("nan")), r"load must be finite everywhere, got nan at index \(0,\)"),
    (dict(load=[1.0, float("inf")], times=[0.0, 1.0]), r"load must be finite everywhere, got inf at index \(1,\)"),
    (dict(load=1e300), r"load must stay below 1e\+12 N, the range this framework accepts, got 1e\+300 N at t = 0 s"),
    (dict(approach=loads.Ramp(end=2e6, duration=1.0), times=[0.5, 1.0]), r"approach must stay below 1e\+06 m, .*"
                                                                           r"got 2000000.0 m at t = 1 s"),
    (dict(load=1.0, times=[0.0, 1e300]), r"times must be 0 or lie between 1e-15 and 1e\+15 s, .*got 1e\+300"),
    (dict(load=1.0, times=[0.0, 1e-300]), r"times must be 0 or lie between 1e-15 and 1e\+15 s, .*got 1e-300"),
])
def test_bad_loads_name_load_or_approach(kwargs, message):
    with pytest.raises(errors.ParameterError, match=message):
        schedules.Static(**kwargs)


def test_missing_depth_is_named():
    with pytest.raises(errors.ParameterError, match=r"depth is missing: layers = 4 needs the depth \[m\]"):
        fw.Grid(shape=(8, 8), size=(1.0, 1.0), layers=4)


@pytest.mark.parametrize("shape, periodic, message", [
    ((1, 1), (False, False), r"grid: shape\[0\] must be >= 3 along the non-periodic axis x1 .*got 1"),
    ((16, 2), (False, False), r"grid: shape\[1\] must be >= 3 along the non-periodic axis x2 .*got 2"),
    ((2, 16), (False, True), r"grid: shape\[0\] must be >= 3 along the non-periodic axis x1"),
])
def test_too_few_cells_for_a_contact(shape, periodic, message):
    with pytest.raises(errors.ParameterError, match=message):
        simulation(grid=fw.Grid(shape=shape, size=(1e-3, 1e-3), periodic=periodic))


def test_one_cell_along_a_periodic_axis_is_a_line_contact():
    """A body uniform along a periodic axis needs one cell there: Hertz's line contact (half width b)."""
    grid = fw.Grid(shape=(401, 1), size=(2e-3, 1e-4), periodic=(False, True))
    result = simulation(grid=grid, indenter=indenters.Cylinder(radius=5e-3, axis=1)).run()
    load_per_length = 1.0 / 1e-4
    b = np.sqrt(4 * load_per_length * 5e-3 / (np.pi * ELASTIC.contact_modulus))  # Johnson (1985) eq. 4.43
    width = np.count_nonzero(result.pressure(0)[:, 0] > 0) * grid.spacing[0] / 2
    assert abs(width / b - 1) < 0.02


# --------------------------------------------------------------------------- sizes out of range

@pytest.mark.parametrize("factory, message", [
    (lambda v: fw.Grid(shape=(8, 8), size=(v, 1e-3)), r"size\[0\] must lie between 1e-12 and 1e\+06 m"),
    (lambda v: fw.Grid(shape=(8, 8), size=(1e-3, 1e-3), depth=v, layers=2), r"depth must lie between 1e-12 and 1e\+06 m"),
    (lambda v: materials.Elastic(young=v, poisson=0.3), r"young must lie between 0.001 and 1e\+15 Pa"),
    (lambda v: materials.Viscoelastic.from_prony(e_inf=v, terms=[(1e9, 1.0)], poisson=0.3),
     r"e_inf must lie between 0.001 and 1e\+15 Pa"),
    (lambda v: materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(1e9, v)], poisson=0.3),
     r"terms\[0\] relaxation time must lie between 1e-40 and 1e\+40 s"),
    (lambda v: materials.Viscoelastic.from_creep(j0=1e-9, terms=[(1e-9, v)], poisson=0.3),
     r"terms\[0\] retardation time must lie between 1e-40 and 1e\+40 s"),
    (lambda v: materials.StandardLinearSolid(e_inf=1e9, e_1=1e9, tau=v, poisson=0.3), r"tau must lie between"),
    (lambda v: materials.Maxwell(young=v, relaxation_time=1.0, poisson=0.3), r"young must lie between"),
    (lambda v: materials.Maxwell(young=1e9, relaxation_time=v, poisson=0.3), r"relaxation_time must lie between"),
    (lambda v: materials.KelvinVoigt(young=1e9, viscosity=v, poisson=0.3),
     r"viscosity must lie between 1e-06 and 1e\+24 Pa s"),
    (lambda v: indenters.Sphere(radius=v), r"radius must lie between 1e-12 and 1e\+06 m"),
    (lambda v: indenters.FlatPunch(radius=v), r"radius must lie between"),
    (lambda v: indenters.RoundedFlatPunch(flat_radius=v, edge_radius=1e-3), r"flat_radius must lie between .*\(or be 0\)"),
    (lambda v: indenters.RoundedFlatPunch(flat_radius=0.0, edge_radius=v), r"edge_radius must lie between"),
    (lambda v: indenters.Cylinder(radius=v), r"radius must lie between"),
    (lambda v: loads.Ramp(end=1.0, duration=v), r"duration must lie between 1e-15 and 1e\+15 s"),
    (lambda v: loads.Ramp(end=1.0, duration=1.0, start=v), r"start must lie between .*\(or be 0\)"),
    (lambda v: loads.Step(1.0, at=v), r"at must lie between 1e-15 and 1e\+15 s \(or be 0\)"),
    (lambda v: loads.Hold(duration=v), r"duration must lie between"),
    (lambda v: loads.Cyclic(mean=1.0, amplitude=0.5, period=v), r"period must lie between"),
    (lambda v: loads.Table(times=[0.0, v], values=[0.0, 1.0]), r"times must be 0 or lie between"),
    (lambda v: schedules.Static(load=v), r"load must stay below 1e\+12 N"),
])
@pytest.mark.parametrize("value", [1e-300, 1e300])
def test_values_far_outside_any_physical_range(factory, message, value):
    """1e-300 and 1e300 gave ZeroDivisionError, OverflowError or a misleading message deep inside a run."""
    if "stay below" in message and value < 1:
        factory(value)  # a tiny load is fine: a history passes through small values
        return
    with pytest.raises(errors.ParameterError, match=rf"{message}.*got {re.escape(repr(value))}"):
        factory(value)


def test_ranges_extremes_run():
    """Values at the edges of the accepted ranges give finite results (or a clear error), no arithmetic fault."""
    with np.errstate(over="raise", divide="raise", invalid="raise"):
        for tau in (1e-15, 1e15):
            material = materials.StandardLinearSolid(e_inf=1e9, e_1=1e9, tau=tau, poisson=0.3)
            result = simulation(material=material, schedule=schedules.Static(load=1.0, times=[0.0, 1e-15, 1e15])).run()
            assert np.all(np.isfinite(result.approach))
        big = fw.Grid(shape=(16, 16), size=(1e6, 1e6))
        result = simulation(grid=big, indenter=indenters.Sphere(radius=1e6), schedule=schedules.Static(load=1e12)).run()
        assert np.all(np.isfinite(result.max_pressure)) and result.load[0] == pytest.approx(1e12)
        for e_inf, e_1, tau in [(1e-3, 1e15, 1e-15), (1e15, 1e-3, 1e15), (1e-3, 1e-3, 1e15)]:
            material = materials.Viscoelastic.from_prony(e_inf=e_inf, terms=[(e_1, tau)], poisson=0.3)
            assert material.creep(0.0) * (e_inf + e_1) == pytest.approx(1.0, rel=1e-12)
            assert material.creep(np.inf) * e_inf == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("factory", [
    lambda: materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(1e-300, 1.0), (1e9, 10.0)], poisson=0.3),
    lambda: materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(5e-324, 1e-15), (1e9, 10.0)], poisson=0.3),
    lambda: materials.Viscoelastic.from_creep(j0=1e3, terms=[(1e-15, 1e-15)], poisson=0.3),
    lambda: materials.Viscoelastic.from_creep(j0=1e-9, terms=[(1e-300, 1.0), (1e-9, 10.0)], poisson=0.3),
])
def test_negligible_prony_terms_are_named(factory):
    """A term weaker than rounding used to divide by zero in the conversion."""
    with pytest.raises(errors.ParameterError, match=r"a Prony term is too weak to resolve in double precision: .*"
                                                     r"1/rate = .* s\); drop the negligible term"):
        factory()


def test_creep_data_with_a_relaxed_modulus_out_of_range():
    with pytest.raises(errors.ParameterError, match=r"j0 plus the terms' compliances, J\(inf\) = 1/e_inf, must stay "
                                                     r"below 1000 1/Pa, .*got 2000.0"):
        materials.Viscoelastic.from_creep(j0=1e3, terms=[(1e3, 1.0)], poisson=0.3)


def test_height_map_out_of_range():
    with pytest.raises(errors.ParameterError, match=r"HeightMap height must lie within \+/-1e\+06 m, got 1e\+300 at "
                                                     r"index \(2, 3\)"):
        heights = np.zeros((16, 16))
        heights[2, 3] = 1e300
        simulation(indenter=indenters.HeightMap(heights))
    with pytest.raises(errors.ParameterError, match=r"HeightMap height must be an array of real numbers"):
        simulation(indenter=indenters.HeightMap(lambda x1, x2: np.full(x1.shape, "high")))
    with pytest.raises(errors.ShapeError, match=r"HeightMap height has shape \(\), expected \(16, 16\)"):
        simulation(indenter=indenters.HeightMap(lambda x1, x2: 0.0))


# --------------------------------------------------------------------------- found when the simulation is built

def test_offset_outside_the_body_is_refused_before_any_step():
    schedule = schedules.Eccentric(load=1.0, offset=(4e-4, 0.0))
    with pytest.raises(errors.LoadNotCarriedError, match=r"offset \(0.0004, 0.0\) m lies outside the area"):
        simulation(indenter=indenters.FlatPunch(radius=1e-4), schedule=schedule)


def test_sudden_change_on_a_kelvin_voigt_solid_is_refused_before_any_step():
    solid = materials.KelvinVoigt(young=1e9, viscosity=1e9, poisson=0.3)
    history = loads.Sequence([loads.Ramp(1.0, 1.0), loads.Step(2.0)])
    with pytest.raises(errors.ParameterError, match=r"no instantaneous compliance .* cannot change suddenly, as it "
                                                     r"does at t = 1 s \(from 1 to 2\)"):
        simulation(material=solid, schedule=schedules.Static(load=history, times=[0.5, 1.0, 2.0]))


def test_a_schedule_with_too_many_steps_is_refused():
    history = loads.Cyclic(mean=10.0, amplitude=5.0, period=1e-3, cycles=10**6)
    with pytest.raises(errors.ParameterError, match=r"the schedule needs 32000002 time steps up to t = 1000 s .*"
                                                     r"32 steps per period, .*\), more than 1000000"):
        simulation(material=materials.PMMA, schedule=schedules.Static(load=history, times=[0.0, 1e3]))


def test_center_at_zero_load_is_the_point_of_application():
    """No pressure, no centroid: the centre is then where the schedule applies the load (no NaN)."""
    result = simulation(schedule=schedules.Static(load=[0.0, 1.0], times=[0.0, 1.0])).run()
    assert np.array_equal(result.center[0], [0.0, 0.0]) and np.all(np.isfinite(result.center))
    punch = indenters.RoundedFlatPunch(flat_radius=2e-4, edge_radius=1e-3)
    schedule = schedules.Eccentric(load=[0.0, 1.0], offset=(5e-5, -2e-5), times=[0.0, 1.0])
    result = simulation(indenter=punch, schedule=schedule).run()
    assert np.array_equal(result.center[0], [5e-5, -2e-5])
    assert np.allclose(result.center[1], [5e-5, -2e-5], atol=1e-12)  # where the load acts, balanced
    assert not np.isnan(result.summary()["center_x1"]).any()
