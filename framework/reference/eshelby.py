"""Ellipsoidal inclusions and inhomogeneities in an infinite isotropic matrix.

Closed-form references for the equivalent inclusion method:

- the Eshelby tensor of an ellipsoid (J. D. Eshelby, "The determination of
  the elastic field of an ellipsoidal inclusion, and related problems",
  Proc. R. Soc. Lond. A 241 (1957) 376-396; T. Mura, *Micromechanics of
  Defects in Solids*, 2nd ed., Nijhoff (1987), section 11, eqs. 11.16-11.19),
  with the integrals ``I_i`` written as Carlson's symmetric elliptic integral
  ``R_D`` (B. C. Carlson, "Numerical computation of real or complex elliptic
  integrals", Numer. Algorithms 10 (1995) 13-26);
- the uniform interior field of an ellipsoidal inhomogeneity (any, possibly
  anisotropic, stiffness) under a remote uniform strain (Mura section 22);
- the surface displacement of a centre of dilatation in a half-space
  (R. D. Mindlin and D. H. Cheng, "Nuclei of strain in the semi-infinite
  solid", J. Appl. Phys. 21 (1950) 926-930);
- the first-order change of an indenter's approach caused by a small
  inhomogeneity (Betti's reciprocal theorem), with the Hertz stresses on the
  axis that it needs.

Conventions: full tensors, numpy arrays of shape ``(3, 3)`` (strain, stress)
and ``(3, 3, 3, 3)`` (stiffness, Eshelby tensor) with the minor symmetries;
tensor shear strains (``eps_12``, not ``gamma_12``); SI units; stresses
positive in tension; ``x3 >= 0`` depth into the half-space.  This module uses
nothing of the framework but its input checks and exceptions, so that it can
check the framework's inclusion code.
"""
from typing import NamedTuple

import numpy as np
from scipy.special import elliprd

from .._validation import check_finite_array, check_poisson, check_positive
from ..errors import ParameterError
from .hertz import HertzSphere

#: Mandel weights: a symmetric tensor's components 11, 22, 33, 23, 13, 12 times these form a
#: vector whose dot product is the tensor contraction, so that 6x6 matrices compose like the tensors.
_MANDEL_INDEX = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))
_MANDEL_WEIGHT = np.array([1.0, 1.0, 1.0, np.sqrt(2.0), np.sqrt(2.0), np.sqrt(2.0)])

#: Imaginary step of the complex-step derivatives of R_D, relative to the argument: the derivative
#: comes out as Im(R_D(x + i h)) / h with no subtraction, exact to rounding for any h this small.
_COMPLEX_STEP = 1e-30

#: Tolerance of the checks that a matrix is a rotation and that tensors have their symmetries.
_SYMMETRY_TOLERANCE = 1e-10


class InteriorSolution(NamedTuple):
    """Uniform interior field of an ellipsoidal inhomogeneity, global frame.

    Attributes
    ----------
    eigenstrain : numpy.ndarray
        Equivalent eigenstrain eps*, shape (3, 3) [-].
    strain : numpy.ndarray
        Total strain inside, eps0 + S eps*, shape (3, 3) [-].
    stress : numpy.ndarray
        Stress inside, C_I (eps0 + S eps*), shape (3, 3) [Pa].
    """

    eigenstrain: np.ndarray
    strain: np.ndarray
    stress: np.ndarray


def isotropic_stiffness(young, poisson):
    """Stiffness tensor of an isotropic solid.

    Parameters
    ----------
    young : float
        Young's modulus E [Pa].
    poisson : float
        Poisson's ratio nu [-], -1 < nu < 0.5.

    Returns
    -------
    numpy.ndarray
        C_ijkl = lambda delta_ij delta_kl + mu (delta_ik delta_jl + delta_il delta_jk) [Pa],
        shape (3, 3, 3, 3).
    """
    young = check_positive(young, name="young", unit="Pa")
    poisson = check_poisson(poisson)
    if poisson == 0.5:
        raise ParameterError("poisson must be < 0.5 for a finite stiffness tensor, got 0.5")
    shear = young / (2.0 * (1.0 + poisson))
    lame = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson))
    delta = np.eye(3)
    return (lame * np.einsum("ij,kl->ijkl", delta, delta)
            + shear * (np.einsum("ik,jl->ijkl", delta, delta) + np.einsum("il,jk->ijkl", delta, delta)))


