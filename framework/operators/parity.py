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


def folded_spectrum(values, parity, size, axis):
    """:func:`half_spectrum` of the kernel summed over the periods of a lattice of ``size`` (even) points.

    The kernel is given at the offsets ``0 .. S`` (``S < size``) along ``axis``; the lattice's point ``d``
    (``0 .. size/2``) gets ``x_d + parity x_(size - d)``, its own offset and the image of ``d - size``
    (``d`` and ``d - size`` are one point of the lattice; at ``d = size/2`` both images count). A lattice
    shorter than twice the offsets makes the periodic cell of a preconditioner, not a linear convolution.
    """
    half = size // 2
    count = values.shape[axis]
    if count > size:
        raise ValueError(f"{count} offsets exceed a period of {size}")
    moved = np.moveaxis(values, axis, 0)
    folded = np.zeros((half + 1, *moved.shape[1:]))
    kept = min(count, half + 1)
    folded[:kept] = moved[:kept]
    for d in range(max(0, size - count + 1), half + 1):
        folded[d] += parity * moved[size - d]
    folded = np.moveaxis(folded, 0, axis)
    if parity > 0:      # DCT-I over 0 .. size/2: x_0 + (-1)^q x_(size/2) + 2 sum x_n cos(2 pi q n / size)
        return scipy.fft.dct(folded, type=1, axis=axis)
    # odd: x_0 and x_(size/2) vanish (the two images of size/2 cancel), so the DST-I of the rest
    return half_spectrum(np.take(folded, np.arange(half), axis=axis), parity, size, axis)
