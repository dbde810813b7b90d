"""The fused contact iteration (framework._fused) against the plain one it replaced.

``solver._iterate_reference`` is the Polonsky-Keer loop as plain numpy
expressions, kept as the reference. Both loops are run to a tolerance of 1e-14,
where each reaches the one solution of the discrete problem, so that pressures,
displacements, gaps and approaches must agree to 1e-12 of their largest value
whatever the rounding of the sums. Grids of 64^2 (open, with the box of the
windowed product) and 64^2 periodic; load and approach control; a rough
surface; a tilting punch.

One exception, approach control: both loops stop where the gap over the
contact is flat to 1e-12 of the displacement (the solver's rounding floor,
below which it takes no step), and there a pressure with no load to fix its
scale, and the displacement it makes, are only determined to a few times that:
between the compiled and the reference loop on the open grid, 1.5e-12 to 2e-11
from one process to the next (FFTW chooses its plans, and so its rounding, by
timing them): 1e-10.

Each case is solved with and without the preconditioner (the surface
stiffness, :class:`framework.operators.SurfaceStiffness`): fused against
reference in both, to the bounds above; preconditioned against plain to
1e-10: the two iterations stop at the same rounding floor (the gap over the
contact flat to 1e-12 of the displacement) by different paths, and the
pressure is only determined to the contact's condition number times that
(1.2e-11 to 3.6e-11 of the peak pressure measured on these 64^2 cases).
"""
import numpy as np
import pytest

import framework as fw
from framework import _fused, fft, indenters, materials, schedules, solver
from framework.errors import ParameterError
from framework.operators import SurfaceCompliance, SurfaceStiffness

ELASTIC = materials.Elastic(young=1e9, poisson=0.3)
TIGHT = fw.SolverOptions(tolerance=1e-14, residual_tolerance=1e-10)
COMPLIANCE = 1 / ELASTIC.contact_modulus
PASSES = [False, pytest.param(True, marks=pytest.mark.skipif(not _fused.numba_available(),
                                                              reason="numba is not installed (the jit extra)"))]


@pytest.fixture(autouse=True)
def compile_small_grids(monkeypatch):
    """The compiled passes on these small grids too (a run takes them from 128^2 cells)."""
    monkeypatch.setattr(_fused, "COMPILED_FROM", 0)


def solve(grid, heights, reference, preconditioned=False, **control):
    operator = SurfaceCompliance(grid)
    loop = solver._iterate_reference if reference else solver._iterate
    stiffness = SurfaceStiffness(grid)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(solver, "_iterate", loop)
        return fw.solve_normal(lambda p: operator.apply(p, COMPLIANCE, copy=False), heights,
                               cell_area=grid.cell_area, options=TIGHT, window=operator.window,
                               apply_window=lambda f, box: operator.apply_window(f, box, COMPLIANCE, copy=False),
                               precondition=stiffness if preconditioned else None,
                               **control)


def assert_same(fast, plain, tolerance=1e-12):
    for name in ("pressure", "displacement", "gap"):
        a, b = getattr(fast, name), getattr(plain, name)
        assert np.abs(a - b).max() <= tolerance * np.abs(b).max(), name
    assert fast.approach == pytest.approx(plain.approach, rel=tolerance)
    assert fast.load == pytest.approx(plain.load, rel=tolerance)
    assert fast.success and plain.success


