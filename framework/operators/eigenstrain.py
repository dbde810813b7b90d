"""Strain of the half-space caused by eigenstrains on a box of cuboids (Chiu 1977, 1978).

A uniform eigenstrain ``e*`` in a cuboid of an infinite isotropic body causes the strain
(Mura 1987, eq. 11.30; ``phi`` and ``psi`` the Newtonian and biharmonic potentials of the
cuboid, ``phi = int 1/|x-x'| dV'``, ``psi = int |x-x'| dV'``)::

    8 pi (1-nu) e_ik = psi_,ijkl e*_jl - 2 nu e*_mm phi_,ik - 2 (1-nu) (e*_il phi_,lk + e*_kl phi_,li)

The derivatives of the potentials of a cuboid are corner sums of closed forms (Chiu 1977):
with ``H`` the triple antiderivative of ``1/r`` (or ``r``), ``D phi(x) = sum_corners +- D H(x - c)``;
on a lattice of cuboids the corner sum is a first difference along each axis of ``D H`` sampled at
the cuboids' faces (:func:`potential_kernels`).

In the half-space ``x3 >= 0`` (Chiu 1978; Liu & Wang 2005) the strain is the sum of

1. the infinite-space strain of the eigenstrains (a 3-D convolution);
2. the infinite-space strain of their mirror image ``e*(x1, x2, -x3)`` with ``e*_13``, ``e*_23``
   negated (a convolution in x1, x2 and a correlation in x3): the two together leave no shear
   traction on ``x3 = 0`` and twice the normal stress ``s33`` of the first;
3. the Boussinesq field of the surface pressure ``p = 2 s33`` that removes that normal traction,
   with Love's coefficients (:class:`~framework.operators.stress.SubsurfaceStress`).

Strains are stored as ``(..., 6)`` arrays in Voigt order xx yy zz yz xz xy with *tensor* shears
(``e_23``, not ``2 e_23``).
"""
import numpy as np
import scipy.fft

from .. import fft
from ..errors import ParameterError, ShapeError
from ..grid import Grid
from .stress import _PHASE, SubsurfaceStress

#: The surface patch of the Boussinesq correction reaches this many box-bottom depths beyond the box.
PATCH_DEPTHS = 4.0

#: Gauss points per axis of the rule that averages the kernels over a target cuboid (the Galerkin
#: operator, ``HalfSpaceEigenstrain(average=True)``). Collocated at the centres, the operator has a
#: checkerboard mode of eigenvalue ~1.21 in ``C^-1/2 (C:D) C^-1/2`` (a continuous operator's lie in
#: [0, 1]): the equivalent-inclusion system of an inhomogeneity softer than ~0.17 of the matrix is
#: then singular. Averaged over the target by this rule the largest eigenvalue is 0.983 (2 points;
#: 0.980 with 4), so any positive stiffness works.
AVERAGE_POINTS = 2

#: Index pairs of the six strain components, in Voigt order xx yy zz yz xz xy.
COMPONENTS = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))
#: Weights of the six components in a contraction ``a : b`` (shears count twice).
CONTRACTION = np.array([1.0, 1.0, 1.0, 2.0, 2.0, 2.0])
#: Mandel's scaling of the six components (shears times sqrt 2): symmetric stiffness matrices.
MANDEL = np.array([1.0, 1.0, 1.0, np.sqrt(2.0), np.sqrt(2.0), np.sqrt(2.0)])
#: Sign of each component in the mirror image (x3 -> -x3): the 13 and 23 shears change sign.
MIRROR = np.array([1.0, 1.0, 1.0, -1.0, -1.0, 1.0])


def _sum_r(t, r, rest2):
    """``r + t`` without cancellation when ``t < 0`` (``rest2 = r^2 - t^2``)."""
    return np.where(t >= 0, r + t, rest2 / np.where(t >= 0, 1.0, r - t))