def _check_semi_axes(semi_axes):
    semi_axes = check_finite_array(semi_axes, name="semi_axes", shape=(3,))
    if np.any(semi_axes <= 0.0):
        raise ParameterError(f"semi_axes must all be positive [m], got {semi_axes.tolist()!r}")
    return semi_axes


def eshelby_integrals(semi_axes):
    """Eshelby's integrals I_i and I_ij of an ellipsoid (Mura 1987, eqs. 11.18-11.19).

    ``I_i = 2 pi a1 a2 a3 int_0^inf ds / ((a_i^2 + s) Delta(s))`` and
    ``I_ij = 2 pi a1 a2 a3 int_0^inf ds / ((a_i^2 + s)(a_j^2 + s) Delta(s))``,
    ``Delta(s) = sqrt((a1^2 + s)(a2^2 + s)(a3^2 + s))``.

    Parameters
    ----------
    semi_axes : array_like
        Semi-axes (a1, a2, a3) [m], any order.

    Returns
    -------
    single : numpy.ndarray
        I_i [-], shape (3,).
    double : numpy.ndarray
        I_ij [1/m^2], shape (3, 3), symmetric.

    Notes
    -----
    With Carlson's ``R_D(x, y, z) = (3/2) int_0^inf dt / (sqrt((t+x)(t+y)) (t+z)^(3/2))``
    (Carlson 1995), ``I_i = (4 pi / 3) a1 a2 a3 R_D(a_j^2, a_k^2, a_i^2)``.  Differentiating under
    the integral sign,

    - ``I_ij = -(8 pi / 3) a1 a2 a3 dR_D(y, a_k^2, a_i^2)/dy`` at ``y = a_j^2`` (i != j),
    - ``I_ii = -(8 pi / 9) a1 a2 a3 dR_D(a_j^2, a_k^2, z)/dz`` at ``z = a_i^2``,

    and the derivatives are taken by a complex step (``R_D`` is analytic off the negative real
    axis), so no difference of nearly equal numbers is formed: the result keeps its accuracy for
    equal or nearly equal semi-axes, where the usual ``I_ij = (I_j - I_i)/(a_i^2 - a_j^2)`` loses
    about ``1e-16 / delta^2``.  The integrals are evaluated on the semi-axes divided by the largest
    and scaled back, since ``I_i`` is scale-free and ``I_ij`` scales like ``1/a^2``.
    """
    semi_axes = _check_semi_axes(semi_axes)
    scale = semi_axes.max()
    axes = semi_axes / scale
    squared = axes**2
    volume_factor = np.prod(axes)
    others = [[j for j in range(3) if j != i] for i in range(3)]
    single = np.array([4.0 * np.pi / 3.0 * volume_factor * elliprd(squared[j], squared[k], squared[i])
                       for i, (j, k) in enumerate(others)])
    double = np.empty((3, 3))
    for i, (j, k) in enumerate(others):
        step = _COMPLEX_STEP * squared[i]
        derivative = elliprd(squared[j], squared[k], squared[i] + 1j * step).imag / step
        double[i, i] = -8.0 * np.pi / 9.0 * volume_factor * derivative
        for j_ in (j, k):
            k_ = 3 - i - j_
            step = _COMPLEX_STEP * squared[j_]
            derivative = elliprd(squared[j_] + 1j * step, squared[k_], squared[i]).imag / step
            double[i, j_] = -8.0 * np.pi / 3.0 * volume_factor * derivative
    # The two derivatives that give I_ij and I_ji are equal analytically; average the rounding.
    double = 0.5 * (double + double.T)
    return single, double / scale**2


