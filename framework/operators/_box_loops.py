"""The spectral passes of the eigenstrain operator, compiled by numba when it is installed.

A product of :class:`~framework.operators.eigenstrain.HalfSpaceEigenstrain` is a few FFTs and
two spectral passes; as numpy expressions the passes cost more than the FFTs (36 products of
whole spectra, each a temporary). Here each is one loop:

===============  ==================================================================================
``stiffness``    ``s <- K_direct s + K_mirror m`` in place on the six spectra ``s`` of a box (or of a block
                 of ``q3``, with the kernels of that block; ``(N1, N2, 6, b)``: a wavenumber's six components
                 side by side, :mod:`~framework.operators.box_fft`), ``m``
                 the mirror image's spectra (``conj(s)`` at the reversed wavenumbers ``-q1, -q2``
                 times the component's mirror sign; the phase in ``q3`` is in ``K_mirror``). The 21 kernels of each
                 term are stored for ``q1, q2 >= 0`` only (each is even or odd in ``q1`` and ``q2``:
                 a quarter of the memory), on a square lattice for ``q1 <= q2`` only (:func:`kernel_table`:
                 an eighth); a wavenumber and its reversal share their kernel values,
                 so the loop takes them in pairs, which also lets it write in place. It takes the wavenumbers
                 its items name (:func:`pass_items`: some columns ``q2`` and their reversals, while a
                 block's transforms along ``x1`` are taken a few columns at a time), and a block's rows
                 ``q1`` may be padded (:func:`flat_rows`)
``surface_sum``  ``total += sum_p kernels[p] * spectra[p]``: the sum over a box's layers and
                 components that gives a surface field's spectrum (the kernels stored for
                 ``q1 >= 0`` as real factors, each with a complex factor and its parity in ``q1``)
``surface_spread`` ``out[p] = kernels[p] * spectrum``: a surface field's spectrum spread over the
                 layers and components of a box, the same storage
``surface_planes`` a layer of a box field into the six planes of its surface transforms (``surface_add``: back,
                 scaled, into a box field)
``take_lines``   a box field's six components into the lines of its transforms along ``x3``
                 ``(m1, m2, 6, >= N3)``, weighted, their zero padding written (``put_lines``: back, weighted)
``compliance``   Hooke's law inverted in place on ``(n, 6)`` stresses (unit modulus)
``fourier_apply`` ``s(q) <- M(q) s(q)``, a 6 x 6 real matrix per wavenumber (a preconditioner's), stored
                 for every wavenumber or, when the components' parities allow, for ``q1, q2 >= 0``
===============  ==================================================================================

The copies are loops too: as numpy expressions they gather or scatter a component at a stride of six, with a
temporary, 0.7 of the rolling bench's 22 ms product.

The compiled loops are used when numba is installed and :func:`framework._fused.set_compiled`
allows it; else the numpy forms below, which give the same numbers to rounding.
"""
import numpy as np

from .. import _fused

#: The 21 entries ``(a, b)``, ``a <= b``, of ``C : D`` (a symmetric 6 x 6 kernel), in the order of the stored spectra.
ENTRIES = tuple((a, b) for b in range(6) for a in range(b + 1))
#: Wavenumbers ``q3`` the compiled stiffness pass takes at a time: the pitch of its scratch rows (a multiple of 8,
#: the vector loop's width).
CHUNK = 32
#: The entry of ``C : D`` that each entry of ENTRIES becomes when x1 and x2 swap (xx <-> yy, yz <-> xz): a kernel at
#: ``(q2, q1)`` is the one at ``(q1, q2)`` with its entries so permuted, on a lattice and cuboids square in x1, x2.
SWAP = (1, 0, 2, 4, 3, 5)
PERMUTATION = np.array([ENTRIES.index(tuple(sorted((SWAP[a], SWAP[b])))) for a, b in ENTRIES], dtype=np.int64)


def kernel_table(q1, q2, symmetric):
    """Which stored kernel serves each wavenumber ``(i1, i2)`` of ``q1, q2 >= 0`` (``q1 x q2`` of them):
    ``(table, first, second)`` with ``table (q1, q2, 2)`` the stored kernel's index and 1 where it is read with its
    entries permuted (:data:`PERMUTATION`: if ``symmetric`` (``q1 == q2``), the kernels of ``i1 > i2`` are those of
    ``(i2, i1)`` so read), and ``first, second`` the stored kernels' ``(i1, i2)`` in the whole ``(q1, q2)`` arrays
    (``kernels[:, first, second]`` packs them: ``T = q (q + 1) / 2`` when symmetric, ``q1 q2`` else)."""
    if symmetric and q1 != q2:
        raise ValueError(f"symmetric kernels need a square lattice, got {q1} x {q2} wavenumbers")
    if symmetric:
        first, second = np.triu_indices(q1)
    else:
        first, second = (index.ravel() for index in np.indices((q1, q2)))
    table = np.zeros((q1, q2, 2), dtype=np.int64)
    table[first, second, 0] = np.arange(first.size)
    if symmetric:
        table[second, first, 0] = np.arange(first.size)
        table[second, first, 1] = first != second
    return table, first, second


