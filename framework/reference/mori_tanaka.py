"""Mori-Tanaka effective stiffness of a matrix filled with spheroids, elastic or viscoelastic.

Mori & Tanaka (Acta Metall. 21, 1973) in the form of Benveniste (Mech. Mater. 6, 1987): with the
matrix stiffness ``C0`` (volume fraction ``f0 = 1 - f``), the filler's ``C1`` (fraction ``f``) and
the dilute strain concentration tensor of one spheroid in the matrix,

    A = [I + S C0^-1 (C1 - C0)]^-1        (Eshelby 1957; S the Eshelby tensor of the spheroid),

the effective stiffness is

    C* = (f0 C0 + f1 <C1 A>) (f0 I + f1 <A>)^-1,

``< >`` the average over the spheroids' orientations. The filler is isotropic, so
``<C1 A> = C1 <A>``:

- ``"aligned"``: every symmetry axis along x1 (or along a given unit vector): ``<A> = A``, C*
  transversely isotropic about that axis;
- ``"random"``: isotropic orientation. The average of a fourth-order tensor over all rotations is
  its orthogonal projection on the isotropic tensors, ``<A> = (J :: A) J + (K :: A)/5 K`` with
  ``J = (1/3) delta delta`` and ``K = I - J`` (``J :: J = 1``, ``K :: K = 5``), so that
  ``3 K* = (f0 3 K0 + f1 3 K1 a_K) / (f0 + f1 a_K)`` and
  ``2 G* = (f0 2 G0 + f1 2 G1 a_G) / (f0 + f1 a_G)``, with ``a_K = J :: A`` and ``a_G = (K :: A)/5``;
- ``"planar"``: symmetry axes spread evenly in the x1-x2 plane. Rotated by ``theta`` about x3,
  A's components are trigonometric polynomials of degree 4 in ``theta`` and period pi, so the
  :data:`PLANAR_POINTS`-point trapezoid rule over ``[0, pi)`` averages them exactly.

Spheres give the Hashin-Shtrikman bound on the matrix's side; aligned long fibres the composite
cylinder assemblage (Hill 1964, Hashin 1979), and the tests check both. ``aspect`` is the
spheroid's semi-axis along its symmetry axis over the two others (> 1 prolate fibres, < 1 oblate
discs, whose symmetry axis is then the disc's normal).

Viscoelastic matrix: correspondence principle. The framework's viscoelastic solids have a constant
Poisson ratio ``nu0``, so the matrix's Carson transform ``s C0~(s) = E0~(s) C0u`` is its Carson
Young's modulus ``E0~(s) = e_inf + sum_i E_i s tau_i / (1 + s tau_i)`` times one fixed unit
tensor; the Eshelby tensor, which depends on ``nu0`` only, is the same at every ``s``, and the
Mori-Tanaka formulas above hold at each ``s`` with ``C0 -> E0~(s) C0u`` (the filler is elastic:
``C1`` unchanged). :func:`mori_tanaka_moduli` gives the composite's Carson bulk and shear moduli
exactly, at any real ``s >= 0`` or on the imaginary axis ``s = i w`` (the dynamic moduli).

The composite's Poisson ratio is not constant in time, while a :class:`Viscoelastic` has one:
:func:`mori_tanaka_fit` (used by :func:`mori_tanaka`) keeps the contact exact and the Poisson ratio
approximate. It fits the composite's plane-strain (contact) modulus
``M~ = E~ / (1 - nu~^2) = 4 G~ (3 K~ + G~) / (3 K~ + 4 G~)``, which alone sets the surface
response of a half-space to normal pressure (the contact compliance is ``1 / M~`` in the Carson
domain), evaluated at ``s = i w`` as dynamic data ``M*(w)`` over :data:`FIT_MARGIN` decades beyond
the matrix's relaxation times, with the project's Prony fit (:func:`framework.materials.fit_prony`,
``kind="dynamic"``, times and moduli fitted). The constant Poisson ratio is the middle of the
range the composite's ``nu~(s)`` spans, and ``E(t) = (1 - nu^2) M(t)``, so that the material's
contact compliance ``(1 - nu^2) J(t)`` is the fitted one; the half-range is the Poisson ratio's
error, which reaches only the subsurface stresses (a few 1e-3 for glass in PMMA).
"""
from typing import NamedTuple

