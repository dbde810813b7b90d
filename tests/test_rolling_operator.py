"""The steady-rolling compliance: the exponential filter of the kernel along the motion.

References written here: adaptive quadrature (scipy.integrate.quad) of
``int_0^inf (1/L) exp(-xi/L) K(r + xi) dxi`` with Love's rectangle kernel (and
the plane-strain strip kernel) evaluated directly, and the limits of slow and
fast motion.
"""
import warnings

import numpy as np
import pytest
from scipy import integrate

import framework as fw
from framework import materials
from framework.operators.kernels import surface_displacement
from framework.operators import rolling
from framework.operators.rolling import SteadyRollingCompliance, exponential_filter, steady_rolling_kernel
from framework.operators.surface import SurfaceCompliance

DX = 1e-5  # m


def love_row(x2):
    """Love's kernel along x1 at the fixed offset x2 (per unit compliance)."""
    return lambda x: surface_displacement(np.asarray(x)[:, None], x2, half1=DX / 2, half2=DX / 2)


def filtered_by_quadrature(kernel, r, length):
    """``int_0^{80 L} (1/L) exp(-xi/L) K(r + xi) dxi`` (the rest is below 1e-34), breakpoints at the cell edges."""
    def f(xi):
        return np.exp(-xi / length) / length * float(kernel(np.array([r + xi]))[0, 0])
    edges = [e - r for e in (-DX / 2, DX / 2) if 0 < e - r < 80 * length]
    with warnings.catch_warnings():  # quad may doubt reaching 1e-11 on the log kernel; the 1e-10 comparison tells
        warnings.simplefilter("ignore", integrate.IntegrationWarning)
        return integrate.quad(f, 0.0, 80 * length, points=edges or None, limit=500, epsabs=0, epsrel=1e-11)[0]


@pytest.mark.parametrize("length", [0.01 * DX, 0.7 * DX, 5 * DX, 300 * DX])
@pytest.mark.parametrize("x2", [0.0, 2 * DX])
def test_filter_of_love_kernel_against_quadrature(length, x2):
    n = 12
    values = exponential_filter(love_row(x2), DX, n, length)[:, 0]
    offsets = np.arange(-(n - 1), n) * DX
    for j in (0, n - 3, n - 2, n - 1, n, 2 * n - 2):
        reference = filtered_by_quadrature(love_row(x2), offsets[j], length)
        assert values[j] == pytest.approx(reference, rel=1e-10, abs=1e-13 * values.max())


@pytest.mark.parametrize("length", [0.01 * DX, 0.7 * DX, 5 * DX, 300 * DX])
@pytest.mark.parametrize("cells", [1, 2, 5])
def test_plain_rule_off_the_loaded_column_against_quadrature(length, cells):
    """Off the loaded cell's column Love's kernel is analytic along the motion: the plain rules the steady
    kernel takes there (16 nodes a piece one column off, 10 farther) meet the adaptive quadrature too."""
    n, x2 = 12, cells * DX
    nodes = rolling._OFF_COLUMN_NODES[min(cells, 2)]
    values = exponential_filter(love_row(x2), DX, n, length, nodes=nodes)[:, 0]
    offsets = np.arange(-(n - 1), n) * DX
    for j in (0, n - 3, n - 2, n - 1, n, 2 * n - 2):
        reference = filtered_by_quadrature(love_row(x2), offsets[j], length)
        assert values[j] == pytest.approx(reference, rel=1e-10, abs=1e-13 * values.max())


@pytest.mark.parametrize("axis", [0, 1])
def test_steady_kernel_with_plain_rules_equals_the_graded_one(monkeypatch, axis):
    """The steady kernel assembled from the three column groups equals the one with the graded rule on every
    column (checked against quadrature above) to 1e-12: the groups land on their columns."""
    shape = (12, 9) if axis == 0 else (9, 12)
    grid = fw.Grid(shape=shape, size=(shape[0] * DX, shape[1] * DX))
    solid = materials.StandardLinearSolid(e_inf=1e6, e_1=9e6, tau=1.0, poisson=0.5)
    velocity = (3 * DX, 0.0) if axis == 0 else (0.0, -3 * DX)
    fast = steady_rolling_kernel(grid, solid.contact_compliance(), velocity)
    love_along = rolling._love_along

    def graded(grid, axis):
        kernel, expand, groups = love_along(grid, axis)
        assert [nodes for _, nodes in groups] == [None, 16, 10]
        return kernel, expand, [(np.sort(np.concatenate([columns for columns, _ in groups])), None)]
    monkeypatch.setattr(rolling, "_love_along", graded)
    reference = steady_rolling_kernel(grid, solid.contact_compliance(), velocity)
    assert np.abs(fast - reference).max() <= 1e-12 * np.abs(reference).max()