def pass_items(table, columns=None):
    """The stiffness pass's items ``(M, 4)``, rows ``(t, i1, i2, permuted)`` of :func:`kernel_table`'s ``table``, for
    every ``i1`` of ``q1`` (with their reversals ``-i1``) and the wavenumbers ``i2`` in ``columns`` (each at most
    ``q2 - 1``, with their reversals), column by column; by default for every ``i2``, ordered by stored kernel (a
    kernel's two readers one after the other: the second reads it from the caches)."""
    q1, q2 = table.shape[:2]
    every = columns is None
    columns = np.arange(q2) if every else np.asarray(list(columns), dtype=np.int64)
    i1, i2 = np.tile(np.arange(q1), columns.size), np.repeat(columns, q1)
    items = np.stack([table[i1, i2, 0], i1, i2, table[i1, i2, 1]], axis=1)
    if every:
        items = items[np.lexsort((items[:, 3], items[:, 0]))]
    return np.ascontiguousarray(items)


class PassItems:
    """An operator's stiffness-pass items (:func:`pass_items` of its kernels' ``table``), made at first use and kept:
    ``items((c0, c1))`` for the columns ``c0 <= q2 < c1`` (a pass by columns,
    :class:`~framework.operators.box_fft.BoxFFT`), ``items(None)`` for all of them."""

    def __init__(self, table):
        self.table, self._made = table, {}

    def __call__(self, columns=None):
        if columns not in self._made:
            self._made[columns] = pass_items(self.table, None if columns is None else range(*columns))
        return self._made[columns]


def flat_rows(spectra):
    """The memory of a block's spectra ``(N1, N2, 6, b)`` (C-ordered but for a padding after each row ``i1``) as
    ``(N1, pitch)``: each row and its padding, what the compiled stiffness pass indexes."""
    pitch = spectra.strides[0] // spectra.itemsize
    if spectra.strides[1:] != (6 * spectra.shape[3] * 16, spectra.shape[3] * 16, 16) or pitch < spectra[0].size:
        raise ValueError(f"spectra of strides {spectra.strides} are not a block's (N1, N2, 6, b) rows")
    return np.lib.stride_tricks.as_strided(spectra, shape=(spectra.shape[0], pitch),
                                           strides=(spectra.strides[0], spectra.itemsize))


def stored_kernels(kernels):
    """The 21 entries' kernels ``(21, q1, q2, b)``, or ``(21, T, b)`` (those stored, :func:`kernel_table`), laid out
    as the stiffness pass reads them: ``(T, 21, b)``, a stored kernel's entries side by side (laid out ``(21, T,
    b)``, the pass read each wavenumber's from 42 places a block's whole kernels apart, 1.3 MB on a 256^3 lattice:
    its pass 7-8 % slower there, 5 % on 128^3)."""
    return np.ascontiguousarray(np.moveaxis(kernels.reshape(kernels.shape[0], -1, kernels.shape[-1]), 0, 1))


