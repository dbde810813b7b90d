"""Cuboids cut by an inhomogeneity's boundary, each taken as a two-layer laminate (sub-cell geometry).

A body of whole cuboids is a staircase: its interior mean stress converges at first order with a large
constant (a stiff sphere 1.0 % off Eshelby's over its whole cuboids at 8 cuboids per semi-axis, 0.47 %
at 16) and its boundary cuboids do not converge at all (+-11 % von Mises). Here a cuboid that the
boundary cuts keeps the body's share ``f`` of its volume (:meth:`Ellipsoid.cell_fractions`) and the
stiffness of a laminate of the two materials whose layers are parallel to the boundary there (normal
``n``): the exact effective stiffness of a cuboid split by a plane, and so of a cut cuboid as the
cuboid shrinks (the boundary is then locally flat).

In a laminate each phase's strain is uniform. Where the layers meet, the displacement is continuous,
so the strains differ by a rank-one jump ``[e] = e1 - e2 = sym(a (x) n)`` (Hadamard), and the traction
is continuous, ``(C1 e1 - C2 e2) n = 0``. With ``e1 = e + (1 - f) [e]``, ``e2 = e - f [e]`` (their
volume average is the cuboid's strain ``e``)::

    ((1 - f) C1 + f C2) : sym(a (x) n) . n = -((C1 - C2) : e) . n      ->   a = -K^-1 ((C1 - C2) : e) n

``K_ik = n_j ((1 - f) C1 + f C2)_ijkl n_l`` the acoustic tensor of the reversed mixture. The average
stress ``f C1 e1 + (1 - f) C2 e2`` is then ``C_lam : e`` with::

    C_lam = f C1 + (1 - f) C2 + f (1 - f) (C1 - C2) : M,     [e] = M : e,
    M_klrs = -1/2 (K^-1_kp n_l + K^-1_lp n_k) (C1 - C2)_pjrs n_j

(G. E. Backus, J. Geophys. Res. 67 (1962) 4427, for isotropic layers; G. W. Milton, *The Theory of
Composites* (2002), sec. 9.2, for any). ``C_lam`` has the major symmetry, lies between the Reuss and
Voigt mixtures, and is the body's stiffness at ``f = 1`` and the matrix's at ``f = 0``.

In the equivalent inclusion method (:mod:`framework.inclusions.equivalent`) a cut cuboid is then one
more material: ``C_lam : e = C_M : (e - e*)`` gives its eigenstrain ``e*``, the cuboid's share of the
body's (its average over the cuboid). Its stress in the box fields is the cuboid's mean stress
``C_lam : e``; each phase's is ``C1 : (I + (1 - f) M) : e`` and ``C2 : (I - f M) : e``
(:func:`laminate`).
"""
import numpy as np

from ..errors import ParameterError, ShapeError

#: How the cuboids hold a body (``InclusionProblem(geometry=...)``): whole cuboids whose centre it contains,
#: or those and the cuboids its boundary cuts as laminates.
GEOMETRIES = ("staircase", "laminate")