import numpy as np

from .._validation import check_positive_int, check_real
from ..errors import ParameterError
from ..materials import AnisotropicElastic, Elastic, PronyFit, Viscoelastic, fit_prony
from .eshelby import eshelby_tensor, rotate_tensor, to_mandel

__all__ = ["HomogenisedViscoelastic", "mori_tanaka", "mori_tanaka_fit", "mori_tanaka_moduli", "mori_tanaka_stiffness"]

#: Orientation distributions of the spheroids' symmetry axes by name (a unit vector is also accepted).
ORIENTATIONS = ("random", "aligned", "planar")
#: Aspect ratios accepted: the Eshelby tensor keeps ~1e-14 relative accuracy down to 1e-3
#: (:func:`framework.reference.eshelby_tensor`), and beyond 1e3 a fibre is a cylinder to 1e-5.
ASPECT_RANGE = (1e-3, 1e3)
#: Points of the trapezoid rule over the in-plane angle in [0, pi): exact for the degree-4, period-pi
#: trigonometric polynomials a rotated fourth-order tensor's components are (3 would do).
PLANAR_POINTS = 6
#: How far from 1 the length of an orientation vector may be (then normalised): typed decimals such as 0.7071.
UNIT_TOLERANCE = 1e-4
#: Decades of frequency beyond the matrix's fastest and slowest relaxation (1/tau) that the fit's dynamic
#: data cover: at 2 decades the matrix's modulus is within 1e-4 of its glassy and relaxed values there, and
#: the composite's extra relaxation times lie between and next to the matrix's (they are where E0~(s) takes
#: fixed negative values: one in each interval between its poles, -1/tau_i).
FIT_MARGIN = 2.0
#: Frequencies per decade of the fit's data.
FIT_POINTS_PER_DECADE = 20

# Mandel forms of the isotropic projectors: J = (1/3) delta delta (bulk), K = I - J (deviatoric).
_TRACE = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
_BULK = np.outer(_TRACE, _TRACE) / 3.0
_DEVIATORIC = np.eye(6) - _BULK
# Mandel to Voigt (engineering shear strains): C_voigt = C_mandel / (w w^T), w = (1, 1, 1, sqrt 2 x 3).
_MANDEL_WEIGHT = np.array([1.0, 1.0, 1.0, np.sqrt(2.0), np.sqrt(2.0), np.sqrt(2.0)])


class HomogenisedViscoelastic(NamedTuple):
    """The outcome of :func:`mori_tanaka_fit`.

    Attributes
    ----------
    material : Viscoelastic
        The composite with the fitted contact modulus and the constant Poisson ratio ``poisson``.
    fit : PronyFit
        The dynamic Prony fit of ``(1 - poisson^2) M*(w)`` (its ``max_relative_error`` over the data).
    frequencies : numpy.ndarray
        The angular frequencies of the fitted data [rad/s].
    poisson_range : tuple of float
        Smallest and largest Poisson ratio ``nu~(s)`` of the composite over real ``s`` from the relaxed
        to the glassy state; the material's is their middle.
    """

    material: Viscoelastic
    fit: PronyFit
    frequencies: np.ndarray
    poisson_range: tuple


def _unit_stiffness(poisson):
    """Mandel stiffness of an isotropic solid of unit Young's modulus, (6, 6)."""
    shear = 0.5 / (1.0 + poisson)
    bulk = 1.0 / (3.0 * (1.0 - 2.0 * poisson))
    return 3.0 * bulk * _BULK + 2.0 * shear * _DEVIATORIC


