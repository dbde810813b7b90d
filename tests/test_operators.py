"""Half-space operators: DC-FFT against direct sums, symmetry, balance, backends."""
import numpy as np
import pytest

import framework as fw
from framework import fft
from framework.operators import SubsurfaceStress, SurfaceCompliance, SurfaceStiffness
from framework.operators.kernels import subsurface_stress, surface_displacement

RNG = np.random.default_rng(0)


def direct_surface(grid, pressure):
    x1, x2 = grid.coordinates()
    dx1, dx2 = grid.spacing
    out = np.zeros(grid.shape)
    for (i, j), p in np.ndenumerate(pressure):
        out += p * surface_displacement(x1 - x1[i, j], x2 - x2[i, j], half1=dx1 / 2, half2=dx2 / 2)
    return out


def direct_stress(grid, pressure, depth, poisson):
    x1, x2 = grid.coordinates()
    dx1, dx2 = grid.spacing
    out = np.zeros(grid.shape + (6,))
    for (i, j), p in np.ndenumerate(pressure):
        out += p * subsurface_stress(x1 - x1[i, j], x2 - x2[i, j], depth, half1=dx1 / 2, half2=dx2 / 2,
                                     poisson=poisson)
    return out


@pytest.mark.parametrize("shape", [(7, 10), (8, 8), (9, 5)])
def test_dcfft_equals_direct_linear_convolution(shape):
    grid = fw.Grid(shape=shape, size=(1.3e-3, 0.7e-3))
    pressure = RNG.random(shape)
    direct = direct_surface(grid, pressure)
    assert np.abs(SurfaceCompliance(grid).apply(pressure) - direct).max() <= 1e-12 * np.abs(direct).max()


@pytest.mark.parametrize("shape", [(7, 6), (8, 9)])
def test_stress_dcfft_equals_direct_sum(shape):
    grid = fw.Grid(shape=shape, size=(1e-3, 1.5e-3), depth=0.6e-3, layers=3)
    pressure = RNG.random(shape)
    stress = SubsurfaceStress(grid, 0.3).apply(pressure)
    for k, depth in enumerate(grid.x3):
        direct = direct_stress(grid, pressure, depth, 0.3)
        assert np.abs(stress[:, :, k] - direct).max() <= 1e-12 * np.abs(direct).max()


@pytest.mark.parametrize("periodic", [(False, False), (True, True), (False, True), (True, False)])
def test_surface_operator_is_symmetric(periodic):
    grid = fw.Grid(shape=(12, 9), size=(1.0, 0.8), periodic=periodic)
    operator = SurfaceCompliance(grid)
    p, q = RNG.random(grid.shape), RNG.random(grid.shape)
    left, right = np.vdot(q, operator.apply(p)), np.vdot(p, operator.apply(q))
    assert abs(left - right) <= 1e-12 * abs(left)


@pytest.mark.parametrize("periodic", [(False, False), (True, True), (False, True)])
def test_surface_operator_is_positive(periodic):
    """The compliance is positive definite on fields that it does not shift (mean-free when periodic)."""
    grid = fw.Grid(shape=(10, 8), size=(1.0, 1.0), periodic=periodic)
    operator = SurfaceCompliance(grid)
    for _ in range(5):
        p = RNG.standard_normal(grid.shape)
        if any(periodic):
            p -= p.mean()
        assert np.vdot(p, operator.apply(p)) > 0


def test_periodic_kernel_of_a_mode_is_two_over_q():
    """Doubly periodic: a cosine of wavenumber k gives u = (2/k) p (Westergaard)."""
    grid = fw.Grid(shape=(32, 4), size=(2.0, 0.25), periodic=(True, True))
    x1, _ = grid.coordinates()
    k = 2 * np.pi * 3 / 2.0
    u = SurfaceCompliance(grid).apply(np.cos(k * x1))
    assert np.allclose(u, 2 / k * np.cos(k * x1), atol=1e-13)


def test_one_periodic_axis_cosine_along_open_axis_is_plane_strain():
    """Periodic along x2, p = exp(-(x1/s)^2) cos(k x1) on a long strip: u -> (2/k) cos(k x1) at the centre.

    The envelope's curvature adds O(1/(k s)^2): the error must fall fourfold when s doubles.
    """
    grid = fw.Grid(shape=(8192, 2), size=(128.0, 1.0), periodic=(False, True))
    x1, _ = grid.coordinates()
    k = 2 * np.pi  # 64 cells per wavelength: the piecewise-constant sinc factor is 0.9996
    centre = np.abs(x1) < 1
    errors = []
    for width in (12.0, 24.0):
        u = SurfaceCompliance(grid).apply(np.exp(-(x1 / width) ** 2) * np.cos(k * x1))
        errors.append(np.abs(u[centre] - 2 / k * np.cos(k * x1[centre])).max() / (2 / k))
    assert errors[1] < 3e-3
    assert 3.0 < errors[0] / errors[1] < 5.0