def eshelby_tensor(semi_axes, poisson):
    """Eshelby tensor of an ellipsoid in an isotropic matrix, in the ellipsoid's frame.

    Parameters
    ----------
    semi_axes : array_like
        Semi-axes (a1, a2, a3) [m], along x1, x2, x3 of the ellipsoid's frame, any order,
        equal ones allowed (sphere, spheroids).
    poisson : float
        Poisson's ratio nu of the matrix [-].

    Returns
    -------
    numpy.ndarray
        S_ijkl [-], shape (3, 3, 3, 3): the uniform strain inside is ``S_ijkl eps*_kl`` for
        a uniform eigenstrain eps* (Eshelby 1957).

    Notes
    -----
    Mura (1987) eqs. 11.16, with ``c = 1 / (8 pi (1 - nu))`` and no sum on repeated indices::

        S_iiii = 3 c a_i^2 I_ii + (1 - 2 nu) c I_i
        S_iijj = c a_j^2 I_ij - (1 - 2 nu) c I_i                      (i != j)
        S_ijij = S_ijji = (c/2) (a_i^2 + a_j^2) I_ij + ((1 - 2 nu) c / 2) (I_i + I_j)

    all other components zero; the integrals come from :func:`eshelby_integrals` (Carlson 1995).
    Its relative accuracy is about 1e-14 for aspect ratios down to 1e-3 and any near-equality.
    """
    semi_axes = _check_semi_axes(semi_axes)
    poisson = check_poisson(poisson)
    single, double = eshelby_integrals(semi_axes)
    squared = semi_axes**2
    c = 1.0 / (8.0 * np.pi * (1.0 - poisson))
    tensor = np.zeros((3, 3, 3, 3))
    for i in range(3):
        tensor[i, i, i, i] = 3.0 * c * squared[i] * double[i, i] + (1.0 - 2.0 * poisson) * c * single[i]
        for j in range(3):
            if j == i:
                continue
            tensor[i, i, j, j] = c * squared[j] * double[i, j] - (1.0 - 2.0 * poisson) * c * single[i]
            shear = (0.5 * c * (squared[i] + squared[j]) * double[i, j]
                     + 0.5 * (1.0 - 2.0 * poisson) * c * (single[i] + single[j]))
            tensor[i, j, i, j] = tensor[i, j, j, i] = shear
    return tensor


def to_mandel(tensor):
    """Mandel form of a symmetric 2nd-order tensor (6,) or a minor-symmetric 4th-order one (6, 6).

    Parameters
    ----------
    tensor : numpy.ndarray
        Shape (3, 3) or (3, 3, 3, 3).

    Returns
    -------
    numpy.ndarray
        Components in the order 11, 22, 33, 23, 13, 12, shear ones times sqrt(2) (per index pair),
        so that contractions become matrix products.
    """
    rows, cols = (np.array(index) for index in zip(*_MANDEL_INDEX))
    if tensor.ndim == 2:
        return tensor[rows, cols] * _MANDEL_WEIGHT
    return (tensor[rows[:, None], cols[:, None], rows[None, :], cols[None, :]]
            * np.outer(_MANDEL_WEIGHT, _MANDEL_WEIGHT))


def from_mandel(vector):
    """Symmetric (3, 3) tensor from its Mandel vector (6,), the inverse of :func:`to_mandel`."""
    tensor = np.empty((3, 3))
    for (i, j), value, weight in zip(_MANDEL_INDEX, vector, _MANDEL_WEIGHT):
        tensor[i, j] = tensor[j, i] = value / weight
    return tensor


def rotate_tensor(tensor, rotation):
    """Components in the global frame of a tensor given in a rotated frame.

    Parameters
    ----------
    tensor : numpy.ndarray
        Shape (3, 3) or (3, 3, 3, 3), components in the frame whose axes are the columns of
        ``rotation``.
    rotation : numpy.ndarray
        Rotation matrix Q, shape (3, 3).

    Returns
    -------
    numpy.ndarray
        ``Q_ia Q_jb ... T_ab...``, same shape.
    """
    if tensor.ndim == 2:
        return np.einsum("ia,jb,ab->ij", rotation, rotation, tensor)
    return np.einsum("ia,jb,kc,ld,abcd->ijkl", rotation, rotation, rotation, rotation, tensor)


def _check_rotation(orientation):
    if orientation is None:
        return np.eye(3)
    orientation = check_finite_array(orientation, name="orientation", shape=(3, 3))
    if (np.abs(orientation.T @ orientation - np.eye(3)).max() > _SYMMETRY_TOLERANCE
            or np.linalg.det(orientation) < 0.0):
        raise ParameterError(f"orientation must be a rotation matrix (orthonormal columns, determinant +1), "
                             f"got {orientation.tolist()!r}")
    return orientation


