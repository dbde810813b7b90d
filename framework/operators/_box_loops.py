"""The spectral passes of the eigenstrain operator, compiled by numba when it is installed.

A product of :class:`~framework.operators.eigenstrain.HalfSpaceEigenstrain` is a few FFTs and
two spectral passes; as numpy expressions the passes cost more than the FFTs (36 products of
whole spectra, each a temporary). Here each is one loop:

===============  ==================================================================================
``stiffness``    ``s <- K_direct s + K_mirror m`` in place on the six spectra ``s`` of a box (or of a block
                 of ``q3``, with the kernels of that block), ``m``
                 the mirror image's spectra (``conj(s)`` at the reversed wavenumbers ``-q1, -q2``
                 times the component's mirror sign; the phase in ``q3`` is in ``K_mirror``). The 21 kernels of each
                 term are stored for ``q1, q2 >= 0`` only (each is even or odd in ``q1`` and ``q2``:
                 a quarter of the memory); a wavenumber and its reversal share their kernel values,
                 so the loop takes them in pairs, which also lets it write in place.
``surface_sum``  ``total += sum_p kernels[p] * spectra[p]``: the sum over a box's layers and
                 components that gives a surface field's spectrum (the kernels stored for
                 ``q1 >= 0`` as real factors, each with a complex factor and its parity in ``q1``)
``surface_spread`` ``out[p] = kernels[p] * spectrum``: a surface field's spectrum spread over the
                 layers and components of a box, the same storage
``fourier_apply`` ``s(q) <- M(q) s(q)``, a 6 x 6 real matrix per wavenumber (a preconditioner's), stored
                 for every wavenumber or, when the components' parities allow, for ``q1, q2 >= 0``
===============  ==================================================================================

The compiled loops are used when numba is installed and :func:`framework._fused.set_compiled`
allows it; else the numpy forms below, which give the same numbers to rounding.
"""
import numpy as np

from .. import _fused


