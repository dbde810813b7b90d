"""Eshelby's equivalent inclusion method on the cuboid lattice (THEORY.md sec. 8).

Each inhomogeneity (stiffness ``C_I``) is replaced by matrix material (``C_M``) with an
eigenstrain ``e*`` such that the stress is the same in every cuboid of the inhomogeneity
(Eshelby 1957; Mura 1987 sec. 22; Jacq et al. 2002; Koumi et al. 2014)::

    C_I : (e0 + D[e*]) = C_M : (e0 + D[e*] - e*)

``e0`` the strain without the inhomogeneities, ``D`` the half-space eigenstrain operator
(:class:`~framework.operators.eigenstrain.HalfSpaceEigenstrain`). Written as
``(C_I - C_M) D[e*] + C_M e* = (C_M - C_I) e0`` it is solved by GMRES (the operator is not
symmetric), left-preconditioned per inhomogeneity by ``[(C_I - C_M) S + C_M]^-1`` with
``S`` the strain a cuboid's own eigenstrain causes in it (as the operator takes it: averaged over
the cuboid or at its centre): for an isolated cuboid
this is the exact local solve, and it makes the iteration count nearly independent of the
resolution and of the stiffness contrast.

Strains are ``(..., 6)`` arrays in Voigt order xx yy zz yz xz xy with tensor shears;
internally the unknowns are in Mandel's basis (shears times sqrt 2), where the 6x6
matrices of the stiffness tensors are symmetric.
"""
from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_triangular

from ..errors import ConvergenceError, ParameterError, ShapeError
from ..materials import isotropic_tensor
from ..operators._box_loops import fourier_kernels, loops
from ..operators.eigenstrain import COMPONENTS, MANDEL, cuboid_potentials, strain_from_potentials

#: GMRES restart length: the Krylov basis holds this many vectors of 6 values per cuboid of the
#: inhomogeneities (the preconditioned system converges in 5 to 30 iterations).
RESTART = 30

#: Directions of earlier solves the Krylov solver keeps (:class:`RecycledSpace`), and the memory they
#: may take [bytes] (three values per unknown each: direction, strain, image; a large box keeps fewer).
RECYCLED = 400
RECYCLED_BYTES = 128 * 2**20
#: The recycled space forgets how much a direction was used by this factor per use.
USE_MEMORY = 0.98

#: Memory the GMRES basis (and, when recycling, its directions and their strains on the cuboids) may take
#: [bytes]: a large box restarts sooner (a 128^3 box's basis, 16 vectors of 53 MB, was a quarter of its 3.3 GiB).
GMRES_BYTES = 384 * 2**20

#: Memory the directions' strains on the whole box may take [bytes]: a larger box carries its residual by the
#: Arnoldi relation and computes its solution's strain by one more product at the end instead.
IMAGES_BYTES = 768 * 2**20

#: Memory the Fourier preconditioner's per-wavenumber matrices and, on the folded lattice, its transforms' buffers
#: may take [bytes] (else each cuboid is solved alone): a sphere filling a 128^3 box, on the 136^3 folded lattice
#: (360 MiB), took 13 GMRES iterations against 17 cuboid by cuboid, 80 s against 83, and 3.24 GiB against 2.86.
FOURIER_BYTES = 256 * 2**20
#: ... or, on a larger box, this many bytes per box cuboid: the per-wavenumber matrices on the box's own lattice, both
#: the inverse and the operator of its inner solve, take 75-103 bytes a box cuboid (a run about 1.5 KB), and without
#: them each cuboid is solved alone: 300 glass spheres at 8 cuboids per radius (box 7.75 M cuboids, matrices 631 MB)
#: took 32 products a step cuboid by cuboid (542 s a step), against 7-8 for 10 to 300 bodies at 4 cuboids per radius.
FOURIER_CUBOID_BYTES = 96

#: Bodies the Fourier preconditioner fills the box with, at their own stiffness, at most: one. It fills the box with
#: the bodies' material, matrix between them included: right for one body (no unknowns outside it), ever more
#: wrong for several (glass spheres at 10 % in a polymer, to 1e-7, 4 cuboids per radius: 2 / 4 / 8 / 12 / 16 bodies
#: 20 / 17 / 18 / 27 / 37 iterations at their own contrast, 15 / 15 / 16 / 16 / 16 at DISPERSION_CONTRAST; 40 bodies
#: 79, 60 none in 500 at their own; 12 beads at 20 % under a contact did not converge in 100 couplings). More
#: bodies fill it with a medium of :data:`DISPERSION_CONTRAST` of their contrast with the matrix instead.
FOURIER_BODIES = 1

#: The share of the bodies' contrast with the matrix (``C_I - C_M``) the Fourier preconditioner takes for more
#: than :data:`FOURIER_BODIES` bodies: the same dispersions took 16 iterations at 0.3 for 30, 60 and 100 bodies
#: (17 at 0.1), against 28 cuboid by cuboid; 15-16 for 2 to 16 bodies.
DISPERSION_CONTRAST = 0.3

#: The relative residual to which the Fourier preconditioner solves the cuboids' system of its filled periodic
#: cell (:meth:`EquivalentInclusionProblem._inner_solve`), and its iterations at most. A glass sphere 20 cuboids
#: across in a polymer (bench/rolling_inclusion.py's), to 1e-7 from nothing: 22 GMRES iterations with the cell's
#: inverse alone, 10 / 8 / 7 / 7 with the cell's system solved to 0.3 / 0.1 / 0.03 / 0.01; that bench's rolling
#: steps 9.0 / 7.4 / 7.4 / 7.25 products, 0.61 / 0.57 / 0.58 / 0.63 s (4.9 / 7.5 / 11 / 14 transforms of the cell
#: a solve); 100 glass spheres at 4 cuboids per radius (bench/dispersion.py) 7.8 and 7.4 products a step at 0.1
#: and 0.01, 5.7 and 6.6 s.
INNER_TOLERANCE = 0.1
INNER_ITERATIONS = 20
#: The inner solve is used on the box's own lattice (the cell as large as the box: an inner iteration costs a tenth
#: of a product or less), and on the folded one (bodies filling their box: the cell nearly as large as a product's,
#: the images close) where :func:`filled_cell_estimate` (the filled cell's inverse alone on a sphere's uniform modes)
#: reaches this: a contrast of about 5.5 (a stiff body) or 0.15 (a soft one). A sphere 20 cuboids across in a 30^3
#: box, to 1e-8, own lattice: contrast 3 8 -> 6 iterations (0.30 -> 0.24 s), 10 13 -> 7, 31 23 -> 8 (0.68 -> 0.36
#: s). Filling its box, folded lattice, to 1e-10: 32^3, contrast 3 12 -> 11 (0.45 -> 0.48 s), 10 22 -> 13 (0.81 ->
#: 1.15 s), 31 62 -> 17 (3.1 -> 3.5 s); carbide in steel on 64^3 (estimate 1.3) 12 -> 11 but 4.2 -> 5.7-5.9 s.
INNER_FROM = 2.0
#: Memory the inner solve's vectors may take [bytes] (two per iteration, 8 bytes per unknown).
INNER_BYTES = 256 * 2**20