def test_transposed_mixed_periodicity_is_the_transpose():
    a = fw.Grid(shape=(20, 6), size=(2.0, 0.6), periodic=(False, True))
    b = fw.Grid(shape=(6, 20), size=(0.6, 2.0), periodic=(True, False))
    p = RNG.random(a.shape)
    assert np.allclose(SurfaceCompliance(a).apply(p), SurfaceCompliance(b).apply(p.T).T, rtol=1e-12, atol=0)


def test_periodic_stress_balance_and_surface_traction():
    """Mean s33 over a period equals -mean pressure at every depth; s33(0) = -p."""
    grid = fw.Grid(shape=(16, 12), size=(1.0, 1.0), depth=0.5, layers=5, periodic=(True, True))
    p = RNG.random(grid.shape)
    stress = SubsurfaceStress(grid, 0.25).apply(p, depths=np.r_[0.0, grid.x3])
    assert np.allclose(stress[..., 2].mean(axis=(0, 1)), -p.mean(), rtol=1e-12)
    assert np.allclose(stress[:, :, 0, 2], -p, atol=1e-12)
    assert np.allclose(stress[:, :, 0, 3:5], 0.0, atol=1e-12)


def test_periodic_stress_matches_love_for_a_small_load_in_a_large_period():
    """Far from the images, the doubly periodic stresses approach the non-periodic ones."""
    n = 64
    open_grid = fw.Grid(shape=(n, n), size=(1.0, 1.0))
    periodic = fw.Grid(shape=(n, n), size=(1.0, 1.0), periodic=(True, True))
    x1, x2 = open_grid.coordinates()
    p = np.where(np.hypot(x1, x2) < 0.05, 1.0, 0.0)
    depths = [0.02, 0.05]
    reference = SubsurfaceStress(open_grid, 0.3).apply(p, depths=depths)
    candidate = SubsurfaceStress(periodic, 0.3).apply(p, depths=depths)
    near = np.hypot(x1, x2) < 0.1
    # The periodic field differs by the images and by the mean-pressure convention, O((a/L)^2) here.
    assert np.abs(candidate[near] - reference[near]).max() < 0.02


@pytest.mark.skipif("pyfftw" not in fft.available_backends(), reason="pyFFTW not installed")
@pytest.mark.parametrize("periodic", [(False, False), (True, True)])
def test_backends_agree(periodic):
    grid = fw.Grid(shape=(30, 17), size=(1.0, 1.0), depth=0.3, layers=2, periodic=periodic)
    p = RNG.random(grid.shape)
    out = {}
    for backend in fft.available_backends():
        with fft.use_backend(backend):
            out[backend] = (SurfaceCompliance(grid).apply(p), SubsurfaceStress(grid, 0.3).apply(p))
    for a, b in zip(out["pyfftw"], out["scipy"]):
        assert np.abs(a - b).max() <= 1e-12 * np.abs(b).max()


@pytest.mark.parametrize("backend", fft.available_backends())
def test_forward_from_reads_any_array_and_leaves_it_unchanged(backend):
    """``RealFFTPair.forward_from``: an aligned array (read in place by pyFFTW: the pair's input buffer
    keeps what it held), an unaligned one and a strided one (copied) all give rfft2 to rounding; none
    is changed, and the plan then reads its own buffer again."""
    shape = (24, 18)
    with fft.use_backend(backend):
        pair = fft.RealFFTPair(shape)
        aligned = fft.empty_aligned(shape)
        unaligned = np.frombuffer(np.zeros(aligned.size * 8 + 8, np.uint8)[8:].data, dtype=float).reshape(shape)
        strided = np.empty((2 * shape[0], shape[1]))[::2]
        for array in (aligned, unaligned, strided):
            array[...] = RNG.random(shape)
            kept = array.copy()
            pair.real_in[...] = 7.0
            pair.forward_from(array)
            assert np.allclose(pair.spectrum, np.fft.rfft2(kept), rtol=0, atol=1e-12 * np.abs(kept).sum())
            assert np.array_equal(array, kept)
            if array is aligned:
                assert (pair.real_in == 7.0).all()
            pair.forward()
            assert pair.spectrum[0, 0] == pytest.approx(pair.real_in.sum(), rel=1e-14)


