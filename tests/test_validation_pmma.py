"""Seed 001's findings on PMMA (rounded punch, 25 cells per initial contact radius, 12 times)."""
import os
import runpy

import numpy as np
import pytest

EXAMPLE = runpy.run_path(os.path.join(os.path.dirname(__file__), "..", "examples", "rounded_punch_pmma.py"))


@pytest.fixture(scope="module")
def changes():
    """Relative change over 1000 s of area, maximum and central pressure, per flat ratio."""
    out = {}
    for ratio in EXAMPLE["RATIOS"]:
        result, _ = EXAMPLE["run_case"](ratio, cells=75, steps=12)
        centre = np.unravel_index(np.argmin(np.hypot(*result.grid.coordinates())), result.grid.shape)
        central = np.array([result.pressure(k)[centre] for k in range(len(result))])
        assert np.all(np.diff(result.contact_area) >= 0)
        assert np.all(np.diff(result.max_pressure) <= 1e-9 * result.max_pressure[0])
        assert np.all(np.diff(central) <= 1e-9 * central[0])
        out[ratio] = (result.contact_area[-1] / result.contact_area[0] - 1,
                      result.max_pressure[-1] / result.max_pressure[0] - 1, central[-1] / central[0] - 1)
    return out


def test_area_grows_and_pressures_fall(changes):
    for area, peak, central in changes.values():
        assert area > 0.02 and peak < -0.05 and central < -0.02


def test_the_smaller_the_flat_the_larger_the_changes(changes):
    ratios = sorted(changes)
    for small, large in zip(ratios[:-1], ratios[1:]):
        assert changes[small][0] > changes[large][0]
        assert changes[small][1] < changes[large][1]
        assert changes[small][2] < changes[large][2]
