"""Stress on the whole subsurface grid caused by eigenstrains on a box of its cuboids (Chiu 1977, 1978).

:class:`~framework.operators.eigenstrain.HalfSpaceEigenstrain` maps eigenstrains on a box to
the strain on the same box: the equivalent-inclusion solve needs no more. The eigenstrains'
field reaches beyond the box (it decays like ``1/r^3``), and a picture of the stress that stops
at the box shows a rectangular step there. :class:`EigenstrainField` maps the same box
eigenstrains to the stress at every cuboid centre of the grid, with the same three terms and
the same cell-averaged kernels (:func:`~framework.operators.eigenstrain.potential_kernel_items`),
so that in the box it gives the box operator's strain and beyond it the field's continuation:

1. the infinite-space field, a 3-D linear convolution of the box with the kernels of every
   offset between a grid cuboid and a box cuboid. Each kernel is even or odd in each offset
   (:mod:`framework.operators.parity`): it is evaluated on the offsets ``0 .. K`` of each axis
   (``K`` the largest offset, wherever a rolling box goes) and transformed on a period
   ``N > 2K``, an eighth of its spectrum stored; the box's transforms are pruned as the box operator's, and
   taken back onto the grid's points of the lattice;
2. the mirror image's field, a correlation in x3 of the box with the kernels of the sums of
   depths (``N3 >= layers + m3 - 1``), a quarter stored; both terms go through the box
   operator's compiled spectral pass (:mod:`framework.operators._box_loops`);
3. the Boussinesq correction: the traction ``2 s33`` that the two leave on the whole surface
   (a 2-D convolution per layer of the box, :class:`~framework.operators.box_surface.BoxSurface`)
   is a pressure whose Love stress at every layer :class:`~framework.operators.stress.SubsurfaceStress`
   gives; a caller that also has a contact pressure adds it to that pressure, one surface
   transform for both.

The box operator's Boussinesq correction takes the traction on a patch around the box only
(:data:`~framework.operators.eigenstrain.PATCH_DEPTHS`); here it covers the grid, so in the box
the two differ by what the patch leaves out (below ~1e-3 of the correction).
"""
import math

import numpy as np

from .. import fft
from ..errors import ParameterError, ShapeError
from ._box_loops import PERMUTATION, PassItems, kernel_table, loops, stored_kernels
from . import box_fft
from .box_surface import BoxSurface
from .eigenstrain import (COMPONENTS, ENTRIES, MANDEL, MIRROR, kernel_spectra, surface_traction_kernels)
from .stress import SubsurfaceStress


def _largest_offset(size, first, last, extent):
    """Largest ``|target - source|`` in cuboids along an axis of ``size`` cuboids, the box of ``extent`` cuboids
    starting anywhere from ``first`` to ``last``."""
    return int(max(last + extent - 1, size - 1 - first))