def _check_symmetric(array, *, name, shape):
    array = check_finite_array(array, name=name, shape=shape)
    transposes = [array.T] if array.ndim == 2 else [array.transpose(1, 0, 2, 3), array.transpose(0, 1, 3, 2)]
    scale = max(np.abs(array).max(), np.finfo(float).tiny)
    if any(np.abs(array - other).max() > _SYMMETRY_TOLERANCE * scale for other in transposes):
        raise ParameterError(f"{name} must have the minor symmetries of a strain or stiffness tensor, "
                             f"got an unsymmetric array of shape {array.shape}")
    return array


def interior_solution(semi_axes, orientation, young, poisson, inclusion_stiffness, applied_strain):
    """Uniform interior field of an ellipsoidal inhomogeneity in an infinite isotropic matrix.

    Eshelby's equivalent inclusion (Eshelby 1957; Mura 1987 section 22): the inhomogeneity of
    stiffness C_I under the remote strain eps0 carries the same stress as matrix material with the
    eigenstrain eps* solving ``[(C_I - C_M) S + C_M] eps* = (C_M - C_I) eps0``; inside, the strain
    is ``eps0 + S eps*`` and the stress ``C_I (eps0 + S eps*)``, both uniform.

    Parameters
    ----------
    semi_axes : array_like
        Semi-axes (a1, a2, a3) [m].
    orientation : array_like or None
        Rotation matrix, shape (3, 3), whose columns are the directions of the semi-axes in the
        global frame; None for the global axes.
    young : float
        Young's modulus of the matrix [Pa].
    poisson : float
        Poisson's ratio of the matrix [-].
    inclusion_stiffness : array_like
        Stiffness C_I of the inhomogeneity in the global frame [Pa], shape (3, 3, 3, 3), any
        anisotropy; zero for a cavity.
    applied_strain : array_like
        Remote uniform strain eps0 in the global frame [-], shape (3, 3), symmetric.

    Returns
    -------
    InteriorSolution
        ``eigenstrain``, ``strain`` and ``stress`` inside, global frame.

    Notes
    -----
    The system is solved on the 6 components of symmetric tensors (Mandel basis), where it is
    well posed, unlike the singular 9x9 form of the full tensors.
    """
    rotation = _check_rotation(orientation)
    matrix_stiffness = isotropic_stiffness(young, poisson)
    inclusion_stiffness = _check_symmetric(inclusion_stiffness, name="inclusion_stiffness", shape=(3, 3, 3, 3))
    applied_strain = _check_symmetric(applied_strain, name="applied_strain", shape=(3, 3))
    eshelby = to_mandel(rotate_tensor(eshelby_tensor(semi_axes, poisson), rotation))
    c_matrix, c_inclusion = to_mandel(matrix_stiffness), to_mandel(inclusion_stiffness)
    applied = to_mandel(applied_strain)
    eigenstrain = np.linalg.solve((c_inclusion - c_matrix) @ eshelby + c_matrix, (c_matrix - c_inclusion) @ applied)
    strain = applied + eshelby @ eigenstrain
    return InteriorSolution(eigenstrain=from_mandel(eigenstrain), strain=from_mandel(strain),
                            stress=from_mandel(c_inclusion @ strain))


def dilatation_strength(radius, eigenstrain, poisson):
    """Strength C of the centre of dilatation equivalent to a dilating sphere.

    Parameters
    ----------
    radius : float
        Radius a of the sphere [m].
    eigenstrain : float
        Uniform dilatational eigenstrain eps* (eigenstrain tensor eps* delta_ij) [-].
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    float
        ``C = (1 + nu) eps* a^3 / (3 (1 - nu))`` [m^3]: outside the sphere, in an infinite body,
        the displacement is ``u = C x / |x|^3`` (Eshelby 1957; Mura 1987 eq. 11.50 with the
        sphere's Eshelby tensor).
    """
    radius = check_positive(radius, name="radius", unit="m")
    poisson = check_poisson(poisson)
    if not np.isfinite(eigenstrain):
        raise ParameterError(f"eigenstrain must be finite, got {eigenstrain!r}")
    return (1.0 + poisson) * eigenstrain * radius**3 / (3.0 * (1.0 - poisson))


