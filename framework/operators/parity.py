"""Spectra of kernels that are even or odd in each offset, from one quadrant (or octant) of their values.

A kernel sampled at the offsets ``-S .. S`` of an axis and padded to a period ``N = 2M > 2S`` has the
DFT ``X[q] = x0 + 2 sum_{n=1}^{M-1} x_n cos(pi q n / M)`` if it is even (a DCT-I of ``x_0 .. x_M``)
and ``X[q] = -2i sum_{n=1}^{M-1} x_n sin(pi q n / M)`` if it is odd (``-i`` times a DST-I of
``x_1 .. x_{M-1}``), with ``X[-q] = X[q]`` or ``-X[q]``. So only the offsets ``0 .. S`` are evaluated
and only the wavenumbers ``0 .. M`` are stored: per axis half of each. The kernels of Love, Chiu and
Boussinesq here all have this symmetry (they are derivatives of potentials that are even in each
offset), and it is exact, not an approximation.
"""
import numpy as np
import scipy.fft


def half_spectrum(values, parity, size, axis):
    """Real factor of the DFT (period ``size``, even) of a kernel given at the offsets ``0 .. S`` along ``axis``.

    Returns the wavenumbers ``0 .. size/2`` along ``axis``; the DFT is this factor for an even kernel
    (``parity`` +1) and ``-1j`` times it for an odd one (-1).
    """
    half = size // 2
    count = values.shape[axis]
    if count > half:
        raise ValueError(f"{count} offsets do not fit a period of {size}")
    # (the transforms' n pads with zeros: no padded copies, a tenth of a 128^3 box's kernel build)
    if parity > 0:
        return scipy.fft.dct(values, type=1, n=half + 1, axis=axis)
    shape = list(values.shape)
    shape[axis] = half + 1
    out = np.zeros(shape)
    if half < 2 or count < 2:
        return out
    inner = values[(slice(None),) * (axis % values.ndim) + (slice(1, count),)]
    middle = (slice(None),) * (axis % values.ndim) + (slice(1, half),)
    out[middle] = scipy.fft.dst(inner, type=1, n=half - 1, axis=axis)
    return out


def quadrant(index, size):
    """For indices of a full DFT axis of length ``size``: the stored wavenumber ``min(i, size - i)`` and
    whether the index is a negative wavenumber (``i > size / 2``)."""
    index = np.asarray(index)
    return np.minimum(index, size - index), index > size // 2


def phase(parities):
    """``(-1j) ** (number of odd axes)``: the factor between a kernel's DFT and its real factor."""
    odd = int(np.count_nonzero(np.asarray(parities) < 0))
    return (-1j) ** odd
