"""Pruned 3-D FFTs of a box of cuboids on its padded lattice, a block of ``q3`` wavenumbers at a time.

A box field ``(m1, m2, m3)`` zero-padded to ``N1 x N2 x N3`` (each ``N >= 2 m``, so that circular
convolutions are linear) has most of its padded lattice zero, and a product needs its result on the
box only. The 3-D transform is taken one axis at a time, each over the lines that can be nonzero
(forward) or that are needed (inverse):

- along ``x3`` (real to complex): the ``m1 m2`` lines of the box (of the ``N1 N2`` of the lattice);
- along ``x2``: the ``m1`` rows of ``x1`` the box covers, for each ``q3``;
- along ``x1``: every line, for each ``q3``.

That is half the work of the whole lattice's transforms (``8 m^3`` against ``16 m^3`` line points
for ``N = 2 m``). The result may also be taken on other points of the lattice than the box's (``target``: a
grid around the box, :class:`~framework.operators.eigenstrain_field.EigenstrainField`'s): then every row is
transformed back along ``x2`` and the target's lines along ``x3``. The spectral pass between the forward and
inverse transforms acts on each ``q3`` alone (the passes of :mod:`framework.operators._box_loops` pair
``q1, q2`` with ``-q1, -q2`` only), so the spectra are held for a block of ``q3`` at a time: ``6 N1 N2 b`` values instead of
``6 N1 N2 (N3/2 + 1)``, and no padded real array: memory follows the box, not its padded lattice.

A block's spectra are laid out ``(N1, N2, 6, b)``: a wavenumber's six components side by side, the ``6 b`` values the
passes read and write together in one run of memory. Laid out ``(6, N1, N2, b)``, a pass gathered six rows of ``b``
values from six places for each wavenumber; on wide lattices, whose blocks are short, that cost it a third of its
time (30 glass spheres' 250 x 250 x 120 lattice, blocks of 21: 45 -> 33 ms a block), and the transforms along x1
and x2, batched over ``6 b`` contiguous values instead of ``b``, ran faster too there (31 -> 25 ms along x1). The
box's lines along x3 are laid out the same way, ``(m1, m2, 6, N3/2 + 1)``, all six components transformed by one
plan in place (the real values of a line in its spectrum's memory): a block's box rows are a slice of them, copied
in one run of ``b`` values a line. In one block of ``q3`` (every box up to about 85^3 cuboids) the lines are the
block's own box rows, and nothing is copied between the transforms along x3 and x2. The copies between a box field
``(m1, m2, m3, 6)`` and the lines read or write a cuboid's six components together (a component at a time, each pass
wrote every cache line of the field: 4.6 ms of a 64^3 box's product).

Each row ``q1`` of a block is followed by a few numbers of padding (:data:`ROW_PAD`: rows a power of two apart share
the caches' sets), and a block larger than :data:`COLUMNS_FROM` may be transformed along x1 a column ``q2`` and its
reversal at a time, passed between its transforms while they are in the caches (``by_columns``; the eigenstrain
operator's stiffness pass runs on the columns it is given).
"""
import numpy as np

from .. import fft
from ._box_loops import loops

#: Applications planned by FFTW's estimate before the transforms are planned again by measurement (where asked):
#: measuring costs more than it saves in a short solve (a 64^3 box: 1.6 s of planning for 85 instead of 107 ms
#: an application) and pays within a few steps of a long run (a 30^3 box: 0.4 s, 6.3 instead of 12.4 ms). Plans
#: FFTW's wisdom already holds (measured by an earlier process, :mod:`framework.fft`) are taken measured at once.
MEASURE_AFTER = 64
#: Lattices of more points than this are planned by measurement at once: their estimated plans (strided batches
#: of long lines) run far slower (a 96^3 box: 730 against 393 ms an application; 128^3: 5.4 against 1.1 s).
MEASURE_AT_ONCE_POINTS = 2 ** 22