def test_scipy_backend_runs_a_contact():
    """The fallback path solves a contact alone (as on a machine without pyFFTW)."""
    grid = fw.Grid(shape=(32, 32), size=(1e-3, 1e-3))
    sim = fw.Simulation(grid=grid, material=fw.materials.Elastic(young=1e9, poisson=0.3),
                        indenter=fw.indenters.Sphere(radius=5e-3), schedule=fw.schedules.Static(load=1.0))
    with fft.use_backend("scipy"):
        scipy_result = sim.run()
    assert scipy_result.iterations[0] > 0 and abs(scipy_result.load[0] - 1.0) < 1e-12
    if "pyfftw" in fft.available_backends():
        with fft.use_backend("pyfftw"):
            fftw_result = sim.run()
        assert np.allclose(fftw_result.pressure(0), scipy_result.pressure(0), rtol=0, atol=1e-9 * 
                           scipy_result.max_pressure[0])


def test_unknown_backend_is_rejected():
    with pytest.raises(fw.errors.ParameterError, match="backend must be one of .* got 'cufft'"):
        fft.set_backend("cufft")


def test_operator_rejects_wrong_shape():
    operator = SurfaceCompliance(fw.Grid(shape=(8, 6), size=(1.0, 1.0)))
    with pytest.raises(fw.errors.ShapeError, match=r"\(6, 8\).*\(8, 6\)"):
        operator.apply(np.zeros((6, 8)))


def test_windowed_apply_equals_the_full_convolution_on_the_window():
    grid = fw.Grid(shape=(90, 80), size=(1.0, 1.0))
    operator = SurfaceCompliance(grid)
    support = np.zeros(grid.shape, bool)
    support[20:41, 7:30] = RNG.random((21, 23)) > 0.3
    field = np.where(support, RNG.random(grid.shape), 0.0)
    box = operator.window(support)
    assert all((s.stop - s.start) % 32 == 0 for s in box)
    assert support[box].sum() == support.sum()
    full = operator.apply(field)[box]
    assert np.abs(operator.apply_window(field[box], box) - full).max() <= 1e-12 * np.abs(full).max()


@pytest.mark.parametrize("shape", [(121, 121), (64, 48), (97, 30)])
def test_repeated_applications_keep_the_zero_padding(shape):
    """The reused FFT buffers give the same answer on every call (the padding must stay zero)."""
    grid = fw.Grid(shape=shape, size=(1.0, 1.0))
    operator = SurfaceCompliance(grid)
    fields = [RNG.random(shape) for _ in range(4)]
    first = [operator.apply(f) for f in fields]
    for f, expected in zip(fields, first):
        assert np.array_equal(operator.apply(f), expected)
    direct = direct_surface(fw.Grid(shape=(9, 7), size=(1.0, 1.0)), fields[0][:9, :7])
    small = SurfaceCompliance(fw.Grid(shape=(9, 7), size=(1.0, 1.0)))
    for _ in range(3):
        assert np.abs(small.apply(fields[0][:9, :7]) - direct).max() <= 1e-12 * np.abs(direct).max()


def test_fft_threads_from_the_environment():
    """FRAMEWORK_FFT_THREADS: unset -> 1, 'auto' -> the cores this process may use, a bad value named."""
    import os
    from framework import fft
    from framework.errors import ParameterError
    assert fft.threads_from_environment(None) == 1
    assert fft.threads_from_environment("3") == 3
    assert fft.threads_from_environment(" AUTO ") == len(os.sched_getaffinity(0)) >= 1
    for bad in ("0", "two", "-1", "1.5"):
        with pytest.raises(ParameterError, match=rf"FRAMEWORK_FFT_THREADS must be a whole number >= 1 or 'auto', got {bad!r}"):
            fft.threads_from_environment(bad)


@pytest.mark.parametrize("periodic", [(False, False), (True, True)])
def test_scaled_product_and_its_uncopied_buffer(periodic):
    """``apply(p, scale)`` is ``scale`` times the product, against the direct sum on the open grid; with
    ``copy=False`` the same numbers in the operator's buffer, which the next product overwrites; a
    scale changed between calls is taken (the scaled kernel is rebuilt)."""
    grid = fw.Grid(shape=(9, 7), size=(1.0, 1.0), periodic=periodic)
    operator = SurfaceCompliance(grid)
    pressure = RNG.random(grid.shape)
    plain = direct_surface(grid, pressure) if periodic == (False, False) else operator.apply(pressure)
    for scale in (2.5e-9, 7.0, 2.5e-9):
        scaled = operator.apply(pressure, scale)
        assert np.abs(scaled - scale * plain).max() <= 1e-12 * scale * np.abs(plain).max()
        buffer = operator.apply(pressure, scale, copy=False)
        assert np.array_equal(buffer, scaled)
    again = operator.apply(2 * pressure, copy=False)
    assert np.shares_memory(buffer, again) and np.abs(buffer - 2 * plain).max() <= 1e-12 * np.abs(plain).max()
    box = operator.window(np.ones(grid.shape, bool))
    assert np.array_equal(operator.apply_window(pressure, box, 7.0), operator.apply(pressure, 7.0))