#: Cuboids of matrix between the bodies' periodic images on the box's own lattice, along every axis, for the
#: Fourier preconditioner to work there (:class:`FourierPreconditioner`, ``"own"``): a gap of 5 cost a carbide
#: sphere 40 cuboids across one iteration in 12, one of 3.6 a small glass sphere 10 % more in a rolling run.
#: Elsewhere it works on the box grown by :data:`~framework.operators.eigenstrain.FOLDED_GAP` (``"folded"``).
OWN_LATTICE_GAP = 6


#: Whether the Fourier preconditioner's cell takes the kernels' symbol with the eigenvalues of ``D`` (in the matrix's
#: energy) clipped to [0, 1] (:func:`admissible_symbol`), the continuous Green operator's range. The kernels of a box
#: on a periodic lattice are its own, cut off beyond the box: their symbol overshoots, from -0.027 to 1.102 on a 16^3
#: box's padded lattice and -0.055 to 1.082 on its folded one (-0.010 to 1.023 on its own lattice). The cell's
#: operator ``(C_I - C_M) D + C_M`` is then singular at some wavenumber for a contrast above about 1 / 0.05 = 20 or
#: below 1 - 1 / 1.08 = 0.07 (glass in a polymer: 25 in shear), and its system on the bodies indefinite (Ritz values
#: down to -5.2): the inner solve crawled, and had been moved from the folded lattice to the padded one. Clipped, a
#: sphere filling a 16^3 box, to 1e-10, on the folded lattice: glass in a polymer 200 -> 68 transforms of the cell (12
#: GMRES iterations either way), a body 0.05 times as stiff as steel 152 -> 74; carbide in steel (the inverse alone)
#: 11 iterations either way. The folded lattice serves the inner solve again, on fewer points than the padded one:
#: glass filling a 24^3, 32^3, 48^3 and 64^3 box 0.41 -> 0.21, 0.91 -> 0.52, 6.1 -> 3.0 and 11.3 -> 6.9 s (one more
#: iteration, three at 64^3).
CLIP_SYMBOL = True


def periodic_cell(own_shape, cells):
    """The Fourier preconditioner's periodic cell for bodies on the cuboids ``cells`` (``np.nonzero`` of an
    indicator) of a box whose own lattice (half its padded one) is ``own_shape``: ``"own"`` where their periodic
    images stay :data:`OWN_LATTICE_GAP` cuboids apart on it, else ``"folded"`` (the box grown by a gap; the padded
    lattice where that is no smaller)."""
    own = len(cells[0]) > 0 and all(n - (np.ptp(c) + 1) >= OWN_LATTICE_GAP for n, c in zip(own_shape, cells))
    return "own" if own else "folded"


def preconditioner_cell(lattices, cells, stiffnesses, young, poisson, preconditioner="auto", lattice=None):
    """How :class:`EquivalentInclusionProblem` preconditions bodies on the cuboids ``cells`` (``np.nonzero`` of an
    indicator) of a box, of the stiffnesses ``stiffnesses`` (Mandel matrices) in a matrix of Young's modulus ``young``
    [Pa] and Poisson ratio ``poisson``: ``(lattice, preconditioner, inner)``, the Fourier preconditioner's periodic
    cell, ``"fourier"`` or ``"local"``, and whether the cell's system is solved on the bodies' cuboids.

    ``lattices`` is the box's operator or, before it is built, its
    :class:`~framework.operators.eigenstrain.BoxLattices`: the operator builds the folded lattice's kernels only where
    this chooses that lattice for the Fourier preconditioner (not for bodies of several materials, preconditioned
    cuboid by cuboid). ``preconditioner`` and ``lattice`` as the problem takes them."""
    chosen = periodic_cell(lattices.own_shape, cells)
    if chosen == "folded" and np.prod(lattices.folded_shape) >= np.prod(lattices.fft_shape):
        chosen = "padded"
    if lattice is not None:
        chosen = lattice
    if preconditioner == "auto":    # the Fourier one fills the box with one material: all must share it
        same = all(np.abs(c - stiffnesses[0]).max() <= 1e-12 * np.abs(stiffnesses[0]).max() for c in stiffnesses)
        preconditioner = "fourier" if same and FourierPreconditioner.fits(lattices, stiffnesses, chosen) else "local"
    # on the box's own lattice, or where the filled cell's inverse alone leaves a body's smooth modes far from 1
    # (INNER_FROM), the Fourier preconditioner solves the bodies' system in that cell on their cuboids (the cell's
    # operator, at their own contrast, kept beside the inverse); a nonlinear map: the Krylov solver keeps its
    # directions
    estimate = filled_cell_estimate(stiffnesses[0], young, poisson, 200)[0] \
        if preconditioner == "fourier" and len(cells[0]) > 0 else np.zeros(1)
    inner = bool((estimate.max() >= INNER_FROM or (estimate.max() > 0.0 and chosen == "own"))
                 and FourierPreconditioner.fits(lattices, stiffnesses, chosen, forward=True))
    return chosen, preconditioner, inner


def mandel_matrix(tensor):
    """6x6 Mandel matrix of a stiffness tensor ``(3, 3, 3, 3)``."""
    out = np.empty((6, 6))
    for a, (i, j) in enumerate(COMPONENTS):
        for b, (k, l) in enumerate(COMPONENTS):
            out[a, b] = tensor[i, j, k, l] * MANDEL[a] * MANDEL[b]
    return out