@pytest.mark.parametrize("compiled", PASSES)
@pytest.mark.parametrize("periodic", [False, True])
@pytest.mark.parametrize("control", ["load", "approach"])
@pytest.mark.parametrize("preconditioned", [False, True])
def test_fused_loop_gives_the_reference_solution(compiled, periodic, control, preconditioned):
    """A sphere on 64^2 cells, contact radius about a quarter of the grid side."""
    grid = fw.Grid(shape=(64, 64), size=(2e-3, 2e-3), periodic=(periodic, periodic))
    heights = indenters.Sphere(radius=10e-3).on_grid(grid)
    arguments = {"load": 5.0} if control == "load" else {"approach": heights.min() + 1e-5}
    with _fused.use_compiled(compiled):
        fast = solve(grid, heights, False, preconditioned, **arguments)
    plain = solve(grid, heights, True, preconditioned, **arguments)
    # Both loops run at tolerance 1e-14, at the rounding floor; conjugate gradients amplify their rounding
    # differences mid-solve (to 4e-9 of the peak pressure, measured) before both converge again. With pyFFTW's
    # rounding they stop on the same iteration, 1e-12 apart; with scipy's (the fallback without pyFFTW) the
    # periodic plain case stops one iteration later, whose last step moves the pressure by 2.3e-11: within what
    # the stopping tests guarantee, as under approach control.
    assert_same(fast, plain, 1e-12 if control == "load" and fft.get_backend() == "pyfftw" else 1e-10)
    if preconditioned:   # the same solution as the plain Polonsky-Keer iteration, in fewer iterations
        unpreconditioned = solve(grid, heights, True, False, **arguments)
        assert_same(fast, unpreconditioned, 1e-10)
        assert fast.iterations < 0.7 * unpreconditioned.iterations
    # the displacement returned is the one of the pressure returned (the products write into reused buffers)
    check = SurfaceCompliance(grid).apply(fast.pressure, COMPLIANCE)
    assert np.abs(fast.displacement - check).max() <= 1e-13 * np.abs(check).max()
    assert fast.iterations > 5 and 0.05 < np.mean(fast.pressure > 0) < 0.5   # a real solve, not a trivial one


@pytest.mark.parametrize("compiled", PASSES)
@pytest.mark.parametrize("preconditioned", [False, True])
def test_fused_loop_gives_the_reference_rough_contact(compiled, preconditioned):
    """A random rough surface on a periodic 64^2 grid: many spots in every row, which merge and split."""
    grid = fw.Grid(shape=(64, 64), size=(1e-3, 1e-3), periodic=(True, True))
    rng = np.random.default_rng(7)
    spectrum = np.fft.rfft2(rng.standard_normal(grid.shape))
    q = np.hypot(*np.meshgrid(np.fft.fftfreq(64), np.fft.rfftfreq(64), indexing="ij"))
    spectrum *= np.where((q > 0) & (q < 0.2), np.maximum(q, 1e-3) ** -1.8, 0.0)
    heights = np.fft.irfft2(spectrum, grid.shape)
    heights *= 1e-6 / heights.std()   # 1 um rms
    with _fused.use_compiled(compiled):
        fast = solve(grid, heights, False, preconditioned, load=1.0)
    plain = solve(grid, heights, True, preconditioned, load=1.0)
    assert_same(fast, plain)
    if preconditioned:
        assert_same(fast, solve(grid, heights, True, False, load=1.0), 1e-10)
    touched = fast.pressure > 0
    assert 0.05 < touched.mean() < 0.5 and 0.5 < touched.any(axis=1).mean() < 1   # spots in most rows, not all


@pytest.mark.parametrize("compiled", PASSES)
@pytest.mark.parametrize("preconditioned", [False, True])
def test_fused_loop_gives_the_reference_tilt(compiled, preconditioned):
    """A flat punch on 64^2 cells under an eccentric load: the tilt and the clipped edge agree too."""
    grid = fw.Grid(shape=(64, 64), size=(3e-3, 3e-3))
    heights = indenters.FlatPunch(radius=1e-3).on_grid(grid)
    arguments = dict(load=10.0, offset=(0.4e-3, -0.1e-3), coordinates=grid.coordinates())
    with _fused.use_compiled(compiled):
        fast = solve(grid, heights, False, preconditioned, **arguments)
    plain = solve(grid, heights, True, preconditioned, **arguments)
    assert_same(fast, plain)
    assert fast.slopes == pytest.approx(plain.slopes, rel=1e-10)
    if preconditioned:
        unpreconditioned = solve(grid, heights, True, False, **arguments)
        assert_same(fast, unpreconditioned, 1e-10)
        assert fast.slopes == pytest.approx(unpreconditioned.slopes, rel=1e-9)
    assert 0 < np.mean(fast.pressure > 0) < np.mean(heights == heights.min())  # the far edge lifted off


