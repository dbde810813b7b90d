"""Anisotropic linear elastic solid, and the stiffness-tensor helpers shared by every elastic material.

Voigt convention (engineering shear strains): index pairs in the order 11, 22, 33, 23, 13, 12, and
``sigma = C @ [e11, e22, e33, 2 e23, 2 e13, 2 e12]``, so that the 6x6 matrix holds the tensor's
components unscaled: ``C6[I, J] = C[i, j, k, l]`` for ``I = (i, j)``, ``J = (k, l)``.
"""
from dataclasses import dataclass, field

import numpy as np

from .._validation import LIMITS, check_finite_array, check_poisson, check_quantity
from ..errors import ParameterError, ShapeError
from .base import refuse_shift

#: Tensor index pair ``(i, j)`` of each Voigt index 0..5.
VOIGT_PAIRS = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))

#: Voigt index of each tensor index pair: ``VOIGT_INDEX[i, j]``.
VOIGT_INDEX = np.array([[0, 5, 4], [5, 1, 3], [4, 3, 2]])

#: Largest relative asymmetry ``max |C - C^T| / max |C|`` accepted in a Voigt stiffness.
SYMMETRY_TOLERANCE = 1e-10


def voigt_to_tensor(stiffness):
    """Fourth-order stiffness tensor from a 6x6 Voigt matrix.

    Parameters
    ----------
    stiffness : array_like, shape (6, 6)
        Voigt stiffness [Pa] (engineering shear strains, order 11, 22, 33, 23, 13, 12).

    Returns
    -------
    ndarray, shape (3, 3, 3, 3)
        ``C[i, j, k, l] = stiffness[VOIGT_INDEX[i, j], VOIGT_INDEX[k, l]]`` [Pa], with the minor
        symmetries by construction.
    """
    stiffness = check_finite_array(stiffness, name="stiffness", shape=(6, 6))
    return stiffness[VOIGT_INDEX[:, :, None, None], VOIGT_INDEX[None, None, :, :]]


def tensor_to_voigt(tensor):
    """6x6 Voigt matrix [Pa] of a fourth-order stiffness tensor (the inverse of :func:`voigt_to_tensor`).

    Parameters
    ----------
    tensor : array_like, shape (3, 3, 3, 3)
        Stiffness tensor [Pa] with the minor symmetries (only the components ``(i <= j, k <= l)`` of
        :data:`VOIGT_PAIRS` are read).
    """
    tensor = check_finite_array(tensor, name="tensor", shape=(3, 3, 3, 3))
    rows, cols = np.array(VOIGT_PAIRS).T
    return tensor[rows[:, None], cols[:, None], rows[None, :], cols[None, :]]


def isotropic_tensor(young, poisson):
    """Isotropic stiffness ``C_ijkl = lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk)`` [Pa], shape (3, 3, 3, 3).

    Parameters
    ----------
    young : float
        Young's modulus [Pa].
    poisson : float
        Poisson ratio in (-1, 0.5); 0.5 (incompressible) has no finite stiffness and is refused.
    """
    young = check_quantity(young, name="young", unit="Pa")
    poisson = check_poisson(poisson)
    if poisson == 0.5:
        raise ParameterError("poisson = 0.5 (incompressible) has no finite stiffness tensor; "
                             "expected poisson < 0.5 for a stiffness (e.g. 0.499)")
    lame = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson))
    shear = young / (2.0 * (1.0 + poisson))
    delta = np.eye(3)
    return (lame * np.einsum("ij,kl->ijkl", delta, delta)
            + shear * (np.einsum("ik,jl->ijkl", delta, delta) + np.einsum("il,jk->ijkl", delta, delta)))


def rotate_stiffness(tensor, rotation):
    """Stiffness tensor in a rotated frame: ``C'_ijkl = R_ip R_jq R_kr R_ls C_pqrs`` [Pa].

    Parameters
    ----------
    tensor : array_like, shape (3, 3, 3, 3)
        Stiffness [Pa] given in the frame whose axes are the columns of ``rotation``.
    rotation : array_like, shape (3, 3)
        Rotation matrix; column ``k`` is the ``k``-th axis of that frame in the global frame.

    Returns
    -------
    ndarray, shape (3, 3, 3, 3)
        The same stiffness in the global frame [Pa].
    """
    tensor = check_finite_array(tensor, name="tensor", shape=(3, 3, 3, 3))
    rotation = check_finite_array(rotation, name="rotation", shape=(3, 3))
    return np.einsum("ip,jq,kr,ls,pqrs->ijkl", rotation, rotation, rotation, rotation, tensor, optimize=True)


