"""Normal surface displacement of the half-space under a surface pressure."""
import numpy as np
from scipy.special import iti0k0

from .. import fft
from ..errors import ParameterError
from .convolution import Convolution, wavenumbers, wrapped_offsets
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
    kernel : ndarray, optional
        Another kernel in the same layout as the default one (used by
        :class:`framework.operators.rolling.SteadyRollingCompliance`): on an
        open grid the ``(2 n1, 2 n2)`` samples in DC-FFT wrap-around order, on
        a grid periodic along one axis the open axis's wrapped samples times
        the DFT modes of the periodic axis (see :func:`mixed_mode_kernel`).
    """

    #: Window boxes whose kernel spectra and FFT plans are kept, the most recently used: a run whose contact
    #: grows (creep, a transient roll) meets box after box, and would keep them all.
    KEPT = 4

    def __init__(self, grid, kernel=None):
        self.grid = grid
        periodic = grid.periodic
        self._windows = {}    # box shape -> its Convolution, least recently used first
        if all(periodic):
            if kernel is not None:
                raise ParameterError("kernel: a doubly periodic grid takes the spectral kernel 2/|q| only; "
                                     f"another kernel needs an open axis, got periodic={grid.periodic}")
            spectrum = self._periodic_spectrum(grid)
        elif any(periodic):
            spectrum = _mixed_spectrum(grid, _mixed_kernel(grid) if kernel is None else kernel)
        else:
            self._kernel = self._love_kernel(grid) if kernel is None else kernel
            spectrum = fft.rfft2(self._kernel)
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
        q = np.hypot(*wavenumbers(grid.shape, grid.spacing))
        with np.errstate(divide="ignore"):
            spectrum = np.where(q > 0, 2.0 / q, 0.0)
        return spectrum

    @property
    def diagonal(self):
        """``K * p`` at a cell under its own unit pressure (the same at every cell): the operator's diagonal."""
        if getattr(self, "_diagonal", None) is None:
            if hasattr(self, "_kernel"):
                self._diagonal = float(self._kernel[0, 0])
            else:
                unit = np.zeros(self.grid.shape)
                unit[0, 0] = 1.0
                self._diagonal = float(self.apply(unit)[0, 0])
        return self._diagonal

    def apply(self, pressure, scale=1.0, copy=True):
        """``K * p`` [Pa m] for a pressure field ``(n1, n2)`` [Pa], times ``scale``.

        With ``scale`` a contact compliance [1/Pa] it is the displacement [m],
        at no extra cost. ``copy=False`` returns the operator's own buffer,
        overwritten by the next product (see :meth:`Convolution.apply
        <framework.operators.convolution.Convolution.apply>`).
        """
        return self._convolution.apply(pressure, scale, copy)

    def window(self, support):
        """Slices of a box holding ``support`` (boolean ``(n1, n2)``), for :meth:`apply_window`.

        Box sides are multiples of 32 cells, and a box already planned that
        holds the support is reused, so that a whole run needs few FFT plans;
        a box nearly as large as the grid, or a periodic grid, gets the whole grid.
        """
        if any(self.grid.periodic):
            return (slice(None), slice(None))
        return box_around(support, self._windows)

    def apply_window(self, field, window, scale=1.0, copy=True):
        """``K * field`` on the box ``window`` for a field that vanishes outside it, times ``scale``.

        ``field`` has the box's shape; the result is the exact linear
        convolution restricted to the box, at the cost of an FFT of twice the
        box instead of twice the grid. ``scale`` and ``copy`` as for :meth:`apply`.
        """
        if window == (slice(None), slice(None)):
            return self.apply(field, scale, copy)
        shape = np.shape(field)
        return most_recent(self._windows, shape, lambda: self._window_convolution(shape), self.KEPT).apply(
            field, scale, copy)

    def _window_convolution(self, shape):
        """The DC-FFT convolution of a box of ``shape``: the kernel's offsets within the box, wrapped."""
        (n1, n2), (m1, m2) = self.grid.shape, shape
        rows = np.r_[0:m1, 2 * n1 - m1:2 * n1]
        cols = np.r_[0:m2, 2 * n2 - m2:2 * n2]
        kernel = self._kernel[np.ix_(rows, cols)].copy()
        kernel[m1, :] = 0.0  # offsets -m, never used by an m-point linear convolution
        kernel[:, m2] = 0.0
        return Convolution(fft.rfft2(kernel), shape, (False, False))


def most_recent(cache, key, build, kept, valid=lambda value: True):
    """``cache[key]``, made by ``build()`` when missing (or not ``valid``), and marked the most recently used;
    ``cache`` (a dict, least recently used first) keeps ``kept`` entries at most."""
    value = cache.pop(key, None)
    if value is None or not valid(value):
        while len(cache) >= kept:
            del cache[next(iter(cache))]
        value = build()
    cache[key] = value
    return value


