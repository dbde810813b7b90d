"""Subsurface stresses of the half-space under a surface pressure."""
import numpy as np

from .. import fft
from ..errors import ParameterError, ShapeError
from .convolution import Convolution, wavenumbers, wrapped_offsets
from .kernels import periodic_subsurface_stress, subsurface_stress

VOIGT = ("xx", "yy", "zz", "yz", "xz", "xy")
# Love's kernels (and their sums over periodic images) are even or odd in each offset, so each
# spectrum is real or imaginary:
# xx, yy, zz (even, even) and xy (odd, odd) real; yz (even, odd) and xz (odd, even) imaginary.
_PHASE = np.array([1, 1, 1, 1j, 1j, 1])[:, None, None]
_REAL = _PHASE.imag == 0
# Voigt components seen from the transposed axes: xx <-> yy, yz <-> xz.
_SWAP_AXES = [1, 0, 2, 4, 3, 5]


class SubsurfaceStress:
    """Stress tensor at given depths from a surface pressure (homogeneous half-space).

    Non-periodic grids use Love's closed-form coefficients of a uniformly loaded
    rectangle (Love 1929; Johnson 1985) at every depth, one DC-FFT per depth and
    component (Liu, Wang & Liu 2000). Doubly periodic grids use the exact
    Fourier-mode solution: each mode of wavevector ``q`` is a plane-strain field
    in the plane of ``q`` and ``x3`` (sinusoidal pressure on a half-space, Johnson 1985 ch. 2):
    ``s_nn = -(1 - k z) e^{-kz}``, ``s_zz = -(1 + k z) e^{-kz}``,
    ``s_nz = i k z e^{-kz}``, ``s_tt = nu (s_nn + s_zz)`` per unit pressure,
    ``k = |q|``; the mean pressure gives ``s_zz = -p`` and the angular mean
    ``s_11 = s_22 = -(1 + 2 nu) p / 2``. Grids periodic along one axis (line
    contacts) use the sum of Love's coefficients over the periodic images of
    each cell (:func:`~framework.operators.kernels.periodic_subsurface_stress`:
    the plane-strain strip, Johnson 1985 sec. 2.7, plus tapered image sums,
    ~1e-13 of the pressure), DC-FFT along the open axis and circular along the
    periodic one; the pressure is piecewise constant along both axes.

    Kernel spectra are cached per depth while they fit in ``cache_bytes``.

    Parameters
    ----------
    grid : framework.Grid
        The surface grid (its layers give the default depths).
    poisson : float
        Poisson ratio of the half-space (the stresses from a pressure do not
        depend on the modulus).
    cache_bytes : int
        Memory allowed for cached kernel spectra [bytes].
    """

    def __init__(self, grid, poisson, cache_bytes=2 * 1024**3):
        self.grid = grid
        self.poisson = float(poisson)
        self.cache_bytes = cache_bytes
        self._cache = {}
        self._convolution = None if all(grid.periodic) else Convolution(None, grid.shape, grid.periodic)

    def _love_kernel(self, depth):
        (n1, n2), (dx1, dx2) = self.grid.shape, self.grid.spacing
        o1 = np.nan_to_num(wrapped_offsets(n1, dx1, False))
        o2 = np.nan_to_num(wrapped_offsets(n2, dx2, False))
        offsets1, offsets2 = np.meshgrid(o1, o2, indexing="ij")
        kernel = subsurface_stress(offsets1, offsets2, depth, half1=dx1 / 2, half2=dx2 / 2, poisson=self.poisson)
        kernel[n1, :] = 0.0
        kernel[:, n2] = 0.0
        return kernel

    def _image_kernel(self, depth):
        # Build with axis 0 open and axis 1 periodic; for the transposed grid, swap the
        # axes and the components (xx <-> yy, yz <-> xz) at the end.
        transpose = self.grid.periodic[0]
        (n_open, n_per), (d_open, d_per) = self.grid.shape, self.grid.spacing
        if transpose:
            n_open, n_per, d_open, d_per = n_per, n_open, d_per, d_open
        offsets = np.nan_to_num(wrapped_offsets(n_open, d_open, False))
        kernel = periodic_subsurface_stress(offsets, depth, half1=d_open / 2, half2=d_per / 2, cells=n_per,
                                            poisson=self.poisson)
        kernel[n_open] = 0.0
        if transpose:
            return kernel.transpose(1, 0, 2)[..., _SWAP_AXES]
        return kernel

    def _kernel_spectrum(self, depth):
        spectrum = self._cache.get(depth)
        if spectrum is not None:
            return spectrum
        kernel = self._image_kernel(depth) if any(self.grid.periodic) else self._love_kernel(depth)
        full = fft.rfft2(np.ascontiguousarray(np.moveaxis(kernel, -1, 0)))
        spectrum = np.where(_REAL, full.real, full.imag)
        if (len(self._cache) + 1) * spectrum.nbytes <= self.cache_bytes:
            self._cache[depth] = spectrum
        return spectrum

    def _periodic_modes(self, depth):
        q1, q2 = wavenumbers(self.grid.shape, self.grid.spacing)
        k = np.hypot(q1, q2)
        safe = np.where(k > 0, k, 1.0)
        n1c, n2c = q1 / safe, q2 / safe
        decay = np.exp(-k * depth)
        s_nn = -(1 - k * depth) * decay
        s_zz = -(1 + k * depth) * decay
        s_nz = 1j * k * depth * decay
        s_tt = self.poisson * (s_nn + s_zz)
        modes = np.array([s_nn * n1c**2 + s_tt * n2c**2, s_nn * n2c**2 + s_tt * n1c**2, s_zz,
                          s_nz * n2c, s_nz * n1c, (s_nn - s_tt) * n1c * n2c])
        modes[:, 0, 0] = [-(1 + 2 * self.poisson) / 2, -(1 + 2 * self.poisson) / 2, -1, 0, 0, 0]
        return modes

    def apply(self, pressure, depths=None):
        """Stresses [Pa], shape ``(n1, n2, n_depths, 6)`` in Voigt order xx yy zz yz xz xy.

        Parameters
        ----------
        pressure : ndarray
            Surface pressure ``(n1, n2)`` [Pa], compressive positive.
        depths : array_like, optional
            Depths ``x3 >= 0`` [m]; default the grid's layer centres.
        """
        depths = self.grid.x3 if depths is None else np.atleast_1d(np.asarray(depths, dtype=float))
        if np.any(depths < 0) or not np.all(np.isfinite(depths)):
            raise ParameterError(f"depths must be finite and >= 0 [m], got {depths!r}")
        n1, n2 = self.grid.shape
        out = np.empty((n1, n2, depths.size, 6))
        if all(self.grid.periodic):
            p_hat = fft.rfft2(np.asarray(pressure, dtype=float))
            for j, depth in enumerate(depths):
                out[:, :, j, :] = np.moveaxis(fft.irfft2(self._periodic_modes(depth) * p_hat, (n1, n2)), 0, -1)
            return out
        p_hat = self._convolution.transform(pressure)
        for j, depth in enumerate(depths):
            stresses = self._convolution.apply_spectrum(p_hat, self._kernel_spectrum(float(depth)) * _PHASE)
            out[:, :, j, :] = np.moveaxis(stresses, 0, -1)
        return out

    def transpose(self, fields, depths):
        """The adjoint of :meth:`apply`: ``out(x) = sum_depth sum_c int K_c(xi - x) f_c(xi)``.

        With ``f`` an eigenstrain (tensor shears, counted twice) times the layer
        thickness, this is the normal surface displacement it causes, by Betti's
        reciprocal theorem (THEORY.md sec. 8): the work of a unit pressure on a
        cell through the eigenstrain's displacement equals the work of the
        pressure's stress through the eigenstrain.

        Parameters
        ----------
        fields : ndarray
            ``(n1, n2, n_depths, 6)`` in Voigt order xx yy zz yz xz xy.
        depths : array_like
            The depths [m] of the field's layers.

        Returns
        -------
        ndarray
            ``(n1, n2)``, in the fields' units times those of the kernel [1 per unit pressure].
        """
        if any(self.grid.periodic):
            raise ParameterError(f"the transpose stress operator needs an open grid, got periodic={self.grid.periodic}")
        depths = np.atleast_1d(np.asarray(depths, dtype=float))
        n1, n2 = self.grid.shape
        if fields.shape != (n1, n2, depths.size, 6):
            raise ShapeError(f"fields have shape {fields.shape}, expected {(n1, n2, depths.size, 6)}")
        total = 0.0
        for j, depth in enumerate(depths):
            spectra = self._convolution.transform(np.moveaxis(fields[:, :, j, :], -1, 0))
            total = total + np.sum(self._kernel_spectrum(float(depth)) * np.conj(_PHASE) * spectra, axis=0)
        return fft.irfft2(total, self._convolution.fft_shape)[:n1, :n2]

