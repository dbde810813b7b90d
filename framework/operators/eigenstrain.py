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
import math

import numpy as np

from .. import fft
from ..errors import ParameterError, ShapeError
from . import parity
from ._box_loops import ENTRIES, PERMUTATION, NumpyLoops, PassItems, kernel_table, loops, stored_kernels
from .box_fft import BLOCK_BYTES, LEAST_Q3, BoxFFT, buffer_bytes, q3_blocks
from .box_surface import BoxSurface

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


def corner_case(key):
    """Which closed form a corner function ``D H`` (``key`` a sorted index tuple) takes, and the axes ``(i, j, k)``
    whose offsets it takes in that order: ``"phi_diagonal"``, ``"phi_mixed"``, ``"psi_four"``,
    ``"psi_three_one"``, ``"psi_two_two"`` or ``"psi_two_one_one"`` (axes by decreasing count in the key)."""
    counts = [key.count(axis) for axis in range(3)]
    order = tuple(sorted(range(3), key=lambda axis: -counts[axis]))
    i, j, _ = order
    if len(key) == 2:
        return ("phi_diagonal" if counts[i] == 2 else "phi_mixed"), order   # phi_mixed's k: the axis not in the key
    if counts[i] == 4:
        return "psi_four", order
    if counts[i] == 3:
        return "psi_three_one", order
    return ("psi_two_two" if counts[j] == 2 else "psi_two_one_one"), order


#: The closed forms of :func:`corner_case`'s names, in floating point.
CORNER_FORMS = {"phi_diagonal": _phi_diagonal, "phi_mixed": _phi_mixed, "psi_four": _psi_four,
                "psi_three_one": _psi_three_one, "psi_two_two": _psi_two_two, "psi_two_one_one": _psi_two_one_one}


def _corner_function(key, t, r):
    """One corner function ``D H`` (``key`` a sorted index tuple) at offsets ``t`` with ``r = |t|``."""
    name, (i, j, k) = corner_case(key)
    return CORNER_FORMS[name](t[i], t[j], t[k], r)


#: The 21 derivatives of the potentials a strain needs: ``(i, j)`` for ``phi_,ij``, ``(i, j, k, l)`` for ``psi_,ijkl``.
KEYS = tuple(sorted({tuple(sorted(c)) for c in np.ndindex(3, 3)} | {tuple(sorted(c)) for c in np.ndindex(3, 3, 3, 3)},
                    key=lambda key: (len(key), key)))


def _sum_r_one(t, r, rest2):
    """:func:`_sum_r` of one value (the compiled closed forms' :func:`_sum_r`)."""
    return r + t if t >= 0 else rest2 / (r - t)


def _lattice_keys(faces1, faces2, faces3, shifts, weights, out):
    """``out[n, a, b, c] = sum_p weights[p] D H_n(t_p)``, ``t_p = (faces1[a], faces2[b], faces3[c]) + shifts[p]``: the
    21 corner functions of :data:`KEYS` (in order, each with its :func:`corner_case`'s form and axes) over a lattice
    and an averaging rule, in one pass. Compiled by :func:`compiled_lattice` (the forms and their ``_sum_r`` bound to
    one-value versions there), not called as Python: the keys share their point's offsets, its length and the
    forms' six transcendental values (three arctangents, three logarithms), which the compiler computes once
    where the 21 forms would compute them 15 times."""
    for a in range(out.shape[1]):
        for b in range(out.shape[2]):
            for c in range(out.shape[3]):
                s0 = s1 = s2 = s3 = s4 = s5 = s6 = s7 = s8 = s9 = s10 = 0.0
                s11 = s12 = s13 = s14 = s15 = s16 = s17 = s18 = s19 = s20 = 0.0
                for p in range(weights.shape[0]):
                    weight = weights[p]
                    t0, t1, t2 = faces1[a] + shifts[p, 0], faces2[b] + shifts[p, 1], faces3[c] + shifts[p, 2]
                    r = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
                    s0 += weight * _phi_diagonal(t0, t1, t2, r)
                    s1 += weight * _phi_mixed(t0, t1, t2, r)
                    s2 += weight * _phi_mixed(t0, t2, t1, r)
                    s3 += weight * _phi_diagonal(t1, t0, t2, r)
                    s4 += weight * _phi_mixed(t1, t2, t0, r)
                    s5 += weight * _phi_diagonal(t2, t0, t1, r)
                    s6 += weight * _psi_four(t0, t1, t2, r)
                    s7 += weight * _psi_three_one(t0, t1, t2, r)
                    s8 += weight * _psi_three_one(t0, t2, t1, r)
                    s9 += weight * _psi_two_two(t0, t1, t2, r)
                    s10 += weight * _psi_two_one_one(t0, t1, t2, r)
                    s11 += weight * _psi_two_two(t0, t2, t1, r)
                    s12 += weight * _psi_three_one(t1, t0, t2, r)
                    s13 += weight * _psi_two_one_one(t1, t0, t2, r)
                    s14 += weight * _psi_two_one_one(t2, t0, t1, r)
                    s15 += weight * _psi_three_one(t2, t0, t1, r)
                    s16 += weight * _psi_four(t1, t0, t2, r)
                    s17 += weight * _psi_three_one(t1, t2, t0, r)
                    s18 += weight * _psi_two_two(t1, t2, t0, r)
                    s19 += weight * _psi_three_one(t2, t1, t0, r)
                    s20 += weight * _psi_four(t2, t0, t1, r)
                out[0, a, b, c] = s0; out[1, a, b, c] = s1; out[2, a, b, c] = s2
                out[3, a, b, c] = s3; out[4, a, b, c] = s4; out[5, a, b, c] = s5
                out[6, a, b, c] = s6; out[7, a, b, c] = s7; out[8, a, b, c] = s8
                out[9, a, b, c] = s9; out[10, a, b, c] = s10; out[11, a, b, c] = s11
                out[12, a, b, c] = s12; out[13, a, b, c] = s13; out[14, a, b, c] = s14
                out[15, a, b, c] = s15; out[16, a, b, c] = s16; out[17, a, b, c] = s17
                out[18, a, b, c] = s18; out[19, a, b, c] = s19; out[20, a, b, c] = s20