class _Loops:
    """The passes as loops, for numba."""

    def stiffness_rows(rows_memory, n2, h, direct, mirror, items, permutation, parity1, parity2, mirror_sign):
        # The four wavenumbers +-q1, +-q2 that share a stored kernel value (a group), a chunk of CHUNK q3 at a time:
        # their six components (times their signs) are copied into the rows of S, real and imaginary parts apart,
        # and the kernels into K; one loop computes a pair's (a wavenumber's and its reversal's) results into O,
        # which go back. Rows of one array at the constant pitch CHUNK let the compiler vectorise that loop (8 q3 at
        # once: rows of arrays that may alias at runtime distances needed too many alias checks, and complex values
        # read in place kept it scalar): 6.1 -> 3.1-3.8 ms on the rolling bench's 60 x 64 x 31 lattice, 45 -> 27 ms
        # on a 128 x 128 x 65 half lattice, the same numbers. The copies index by unsigned offsets (numba wraps a
        # signed index that may be negative, which keeps a loop scalar). Unrolled for the 21 entries of ENTRIES
        # (first, second are theirs: the numpy form reads them).
        # An item (t, i1, i2, permuted) names a group (i1, i2 >= 0 and their reversals) and its stored kernel t,
        # whose 21 entries go into K permuted (``permutation``) where ``permuted``: a square lattice stores the
        # kernels of q1 <= q2 only, half the memory (:func:`kernel_table`). ``rows_memory`` is the block's
        # (N1, pitch) memory (:func:`flat_rows`), ``n2, h`` its columns and q3.
        # A pair whose image factors f are all 1 (``plain``: every pair but those of a row or column that is its own
        # reversal, for the half-space's mirror signs and parities) has o_p = A x + B y and conj(o_q) = A y + conj(B) x,
        # x = s_p, y = conj(s_q), A the real direct kernel, B = Br + i Bi the mirror one: with s = x + y, d = x - y,
        # o_p + conj(o_q) = (A + Br) s - i Bi d and o_p - conj(o_q) = (A - Br) d + i Bi s. That is eight real 6 x 6
        # products a pair instead of twelve, in two sweeps of 24 live values (the real parts of the first sum and
        # the imaginary parts of the second, then the others), K holding (A + Br) / 2, (A - Br) / 2 and Bi / 2:
        # a 128 x 128 x 65 half lattice's pass 24.8 -> 22.3 ms, the static bench's product 1.46-1.51 -> 1.41 its FFTs.
        n1, pitch = rows_memory.shape
        values = rows_memory.reshape(-1).view(np.float64)      # real and imaginary parts, interleaved
        kernel, image = direct.reshape(-1), mirror.reshape(-1).view(np.float64)
        half1, half2 = n1 // 2, n2 // 2
        C = CHUNK
        S = np.zeros(24 * C)    # rows: the wavenumber's six real parts, its six imaginary parts, then its reversal's
        O = np.zeros(24 * C)    # the results, the same rows
        K = np.zeros(63 * C)    # rows: the 21 direct kernels, the 21 mirror kernels' real parts, their imaginary parts
        g, f = np.empty((4, 6)), np.empty(6)
        offsets = np.empty((2, 6), dtype=np.uint64)  # where a pair's six components start in the spectra
        rows, columns = np.empty(4, dtype=np.int64), np.empty(4, dtype=np.int64)
        one, two = np.uint64(1), np.uint64(2)
        for item in range(items.shape[0]):
            t, i1, i2, swapped = items[item, 0], items[item, 1], items[item, 2], items[item, 3] != 0
            r1, r2 = (n1 - i1) % n1, (n2 - i2) % n2
            # two pairs (a wavenumber, its reversal) share the kernel at (i1, i2); one where a row or a
            # column is its own reversal
            rows[0], columns[0], rows[1], columns[1] = i1, i2, r1, r2
            rows[2], columns[2], rows[3], columns[3] = i1, r2, r1, i2
            npairs = 2 if i1 != r1 and i2 != r2 else 1
            single = i1 == r1 and i2 == r2
            for s in range(4):
                for c in range(6):
                    g[s, c] = ((parity1[c] if rows[s] > half1 else 1.0) * (parity2[c] if columns[s] > half2 else 1.0))
            plain = True
            for pair in range(npairs):
                for c in range(6):
                    if mirror_sign[c] * g[2 * pair, c] * g[2 * pair + 1, c] != 1.0:
                        plain = False
            for k0 in range(0, h, C):
                count = min(C, h - k0)
                n = np.uint64(count)
                # the kernels (a swapped wavenumber's entries permuted)
                for e in range(21):
                    entry = permutation[e] if swapped else e
                    at = np.uint64((t * 21 + entry) * h + k0)
                    d, re, im = np.uint64(e * C), np.uint64((21 + e) * C), np.uint64((42 + e) * C)
                    if plain:
                        for k in range(n):
                            kd, mr = kernel[at + k], image[two * (at + k)]
                            K[d + k], K[re + k] = 0.5 * (kd + mr), 0.5 * (kd - mr)
                            K[im + k] = 0.5 * image[two * (at + k) + one]
                    else:
                        for k in range(n):
                            K[d + k] = kernel[at + k]
                            K[re + k], K[im + k] = image[two * (at + k)], image[two * (at + k) + one]
                for pair in range(npairs):
                    p, q = 2 * pair, 2 * pair + 1
                    for c in range(6):
                        gp, gq = g[p, c], g[q, c]
                        f[c] = mirror_sign[c] * gp * gq     # the image: f times the other's conjugate, as copied
                        offsets[0, c] = a = np.uint64(2 * (rows[p] * pitch + (columns[p] * 6 + c) * h + k0))
                        offsets[1, c] = b = np.uint64(2 * (rows[q] * pitch + (columns[q] * 6 + c) * h + k0))
                        s0, s1 = np.uint64(c * C), np.uint64((6 + c) * C)
                        s2, s3 = np.uint64((12 + c) * C), np.uint64((18 + c) * C)
                        for k in range(n):
                            S[s0 + k], S[s1 + k] = gp * values[a + two * k], gp * values[a + two * k + one]
                            S[s2 + k], S[s3 + k] = gq * values[b + two * k], gq * values[b + two * k + one]
                    if plain:     # f = 1: the sums and differences of the pair (see above)
                        # two sweeps of one form: s = 1 takes x, y = the real parts of the sum, the imaginary
                        # ones of the difference, and gives u, v = the real parts of (A + Br) s - i Bi d, the
                        # imaginary ones of (A - Br) d + i Bi s; s = -1 the others
                        for sweep in range(2):
                            s = 1.0 - 2.0 * sweep
                            xs, ys, us = 6 * sweep * C, 6 * (1 - sweep) * C, 12 * sweep * C
                            for k in range((count + 7) // 8 * 8):
                                x0 = S[k + xs + 0 * C] + s * S[k + xs + 12 * C]
                                y0 = S[k + ys + 0 * C] + s * S[k + ys + 12 * C]
                                x1 = S[k + xs + 1 * C] + s * S[k + xs + 13 * C]
                                y1 = S[k + ys + 1 * C] + s * S[k + ys + 13 * C]
                                x2 = S[k + xs + 2 * C] + s * S[k + xs + 14 * C]
                                y2 = S[k + ys + 2 * C] + s * S[k + ys + 14 * C]
                                x3 = S[k + xs + 3 * C] + s * S[k + xs + 15 * C]
                                y3 = S[k + ys + 3 * C] + s * S[k + ys + 15 * C]
                                x4 = S[k + xs + 4 * C] + s * S[k + xs + 16 * C]
                                y4 = S[k + ys + 4 * C] + s * S[k + ys + 16 * C]
                                x5 = S[k + xs + 5 * C] + s * S[k + xs + 17 * C]
                                y5 = S[k + ys + 5 * C] + s * S[k + ys + 17 * C]
                                kp, km, kb = K[k + 0 * C], K[k + 21 * C], s * K[k + 42 * C]
                                u0 = kp * x0 + kb * y0; v0 = km * y0 + kb * x0
                                kp, km, kb = K[k + 1 * C], K[k + 22 * C], s * K[k + 43 * C]
                                u0 += kp * x1 + kb * y1; v0 += km * y1 + kb * x1
                                u1 = kp * x0 + kb * y0; v1 = km * y0 + kb * x0
                                kp, km, kb = K[k + 2 * C], K[k + 23 * C], s * K[k + 44 * C]
                                u1 += kp * x1 + kb * y1; v1 += km * y1 + kb * x1
                                kp, km, kb = K[k + 3 * C], K[k + 24 * C], s * K[k + 45 * C]
                                u0 += kp * x2 + kb * y2; v0 += km * y2 + kb * x2
                                u2 = kp * x0 + kb * y0; v2 = km * y0 + kb * x0
                                kp, km, kb = K[k + 4 * C], K[k + 25 * C], s * K[k + 46 * C]
                                u1 += kp * x2 + kb * y2; v1 += km * y2 + kb * x2
                                u2 += kp * x1 + kb * y1; v2 += km * y1 + kb * x1
                                kp, km, kb = K[k + 5 * C], K[k + 26 * C], s * K[k + 47 * C]
                                u2 += kp * x2 + kb * y2; v2 += km * y2 + kb * x2
                                kp, km, kb = K[k + 6 * C], K[k + 27 * C], s * K[k + 48 * C]
                                u0 += kp * x3 + kb * y3; v0 += km * y3 + kb * x3
                                u3 = kp * x0 + kb * y0; v3 = km * y0 + kb * x0
                                kp, km, kb = K[k + 7 * C], K[k + 28 * C], s * K[k + 49 * C]
                                u1 += kp * x3 + kb * y3; v1 += km * y3 + kb * x3
                                u3 += kp * x1 + kb * y1; v3 += km * y1 + kb * x1
                                kp, km, kb = K[k + 8 * C], K[k + 29 * C], s * K[k + 50 * C]
                                u2 += kp * x3 + kb * y3; v2 += km * y3 + kb * x3
                                u3 += kp * x2 + kb * y2; v3 += km * y2 + kb * x2
                                kp, km, kb = K[k + 9 * C], K[k + 30 * C], s * K[k + 51 * C]
                                u3 += kp * x3 + kb * y3; v3 += km * y3 + kb * x3
                                kp, km, kb = K[k + 10 * C], K[k + 31 * C], s * K[k + 52 * C]
                                u0 += kp * x4 + kb * y4; v0 += km * y4 + kb * x4
                                u4 = kp * x0 + kb * y0; v4 = km * y0 + kb * x0
                                kp, km, kb = K[k + 11 * C], K[k + 32 * C], s * K[k + 53 * C]
                                u1 += kp * x4 + kb * y4; v1 += km * y4 + kb * x4
                                u4 += kp * x1 + kb * y1; v4 += km * y1 + kb * x1
                                kp, km, kb = K[k + 12 * C], K[k + 33 * C], s * K[k + 54 * C]
                                u2 += kp * x4 + kb * y4; v2 += km * y4 + kb * x4
                                u4 += kp * x2 + kb * y2; v4 += km * y2 + kb * x2
                                kp, km, kb = K[k + 13 * C], K[k + 34 * C], s * K[k + 55 * C]
                                u3 += kp * x4 + kb * y4; v3 += km * y4 + kb * x4
                                u4 += kp * x3 + kb * y3; v4 += km * y3 + kb * x3
                                kp, km, kb = K[k + 14 * C], K[k + 35 * C], s * K[k + 56 * C]
                                u4 += kp * x4 + kb * y4; v4 += km * y4 + kb * x4
                                kp, km, kb = K[k + 15 * C], K[k + 36 * C], s * K[k + 57 * C]
                                u0 += kp * x5 + kb * y5; v0 += km * y5 + kb * x5
                                u5 = kp * x0 + kb * y0; v5 = km * y0 + kb * x0
                                kp, km, kb = K[k + 16 * C], K[k + 37 * C], s * K[k + 58 * C]
                                u1 += kp * x5 + kb * y5; v1 += km * y5 + kb * x5
                                u5 += kp * x1 + kb * y1; v5 += km * y1 + kb * x1
                                kp, km, kb = K[k + 17 * C], K[k + 38 * C], s * K[k + 59 * C]
                                u2 += kp * x5 + kb * y5; v2 += km * y5 + kb * x5
                                u5 += kp * x2 + kb * y2; v5 += km * y2 + kb * x2
                                kp, km, kb = K[k + 18 * C], K[k + 39 * C], s * K[k + 60 * C]
                                u3 += kp * x5 + kb * y5; v3 += km * y5 + kb * x5
                                u5 += kp * x3 + kb * y3; v5 += km * y3 + kb * x3
                                kp, km, kb = K[k + 19 * C], K[k + 40 * C], s * K[k + 61 * C]
                                u4 += kp * x5 + kb * y5; v4 += km * y5 + kb * x5
                                u5 += kp * x4 + kb * y4; v5 += km * y4 + kb * x4
                                kp, km, kb = K[k + 20 * C], K[k + 41 * C], s * K[k + 62 * C]
                                u5 += kp * x5 + kb * y5; v5 += km * y5 + kb * x5
                                O[k + us + 0 * C], O[k + us + 6 * C] = u0, v0
                                O[k + us + 1 * C], O[k + us + 7 * C] = u1, v1
                                O[k + us + 2 * C], O[k + us + 8 * C] = u2, v2
                                O[k + us + 3 * C], O[k + us + 9 * C] = u3, v3
                                O[k + us + 4 * C], O[k + us + 10 * C] = u4, v4
                                O[k + us + 5 * C], O[k + us + 11 * C] = u5, v5
                        for c in range(6):           # the pair's results from the sum and the difference
                            for k in range((count + 7) // 8 * 8):
                                ur, vi = O[k + c * C], O[k + (6 + c) * C]
                                ui, vr = O[k + (12 + c) * C], O[k + (18 + c) * C]
                                O[k + c * C], O[k + (12 + c) * C] = ur + vr, ur - vr
                                O[k + (6 + c) * C], O[k + (18 + c) * C] = ui + vi, vi - ui
                    else:
                        f0, f1, f2, f3, f4, f5 = f[0], f[1], f[2], f[3], f[4], f[5]
                        for k in range((count + 7) // 8 * 8):      # whole vectors (the rows' ends are scratch)
                            sp0, sq0 = complex(S[k], S[k + 6 * C]), complex(S[k + 12 * C], S[k + 18 * C])
                            sp1, sq1 = complex(S[k + 1 * C], S[k + 7 * C]), complex(S[k + 13 * C], S[k + 19 * C])
                            sp2, sq2 = complex(S[k + 2 * C], S[k + 8 * C]), complex(S[k + 14 * C], S[k + 20 * C])
                            sp3, sq3 = complex(S[k + 3 * C], S[k + 9 * C]), complex(S[k + 15 * C], S[k + 21 * C])
                            sp4, sq4 = complex(S[k + 4 * C], S[k + 10 * C]), complex(S[k + 16 * C], S[k + 22 * C])
                            sp5, sq5 = complex(S[k + 5 * C], S[k + 11 * C]), complex(S[k + 17 * C], S[k + 23 * C])
                            ip0, iq0 = f0 * sq0.conjugate(), f0 * sp0.conjugate()
                            ip1, iq1 = f1 * sq1.conjugate(), f1 * sp1.conjugate()
                            ip2, iq2 = f2 * sq2.conjugate(), f2 * sp2.conjugate()
                            ip3, iq3 = f3 * sq3.conjugate(), f3 * sp3.conjugate()
                            ip4, iq4 = f4 * sq4.conjugate(), f4 * sp4.conjugate()
                            ip5, iq5 = f5 * sq5.conjugate(), f5 * sp5.conjugate()
                            kd, km = K[k], complex(K[k + 21 * C], K[k + 42 * C])
                            op0 = kd * sp0 + km * ip0; oq0 = kd * sq0 + km * iq0
                            kd, km = K[k + 1 * C], complex(K[k + 22 * C], K[k + 43 * C])
                            op0 += kd * sp1 + km * ip1; oq0 += kd * sq1 + km * iq1
                            op1 = kd * sp0 + km * ip0; oq1 = kd * sq0 + km * iq0
                            kd, km = K[k + 2 * C], complex(K[k + 23 * C], K[k + 44 * C])
                            op1 += kd * sp1 + km * ip1; oq1 += kd * sq1 + km * iq1
                            kd, km = K[k + 3 * C], complex(K[k + 24 * C], K[k + 45 * C])
                            op0 += kd * sp2 + km * ip2; oq0 += kd * sq2 + km * iq2
                            op2 = kd * sp0 + km * ip0; oq2 = kd * sq0 + km * iq0
                            kd, km = K[k + 4 * C], complex(K[k + 25 * C], K[k + 46 * C])
                            op1 += kd * sp2 + km * ip2; oq1 += kd * sq2 + km * iq2
                            op2 += kd * sp1 + km * ip1; oq2 += kd * sq1 + km * iq1
                            kd, km = K[k + 5 * C], complex(K[k + 26 * C], K[k + 47 * C])
                            op2 += kd * sp2 + km * ip2; oq2 += kd * sq2 + km * iq2
                            kd, km = K[k + 6 * C], complex(K[k + 27 * C], K[k + 48 * C])
                            op0 += kd * sp3 + km * ip3; oq0 += kd * sq3 + km * iq3
                            op3 = kd * sp0 + km * ip0; oq3 = kd * sq0 + km * iq0
                            kd, km = K[k + 7 * C], complex(K[k + 28 * C], K[k + 49 * C])
                            op1 += kd * sp3 + km * ip3; oq1 += kd * sq3 + km * iq3
                            op3 += kd * sp1 + km * ip1; oq3 += kd * sq1 + km * iq1
                            kd, km = K[k + 8 * C], complex(K[k + 29 * C], K[k + 50 * C])
                            op2 += kd * sp3 + km * ip3; oq2 += kd * sq3 + km * iq3
                            op3 += kd * sp2 + km * ip2; oq3 += kd * sq2 + km * iq2
                            kd, km = K[k + 9 * C], complex(K[k + 30 * C], K[k + 51 * C])
                            op3 += kd * sp3 + km * ip3; oq3 += kd * sq3 + km * iq3
                            kd, km = K[k + 10 * C], complex(K[k + 31 * C], K[k + 52 * C])
                            op0 += kd * sp4 + km * ip4; oq0 += kd * sq4 + km * iq4
                            op4 = kd * sp0 + km * ip0; oq4 = kd * sq0 + km * iq0
                            kd, km = K[k + 11 * C], complex(K[k + 32 * C], K[k + 53 * C])
                            op1 += kd * sp4 + km * ip4; oq1 += kd * sq4 + km * iq4
                            op4 += kd * sp1 + km * ip1; oq4 += kd * sq1 + km * iq1
                            kd, km = K[k + 12 * C], complex(K[k + 33 * C], K[k + 54 * C])
                            op2 += kd * sp4 + km * ip4; oq2 += kd * sq4 + km * iq4
                            op4 += kd * sp2 + km * ip2; oq4 += kd * sq2 + km * iq2
                            kd, km = K[k + 13 * C], complex(K[k + 34 * C], K[k + 55 * C])
                            op3 += kd * sp4 + km * ip4; oq3 += kd * sq4 + km * iq4
                            op4 += kd * sp3 + km * ip3; oq4 += kd * sq3 + km * iq3
                            kd, km = K[k + 14 * C], complex(K[k + 35 * C], K[k + 56 * C])
                            op4 += kd * sp4 + km * ip4; oq4 += kd * sq4 + km * iq4
                            kd, km = K[k + 15 * C], complex(K[k + 36 * C], K[k + 57 * C])
                            op0 += kd * sp5 + km * ip5; oq0 += kd * sq5 + km * iq5
                            op5 = kd * sp0 + km * ip0; oq5 = kd * sq0 + km * iq0
                            kd, km = K[k + 16 * C], complex(K[k + 37 * C], K[k + 58 * C])
                            op1 += kd * sp5 + km * ip5; oq1 += kd * sq5 + km * iq5
                            op5 += kd * sp1 + km * ip1; oq5 += kd * sq1 + km * iq1
                            kd, km = K[k + 17 * C], complex(K[k + 38 * C], K[k + 59 * C])
                            op2 += kd * sp5 + km * ip5; oq2 += kd * sq5 + km * iq5
                            op5 += kd * sp2 + km * ip2; oq5 += kd * sq2 + km * iq2
                            kd, km = K[k + 18 * C], complex(K[k + 39 * C], K[k + 60 * C])
                            op3 += kd * sp5 + km * ip5; oq3 += kd * sq5 + km * iq5
                            op5 += kd * sp3 + km * ip3; oq5 += kd * sq3 + km * iq3
                            kd, km = K[k + 19 * C], complex(K[k + 40 * C], K[k + 61 * C])
                            op4 += kd * sp5 + km * ip5; oq4 += kd * sq5 + km * iq5
                            op5 += kd * sp4 + km * ip4; oq5 += kd * sq4 + km * iq4
                            kd, km = K[k + 20 * C], complex(K[k + 41 * C], K[k + 62 * C])
                            op5 += kd * sp5 + km * ip5; oq5 += kd * sq5 + km * iq5
                            O[k], O[k + 6 * C] = op0.real, op0.imag
                            O[k + 1 * C], O[k + 7 * C] = op1.real, op1.imag
                            O[k + 2 * C], O[k + 8 * C] = op2.real, op2.imag
                            O[k + 3 * C], O[k + 9 * C] = op3.real, op3.imag
                            O[k + 4 * C], O[k + 10 * C] = op4.real, op4.imag
                            O[k + 5 * C], O[k + 11 * C] = op5.real, op5.imag
                            O[k + 12 * C], O[k + 18 * C] = oq0.real, oq0.imag
                            O[k + 13 * C], O[k + 19 * C] = oq1.real, oq1.imag
                            O[k + 14 * C], O[k + 20 * C] = oq2.real, oq2.imag
                            O[k + 15 * C], O[k + 21 * C] = oq3.real, oq3.imag
                            O[k + 16 * C], O[k + 22 * C] = oq4.real, oq4.imag
                            O[k + 17 * C], O[k + 23 * C] = oq5.real, oq5.imag
                    for c in range(6):
                        gp, gq = g[p, c], g[q, c]
                        a, b = offsets[0, c], offsets[1, c]
                        s0, s1 = np.uint64(c * C), np.uint64((6 + c) * C)
                        for k in range(n):
                            values[a + two * k], values[a + two * k + one] = gp * O[s0 + k], gp * O[s1 + k]
                        if not single:
                            s2, s3 = np.uint64((12 + c) * C), np.uint64((18 + c) * C)
                            for k in range(n):
                                values[b + two * k], values[b + two * k + one] = gq * O[s2 + k], gq * O[s3 + k]

    def surface_sum(total, kernels, factors, parity1, spectra, first):
        # the six planes of a layer at once: the total read and written once a layer, not six times (1.10 -> 0.98 ms
        # for the rolling bench's 30 layers)
        _, n1, h = spectra.shape
        half = n1 // 2
        g = np.empty(6, dtype=np.complex128)
        for i1 in range(n1):
            j1 = i1 if i1 <= half else n1 - i1
            for p in range(6):
                g[p] = factors[first + p] * parity1[first + p] if i1 > half else factors[first + p]
            g0, g1, g2, g3, g4, g5 = g[0], g[1], g[2], g[3], g[4], g[5]
            K0, K1, K2 = kernels[first, j1], kernels[first + 1, j1], kernels[first + 2, j1]
            K3, K4, K5 = kernels[first + 3, j1], kernels[first + 4, j1], kernels[first + 5, j1]
            S0, S1, S2 = spectra[0, i1], spectra[1, i1], spectra[2, i1]
            S3, S4, S5 = spectra[3, i1], spectra[4, i1], spectra[5, i1]
            T = total[i1]
            for k in range(h):
                T[k] += (g0 * (K0[k] * S0[k]) + g1 * (K1[k] * S1[k]) + g2 * (K2[k] * S2[k])
                         + g3 * (K3[k] * S3[k]) + g4 * (K4[k] * S4[k]) + g5 * (K5[k] * S5[k]))

    def surface_spread(out, kernels, factors, parity1, spectrum, first):
        planes, n1, h = out.shape
        half = n1 // 2
        for p in range(planes):
            factor = factors[first + p]
            for i1 in range(n1):
                j1 = i1 if i1 <= half else n1 - i1
                g = factor * parity1[first + p] if i1 > half else factor
                for k in range(h):
                    out[p, i1, k] = g * (kernels[first + p, j1, k] * spectrum[i1, k])


    def surface_planes(planes, field, layer, offset):
        # a cuboid's six components read together (one cache line of the field), written to six rows
        m1, m2 = field.shape[0], field.shape[1]
        for i in range(m1):
            for j in range(m2):
                for c in range(6):
                    planes[c, i, offset + j] = field[i, j, layer, c]

    def surface_add(out, planes, layer, offset, scale, add):
        m1, m2 = out.shape[0], out.shape[1]
        for i in range(m1):
            for j in range(m2):
                for c in range(6):
                    value = scale * planes[c, i, offset + j]
                    out[i, j, layer, c] = out[i, j, layer, c] + value if add else value

    def take_lines(lines, field, weights, n3):
        # a cuboid's six components read together, written to the six lines of its column, then their zero padding
        m1, m2, m3 = field.shape[0], field.shape[1], field.shape[2]
        for i in range(m1):
            for j in range(m2):
                for c in range(6):
                    weight = weights[c]
                    for k in range(m3):
                        lines[i, j, c, k] = weight * field[i, j, k, c]
                    for k in range(m3, n3):
                        lines[i, j, c, k] = 0.0

    def put_lines(out, lines, weights):
        m1, m2, m3 = out.shape[0], out.shape[1], out.shape[2]
        for i in range(m1):
            for j in range(m2):
                for k in range(m3):
                    for c in range(6):
                        out[i, j, k, c] = weights[c] * lines[i, j, c, k]

    def compliance(stress, poisson):
        for i in range(stress.shape[0]):
            trace = poisson * (stress[i, 0] + stress[i, 1] + stress[i, 2])
            for c in range(6):
                stress[i, c] *= 1.0 + poisson
            for c in range(3):
                stress[i, c] -= trace

    def fourier_apply(spectra, matrices, parity1, parity2, offset):
        n1, n2, _, h = spectra.shape
        half = matrices.shape[0] != n1          # stored for q1, q2 >= 0: the signs of the components' parities
        x = np.empty(6, dtype=np.complex128)
        sign = np.ones(6)
        for i1 in range(n1):
            j1 = min(i1, n1 - i1) if half else i1
            for i2 in range(n2):
                j2 = min(i2, n2 - i2) if half else i2
                if half:
                    for a in range(6):
                        g = 1.0
                        if i1 > n1 // 2:
                            g *= parity1[a]
                        if i2 > n2 // 2:
                            g *= parity2[a]
                        sign[a] = g
                for k in range(h):
                    m = matrices[j1, j2, offset + k]
                    for a in range(6):
                        x[a] = sign[a] * spectra[i1, i2, a, k]
                    for a in range(6):
                        total = 0j
                        for b in range(6):
                            total += m[a, b] * x[b]
                        spectra[i1, i2, a, k] = sign[a] * total


class NumpyLoops:
    """The same passes as numpy expressions."""

    @staticmethod
    def stiffness(spectra, direct, mirror, items, permutation, first, second, parity1, parity2, mirror_sign):
        # a few items at a time (their wavenumbers and the reversals they read are theirs alone): the gathered
        # kernels take 24 bytes an entry, wavenumber and q3
        step = max(1, 2**22 // (4 * 21 * 24 * spectra.shape[3]))
        for start in range(0, len(items), step):
            NumpyLoops._stiffness_items(spectra, direct, mirror, items[start:start + step], permutation, first,
                                        second, parity1, parity2, mirror_sign)

    @staticmethod
    def _stiffness_items(spectra, direct, mirror, items, permutation, first, second, parity1, parity2, mirror_sign):
        n1, n2 = spectra.shape[:2]
        t, i1, i2, permuted = items.T
        # the items' wavenumbers, each once: (i1, i2) and its reversal, (i1, -i2) and its reversal
        rows = np.concatenate([i1, (n1 - i1) % n1, i1, (n1 - i1) % n1])
        columns = np.concatenate([i2, (n2 - i2) % n2, (n2 - i2) % n2, i2])
        _, once = np.unique(rows * n2 + columns, return_index=True)
        rows, columns, item = rows[once], columns[once], np.tile(np.arange(len(items)), 4)[once]
        entries = np.where(permuted[item, None] != 0, permutation[None, :], np.arange(len(ENTRIES))[None, :])
        direct, mirror = direct[t[item, None], entries], mirror[t[item, None], entries]          # (K, 21, b)
        signs = (np.where(rows[:, None] > n1 // 2, parity1, 1.0)
                 * np.where(columns[:, None] > n2 // 2, parity2, 1.0))[..., None]              # (K, 6, 1)
        source = spectra[rows, columns] * signs                                                 # (K, 6, b)
        image = np.conj(spectra[(n1 - rows) % n1, (n2 - columns) % n2]) * signs * mirror_sign[:, None]
        out = np.zeros_like(source)
        for e, (a, b) in enumerate(zip(first, second)):
            out[:, a] += direct[:, e] * source[:, b] + mirror[:, e] * image[:, b]
            if a != b:
                out[:, b] += direct[:, e] * source[:, a] + mirror[:, e] * image[:, a]
        spectra[rows, columns] = out * signs

    @staticmethod
    def unpacked(kernels, table, permutation):
        """Stored kernels ``(T, 21, b)`` (:func:`kernel_table`) as ``(21, q1, q2, b)`` for every ``q1, q2 >= 0``."""
        out = kernels[table[..., 0]]                                        # (q1, q2, 21, b)
        permuted = table[..., 1] != 0
        out[permuted] = out[permuted][:, permutation]
        return np.moveaxis(out, 2, 0)

    @staticmethod
    def _expanded(kernels, factors, parity1, first, planes, n1):
        index = np.arange(n1)
        rows, negative = np.minimum(index, n1 - index), index > n1 // 2
        chosen = slice(first, first + planes)
        signs = np.where(negative[None, :], parity1[chosen, None], 1.0) * factors[chosen, None]
        return kernels[chosen][:, rows] * signs[..., None]

    @staticmethod
    def surface_sum(total, kernels, factors, parity1, spectra, first):
        expanded = NumpyLoops._expanded(kernels, factors, parity1, first, spectra.shape[0], spectra.shape[1])
        total += np.einsum("pij,pij->ij", expanded, spectra)

    @staticmethod
    def surface_spread(out, kernels, factors, parity1, spectrum, first):
        out[...] = NumpyLoops._expanded(kernels, factors, parity1, first, out.shape[0], out.shape[1]) * spectrum


    @staticmethod
    def surface_planes(planes, field, layer, offset):
        planes[:, :, offset:offset + field.shape[1]] = np.moveaxis(field[:, :, layer, :], -1, 0)

    @staticmethod
    def surface_add(out, planes, layer, offset, scale, add):
        values = scale * np.moveaxis(planes[:, :, offset:offset + out.shape[1]], 0, -1)
        if add:
            out[:, :, layer, :] += values
        else:
            out[:, :, layer, :] = values

    @staticmethod
    def take_lines(lines, field, weights, n3):
        m1, m2, m3 = field.shape[:3]
        lines[:m1, :m2, :, :m3] = np.moveaxis(field, 3, 2) * weights[:, None]
        lines[:m1, :m2, :, m3:n3] = 0.0

    @staticmethod
    def put_lines(out, lines, weights):
        m1, m2, m3 = out.shape[:3]
        np.multiply(np.moveaxis(lines[:m1, :m2, :, :m3], 2, 3), weights, out=out)

    @staticmethod
    def compliance(stress, poisson):
        from .eigenstrain import strain_from_stress      # (that module imports this one)
        strain_from_stress(stress, poisson, out=stress)

    @staticmethod
    def fourier_apply(spectra, matrices, parity1, parity2, offset):
        spectra = np.moveaxis(spectra, 2, 0)        # a view (6, N1, N2, b): written through
        n1, n2, h = spectra.shape[1:]
        matrices = matrices[:, :, offset:offset + h]
        if matrices.shape[0] != n1:
            rows, columns = np.arange(n1), np.arange(n2)
            j1, j2 = np.minimum(rows, n1 - rows), np.minimum(columns, n2 - columns)
            sign = (np.where(rows[:, None] > n1 // 2, parity1[None, :], 1.0)[:, None, None, :]
                    * np.where(columns[:, None] > n2 // 2, parity2[None, :], 1.0)[None, :, None, :])
            matrices = matrices[j1][:, j2] * sign[..., :, None] * sign[..., None, :]
        spectra[...] = np.einsum("...ab,b...->a...", matrices, spectra)


def fourier_kernels(direct, first, second, parity1, parity2, n1, n2, rows=None, columns=None):
    """``K(q)`` ``(rows, columns, h, 6, 6)`` for the rows ``i1`` and columns ``i2`` of the full wavenumber grid (all by
    default), expanded from the stored kernels of ``q1, q2 >= 0`` by the entries' parities."""
    rows = np.arange(n1) if rows is None else np.asarray(rows)
    i2 = np.arange(n2) if columns is None else np.asarray(columns)
    j1, j2 = np.minimum(rows, n1 - rows), np.minimum(i2, n2 - i2)
    kernel = np.empty((len(rows), len(i2), direct.shape[-1], 6, 6))
    for e, (a, b) in enumerate(zip(first, second)):
        sign = (np.where(rows > n1 // 2, parity1[a] * parity1[b], 1.0)[:, None]
                * np.where(i2 > n2 // 2, parity2[a] * parity2[b], 1.0)[None, :])
        value = direct[e][j1][:, j2] * sign[..., None]
        kernel[..., a, b] = value
        kernel[..., b, a] = value
    return kernel


#: The loops, by name.
NAMES = ("stiffness_rows", "surface_sum", "surface_spread", "surface_planes", "surface_add", "take_lines",
         "put_lines", "compliance", "fourier_apply")
_cache = {}


def loops():
    """The compiled loops when numba is installed and allowed, else :class:`NumpyLoops`."""
    if not (_fused._compiled and _fused.numba_available()):
        return NumpyLoops
    if "compiled" not in _cache:
        jit = _fused._cache["numba"].njit(cache=True, nogil=True, fastmath={"reassoc", "nsz", "nnan", "contract"})
        compiled = {name: jit(getattr(_Loops, name)) for name in NAMES}
        rows_pass = compiled["stiffness_rows"]

        def stiffness(spectra, direct, mirror, items, permutation, first, second, parity1, parity2, mirror_sign):
            rows_pass(flat_rows(spectra), spectra.shape[1], spectra.shape[3], direct, mirror, items, permutation,
                      parity1, parity2, mirror_sign)
        compiled["stiffness"] = stiffness
        _cache["compiled"] = type("CompiledBoxLoops", (), {name: staticmethod(f) for name, f in compiled.items()})
    return _cache["compiled"]
