"""Bad input gets a specific exception naming the parameter and the value."""
import numpy as np
import pytest

import framework as fw
from framework import errors, indenters, loads, materials, schedules


@pytest.mark.parametrize("young", [0.0, -1e9, float("nan"), "steel"])
def test_non_positive_or_non_numeric_modulus(young):
    with pytest.raises(errors.ParameterError, match=r"young must be .*got"):
        materials.Elastic(young=young, poisson=0.3)


@pytest.mark.parametrize("poisson", [0.6, -1.0, -1.5, 0.5000001])
def test_poisson_outside_range(poisson):
    with pytest.raises(errors.ParameterError, match=rf"poisson must lie in \(-1, 0.5\], got {poisson!r}"):
        materials.Elastic(young=1e9, poisson=poisson)


def test_poisson_limits_inside_range():
    assert materials.Elastic(young=1e9, poisson=0.5).contact_modulus == pytest.approx(4e9 / 3)
    assert materials.Elastic(young=1e9, poisson=-0.99).poisson == -0.99


def small_simulation(load, **kwargs):
    grid = fw.Grid(shape=(32, 32), size=(1e-3, 1e-3))
    return fw.Simulation(grid=grid, material=materials.Elastic(young=1e9, poisson=0.3),
                         indenter=indenters.Sphere(radius=5e-3), schedule=schedules.Static(load=load), **kwargs)


def test_load_too_large_for_the_grid():
    with pytest.raises(errors.GridTooSmallError, match=r"grid edge .* load = 500 .*enlarge size"):
        small_simulation(500.0).run()


def test_finished_steps_survive_a_late_failure():
    sim = small_simulation([1.0, 2.0, 500.0])
    with pytest.raises(errors.GridTooSmallError) as info:
        sim.run()
    assert len(info.value.partial_result) == 2
    assert sim.result.load[-1] == pytest.approx(2.0)


def test_non_finite_height_map():
    heights = np.zeros((32, 32))
    heights[3, 4] = np.nan
    with pytest.raises(errors.ParameterError, match=r"heights must be finite everywhere, got nan at index \(3, 4\)"):
        indenters.HeightMap(heights)


def test_callable_height_map_returning_inf():
    """Found when the simulation is built, before any step."""
    with pytest.raises(errors.ParameterError, match="HeightMap height must be finite"):
        with np.errstate(divide="ignore", invalid="ignore"):
            fw.Simulation(grid=fw.Grid(shape=(8, 8), size=(1.0, 1.0)),
                          material=materials.Elastic(young=1e9, poisson=0.3),
                          indenter=indenters.HeightMap(lambda x1, x2: 1 / (x1 - x1)),
                          schedule=schedules.Static(load=1.0))


def test_height_map_of_the_wrong_shape():
    with pytest.raises(errors.ShapeError, match=r"\(6, 8\).*\(8, 6\)"):
        fw.Simulation(grid=fw.Grid(shape=(8, 6), size=(1.0, 1.0)),
                      material=materials.Elastic(young=1e9, poisson=0.3),
                      indenter=indenters.HeightMap(np.zeros((6, 8))), schedule=schedules.Static(load=1.0))


@pytest.mark.parametrize("kwargs, message", [
    (dict(shape=(0, 4), size=(1.0, 1.0)), r"shape\[0\] must be an integer >= 1, got 0"),
    (dict(shape=(4,), size=(1.0, 1.0)), r"shape must be a pair"),
    (dict(shape=(4, 4), size=(1.0, -2.0)), r"size\[1\] must be positive \[m\], got -2.0"),
    (dict(shape=(4, 4), size=(1.0, 1.0), layers=3), r"depth is missing: layers = 3 needs the depth \[m\]"),
    (dict(shape=(4, 4), size=(1.0, 1.0), depth=1.0, layers=-1), r"layers must be an integer >= 0, got -1"),
    (dict(shape=(4, 4), size=(1.0, 1.0), periodic=(1, 0)), r"periodic\[0\] must be a boolean, true or false, got 1"),
])
def test_bad_grids(kwargs, message):
    with pytest.raises(errors.ParameterError, match=message):
        fw.Grid(**kwargs)


@pytest.mark.parametrize("factory, message", [
    (lambda: indenters.Sphere(radius=0.0), r"radius must be positive \[m\], got 0.0"),
    (lambda: indenters.RoundedFlatPunch(flat_radius=-1e-3, edge_radius=1e-3), r"flat_radius must be >= 0"),
    (lambda: indenters.Cylinder(radius=1.0, axis=2), r"axis must be 0 .* got 2"),
])
def test_bad_indenters(factory, message):
    with pytest.raises(errors.ParameterError, match=message):
        factory()


@pytest.mark.parametrize("kwargs, message", [
    (dict(load=1.0, approach=1e-6), "give exactly one of load and approach"),
    (dict(), "give exactly one of load and approach"),
    (dict(load=-1.0), r"load must be >= 0 at every time, got -1.0"),
    (dict(load=[1.0, 2.0], times=[0.0, 0.0]), r"times must be strictly increasing, got 0.0 followed by 0.0"),
    (dict(load=[1.0, 2.0], times=[0.0]), r"load has 2 values but times has 1 entries"),
    (dict(load=1.0, times=[-1.0, 1.0]), r"times must be >= 0 \[s\], got -1.0"),
    (dict(approach=loads.Ramp(end=-1e-6, duration=1.0), times=[0.5, 1.0]), r"approach must be >= 0"),
])
def test_bad_schedules(kwargs, message):
    with pytest.raises(errors.ParameterError, match=message):
        schedules.Static(**kwargs)


def test_solver_that_does_not_converge_raises_with_its_figures():
    sim = small_simulation(1.0, options={"max_iterations": 2})
    with pytest.raises(errors.ConvergenceError, match=r"stopped after 2 iterations .* raise max_iterations") as info:
        sim.run()
    assert not info.value.result.success


def test_solver_may_continue_when_asked():
    result = small_simulation(1.0, options={"max_iterations": 2, "raise_on_failure": False}).run()
    assert not result.records[0].success


def test_unknown_option():
    with pytest.raises(errors.ParameterError, match=r"unknown option\(s\) \['tolerence'\]"):
        small_simulation(1.0, options={"tolerence": 1e-3})


def test_stress_without_layers_and_bad_step():
    result = small_simulation(1.0).run()
    with pytest.raises(errors.ParameterError, match="layers=0"):
        result.stress(0)
    with pytest.raises(errors.ParameterError, match=r"step must be an integer index in \[-1, 1\), got 3"):
        result.pressure(3)


def test_errors_are_builtin_subclasses():
    assert issubclass(errors.ParameterError, ValueError)
    assert issubclass(errors.ShapeError, ValueError)
    assert issubclass(errors.ConvergenceError, RuntimeError)
