"""Surface fields of a box of cuboids, and the stress in the box of a surface field, on one FFT grid.

Three maps link a box of eigenstrain cuboids (``m1 x m2 x m3``) with a region of the surface
(``n1 x n2`` cells of the grid), each a 2-D convolution per layer of the box and component:

- the traction ``2 s33`` that the eigenstrains and their mirror image leave on the surface
  (Chiu 1978; the corner sums of :mod:`framework.operators.eigenstrain`, sampled at the cell centres);
- the normal surface displacement of the eigenstrains, by Betti's reciprocal theorem from Love's
  pressure-to-stress coefficients (THEORY.md sec. 8);
- the stress at the box's cuboid centres caused by a surface pressure (Love 1929; Johnson 1985):
  the Boussinesq correction of the eigenstrain operator and the contact's stress at the box.

All three run on one padded grid of ``P1 x P2`` points that holds every offset between a region
cell and a footprint cell for every place the box takes (a rolling run moves it), so the linear
convolutions are exact and no kernel is rebuilt when the box moves. Each kernel is even or odd in
each offset (:mod:`framework.operators.parity`): a quarter of its spectrum is stored, as a real
factor. A box's planes are transformed pruned: their rows hold the footprint only, so the rows
are transformed first (``m1`` rows a plane instead of ``P1``) and the columns second; the other
way, only the footprint's rows and columns are transformed back. Layers go six planes at a time
(one per component), which stays in the processor's caches.
"""
import numpy as np

from .. import fft
from ..errors import ParameterError
from . import parity
from ._box_loops import loops
from .kernels import subsurface_stress

#: Index pairs of the six components, in Voigt order xx yy zz yz xz xy.
_COMPONENTS = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))


def surface_parities(component):
    """Parity (+1 even, -1 odd) along x1 and x2 of a kernel that carries the Voigt ``component``."""
    indices = _COMPONENTS[component]
    return np.array([1 - 2 * (indices.count(0) % 2), 1 - 2 * (indices.count(1) % 2)])