def _check_materials(matrix, filler):
    if not isinstance(filler, Elastic):
        raise ParameterError(f"filler must be an isotropic materials.Elastic(young, poisson), got "
                             f"{type(filler).__name__}; expected elastic isotropic particles or fibres")
    if not isinstance(matrix, (Elastic, Viscoelastic)):
        raise ParameterError(f"matrix must be a materials.Elastic or a materials.Viscoelastic (Prony series with a "
                             f"relaxed modulus), got {type(matrix).__name__}")
    for name, material in (("matrix", matrix), ("filler", filler)):
        if material.poisson == 0.5:
            raise ParameterError(f"{name}.poisson must be < 0.5 (an incompressible solid has no finite bulk "
                                 f"modulus), got 0.5; use e.g. 0.499")


def _check_fraction(fraction):
    fraction = check_real(fraction, name="fraction")
    if not 0.0 <= fraction <= 1.0:
        raise ParameterError(f"fraction must lie in [0, 1] (the filler's volume fraction), got {fraction!r}")
    return fraction


def _check_aspect(aspect):
    aspect = check_real(aspect, name="aspect")
    low, high = ASPECT_RANGE
    if not low <= aspect <= high:
        raise ParameterError(f"aspect must lie between {low:g} and {high:g} (the spheroid's axial semi-axis over the "
                             f"others: 1 spheres, > 1 fibres, < 1 discs), got {aspect!r}")
    return aspect


def _axis_rotation(axis):
    """Rotation whose first column is the unit vector ``axis`` (the rest: any orthonormal completion)."""
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    second = np.cross(axis, helper)
    second /= np.linalg.norm(second)
    return np.column_stack([axis, second, np.cross(axis, second)])


def _check_orientation(orientation):
    """``"random"``, or the list of rotations of the symmetry axis (x1) to average over."""
    if isinstance(orientation, str):
        if orientation == "random":
            return orientation
        if orientation == "aligned":
            return [np.eye(3)]
        if orientation == "planar":
            angles = np.pi * np.arange(PLANAR_POINTS) / PLANAR_POINTS
            return [_axis_rotation(np.array([np.cos(a), np.sin(a), 0.0])) for a in angles]
    else:
        try:
            axis = np.asarray(orientation, dtype=float)
        except (TypeError, ValueError):
            axis = None
        if axis is not None and axis.shape == (3,) and np.all(np.isfinite(axis)) \
                and abs(np.linalg.norm(axis) - 1.0) <= UNIT_TOLERANCE:
            return [_axis_rotation(axis / np.linalg.norm(axis))]
    raise ParameterError(f"orientation must be one of {', '.join(map(repr, ORIENTATIONS))} or a unit vector "
                         f"(3 components) along which the spheroids are aligned, got {orientation!r}")


def _check_carson(s):
    """Carson variables: real s >= 0 (inf allowed), or complex ones with Re(s) >= 0, not 0 + 0j."""
    try:
        s = np.asarray(s)
        s = s.astype(complex if np.iscomplexobj(s) else float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"s must be Carson (Laplace) variables, real >= 0 or complex with Re(s) >= 0 "
                             f"[1/s], got {type(s).__name__}") from exc
    if np.iscomplexobj(s):
        bad = ~np.isfinite(s) | (s.real < 0) | (s == 0)
    else:
        bad = np.isnan(s) | (s < 0)
    if np.any(bad):
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        raise ParameterError(f"s must be Carson (Laplace) variables, real >= 0 (inf allowed) or complex with "
                             f"Re(s) >= 0 and finite [1/s], got {s[index].item()!r} at index {index}")
    return s


def _carson_young(matrix, s):
    """Carson Young's modulus ``E0~(s) = e_inf + sum_i E_i s tau_i / (1 + s tau_i)`` [Pa], shape of s."""
    if isinstance(matrix, Elastic):
        return np.full(s.shape, matrix.young, dtype=s.dtype)
    e_inf, terms = matrix.relaxation_terms
    value = np.full(s.shape, e_inf, dtype=s.dtype)
    for modulus, tau in terms:
        x = s * tau
        with np.errstate(divide="ignore", invalid="ignore"):
            arm = np.where(x == 0, 0.0, 1.0 / (1.0 + 1.0 / np.where(x == 0, 1.0, x)))   # s tau/(1 + s tau), inf -> 1
        value = value + modulus * arm
    return value


