"""Normal surface displacement of the half-space under a surface pressure."""
import numpy as np
from scipy.special import iti0k0

from .. import fft
from .convolution import Convolution, wrapped_offsets
from .kernels import surface_displacement


class SurfaceCompliance:
    """Normal displacement per unit contact compliance: ``u3 = C* (K * p)``.

    The operator returns ``K * p`` [Pa m]; multiplied by a contact compliance
    ``C* = (1 - nu^2)/E`` [1/Pa] (or its viscoelastic counterpart) it is the
    normal surface displacement [m], positive into the solid.

    Kernels (piecewise-constant pressure per cell, displacement at cell centres):

    - non-periodic axes: Love's rectangle coefficients (Love 1929; Johnson 1985,
      sec. 3.2), exact, convolved by DC-FFT (Liu, Wang & Liu 2000);
    - both axes periodic: the Fourier kernel ``2/|q|`` of the continuous
      half-space sampled at the grid wavenumbers (Stanley & Kato 1997), mean
      displacement zero;
    - one periodic axis: per Fourier mode ``q`` of the periodic axis, the exact
      cell integral along the open axis of ``(2/pi) K0(|q| s)``; the mode ``q = 0``
      is the plane-strain strip ``-(2/pi) int ln(|s|/L)``, ``L`` the grid side
      along the open axis (plane-strain displacements are defined up to a
      constant; this fixes it).

    Parameters
    ----------
    grid : framework.Grid
        The surface grid.
    """

    def __init__(self, grid):
        self.grid = grid
        periodic = grid.periodic
        self._windows = {}
        if not any(periodic):
            self._kernel = self._love_kernel(grid)
            spectrum = fft.rfft2(self._kernel)
        elif all(periodic):
            spectrum = self._periodic_spectrum(grid)
        else:
            spectrum = self._mixed_spectrum(grid)
        self._convolution = Convolution(spectrum, grid.shape, periodic)

    @staticmethod
    def _love_kernel(grid):
        (n1, n2), (dx1, dx2) = grid.shape, grid.spacing
        o1 = wrapped_offsets(n1, dx1, False)
        o2 = wrapped_offsets(n2, dx2, False)
        offsets1, offsets2 = np.meshgrid(np.nan_to_num(o1), np.nan_to_num(o2), indexing="ij")
        kernel = surface_displacement(offsets1, offsets2, half1=dx1 / 2, half2=dx2 / 2)
        kernel[n1, :] = 0.0
        kernel[:, n2] = 0.0
        return kernel

    @staticmethod
    def _periodic_spectrum(grid):
        (n1, n2), (dx1, dx2) = grid.shape, grid.spacing
        q1 = 2 * np.pi * np.fft.fftfreq(n1, dx1)
        q2 = 2 * np.pi * np.fft.rfftfreq(n2, dx2)
        q = np.hypot(*np.meshgrid(q1, q2, indexing="ij"))
        with np.errstate(divide="ignore"):
            spectrum = np.where(q > 0, 2.0 / q, 0.0)
        return spectrum

    @staticmethod
    def _mixed_spectrum(grid):
        # Work with axis 0 open and axis 1 periodic; transpose back at the end.
        transpose = grid.periodic[0]
        (n_open, n_per), (d_open, d_per) = grid.shape, grid.spacing
        size_open = grid.size[0]
        if transpose:
            n_open, n_per, d_open, d_per = n_per, n_open, d_per, d_open
            size_open = grid.size[1]
        offsets = np.nan_to_num(wrapped_offsets(n_open, d_open, False))
        upper = offsets[:, None] + d_open / 2
        lower = offsets[:, None] - d_open / 2
        q = 2 * np.pi * np.fft.fftfreq(n_per, d_per)[None, :]
        kernel = np.empty((offsets.size, n_per))

        def integral_k0(x):  # int_0^x K0(t) dt, odd in x
            return np.sign(x) * iti0k0(np.abs(x))[1]

        qn = np.abs(q[:, 1:])
        kernel[:, 1:] = (2 / np.pi) * (integral_k0(qn * upper) - integral_k0(qn * lower)) / qn

        def integral_log(x):  # int_0^x ln(|s|/L) ds
            with np.errstate(divide="ignore", invalid="ignore"):
                value = x * np.log(np.abs(x) / size_open) - x
            return np.where(x == 0, 0.0, value)

        kernel[:, 0] = -(2 / np.pi) * (integral_log(upper[:, 0]) - integral_log(lower[:, 0]))
        kernel[n_open, :] = 0.0
        # kernel holds the DFT along the periodic axis; finish with the FFT along the open axis
        spectrum = np.fft.fft(kernel, axis=0)
        if transpose:  # rfft layout: the last (padded open) axis keeps its first half
            return spectrum.T[:, : n_open + 1]
        return spectrum[:, : n_per // 2 + 1]

    def apply(self, pressure):
        """``K * p`` [Pa m] for a pressure field ``(n1, n2)`` [Pa]."""
        return self._convolution.apply(pressure)

    def window(self, support):
        """Slices of a box holding ``support`` (boolean ``(n1, n2)``), for :meth:`apply_window`.

        Box sides are multiples of 32 cells, and a box already planned that
        holds the support is reused, so that a whole run needs few FFT plans;
        a box nearly as large as the grid, or a periodic grid, gets the whole grid.
        """
        whole = (slice(None), slice(None))
        if any(self.grid.periodic) or not support.any():
            return whole
        ranges = [np.flatnonzero(support.any(axis=1 - axis))[[0, -1]] for axis in (0, 1)]
        need = [int(last - first + 1) for first, last in ranges]
        shape = tuple(min(n, -(-e // 32) * 32) for e, n in zip(need, self.grid.shape))
        planned = [s for s in self._windows if s[0] >= need[0] and s[1] >= need[1]]
        if planned:
            best = min(planned, key=lambda s: s[0] * s[1])
            if best[0] * best[1] <= 1.5 * shape[0] * shape[1]:
                shape = best
        if shape[0] * shape[1] > 0.6 * self.grid.shape[0] * self.grid.shape[1]:
            return whole
        slices = []
        for (first, last), size, n in zip(ranges, shape, self.grid.shape):
            start = min(max(0, int(first) - (size - int(last - first + 1)) // 2), n - size)
            slices.append(slice(start, start + size))
        return tuple(slices)

    def apply_window(self, field, window):
        """``K * field`` on the box ``window`` for a field that vanishes outside it.

        ``field`` has the box's shape; the result is the exact linear
        convolution restricted to the box, at the cost of an FFT of twice the
        box instead of twice the grid.
        """
        if window == (slice(None), slice(None)):
            return self.apply(field)
        shape = np.shape(field)
        convolution = self._windows.get(shape)
        if convolution is None:
            (n1, n2), (m1, m2) = self.grid.shape, shape
            rows = np.r_[0:m1, 2 * n1 - m1:2 * n1]
            cols = np.r_[0:m2, 2 * n2 - m2:2 * n2]
            kernel = self._kernel[np.ix_(rows, cols)].copy()
            kernel[m1, :] = 0.0  # offsets -m, never used by an m-point linear convolution
            kernel[:, m2] = 0.0
            convolution = self._windows[shape] = Convolution(fft.rfft2(kernel), shape, (False, False))
        return convolution.apply(field)

