"""DC-FFT convolution of surface fields with a cached kernel spectrum.

Liu, Wang & Liu, Wear 243 (2000): the kernel is sampled at the offsets
``-(n-1) .. (n-1)`` and stored in wrap-around order on a ``2n`` grid, the field is
zero-padded to ``2n``; the product of the spectra is then the exact *linear*
convolution. A periodic axis is not padded: there the product is the circular
convolution with a kernel that is already periodic on that axis.
"""
import numpy as np

from .. import _fused, fft
from ..errors import ShapeError


def wrapped_offsets(n, spacing, periodic):
    """Offsets [m] of the kernel samples along one axis, in FFT order.

    Non-periodic: ``2n`` samples, offsets ``0..n-1`` then ``-(n-1)..-1``; the
    sample at index ``n`` (offset ``-n``) never enters a linear convolution of
    ``n`` values and is returned as NaN so that builders set it to zero.
    Periodic: ``n`` samples at the signed offsets of the circular convolution.
    """
    if periodic:
        index = np.fft.fftfreq(n) * n
        return index * spacing
    index = np.fft.fftfreq(2 * n) * 2 * n
    offsets = index * spacing
    offsets[n] = np.nan
    return offsets


def wavenumbers(shape, spacing):
    """Angular wavenumbers ``(q1, q2)`` [rad/m] of a real 2-D FFT of ``shape`` (the ``rfft2`` layout), as grids."""
    return np.meshgrid(2 * np.pi * np.fft.fftfreq(shape[0], spacing[0]),
                       2 * np.pi * np.fft.rfftfreq(shape[1], spacing[1]), indexing="ij")


def padded_shape(shape, periodic):
    """Shape of the FFT grid: doubled along the non-periodic axes."""
    return tuple(n if p else 2 * n for n, p in zip(shape, periodic))


class Convolution:
    """Convolution of ``(..., n1, n2)`` fields with one or several kernels.

    Parameters
    ----------
    spectrum : ndarray or None
        Kernel spectrum on the padded grid, shape ``(..., m1, m2 // 2 + 1)`` as
        returned by :func:`framework.fft.rfft2` of the wrapped kernel; None when
        the kernels are passed to :meth:`apply_spectrum` call by call.
    shape : tuple of int
        Surface shape ``(n1, n2)`` of the fields.
    periodic : tuple of bool
        Periodicity of each surface axis.
    """

    def __init__(self, spectrum, shape, periodic):
        self.shape = tuple(shape)
        self.periodic = tuple(periodic)
        self.fft_shape = padded_shape(self.shape, self.periodic)
        self._pair = None
        self._scaled = None       # (factor, kernel spectrum times it) of the last product
        if spectrum is None:
            self.spectrum = None
            return
        expected = (self.fft_shape[0], self.fft_shape[1] // 2 + 1)
        if spectrum.shape[-2:] != expected:
            raise ShapeError(f"kernel spectrum has shape {spectrum.shape}, expected (..., {expected[0]}, {expected[1]})")
        # A kernel even in both offsets has a real spectrum: store it real, it halves the product.
        if np.iscomplexobj(spectrum) and np.allclose(spectrum.imag, 0.0, atol=1e-14 * np.abs(spectrum).max()):
            spectrum = np.ascontiguousarray(spectrum.real)
        self.spectrum = spectrum

    def _pad(self, field):
        if field.shape[-2:] != self.shape:
            raise ShapeError(f"field has shape {field.shape[-2:]}, the operator's grid is {self.shape}")
        if self.fft_shape == self.shape:
            return np.ascontiguousarray(field, dtype=float)
        padded = np.zeros(field.shape[:-2] + self.fft_shape)
        padded[..., : self.shape[0], : self.shape[1]] = field
        return padded

    def transform(self, field):
        """Spectrum of the zero-padded field (reusable for several kernels)."""
        return fft.rfft2(self._pad(np.asarray(field, dtype=float)))

    def apply_spectrum(self, field_spectrum, spectrum):
        """Convolve a field given by its spectrum with kernel(s) given by theirs, ``(..., m1, m2 // 2 + 1)``."""
        full = fft.irfft2(spectrum * field_spectrum, self.fft_shape)
        return full[..., : self.shape[0], : self.shape[1]]

    def apply(self, field, scale=1.0, copy=True):
        """``scale`` times the convolution of ``field`` (shape ``(n1, n2)``) with the kernel, through reused buffers.

        The factor costs no pass of its own: it joins the FFT's normalisation
        in a copy of the kernel spectrum, made once per factor. With
        ``copy=False`` the result is the operator's own output buffer (no pass
        to copy it out, and one grid less in the caches), valid until the next
        product: for a caller that reads it before then and copies what it keeps.
        """
        if np.shape(field) != self.shape:
            raise ShapeError(f"field has shape {np.shape(field)}, the operator's grid is {self.shape}")
        pair = self._pair
        if pair is None or (pair.backend, pair.threads) != (fft.get_backend(), fft.THREADS):
            pair = self._pair = fft.RealFFTPair(self.fft_shape)
        factor = scale * pair.normalisation
        if self._scaled is None or self._scaled[0] != factor:
            self._scaled = (factor, self.spectrum * factor)
        n1, n2 = self.shape
        if self.fft_shape == self.shape:   # unpadded (a doubly periodic grid): an aligned field is read in place
            pair.forward_from(field)
        else:
            pair.real_in[:n1, :n2] = field
            pair.forward()
        _fused.multiply(pair.spectrum, self._scaled[1])
        pair.inverse()
        block = pair.real_out[:n1, :n2]
        return block.copy() if copy else block