def isotropic_mandel(young, poisson):
    """6x6 Mandel matrix of an isotropic stiffness."""
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    mu = young / (2 * (1 + poisson))
    out = 2 * mu * np.eye(6)
    out[:3, :3] += lam
    return out


def admissible_symbol(kernel, factor):
    """The kernels ``K(q)`` ``(..., 6, 6)`` of ``C : D`` (unit modulus, Mandel) with the eigenvalues of ``D`` in the
    matrix's energy (``L^-1 K L^-T``, ``factor`` ``L`` the Cholesky factor of the unit stiffness) clipped to [0, 1],
    the range of the continuous Green operator's (:data:`CLIP_SYMBOL`)."""
    inverse = np.linalg.inv(factor)
    symbol = np.einsum("ab,...bc,dc->...ad", inverse, kernel, inverse)
    values, vectors = np.linalg.eigh(0.5 * (symbol + np.swapaxes(symbol, -1, -2)))
    symbol = np.einsum("...ab,...b,...cb->...ac", vectors, np.clip(values, 0.0, 1.0), vectors)
    return np.einsum("ab,...bc,dc->...ad", factor, symbol, factor)


def filled_cell_estimate(stiffness, young, poisson, directions=1000):
    """The eigenvalues (sorted) that the filled cell's inverse alone leaves on a sphere's uniform modes: those of
    ``[(C_I - C_M) S + C_M] <[(C_I - C_M) D(n) + C_M]^-1>`` (Mandel), ``C_I`` the body's ``stiffness`` (Mandel),
    ``C_M`` the isotropic matrix's (``young`` [Pa], ``poisson``), ``D(n)`` the strain of a plane-wave eigenstrain
    along ``n`` (``sym(n (x) N C_M e* n)``, ``N = (n . C_M . n)^-1``; Mura 1987, sec. 3), ``<.>`` the average
    over ``directions`` unit vectors (a Fibonacci sphere) and ``S = <D(n)>`` Eshelby's tensor of the sphere.

    The box filled with the body's material is exact for a plane wave; on a smooth field confined to the body it
    applies the average of the inverse where the body needs the inverse of the average. For glass in a polymer
    (contrast 31) 6.0 and 8.5 (the operator's largest eigenvalue, 20 cuboids across: 8.55), carbide in steel
    (2.9) 1.1 and 1.35; soft bodies too (contrast 0.01: 25 and 30). Returns ``(eigenvalues, S)``.
    """
    k = np.arange(directions) + 0.5
    polar, azimuth = np.arccos(1 - 2 * k / directions), np.pi * (1 + 5 ** 0.5) * k
    n = np.stack([np.cos(azimuth) * np.sin(polar), np.sin(azimuth) * np.sin(polar), np.cos(polar)], axis=1)
    tensor = isotropic_tensor(young, poisson)
    inverse = np.linalg.inv(np.einsum("mi,ijkl,ml->mjk", n, tensor, n))
    green = 0.25 * (np.einsum("mi,mjk,ml->mijkl", n, inverse, n) + np.einsum("mj,mik,ml->mijkl", n, inverse, n)
                    + np.einsum("mi,mjl,mk->mijkl", n, inverse, n) + np.einsum("mj,mil,mk->mijkl", n, inverse, n))
    rows = np.array(COMPONENTS)
    mandel = green[:, rows[:, 0], rows[:, 1]][:, :, rows[:, 0], rows[:, 1]] * np.outer(MANDEL, MANDEL)
    matrix = mandel_matrix(tensor)
    plane = mandel @ matrix                                         # D(n), (directions, 6, 6)
    contrast = np.asarray(stiffness) - matrix
    eshelby = plane.mean(axis=0)
    average = np.linalg.inv(contrast @ plane + matrix).mean(axis=0)
    return np.sort(np.linalg.eigvals((contrast @ eshelby + matrix) @ average).real), eshelby


def cuboid_self_strain(spacing, poisson, average=False):
    """Mandel matrix of the strain at a cuboid's centre (or its average over the cuboid, ``average``)
    per unit eigenstrain of the cuboid (infinite body)."""
    spacing = np.asarray(spacing, dtype=float)
    potentials = cuboid_potentials(np.zeros(3), 0.5 * spacing, spacing if average else None)
    columns = [strain_from_potentials(potentials, np.eye(6)[c] / MANDEL[c], poisson) * MANDEL for c in range(6)]
    return np.array(columns).T