def test_surface_stiffness_inverts_the_periodic_compliance():
    """The preconditioner's operator is the Fourier inverse of the half-space's: on a doubly periodic
    grid (kernel 2/|q|, Stanley & Kato) it undoes the displacement of any zero-mean pressure, a cosine
    of wavenumber q gets q/2 (per unit compliance), and a uniform field the longest wave's stiffness."""
    grid = fw.Grid(shape=(48, 40), size=(2e-3, 1e-3), periodic=(True, True))
    rng = np.random.default_rng(5)
    pressure = rng.standard_normal(grid.shape)
    pressure -= pressure.mean()
    stiffness = SurfaceStiffness(grid)
    recovered = stiffness.apply(SurfaceCompliance(grid).apply(pressure))
    assert np.abs(recovered - pressure).max() <= 1e-12 * np.abs(pressure).max()
    X1, X2 = grid.coordinates()
    q = np.hypot(2 * np.pi * 3 / 2e-3, 2 * np.pi * 2 / 1e-3)
    wave = np.cos(2 * np.pi * (3 * X1 / 2e-3 + 2 * X2 / 1e-3))
    assert np.allclose(stiffness.apply(wave), q / 2 * wave, rtol=0, atol=1e-12 * q)
    assert np.allclose(stiffness.apply(np.ones(grid.shape)), np.pi / 2e-3, rtol=1e-14)   # (2 pi / L1) / 2
    # any box of the grid is taken as periodic: a box's own wavenumbers
    box = stiffness.apply(np.cos(2 * np.pi * X1[:16, :8] / (16 * 2e-3 / 48)))
    assert np.allclose(box, np.pi / (16 * 2e-3 / 48) * np.cos(2 * np.pi * X1[:16, :8] / (16 * 2e-3 / 48)), atol=1e-9)


def test_surface_compliance_keeps_the_windows_of_its_last_boxes_only():
    """A growing contact meets box after box: the operator keeps the last few, and a box planned again
    gives the same numbers."""
    grid = fw.Grid(shape=(96, 96), size=(1e-3, 1e-3))
    operator = SurfaceCompliance(grid)
    field = np.random.default_rng(4).random(grid.shape)
    first = operator.apply_window(field[:16, :16], (slice(0, 16), slice(0, 16)))
    for side in range(24, 16 + 8 * SurfaceCompliance.KEPT + 1, 8):
        operator.apply_window(field[:side, :side], (slice(0, side), slice(0, side)))
    assert (16, 16) not in operator._windows and len(operator._windows) == SurfaceCompliance.KEPT
    again = operator.apply_window(field[:16, :16], (slice(0, 16), slice(0, 16)))
    assert np.array_equal(again, first)
    padded = np.zeros(grid.shape)
    padded[:16, :16] = field[:16, :16]
    assert np.allclose(again, operator.apply(padded)[:16, :16], rtol=0, atol=1e-12 * np.abs(again).max())


def test_surface_stiffness_keeps_the_plans_of_its_last_boxes_only():
    """A contact shrinking from the whole grid must not keep the whole grid's FFT buffers for the run."""
    grid = fw.Grid(shape=(64, 64), size=(1e-3, 1e-3), periodic=(True, True))
    stiffness = SurfaceStiffness(grid)
    field = np.random.default_rng(2).random(grid.shape)
    whole = stiffness.apply(field)
    for side in (48, 32, 16):
        stiffness.apply(field[:side, :side])
    assert (64, 64) not in stiffness._boxes and len(stiffness._boxes) == SurfaceStiffness.KEPT
    assert np.array_equal(stiffness.apply(field), whole)      # planned again, the same numbers
    buffer = stiffness.input((32, 32))
    buffer[...] = field[:32, :32]
    assert np.array_equal(stiffness.apply(buffer), stiffness.apply(field[:32, :32]))   # its own input: no copy
    assert np.array_equal(buffer, field[:32, :32])                                     # nor any change