class BoxSurface:
    """The three maps between a box of cuboids and a surface region, on one padded FFT grid.

    Parameters
    ----------
    grid : framework.Grid
        Open grid with layers.
    poisson : float
        Poisson ratio of the half-space.
    region : tuple of slice
        The surface cells ``(x1 slice, x2 slice)`` of the grid that the surface fields cover.
    start, shape : tuple of int
        The box's first cuboid and its size (x1, x2, layers).
    traction : callable or None
        ``traction(faces1, faces2)`` -> ``(len(faces1) - 1, len(faces2) - 1, m3, 6)``: ``2 s33`` at the
        surface per unit eigenstrain component of a cuboid of each layer (layers top-down), the
        target at offsets between the faces given [m]; None: no traction map.
    starts : sequence of (int, int), optional
        Every ``(x1, x2)`` start the box will take (a rolling run); by default ``start`` alone.
    """

    def __init__(self, grid, poisson, region, start, shape, traction=None, starts=None):
        self.grid, self.poisson = grid, float(poisson)
        self.region = tuple(region)
        self.low = np.array([s.start for s in self.region])
        self.size = tuple(s.stop - s.start for s in self.region)
        self.footprint_shape, self.layers = tuple(shape[:2]), int(shape[2])
        self.depths = grid.x3[start[2]:start[2] + shape[2]]
        positions = np.array([start[:2]] if starts is None else list(starts), dtype=int) - self.low
        self.first, self.last = positions.min(axis=0), positions.max(axis=0)
        for axis in range(2):
            if self.first[axis] < 0 or self.last[axis] + shape[axis] > self.size[axis]:
                raise ParameterError(f"the box's footprint leaves the surface region along x{axis + 1}")
        # The largest offset between a region cell and a footprint cell, wherever the box goes.
        self.reach = tuple(int(max(self.last[a] + shape[a] - 1, self.size[a] - 1 - self.first[a])) for a in range(2))
        self.fft_shape = tuple(fft.even_size(2 * r + 1) for r in self.reach)
        self.planes = 6 * self.layers
        # Kernels (planes, P1/2 + 1, P2/2 + 1), plane = 6 * layer + component; their factors and parities in q1.
        self._love, self._love_factor, self._love_parity = self._love_kernels()
        self._traction = None
        if traction is not None:
            self._traction, self._traction_factor, self._traction_parity = self._traction_kernels(traction)
        self._buffers()
        self.position = None
        self.move(start[:2])

    # --- kernels -------------------------------------------------------------------------------
    def _spectra(self, values, parities):
        """Real factors ``(P1/2 + 1, P2/2 + 1)`` of a kernel given at the offsets ``0 .. reach``."""
        out = parity.half_spectrum(values, parities[0], self.fft_shape[0], axis=0)
        return parity.half_spectrum(out, parities[1], self.fft_shape[1], axis=1)

    def _love_kernels(self):
        spacing = self.grid.spacing
        offsets = np.meshgrid(np.arange(self.reach[0] + 1) * spacing[0], np.arange(self.reach[1] + 1) * spacing[1],
                              indexing="ij")
        kernels = np.empty((self.planes, self.fft_shape[0] // 2 + 1, self.fft_shape[1] // 2 + 1))
        for layer, depth in enumerate(self.depths):
            stress = subsurface_stress(offsets[0], offsets[1], float(depth), half1=spacing[0] / 2,
                                       half2=spacing[1] / 2, poisson=self.poisson)
            for c in range(6):
                kernels[6 * layer + c] = self._spectra(stress[..., c], surface_parities(c))
        return kernels, *self._factors()

    def _traction_kernels(self, traction):
        spacing = self.grid.spacing
        faces = [(np.arange(r + 2) - 0.5) * h for r, h in zip(self.reach, spacing)]
        values = traction(*faces)                                     # (reach1 + 1, reach2 + 1, m3, 6)
        kernels = np.empty((self.planes, self.fft_shape[0] // 2 + 1, self.fft_shape[1] // 2 + 1))
        for layer in range(self.layers):
            for c in range(6):
                kernels[6 * layer + c] = self._spectra(values[:, :, layer, c], surface_parities(c))
        return kernels, *self._factors()

    def _factors(self):
        factors = np.array([parity.phase(surface_parities(c)) for c in range(6)] * self.layers)
        parities = np.array([surface_parities(c)[0] for c in range(6)] * self.layers, dtype=float)
        return factors, parities

    # --- transforms ----------------------------------------------------------------------------
    def _buffers(self):
        (p1, p2), m1 = self.fft_shape, self.footprint_shape[0]
        h2 = p2 // 2 + 1
        self._rows_in = fft.zeros((6, m1, p2))
        self._columns_in = fft.zeros((6, p1, h2), complex)
        self._columns_out = fft.zeros((6, p1, h2), complex)
        self._back_rows_out = fft.zeros((6, m1, p2))
        self._plane_in = fft.zeros((p1, p2))
        self._plane_spectrum = fft.zeros((p1, h2), complex)
        self._plane_out = fft.zeros((p1, p2))
        self._columns = fft.Transform(self._columns_in, self._columns_out, axes=(1,))
        self._spread = fft.zeros((6, p1, h2), complex)
        self._back_columns = fft.Transform(self._spread, self._columns_out, axes=(1,), inverse=True)
        self._plane_forward = fft.Transform(self._plane_in, self._plane_spectrum, axes=(0, 1))
        self._plane_inverse = fft.Transform(self._plane_spectrum, self._plane_out, axes=(0, 1))
        self._row_transforms = {}

    def _footprint_rows(self, f1):
        """The transforms along x2 of the footprint's rows, which start at the padded grid's row ``f1``: the forward
        one writes them into the columns' input, the inverse one reads them from the columns' output (a copy between
        them and buffers of their own took 0.5 + 0.3 ms of a 64^3 box's product); made at a place's first use."""
        if f1 not in self._row_transforms:
            rows = slice(f1, f1 + self.footprint_shape[0])
            self._row_transforms[f1] = (fft.Transform(self._rows_in, self._columns_in[:, rows], axes=(2,)),
                                        fft.Transform(self._columns_out[:, rows], self._back_rows_out, axes=(2,)))
        return self._row_transforms[f1]

    def move(self, start):
        """The box's footprint starts at the grid cell ``start = (s1, s2)`` (within the places planned)."""
        position = np.array(start[:2], dtype=int) - self.low
        if np.any(position < self.first) or np.any(position > self.last):
            raise ParameterError(f"the box start {tuple(int(s) for s in start[:2])} lies outside the places this "
                                 f"surface map was built for")
        if self.position is None or np.any(position != self.position):
            self._rows_in[...] = 0.0            # the zero padding outside the footprint moves with it
            self._columns_in[...] = 0.0
            self.position = position
            self._rows, self._back_rows = self._footprint_rows(int(position[0]))

    def surface(self, field, *kinds, weights=None):
        """Spectra ``(P1, P2/2 + 1)`` of surface fields of a box field ``(m1, m2, m3, 6)``, unnormalised, one per kind.

        ``"traction"``: the kernels of ``traction``; ``"betti"``: Love's kernels transposed, the components
        times ``weights`` (the surface displacement per unit eigenstrain and layer thickness is the field
        times the shear weights, see :meth:`HalfSpaceEigenstrain.surface_displacement`). Several kinds share
        the transforms of the field.
        """
        f2 = self.position[1]
        sums = []
        for kind in kinds:
            if kind == "traction":
                sums.append((self._traction, self._traction_factor, self._traction_parity))
            else:   # the correlation with Love's kernels: each reversed, i.e. times its parity in x1 and x2
                reversal = np.array([np.prod(surface_parities(c)) for c in range(6)])
                scale = reversal if weights is None else reversal * weights
                sums.append((self._love, self._love_factor * np.tile(scale, self.layers), self._love_parity))
        totals = [np.zeros((self.fft_shape[0], self.fft_shape[1] // 2 + 1), complex) for _ in kinds]
        passes = loops()
        for layer in range(self.layers):
            passes.surface_planes(self._rows_in, field, layer, f2)
            self._rows()                # (into the columns' input)
            self._columns()
            for total, (kernels, factors, parities) in zip(totals, sums):
                passes.surface_sum(total, kernels, factors, parities, self._columns_out, 6 * layer)
        return totals

    def box_stress(self, spectrum, add_to=None):
        """Stress ``(m1, m2, m3, 6)`` at the box's cuboid centres of the surface pressure whose unnormalised
        spectrum (as :meth:`spectrum` gives it) is ``spectrum`` [stress per unit pressure]; added to the box
        field ``add_to`` (and returned) when given."""
        (m1, m2), f2 = self.footprint_shape, self.position[1]
        out = np.empty((m1, m2, self.layers, 6)) if add_to is None else add_to
        scale = 1.0 / (self.fft_shape[0] * self.fft_shape[1])
        passes = loops()
        for layer in range(self.layers):
            passes.surface_spread(self._spread, self._love, self._love_factor, self._love_parity, spectrum, 6 * layer)
            self._back_columns()
            self._back_rows()           # (from the columns' output)
            passes.surface_add(out, self._back_rows_out, layer, f2, scale, add_to is not None)
        return out

    def spectrum(self, field):
        """Unnormalised spectrum of a region field ``(n1, n2)`` on the padded grid."""
        n1, n2 = self.size
        self._plane_in[:n1, :n2] = field
        self._plane_forward()
        return self._plane_spectrum.copy()

    def field(self, spectrum):
        """The region field ``(n1, n2)`` of an unnormalised spectrum (the inverse of :meth:`spectrum` on the region)."""
        n1, n2 = self.size
        self._plane_spectrum[...] = spectrum
        self._plane_inverse()
        return self._plane_out[:n1, :n2] * (1.0 / (self.fft_shape[0] * self.fft_shape[1]))