def dilatation_surface_displacement(radial_distance, depth, strength, poisson):
    """Surface displacement of a centre of dilatation in a half-space (Mindlin & Cheng 1950).

    Parameters
    ----------
    radial_distance : array_like
        Distance r on the surface from the point above the centre [m].
    depth : float
        Depth c > 0 of the centre [m].
    strength : float
        Strength C [m^3] (infinite-body displacement ``C x / |x|^3``).
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    radial : numpy.ndarray
        ``u_r = 4 (1 - nu) C r / R^3`` [m], ``R = sqrt(r^2 + c^2)``.
    normal : numpy.ndarray
        ``u_3 = -4 (1 - nu) C c / R^3`` [m], positive into the solid: a dilatation (C > 0)
        lifts the surface.

    Notes
    -----
    Four times ``(1 - nu)`` the infinite-body field at the same point: the mirror image doubles
    ``u_r`` and cancels ``u_3``, and the Boussinesq response to the normal traction the pair leaves
    on the surface adds ``2 (1 - 2 nu) C r / R^3`` and ``-4 (1 - nu) C c / R^3``.
    """
    depth = check_positive(depth, name="depth", unit="m")
    poisson = check_poisson(poisson)
    r = np.asarray(radial_distance, dtype=float)
    distance_cubed = (r * r + depth * depth) ** 1.5
    factor = 4.0 * (1.0 - poisson) * strength / distance_cubed
    return factor * r, -factor * depth


def hertz_axis_stress(load, sphere_radius, young, poisson, depth):
    """Stress tensor on the axis of a rigid sphere pressed on an elastic half-space (Hertz).

    Parameters
    ----------
    load : float
        Normal load W [N].
    sphere_radius : float
        Radius R of the rigid sphere [m].
    young, poisson : float
        Young's modulus [Pa] and Poisson's ratio [-] of the half-space.
    depth : array_like
        Depth x3 >= 0 on the axis [m].

    Returns
    -------
    numpy.ndarray
        ``diag(s_rr, s_rr, s_zz)`` [Pa], shape ``depth.shape + (3, 3)`` (Johnson 1985, section 3.4;
        see :meth:`framework.reference.HertzSphere.axis_stress`).
    """
    contact = HertzSphere(radius=sphere_radius, load=load,
                          contact_modulus=check_positive(young, name="young", unit="Pa") / (1.0 - poisson**2))
    radial, axial = contact.axis_stress(depth, poisson)
    return _axis_tensor(radial, axial)


def hertz_axis_stress_rate(load, sphere_radius, young, poisson, depth):
    """Derivative with respect to the load of the Hertz stress on the axis.

    It is the stress of a flat punch of the current contact radius a per unit load: the increment
    of a Hertz contact adds the flat punch's pressure on the current contact area.

    Parameters
    ----------
    load, sphere_radius, young, poisson, depth
        As in :func:`hertz_axis_stress`.

    Returns
    -------
    numpy.ndarray
        ``d sigma / dW`` [1/m^2], shape ``depth.shape + (3, 3)``; with ``zeta = x3 / a``::

            ds_zz/dW = -(1 + 3 zeta^2) / (2 pi a^2 (1 + zeta^2)^2)
            ds_rr/dW = [-(1 + nu) / (1 + zeta^2) + (1 + 3 zeta^2) / (2 (1 + zeta^2)^2)] / (2 pi a^2)

    Notes
    -----
    On the axis ``sigma = p0 f(zeta)`` with ``p0 = 2 E* a / (pi R)`` and ``W = 4 E* a^3 / (3 R)``,
    so ``d sigma / dW = (f - zeta f') / (2 pi a^2)``.
    """
    young = check_positive(young, name="young", unit="Pa")
    poisson = check_poisson(poisson)
    contact = HertzSphere(radius=sphere_radius, load=load, contact_modulus=young / (1.0 - poisson**2))
    zeta = np.asarray(depth, dtype=float) / contact.contact_radius
    if np.any(zeta < 0.0):
        raise ParameterError(f"depth must be >= 0 [m], got minimum {np.min(depth)!r}")
    scale = 1.0 / (2.0 * np.pi * contact.contact_radius**2)
    axial = -(1.0 + 3.0 * zeta**2) / (1.0 + zeta**2) ** 2
    radial = -(1.0 + poisson) / (1.0 + zeta**2) - 0.5 * axial
    return _axis_tensor(scale * radial, scale * axial)


