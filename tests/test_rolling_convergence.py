"""Grid refinement of the steady rolling friction at the resolution examples/rolling_friction.py uses.

The issue asks for the friction coefficient converged to 1 % at the example's
resolution. The cases, grids and solver options are the example's own (its
module is loaded here): a sphere (W = 0.2 N on the standard linear solid
E(t) = 10 + 90 exp(-t / 1 s) MPa, nu = 0.5; W = 8 N on PMMA) and a cylinder
(W' = 100 N/m on the solid, 16 kN/m on PMMA), R = 10 mm, at the friction
peak (the example's sampled speed V T / a0 nearest it), on steady grids of
``cells`` square cells per 3 relaxed contact sizes (``CELLS = 96`` in the
example).

Observed (friction relative to a finer solve):

* cylinder, 96 cells against 512: SLS -1.2e-4, PMMA +1.2e-4; least-squares
  order over 10 resolutions from 16 to 128 cells against 512: 1.7 (SLS),
  2.5 (PMMA).
* sphere, 96 cells against 192: SLS -4.3e-5, PMMA -2.5e-4; least-squares
  order over 10 resolutions from 16 to 96 against 192: 3.2 (SLS), 2.3 (PMMA)
  (inflated by the nearness of the reference).

The error oscillates as the contact edges cross cells (from 16 to 64 cells
the cylinder on SLS loses 1.8e-3, 3.9e-4 and 1.9e-4 of its friction: orders
2.2, then 1.0), so three resolutions give almost any order: the order is
fitted by least squares over ten, and asserted above 1.
"""
import os
import runpy

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLE = runpy.run_path(os.path.join(ROOT, "examples", "rolling_friction.py"))
CASES = {case.name: case for case in EXAMPLE["CASES"]}
CELLS = EXAMPLE["CELLS"]
#: The friction peak of each case among the example's speeds (4 per decade): V T / a0.
PEAK = {"sphere_sls": 1.0, "sphere_pmma": 1.0, "cylinder_sls": 10**0.25, "cylinder_pmma": 10**0.5}


def friction(name, cells):
    """Steady friction coefficient of the example's case ``name`` at its peak, on ``cells`` cells."""
    return EXAMPLE["steady"](CASES[name], PEAK[name], cells).friction_coefficient[0]


def observed_order(name, finest, exact, count=10):
    """Least-squares slope of log |mu_n / exact - 1| against log(1/n), n = 16 .. finest (even, log-spaced)."""
    cells = np.unique(np.round(np.geomspace(16, finest, count) / 2).astype(int) * 2)
    errors = np.array([abs(friction(name, int(n)) / exact - 1) for n in cells])
    return np.polyfit(np.log(1.0 / cells), np.log(errors), 1)[0]


def test_the_example_resolution_is_the_one_tested():
    assert CELLS == 96
    assert EXAMPLE["main"].__defaults__[0] == CELLS


@pytest.mark.parametrize("name", ["cylinder_sls", "cylinder_pmma"])
def test_line_contact_friction_is_converged_to_1_percent(name):
    """The example's resolution against 512 cells; the order from 10 resolutions (16 to 128 cells)."""
    mu = friction(name, CELLS)
    finer = friction(name, 512)
    assert mu > 1e-3
    assert abs(mu / finer - 1) < 0.01
    assert observed_order(name, finest=128, exact=finer) > 1.0


def test_sphere_friction_changes_by_far_less_than_1_percent_from_half_the_example_resolution():
    """Default-suite check (the sphere at 2x the example's cells takes ~10 s): halving the cells moves mu by < 0.2 %.

    With the error falling at order > 1 (the slow test), the example's error is then below 0.1 %.
    """
    coarse, example = friction("sphere_sls", CELLS // 2), friction("sphere_sls", CELLS)
    assert example > 0.01
    assert abs(coarse / example - 1) < 0.002


@pytest.mark.slow
@pytest.mark.parametrize("name", ["sphere_sls", "sphere_pmma"])
def test_sphere_friction_is_converged_to_1_percent(name):
    """The example's resolution against 1.5 and 2 times finer; the order from 10 resolutions (16 to 96 cells)."""
    mu = friction(name, CELLS)
    finer = [friction(name, int(factor * CELLS)) for factor in (1.5, 2)]
    for value in finer:
        assert abs(mu / value - 1) < 0.01
    assert observed_order(name, finest=CELLS, exact=finer[-1]) > 1.0