def laminate(inside, outside, fraction, normal):
    """Effective stiffness of two-layer laminates and the jump of their strain across the layers.

    Parameters
    ----------
    inside, outside : ndarray, shape (3, 3, 3, 3)
        Stiffness tensors [Pa] of the layer of volume fraction ``fraction`` (the body) and of the other
        (the matrix), global frame.
    fraction : array_like, shape (m,)
        Volume fraction of ``inside`` in each laminate, in [0, 1].
    normal : array_like, shape (m, 3)
        Normal to the layers in each laminate (any non-zero length).

    Returns
    -------
    stiffness : ndarray, shape (m, 3, 3, 3, 3)
        ``C_lam`` [Pa]: the mean stress is ``C_lam : e`` for the mean strain ``e``.
    jump : ndarray, shape (m, 3, 3, 3, 3)
        ``M``: the strain of ``inside`` minus that of ``outside`` is ``M : e``; the layers' strains are
        ``(I + (1 - f) M) : e`` and ``(I - f M) : e``.
    """
    inside, outside = np.asarray(inside, dtype=float), np.asarray(outside, dtype=float)
    for name, value in (("inside", inside), ("outside", outside)):
        if value.shape != (3, 3, 3, 3):
            raise ShapeError(f"{name} must be a stiffness tensor of shape (3, 3, 3, 3), got {value.shape}")
    fraction = np.asarray(fraction, dtype=float)
    normal = np.asarray(normal, dtype=float)
    if fraction.ndim != 1 or normal.shape != (len(fraction), 3):
        raise ShapeError(f"fraction must have shape (m,) and normal (m, 3), got {fraction.shape} and {normal.shape}")
    if not np.all((fraction >= 0.0) & (fraction <= 1.0)):
        raise ParameterError(f"fraction must lie in [0, 1], got values from {fraction.min():g} to {fraction.max():g}")
    length = np.linalg.norm(normal, axis=1)
    if not np.all(length > 0.0):
        raise ParameterError(f"normal must be non-zero vectors, got a zero one at index {int(np.argmin(length))}")
    n = normal / length[:, None]
    f = fraction[:, None, None, None, None]
    contrast = inside - outside
    acoustic = np.einsum("mj,mijkl,ml->mik", n, (1.0 - f) * inside + f * outside, n)
    traction = np.einsum("pjrs,mj->mprs", contrast, n)                    # ((C1 - C2) : e) n, per unit e
    amplitude = -np.einsum("mkp,mprs->mkrs", np.linalg.inv(acoustic), traction)
    jump = 0.5 * (np.einsum("mkrs,ml->mklrs", amplitude, n) + np.einsum("mlrs,mk->mklrs", amplitude, n))
    stiffness = (f * inside + (1.0 - f) * outside
                 + f * (1.0 - f) * np.einsum("ijkl,mklrs->mijrs", contrast, jump))
    return stiffness, jump


def phase_strains(jump, fraction, strain):
    """Strains ``(e1, e2)`` of the two layers of laminates from their mean strain (full tensors).

    Parameters
    ----------
    jump : ndarray, shape (m, 3, 3, 3, 3)
        ``M`` of :func:`laminate`.
    fraction : array_like, shape (m,)
        Volume fraction of the first layer.
    strain : ndarray, shape (m, 3, 3)
        Mean strain of each laminate.
    """
    difference = np.einsum("mijkl,mkl->mij", jump, strain)
    f = np.asarray(fraction, dtype=float)[:, None, None]
    return strain + (1.0 - f) * difference, strain - f * difference


def cut_cell_materials(owner, fraction, normal, stiffnesses, matrix_stiffness):
    """The equivalent-inclusion solver's indicator and stiffnesses with each cut cuboid a laminate.

    Parameters
    ----------
    owner : ndarray of int, shape (m1, m2, m3)
        0 in the matrix, ``k + 1`` where the ``k``-th body reaches (:meth:`InclusionSet.fractions`).
    fraction : ndarray, shape (m1, m2, m3)
        The owner's share of each cuboid.
    normal : ndarray, shape (m1, m2, m3, 3)
        The owner's outward normal at each cuboid.
    stiffnesses : sequence of ndarray (3, 3, 3, 3)
        The bodies' stiffness tensors [Pa], global frame.
    matrix_stiffness : ndarray, shape (3, 3, 3, 3)
        The matrix's stiffness tensor [Pa].

    Returns
    -------
    materials : ndarray of int32, shape (m1, m2, m3)
        0 in the matrix, ``k + 1`` in the whole cuboids of body ``k`` (as the staircase indicator), and
        ``len(stiffnesses) + j + 1`` in the ``j``-th cut cuboid (C order).
    stiffness : list of ndarray (3, 3, 3, 3)
        The bodies' stiffnesses followed by one laminate per cut cuboid.
    """
    whole = (owner > 0) & (fraction >= 1.0)
    materials = np.where(whole, owner, 0).astype(np.int32)
    cut = np.nonzero((owner > 0) & (fraction > 0.0) & (fraction < 1.0))
    bodies = owner[cut] - 1
    materials[cut] = len(stiffnesses) + 1 + np.arange(len(bodies))
    stiffness = list(stiffnesses) + [None] * len(bodies)
    for k in np.unique(bodies):
        rows = np.nonzero(bodies == k)[0]
        laminates, _ = laminate(stiffnesses[k], matrix_stiffness, fraction[cut][rows], normal[cut][rows])
        for row, value in zip(rows, laminates):
            stiffness[len(stiffnesses) + row] = value
    return materials, stiffness