def _axis_tensor(radial, axial):
    tensor = np.zeros(np.shape(radial) + (3, 3))
    tensor[..., 0, 0] = tensor[..., 1, 1] = radial
    tensor[..., 2, 2] = axial
    return tensor


def dilute_approach_change(stress, semi_axes, orientation, young, poisson, inclusion_stiffness, load,
                           stress_rate=None):
    """First-order change of an indenter's approach caused by one small inhomogeneity.

    Parameters
    ----------
    stress : array_like
        Stress sigma0 of the homogeneous contact at the inhomogeneity [Pa], shape (3, 3).
    semi_axes, orientation, young, poisson, inclusion_stiffness
        The inhomogeneity and the matrix, as in :func:`interior_solution`.
    load : float
        Indenter load W [N], held fixed.
    stress_rate : array_like, optional
        ``d sigma0 / dW`` at the inhomogeneity along the loading [1/m^2], shape (3, 3).  Default
        ``sigma0 / W``, exact when the contact area does not depend on the load (flat punch); for
        a curved indenter pass the stress of a flat punch of the current contact area per unit
        load (:func:`hertz_axis_stress_rate` on the axis of a sphere).

    Returns
    -------
    float
        ``d_delta = V (d sigma0 / dW) : eps*`` [m], ``V = 4 pi a1 a2 a3 / 3`` and eps* the
        equivalent eigenstrain of the isolated inhomogeneity in the uniform field sigma0 (remote
        strain ``C_M^-1 sigma0``); positive when the indenter sinks deeper.

    Notes
    -----
    Derivation (Betti's reciprocal theorem).  With an eigenstrain eps* in a region Omega of a body
    loaded by surface tractions t2 and displaced by u2, and a second state (t1, u1, sigma1) of the
    same body without eigenstrain, ``int_S t1.u2 dS = int_S t2.u1 dS + int_Omega sigma1 : eps* dV``
    (write ``int sigma1 : eps2`` with ``eps2 = C^-1 sigma2 + eps*``).  To first order the
    inhomogeneity acts as the eigenstrain eps* it carries in the homogeneous field.  At the same
    load the perturbed contact is the homogeneous one at approach ``delta + d_delta`` plus a field
    w of the eigenstrain whose surface displacement vanishes on the contact area A (pressure p_w
    there, no traction elsewhere); the load balance reads ``K d_delta + int_A p_w = 0``, K =
    dW/d delta.  State 1 = the flat punch on A with unit approach (pressure q, ``u_3 = 1`` on A,
    load K, stress sigma_q): ``int_A q w_3 = 0 = int_A p_w + int_Omega sigma_q : eps*``, hence
    ``K d_delta = V sigma_q : eps*``.  An increment of load adds the flat punch's pressure on the
    current area (``d sigma0 = sigma_q d delta``), so ``d_delta = V (d sigma0/dW) : eps*``, which is
    ``W d_delta = V sigma0 : eps*`` only when sigma0 is proportional to W (fixed contact area).
    A soft inhomogeneity under compression strains more than its surroundings, in the same sense
    as the stress (eps* : sigma0 > 0): the indenter sinks deeper.
    """
    stress = _check_symmetric(stress, name="stress", shape=(3, 3))
    load = check_positive(load, name="load", unit="N")
    rate = stress / load if stress_rate is None else _check_symmetric(stress_rate, name="stress_rate", shape=(3, 3))
    applied_strain = from_mandel(np.linalg.solve(to_mandel(isotropic_stiffness(young, poisson)), to_mandel(stress)))
    semi_axes = _check_semi_axes(semi_axes)
    eigenstrain = interior_solution(semi_axes, orientation, young, poisson, inclusion_stiffness,
                                    applied_strain).eigenstrain
    volume = 4.0 * np.pi / 3.0 * np.prod(semi_axes)
    return float(volume * np.einsum("ij,ij->", rate, eigenstrain))