def test_fused_loop_gives_the_reference_eccentric_run(monkeypatch):
    """Through the stepper: a ball creeping into a standard linear solid under an eccentric step load,
    three output times (the contact grows and moves, the ball tilts about both axes)."""
    grid = fw.Grid(shape=(48, 48), size=(3e-3, 3e-3))
    visco = materials.StandardLinearSolid(e_inf=1e9, e_1=2e9, tau=1.0, poisson=0.3)

    def run():
        return fw.Simulation(grid=grid, material=visco, indenter=indenters.Sphere(radius=10e-3),
                             schedule=schedules.Eccentric(load=10.0, offset=(0.1e-3, 0.05e-3), times=[0.0, 0.5, 3.0]),
                             options={"tolerance": 1e-14, "residual_tolerance": 1e-10}).run()
    fast = run()
    monkeypatch.setattr(solver, "_iterate", solver._iterate_reference)
    plain = run()
    for step in range(3):
        for field in (fast.pressure, fast.displacement):
            reference = getattr(plain, field.__name__)(step)
            assert np.abs(field(step) - reference).max() <= 1e-12 * np.abs(reference).max()
    assert np.allclose(fast.tilt, plain.tilt, rtol=1e-12, atol=0) and np.abs(plain.tilt).min() > 1e-4


@pytest.mark.skipif(not _fused.numba_available(), reason="numba is not installed (the jit extra)")
def test_compiled_passes_equal_numpy_passes():
    """Each pass on the same random fields (a contact set, free cells that interpenetrate): fields
    bit for bit where no sum is involved (but the preconditioned direction's two additions), sums to
    rounding (1e-12)."""
    rng = np.random.default_rng(3)
    shape = (37, 23)
    pressure = np.where(rng.random(shape) < 0.4, rng.random(shape), 0.0)
    pressure[:4] = pressure[30:] = 0.0     # rows without contact: the gap pass returns rows 4-29
    padded = rng.random((2 * shape[0], 2 * shape[1]))   # the displacement as a block of a padded FFT buffer
    fields = dict(base=rng.random(shape), displacement=padded[:shape[0], :shape[1]],
                  direction=rng.standard_normal(shape), response=rng.standard_normal((11, 7)),
                  spectrum=rng.standard_normal((9, 5)) + 1j * rng.standard_normal((9, 5)), multiplier=rng.random((9, 5)))
    results = {}
    for compiled in (False, True):
        with _fused.use_compiled(compiled):
            passes = _fused.passes()
            gap, contact = np.empty(shape), np.empty(shape, dtype=bool)
            direction, fresh = fields["direction"].copy(), np.empty(shape)
            flat = [a.reshape(-1) for a in (gap, contact, direction, fresh)]
            sums = [passes.gap(fields["base"], fields["displacement"], pressure, gap, contact, 0, shape[0])]
            # the gap stays b + u: the shift 0.7 where read
            sums.append(passes.norm(gap, contact, fields["base"], fields["displacement"], 0.7, 0, shape[0]))
            sums.append(passes.direction(flat[2], flat[0], flat[1], 0.3, 0.7))
            sums.append(passes.curvature(fields["response"], direction, contact, 5, 9))
            boxed = direction.copy()   # on rows 3-30 (the old contact's), with the box's contact
            box_contact = contact & np.pad(np.ones((21, 9), bool), ((6, 10), (8, 6)))  # the box: rows 6-26, columns 8-16
            sums.append(passes.direction_box(boxed, fields["base"][6:27, 8:17] - 0.4, gap,
                                             box_contact, 0.3, 0.1, 3, 31, 6, 8, 0.7))
            masked = np.empty((21, 9))
            passes.mask(masked, gap, contact, 6, 8, 0.7)
            sums.append(passes.preconditioned(fields["displacement"][6:27, 8:17], masked, contact, 6, 8))
            sums.append(passes.advance(flat[3], pressure.reshape(-1), flat[2], flat[0], flat[1], 0.2, 0.5, 0.7))
            sums.append(passes.rescale(flat[3], pressure.reshape(-1), 1.3))
            spectrum = fields["spectrum"].copy()
            passes.multiply(spectrum, fields["multiplier"])
            results[compiled] = (np.concatenate([np.ravel(s) for s in sums]), gap, contact, direction, fresh, masked,
                                 spectrum, boxed)
    numpy_sums, compiled_sums = results[False][0], results[True][0]
    assert tuple(numpy_sums[3:5]) == tuple(compiled_sums[3:5]) == (4, 30)
    numpy_sums[2] = compiled_sums[2] = 0.0  # the numpy pass returns max u^4, the compiled one the bound sum u^4
    assert np.allclose(compiled_sums, numpy_sums, rtol=1e-12, atol=0)
    for a, b in zip(results[False][1:-1], results[True][1:-1]):
        assert np.array_equal(a, b)
    # beta d + z - mean: two additions the compiler may reassociate
    assert np.allclose(results[True][-1], results[False][-1], rtol=1e-15, atol=1e-15)
    walked = results[True][-1][3:31]    # the rows walked: the direction on the box's contact only
    assert np.array_equal(walked != 0, box_contact[3:31])
    rest = [np.delete(a, np.s_[3:31], axis=0) for a in (results[True][-1], results[True][3])]
    assert np.array_equal(*rest)      # the rows not walked, as they were
    assert results[False][2].any() and not results[False][2].all() and (results[False][4] > 0).any()
    assert np.array_equal(results[False][5], np.where(contact[6:27, 8:17], gap[6:27, 8:17] - 0.7, 0.0))
    assert np.array_equal(results[False][6], fields["spectrum"] * fields["multiplier"])