#: Memory the spectra of one block of ``q3`` wavenumbers may take [bytes] (a small box takes them all at once).
#: Shorter blocks cost the spectral pass its runs along ``q3``: on a 256 x 256 x 256 lattice (a 128^3 box) a
#: product's pass took 226 ms in blocks of 19 (128 MiB), 205 in blocks of 24, 181-189 in blocks of 32 or 40, and
#: the product 1.01, 0.97 (blocks of 16), 0.95 and 0.92 s (blocks of 40, 252 MB).
BLOCK_BYTES = 256 * 2**20
#: A block's ``q3`` are a multiple of this many where there are more (the compiled pass's vectors: 19 q3 took as
#: long as 24).
VECTOR = 8
#: The eigenstrain operator's blocks hold at least this many ``q3`` (one vector of its spectral pass) whatever their
#: memory: on a wide lattice :data:`BLOCK_BYTES` left a few, and the pass, which runs along ``q3``, slowed to three
#: times its speed on long runs (300 glass spheres' 744 x 744 x 120 lattice: blocks of 2, its pass 3.9 s against its
#: transforms' 2.7 s; blocks of 8, 430 MB, 1.9 s: a product 10.4 -> 8.0 s).
LEAST_Q3 = 8
#: Complex numbers after each row ``q1`` of a block's spectra: rows a multiple of 4 KiB apart (blocks of 8, 16, 32
#: q3 on a 256-wide lattice) mapped the transforms along x1 onto a few cache sets, 1.4-1.5 ms a q3 against 1.0
#: (a 256 x 256 x 6 x 32 block's forward transform along x1 44.7 -> 31.5 ms).
ROW_PAD = 4
#: Memory of the columns ``q2`` (with their reversals) whose transforms along x1 and pass are taken together
#: (``by_columns``) [bytes]: they stay in the processor's caches between the three, where a whole block went through
#: the memory three times (a 64^3 box's transforms and pass 75.7 -> 68.7 ms, its pass 22 ms of which 8 ms reading
#: the kernels, each twice).
COLUMN_BYTES = 2 * 2**20
#: Blocks of at most this many bytes are passed whole even ``by_columns`` (they stay in the caches anyway, and a pass
#: by columns reads each stored kernel twice, far apart: a 31^3 box's transforms and pass 5.5 against 5.1 ms whole; a
#: 64^3 box's, 102 MB a block, 68.7 against 75.7 ms).
COLUMNS_FROM = 32 * 2**20