def test_filter_limits():
    n = 8
    kernel = love_row(DX)
    direct = kernel(np.arange(-(n - 1), n) * DX)[:, 0]
    slow = exponential_filter(kernel, DX, n, 1e-6 * DX)[:, 0]
    np.testing.assert_allclose(slow, direct, rtol=1e-5)          # L -> 0: the kernel itself (error ~ L K')
    fast = exponential_filter(kernel, DX, n, 1e9 * DX)[:, 0]
    assert fast.max() < 1e-7 * direct.max()                       # L -> inf: nothing responds yet


def test_elastic_steady_kernel_is_the_elastic_operator():
    grid = fw.Grid(shape=(9, 6), size=(9 * DX, 6 * DX))
    steel = materials.Elastic(young=210e9, poisson=0.3)
    moving = SteadyRollingCompliance(grid, steel.contact_compliance(), (3.0, 0.0))
    still = SurfaceCompliance(grid)
    p = np.random.default_rng(0).random(grid.shape)
    np.testing.assert_allclose(moving.apply(p), still.apply(p) / steel.contact_modulus, rtol=1e-13)


@pytest.mark.parametrize("periodic", [(False, False), (False, True), (True, False)])
def test_reversed_motion_mirrors_the_kernel(periodic):
    shape = (8, 5) if periodic != (True, False) else (5, 8)
    grid = fw.Grid(shape=shape, size=(shape[0] * DX, shape[1] * DX), periodic=periodic)
    solid = materials.StandardLinearSolid(e_inf=1e6, e_1=9e6, tau=1.0, poisson=0.5)
    axis = 1 if periodic[0] else 0
    velocity = np.zeros(2)
    velocity[axis] = 4 * DX
    forward = SteadyRollingCompliance(grid, solid.contact_compliance(), tuple(velocity))
    backward = SteadyRollingCompliance(grid, solid.contact_compliance(), tuple(-velocity))
    p = np.random.default_rng(1).random(grid.shape)
    mirrored = np.flip(backward.apply(np.flip(p, axis)), axis)
    np.testing.assert_allclose(forward.apply(p), mirrored, rtol=1e-12)
    assert not np.allclose(forward.apply(p), backward.apply(p), rtol=1e-3, atol=0)   # the motion matters


def test_line_contact_filter_against_quadrature():
    """Plane strain (mode q = 0 of a grid periodic along x2): the filtered strip kernel."""
    from framework.operators.surface import mixed_mode_kernel
    grid = fw.Grid(shape=(10, 4), size=(10 * DX, 4 * DX), periodic=(False, True))
    kernel = mixed_mode_kernel(grid)
    for length in (0.3 * DX, 20 * DX):
        values = exponential_filter(kernel, DX, 10, length)
        for j in (5, 9, 18):
            r = (j - 9) * DX
            for mode in (0, 1):
                reference = filtered_by_quadrature(lambda x: kernel(x)[:, mode:mode + 1], r, length)
                assert values[j, mode] == pytest.approx(reference, rel=1e-10, abs=1e-12 * np.abs(values).max())


def test_fluid_and_periodic_motion_axis_are_refused():
    grid = fw.Grid(shape=(8, 8), size=(8 * DX, 8 * DX), periodic=(True, False))
    solid = materials.StandardLinearSolid(e_inf=1e6, e_1=9e6, tau=1.0, poisson=0.5)
    with pytest.raises(fw.errors.ParameterError, match="axis 0 of the grid is periodic"):
        steady_rolling_kernel(grid, solid.contact_compliance(), (1.0, 0.0))
    fluid = materials.Maxwell(young=1e6, relaxation_time=1.0, poisson=0.5)
    with pytest.raises(fw.errors.ParameterError, match="no steady rolling state"):
        steady_rolling_kernel(fw.Grid(shape=(8, 8), size=(1.0, 1.0)), fluid.contact_compliance(), (1.0, 0.0))