class _Loops:
    """The passes as loops, for numba."""

    def stiffness(spectra, direct, mirror, first, second, parity1, parity2, mirror_sign):
        # Unrolled for the 21 entries of eigenstrain.ENTRIES (first, second are theirs: the numpy form reads them):
        # the six components of a wavenumber and of its reversal stay in registers, and the four wavenumbers
        # +-q1, +-q2 that share a stored kernel value read it once (a loop over the entries read and wrote
        # the sums at each of its 36 products: 81 -> 63 ms on a 128^3 lattice). A pair's two wavenumbers go in two
        # loops over q3, the reversal's into T first (it reads both inputs), then the wavenumber's in place: half the
        # sums live at a time (the registers spill less), 53.7 -> 43.1 ms on a 128 x 128 x 65 half lattice, 7.0 ->
        # 6.4 ms on the rolling bench's 60 x 64 x 31 (two output groups of three in each loop: no better).
        _, n1, n2, h = spectra.shape
        half1, half2 = n1 // 2, n2 // 2
        g, m = np.empty((4, 6)), np.empty((4, 6))
        T = np.empty((6, h), dtype=np.complex128)     # the reversal's results, until its inputs are read
        rows, columns = np.empty(4, dtype=np.int64), np.empty(4, dtype=np.int64)
        for i1 in range(half1 + 1):
            r1 = (n1 - i1) % n1
            for i2 in range(half2 + 1):
                r2 = (n2 - i2) % n2
                # two pairs (a wavenumber, its reversal) share the kernel at (i1, i2); one where a row or a
                # column is its own reversal
                rows[0], columns[0], rows[1], columns[1] = i1, i2, r1, r2
                rows[2], columns[2], rows[3], columns[3] = i1, r2, r1, i2
                pairs = 2 if i1 != r1 and i2 != r2 else 1
                same = i1 == r1 and i2 == r2
                for s in range(4):
                    for c in range(6):
                        x = (parity1[c] if rows[s] > half1 else 1.0) * (parity2[c] if columns[s] > half2 else 1.0)
                        g[s, c], m[s, c] = x, x * mirror_sign[c]
                D0, M0 = direct[0, i1, i2], mirror[0, i1, i2]; D1, M1 = direct[1, i1, i2], mirror[1, i1, i2]
                D2, M2 = direct[2, i1, i2], mirror[2, i1, i2]; D3, M3 = direct[3, i1, i2], mirror[3, i1, i2]
                D4, M4 = direct[4, i1, i2], mirror[4, i1, i2]; D5, M5 = direct[5, i1, i2], mirror[5, i1, i2]
                D6, M6 = direct[6, i1, i2], mirror[6, i1, i2]; D7, M7 = direct[7, i1, i2], mirror[7, i1, i2]
                D8, M8 = direct[8, i1, i2], mirror[8, i1, i2]; D9, M9 = direct[9, i1, i2], mirror[9, i1, i2]
                D10, M10 = direct[10, i1, i2], mirror[10, i1, i2]; D11, M11 = direct[11, i1, i2], mirror[11, i1, i2]
                D12, M12 = direct[12, i1, i2], mirror[12, i1, i2]; D13, M13 = direct[13, i1, i2], mirror[13, i1, i2]
                D14, M14 = direct[14, i1, i2], mirror[14, i1, i2]; D15, M15 = direct[15, i1, i2], mirror[15, i1, i2]
                D16, M16 = direct[16, i1, i2], mirror[16, i1, i2]; D17, M17 = direct[17, i1, i2], mirror[17, i1, i2]
                D18, M18 = direct[18, i1, i2], mirror[18, i1, i2]; D19, M19 = direct[19, i1, i2], mirror[19, i1, i2]
                D20, M20 = direct[20, i1, i2], mirror[20, i1, i2]
                for pair in range(pairs):
                    p, q = 2 * pair, 2 * pair + 1
                    P0 = spectra[0, rows[p], columns[p]]
                    Q0 = spectra[0, rows[q], columns[q]]
                    P1 = spectra[1, rows[p], columns[p]]
                    Q1 = spectra[1, rows[q], columns[q]]
                    P2 = spectra[2, rows[p], columns[p]]
                    Q2 = spectra[2, rows[q], columns[q]]
                    P3 = spectra[3, rows[p], columns[p]]
                    Q3 = spectra[3, rows[q], columns[q]]
                    P4 = spectra[4, rows[p], columns[p]]
                    Q4 = spectra[4, rows[q], columns[q]]
                    P5 = spectra[5, rows[p], columns[p]]
                    Q5 = spectra[5, rows[q], columns[q]]
                    gp0, gq0, mp0, mq0 = g[p, 0], g[q, 0], m[p, 0], m[q, 0]
                    gp1, gq1, mp1, mq1 = g[p, 1], g[q, 1], m[p, 1], m[q, 1]
                    gp2, gq2, mp2, mq2 = g[p, 2], g[q, 2], m[p, 2], m[q, 2]
                    gp3, gq3, mp3, mq3 = g[p, 3], g[q, 3], m[p, 3], m[q, 3]
                    gp4, gq4, mp4, mq4 = g[p, 4], g[q, 4], m[p, 4], m[q, 4]
                    gp5, gq5, mp5, mq5 = g[p, 5], g[q, 5], m[p, 5], m[q, 5]
                    if not same:      # the reversal's first (into T: both loops read the inputs), then in place
                        for k in range(h):
                            a, b = P0[k], Q0[k]
                            sq0, iq0 = gq0 * b, mq0 * a.conjugate()
                            a, b = P1[k], Q1[k]
                            sq1, iq1 = gq1 * b, mq1 * a.conjugate()
                            a, b = P2[k], Q2[k]
                            sq2, iq2 = gq2 * b, mq2 * a.conjugate()
                            a, b = P3[k], Q3[k]
                            sq3, iq3 = gq3 * b, mq3 * a.conjugate()
                            a, b = P4[k], Q4[k]
                            sq4, iq4 = gq4 * b, mq4 * a.conjugate()
                            a, b = P5[k], Q5[k]
                            sq5, iq5 = gq5 * b, mq5 * a.conjugate()
                            kd, km = D0[k], M0[k]; oq0 = kd * sq0 + km * iq0
                            kd, km = D1[k], M1[k]; oq0 += kd * sq1 + km * iq1
                            oq1 = kd * sq0 + km * iq0
                            kd, km = D2[k], M2[k]; oq1 += kd * sq1 + km * iq1
                            kd, km = D3[k], M3[k]; oq0 += kd * sq2 + km * iq2
                            oq2 = kd * sq0 + km * iq0
                            kd, km = D4[k], M4[k]; oq1 += kd * sq2 + km * iq2
                            oq2 += kd * sq1 + km * iq1
                            kd, km = D5[k], M5[k]; oq2 += kd * sq2 + km * iq2
                            kd, km = D6[k], M6[k]; oq0 += kd * sq3 + km * iq3
                            oq3 = kd * sq0 + km * iq0
                            kd, km = D7[k], M7[k]; oq1 += kd * sq3 + km * iq3
                            oq3 += kd * sq1 + km * iq1
                            kd, km = D8[k], M8[k]; oq2 += kd * sq3 + km * iq3
                            oq3 += kd * sq2 + km * iq2
                            kd, km = D9[k], M9[k]; oq3 += kd * sq3 + km * iq3
                            kd, km = D10[k], M10[k]; oq0 += kd * sq4 + km * iq4
                            oq4 = kd * sq0 + km * iq0
                            kd, km = D11[k], M11[k]; oq1 += kd * sq4 + km * iq4
                            oq4 += kd * sq1 + km * iq1
                            kd, km = D12[k], M12[k]; oq2 += kd * sq4 + km * iq4
                            oq4 += kd * sq2 + km * iq2
                            kd, km = D13[k], M13[k]; oq3 += kd * sq4 + km * iq4
                            oq4 += kd * sq3 + km * iq3
                            kd, km = D14[k], M14[k]; oq4 += kd * sq4 + km * iq4
                            kd, km = D15[k], M15[k]; oq0 += kd * sq5 + km * iq5
                            oq5 = kd * sq0 + km * iq0
                            kd, km = D16[k], M16[k]; oq1 += kd * sq5 + km * iq5
                            oq5 += kd * sq1 + km * iq1
                            kd, km = D17[k], M17[k]; oq2 += kd * sq5 + km * iq5
                            oq5 += kd * sq2 + km * iq2
                            kd, km = D18[k], M18[k]; oq3 += kd * sq5 + km * iq5
                            oq5 += kd * sq3 + km * iq3
                            kd, km = D19[k], M19[k]; oq4 += kd * sq5 + km * iq5
                            oq5 += kd * sq4 + km * iq4
                            kd, km = D20[k], M20[k]; oq5 += kd * sq5 + km * iq5
                            T[0, k], T[1, k], T[2, k] = gq0 * oq0, gq1 * oq1, gq2 * oq2
                            T[3, k], T[4, k], T[5, k] = gq3 * oq3, gq4 * oq4, gq5 * oq5
                    for k in range(h):
                        a, b = P0[k], Q0[k]
                        sp0, ip0 = gp0 * a, mp0 * b.conjugate()
                        a, b = P1[k], Q1[k]
                        sp1, ip1 = gp1 * a, mp1 * b.conjugate()
                        a, b = P2[k], Q2[k]
                        sp2, ip2 = gp2 * a, mp2 * b.conjugate()
                        a, b = P3[k], Q3[k]
                        sp3, ip3 = gp3 * a, mp3 * b.conjugate()
                        a, b = P4[k], Q4[k]
                        sp4, ip4 = gp4 * a, mp4 * b.conjugate()
                        a, b = P5[k], Q5[k]
                        sp5, ip5 = gp5 * a, mp5 * b.conjugate()
                        kd, km = D0[k], M0[k]; op0 = kd * sp0 + km * ip0
                        kd, km = D1[k], M1[k]; op0 += kd * sp1 + km * ip1
                        op1 = kd * sp0 + km * ip0
                        kd, km = D2[k], M2[k]; op1 += kd * sp1 + km * ip1
                        kd, km = D3[k], M3[k]; op0 += kd * sp2 + km * ip2
                        op2 = kd * sp0 + km * ip0
                        kd, km = D4[k], M4[k]; op1 += kd * sp2 + km * ip2
                        op2 += kd * sp1 + km * ip1
                        kd, km = D5[k], M5[k]; op2 += kd * sp2 + km * ip2
                        kd, km = D6[k], M6[k]; op0 += kd * sp3 + km * ip3
                        op3 = kd * sp0 + km * ip0
                        kd, km = D7[k], M7[k]; op1 += kd * sp3 + km * ip3
                        op3 += kd * sp1 + km * ip1
                        kd, km = D8[k], M8[k]; op2 += kd * sp3 + km * ip3
                        op3 += kd * sp2 + km * ip2
                        kd, km = D9[k], M9[k]; op3 += kd * sp3 + km * ip3
                        kd, km = D10[k], M10[k]; op0 += kd * sp4 + km * ip4
                        op4 = kd * sp0 + km * ip0
                        kd, km = D11[k], M11[k]; op1 += kd * sp4 + km * ip4
                        op4 += kd * sp1 + km * ip1
                        kd, km = D12[k], M12[k]; op2 += kd * sp4 + km * ip4
                        op4 += kd * sp2 + km * ip2
                        kd, km = D13[k], M13[k]; op3 += kd * sp4 + km * ip4
                        op4 += kd * sp3 + km * ip3
                        kd, km = D14[k], M14[k]; op4 += kd * sp4 + km * ip4
                        kd, km = D15[k], M15[k]; op0 += kd * sp5 + km * ip5
                        op5 = kd * sp0 + km * ip0
                        kd, km = D16[k], M16[k]; op1 += kd * sp5 + km * ip5
                        op5 += kd * sp1 + km * ip1
                        kd, km = D17[k], M17[k]; op2 += kd * sp5 + km * ip5
                        op5 += kd * sp2 + km * ip2
                        kd, km = D18[k], M18[k]; op3 += kd * sp5 + km * ip5
                        op5 += kd * sp3 + km * ip3
                        kd, km = D19[k], M19[k]; op4 += kd * sp5 + km * ip5
                        op5 += kd * sp4 + km * ip4
                        kd, km = D20[k], M20[k]; op5 += kd * sp5 + km * ip5
                        P0[k] = gp0 * op0; P1[k] = gp1 * op1; P2[k] = gp2 * op2
                        P3[k] = gp3 * op3; P4[k] = gp4 * op4; P5[k] = gp5 * op5
                    if not same:
                        Q0[:] = T[0]; Q1[:] = T[1]; Q2[:] = T[2]; Q3[:] = T[3]; Q4[:] = T[4]; Q5[:] = T[5]

    def surface_sum(total, kernels, factors, parity1, spectra, first):
        planes, n1, h = spectra.shape
        half = n1 // 2
        for p in range(planes):
            factor = factors[first + p]
            for i1 in range(n1):
                j1 = i1 if i1 <= half else n1 - i1
                g = factor * parity1[first + p] if i1 > half else factor
                for k in range(h):
                    total[i1, k] += g * (kernels[first + p, j1, k] * spectra[p, i1, k])

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


    def fourier_apply(spectra, matrices, parity1, parity2, offset):
        _, n1, n2, h = spectra.shape
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
                        x[a] = sign[a] * spectra[a, i1, i2, k]
                    for a in range(6):
                        total = 0j
                        for b in range(6):
                            total += m[a, b] * x[b]
                        spectra[a, i1, i2, k] = sign[a] * total