def q3_blocks(fft_shape, block_bytes=BLOCK_BYTES, least=1):
    """The blocks ``[(k0, k1), ...]`` of ``q3`` wavenumbers (``0 .. N3/2``) whose six spectra on the lattice
    ``fft_shape`` take at most ``block_bytes`` each, or hold ``least`` wavenumbers where that takes more: all of one
    size, a multiple of :data:`VECTOR` where it is more, but the last."""
    n1, n2, n3 = fft_shape
    h = n3 // 2 + 1
    size = int(min(h, max(1, least, block_bytes // (6 * n1 * n2 * 16))))
    if VECTOR < size < h:
        size -= size % VECTOR
    return [(k0, min(h, k0 + size)) for k0 in range(0, h, size)]


def buffer_sizes(shape, fft_shape, block_bytes=BLOCK_BYTES, least=1):
    """Memory of each of a :class:`BoxFFT`'s buffers [bytes], by name: one block of ``q3``'s spectra on the lattice
    and, where there are several blocks, the box's lines' spectra along x3 (in one block, the block holds them)."""
    (m1, m2, _), (n1, n2, n3) = shape, fft_shape
    h = n3 // 2 + 1
    blocks = q3_blocks(fft_shape, block_bytes, least)
    sizes = {"block": 16 * n1 * (6 * n2 * max(k1 - k0 for k0, k1 in blocks) + ROW_PAD)}
    if len(blocks) > 1:
        sizes["lines"] = 16 * 6 * m1 * m2 * h
    return sizes


def buffer_bytes(shape, fft_shape, block_bytes=BLOCK_BYTES, least=1, share=None):
    """Memory of a :class:`BoxFFT`'s buffers [bytes]; with ``share`` (the ``(fft_shape, block_bytes, least)`` of a
    BoxFFT of the same box whose buffers it takes), only what those cannot hold."""
    sizes = buffer_sizes(shape, fft_shape, block_bytes, least)
    if share is None:
        return sum(sizes.values())
    held = buffer_sizes(shape, *share)
    return sum(size for name, size in sizes.items() if size > held.get(name, 0))


class BoxFFT:
    """``F^-1 [pass(F field)]`` on the padded lattice of a box, restricted to the box, for six components.

    Parameters
    ----------
    shape : tuple of int
        The box ``(m1, m2, m3)``.
    fft_shape : tuple of int
        The padded lattice ``(N1, N2, N3)``, each at least the box's.
    effort : str
        FFTW's planner flag for the transforms ("FFTW_MEASURE": on a lattice of at most
        :data:`MEASURE_AT_ONCE_POINTS` points by estimate for the first :data:`MEASURE_AFTER`
        applications, then measured).
    block_bytes : int
        Memory of the spectra of one block of ``q3`` [bytes].
    least : int
        Wavenumbers ``q3`` a block holds at least (:func:`q3_blocks`).
    share : BoxFFT, optional
        A BoxFFT of the same box on another lattice whose buffers this one takes where they are large enough
        (:func:`buffer_bytes`): the two must not run at once (a product's transforms and a preconditioner's are
        taken in turns). Each application writes every value it reads (the lines' padding included), so either may
        follow the other.
    by_columns : bool
        Take a block's transforms along x1 a few columns ``q2`` at a time (:data:`COLUMN_BYTES`, with their
        reversals ``-q2``: :attr:`column_ranges` of ``0 .. N2/2``), so that :meth:`apply` may pass each group between
        its forward and inverse transforms while it is in the caches (``columns=True``), where a block takes more
        than :data:`COLUMNS_FROM` (the attribute tells whether it does).
    """

    def __init__(self, shape, fft_shape, effort="FFTW_MEASURE", block_bytes=BLOCK_BYTES, least=1, share=None,
                 by_columns=False):
        self.shape, self.fft_shape = tuple(shape), tuple(fft_shape)
        (m1, m2, _), (n1, n2, n3) = self.shape, self.fft_shape
        if share is not None and share.shape != self.shape:
            raise ValueError(f"a BoxFFT shares the buffers of one of the same box, not {share.shape}")
        self.h = n3 // 2 + 1
        self.blocks = q3_blocks(self.fft_shape, block_bytes, least)
        self.block = self.blocks[0][1]
        self._owner = self if share is None else share._owner    # who holds the memory
        if share is None:
            self._memory = {}
        self._buffers = {}          # a block of q3's spectra, by block size
        self._block_memory = None   # the first block's, which the last one's takes
        self._state = None          # (the BoxFFT, the block size) whose rows q1 >= m1 the memory holds zeroed
        n1, n2 = self.fft_shape[:2]
        self.by_columns = bool(by_columns) and 16 * n1 * (6 * n2 * self.block + ROW_PAD) > COLUMNS_FROM
        width = max(1, COLUMN_BYTES // (2 * n1 * 6 * self.block * 16))
        self.column_ranges = [(c0, min(n2 // 2 + 1, c0 + width)) for c0 in range(0, n2 // 2 + 1, width)]
        self._all_rows = {}         # every row's inverse along x2, by block size (a target's)
        # The box's lines along x3, (m1, m2, 6, N3/2 + 1) complex, transformed in place (their real values (m1, m2, 6,
        # N3) in the same memory, each line's N3/2 + 1 complex numbers): in one block of q3, the block's own box
        # rows and columns, so nothing is copied between the transforms along x3 and x2 (a 64^3 box's product 4 ms
        # less, and 26 MB); in several, an array of their own, a block's q3 copied in and out.
        self.direct = len(self.blocks) == 1
        if self.direct:
            block = self._block_buffer(self.block)
            self._lines, self._lines_real = block[:m1, :m2], block.view(float)
        else:
            self._lines = self._buffer("lines", (m1, m2, 6, self.h), complex)
            self._lines_real = self._lines.view(float)
        self.measure, self.applications = effort == "FFTW_MEASURE", 0
        later = self.measure and n1 * n2 * n3 <= MEASURE_AT_ONCE_POINTS
        self._plan("wisdom" if later else effort)

    def _buffer(self, name, shape, dtype):
        """A zeroed array of ``shape`` in the owner's memory ``name`` where that holds it, else of its own (the
        owner's becomes that memory)."""
        size = int(np.prod(shape)) * np.dtype(dtype).itemsize
        memory = self._owner._memory.get(name)
        if memory is not None and memory.nbytes >= size:
            memory[:size] = 0
            return memory[:size].view(dtype).reshape(shape)
        array = fft.zeros(shape, dtype)
        if self._owner is self:
            self._memory[name] = array.reshape(-1).view(np.uint8)
        return array

    def _block_buffer(self, size):
        """The spectra ``(N1, N2, 6, size)`` of a block of ``size`` q3, each row ``q1`` followed by :data:`ROW_PAD`
        numbers (a shorter last block in the first's memory)."""
        if size not in self._buffers:
            n1, n2 = self.fft_shape[:2]
            pitch = 6 * n2 * size + ROW_PAD
            if self._block_memory is None or size > self.block:
                self._block_memory = self._buffer("block", (n1 * pitch,), complex)
            memory = self._block_memory[:n1 * pitch]
            self._buffers[size] = memory.reshape(n1, pitch)[:, :6 * n2 * size].reshape(n1, n2, 6, size)
        return self._buffers[size]

    def _plan(self, effort):
        """(Re)plan every transform with FFTW's ``effort`` (the buffers' contents are not kept: each application
        writes what it reads); ``"wisdom"``: measured where FFTW's wisdom holds the plan, else estimated
        (:class:`framework.fft.Transform`)."""
        self.effort = effort
        self._owner._state = None       # measuring writes on the buffers
        m1, m2, n3 = self.shape[0], self.shape[1], self.fft_shape[2]
        values = self._lines_real[:m1, :m2, :, :n3]
        self._line_forward = fft.Transform(values, self._lines, axes=(3,), effort=effort)
        self._line_inverse = fft.Transform(self._lines, values, axes=(3,), effort=effort)
        self._plans = {}
        for size in sorted({k1 - k0 for k0, k1 in self.blocks}, reverse=True):     # the first block's buffer first
            self._block_plans(size)
        if effort == "wisdom":      # measured if every transform was (none to plan again), else estimated
            transforms = [self._line_forward, self._line_inverse]
            for _, rows_forward, slabs, rows_inverse in self._plans.values():
                transforms += [rows_forward, rows_inverse, *(t for _, forward, inverse in slabs
                                                              for t in (*forward, *inverse))]
            self.effort = ("FFTW_MEASURE" if all(t.effort == "FFTW_MEASURE" for t in transforms)
                           else "FFTW_ESTIMATE")

    def _block_plans(self, size):
        """Buffer ``(N1, N2, 6, size)`` and its transforms (for the block size and for the last, shorter one):
        ``(spectra, rows_forward, slabs, rows_inverse)``, ``slabs`` the transforms along x1 as
        ``[(columns, forward, inverse), ...]`` (one slab of every column where not :attr:`by_columns`)."""
        if size not in self._plans:
            spectra = self._block_buffer(size)
            rows = spectra[:self.shape[0]]
            effort, n2 = self.effort, self.fft_shape[1]
            slabs = []
            for c0, c1 in (self.column_ranges if self.by_columns else [(0, n2)]):
                parts = [spectra[:, c0:c1]]
                low, high = max(n2 - c1 + 1, n2 // 2 + 1), min(n2 - c0 + 1, n2)      # the reversals' columns
                if self.by_columns and low < high:
                    parts.append(spectra[:, low:high])
                slabs.append(((c0, c1), [fft.Transform(part, part, axes=(0,), effort=effort) for part in parts],
                              [fft.Transform(part, part, axes=(0,), inverse=True, effort=effort) for part in parts]))
            self._plans[size] = (spectra,
                                 fft.Transform(rows, rows, axes=(1,), effort=effort),                # x2, box rows
                                 slabs,
                                 fft.Transform(rows, rows, axes=(1,), inverse=True, effort=effort))
        return self._plans[size]

    def apply(self, field, spectral_pass, weights_in=None, weights_out=None, target=None, columns=False):
        """The box field ``(m1, m2, m3, 6)`` of ``F^-1 [spectral_pass(F (field * weights_in))] * weights_out``.

        ``spectral_pass(spectra, k0, k1)`` changes the six spectra ``(N1, N2, 6, k1 - k0)`` of the
        wavenumbers ``q3 = k0 .. k1 - 1`` in place (``q1, q2`` over the whole lattice, unnormalised);
        the result is normalised by the lattice's number of points. With ``columns`` (a BoxFFT made
        ``by_columns``), ``spectral_pass(spectra, k0, k1, (c0, c1))`` changes those of the columns ``c0 <= q2 < c1``
        and their reversals only, called for each group of :attr:`column_ranges` while it is in the caches.

        ``target``, three arrays of lattice indices (one per axis): the result ``(t1, t2, t3, 6)`` at those
        points instead of the box's (the box lies at the lattice's indices ``0 .. m - 1``). Its spectra along
        ``x3`` are held for every ``q3`` (``6 t1 t2 (N3/2 + 1)`` complex numbers) while the blocks go, and its
        line transforms are planned by estimate at each call.
        """
        ones = np.ones(6)
        weights_in = ones if weights_in is None else weights_in
        weights_out = ones if weights_out is None else weights_out
        if target is not None:
            return self._apply_to(field, spectral_pass, weights_in, weights_out, [np.asarray(t) for t in target],
                                  columns)
        (m1, m2, m3), (n1, n2, n3) = self.shape, self.fft_shape
        self.applications += 1
        if self.measure and self.effort != "FFTW_MEASURE" and self.applications >= MEASURE_AFTER:
            self._plan("FFTW_MEASURE")
        for k0, k1, spectra, rows_inverse in self._passes(field, spectral_pass, weights_in, columns=columns):
            rows_inverse()
            if not self.direct:
                self._lines[..., k0:k1] = spectra[:m1, :m2]
        out = np.empty((m1, m2, m3, 6))
        self._line_inverse()
        loops().put_lines(out, self._lines_real, (1.0 / (n1 * n2 * n3)) * np.asarray(weights_out, dtype=float))
        return out

    def _passes(self, field, spectral_pass, weights_in, clear=True, columns=False):
        """The box's lines transformed along x3, then for each block of q3 its spectra transformed along x2 and x1,
        passed, and back along x1 (by groups of columns where :attr:`by_columns`): yields ``(k0, k1, spectra,
        rows_inverse)`` (the box rows' transform back along x2). With ``clear``, the rows ``q1 >= m1`` are zeroed
        again after the transforms back along x1 (a target reads them: then at the next block)."""
        (m1, m2, _), n3 = self.shape, self.fft_shape[2]
        if columns and not self.by_columns:
            raise ValueError("a pass by columns needs a BoxFFT made by_columns")
        loops().take_lines(self._lines_real, field, np.asarray(weights_in, dtype=float), n3)
        self._line_forward()
        for k0, k1 in self.blocks:
            spectra, rows_forward, slabs, rows_inverse = self._block_plans(k1 - k0)
            if self._owner._state != (self, k1 - k0):       # the rows' padding holds another's values
                spectra[m1:] = 0.0
            self._owner._state = None                       # (until this block is through)
            spectra[:m1, m2:] = 0.0                         # the columns' padding (the last inverse left values)
            if not self.direct:
                spectra[:m1, :m2] = self._lines[..., k0:k1]
            rows_forward()
            # by columns, each group passed between its transforms; else all transformed, passed, transformed back
            groups = slabs if columns else [(None, [t for _, forward, _ in slabs for t in forward],
                                             [t for _, _, inverse in slabs for t in inverse])]
            for group, forward, inverse in groups:
                for transform in forward:
                    transform()
                if columns:
                    spectral_pass(spectra, k0, k1, group)
                else:
                    spectral_pass(spectra, k0, k1)
                for transform in inverse:
                    transform()
                    if clear:
                        transform.target[m1:] = 0.0         # (by columns, while in the caches)
            self._owner._state = (self, k1 - k0) if clear else None
            yield k0, k1, spectra, rows_inverse

    def _apply_to(self, field, spectral_pass, weights_in, weights_out, target, columns):
        """:meth:`apply` with a ``target``: every row back along x2, the target's rows and columns gathered a block at
        a time, then the target's lines back along x3."""
        n1, n2, n3 = self.fft_shape
        t1, t2, t3 = target
        lines = np.empty((6, t1.size, t2.size, self.h), complex)
        for k0, k1, spectra, _ in self._passes(field, spectral_pass, weights_in, clear=False, columns=columns):
            if (k1 - k0) not in self._all_rows:
                self._all_rows[k1 - k0] = fft.Transform(spectra, spectra, axes=(1,), inverse=True,
                                                        effort="FFTW_ESTIMATE")
            self._all_rows[k1 - k0]()
            lines[..., k0:k1] = np.moveaxis(np.take(np.take(spectra, t1, axis=0), t2, axis=1), 2, 0)
        spectrum, values = fft.zeros((t1.size, t2.size, self.h), complex), fft.zeros((t1.size, t2.size, n3))
        back = fft.Transform(spectrum, values, axes=(2,), effort="FFTW_ESTIMATE")
        out = np.empty((t1.size, t2.size, t3.size, 6))
        scale = 1.0 / (n1 * n2 * n3)
        for c in range(6):
            spectrum[...] = lines[c]
            back()
            np.multiply(np.take(values, t3, axis=2), scale * weights_out[c], out=out[..., c])
        return out

    def transforms_alone(self):
        """Run the transforms of one :meth:`apply`, in its order, without the copies and the pass: the FFT
        work a product must do (the benches' floor)."""
        self._line_forward()
        for k0, k1 in self.blocks:
            _, rows_forward, slabs, rows_inverse = self._block_plans(k1 - k0)
            rows_forward()
            for _, forward, inverse in slabs:
                for transform in (*forward, *inverse):
                    transform()
            rows_inverse()
        self._line_inverse()