@dataclass(frozen=True, eq=False)
class AnisotropicElastic:
    """Linear elastic material of any anisotropy, given by its 6x6 Voigt stiffness.

    Used for inhomogeneities (:class:`framework.inclusions.Ellipsoid`, which reads the stiffness in
    the ellipsoid's own frame). Two materials compare equal when their stiffnesses are equal.

    Parameters
    ----------
    stiffness : array_like, shape (6, 6)
        Voigt stiffness [Pa], order 11, 22, 33, 23, 13, 12, engineering shear strains
        (``sigma = C @ [e11, e22, e33, 2 e23, 2 e13, 2 e12]``). Finite, symmetric to a relative
        :data:`SYMMETRY_TOLERANCE` (then made exactly symmetric), positive definite, its diagonal
        within and its other entries below the ``"Pa"`` limits of ``framework._validation.LIMITS``.
    """

    stiffness: np.ndarray = field(repr=False)

    def __post_init__(self):
        stiffness = check_finite_array(self.stiffness, name="stiffness")
        if stiffness.shape != (6, 6):
            raise ShapeError(f"stiffness must be a 6x6 Voigt matrix [Pa], got shape {stiffness.shape}")
        scale = np.max(np.abs(stiffness))
        asymmetry = np.max(np.abs(stiffness - stiffness.T))
        if asymmetry > SYMMETRY_TOLERANCE * scale:
            i, j = np.unravel_index(np.argmax(np.abs(stiffness - stiffness.T)), stiffness.shape)
            raise ParameterError(
                f"stiffness must be symmetric, got |C[{i},{j}] - C[{j},{i}]| = {asymmetry:.6g} Pa "
                f"({asymmetry / scale:.3g} of the largest entry); expected at most {SYMMETRY_TOLERANCE:g} of it")
        stiffness = 0.5 * (stiffness + stiffness.T)
        low, high = LIMITS["Pa"]
        diagonal = np.diag(stiffness)
        for i, value in enumerate(diagonal):
            if not low <= value <= high:
                raise ParameterError(f"stiffness[{i},{i}] must lie between {low:g} and {high:g} Pa, "
                                     f"the range this framework accepts, got {value!r}")
        if scale > high:
            i, j = np.unravel_index(np.argmax(np.abs(stiffness)), stiffness.shape)
            raise ParameterError(f"stiffness[{i},{j}] must be at most {high:g} Pa in magnitude, "
                                 f"the range this framework accepts, got {stiffness[i, j]!r}")
        smallest = np.linalg.eigvalsh(stiffness)[0]
        if smallest <= 0.0:
            raise ParameterError(f"stiffness must be positive definite (a stable solid), got smallest "
                                 f"eigenvalue {smallest:.6g} Pa; expected > 0")
        stiffness.setflags(write=False)
        object.__setattr__(self, "stiffness", stiffness)

    @property
    def stiffness_tensor(self):
        """Fourth-order stiffness tensor ``C_ijkl`` [Pa], shape (3, 3, 3, 3)."""
        return voigt_to_tensor(self.stiffness)

    def at(self, temperature, shift=None):
        """Refused: an elastic solid has no relaxation times for a time-temperature shift to scale.

        Raises
        ------
        ParameterError
            Always, naming the temperature received: give the stiffness at that temperature instead.
        """
        refuse_shift(self, temperature, shift, "an elastic solid has no relaxation times to shift; for the solid "
                     "at another temperature give its stiffness at that temperature")

    def __eq__(self, other):
        if not isinstance(other, AnisotropicElastic):
            return NotImplemented
        return bool(np.array_equal(self.stiffness, other.stiffness))

    def __hash__(self):
        return hash(self.stiffness.tobytes())