class RecycledSpace:
    """Directions ``u`` of earlier Krylov solves, their strains ``D[u]`` and their images ``A u``.

    A sequence of solves with similar right-hand sides (the couplings of a step, the steps of a
    rolling run, where the body moves by one cell per step) spends most of its products finding
    again what the last solves found. Kept, the directions deflate the next solve's preconditioner
    (Parks et al. 2006, "Recycling Krylov subspaces for sequences of linear systems", SIAM J. Sci.
    Comput. 28): the least-squares part of a residual in their images is solved at once. The
    images are kept orthonormal as directions are added (Gram-Schmidt twice; the directions and
    strains follow the same combinations), so one can be dropped without touching the
    others; a new matrix modulus (a viscoelastic matrix's changes with the step) recomputes them
    from the strains. When the box has moved since a direction was found, its image is slightly
    off (the surface patch sees the box elsewhere): the preconditioner stays good, and the
    solution is exact anyway (each new direction's product is). :data:`RECYCLED` directions are
    kept (fewer when they would take more than :data:`RECYCLED_BYTES`); when full, a new one
    replaces the one the last residuals used least (dropping the oldest lost the gain: the first
    steps' directions keep serving the later ones).
    """

    def __init__(self, size):
        self.size = size
        self.kept = max(0, min(RECYCLED, RECYCLED_BYTES // max(1, 24 * size)))
        self.clear()

    def clear(self):
        self._store = np.empty((3, self.kept, self.size))      # directions, strains, images
        self.use = np.zeros(self.kept)                            # how much the residuals used each, lately
        self.count, self.key = 0, None

    def __len__(self):
        return self.count

    @property
    def directions(self):
        return self._store[0, :self.count]

    @property
    def strains(self):
        return self._store[1, :self.count]

    @property
    def images(self):
        return self._store[2, :self.count]

    def _append(self, triples):
        """Add triples ``(b, 3, size)`` (direction, strain, image), each image orthogonalised against the kept ones
        and the block's earlier ones (twice) and normalised; when full, the least used make room (the others
        stay orthonormal).

        The block is projected on the kept images at once (two matrix products read the store once, where one
        triple at a time read it eight times: 17 directions a step on the rolling bench's 220 kept, 0.63 ->
        0.18 s on a busy core); within the block one at a time.
        """
        count = self.count
        lengths = np.sqrt(np.einsum("ij,ij->i", triples[:, 2], triples[:, 2]))
        for _ in range(2):
            if count:
                weights = triples[:, 2] @ self.images.T
                for t in range(3):
                    triples[:, t] -= weights @ self._store[t, :count]
        accepted = 0            # the block's independent triples, normalised, moved to its front
        for triple, length in zip(triples, lengths):
            block = triples[:accepted]
            for _ in range(2 if accepted else 0):
                weights = block[:, 2] @ triple[2]
                for t in range(3):
                    triple[t] -= weights @ block[:, t]
            rest = np.linalg.norm(triple[2])
            if np.isfinite(rest) and rest > 1e-10 * max(length, 1e-300):     # else dependent: nothing new
                triples[accepted] = triple / rest
                accepted += 1
        for triple in triples[:accepted]:
            if self.count < self.kept:
                slot = self.count
                self.count += 1
            else:       # full: the direction the last residuals used least makes room
                slot = int(np.argmin(self.use))
            self._store[:, slot] = triple
            self.use[slot] = np.inf if self.count < self.kept else self.use.max()

    def add(self, directions, strains, images_of, key):
        """Keep these directions ``(N,)`` and their strains ``D[u]`` on the cuboids (Mandel, ``(N/6, 6)``);
        ``images_of(u, D[u])`` gives ``A u`` for the operator ``key`` names (its matrix modulus)."""
        if not self.kept:
            return
        self._refresh(images_of, key)
        if len(directions):
            self._append(np.array([[np.ravel(u), np.ravel(d), images_of(u, d)] for u, d in zip(directions, strains)],
                                  dtype=float))

    def _refresh(self, images_of, key):
        """Recompute the images for another operator (from the strains) and orthonormalise them anew."""
        # a preconditioner: images for a modulus within 1e-9 of the key's are as good (the steps of a
        # run at one time step give moduli equal but for rounding)
        if self.count and (self.key is None or abs(key - self.key) > 1e-9 * abs(self.key)):
            triples = np.array([(u, d, images_of(u, d)) for u, d in zip(self.directions, self.strains)])
            self.count = 0
            self._append(triples)
        self.key = key

    def preconditioner(self, images_of, key):
        """``(U, C)`` with ``C = A U`` orthonormal rows, for the operator ``key`` names, or None when empty."""
        self._refresh(images_of, key)
        if not self.count:
            return None
        return self.directions, self.images

    def used(self, weights):
        """Record the share of a residual along each kept image (``weights``, its coefficients)."""
        share = np.square(weights) / max(float(np.square(weights).sum()), 1e-300)
        self.use[:self.count] = USE_MEMORY * np.where(np.isinf(self.use[:self.count]), 0.0, self.use[:self.count]) + share

    def snapshot(self):
        """The kept triples and the operator's key, as arrays."""
        return {"directions": self.directions.copy(), "strains": self.strains.copy(), "images": self.images.copy(),
                "key": np.array(np.nan if self.key is None else self.key), "use": self.use[:self.count].copy()}

    def restore(self, snapshot):
        """Continue from :meth:`snapshot`'s arrays, bit for bit."""
        self.clear()
        count = len(snapshot["directions"])
        self._store[0, :count], self._store[1, :count] = snapshot["directions"], snapshot["strains"]
        self._store[2, :count] = snapshot["images"]
        key = float(snapshot["key"])
        self.use[:count] = snapshot["use"]
        self.count, self.key = count, None if np.isnan(key) else key


class FourierPreconditioner:
    """Approximate inverse of the equivalent-inclusion operator: the padded box taken as one periodic cell
    filled with the inhomogeneity.

    Filled so, the operator ``(C_I - C_M) D + C_M`` would be a convolution, diagonal in Fourier space:
    a 6 x 6 system per wavenumber, ``(C_I - C_M) C_bar^-1 K(q) + C_M`` with ``K(q)`` the spectra of the
    infinite-space term of ``C : D`` (:meth:`HalfSpaceEigenstrain.infinite_spectra`, unit modulus)
    (the idea of Moulinec & Suquet 1998 and of the FFT-based solvers of composites, here as a
    preconditioner). In the inhomogeneities' interior it is nearly the inverse (half the spectrum of
    the preconditioned operator within 1e-2 of 1); the cuboids next to the matrix spread the rest over
    [1, 5], against [0.13, 1.95] with each cuboid solved alone: GMRES needs about half the products
    (glass in a polymer, 20 cuboids across: 26 against 47 for 1e-10). It needs one material in all the
    inhomogeneities (bodies of several stiffnesses, or one anisotropic material turned differently,
    are preconditioned cuboid by cuboid: with a stiff and a soft body sharing a mean contrast the
    iteration stalled). The matrices (36 values per wavenumber, a quarter of the wavenumbers for
    isotropic materials), with the transforms' buffers on the folded lattice, must fit in
    :data:`FOURIER_BYTES` (or :data:`FOURIER_CUBOID_BYTES` a box cuboid), else each cuboid is solved alone.

    ``lattice``, the periodic cell (:meth:`~framework.operators.eigenstrain.HalfSpaceEigenstrain.lattice_shape`,
    the kernels folded onto it): ``"own"``, half the padded lattice along each axis, eight times fewer
    points to transform and to store. Where the box leaves matrix cuboids around the inhomogeneities (a
    margin), it preconditions as well: one GMRES iteration more or none (a carbide sphere 40 cuboids
    across, 1 and 3 cuboids of margin: 12 and 11 iterations against 11 and 10; the rolling bench's glass
    sphere: the same counts), each iteration 25-30 % cheaper. Where the bodies' periodic images come close
    it does worse (a sphere filling a 64^3 box, images touching: 17 against 11), so
    :class:`EquivalentInclusionProblem` uses it only where they stay :data:`OWN_LATTICE_GAP` cuboids apart,
    and elsewhere ``"folded"``, the box grown by :data:`~framework.operators.eigenstrain.FOLDED_GAP` cuboids
    (a sphere filling a 64^3 box: 72^3 points instead of 128^3, 12 iterations against 11).

    The inverse alone leaves a stiff (or soft) body's smooth modes far from 1 (:func:`filled_cell_estimate`): on
    the own lattice, and on the folded one where that estimate reaches :data:`INNER_FROM`,
    :class:`EquivalentInclusionProblem` keeps the cell's operator too (``forward``, at the bodies' own contrast) and
    solves the bodies' system in the cell on their cuboids (:meth:`EquivalentInclusionProblem._inner_solve`).
    """

    def __init__(self, operator, contrast, matrix, lattice="padded", forward=None):
        self.operator, self.lattice = operator, lattice
        direct, (first, second), parities = operator.infinite_spectra(lattice)
        unit = isotropic_mandel(1.0, operator.poisson)
        left, factor = contrast @ np.linalg.inv(unit), np.linalg.cholesky(unit)
        same = forward is not None and np.array_equal(forward, contrast)
        forward_left = None if forward is None or same else forward @ np.linalg.inv(unit)
        n1, n2, n3 = operator.lattice_shape(lattice)
        # Reflected along x1 or x2, K(q) changes the signs of the components odd along that axis; when the
        # contrast and the matrix keep them (isotropic, or orthotropic along the axes), so do the inverses,
        # and a quarter of them is stored.
        reflections = [np.diag(p) for p in parities]
        symmetric = all(np.allclose(r @ c @ r, c, rtol=0.0, atol=1e-12 * np.abs(c).max())
                        for r in reflections for c in (contrast, matrix) + (() if forward is None else (forward,)))
        rows, columns = ((np.arange(n1 // 2 + 1), np.arange(n2 // 2 + 1)) if symmetric
                         else (np.arange(n1), np.arange(n2)))
        self.parities = parities if symmetric else (np.ones(6), np.ones(6))
        self.matrices = np.empty((len(rows), len(columns), n3 // 2 + 1, 6, 6))
        self.forward = None if forward is None else np.empty_like(self.matrices)
        for row in rows:        # a row at a time: no second array of the matrices' size
            kernel = fourier_kernels(direct, first, second, *parities, n1, n2, rows=[row], columns=columns)[0]
            if CLIP_SYMBOL:
                kernel = admissible_symbol(kernel, factor)
            matrices = np.einsum("ac,...cb->...ab", left, kernel) + matrix
            if forward is not None:
                self.forward[row] = matrices if same else np.einsum("ac,...cb->...ab", forward_left, kernel) + matrix
            self.matrices[row] = np.linalg.inv(matrices)

    @staticmethod
    def fits(operator, stiffnesses, lattice="padded", forward=False):
        """Whether the matrices for these inhomogeneities' stiffnesses (Mandel), twice as many with ``forward``, and
        what the transforms on their lattice add, take at most :data:`FOURIER_BYTES`, or :data:`FOURIER_CUBOID_BYTES` per
        box cuboid where that is more."""
        n1, n2, n3 = operator.lattice_shape(lattice)
        isotropic = all(np.allclose(np.diag(p) @ c @ np.diag(p), c, rtol=0.0, atol=1e-12 * np.abs(c).max())
                        for p in operator.kernel_parities for c in stiffnesses)
        rows, columns = (n1 // 2 + 1, n2 // 2 + 1) if isotropic else (n1, n2)
        # the transforms on the own or folded lattice take the product's buffers: what they add counts (none, as
        # those lattices are no larger; the folded one's had counted on their own, a 128^3 box's 272 MiB)
        transforms = operator.transform_bytes(lattice) if lattice != "padded" else 0
        limit = max(FOURIER_BYTES, FOURIER_CUBOID_BYTES * int(np.prod(operator.shape)))
        return rows * columns * (n3 // 2 + 1) * 36 * 8 * (2 if forward else 1) + transforms <= limit

    def __call__(self, field):
        """The preconditioned box field of a box field ``(m1, m2, m3, 6)`` (Mandel components)."""
        return self.apply(field)

    def apply(self, field, forward=False):
        """The box field ``(m1, m2, m3, 6)`` (Mandel components) times the inverse of the filled cell's operator,
        or with ``forward`` (built with a ``forward`` contrast) times the cell's operator at that contrast."""
        passes, matrices = loops(), self.forward if forward else self.matrices
        return self.operator.fourier(field, lambda spectra, k0, k1: passes.fourier_apply(
            spectra, matrices, *self.parities, k0), lattice=self.lattice)


@dataclass
class EquivalentInclusionSolution:
    """Solution of one equivalent-inclusion solve on an operator's box.

    Attributes
    ----------
    eigenstrain : ndarray
        ``(m1, m2, m3, 6)`` equivalent eigenstrain (zero in the matrix).
    strain : ndarray
        ``(m1, m2, m3, 6)`` total strain ``e0 + D[e*]``.
    stress : ndarray
        ``(m1, m2, m3, 6)`` total stress [Pa]: ``C_I : strain`` in the inhomogeneities,
        ``C_M : strain`` in the matrix.
    iterations : int
        GMRES iterations.
    residual : float
        Final ``|A e* - b| / |b|`` of the unpreconditioned system.
    success : bool
        Whether the residual met the tolerance.
    """

    eigenstrain: np.ndarray
    strain: np.ndarray
    stress: np.ndarray
    iterations: int
    residual: float
    success: bool


class EquivalentInclusionProblem:
    """The linear system of the equivalent inclusion method on one box.

    Parameters
    ----------
    operator : framework.operators.eigenstrain.HalfSpaceEigenstrain
        The matrix's eigenstrain operator on the box.
    indicator : ndarray of int
        ``(m1, m2, m3)``: 0 in the matrix, ``k + 1`` in the cuboids of the ``k``-th inhomogeneity.
    stiffnesses : sequence of ndarray
        Stiffness tensors ``(3, 3, 3, 3)`` [Pa] of the inhomogeneities, in the global frame.
    young : float
        Young's modulus of the matrix [Pa] (its Poisson ratio is the operator's).
    recycle : bool
        Keep the directions of each solve to deflate the next ones (:class:`RecycledSpace`); False: only
        within a solve, across its restarts (a hard one needs them: a sphere 1e6 times stiffer than its
        matrix stalled without), and not its last cycle's (at 64^3 keeping a one-cycle solve's 11
        directions took 1 s of 8).
    lattice : str, optional
        The Fourier preconditioner's periodic cell (``"own"``, ``"folded"``, ``"padded"``); None: chosen by
        :func:`periodic_cell`.
    shared : dict, optional
        The Fourier preconditioner made at the latest matrix modulus, shared with the problems of bodies that fill
        boxes of the same operator, lattice and material (a dispersion's bodies, each its own problem): made once.
    """

    def __init__(self, operator, indicator, stiffnesses, young, preconditioner="auto", recycle=True, lattice=None,
                 shared=None):
        if preconditioner not in ("auto", "fourier", "local"):
            raise ParameterError(f"preconditioner must be 'auto', 'fourier' or 'local', got {preconditioner!r}")
        if lattice not in (None, "own", "folded", "padded"):
            raise ParameterError(f"lattice must be None, 'own', 'folded' or 'padded', got {lattice!r}")
        indicator = np.asarray(indicator)
        if indicator.shape != operator.shape:
            raise ShapeError(f"indicator has shape {indicator.shape}, the operator's box is {operator.shape}")
        self.operator = operator
        self.indicator = indicator
        self.cells = np.nonzero(indicator)
        # the cuboids' flat indices in a box field's (m1 m2 m3, 6) rows: gathers and scatters by them take a
        # quarter of the time of the index tuple's (a 64^3 box's 137 376 cuboids: 0.3 against 2.8 ms)
        self._flat = np.ravel_multi_index(self.cells, operator.shape)
        self.material = indicator[self.cells] - 1
        self.stiffness = [mandel_matrix(c) for c in stiffnesses]
        self._lattice, self.preconditioner, self.inner = preconditioner_cell(
            operator, self.cells, self.stiffness, young, operator.poisson, preconditioner, lattice)
        # the contrast the Fourier preconditioner fills the box with: the bodies' own, or a dispersion's share
        self._share = 1.0 if len(self.stiffness) <= FOURIER_BODIES else DISPERSION_CONTRAST
        self._local = cuboid_self_strain(operator.spacing, operator.poisson, operator.average)
        self._fourier = None
        self._shared = shared       # (the latest modulus's only: the problems sharing it share their modulus)
        self._field = None          # the preconditioner's box field
        # the inner solve's tolerance and iterations at most (None: INNER_TOLERANCE and INNER_ITERATIONS)
        self.inner_tolerance = self.inner_iterations = None
        self.recycled = RecycledSpace(6 * self.material.size)
        self.recycle = recycle
        self.products = 0           # eigenstrain-operator products so far
        self.young = None
        self.set_modulus(young)

    def set_modulus(self, young):
        """Give the matrix the Young's modulus ``young`` [Pa] (a viscoelastic matrix's effective one of a step)."""
        if young == self.young:
            return
        self.young = young
        self.matrix = isotropic_mandel(young, self.operator.poisson)
        self.contrast = [c - self.matrix for c in self.stiffness]
        self._preconditioner = [np.linalg.inv(d @ self._local + self.matrix) for d in self.contrast]
        if self._fourier is not None and abs(young - self._fourier[0]) > 1e-9 * young:
            self._fourier = None    # built again at its next use (a modulus equal but for rounding keeps it)

    @property
    def size(self):
        """Number of unknowns (6 per cuboid of the inhomogeneities)."""
        return 6 * self.material.size

    def per_material(self, matrices, values):
        """``values (N, 6)`` each times its cuboid's material's matrix (``matrices[k]`` for material ``k``)."""
        if len(matrices) == 1:  # one material: no masks (two copies of the values each)
            return values @ matrices[0].T
        if len(matrices) > 8:   # many materials (the laminate's cut cuboids): one gathered product, not a loop of masks
            return np.einsum("nij,nj->ni", np.asarray(matrices)[self.material], values)
        out = np.empty_like(values)
        for k, matrix in enumerate(matrices):
            rows = self.material == k
            out[rows] = values[rows] @ matrix.T
        return out

    def box_field(self, values):
        """Tensor-shear box field ``(m1, m2, m3, 6)`` of Mandel values ``(N, 6)`` on the inhomogeneities' cuboids."""
        field = np.zeros((*self.operator.shape, 6))
        field.reshape(-1, 6)[self._flat] = np.reshape(values, (-1, 6)) / MANDEL
        return field

    def on_cells(self, field):
        """The values ``(N, 6)`` of a box field ``(m1, m2, m3, 6)`` on the inhomogeneities' cuboids."""
        return np.take(np.reshape(field, (-1, 6)), self._flat, axis=0)

    def _apply(self, values, disturbance):
        """``A x`` (Mandel, ``(N, 6)``) of the values ``x`` whose strain ``D[x]`` (box field) is known."""
        return self._image(values, self.on_cells(disturbance) * MANDEL).reshape(-1, 6)

    def _image(self, values, strains):
        """``A x`` as a flat vector, from ``x`` and its strain ``D[x]`` on the cuboids (both Mandel, any shape)."""
        return (self.per_material(self.contrast, np.reshape(strains, (-1, 6)))
                + np.reshape(values, (-1, 6)) @ self.matrix.T).ravel()

    def solve(self, applied_strain, initial=None, tolerance=1e-10, max_iterations=500, raise_on_failure=True):
        """Equivalent eigenstrain for the strain ``applied_strain`` the matrix would have without inhomogeneities.

        Parameters
        ----------
        applied_strain : ndarray
            ``(m1, m2, m3, 6)`` tensor-shear strain on the box, or ``(6,)`` uniform.
        initial : ndarray, optional
            ``(m1, m2, m3, 6)`` eigenstrain to start from (warm start across steps).
        tolerance : float
            Relative residual of the preconditioned system.
        max_iterations : int
            GMRES iterations (restarted every :data:`RESTART`) before the solve is declared failed.
        raise_on_failure : bool
            Raise :class:`~framework.errors.ConvergenceError` when the tolerance is not met.
        """
        shape = (*self.operator.shape, 6)
        applied = np.broadcast_to(np.asarray(applied_strain, dtype=float), shape)
        right = -self.per_material(self.contrast, self.on_cells(applied) * MANDEL)
        eigenstrain, disturbance, iterations, residual, success = self.solve_for(
            right, initial=initial, tolerance=tolerance, max_iterations=max_iterations,
            raise_on_failure=raise_on_failure)
        return self._solution(eigenstrain, applied, iterations, residual, success, disturbance)

    def solve_for(self, right, initial=None, tolerance=1e-10, max_iterations=500, raise_on_failure=True,
                  initial_disturbance=None):
        """Solve ``(C_I - C_M) D[e*] + C_M e* = right`` for any right-hand side (Mandel, ``(N, 6)``).

        ``initial_disturbance``, the box field ``D[initial]`` when the caller knows it (the
        last solve's), saves the first product. Returns ``(eigenstrain, disturbance,
        iterations, residual, success)``: the box fields ``e*`` and ``D[e*]`` (tensor
        shears), the GMRES count, the relative residual, convergence.
        """
        shape = (*self.operator.shape, 6)
        n = self.size
        scale = np.linalg.norm(right)
        if n == 0 or scale == 0.0:
            return np.zeros(shape), np.zeros(shape), 0, 0.0, True
        values = np.zeros((self.material.size, 6))
        disturbance = np.zeros(shape)
        if initial is not None:
            values = self.on_cells(np.asarray(initial, dtype=float)) * MANDEL
            if initial_disturbance is None:
                disturbance = self.operator.strain(self.box_field(values))
                self.products += 1
            else:
                disturbance = np.asarray(initial_disturbance, dtype=float)
        values, disturbance, iterations, residual = self._gmres(right.ravel(), values, disturbance, tolerance,
                                                                max_iterations)
        success = residual <= 10 * tolerance
        if not success and raise_on_failure:
            raise ConvergenceError(f"the equivalent-inclusion solve stopped after {iterations} GMRES iterations at "
                                   f"relative residual {residual:.3g}, tolerance {tolerance:g}")
        return self.box_field(values), disturbance, iterations, residual, success

    def _gmres(self, right, values, disturbance, tolerance, max_iterations):
        """Restarted flexible GMRES (Saad 1993) on ``A x = b``, preconditioned on the right, that carries ``D[x]``.

        The preconditioner is the Fourier one (or each cuboid's exact solve alone), deflated by the
        directions of earlier solves (:class:`RecycledSpace`): ``M v = U y + P (v - C y)``, ``y``
        the least-squares fit of ``v`` by ``C = A U``. Earlier solves' ``A U`` are known without
        products, and stay a good preconditioner when the box has moved since (then they are
        slightly off: the operator's surface patch sees the box elsewhere); each direction's own
        product ``A z`` is exact, so the solution and its residual are. Each product computes
        ``D[z]`` of a direction; keeping them gives ``D[x]`` as the same combination, without the
        extra product a library GMRES would need. Classical Gram-Schmidt, repeated once (Giraud et
        al. 2005). Stops when ``|b - A x| <= tolerance |b|``; returns ``(values, D[x], iterations,
        that relative residual)``.
        """
        scale = np.linalg.norm(right)
        target = tolerance * scale
        residual = right - self._apply(values, disturbance).ravel()
        beta = np.linalg.norm(residual)
        iterations = 0
        # a large box keeps neither the directions' strains nor a long basis: D[x] is computed once at the end
        box_bytes = 8 * 6 * int(np.prod(self.operator.shape))
        keep_images = RESTART * box_bytes <= IMAGES_BYTES
        recycling = self.recycled.kept > 0
        flexible = recycling or self.inner     # a preconditioner that changes with its input: its directions kept
        # without recycling nothing needs the directions: within a cycle the preconditioner is one linear map, so
        # the step is M (V y) (plain right-preconditioned GMRES), and the basis alone is kept
        per_iteration = 8 * self.size * (3 if flexible else 1) + (box_bytes if keep_images else 0)
        restart = max(4, min(RESTART, GMRES_BYTES // per_iteration))
        pending = None      # without the images: the steps whose strain D is not yet in ``disturbance``
        while beta > target and iterations < max_iterations:
            deflation = self.recycled.preconditioner(self._image, self.young)
            size = min(restart, self.size, max_iterations - iterations)
            basis = np.zeros((size + 1, self.size))
            directions, images, cells_images = [], [], []
            hessenberg = np.zeros((size + 1, size))
            arnoldi = np.zeros((size + 1, size))        # the same columns before the rotations
            rotations = np.zeros((size, 2))
            projected = np.zeros(size + 1)
            basis[0], projected[0] = residual / beta, beta
            used = 0
            for j in range(size):
                direction = self._precondition(basis[j], deflation)
                image = self.operator.strain(self.box_field(direction.reshape(-1, 6)))
                self.products += 1
                if flexible:
                    directions.append(direction)
                cells_image = self.on_cells(image) * MANDEL
                if recycling:
                    cells_images.append(cells_image)
                if keep_images:
                    images.append(image)
                w = self._image(direction, cells_image)
                del image, direction
                h = basis[:j + 1] @ w
                w -= h @ basis[:j + 1]
                again = basis[:j + 1] @ w
                w -= again @ basis[:j + 1]
                length = np.linalg.norm(w)
                column = np.zeros(size + 1)
                column[:j + 1], column[j + 1] = h + again, length
                arnoldi[:, j] = column
                for i in range(j):          # the earlier Givens rotations
                    c, s = rotations[i]
                    column[i], column[i + 1] = c * column[i] + s * column[i + 1], -s * column[i] + c * column[i + 1]
                radius = np.hypot(column[j], column[j + 1])
                c, s = (1.0, 0.0) if radius == 0.0 else (column[j] / radius, column[j + 1] / radius)
                rotations[j] = c, s
                column[j], column[j + 1] = radius, 0.0
                projected[j], projected[j + 1] = c * projected[j], -s * projected[j]
                hessenberg[:, j] = column
                used, iterations = j + 1, iterations + 1
                if length > 0.0:
                    basis[j + 1] = w / length
                if abs(projected[j + 1]) <= target or length == 0.0:
                    break
            weights = solve_triangular(hessenberg[:used, :used], projected[:used])
            if flexible:
                step = np.zeros(self.size)     # (not weights @ np.array(...): a copy of all the directions)
                for weight, direction in zip(weights, directions[:used]):
                    step += weight * direction
                step = step.reshape(-1, 6)
            else:
                step = self._precondition(weights @ basis[:used], deflation).reshape(-1, 6)
            values = values + step
            if keep_images:
                for weight, image in zip(weights, images[:used]):
                    disturbance = disturbance + weight * image
                residual = right - self._apply(values, disturbance).ravel()
            else:
                # the residual by the Arnoldi relation b - A (x + Z y) = V (beta e1 - H y), without a product; the
                # steps' strain by one product once converged (was one a restart: 20 -> 18 on a 128^3 box)
                pending = step if pending is None else pending + step
                residual = (beta * np.eye(used + 1)[0] - arnoldi[:used + 1, :used] @ weights) @ basis[:used + 1]
            del basis, step
            beta = np.linalg.norm(residual)
            if self.recycle or (beta > target and iterations < max_iterations):     # (else no cycle follows)
                self.recycled.add(directions[:used], cells_images[:used], self._image, self.young)
            del directions, images, cells_images
            if pending is not None and (beta <= target or iterations >= max_iterations):
                disturbance = disturbance + self.operator.strain(self.box_field(pending))
                self.products += 1
                pending = None
                residual = right - self._apply(values, disturbance).ravel()     # the true one decides
                beta = np.linalg.norm(residual)
        return values, disturbance, iterations, float(beta / scale)

    def precondition(self, values):
        """The preconditioner without the recycled directions on values ``(N, 6)`` (Mandel) on the cuboids: the Fourier
        one (with its inner solve), or each cuboid solved alone; ``(N, 6)``."""
        return self._local_solve(np.ravel(values)).reshape(-1, 6)

    def _local_solve(self, vector):
        """The preconditioner without deflation: the Fourier one, or each cuboid solved alone."""
        values = vector.reshape(-1, 6)
        if self.preconditioner == "local":
            return self.per_material(self._preconditioner, values).ravel()
        if self._fourier is None or (self.inner and self._fourier[1].forward is None):  # (its modulus, itself)
            made = None if self._shared is None else self._shared.get(self.young)
            if made is None or (self.inner and made[1].forward is None):
                made = (self.young, FourierPreconditioner(self.operator, self._share * self.contrast[0], self.matrix,
                                                          lattice=self._lattice,
                                                          forward=self.contrast[0] if self.inner else None))
                if self._shared is not None:
                    self._shared.clear()
                    self._shared[self.young] = made
            self._fourier = made
        if self.inner:
            return self._inner_solve(values)
        return self._filled(values)

    def _filled(self, values, forward=False):
        """The Fourier preconditioner's filled cell on values ``(N, 6)`` (Mandel) on the cuboids: its inverse, or its
        operator with ``forward``; flat. The box field they fill is kept (zero outside the cuboids), written and
        read through the cuboids' flat indices."""
        if self._field is None:
            self._field = np.zeros((*self.operator.shape, 6))
        self._field.reshape(-1, 6)[self._flat] = np.reshape(values, (-1, 6))
        return self.on_cells(self._fourier[1].apply(self._field, forward)).ravel()

    def _inner_solve(self, values):
        """The bodies' system in the filled periodic cell, ``P F P x = v`` (``F`` the cell's operator filled with the
        bodies' material, ``P`` the inhomogeneities' cuboids), solved to :data:`INNER_TOLERANCE` (or the problem's
        ``inner_tolerance``) by GMRES preconditioned by the cell's inverse (filled with a dispersion's share of the
        contrast, :data:`DISPERSION_CONTRAST`), :data:`INNER_ITERATIONS` (or ``inner_iterations``) at most (fewer
        where their vectors would take more than :data:`INNER_BYTES`).

        The cell's inverse alone is exact for a plane wave but not for a smooth field confined to a stiff body (the
        average over directions of the inverse where the body needs the inverse of the average: eigenvalues of
        the preconditioned operator up to 8.5 for glass in a polymer, ``bench/preconditioner_spectrum.py``).
        ``P F P`` is the bodies' own system in the infinite periodic medium (``F``'s Green operator is the
        matrix's), less the mirror image and the surface correction: solved, it leaves eigenvalues within 1.2 of 1.
        An iteration costs two transforms of the cell and no product.
        """
        right = values.ravel()
        scale = np.linalg.norm(right)
        if scale == 0.0:
            return np.zeros_like(right)
        tolerance = INNER_TOLERANCE if self.inner_tolerance is None else self.inner_tolerance
        iterations = INNER_ITERATIONS if self.inner_iterations is None else self.inner_iterations
        size = max(1, min(iterations, INNER_BYTES // (16 * right.size)))
        basis, directions = [right / scale], []
        hessenberg = np.zeros((size + 1, size))
        target = np.zeros(size + 1)
        target[0] = scale
        for j in range(size):
            directions.append(self._filled(basis[j].reshape(-1, 6)))
            w = self._filled(directions[j].reshape(-1, 6), forward=True)
            for i, v in enumerate(basis):           # modified Gram-Schmidt
                hessenberg[i, j] = v @ w
                w -= hessenberg[i, j] * v
            hessenberg[j + 1, j] = np.linalg.norm(w)
            weights, *_ = np.linalg.lstsq(hessenberg[:j + 2, :j + 1], target[:j + 2], rcond=None)
            rest = np.linalg.norm(hessenberg[:j + 2, :j + 1] @ weights - target[:j + 2])
            if rest <= tolerance * scale or hessenberg[j + 1, j] == 0.0:
                break
            basis.append(w / hessenberg[j + 1, j])
        out = np.zeros_like(right)
        for weight, direction in zip(weights, directions):
            out += weight * direction
        return out

    def _precondition(self, vector, deflation):
        """``M v``: the recycled directions' least-squares part, the preconditioner on the rest."""
        if deflation is None:
            return self._local_solve(vector)
        directions, images = deflation
        weights = images @ vector        # the images are orthonormal rows
        self.recycled.used(weights)
        rest = vector - weights @ images
        return weights @ directions + self._local_solve(rest)

    def _solution(self, eigenstrain, applied, iterations, residual, success, disturbance=0.0):
        strain = applied + disturbance
        stress = (strain * MANDEL) @ self.matrix.T
        stress[self.cells] = self.per_material(self.stiffness, strain[self.cells] * MANDEL)
        return EquivalentInclusionSolution(eigenstrain=eigenstrain, strain=np.array(strain), stress=stress / MANDEL,
                                           iterations=iterations, residual=residual, success=success)
