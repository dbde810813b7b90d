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
        _, n1, n2, h = spectra.shape
        half1, half2 = n1 // 2, n2 // 2
        entries = first.shape[0]
        source_p = np.empty((6, h), dtype=np.complex128)
        source_q = np.empty((6, h), dtype=np.complex128)
        image_p = np.empty((6, h), dtype=np.complex128)
        image_q = np.empty((6, h), dtype=np.complex128)
        out_p = np.empty((6, h), dtype=np.complex128)
        out_q = np.empty((6, h), dtype=np.complex128)
        sign_p = np.empty(6)
        sign_q = np.empty(6)
        for i1 in range(n1):
            r1 = (n1 - i1) % n1
            if r1 < i1:
                continue
            j1 = min(i1, r1)
            for i2 in range(n2):
                r2 = (n2 - i2) % n2
                if i1 == r1 and r2 < i2:
                    continue
                j2 = min(i2, r2)
                for c in range(6):
                    # an entry's parity is the product of its two components': the signs of a negative
                    # wavenumber go on the sources and on the results, not on each of the 36 products
                    g_p, g_q = 1.0, 1.0
                    if i1 > half1:
                        g_p *= parity1[c]
                    if r1 > half1:
                        g_q *= parity1[c]
                    if i2 > half2:
                        g_p *= parity2[c]
                    if r2 > half2:
                        g_q *= parity2[c]
                    sign_p[c], sign_q[c] = g_p, g_q
                    for k in range(h):
                        a = spectra[c, i1, i2, k]
                        b = spectra[c, r1, r2, k]
                        source_p[c, k] = g_p * a
                        source_q[c, k] = g_q * b
                        image_p[c, k] = (g_p * mirror_sign[c]) * b.conjugate()
                        image_q[c, k] = (g_q * mirror_sign[c]) * a.conjugate()
                        out_p[c, k] = 0.0
                        out_q[c, k] = 0.0
                for e in range(entries):
                    a, b = first[e], second[e]
                    for k in range(h):
                        kd, km = direct[e, j1, j2, k], mirror[e, j1, j2, k]
                        out_p[a, k] += kd * source_p[b, k] + km * image_p[b, k]
                        out_q[a, k] += kd * source_q[b, k] + km * image_q[b, k]
                        if a != b:
                            out_p[b, k] += kd * source_p[a, k] + km * image_p[a, k]
                            out_q[b, k] += kd * source_q[a, k] + km * image_q[a, k]
                same = i1 == r1 and i2 == r2
                for c in range(6):
                    for k in range(h):
                        spectra[c, i1, i2, k] = sign_p[c] * out_p[c, k]
                    if not same:
                        for k in range(h):
                            spectra[c, r1, r2, k] = sign_q[c] * out_q[c, k]

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
