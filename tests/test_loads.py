"""Load and approach histories: values, jumps and kinks, and bad input."""
import numpy as np
import pytest

from framework import errors, loads, schedules


def test_sequence_chains_segments():
    history = loads.Sequence([loads.Ramp(100.0, 10.0), loads.Hold(100.0), loads.Ramp(0.0, 10.0), loads.Hold(300.0)])
    t = np.array([0.0, 5.0, 10.0, 50.0, 110.0, 115.0, 120.0, 400.0])
    assert np.allclose(history(t), [0, 50, 100, 100, 100, 50, 0, 0])
    assert history.kinks == (0.0, 10.0, 110.0, 120.0) and history.jumps == ()
    assert history.span == 420.0


def test_steps_in_a_sequence_jump_with_both_sides_known():
    history = loads.Sequence([loads.Step(5.0), loads.Hold(2.0), loads.Step(8.0), loads.Hold(1.0, value=2.0)])
    assert history.jumps == (0.0, 2.0, 2.0)
    assert float(history.left(2.0)) == 5.0 and float(history(2.0)) == 2.0
    assert float(history(-1.0)) == 0.0 and float(history(0.0)) == 5.0


def test_cyclic_shapes():
    sine = loads.Cyclic(mean=50.0, amplitude=20.0, period=4.0, cycles=2)
    assert np.allclose(sine(np.array([0.0, 1.0, 3.0, 8.0, 20.0])), [50, 70, 30, 50, 50])
    triangle = loads.Cyclic(mean=50.0, amplitude=20.0, period=4.0, cycles=2, shape="triangle")
    assert np.allclose(triangle(np.array([0.5, 1.0, 2.0, 3.0])), [60, 70, 50, 30])
    assert triangle.kinks[:3] == (1.0, 3.0, 5.0)


def test_table_and_step_alone():
    table = loads.Table(times=[1.0, 2.0], values=[3.0, 4.0])
    assert np.allclose(table(np.array([0.0, 1.0, 1.5, 3.0])), [0, 3, 3.5, 4])
    assert float(loads.Step(5.0, at=2.0)(1.0)) == 0.0 and float(loads.Step(5.0, at=2.0)(2.0)) == 5.0


@pytest.mark.parametrize("factory, message", [
    (lambda: loads.Table(times=[0.0, 2.0, 1.0], values=[1.0, 2.0, 3.0]),
     r"times must be strictly increasing, got 2.0 followed by 1.0 at index 2"),
    (lambda: loads.Table(times=[0.0, 1.0], values=[1.0]), r"same non-zero length, got 2 and 1"),
    (lambda: loads.Table(times=[-1.0, 1.0], values=[1.0, 2.0]), r"times must be >= 0 \[s\], got -1.0"),
    (lambda: loads.Ramp(1.0, duration=0.0), r"duration must be positive \[s\], got 0.0"),
    (lambda: loads.Hold(-2.0), r"duration must be >= 0 \[s\], got -2.0"),
    (lambda: loads.Cyclic(mean=1.0, amplitude=1.0, period=1.0, shape="square"), r"shape must be 'sine' or 'triangle'"),
    (lambda: loads.Cyclic(mean=1.0, amplitude=1.0, period=1.0, cycles=0), r"cycles must be an integer >= 1, got 0"),
    (lambda: loads.Sequence([]), r"segments must be a non-empty list"),
])
def test_bad_histories(factory, message):
    with pytest.raises(errors.ParameterError, match=message):
        factory()


def test_history_with_negative_load_is_rejected_by_the_schedule():
    history = loads.Sequence([loads.Ramp(10.0, 1.0), loads.Ramp(-5.0, 1.0)])
    with pytest.raises(errors.ParameterError, match=r"load must be >= 0 at every time, got -"):
        schedules.Static(load=history, times=[0.5, 1.0, 2.0])


def test_cyclic_load_dipping_below_zero_is_rejected():
    with pytest.raises(errors.ParameterError, match=r"load must be >= 0"):
        schedules.Static(load=loads.Cyclic(mean=1.0, amplitude=2.0, period=1.0), times=np.linspace(0.1, 1.0, 10))