def _effective(matrix_young, matrix_poisson, filler, fraction, aspect, orientation):
    """Mandel stiffness C* [Pa], shape ``matrix_young.shape + (6, 6)`` (real or complex with the moduli)."""
    unit_matrix, unit_filler = _unit_stiffness(matrix_poisson), _unit_stiffness(filler.poisson)
    ratio = (filler.young / matrix_young)[..., None, None]                     # E1 / E0
    # C0^-1 (C1 - C0) = (E1/E0) C0u^-1 C1u - I, so A = [I - S + (E1/E0) S C0u^-1 C1u]^-1
    contrast = np.linalg.solve(unit_matrix, unit_filler)
    eshelby = eshelby_tensor((aspect, 1.0, 1.0), matrix_poisson)
    if isinstance(orientation, str):                                          # random: isotropic projection
        local = to_mandel(eshelby)
        concentration = np.linalg.inv(np.eye(6) - local + ratio * (local @ contrast))
        bulk = np.einsum("ij,...ji->...", _BULK, concentration)
        deviatoric = np.einsum("ij,...ji->...", _DEVIATORIC, concentration) / 5.0
        average = bulk[..., None, None] * _BULK + deviatoric[..., None, None] * _DEVIATORIC
    else:
        average = 0.0
        for rotation in orientation:
            turned = to_mandel(rotate_tensor(eshelby, rotation))
            average = average + np.linalg.inv(np.eye(6) - turned + ratio * (turned @ contrast))
        average = average / len(orientation)
    others = 1.0 - fraction
    numerator = others * unit_matrix + fraction * ratio * (unit_filler @ average)
    # C* (f0 I + f1 <A>) = numerator, solved as the transpose system: X^T = (f0 I + f1 <A>)^-T numerator^T
    denominator = others * np.eye(6) + fraction * average
    unit_effective = np.swapaxes(np.linalg.solve(np.swapaxes(denominator, -1, -2), np.swapaxes(numerator, -1, -2)),
                                 -1, -2)
    return matrix_young[..., None, None] * unit_effective


def _isotropic_moduli(stiffness):
    """Bulk and shear moduli of the isotropic projection of Mandel stiffnesses (..., 6, 6)."""
    bulk = np.einsum("ij,...ji->...", _BULK, stiffness) / 3.0
    shear = np.einsum("ij,...ji->...", _DEVIATORIC, stiffness) / 10.0
    return bulk, shear


def mori_tanaka_stiffness(matrix, filler, fraction, aspect=1.0, orientation="random", s=None):
    """Mori-Tanaka stiffness of a matrix with spheroidal filler, 6x6 Voigt (Benveniste 1987).

    Parameters
    ----------
    matrix : Elastic or Viscoelastic
        The matrix (a viscoelastic one with its constant Poisson ratio).
    filler : Elastic
        The particles or fibres, isotropic.
    fraction : float
        Volume fraction of the filler, in [0, 1] [-].
    aspect : float
        Semi-axis along the spheroid's symmetry axis over the others [-]: 1 spheres, > 1 fibres, < 1 discs.
    orientation : str or array_like
        ``"random"`` (isotropic), ``"aligned"`` (symmetry axes along x1), ``"planar"`` (spread evenly in the
        x1-x2 plane) or a unit vector (aligned along it).
    s : array_like, optional
        Carson variables [1/s] (real >= 0, or ``i w`` for dynamic moduli) at which the correspondence principle
        takes the matrix's Carson modulus; default: the elastic matrix, or the glassy (``s = inf``) state of a
        viscoelastic one.

    Returns
    -------
    numpy.ndarray
        Voigt stiffness [Pa] (order 11, 22, 33, 23, 13, 12, engineering shear strains, as
        :class:`~framework.materials.AnisotropicElastic`), shape (6, 6), or ``np.shape(s) + (6, 6)``;
        with ``s``: the Carson transform ``s C*~(s)`` (complex for complex ``s``).
    """
    _check_materials(matrix, filler)
    fraction, aspect = _check_fraction(fraction), _check_aspect(aspect)
    orientation = _check_orientation(orientation)
    carson = _check_carson(np.inf if s is None else s)
    stiffness = _effective(_carson_young(matrix, carson), matrix.poisson, filler, fraction, aspect, orientation)
    return stiffness / np.outer(_MANDEL_WEIGHT, _MANDEL_WEIGHT)


