"""The pruned box transforms (:class:`framework.operators.box_fft.BoxFFT`) against numpy's whole-lattice FFTs.

A box field zero-padded to its lattice, transformed by ``numpy.fft.rfftn``, multiplied by a spectral factor
per component and transformed back by ``irfftn``, cut to the box: the pruned transforms (lines of the box
along x3, rows of the box along x2, every line along x1, a block of q3 at a time) give the same to 1e-14 of
its largest value, for boxes on padded lattices, on their own lattice (no padding) and with odd sizes, in
one block or several.
"""
import numpy as np
import pytest

from framework.operators import box_fft as box_fft_module
from framework.operators.box_fft import BoxFFT


@pytest.mark.parametrize("shape, fft_shape, blocks", [
    ((5, 6, 7), (10, 12, 14), 1),          # padded, the spectra at once
    ((5, 6, 7), (10, 12, 14), 3),          # several blocks of q3 (the last one shorter)
    ((7, 4, 9), (15, 8, 18), 4),           # odd lattice sizes
    ((6, 6, 6), (6, 6, 6), 1),             # the box's own lattice: nothing padded
    ((3, 5, 4), (7, 5, 9), 2),
])
def test_pruned_transforms_equal_the_whole_lattices(shape, fft_shape, blocks):
    rng = np.random.default_rng(1)
    field = rng.normal(size=(*shape, 6))
    h = fft_shape[2] // 2 + 1
    factor = rng.normal(size=(6, *fft_shape[:2], h)) + 1j * rng.normal(size=(6, *fft_shape[:2], h))
    per_block = -(-h // blocks)
    box = BoxFFT(shape, fft_shape, block_bytes=6 * fft_shape[0] * fft_shape[1] * 16 * per_block)
    assert box.block == per_block
    weights_in, weights_out = np.arange(1.0, 7.0), 1.0 / np.arange(2.0, 8.0)
    seen = []

    def spectral_pass(spectra, k0, k1):
        seen.append((k0, k1))
        spectra *= np.moveaxis(factor[..., k0:k1], 0, 2)     # laid out (N1, N2, 6, b)

    out = box.apply(field, spectral_pass, weights_in, weights_out)
    assert seen[0][0] == 0 and seen[-1][1] == h and all(a[1] == b[0] for a, b in zip(seen, seen[1:]))
    expected = np.empty_like(out)
    for c in range(6):
        padded = np.zeros(fft_shape)
        padded[:shape[0], :shape[1], :shape[2]] = field[..., c] * weights_in[c]
        back = np.fft.irfftn(np.fft.rfftn(padded) * factor[c], s=fft_shape, axes=(0, 1, 2))
        expected[..., c] = back[:shape[0], :shape[1], :shape[2]] * weights_out[c]
    assert np.abs(out - expected).max() <= 1e-14 * np.abs(expected).max()
    again = box.apply(field, spectral_pass, weights_in, weights_out)    # the buffers' padding stays zero
    assert np.array_equal(again, out)


@pytest.mark.parametrize("shape, fft_shape, blocks, target_shape, place", [
    ((5, 6, 7), (22, 20, 18), 1, (12, 11, 9), (4, 2, 1)),      # a grid around the box, the spectra at once
    ((5, 6, 7), (22, 20, 18), 3, (12, 11, 9), (7, 5, 2)),      # several blocks of q3, the box elsewhere
    ((3, 4, 2), (15, 14, 9), 2, (8, 9, 6), (0, 5, 4)),         # odd lattice sizes, the box at the grid's edges
])
def test_pruned_transforms_onto_a_target_equal_the_whole_lattices(shape, fft_shape, blocks, target_shape, place):
    """``target``: the result on other points of the lattice than the box's (EigenstrainField's grid around its box:
    the lattice's indices ``(i - place) mod N`` of each axis), the same as numpy's whole-lattice transforms taken
    there, to 1e-14; the box's own product afterwards as before."""
    rng = np.random.default_rng(2)
    field = rng.normal(size=(*shape, 6))
    h = fft_shape[2] // 2 + 1
    factor = rng.normal(size=(6, *fft_shape[:2], h)) + 1j * rng.normal(size=(6, *fft_shape[:2], h))
    per_block = -(-h // blocks)
    box = BoxFFT(shape, fft_shape, effort="FFTW_ESTIMATE", block_bytes=6 * fft_shape[0] * fft_shape[1] * 16 * per_block)
    weights_in, weights_out = np.arange(1.0, 7.0), 1.0 / np.arange(2.0, 8.0)
    target = [(np.arange(size) - s) % n for size, s, n in zip(target_shape, place, fft_shape)]

    def spectral_pass(spectra, k0, k1):
        spectra *= np.moveaxis(factor[..., k0:k1], 0, 2)     # laid out (N1, N2, 6, b)

    out = box.apply(field, spectral_pass, weights_in, weights_out, target=target)
    assert out.shape == (*target_shape, 6)
    expected = np.empty_like(out)
    for c in range(6):
        padded = np.zeros(fft_shape)
        padded[:shape[0], :shape[1], :shape[2]] = field[..., c] * weights_in[c]
        back = np.fft.irfftn(np.fft.rfftn(padded) * factor[c], s=fft_shape, axes=(0, 1, 2))
        expected[..., c] = back[np.ix_(*target)] * weights_out[c]
    assert np.abs(out - expected).max() <= 1e-14 * np.abs(expected).max()
    inside = tuple(slice(p, p + m) for p, m in zip(place, shape))
    own = box.apply(field, spectral_pass, weights_in, weights_out)      # the padding zeroed again after the target
    assert np.abs(own - out[inside]).max() <= 1e-14 * np.abs(own).max()


def test_kernels_held_in_blocks_give_the_same_product(monkeypatch):
    """An operator whose kernels and spectra are held a block of q3 at a time (a large box's; here forced on a
    small one by a small block size) gives the product of the one-block operator to 1e-14, and the same
    whole-lattice and own-lattice infinite-space spectra."""
    import framework as fw
    from framework.operators import box_fft, eigenstrain
    grid = fw.Grid(shape=(16, 14), size=(16e-6, 14e-6), depth=12e-6, layers=12)
    field = np.random.default_rng(3).normal(size=(9, 8, 7, 6))
    one = eigenstrain.HalfSpaceEigenstrain(grid, 0.3, (3, 2, 2), (9, 8, 7))
    monkeypatch.setattr(box_fft, "BLOCK_BYTES", 6 * 18 * 16 * 16 * 2)      # blocks of two q3
    monkeypatch.setattr(eigenstrain, "q3_blocks", lambda shape, least: box_fft.q3_blocks(shape, box_fft.BLOCK_BYTES))
    several = eigenstrain.HalfSpaceEigenstrain(grid, 0.3, (3, 2, 2), (9, 8, 7))
    several._ffts["padded"] = box_fft.BoxFFT(several.shape, several.fft_shape, block_bytes=box_fft.BLOCK_BYTES,
                                             by_columns=True)
    assert one.fft_shape == (18, 16, 16) and len(several._kernel_blocks) == 5      # q3 = 0 .. 8 by twos
    expected = one.strain(field)
    assert np.abs(several.strain(field) - expected).max() <= 1e-14 * np.abs(expected).max()
    for lattice in ("padded", "own", "folded"):       # (to rounding: the entries are one matrix product a block)
        blocks, whole = several.infinite_spectra(lattice)[0], one.infinite_spectra(lattice)[0]
        assert blocks.shape == whole.shape and np.abs(blocks - whole).max() <= 1e-14 * np.abs(whole).max()


def test_transforms_planned_again_by_measurement(monkeypatch):
    """Asked to measure, the transforms are planned by estimate for the first MEASURE_AFTER applications where
    FFTW's wisdom does not hold them (here it is made to hold nothing), then by measurement; a later box of the
    same lattice takes the measured plans from the wisdom at once. The same results to rounding, the zero padding
    kept."""
    pyfftw = pytest.importorskip("pyfftw")
    from framework.operators import box_fft
    monkeypatch.setattr(box_fft, "MEASURE_AFTER", 2)
    field = np.random.default_rng(4).normal(size=(5, 6, 7, 6))
    planner = pyfftw.FFTW

    def without_wisdom(*args, flags=(), **kwargs):
        if "FFTW_WISDOM_ONLY" in flags:
            raise RuntimeError("No FFTW wisdom is known for this plan.")
        return planner(*args, flags=flags, **kwargs)
    with monkeypatch.context() as patch:
        patch.setattr(pyfftw, "FFTW", without_wisdom)
        box = BoxFFT((5, 6, 7), (10, 12, 14), effort="FFTW_MEASURE")
        first = box.apply(field, lambda spectra, k0, k1: None)
        assert box.effort == "FFTW_ESTIMATE"
        second = box.apply(field, lambda spectra, k0, k1: None)
        assert box.effort == "FFTW_MEASURE"
    for out in (second, box.apply(field, lambda spectra, k0, k1: None)):
        assert np.abs(out - first).max() <= 1e-14 * np.abs(first).max()
    assert np.abs(first - field).max() <= 1e-14 * np.abs(field).max()       # no pass: the field itself
    again = BoxFFT((5, 6, 7), (10, 12, 14), effort="FFTW_MEASURE")
    assert again.effort == "FFTW_MEASURE"
    out = again.apply(field, lambda spectra, k0, k1: None)
    assert np.abs(out - field).max() <= 1e-14 * np.abs(field).max()


@pytest.mark.parametrize("block_bytes", [None, 20000])
def test_buffer_bytes_counts_the_buffers_a_box_fft_holds(block_bytes):
    """buffer_bytes (which decides whether a Fourier preconditioner on a lattice of its own fits its memory) is the
    bytes of the buffers a BoxFFT holds after an application, in one block of q3 or in several."""
    from framework.operators import box_fft
    kwargs = {} if block_bytes is None else {"block_bytes": block_bytes}
    box = BoxFFT((5, 6, 7), (10, 12, 14), effort="FFTW_ESTIMATE", **kwargs)
    box.apply(np.ones((5, 6, 7, 6)), lambda spectra, k0, k1: None)
    assert box.direct == (block_bytes is None)          # one block of q3: the lines are the block's box rows
    assert set(box._memory) == ({"block"} if box.direct else {"block", "lines"})
    assert box_fft.buffer_bytes((5, 6, 7), (10, 12, 14), **kwargs) == sum(a.nbytes for a in box._memory.values())


def test_blocks_hold_at_least_a_vector_of_q3():
    """The eigenstrain operator's blocks of q3 hold at least LEAST_Q3 wavenumbers (one vector of its pass) where
    BLOCK_BYTES would leave fewer (a wide lattice), all of them where there are fewer; the mechanism's default keeps
    BLOCK_BYTES alone; buffer_bytes counts the larger block."""
    from framework.operators import box_fft
    wide = (744, 744, 120)                               # 300 glass spheres' lattice: 53 MB a q3
    few = box_fft.BLOCK_BYTES // (6 * 744 * 744 * 16)
    assert 1 <= few < box_fft.LEAST_Q3 and max(k1 - k0 for k0, k1 in box_fft.q3_blocks(wide)) == few
    blocks = box_fft.q3_blocks(wide, least=box_fft.LEAST_Q3)
    assert blocks[0][0] == 0 and blocks[-1][1] == 61 and all(b[1] == c[0] for b, c in zip(blocks, blocks[1:]))
    assert all(k1 - k0 == box_fft.LEAST_Q3 for k0, k1 in blocks[:-1])
    assert box_fft.q3_blocks((744, 744, 10), least=box_fft.LEAST_Q3) == [(0, 6)]
    assert (box_fft.buffer_bytes((372, 372, 56), wide, least=box_fft.LEAST_Q3)
            - box_fft.buffer_bytes((372, 372, 56), wide)) == 16 * 6 * 744 * 744 * (box_fft.LEAST_Q3 - few)
    # blocks of more q3 than a vector: a multiple of it, the last block shorter (a 128^3 box: three of 40, one of 9)
    assert box_fft.q3_blocks((256, 256, 256)) == [(0, 40), (40, 80), (80, 120), (120, 129)]
    assert box_fft.q3_blocks((256, 256, 256), block_bytes=6 * 256 * 256 * 16 * 19) == [
        (k0, min(129, k0 + 16)) for k0 in range(0, 129, 16)]


@pytest.mark.parametrize("block_bytes", [box_fft_module.BLOCK_BYTES, 3000])
def test_a_box_fft_sharing_anothers_buffers_gives_what_it_gives_alone(block_bytes):
    """The BoxFFTs of one box on two lattices (a product's padded one, a preconditioner's smaller periodic cell) share
    the larger one's buffers: taken in turns, each gives bit for bit what it gives alone (each writes its lines'
    padding again, whatever the other left there), and the smaller one adds no memory; in one block of q3 or in
    several (the lines an array of their own)."""
    from framework.operators import box_fft
    shape, padded, own = (5, 6, 7), (10, 12, 14), (6, 6, 8)
    rng = np.random.default_rng(3)
    field = rng.normal(size=(*shape, 6))
    factors = {s: rng.normal(size=(s[0], s[1], 6, s[2] // 2 + 1)) for s in (padded, own)}

    def spectral_pass(lattice):
        def multiply(spectra, k0, k1):
            spectra *= factors[lattice][..., k0:k1]
        return multiply
    alone = {s: BoxFFT(shape, s, effort="FFTW_ESTIMATE", block_bytes=block_bytes).apply(field, spectral_pass(s))
             for s in (padded, own)}
    large = BoxFFT(shape, padded, effort="FFTW_ESTIMATE", block_bytes=block_bytes)
    small = BoxFFT(shape, own, effort="FFTW_ESTIMATE", block_bytes=block_bytes, share=large)
    assert large.direct == small.direct == (block_bytes == box_fft.BLOCK_BYTES)
    for _ in range(2):
        assert np.array_equal(large.apply(field, spectral_pass(padded)), alone[padded])
        assert np.array_equal(small.apply(field, spectral_pass(own)), alone[own])
    assert np.shares_memory(small._lines, large._lines)
    assert np.shares_memory(small._buffers[small.block], large._buffers[large.block])
    assert box_fft.buffer_bytes(shape, own, block_bytes, share=(padded, block_bytes, 1)) == 0
    assert box_fft.buffer_bytes(shape, padded, block_bytes, share=(own, block_bytes, 1)) > 0
    with pytest.raises(ValueError, match="same box"):
        BoxFFT((5, 6, 6), own, share=large)


@pytest.mark.parametrize("block_bytes, column_bytes, first", [(box_fft_module.BLOCK_BYTES, 2 * 2 * 10 * 6 * 8 * 16, (0, 2)),
                                                               (3000, 2 * 10 * 6 * 16, (0, 1))])
def test_a_pass_by_columns_gives_the_whole_pass(monkeypatch, block_bytes, column_bytes, first):
    """Made by_columns, a BoxFFT takes its transforms along x1 a few columns q2 (and their reversals) at a time and
    passes each group between them: every column passed once, and the result (on the box, or on a target around it)
    that of the whole block's pass, to rounding; in one block of q3 or several, a group of one column or several."""
    monkeypatch.setattr(box_fft_module, "COLUMN_BYTES", column_bytes)     # groups of two columns or of one
    monkeypatch.setattr(box_fft_module, "COLUMNS_FROM", 0)                # (a block this small is passed whole)
    shape, lattice = (5, 6, 7), (10, 12, 14)
    rng = np.random.default_rng(5)
    field = rng.normal(size=(*shape, 6))
    factors = rng.normal(size=(10, 12, 6, 8)) + 1j * rng.normal(size=(10, 12, 6, 8))

    def whole(spectra, k0, k1):
        spectra *= factors[..., k0:k1]
    seen = []

    def by_columns(spectra, k0, k1, columns):
        c0, c1 = columns
        chosen = sorted({c % 12 for c in range(c0, c1)} | {-c % 12 for c in range(c0, c1)})
        seen.extend((k0, c) for c in chosen)
        spectra[:, chosen] *= factors[:, chosen, :, k0:k1]
    plain = BoxFFT(shape, lattice, effort="FFTW_ESTIMATE", block_bytes=block_bytes)
    grouped = BoxFFT(shape, lattice, effort="FFTW_ESTIMATE", block_bytes=block_bytes, by_columns=True)
    assert grouped.column_ranges[0] == first and grouped.column_ranges[-1][1] == 7
    expected = plain.apply(field, whole)
    for _ in range(2):          # (the padding zeroed again after each)
        seen.clear()
        out = grouped.apply(field, by_columns, columns=True)
        assert np.abs(out - expected).max() <= 1e-14 * np.abs(expected).max()
        assert sorted(seen) == sorted((k0, c) for k0, _ in grouped.blocks for c in range(12))
    assert np.abs(grouped.apply(field, whole) - expected).max() <= 1e-14 * np.abs(expected).max()
    target = [np.arange(-1, 7) % 10, np.arange(8) % 12, np.arange(9) % 14]
    around = plain.apply(field, whole, target=target)
    assert np.abs(grouped.apply(field, by_columns, target=target, columns=True) - around).max() <= 1e-14 * np.abs(
        around).max()
    assert np.abs(grouped.apply(field, by_columns, columns=True) - expected).max() <= 1e-14 * np.abs(expected).max()
    with pytest.raises(ValueError, match="by_columns"):
        plain.apply(field, by_columns, columns=True)


def test_operators_passed_by_columns_give_their_whole_pass(monkeypatch):
    """The eigenstrain operator and the eigenstrains' field on a grid, their blocks passed by columns (a large box's;
    forced here on a small one), give the products of the whole blocks' pass to rounding, in one block of q3 and in
    several, and a block small enough is passed whole."""
    import framework as fw
    from framework.operators import eigenstrain, eigenstrain_field
    grid = fw.Grid(shape=(16, 14), size=(16e-6, 14e-6), depth=12e-6, layers=12)
    field = np.random.default_rng(4).normal(size=(9, 8, 7, 6))
    whole = eigenstrain.HalfSpaceEigenstrain(grid, 0.3, (3, 2, 2), (9, 8, 7))
    expected = whole.strain(field)
    assert not whole._box_fft().by_columns
    grid_field = eigenstrain_field.EigenstrainField(grid, 0.3, (3, 2, 2), (9, 8, 7))
    volume = grid_field.volume(field)
    monkeypatch.setattr(box_fft_module, "COLUMNS_FROM", 0)
    for block_bytes, block in ((box_fft_module.BLOCK_BYTES, 9), (6 * 18 * 16 * 16 * 2, 2)):
        monkeypatch.setattr(box_fft_module, "COLUMN_BYTES", 2 * 2 * 18 * 6 * block * 16)      # two columns a group
        monkeypatch.setattr(box_fft_module, "BLOCK_BYTES", block_bytes)
        monkeypatch.setattr(eigenstrain, "q3_blocks", lambda shape, least: box_fft_module.q3_blocks(shape, block_bytes))
        grouped = eigenstrain.HalfSpaceEigenstrain(grid, 0.3, (3, 2, 2), (9, 8, 7))
        box = grouped._ffts["padded"] = BoxFFT(grouped.shape, grouped.fft_shape, block_bytes=block_bytes,
                                               by_columns=True)
        assert box.by_columns and len(box.column_ranges) == 5 and len(box.blocks) == (1 if block_bytes > 1e6 else 5)
        assert np.abs(grouped.strain(field) - expected).max() <= 1e-14 * np.abs(expected).max()
        grouped_field = eigenstrain_field.EigenstrainField(grid, 0.3, (3, 2, 2), (9, 8, 7))
        assert grouped_field._transforms().by_columns
        assert np.abs(grouped_field.volume(field) - volume).max() <= 1e-14 * np.abs(volume).max()