def _phi_diagonal(ti, tj, tk, r):
    return -np.arctan(tj * tk / (ti * r))


def _phi_mixed(ti, tj, tk, r):
    return np.log(_sum_r(tk, r, ti * ti + tj * tj))


def _psi_four(ti, tj, tk, r):
    ti2, tj2, tk2 = ti * ti, tj * tj, tk * tk
    return (ti * tj / (r * _sum_r(tk, r, ti2 + tj2)) + ti * tk / (r * _sum_r(tj, r, ti2 + tk2))
            - 2 * np.arctan(tj * tk / (ti * r))
            + 2 * ti * tj * tk * (r * r + ti2) / (r * (ti2 + tj2) * (ti2 + tk2)))


def _psi_three_one(ti, tj, tk, r):
    rho2 = ti * ti + tj * tj
    return np.log(_sum_r(tk, r, rho2)) - ti * ti * tk / (rho2 * r)


def _psi_two_two(ti, tj, tk, r):
    return -ti * tj * tk / ((ti * ti + tj * tj) * r)


def _psi_two_one_one(ti, tj, tk, r):
    return ti / r


def _corner_function(key, t, r):
    """One corner function ``D H`` (``key`` a sorted index tuple) at offsets ``t`` with ``r = |t|``."""
    counts = [key.count(axis) for axis in range(3)]
    order = sorted(range(3), key=lambda axis: -counts[axis])     # axes by decreasing count
    i, j, k = order
    if len(key) == 2:
        if counts[i] == 2:
            return _phi_diagonal(t[i], t[j], t[k], r)
        return _phi_mixed(t[i], t[j], t[k], r)                   # k: the axis not in the key
    if counts[i] == 4:
        return _psi_four(t[i], t[j], t[k], r)
    if counts[i] == 3:
        return _psi_three_one(t[i], t[j], t[k], r)
    if counts[j] == 2:
        return _psi_two_two(t[i], t[j], t[k], r)
    return _psi_two_one_one(t[i], t[j], t[k], r)


#: The 21 derivatives of the potentials a strain needs: ``(i, j)`` for ``phi_,ij``, ``(i, j, k, l)`` for ``psi_,ijkl``.
KEYS = tuple(sorted({tuple(sorted(c)) for c in np.ndindex(3, 3)} | {tuple(sorted(c)) for c in np.ndindex(3, 3, 3, 3)},
                    key=lambda key: (len(key), key)))


def _corner_functions(t):
    """The 21 corner functions ``D H`` at offsets ``t = (t1, t2, t3)`` from a cuboid's corner.

    Keys are sorted index tuples: ``(i, j)`` for ``phi_,ij`` and ``(i, j, k, l)`` for
    ``psi_,ijkl``. The offsets must not vanish (the lattices here never put a face
    through a target point).
    """
    r = np.sqrt(t[0] ** 2 + t[1] ** 2 + t[2] ** 2)
    return {key: _corner_function(key, t, r) for key in KEYS}


def cell_average_rule(cell, points=None):
    """Gauss rule averaging over a cuboid target cell: ``(shifts (n, 3) [m], weights (n,))``.

    ``cell`` the cell sizes [m] (``None``: the centre alone); ``points`` per axis, default
    :data:`AVERAGE_POINTS`.
    """
    if cell is None:
        return np.zeros((1, 3)), np.ones(1)
    x, w = np.polynomial.legendre.leggauss(AVERAGE_POINTS if points is None else points)
    grids = np.meshgrid(*[0.5 * h * x for h in cell], indexing="ij")
    weights = np.prod(np.meshgrid(*[0.5 * w] * 3, indexing="ij"), axis=0)
    return np.stack([g.ravel() for g in grids], axis=-1), weights.ravel()