def field_bytes(grid, start, shape, starts=None):
    """Memory an :class:`EigenstrainField` of the box ``start``, ``shape`` (and ``starts``, as its parameters) on
    ``grid`` takes at its peak [bytes], told before it is built: the larger of its kernels' build (the keys' values
    of one term beside the entries of both: 40 bytes per stored wavenumber) and a product (the kernels kept, 24
    bytes per stored wavenumber, the transforms' buffers, the surface maps, Love's kernels of every depth and
    three of the grid's stress fields: a product's terms and their sum)."""
    limits = (*grid.shape, grid.layers)
    places = [tuple(start[:2])] if starts is None else [tuple(s[:2]) for s in starts]
    firsts = [min(s[0] for s in places), min(s[1] for s in places), start[2]]
    lasts = [max(s[0] for s in places), max(s[1] for s in places), start[2]]
    reach = tuple(_largest_offset(limits[a], firsts[a], lasts[a], shape[a]) for a in range(3))
    lattice = tuple(fft.even_size(2 * r + 2) for r in reach)
    wavenumbers = math.prod(n // 2 + 1 for n in lattice)
    h = lattice[2] // 2 + 1
    n1, n2, layers = limits
    surface = math.prod(fft.even_size(2 * r + 1) // 2 + 1 for r in reach[:2])
    transforms = (box_fft.buffer_bytes(shape, lattice) + 16 * 6 * n1 * n2 * h      # the target's lines, all q3
                  + 16 * 6 * lattice[0] * lattice[1] * min(h, max(k1 - k0 for k0, k1 in box_fft.q3_blocks(lattice))))
    build = 40 * len(ENTRIES) * wavenumbers
    love = 8 * 6 * 2 * n1 * (n2 + 1) * layers                  # Love's kernels, a spectrum per depth
    product = (24 * len(ENTRIES) * wavenumbers + transforms + 2 * 8 * 6 * shape[2] * surface + love
               + 3 * 8 * 6 * n1 * n2 * layers)
    return int(max(build, product))


class EigenstrainField:
    """Stress at every cuboid centre of the grid caused by eigenstrains on a box of its cuboids.

    Built once (the kernels' spectra); :meth:`apply` is the one verb. Memory: the 21
    infinite-space kernels take ``21 (N1/2+1)(N2/2+1)(N3/2+1)`` reals and the 21 mirror kernels as
    many complex numbers (held a block of ``q3`` at a time, :func:`~framework.operators.box_fft.q3_blocks`);
    a product's transforms are the box operator's pruned ones (:class:`~framework.operators.box_fft.BoxFFT`,
    taken back onto the grid): one block's six spectra (at most
    :data:`~framework.operators.box_fft.BLOCK_BYTES`), the grid's lines along ``x3`` (``6 n1 n2 (N3/2+1)``
    complex numbers) and one component's real lines, not the whole padded lattice's spectra and two real
    arrays (a 30-body dispersion at 8 cuboids a radius on a 192 x 192 x 64 grid: 2.17 -> 1.66 GiB at the
    first call, kernels included, 2.4 -> 2.2 s a call); the surface maps ``2 x 6 m3`` planes of
    ``(P1/2+1)(P2/2+1)`` reals (``P`` about twice the grid's surface), plus the stress of the grid that a
    product returns.

    Parameters
    ----------
    grid : framework.Grid
        Open grid with layers.
    poisson : float
        Poisson ratio of the half-space.
    start, shape : tuple of int
        The box's first cuboid and its size (x1, x2, layers), as the box operator's.
    starts : sequence of (int, int), optional
        Every ``(x1, x2)`` start the box takes (a rolling run moves it); default ``start`` alone.
    surface_stress : framework.operators.stress.SubsurfaceStress, optional
        The grid's Love operator to share (a result's, which keeps its kernels); default a new one.
    """

    def __init__(self, grid, poisson, start, shape, starts=None, surface_stress=None):
        if any(grid.periodic):
            raise ParameterError(f"the eigenstrains' field needs an open grid, got periodic={grid.periodic}")
        if not grid.layers:
            raise ParameterError("grid.layers is 0: eigenstrains live on the subsurface cuboids; give the grid layers")
        start, shape = tuple(int(s) for s in start), tuple(int(m) for m in shape)
        starts = [tuple(start[:2])] if starts is None else [tuple(int(c) for c in s[:2]) for s in starts]
        limits = (*grid.shape, grid.layers)
        for axis in range(3):
            firsts = [s[axis] for s in starts] if axis < 2 else [start[2]]
            if min(firsts) < 0 or shape[axis] < 1 or max(firsts) + shape[axis] > limits[axis]:
                raise ParameterError(f"box along axis {axis}: cuboids {min(firsts)} .. {max(firsts) + shape[axis] - 1} "
                                     f"lie outside the grid's 0 .. {limits[axis] - 1}")
        self.grid, self.poisson, self.start, self.shape = grid, float(poisson), start, shape
        self.starts = starts
        self.spacing = (*grid.spacing, grid.layer_thickness)
        firsts = [min(s[0] for s in starts), min(s[1] for s in starts), start[2]]
        lasts = [max(s[0] for s in starts), max(s[1] for s in starts), start[2]]
        self.reach = tuple(_largest_offset(limits[a], firsts[a], lasts[a], shape[a]) for a in range(3))
        self.fft_shape = tuple(fft.even_size(2 * r + 2) for r in self.reach)
        self._block_bytes = box_fft.BLOCK_BYTES          # the kernels' blocks of q3 and the transforms' the same
        self._kernels = {k0: tuple(stored_kernels(part) for part in block)
                         for k0, block in self._spectra().items()}       # every (q1, q2 >= 0) stored, in order
        self._table = kernel_table(*(n // 2 + 1 for n in self.fft_shape[:2]), False)[0]
        self._items = PassItems(self._table)
        self._entries = (np.array([a for a, _ in ENTRIES]), np.array([b for _, b in ENTRIES]))
        self._parities = tuple(np.array([1.0 - 2 * (COMPONENTS[c].count(axis) % 2) for c in range(6)])
                               for axis in range(2))
        region = (slice(0, grid.shape[0]), slice(0, grid.shape[1]))
        self._surface = BoxSurface(grid, poisson, region, start, shape, traction=self._traction, starts=starts)
        self.surface_stress = SubsurfaceStress(grid, poisson) if surface_stress is None else surface_stress
        self._box_fft = None

    def _spectra(self):
        """The 21 infinite-space kernels' real factors and the 21 mirror kernels' spectra, each
        ``(21, N1/2+1, N2/2+1, k1 - k0)``, of ``C : D`` (unit Young's modulus, Mandel basis), averaged over
        each target cuboid as the box operator's are, per block of q3 ``{k0: (direct, mirror)}``
        (:func:`~framework.operators.box_fft.q3_blocks` of :data:`~framework.operators.box_fft.BLOCK_BYTES`)."""
        n3 = self.fft_shape[2]
        m3, s3, layers = self.shape[2], self.start[2], self.grid.layers
        h = self.spacing
        faces = [(np.arange(k + 2) - 0.5) * step for k, step in zip(self.reach, h)]
        # target depth index i3, mirror source j3 = s3 + m3 - 1 - b (the box flipped): the offset
        # x3 + x3' is (o + 2 s3 + m3) dx3 with o = (i3 - s3) - b; o runs over -(s3 + m3 - 1) .. layers - 1 - s3
        mirror_faces = (s3 + 0.5 + np.arange(layers + m3)) * h[2]
        place = (np.arange(layers + m3 - 1) - (s3 + m3 - 1)) % n3
        return kernel_spectra(faces, mirror_faces, place, m3, self.fft_shape, self.poisson, h,
                              blocks=box_fft.q3_blocks(self.fft_shape, self._block_bytes))

    def _traction(self, faces1, faces2):
        """``2 s33`` at the surface ``(F1, F2, m3, 6)`` per unit eigenstrain component of a cuboid of each box
        layer (top-down), unit modulus, target minus source between the faces given [m] (the box operator's)."""
        return surface_traction_kernels(faces1, faces2, self.start[2], self.shape[2], self.spacing[2], self.poisson)

    def _transforms(self):
        if self._box_fft is None:
            self._box_fft = box_fft.BoxFFT(self.shape, self.fft_shape, effort="FFTW_ESTIMATE",
                                           block_bytes=self._block_bytes, by_columns=True)
        return self._box_fft

    def _where(self, start):
        start = tuple(self.start[:2]) if start is None else tuple(int(c) for c in start[:2])
        for axis in range(2):
            low, high = min(s[axis] for s in self.starts), max(s[axis] for s in self.starts)
            if not low <= start[axis] <= high:
                raise ParameterError(f"start {start}: the box's first cuboid along x{axis + 1} must lie in {low} .. "
                                     f"{high}, the places this field was built for")
        return start

    def volume(self, eigenstrain, start=None):
        """The infinite-space and mirror terms ``(n1, n2, layers, 6)``: stress per unit Young's modulus times the
        eigenstrain ``(m1, m2, m3, 6)`` (tensor shears) of the box at ``start`` (x1, x2; default the first)."""
        eigenstrain = self._check(eigenstrain)
        s1, s2 = self._where(start)
        grid, passes = self.grid, loops()
        # the box at the lattice's first points; the grid's cuboid i at (i - start) mod N of each axis
        target = [(np.arange(size) - s) % n for size, s, n in zip((*grid.shape, grid.layers), (s1, s2, self.start[2]),
                                                                   self.fft_shape)]
        return self._transforms().apply(
            eigenstrain, lambda spectra, k0, k1, columns=None: passes.stiffness(
                spectra, *self._kernels[k0], self._items(columns), PERMUTATION, *self._entries, *self._parities,
                MIRROR),
            MANDEL, 1.0 / MANDEL, target=target, columns=self._transforms().by_columns)

    def traction(self, eigenstrain, start=None):
        """The pressure ``2 s33`` ``(n1, n2)`` on the grid's surface (per unit Young's modulus times the
        eigenstrain) that the Boussinesq correction removes."""
        eigenstrain = self._check(eigenstrain)
        surface = self._surface
        surface.move(self._where(start))
        spectrum, = surface.surface(eigenstrain, "traction")
        return surface.field(spectrum)

    def apply(self, eigenstrain, start=None, pressure=None):
        """Stress ``(n1, n2, layers, 6)`` [Pa per unit Young's modulus times the eigenstrain] at every cuboid centre
        of the grid, of the box eigenstrain ``(m1, m2, m3, 6)`` (tensor shears) with its first cuboid at
        ``start`` (x1, x2; default the box's first place), plus Love's stress of a surface ``pressure``
        ``(n1, n2)`` [Pa] if given (one surface transform for both).

        ``C : D[eigenstrain]`` (the total strain's stress, not minus the eigenstrain) with the unit-modulus
        stiffness: give the eigenstrain times the matrix's Young's modulus for stresses in Pa.
        """
        surface = self.traction(eigenstrain, start)
        if pressure is not None:
            surface = surface + np.asarray(pressure, dtype=float)
        return self.volume(eigenstrain, start) + self.surface_stress.apply(surface)

    def _check(self, eigenstrain):
        expected = (*self.shape, 6)
        if np.shape(eigenstrain) != expected:
            raise ShapeError(f"eigenstrain has shape {np.shape(eigenstrain)}, the field's box is {expected}")
        return np.asarray(eigenstrain, dtype=float)