def mori_tanaka_moduli(matrix, filler, fraction, s, aspect=1.0):
    """Exact Carson bulk and shear moduli of the randomly oriented composite (correspondence principle).

    Parameters
    ----------
    matrix, filler, fraction, aspect
        As in :func:`mori_tanaka_stiffness`.
    s : array_like
        Carson variables [1/s]: real >= 0 (0 the relaxed state, inf the glassy one), or complex with
        ``Re(s) >= 0`` (``s = i w``: the dynamic moduli at angular frequency w [rad/s]).

    Returns
    -------
    bulk, shear : numpy.ndarray
        ``s K~(s)`` and ``s G~(s)`` [Pa], shape of ``s``, complex for complex ``s``. For an elastic matrix, the
        composite's bulk and shear moduli at every ``s``.
    """
    _check_materials(matrix, filler)
    fraction, aspect = _check_fraction(fraction), _check_aspect(aspect)
    carson = _check_carson(s)
    return _isotropic_moduli(_effective(_carson_young(matrix, carson), matrix.poisson, filler, fraction, aspect,
                                        "random"))


def _poisson_of(bulk, shear):
    return (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear))


def mori_tanaka_fit(matrix, filler, fraction, aspect=1.0, *, n_terms=None):
    """Randomly oriented composite of a viscoelastic matrix as a Prony series, with the fit's details.

    Parameters
    ----------
    matrix : Viscoelastic
        The matrix (Prony series, constant Poisson ratio).
    filler, fraction, aspect
        As in :func:`mori_tanaka_stiffness`.
    n_terms : int, optional
        Prony terms of the fit; default: the fewest the fit's own rule accepts
        (:func:`framework.materials.fit_prony`).

    Returns
    -------
    HomogenisedViscoelastic
        The material, the fit, its frequencies and the composite's Poisson-ratio range.

    Notes
    -----
    The fitted data are ``(1 - nu^2) M*(w)``, ``M* = 4 G* (3 K* + G*) / (3 K* + 4 G*)`` the composite's dynamic
    contact modulus (:func:`mori_tanaka_moduli` at ``s = i w``), over ``w`` from ``10^-FIT_MARGIN / tau_max`` to
    ``10^FIT_MARGIN / tau_min``, :data:`FIT_POINTS_PER_DECADE` per decade; ``nu`` the middle of the composite's
    Poisson ratios at real ``s`` (module docstring).
    """
    if not isinstance(matrix, Viscoelastic):
        raise ParameterError(f"matrix must be a materials.Viscoelastic for a fitted relaxation function, got "
                             f"{type(matrix).__name__}; for an elastic matrix use mori_tanaka")
    _check_materials(matrix, filler)
    fraction, aspect = _check_fraction(fraction), _check_aspect(aspect)
    if not matrix.terms:
        raise ParameterError("matrix has no relaxation terms (an elastic solid as a Viscoelastic), so the composite "
                             "is elastic and has nothing to fit; use mori_tanaka, which returns it")
    if fraction == 1.0:
        raise ParameterError("fraction must be < 1 for a fitted relaxation function, got 1.0: the composite is then "
                             "the elastic filler, which mori_tanaka returns")
    if n_terms is not None:
        n_terms = check_positive_int(n_terms, name="n_terms")
    times = matrix.relaxation_times
    real = np.concatenate([[0.0], np.geomspace(1e-3 / times.max(), 1e3 / times.min(), 61), [np.inf]])
    bulk, shear = mori_tanaka_moduli(matrix, filler, fraction, real, aspect)
    ratios = _poisson_of(bulk, shear)
    poisson_range = (float(ratios.min()), float(ratios.max()))
    poisson = 0.5 * (poisson_range[0] + poisson_range[1])
    decades = np.log10(times.max() / times.min()) + 2.0 * FIT_MARGIN
    w = np.geomspace(10.0**-FIT_MARGIN / times.max(), 10.0**FIT_MARGIN / times.min(),
                     int(np.ceil(decades * FIT_POINTS_PER_DECADE)) + 1)
    bulk, shear = mori_tanaka_moduli(matrix, filler, fraction, 1j * w, aspect)
    contact = 4.0 * shear * (3.0 * bulk + shear) / (3.0 * bulk + 4.0 * shear)
    fit = fit_prony(frequencies=w, complex_modulus=(1.0 - poisson**2) * contact, kind="dynamic", n_terms=n_terms,
                    poisson=poisson)
    return HomogenisedViscoelastic(material=fit.material, fit=fit, frequencies=w, poisson_range=poisson_range)