def potential_kernel_items(faces1, faces2, faces3, cell=None):
    """:func:`potential_kernels` one key at a time, ``(key, array)``: a few lattice arrays in memory (the
    offsets' lengths at each point of the averaging rule, and the key's sum)."""
    shape = (len(faces1), len(faces2), len(faces3))
    rule = []           # per point of the rule: its weight, the offsets and their lengths (shared by the keys)
    for shift, weight in zip(*cell_average_rule(cell)):
        t = [np.broadcast_to(c, shape) for c in np.meshgrid(faces1 + shift[0], faces2 + shift[1], faces3 + shift[2],
                                                            indexing="ij", sparse=True)]
        rule.append((weight, t, np.sqrt(t[0] ** 2 + t[1] ** 2 + t[2] ** 2)))
    for key in KEYS:
        total = 0.0
        for weight, t, r in rule:
            total = total + weight * _corner_function(key, t, r)
        # Per axis, int_a^b f(x - x') dx' = H(x - a) - H(x - b): a forward difference in t = x - c.
        yield key, np.diff(np.diff(np.diff(total, axis=0), axis=1), axis=2)


def potential_kernels(faces1, faces2, faces3, cell=None):
    """Derivatives of the cuboid potentials on a lattice of cuboids, by corner sums.

    Parameters
    ----------
    faces1, faces2, faces3 : ndarray
        Increasing offsets [m] of the cuboid faces from the target point, ``x - c``,
        along each axis: cuboid ``n`` lies between ``faces[n]`` and ``faces[n + 1]``.
        No offset may be zero.
    cell : tuple of float, optional
        Sizes [m] of a target cell centred on the target point: the values are then its
        average over that cell (:func:`cell_average_rule`) instead of the centre's.

    Returns
    -------
    dict
        ``phi_,ij`` and ``psi_,ijkl`` [m^-1... m] per key, arrays of shape
        ``(len(faces1) - 1, len(faces2) - 1, len(faces3) - 1)``; the value for cuboid
        ``n`` is ``D int_cuboid f(x - x') dV'``.
    """
    return dict(potential_kernel_items(faces1, faces2, faces3, cell))


def strain_from_potentials(potentials, eigenstrain, poisson):
    """Strain ``(..., 6)`` from the potentials' derivatives and an eigenstrain ``(..., 6)``.

    Works pointwise on arrays that broadcast (real space) and on spectra (Fourier space,
    where the products are the convolution's).
    """
    nu = poisson
    e = {}
    for c, (i, j) in enumerate(COMPONENTS):
        e[(i, j)] = e[(j, i)] = eigenstrain[..., c]
    trace = eigenstrain[..., 0] + eigenstrain[..., 1] + eigenstrain[..., 2]

    def phi(i, j):
        return potentials[tuple(sorted((i, j)))]

    def psi(i, j, k, l):
        return potentials[tuple(sorted((i, j, k, l)))]

    out = []
    for i, k in COMPONENTS:
        total = -2 * nu * trace * phi(i, k)
        for j in range(3):
            for l in range(3):
                total = total + psi(i, j, k, l) * e[(j, l)]
        for l in range(3):
            total = total - 2 * (1 - nu) * (e[(i, l)] * phi(l, k) + e[(k, l)] * phi(l, i))
        out.append(total / (8 * np.pi * (1 - nu)))
    return np.stack(out, axis=-1)


def stress_from_strain(strain, poisson, young=1.0):
    """Isotropic Hooke's law on ``(..., 6)`` tensor-shear strains."""
    factor = young / (1 + poisson)
    trace = strain[..., 0] + strain[..., 1] + strain[..., 2]
    stress = factor * strain
    stress[..., :3] += (factor * poisson / (1 - 2 * poisson) * trace)[..., None]
    return stress


def strain_from_stress(stress, poisson, young=1.0):
    """Inverse of :func:`stress_from_strain`."""
    trace = stress[..., 0] + stress[..., 1] + stress[..., 2]
    strain = (1 + poisson) / young * stress
    strain[..., :3] -= (poisson / young * trace)[..., None]
    return strain