def box_around(support, planned=()):
    """Slices of a box of the grid holding ``support`` (boolean ``(n1, n2)``), or of the whole grid.

    Box sides are multiples of 32 cells, and a box of ``planned`` (shapes
    already planned) that holds the support is reused if it is at most 1.5
    times larger, so that a run needs few FFT plans; a box of more than 0.6 of
    the grid, or an empty support, gets the whole grid. The box does not wrap
    round a periodic axis: a support across its edge gets the whole axis.
    """
    whole = (slice(None), slice(None))
    rows = np.flatnonzero(support.any(axis=1))
    if not rows.size:
        return whole
    # the columns from the rows that hold the support only
    ranges = [rows[[0, -1]], np.flatnonzero(support[rows[0]:rows[-1] + 1].any(axis=0))[[0, -1]]]
    need = [int(last - first + 1) for first, last in ranges]
    shape = tuple(min(n, -(-e // 32) * 32) for e, n in zip(need, support.shape))
    fitting = [s for s in planned if s[0] >= need[0] and s[1] >= need[1]]
    if fitting:
        best = min(fitting, key=lambda s: s[0] * s[1])
        if best[0] * best[1] <= 1.5 * shape[0] * shape[1]:
            shape = best
    if shape[0] * shape[1] > 0.6 * support.size:
        return whole
    slices = []
    for (first, last), size, n in zip(ranges, shape, support.shape):
        start = min(max(0, int(first) - (size - int(last - first + 1)) // 2), n - size)
        slices.append(slice(start, start + size))
    return tuple(slices)


def _integral_log(x, h, length):
    """``int_{x-h}^{x+h} ln(|s|/length) ds``, without the cancellation of two large terms far away."""
    x = np.asarray(x, dtype=float)
    near = np.abs(x) <= 2 * h

    def primitive(y):  # int_0^y ln(|s|/length) ds
        with np.errstate(divide="ignore", invalid="ignore"):
            value = y * np.log(np.abs(y) / length) - y
        return np.where(y == 0, 0.0, value)

    safe = np.where(near, 2 * h + 1.0, x)
    u = h / safe
    far = 2 * h * np.log(np.abs(safe) / length) + safe * ((1 + u) * np.log1p(u) - (1 - u) * np.log1p(-u)) - 2 * h
    return np.where(near, primitive(x + h) - primitive(x - h), far)


def mixed_mode_kernel(grid):
    """The kernel of a grid periodic along one axis, as a function of the offset along the open axis.

    Returns a function ``kernel(x)`` -> ``(len(x), n_periodic)``: per DFT mode
    ``q`` of the periodic axis, the exact cell integral along the open axis of
    ``(2/pi) K0(|q| s)`` at offsets ``x`` [m] (per unit compliance), and for
    ``q = 0`` the plane-strain strip ``-(2/pi) int ln(|s|/L) ds``, ``L`` the grid
    side along the open axis (plane-strain displacements are defined up to a
    constant; this fixes it).
    """
    open_axis = 1 if grid.periodic[0] else 0
    d_open, size_open = grid.spacing[open_axis], grid.size[open_axis]
    n_per, d_per = grid.shape[1 - open_axis], grid.spacing[1 - open_axis]
    q = np.abs(2 * np.pi * np.fft.fftfreq(n_per, d_per))[None, 1:]

    def integral_k0(y):  # int_0^y K0(t) dt, odd in y
        return np.sign(y) * iti0k0(np.abs(y))[1]

    def kernel(x):
        x = np.asarray(x, dtype=float)[:, None]
        out = np.empty((x.shape[0], n_per))
        out[:, 1:] = (2 / np.pi) * (integral_k0(q * (x + d_open / 2)) - integral_k0(q * (x - d_open / 2))) / q
        out[:, 0] = -(2 / np.pi) * _integral_log(x[:, 0], d_open / 2, size_open)
        return out
    return kernel


def _mixed_kernel(grid):
    """The wrapped kernel of a grid periodic along one axis, in the grid's orientation (modes on the periodic axis)."""
    open_axis = 1 if grid.periodic[0] else 0
    n_open = grid.shape[open_axis]
    kernel = mixed_mode_kernel(grid)(np.nan_to_num(wrapped_offsets(n_open, grid.spacing[open_axis], False)))
    kernel[n_open, :] = 0.0
    return kernel if open_axis == 0 else kernel.T


def _mixed_spectrum(grid, kernel):
    """The rfft-layout spectrum of a wrapped mixed kernel: FFT along the open axis, half of the last axis."""
    open_axis = 1 if grid.periodic[0] else 0
    spectrum = np.fft.fft(kernel, axis=open_axis)
    last = spectrum.shape[1]
    return np.ascontiguousarray(spectrum[:, : last // 2 + 1])