class NumpyLoops:
    """The same passes as numpy expressions."""

    @staticmethod
    def stiffness(spectra, direct, mirror, first, second, parity1, parity2, mirror_sign):
        _, n1, n2, h = spectra.shape
        half1, half2 = n1 // 2, n2 // 2
        i2 = np.arange(n2)
        j2, r2 = np.minimum(i2, n2 - i2), (n2 - i2) % n2
        sign2 = np.where(i2[None, :] > half2, parity2[:, None], 1.0)[..., None]          # (6, n2, 1)
        for i1 in range(half1 + 1):
            r1 = (n1 - i1) % n1
            rows = [i1] if r1 == i1 else [i1, r1]
            signs = np.stack([np.where(row > half1, parity1, 1.0)[:, None, None] * sign2 for row in rows], axis=1)
            source = spectra[:, rows] * signs                                           # (6, rows, n2, h)
            image = np.conj(spectra[:, rows[::-1]][:, :, r2]) * signs * mirror_sign[:, None, None, None]
            direct_row, mirror_row = direct[:, i1][:, j2], mirror[:, i1][:, j2]
            out = np.zeros_like(source)
            for e, (a, b) in enumerate(zip(first, second)):
                out[a] += direct_row[e] * source[b] + mirror_row[e] * image[b]
                if a != b:
                    out[b] += direct_row[e] * source[a] + mirror_row[e] * image[a]
            spectra[:, rows] = out * signs

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
    def fourier_apply(spectra, matrices, parity1, parity2, offset):
        n1, n2, h = spectra.shape[1:]
        matrices = matrices[:, :, offset:offset + h]
        if matrices.shape[0] != n1:
            rows, columns = np.arange(n1), np.arange(n2)
            j1, j2 = np.minimum(rows, n1 - rows), np.minimum(columns, n2 - columns)
            sign = (np.where(rows[:, None] > n1 // 2, parity1[None, :], 1.0)[:, None, None, :]
                    * np.where(columns[:, None] > n2 // 2, parity2[None, :], 1.0)[None, :, None, :])
            matrices = matrices[j1][:, j2] * sign[..., :, None] * sign[..., None, :]
        spectra[...] = np.einsum("...ab,b...->a...", matrices, spectra)


def fourier_matrices(direct, first, second, parity1, parity2, left, right, n1, n2, rows=None, columns=None):
    """``left K(q) + right`` ``(rows, columns, h, 6, 6)`` for the rows ``i1`` and columns ``i2`` of the full wavenumber
    grid (all by default), ``K(q)`` expanded from the stored kernels of ``q1, q2 >= 0`` by the entries' parities."""
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
    return np.einsum("ac,...cb->...ab", left, kernel) + right


_cache = {}


def loops():
    """The compiled loops when numba is installed and allowed, else :class:`NumpyLoops`."""
    if not (_fused._compiled and _fused.numba_available()):
        return NumpyLoops
    if "compiled" not in _cache:
        jit = _fused._cache["numba"].njit(cache=True, nogil=True, fastmath={"reassoc", "nsz", "nnan", "contract"})
        _cache["compiled"] = type("CompiledBoxLoops", (), {name: staticmethod(jit(getattr(_Loops, name)))
                                                           for name in ("stiffness", "surface_sum", "surface_spread", "fourier_apply")})
    return _cache["compiled"]