#: Lattices of at least this many points evaluate the closed forms compiled, all keys at once
#: (:func:`compiled_lattice`) where their values take at most :data:`LATTICE_KEYS_BYTES`, else one key at a time
#: (:func:`lattice_forms`). Loading the first from numba's cache takes 0.2 s once a process, the second 0.6 s.
#: A 64^3 box's build 2.4-2.9 -> 1.75-1.95 s (its kernels' values 0.6 s + 0.8 s -> 0.2 s + 0.5 s), the rolling
#: bench's 30^3 box 0.86-1.2 -> 0.71-0.73 s (numpy's forms before).
COMPILED_LATTICE_POINTS = 2 ** 12
#: Memory the 21 keys' values on a lattice may take when computed together [bytes] (the kernels of a box up to
#: about 70^3); a larger lattice is computed one key at a time (the build of a 128^3 box holds one key's lattice).
LATTICE_KEYS_BYTES = 128 * 2**20
#: Lattices of at least this many points evaluated one key at a time use the compiled forms (:func:`lattice_forms`).
COMPILED_FORMS_POINTS = 2 ** 18


def compiled_lattice(points=None):
    """:func:`_lattice_keys` compiled by numba, for a lattice of ``points`` points, when numba is installed and
    allowed, the lattice has :data:`COMPILED_LATTICE_POINTS` points or more and its 21 keys' values take at most
    :data:`LATTICE_KEYS_BYTES` (or ``points`` is None); else None (:func:`lattice_forms`, one key at a time). The
    loop evaluates the source of :data:`CORNER_FORMS` one value at a time and agrees with the numpy forms to
    rounding (4e-15 of a key's largest value on a 64^3 box's lattice)."""
    from .. import _fused
    if not (_fused._compiled and _fused.numba_available() and (
            points is None or COMPILED_LATTICE_POINTS <= points <= LATTICE_KEYS_BYTES // (8 * len(KEYS)))):
        return None
    if "lattice_keys" not in _fused._cache:
        import types
        numba = _fused._cache["numba"]
        scalar = {**globals(), "_sum_r": numba.njit(_sum_r_one, cache=True)}
        forms = {form.__name__: numba.njit(types.FunctionType(form.__code__, scalar, form.__name__), cache=True)
                 for form in CORNER_FORMS.values()}
        _fused._cache["lattice_keys"] = numba.njit(
            types.FunctionType(_lattice_keys.__code__, {**globals(), **forms}, "_lattice_keys"), cache=True, nogil=True)
    return _fused._cache["lattice_keys"]


def lattice_forms(points=None):
    """The closed forms of :data:`CORNER_FORMS` for a lattice of ``points`` points evaluated one key at a time:
    numba ufuncs of the same source (their ``_sum_r`` one value at a time: no temporary arrays), three times
    faster on large lattices, when numba is installed and allowed and the lattice has
    :data:`COMPILED_FORMS_POINTS` points or more (or ``points`` is None); else the numpy forms. They agree to
    rounding (1e-13 of the kernels' largest value where ``psi_four``'s terms cancel)."""
    from .. import _fused
    if not (_fused._compiled and (points is None or points >= COMPILED_FORMS_POINTS) and _fused.numba_available()):
        return CORNER_FORMS
    if "lattice_forms" not in _fused._cache:
        import types
        numba = _fused._cache["numba"]
        names = {"_sum_r": numba.njit(_sum_r_one, cache=True)}
        _fused._cache["lattice_forms"] = {
            name: numba.vectorize(["f8(f8, f8, f8, f8)"], nopython=True, cache=True)(
                types.FunctionType(form.__code__, {**form.__globals__, **names}, form.__name__))
            for name, form in CORNER_FORMS.items()}
    return _fused._cache["lattice_forms"]


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
    """:func:`potential_kernels` one key at a time, ``(key, array)``: the keys computed together by the compiled loop
    (:func:`compiled_lattice`) where it serves, else a few lattice arrays in memory (the offsets' lengths at each
    point of the averaging rule, and the key's sum)."""
    shape = (len(faces1), len(faces2), len(faces3))
    loop = compiled_lattice(int(np.prod(shape)))
    if loop is not None:
        values = np.empty((len(KEYS), *shape))
        loop(*(np.asarray(f, dtype=float) for f in (faces1, faces2, faces3)), *cell_average_rule(cell), values)
        for key, total in zip(KEYS, values):
            yield key, np.diff(np.diff(np.diff(total, axis=0), axis=1), axis=2)
        return
    rule = []           # per point of the rule: its weight, the offsets and their lengths (shared by the keys)
    for shift, weight in zip(*cell_average_rule(cell)):
        t = [np.broadcast_to(c, shape) for c in np.meshgrid(faces1 + shift[0], faces2 + shift[1], faces3 + shift[2],
                                                            indexing="ij", sparse=True)]
        rule.append((weight, t, np.sqrt(t[0] ** 2 + t[1] ** 2 + t[2] ** 2)))
    forms = lattice_forms(int(np.prod(shape)))
    for key in KEYS:
        name, (i, j, k) = corner_case(key)
        total = None
        for weight, t, r in rule:       # in place: each point's values are a fresh array
            value = forms[name](t[i], t[j], t[k], r)
            value *= weight
            if total is None:
                total = value
            else:
                total += value
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


def strain_from_stress(stress, poisson, young=1.0, out=None):
    """Inverse of :func:`stress_from_strain` (into ``out``, which may be ``stress``, when given)."""
    trace = stress[..., 0] + stress[..., 1] + stress[..., 2]
    strain = np.multiply(stress, (1 + poisson) / young, out=out)
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
    Exact (to rounding) for points anywhere, on faces, edges and corners the one-sided
    limit from the cuboid on the positive side (:mod:`framework.operators.one_sided`); it
    costs ``n N`` kernel evaluations, for checks and a few points. With ``cell`` (sizes [m])
    the strain is averaged over a cell centred on each point (:func:`cell_average_rule`).
    """
    from .one_sided import strain_at_points as one_sided
    return one_sided(points, centres, eigenstrain, half, poisson, chunk=chunk, cell=cell)


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


def _traction_coefficients(poisson):
    """``{key: (6,) weights}``: ``2 s33`` (unit modulus) per unit eigenstrain component (tensor shears) as
    combinations of the potentials. ``C : D`` is symmetric in Mandel's basis, so ``s33`` per unit
    component ``c`` is the ``c``-th stress of a unit ``e*_33`` (Mandel weights squared = CONTRACTION)."""
    out = {}
    for key in KEYS:
        unit = {k: float(k == key) for k in KEYS}
        out[key] = 2.0 * stress_from_strain(strain_from_potentials(unit, np.eye(6)[2], poisson), poisson) * CONTRACTION
    return out


def key_parities(key):
    """Parity (+1 even, -1 odd) along x1, x2, x3 of the potential derivative ``key``."""
    return np.array([1 - 2 * (key.count(axis) % 2) for axis in range(3)])


#: Boxes of more FFT points than this plan their transforms by estimate; smaller ones measure once a run has
#: used them :data:`~framework.operators.box_fft.MEASURE_AFTER` times (whole-lattice 3-D transforms: a
#: 60 x 64 x 60 pair 1.4 ms measured, 2.5 ms estimated; 256^3 forward 148 ms and inverse 179 ms measured against
#: 611 and 682 ms estimated, for 5.6 s of planning; this machine, one thread).
MEASURED_FFT_POINTS = 2 ** 25

#: Cuboids of matrix the folded lattice (:meth:`HalfSpaceEigenstrain.lattice_shape`) adds to the box along each
#: axis, a periodic cell for a Fourier preconditioner where the bodies fill the box: a sphere filling a 64^3 box
#: takes 12 GMRES iterations on it against 11 on the padded lattice (72^3 points against 128^3); a gap of 6 sent a
#: rolling run's coupled iteration over a sphere filling its 10^3 box into stagnation (38 couplings against 19 at
#: a moved step, none converged at 1e-12), 4 and 8 did not (8: the padded lattice's counts).
FOLDED_GAP = 8

#: Cells by which :meth:`HalfSpaceEigenstrain.pressure_stress` grows the window of the pressure and the box's
#: footprint it transforms: the window is kept while they stay inside it.
PRESSURE_WINDOW_SLACK = 16


def padded_shape(shape):
    """A box's padded lattice: even sizes of at least twice the box, with small prime factors (its own lattice,
    :attr:`HalfSpaceEigenstrain.own_shape`, is half of it)."""
    return tuple(fft.even_size(2 * m) for m in shape)


#: A box of cuboids square in x1, x2 whose padded lattice is this close to square (its larger side over its smaller)
#: takes the larger side along both: its kernels are then symmetric in q1, q2 (their entries permuted) and half of
#: them are stored (:func:`~framework.operators._box_loops.kernel_table`). The rolling bench's 30 x 31 footprint:
#: 60 x 64 -> 64 x 64 points.
SQUARE_LATTICE_RATIO = 1.1


def box_lattice(shape, spacing):
    """The padded lattice ``(N1, N2, N3)`` of a box of ``shape`` cuboids of sizes ``spacing`` [m], and whether its
    kernels are symmetric in ``q1, q2`` (:data:`SQUARE_LATTICE_RATIO`; :func:`padded_shape` otherwise)."""
    n1, n2, n3 = padded_shape(shape)
    symmetric = (math.isclose(spacing[0], spacing[1], rel_tol=1e-12)
                 and max(n1, n2) <= SQUARE_LATTICE_RATIO * min(n1, n2))
    if symmetric:
        n1 = n2 = max(n1, n2)
    return (n1, n2, n3), bool(symmetric)


def kernel_spectra(faces, mirror_faces, place, depth, fft_shape, poisson, cell, blocks=None, fold=None,
                   fold_extent=None):
    """The 21 infinite-space kernels' real factors and the 21 mirror kernels' spectra of ``C : D``.

    Each ``(21, N1/2+1, N2/2+1, N3/2+1)`` (unit Young's modulus, Mandel basis) on the padded lattice
    ``fft_shape``. ``faces`` are the target-minus-source offsets' cuboid faces [m] along each axis, from
    offset 0 up (the kernels are even or odd in each offset); ``mirror_faces`` the sums of depths' faces
    and ``place`` where each sum goes on the lattice's third axis; ``depth`` the sources' layers (the
    mirror image is the sources flipped along x3); ``cell`` the sizes of the averaging cuboid (None: at
    the centres). Each entry is a fixed combination of the potentials' derivatives, each even or odd in
    each offset: one derivative at a time is evaluated on the offsets ``>= 0`` of x1 and x2 (and x3 for
    the infinite-space term), transformed by :func:`~framework.operators.parity.half_spectrum` and added
    to the entries it enters (a quarter of the lattice, and no lattice array per entry).

    ``blocks``, a list of ``(k0, k1)`` ranges of q3: the kernels are returned as ``{k0: (direct, mirror)}``, each
    block its own contiguous array, built so (not cut from whole arrays: that held the kernels twice, the peak
    of a 128^3 box's build).

    ``fold``, a lattice ``(L1, L2, L3)`` (even, each at least the offsets): the infinite-space kernels' real
    factors summed over its periods, ``(21, L1/2+1, L2/2+1, L3/2+1)``, from the same values
    (:func:`~framework.operators.parity.folded_spectrum`), returned after the kernels as ``(kernels, folded)``; of the
    first ``fold_extent`` offsets along each axis where given (the box's, where ``faces`` reach beyond it).
    """
    n1, n2, n3 = fft_shape
    # Flipping the box along x3 (the mirror image's correlation) is, on the spectrum of a real
    # field, a reversal of the other two wavenumbers, a conjugation and this phase in q3.
    flip = np.exp(-2j * np.pi * np.arange(n3 // 2 + 1) * (depth - 1) / n3)
    coefficients = _stiffness_coefficients(poisson)
    whole = blocks is None
    blocks = [(0, n3 // 2 + 1)] if whole else blocks
    quarter = (n1 // 2 + 1, n2 // 2 + 1)
    parts = ({}, {})        # the direct and the mirror kernels, by block
    for faces3, part in ((faces[2], 0), (mirror_faces, 1)):
        # the keys' spectra per block, then the entries as one matrix product a block (87 scaled additions of
        # whole spectra read the memory 3 times each: a fifth of a 128^3 box's build)
        dtype = float if part == 0 else complex
        keys = {k0: np.empty((len(KEYS), *quarter, k1 - k0), dtype=dtype) for k0, k1 in blocks}
        weights = np.zeros((len(ENTRIES), len(KEYS)))
        folded = None if fold is None or part else np.empty((len(KEYS), *(n // 2 + 1 for n in fold)))
        for index, (key, values) in enumerate(potential_kernel_items(faces[0], faces[1], faces3, cell=cell)):
            parities = key_parities(key)
            if folded is not None:
                spectrum = values if fold_extent is None else values[tuple(slice(0, m) for m in fold_extent)]
                for axis in range(3):
                    spectrum = parity.folded_spectrum(spectrum, parities[axis], fold[axis], axis)
                folded[index] = spectrum * parity.phase(parities).real
            spectrum = parity.half_spectrum(values, parities[0], n1, axis=0)
            spectrum = parity.half_spectrum(spectrum, parities[1], n2, axis=1)
            if part == 0:
                spectrum = parity.half_spectrum(spectrum, parities[2], n3, axis=2) * parity.phase(parities).real
            else:
                wrapped = np.zeros(spectrum.shape[:2] + (n3,))
                wrapped[:, :, place] = spectrum
                spectrum = np.fft.rfft(wrapped, axis=2) * (parity.phase(parities[:2]) * flip)
            del values
            weights[:, index] = [coefficients[entry].get(key, 0.0) for entry in ENTRIES]
            for k0, k1 in blocks:
                keys[k0][index] = spectrum[..., k0:k1]
        for k0, k1 in blocks:
            block = keys.pop(k0)
            parts[part][k0] = (weights @ block.reshape(len(KEYS), -1)).reshape(len(ENTRIES), *quarter, k1 - k0)
            del block
        if folded is not None:
            folded = (weights @ folded.reshape(len(KEYS), -1)).reshape(len(ENTRIES), *folded.shape[1:])
            parts[0]["folded"] = folded
    out = {k0: (parts[0][k0], parts[1][k0]) for k0, _ in blocks}
    out = out[0] if whole else out
    return out if fold is None else (out, parts[0]["folded"])


def surface_traction_kernels(faces1, faces2, top, layers, thickness, poisson):
    """``2 s33`` at the surface ``(F1, F2, layers, 6)`` per unit eigenstrain component of a cuboid in each of
    the ``layers`` layers from layer ``top`` down (thickness [m]), unit modulus, target minus source between
    the faces ``faces1``, ``faces2`` [m]."""
    # Target on the surface, sources below: x3 - x3' runs from -(bottom) up to -(top of the box).
    faces3 = -(top + layers - np.arange(layers + 1)) * thickness
    if top == 0:
        faces3[-1] = -1e-12 * thickness  # the surface itself: s33 is continuous there (traction)
    weights = _traction_coefficients(poisson)
    out = np.zeros((len(faces1) - 1, len(faces2) - 1, layers, 6))
    for key, values in potential_kernel_items(faces1, faces2, faces3):
        out += values[:, :, ::-1, None] * weights[key]            # layers bottom-up -> top-down
    return out


class BoxLattices:
    """The lattices a box of cuboids lies on, without its kernels: what a preconditioner's choice of periodic cell
    reads (:func:`~framework.inclusions.equivalent.preconditioner_cell`), told before the operator
    (:class:`HalfSpaceEigenstrain`, which is one) is built, so that it builds the folded lattice's kernels only where
    they will serve.

    Parameters
    ----------
    shape : tuple of int
        Cuboids of the box along each axis.
    spacing : tuple of float
        The cuboids' sizes ``(dx1, dx2, dx3)`` [m].
    folded : bool
        Whether the box has a folded lattice (:meth:`lattice_shape`); False: that lattice is the padded one.
    """

    def __init__(self, shape, spacing, folded=True):
        self.shape = tuple(int(m) for m in shape)
        self.spacing = tuple(float(h) for h in spacing)
        self.fft_shape, self.symmetric = box_lattice(self.shape, self.spacing)
        self.folded_shape = (tuple(min(n, fft.even_size(m + FOLDED_GAP)) for m, n in zip(self.shape, self.fft_shape))
                             if folded else self.fft_shape)
        # an entry's parity in x1 and x2 is the product of its two components' parities
        self._parities = tuple(np.array([1.0 - 2 * (COMPONENTS[c].count(axis) % 2) for c in range(6)])
                               for axis in range(2))

    @property
    def own_shape(self):
        """The box's own periodic lattice: half the padded one along each axis (at least the box)."""
        return tuple(n // 2 for n in self.fft_shape)

    def lattice_shape(self, lattice):
        """The points of a lattice the box lies on: ``"padded"`` (:attr:`fft_shape`, a product's: twice the box
        or more, convolutions linear), ``"own"`` (:attr:`own_shape`, half the padded one) or ``"folded"``
        (:attr:`folded_shape`: the box grown by :data:`FOLDED_GAP` cuboids, the padded one where that is not
        smaller). The last two are periodic cells for preconditioners, not linear convolutions."""
        shapes = {"padded": self.fft_shape, "own": self.own_shape, "folded": self.folded_shape}
        if lattice not in shapes:
            raise ParameterError(f"lattice must be 'padded', 'own' or 'folded', got {lattice!r}")
        return shapes[lattice]

    def transform_bytes(self, lattice="padded"):
        """Memory the buffers of a product's transforms on ``lattice`` add [bytes], told before they are made: on a
        lattice other than the padded one, what the padded one's buffers cannot hold (none, on the box's own and
        folded lattices, which are no larger)."""
        shape = self.lattice_shape(lattice)
        share = None if lattice == "padded" else (self.fft_shape, BLOCK_BYTES, LEAST_Q3)
        return buffer_bytes(self.shape, shape, least=LEAST_Q3, share=share)

    @property
    def kernel_parities(self):
        """The six components' parities in x1 and x2 (an entry's is the product of its two components')."""
        return self._parities


class HalfSpaceEigenstrain(BoxLattices):
    """Strain in a box of cuboids of the half-space caused by eigenstrains in the same box.

    The box is a block of the grid's cuboid lattice (surface cells times layers); the
    kernels span the box only, so memory and time follow the box, not the grid. A product
    is six forward and six inverse real 3-D FFTs of the box padded to ``fft_shape`` (even
    sizes of at least twice the box, with small prime factors), one compiled pass over the
    spectra (:mod:`framework.operators._box_loops`), and the Boussinesq correction's surface
    transforms (:class:`~framework.operators.box_surface.BoxSurface`). Memory: the 21 + 21
    kernel spectra of the infinite-space and mirror terms are even or odd in ``q1`` and
    ``q2`` (and, for the first, in ``q3``), so an eighth and a quarter of them are stored
    (66 bytes per point of the padded box, 528 bytes per box cuboid); on a square lattice
    (:func:`box_lattice`: cuboids square in x1, x2) they are symmetric in ``q1, q2`` too and half of
    them are stored (33 bytes a point, 264 a box cuboid), plus the six
    spectra of a product (half the padded points each, complex: 48 bytes per point) and the
    surface kernels (2 x 6 per layer, a quarter of the padded surface grid each).

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
    starts : sequence of (int, int), optional
        Every ``(x1, x2)`` start the box will take when it moves (:meth:`move`; a rolling
        run); by default anywhere on the grid with ``whole_patch``, else ``start`` alone. The
        surface transforms are sized for them once.
    folded : bool
        Also build the infinite-space kernels on the folded lattice (:meth:`lattice_shape`), a Fourier
        preconditioner's periodic cell where bodies fill the box (13 % of a 109 x 109 x 28 box's build, 1.42
        against 1.23 s, and a fifth of the padded kernels' memory); False: that lattice is the padded one
        (:func:`~framework.inclusions.equivalent.preconditioner_cell` tells which before the operator is built).
    """

    def __init__(self, grid, poisson, start, shape, whole_patch=False, average=True, starts=None, folded=True):
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
        super().__init__(shape, (*grid.spacing, grid.layer_thickness), folded)
        self.grid, self.poisson, self.start = grid, float(poisson), start
        self.average = average
        self.depths = grid.x3[start[2]:start[2] + shape[2]]
        # the kernels held a block of q3 at a time, each block contiguous (the pass streams one block per block
        # of spectra: strided slices of whole arrays read four times the memory, twice the time on 256^3)
        fold = self.folded_shape if self.folded_shape != self.fft_shape else None
        # on a square lattice (box_lattice) the kernels are symmetric in q1, q2 (the entries permuted): half of them
        # stored, half the memory and their traffic in a product (a 64^3 box's pass 3.2 -> 2.1 ms)
        quarter = [n // 2 + 1 for n in self.fft_shape[:2]]
        self._table, first, second = kernel_table(*quarter, self.symmetric)
        self._items = PassItems(self._table)
        full_blocks, self._folded = self._box_spectra(self.spacing if average else None,
                                                      q3_blocks(self.fft_shape, least=LEAST_Q3), fold)
        self._kernel_blocks = {}
        for k0 in sorted(full_blocks):
            direct, mirror = full_blocks.pop(k0)            # each block packed, then its whole arrays freed
            self._kernel_blocks[k0] = tuple(stored_kernels(part[:, first, second] if self.symmetric else part)
                                            for part in (direct, mirror))
            del direct, mirror
        self._entries = (np.array([a for a, _ in ENTRIES]), np.array([b for _, b in ENTRIES]))
        # The Boussinesq correction works on a surface patch around the box: the traction the
        # eigenstrains leave decays like 1/r^3, and beyond PATCH_DEPTHS times the box's bottom depth
        # its stress at the box is below ~1e-3 of the correction (which is itself small unless the
        # box is shallow). The patch's cells are the grid's.
        reach = [int(np.ceil(PATCH_DEPTHS * (start[2] + shape[2]) * self.spacing[2] / h)) for h in grid.spacing]
        low = [max(0, start[a] - reach[a]) for a in range(2)]
        high = [min(grid.shape[a], start[a] + shape[a] + reach[a]) for a in range(2)]
        if whole_patch:        # a box that moves over the grid (rolling) keeps the grid as its patch
            low, high = [0, 0], list(grid.shape)
            if starts is None:
                starts = [(0, 0), (grid.shape[0] - shape[0], grid.shape[1] - shape[1])]
        self.patch = tuple(slice(lo, hi) for lo, hi in zip(low, high))
        self._starts = [tuple(start[:2])] if starts is None else [tuple(int(c) for c in s[:2]) for s in starts]
        self._surface = BoxSurface(grid, poisson, self.patch, start, shape, traction=self._traction, starts=self._starts)
        self._grid_surface = None
        self._pressure_surface = None
        self._ffts = {}

    def _box_spectra(self, cell, blocks, fold):
        """Real factors of the 21 infinite-space spectra ``(21, N1/2+1, N2/2+1, N3/2+1)`` and the complex
        mirror spectra ``(21, N1/2+1, N2/2+1, N3/2+1)`` of ``C : D`` (unit Young's modulus, Mandel basis)
        between the box's cuboids (:func:`kernel_spectra`), per block of q3 ``{k0: (direct, mirror)}``, and the
        infinite-space ones folded onto the lattice ``fold``."""
        m3, n3 = self.shape[2], self.fft_shape[2]
        # symmetric: the offsets of the longer side along both (values the box's products never read on the other)
        extent = [max(self.shape[:2])] * 2 + [m3] if self.symmetric else list(self.shape)
        half_faces = [(np.arange(m + 1) - 0.5) * h for m, h in zip(extent, self.spacing)]
        mirror_faces = (2 * self.start[2] + np.arange(2 * m3) + 0.5) * self.spacing[2]
        place = (np.arange(2 * m3 - 1) - (m3 - 1)) % n3      # the mirror kernel's sums of depths, centred
        spectra = kernel_spectra(half_faces, mirror_faces, place, m3, self.fft_shape, self.poisson, cell, blocks, fold,
                                 fold_extent=self.shape)
        return spectra if fold is not None else (spectra, None)

    def _traction(self, faces1, faces2):
        """``2 s33`` at the surface ``(F1, F2, m3, 6)`` per unit eigenstrain component of a cuboid of each layer
        (top-down), unit modulus, target minus source between the faces ``faces1``, ``faces2`` [m]."""
        return surface_traction_kernels(faces1, faces2, self.start[2], self.shape[2], self.spacing[2], self.poisson)

    def _box_fft(self, lattice="padded"):
        """The pruned transforms of a product on one of the box's lattices (:meth:`lattice_shape`), made at their
        first use (:class:`~framework.operators.box_fft.BoxFFT`). Those of the other lattices (a preconditioner's
        periodic cells, never used during a product) take the product's buffers, which hold theirs: 100 and 300 glass
        spheres at 8 cuboids per radius rolled over, 3.43 -> 3.18 and 8.90 -> 8.26 GiB."""
        if lattice not in self._ffts:
            shape = self.lattice_shape(lattice)
            effort = "FFTW_MEASURE" if np.prod(shape) <= MEASURED_FFT_POINTS else "FFTW_ESTIMATE"
            share = None if lattice == "padded" else self._box_fft("padded")
            self._ffts[lattice] = BoxFFT(self.shape, shape, effort=effort, least=LEAST_Q3, share=share,
                                         by_columns=lattice == "padded")
        return self._ffts[lattice]

    def _check(self, eigenstrain):
        expected = (*self.shape, 6)
        if np.shape(eigenstrain) != expected:
            raise ShapeError(f"eigenstrain has shape {np.shape(eigenstrain)}, the operator's box is {expected}")
        return np.asarray(eigenstrain, dtype=float)

    def surface_traction(self, eigenstrain):
        """Pressure ``2 s33(x1, x2, 0)`` [Pa per unit Young's modulus] over the surface patch ``patch``.

        The normal stress that the eigenstrains and their mirror image leave on the
        surface, as the compressive pressure that the Boussinesq correction applies.
        """
        return self._surface.field(self._surface.surface(self._check(eigenstrain), "traction")[0])

    def _grid_map(self):
        """The surface map over the whole grid (the patch's when the patch is the grid)."""
        if self.patch == (slice(0, self.grid.shape[0]), slice(0, self.grid.shape[1])):
            return self._surface
        if self._grid_surface is None:
            region = (slice(0, self.grid.shape[0]), slice(0, self.grid.shape[1]))
            self._grid_surface = BoxSurface(self.grid, self.poisson, region, self.start, self.shape,
                                            starts=self._starts)
        return self._grid_surface

    def surface_displacement(self, eigenstrain):
        """Normal surface displacement ``u3`` [m] over the grid, positive into the solid.

        Betti's reciprocal theorem with Love's pressure-to-stress coefficients (the
        transpose of :meth:`pressure_stress`); it does not depend on the modulus.
        """
        surface = self._grid_map()
        spectrum, = surface.surface(self._check(eigenstrain), "betti", weights=CONTRACTION)
        return self.spacing[2] * surface.field(spectrum)

    def pressure_stress(self, pressure):
        """Stress ``(m1, m2, m3, 6)`` [Pa] at the box's cuboid centres of a surface pressure ``(n1, n2)`` [Pa]
        on the grid (Love's coefficients; the homogeneous half-space).

        The transforms cover the cells that hold pressure and the box's footprint (grown by
        :data:`PRESSURE_WINDOW_SLACK` cells, so that a contact that grows a little or a box that moves a few
        cells keeps the same map), not the grid: a contact over a box is a fraction of a grid that also holds
        its surroundings (the static bench, 128^2 cells: 64^2-point transforms per layer instead of 256^2).
        The pressure outside is zero, so the result is the whole grid's to rounding.
        """
        pressure = np.asarray(pressure, dtype=float)
        loaded = [np.flatnonzero(pressure.any(axis=1 - axis)) for axis in range(2)]
        if not loaded[0].size:
            return np.zeros((*self.shape, 6))
        need = [(min(int(cells[0]), self.start[axis]), max(int(cells[-1]) + 1, self.start[axis] + self.shape[axis]))
                for axis, cells in enumerate(loaded)]
        surface = self._pressure_surface
        if surface is None or not all(
                low >= region.start and high <= region.stop and first <= start - region.start <= last
                for (low, high), region, first, last, start in zip(need, surface.region, surface.first, surface.last,
                                                                    self.start)):
            surface = self._pressure_surface = self._pressure_map(need)
        surface.move(self.start[:2])
        return surface.box_stress(surface.spectrum(pressure[surface.region]))

    def _pressure_map(self, need):
        """The surface map of :meth:`pressure_stress` for a pressure and a footprint within ``need`` [(low, high)
        per axis]: those cells grown by the slack (the whole grid's map when that is nearly the grid)."""
        slack = PRESSURE_WINDOW_SLACK
        region = tuple(slice(max(0, low - slack), min(n, high + slack)) for (low, high), n in zip(need, self.grid.shape))
        if np.prod([r.stop - r.start for r in region]) > 0.5 * np.prod(self.grid.shape):
            return self._grid_map()
        # every start whose footprint stays in the region: the box may move there without a new map
        starts = [(region[0].start, region[1].start),
                  (region[0].stop - self.shape[0], region[1].stop - self.shape[1])]
        return BoxSurface(self.grid, self.poisson, region, self.start, self.shape, starts=starts)

    @property
    def box(self):
        """Slices of the box in the grid's ``(n1, n2, layers)`` arrays."""
        return tuple(slice(s, s + m) for s, m in zip(self.start, self.shape))

    def move(self, cells):
        """Move the box by ``cells = (c1, c2)`` whole surface cells (the material moved under a rolling body).

        The kernels do not depend on where the box lies on the grid, only the footprint
        does; the surface patch must be the whole grid (``whole_patch=True``) and the new
        place one of ``starts``' range.
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
        self._surface.move(start)
        self.start = start

    def fourier(self, field, multiply, lattice="padded"):
        """``F^-1 [multiply(F field)]`` on the padded box, for a box field ``(m1, m2, m3, 6)`` (Mandel components).

        ``multiply(spectra, k0, k1)`` changes the six spectra ``(N1, N2, 6, k1 - k0)`` of the wavenumbers
        ``q3 = k0 .. k1 - 1`` in place (:class:`~framework.operators.box_fft.BoxFFT`); the box part of the
        result is returned. For preconditioners that act on the box as if it were one homogeneous periodic
        cell (:class:`~framework.inclusions.equivalent.FourierPreconditioner`); ``lattice`` names the periodic
        cell (:meth:`lattice_shape`), whose spectra :meth:`infinite_spectra` gives.
        """
        return self._box_fft(lattice).apply(field, multiply)

    @property
    def _direct(self):
        """The infinite-space kernels' real factors ``(21, N1/2+1, N2/2+1, N3/2+1)`` (the blocks joined)."""
        return self._joined(0)

    @property
    def _mirror(self):
        """The mirror kernels' spectra ``(21, N1/2+1, N2/2+1, N3/2+1)`` (the blocks joined)."""
        return self._joined(1)

    def _joined(self, part):
        blocks = [self._unpacked(self._kernel_blocks[k0][part]) for k0 in sorted(self._kernel_blocks)]
        return blocks[0] if len(blocks) == 1 else np.concatenate(blocks, axis=-1)

    def _unpacked(self, kernels):
        """Stored kernels ``(T, 21, b)`` as ``(21, N1/2+1, N2/2+1, b)`` (every ``q1, q2 >= 0``; a copy where half of
        them are stored, else the stored array itself)."""
        return NumpyLoops.unpacked(kernels, self._table, PERMUTATION)

    def infinite_spectra(self, lattice="padded"):
        """The infinite-space term's kernels: real factors ``(21, N1/2+1, N2/2+1, N3/2+1)`` of ``C : D`` (unit
        Young's modulus, Mandel basis) for ``q1, q2 >= 0``, the entries' components ``(first, second)``
        and the components' parities in x1 and x2 (an entry's is their product).

        On the lattice named (:meth:`lattice_shape`): ``"own"``, the padded lattice's even wavenumbers, i.e. the
        kernels summed over the periods of the box's own lattice (a DFT of length N taken at every other
        wavenumber is the DFT of length N/2 of the signal folded onto N/2); ``"folded"``, the kernels summed
        over the periods of :attr:`folded_shape`, made with the padded ones from the same values.
        """
        self.lattice_shape(lattice)
        if lattice == "own":     # the even q3 of each block, without joining the blocks
            blocks = sorted(self._kernel_blocks.items())
            direct = np.concatenate([self._unpacked(block[0][..., k0 % 2::2])[:, ::2, ::2] for k0, block in blocks],
                                    axis=-1)
        elif lattice == "folded" and self._folded is not None:
            direct = self._folded
        else:
            direct = self._direct
        return direct, self._entries, self._parities

    def strain(self, eigenstrain, displacement=False):
        """Total strain ``(m1, m2, m3, 6)`` (tensor shears) in the box from the eigenstrain ``(m1, m2, m3, 6)``.

        With ``displacement``, also its :meth:`surface_displacement`, as ``(strain, displacement)``: when the
        surface patch is the grid (a rolling run's box) it shares the correction's transforms.
        """
        eigenstrain = self._check(eigenstrain)
        passes = loops()
        stress = self._box_fft().apply(
            eigenstrain, lambda spectra, k0, k1, columns=None: passes.stiffness(
                spectra, *self._kernel_blocks[k0], self._items(columns), PERMUTATION, *self._entries,
                *self._parities, MIRROR),
            MANDEL, 1.0 / MANDEL, columns=self._box_fft().by_columns)
        surface = self._surface
        shared = displacement and surface is self._grid_map()
        spectra = surface.surface(eigenstrain, "traction", *(("betti",) if shared else ()), weights=CONTRACTION)
        # the traction is kept on the patch only: back to the surface, cut, and transformed again
        # in place: a 128^3 box's field is 100 MB, and a product held four of them
        surface.box_stress(surface.spectrum(surface.field(spectra[0])), add_to=stress)
        strain = stress                # Hooke's law inverted in place (unit modulus)
        passes.compliance(strain.reshape(-1, 6), self.poisson)
        if not displacement:
            return strain
        return strain, (self.spacing[2] * surface.field(spectra[1]) if shared
                        else self.surface_displacement(eigenstrain))

    def strain_at(self, points, eigenstrain, average=False):
        """Total strain ``(n, 6)`` at arbitrary points ``(n, 3)`` [m] of the half-space, by direct sums.

        The same three terms as :meth:`strain`, each summed over the box's loaded
        cuboids (and, for the Boussinesq term, the surface cells) without FFTs, so the
        points may lie anywhere in the half-space, the surface included; on a face, edge or
        corner of the cuboids (or of the surface cells, at the surface) the value is the
        one-sided limit from the cuboid on the positive side (:mod:`~framework.operators.one_sided`).
        With ``average=True`` the first two terms are averaged over a cuboid centred on each
        point, as the operator's (``average=True``) are.
        """
        from .one_sided import love_stress_at
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
        x1, x2 = (c[self.patch].ravel() for c in self.grid.coordinates())
        stress = love_stress_at(points, x1, x2, pressure.ravel(), spacing=self.grid.spacing, poisson=self.poisson)
        return strain + strain_from_stress(stress, self.poisson)