def mori_tanaka(matrix, filler, fraction, aspect=1.0, orientation="random", *, n_terms=None):
    """Effective material of a matrix filled with spheroids, by Mori-Tanaka (Benveniste 1987).

    Parameters
    ----------
    matrix : Elastic or Viscoelastic
        The matrix, isotropic.
    filler : Elastic
        The particles or fibres, isotropic.
    fraction : float
        Volume fraction of the filler, in [0, 1] [-] (0 gives the matrix, 1 the filler).
    aspect : float
        Semi-axis along the spheroid's symmetry axis over the others [-]: 1 spheres, > 1 fibres (prolate),
        < 1 discs (oblate), between 1e-3 and 1e3.
    orientation : str or array_like
        ``"random"`` (isotropic orientation), ``"aligned"`` (symmetry axes along x1), ``"planar"`` (spread evenly
        in the x1-x2 plane) or a unit vector to align them along.
    n_terms : int, optional
        Viscoelastic matrix: Prony terms of the fitted composite (:func:`mori_tanaka_fit`).

    Returns
    -------
    Elastic, AnisotropicElastic or Viscoelastic
        Elastic matrix: an :class:`Elastic` for random orientation, an :class:`AnisotropicElastic` (6x6 Voigt
        stiffness, transversely isotropic) otherwise. Viscoelastic matrix (random orientation only): the
        :class:`Viscoelastic` fitted by :func:`mori_tanaka_fit` (exact contact modulus to the fit's error,
        Poisson ratio constant within the composite's range).

    Raises
    ------
    ParameterError
        A filler that is not :class:`Elastic`, a matrix that is neither :class:`Elastic` nor
        :class:`Viscoelastic`, a fraction outside [0, 1], an aspect outside :data:`ASPECT_RANGE`, an unknown
        orientation, or an anisotropic orientation with a viscoelastic matrix.
    """
    _check_materials(matrix, filler)
    fraction, aspect = _check_fraction(fraction), _check_aspect(aspect)
    checked = _check_orientation(orientation)
    if isinstance(matrix, Viscoelastic):
        if not isinstance(checked, str):
            raise ParameterError(f"orientation {orientation!r} makes the composite of a viscoelastic matrix "
                                 f"anisotropic, and the framework's viscoelastic materials are isotropic; expected "
                                 f"orientation='random', or mori_tanaka_stiffness(..., s=...) for its Carson stiffness")
        if fraction == 0.0:
            return matrix
        if fraction == 1.0 or not matrix.terms:
            glassy = mori_tanaka(Elastic(matrix.instantaneous_modulus, matrix.poisson), filler, fraction, aspect)
            return Viscoelastic.from_prony(e_inf=glassy.young, terms=(), poisson=glassy.poisson)
        return mori_tanaka_fit(matrix, filler, fraction, aspect, n_terms=n_terms).material
    if isinstance(checked, str):
        bulk, shear = mori_tanaka_moduli(matrix, filler, fraction, np.inf, aspect)
        bulk, shear = float(bulk), float(shear)
        return Elastic(young=9.0 * bulk * shear / (3.0 * bulk + shear), poisson=float(_poisson_of(bulk, shear)))
    return AnisotropicElastic(mori_tanaka_stiffness(matrix, filler, fraction, aspect, orientation))