def cuboid_potentials(offsets, half, cell=None):
    """Derivatives of the potentials of cuboids at arbitrary offsets (direct corner sums).

    Parameters
    ----------
    offsets : ndarray
        ``(..., 3)`` target minus cuboid centre [m]; no target on a face plane.
    half : array_like
        Half sizes of the cuboids ``(h1, h2, h3)`` [m].
    cell : tuple of float, optional
        Sizes [m] of a target cell centred on each target: average over it (:func:`cell_average_rule`).

    Returns
    -------
    dict
        As :func:`potential_kernels`, arrays of shape ``offsets.shape[:-1]``.
    """
    total = {key: 0.0 for key in KEYS}
    for shift, weight in zip(*cell_average_rule(cell)):
        for corner in np.ndindex(2, 2, 2):
            signs = 1 - 2 * np.array(corner)
            t = [offsets[..., a] + shift[a] + signs[a] * half[a] for a in range(3)]
            sign = weight * np.prod(signs)
            for key, value in _corner_functions(t).items():
                total[key] = total[key] + sign * value
    return total


def strain_at_points(points, centres, eigenstrain, half, poisson, chunk=200_000, cell=None):
    """Strain ``(n, 6)`` at ``points (n, 3)`` of an infinite body from cuboids by direct summation.

    ``centres (N, 3)`` and ``eigenstrain (N, 6)`` give the cuboids and their eigenstrains.
    Exact (to rounding) for points anywhere but on a face plane; it costs ``n N`` kernel
    evaluations, for checks and a few points. With ``cell`` (sizes [m]) the strain is
    averaged over a cell centred on each point (:func:`cell_average_rule`).
    """
    out = np.zeros((len(points), 6))
    per_point = max(1, chunk // max(1, len(centres)))
    for begin in range(0, len(points), per_point):
        block = points[begin:begin + per_point]
        offsets = block[:, None, :] - centres[None, :, :]
        out[begin:begin + per_point] = strain_from_potentials(cuboid_potentials(offsets, half, cell),
                                                              eigenstrain[None], poisson).sum(axis=1)
    return out


def _wrapped(values):
    """Kernel samples at offsets ``-(m-1) .. m-1`` per axis, in DC-FFT wrap-around order on ``2m``."""
    padded = np.pad(values, [(1, 0)] * values.ndim)
    return np.fft.ifftshift(padded)


def _to_components_first(field):
    return np.ascontiguousarray(np.moveaxis(field, -1, 0))


def _stiffness_coefficients(poisson):
    """``{(a, b): {key: weight}}``: the entries ``a <= b`` of ``C : D`` as combinations of the potentials."""
    out = {(a, b): {} for b in range(6) for a in range(b + 1)}
    for key in KEYS:
        unit = {k: float(k == key) for k in KEYS}
        for b in range(6):
            column = stress_from_strain(strain_from_potentials(unit, np.eye(6)[b] / MANDEL[b], poisson), poisson)
            for a in range(b + 1):
                out[(a, b)][key] = float(column[a] * MANDEL[a])
    return out


class HalfSpaceEigenstrain:
    """Strain in a box of cuboids of the half-space caused by eigenstrains in the same box.

    The box is a block of the grid's cuboid lattice (surface cells times layers); the
    kernels span the box only, so memory and time follow the box, not the grid: about
    2 kB per cuboid of the box for the 21 + 21 kernel spectra of the infinite-space and
    mirror terms, plus the surface-traction kernels (6 per layer of the box on a surface
    patch reaching :data:`PATCH_DEPTHS` times the box's bottom depth around it, clipped to
    the grid). The surface displacement (Betti) covers the whole grid.

    Parameters
    ----------
    grid : framework.Grid
        Open grid with layers; the cuboids are ``dx1 x dx2 x dx3``.
    poisson : float
        Poisson ratio of the (homogeneous, isotropic) half-space.
    start : tuple of int
        Index of the box's first cuboid along x1, x2 and the layers.
    shape : tuple of int
        Cuboids of the box along each axis.
    whole_patch : bool
        Make the Boussinesq correction's surface patch the whole grid (a box that moves).
    average : bool
        Give each cuboid the strain averaged over it (a Galerkin operator, by the Gauss rule
        of :data:`AVERAGE_POINTS` per axis) rather than the strain at its centre: the
        operator's spectrum then lies in [0, 1] as the continuous one's does. Applies to the
        infinite-space and mirror terms; the Boussinesq correction (smooth in the box) stays
        sampled at the centres.
    """

    def __init__(self, grid, poisson, start, shape, whole_patch=False, average=True):
        if any(grid.periodic):
            raise ParameterError(f"the half-space eigenstrain operator needs an open grid, got periodic={grid.periodic}")
        if not grid.layers:
            raise ParameterError("grid.layers is 0: eigenstrains live on the subsurface cuboids; give the grid layers")
        limits = (*grid.shape, grid.layers)
        start, shape = tuple(int(s) for s in start), tuple(int(m) for m in shape)
        for axis in range(3):
            if start[axis] < 0 or shape[axis] < 1 or start[axis] + shape[axis] > limits[axis]:
                raise ParameterError(f"box along axis {axis}: cuboids {start[axis]} .. {start[axis] + shape[axis] - 1} "
                                     f"lie outside the grid's 0 .. {limits[axis] - 1}")
        if not isinstance(average, bool):
            raise ParameterError(f"average must be a bool, got {average!r}")
        self.grid, self.poisson, self.start, self.shape = grid, float(poisson), start, shape
        self.spacing = (*grid.spacing, grid.layer_thickness)
        self.average = average
        cell = self.spacing if average else None
        self.depths = grid.x3[start[2]:start[2] + shape[2]]
        self.fft_shape = tuple(2 * m for m in shape)
        faces = [(np.arange(-m, m) + 0.5) * h for m, h in zip(shape, self.spacing)]
        # Each kernel is even or odd in each offset with an even number of odd axes: real spectra.
        self._direct = self._stiffness_spectra(potential_kernel_items(*faces, cell=cell), real=True)
        dz = self.spacing[2]
        mirror_faces = (2 * start[2] + np.arange(2 * shape[2]) + 0.5) * dz
        self._mirror = self._stiffness_spectra(potential_kernel_items(faces[0], faces[1], mirror_faces, cell=cell),
                                               real=False)
        # Flipping the box along x3 (the mirror image's correlation) is, on the spectrum of a real
        # field, a reversal of the other two wavenumbers, a conjugation and a phase in q3.
        q3 = np.arange(shape[2] + 1)
        self._flip_phase = np.exp(-2j * np.pi * q3 * (shape[2] - 1) / self.fft_shape[2])
        # The Boussinesq correction works on a surface patch around the box: the traction the
        # eigenstrains leave decays like 1/r^3, and beyond PATCH_DEPTHS times the box's bottom depth
        # its stress at the box is below ~1e-3 of the correction (which is itself small unless the
        # box is shallow). The patch's cells are the grid's.
        reach = [int(np.ceil(PATCH_DEPTHS * (start[2] + shape[2]) * self.spacing[2] / h)) for h in grid.spacing]
        low = [max(0, start[a] - reach[a]) for a in range(2)]
        high = [min(grid.shape[a], start[a] + shape[a] + reach[a]) for a in range(2)]
        if whole_patch:        # a box that moves over the grid (rolling) keeps the grid as its patch
            low, high = [0, 0], list(grid.shape)
        self.patch = tuple(slice(lo, hi) for lo, hi in zip(low, high))
        self._patch_grid = Grid(shape=(high[0] - low[0], high[1] - low[1]),
                                size=((high[0] - low[0]) * grid.spacing[0], (high[1] - low[1]) * grid.spacing[1]))
        self._traction = self._traction_spectra()
        self._stress = SubsurfaceStress(self._patch_grid, poisson)
        self._surface_stress = None
        self._love = None
        self._phase = None

    def _stiffness_spectra(self, items, real):
        """Spectra of the 21 entries ``a <= b`` of ``C : D`` (unit Young's modulus, Mandel basis).

        ``C : D`` is symmetric (it is ``C : Gamma : C``, Gamma the Green operator), so 21
        spectra carry the 36 products, and a product costs 36 multiply-adds. Each entry is
        a fixed combination of the potentials' derivatives: they are accumulated one
        derivative at a time (21 lattice arrays in memory, not 42), then transformed.
        """
        coefficients = _stiffness_coefficients(self.poisson)
        kernels = {}
        for key, values in items:
            for entry, weights in coefficients.items():
                weight = weights[key]
                if weight == 0.0:
                    continue
                if entry in kernels:
                    kernels[entry] += weight * values
                else:
                    kernels[entry] = weight * values
            del values
        spectra = {}
        for entry in list(kernels):
            spectrum = fft.rfft3(_wrapped(kernels.pop(entry)))
            spectra[entry] = np.ascontiguousarray(spectrum.real) if real else spectrum
        return spectra

    def _traction_spectra(self):
        """Spectra ``(m3, 6, 2 n1, n2 + 1)`` of ``s33`` at the surface (unit modulus) per layer and component."""
        (n1, n2), m3, dz = self._patch_grid.shape, self.shape[2], self.spacing[2]
        faces1 = (np.arange(-n1, n1) + 0.5) * self.spacing[0]
        faces2 = (np.arange(-n2, n2) + 0.5) * self.spacing[1]
        # Target on the surface, sources below: x3 - x3' runs from -(bottom) up to -(top of the box).
        top = self.start[2]
        faces3 = -(top + m3 - np.arange(m3 + 1)) * dz
        if top == 0:
            faces3[-1] = -1e-12 * dz  # the surface itself: s33 is continuous there (traction)
        potentials = potential_kernels(faces1, faces2, faces3)
        nu = self.poisson
        # C : D is symmetric in Mandel's basis, so s33 per unit eigenstrain component c is the c-th
        # stress of a unit e*_33: one column instead of six (Mandel weights squared = CONTRACTION).
        column = stress_from_strain(strain_from_potentials(potentials, np.eye(6)[2], nu), nu) * CONTRACTION
        del potentials
        spectra = np.empty((m3, 6, 2 * n1, n2 + 1), dtype=complex)
        for c in range(6):
            s33 = np.pad(column[..., c], [(1, 0), (1, 0), (0, 0)])   # (2n1-1, 2n2-1, m3), layers bottom-up
            s33 = np.fft.ifftshift(s33, axes=(0, 1))[:, :, ::-1]   # layers top-down, wrap-around order
            spectra[:, c] = fft.rfft2(np.ascontiguousarray(np.moveaxis(s33, -1, 0)))
        return spectra

    def _check(self, eigenstrain):
        expected = (*self.shape, 6)
        if np.shape(eigenstrain) != expected:
            raise ShapeError(f"eigenstrain has shape {np.shape(eigenstrain)}, the operator's box is {expected}")
        return np.asarray(eigenstrain, dtype=float)

    def _shift(self):
        """Phase ``exp(-2 pi i k . f / N)`` of the footprint's offset ``f`` in the patch's padded arrays.

        Built when the box moves, not at every product (its conjugate shifts the other way).
        """
        f1, f2 = (s.start for s in self._footprint)
        if self._phase is None or self._phase[0] != (f1, f2):
            big1, big2 = self._stress._convolution.fft_shape
            k1 = np.fft.fftfreq(big1) * f1
            k2 = np.arange(big2 // 2 + 1) / big2 * f2
            self._phase = ((f1, f2), np.exp(-2j * np.pi * (k1[:, None] + k2[None, :])))
        return self._phase[1]

    def surface_traction(self, eigenstrain):
        """Pressure ``2 s33(x1, x2, 0)`` [Pa per unit Young's modulus] over the surface patch ``patch``.

        The normal stress that the eigenstrains and their mirror image leave on the
        surface, as the compressive pressure that the Boussinesq correction applies.
        """
        eigenstrain = self._check(eigenstrain)
        n1, n2 = self._patch_grid.shape
        big1, big2 = self._stress._convolution.fft_shape
        layers = np.transpose(eigenstrain, (2, 3, 0, 1))                       # (m3, 6, m1, m2)
        # The layers are zero outside the box's footprint: transform its m1 rows only along x2, then
        # every column along x1 (the patch's full 2-D transforms spent most of a product on zeros);
        # the footprint's place in the patch is one phase on the sum. Every layer and component at once.
        rows = scipy.fft.rfft(layers, n=big2, axis=-1, workers=fft.THREADS)
        spectra = scipy.fft.fft(rows, n=big1, axis=-2, workers=fft.THREADS, overwrite_x=True)
        total = np.einsum("lcij,lcij->ij", self._traction, spectra) * self._shift()
        return 2.0 * fft.irfft2(total, (big1, big2))[:n1, :n2]

    def _correction(self, pressure):
        """Stress ``(m1, m2, m3, 6)`` of the Boussinesq field of ``pressure`` (on the patch) in the box."""
        if self._love is None:   # Love's kernels at the box's depths, stacked once
            self._love = np.stack([self._stress._kernel_spectrum(float(depth)) * _PHASE for depth in self.depths])
        convolution = self._stress._convolution
        m1, m2 = self.shape[:2]
        # Shifted so that the footprint starts at the origin; only its m1 rows go on to the x2 transform.
        spectrum = convolution.transform(pressure) * np.conj(self._shift())
        columns = scipy.fft.ifft(self._love * spectrum, axis=-2, workers=fft.THREADS, overwrite_x=True)[..., :m1, :]
        full = scipy.fft.irfft(columns, n=convolution.fft_shape[1], axis=-1, workers=fft.THREADS)
        return np.transpose(full[..., :m2], (2, 3, 0, 1))

    def surface_displacement(self, eigenstrain):
        """Normal surface displacement ``u3`` [m per unit strain... i.e. m] over the grid, positive into the solid.

        Betti's reciprocal theorem with Love's pressure-to-stress coefficients
        (:meth:`SubsurfaceStress.transpose`); it does not depend on the modulus.
        """
        eigenstrain = self._check(eigenstrain)
        n1, n2 = self.grid.shape
        if self._surface_stress is None:
            self._surface_stress = SubsurfaceStress(self.grid, self.poisson)
        fields = np.zeros((n1, n2, self.shape[2], 6))
        fields[self.box[:2]] = eigenstrain * CONTRACTION
        return self.spacing[2] * self._surface_stress.transpose(fields, self.depths)

    @property
    def _footprint(self):
        """Slices of the box's surface cells in the patch's arrays."""
        return tuple(slice(s - p.start, s - p.start + m) for s, p, m in zip(self.start, self.patch, self.shape))

    @property
    def box(self):
        """Slices of the box in the grid's ``(n1, n2, layers)`` arrays."""
        return tuple(slice(s, s + m) for s, m in zip(self.start, self.shape))

    def move(self, cells):
        """Move the box by ``cells = (c1, c2)`` whole surface cells (the material moved under a rolling body).

        The kernels do not depend on where the box lies on the grid, only the footprint
        does; the surface patch must be the whole grid (``whole_patch=True``).
        """
        if not any(cells):
            return
        if self.patch != (slice(0, self.grid.shape[0]), slice(0, self.grid.shape[1])):
            raise ParameterError("move: this operator's surface patch is not the whole grid (build it with "
                                 "whole_patch=True to move it)")
        start = (self.start[0] + cells[0], self.start[1] + cells[1], self.start[2])
        for axis in range(2):
            if start[axis] < 0 or start[axis] + self.shape[axis] > self.grid.shape[axis]:
                raise ParameterError(f"move: the box would leave the grid along x{axis + 1} (cuboids {start[axis]} .. "
                                     f"{start[axis] + self.shape[axis] - 1} of 0 .. {self.grid.shape[axis] - 1})")
        self.start = start

    def strain(self, eigenstrain):
        """Total strain ``(m1, m2, m3, 6)`` (tensor shears) in the box from the eigenstrain ``(m1, m2, m3, 6)``."""
        eigenstrain = self._check(eigenstrain)
        m1, m2, m3 = self.shape
        padded = np.zeros((6, *self.fft_shape))
        padded[:, :m1, :m2, :m3] = _to_components_first(eigenstrain * MANDEL)
        direct = fft.rfft3(padded)
        reversed_ = np.roll(direct[:, ::-1, ::-1, :], 1, axis=(1, 2))
        mirror = np.conj(reversed_) * self._flip_phase * MIRROR[:, None, None, None]
        stress = np.zeros_like(direct)
        term = np.empty_like(direct[0])         # one work array: no temporaries in the 72 products
        for spectra, source in ((self._direct, direct), (self._mirror, mirror)):
            for (a, b), kernel in spectra.items():
                stress[a] += np.multiply(kernel, source[b], out=term)
                if a != b:
                    stress[b] += np.multiply(kernel, source[a], out=term)
        infinite = fft.irfft3(stress, self.fft_shape)[:, :m1, :m2, :m3]
        infinite = np.moveaxis(infinite, 0, -1) / MANDEL
        pressure = self.surface_traction(eigenstrain)
        correction = self._correction(pressure)
        return strain_from_stress(infinite + correction, self.poisson)

    def strain_at(self, points, eigenstrain, average=False):
        """Total strain ``(n, 6)`` at arbitrary points ``(n, 3)`` [m] of the half-space, by direct sums.

        The same three terms as :meth:`strain`, each summed over the box's loaded
        cuboids (and, for the Boussinesq term, the surface cells) without FFTs, so the
        points may lie anywhere below the surface but not on a cuboid face. With
        ``average=True`` the first two terms are averaged over a cuboid centred on each
        point, as the operator's (``average=True``) are.
        """
        from .kernels import subsurface_stress
        eigenstrain = self._check(eigenstrain)
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        loaded = np.nonzero(np.any(eigenstrain != 0.0, axis=-1))
        values = eigenstrain[loaded]
        axes = (self.grid.x1[self.box[0]], self.grid.x2[self.box[1]], self.depths)
        centres = np.stack([axis[index] for axis, index in zip(axes, loaded)], axis=-1)
        half = 0.5 * np.asarray(self.spacing)
        mirrored = centres * [1, 1, -1]
        cell = self.spacing if average else None
        strain = (strain_at_points(points, centres, values, half, self.poisson, cell=cell)
                  + strain_at_points(points, mirrored, values * MIRROR, half, self.poisson, cell=cell))
        pressure = self.surface_traction(eigenstrain)
        x1, x2 = (c[self.patch] for c in self.grid.coordinates())
        dx1, dx2 = self.grid.spacing
        stress = np.empty((len(points), 6))
        for i, (y1, y2, y3) in enumerate(points):
            stress[i] = pressure.ravel() @ subsurface_stress((y1 - x1).ravel(), (y2 - x2).ravel(), y3,
                                                             half1=dx1 / 2, half2=dx2 / 2, poisson=self.poisson)
        return strain + strain_from_stress(stress, self.poisson)