@pytest.mark.parametrize("compiled", PASSES)
def test_gap_and_norm_passes_on_the_pressure_rows(compiled):
    """The gap pass writes only the rows where the pressure may be positive (rows 3-30 of 37); the norm
    pass counts the interpenetrating free cells of the other rows from the separation and the displacement,
    and adds their u^2 to the bound: the same overlaps and norm as passes over the whole grid."""
    rng = np.random.default_rng(5)
    shape = (37, 23)
    pressure = np.where(rng.random(shape) < 0.4, rng.random(shape), 0.0)
    pressure[:4] = pressure[30:] = 0.0
    base, displacement = rng.random(shape), rng.standard_normal(shape)
    with _fused.use_compiled(compiled):
        passes = _fused.passes()
        results = []
        for top, bottom in ((0, 37), (3, 31)):
            gap, contact = np.full(shape, np.nan), np.zeros(shape, dtype=bool)
            sums = passes.gap(base, displacement, pressure, gap, contact, top, bottom)
            norm, overlaps, rest = passes.norm(gap, contact, base, displacement, 0.7, top, bottom)
            results.append((sums, norm, overlaps, sums[2] + rest, gap, contact))
    (whole, *rest_whole), (rows, *rest_rows) = results
    assert whole[3:5] == rows[3:5] == (4, 30)
    assert np.allclose(whole[:2], rows[:2], rtol=1e-13, atol=0)
    assert np.isclose(rest_whole[0], rest_rows[0], rtol=1e-13, atol=0) and rest_whole[0] > 0     # norm
    free = (base + displacement - 0.7 < 0) & (pressure == 0)
    assert rest_whole[1] == rest_rows[1] == np.count_nonzero(free) and free[:3].any()          # overlaps
    assert np.sqrt(rest_rows[2]) >= np.abs(displacement).max() ** 2                            # the bound on max u^2
    assert np.array_equal(rest_whole[4], rest_rows[4]) and not rest_rows[4][:3].any()           # the contact
    assert np.isnan(rest_rows[3][:3]).all() and np.isnan(rest_rows[3][31:]).all()               # gap: not written
    assert np.array_equal(rest_rows[3][3:31], (base + displacement)[3:31])


def test_nan_separation_is_refused():
    grid = fw.Grid(shape=(16, 16), size=(1e-3, 1e-3))
    heights = indenters.Sphere(radius=10e-3).on_grid(grid)
    heights[3, 4] = np.nan
    operator = SurfaceCompliance(grid)
    with pytest.raises(ParameterError, match=r"base_gap must hold numbers .* got NaN at 1 of its 256 cells"):
        fw.solve_normal(operator.apply, heights, cell_area=grid.cell_area, load=1.0)


def test_compiled_choice_must_be_a_boolean():
    with pytest.raises(ParameterError, match=r"compiled must be True or False, got 1"):
        _fused.set_compiled(1)


def test_small_grids_take_the_numpy_passes(monkeypatch):
    monkeypatch.setattr(_fused, "COMPILED_FROM", 100)
    with _fused.use_compiled(True):
        assert _fused.passes(99) is _fused.NumpyPasses
        assert (_fused.passes(100) is _fused.NumpyPasses) == (not _fused.numba_available())
    with _fused.use_compiled(False):
        assert _fused.passes(10**6) is _fused.NumpyPasses
