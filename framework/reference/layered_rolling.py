"""Steady rolling of a rigid sphere over a viscoelastic layer (or a gap of matrix and a layer) on a viscoelastic
half-space: the homogenised reference of a filled depth's rolling friction (issue 26).

The correspondence principle in the body's frame turns the elastic layered compliance of
:mod:`framework.reference.layered` into the steady viscoelastic one, at the frequency each surface wave is carried
through the material with.
"""
from dataclasses import dataclass

import numpy as np

from .._validation import check_non_negative, check_positive, check_positive_int
from ..errors import ParameterError
from .layered import _stack, compliance_from_moduli

__all__ = ["LayeredSteadySphere", "layered_steady_sphere"]


def _shear_moduli(material, frequency):
    """Complex shear moduli [Pa] at signed frequencies (``E*(-w) = conj E*(w)``; 0: the relaxed modulus)."""
    magnitude = np.maximum(np.abs(frequency), 1e-300)
    young = material.complex_modulus(magnitude)
    young = np.where(frequency < 0, np.conj(young), young)
    return young / (2.0 * (1.0 + material.poisson))


@dataclass(frozen=True)
class LayeredSteadySphere:
    """Steady rolling of a rigid sphere over a viscoelastic layer on a viscoelastic half-space.

    Attributes
    ----------
    approach : float
        Rigid-body approach [m] (up to the periodic images' constant: only differences are meaningful).
    friction_coefficient : float
        Rolling resistance over the load, ``sum p x1 dA / (R W)`` (positive: the pressure leans ahead).
    contact_area : float
        Area of the cells in contact [m^2].
    max_pressure : float
        Peak pressure [Pa].
    pressure : ndarray
        ``(cells, cells)`` [Pa], axis 0 along the motion, cell-centred on ``(-half_size, half_size)^2``.
    """

    approach: float
    friction_coefficient: float
    contact_area: float
    max_pressure: float
    pressure: np.ndarray


def layered_steady_sphere(radius, load, velocity, h, layer, substrate, *, half_size, cells, period=None, gap=0.0):
    """Steady rolling (frictionless sliding) of a rigid sphere over a viscoelastic layer bonded to a half-space.

    Correspondence principle in the body's frame: a surface wave ``e^{i q . x}`` is carried by the material at the
    frequency ``w = -V q1`` (V along x1), so its compliance is the elastic layered one (:func:`compliance_from_moduli`)
    with the complex shear moduli ``E*(w) / (2 (1 + nu))`` of the layer and the substrate at that ``w``
    (``E*(-w) = conj E*(w)``; the framework's materials have a constant Poisson ratio). The influence coefficients
    of uniform-pressure cells come from that spectrum on a periodic grid of side ``period`` (the cells' transform,
    ``sinc(q1 dx / 2) sinc(q2 dx / 2)``, and no q = 0 term: under a given load a constant only moves the approach),
    and the contact problem, not symmetric, is solved exactly by the dense active set of
    :mod:`framework.reference.rolling`.

    Parameters
    ----------
    radius : float
        Sphere radius R [m].
    load : float
        Normal load W [N].
    velocity : float
        Velocity V of the body along x1 [m/s].
    h : float
        Layer thickness [m], >= 0.
    layer, substrate : material
        Framework materials with ``complex_modulus(w)`` and a constant ``poisson`` (Elastic, Viscoelastic,
        ``reference.mori_tanaka`` of a viscoelastic matrix).
    half_size : float
        Half-side of the square contact grid [m]; it must hold the contact.
    cells : int
        Cells per side of the contact grid, 4 to 64 (dense matrix of ``cells**4`` entries).
    period : float, optional
        Side of the periodic grid [m] (default ``64 * half_size``). The material passes under the body once a
        period: its memory of the last pass fades as ``exp(-period / (V tau))`` and the images' pull as
        ``(a / period)^3``. Against ``reference.steady_sphere`` (layer = substrate, V tau_max = 6.7 a, 32
        cells over 3 a): the friction coefficient -7.2 %, -0.33 %, +0.13 % off at 8, 32, 96 half-sizes.
    gap : float
        Thickness [m] of a top layer of the substrate's material above the layer (:func:`stack_compliance`).

    Returns
    -------
    LayeredSteadySphere
    """
    from .rolling import solve_dense_contact

    radius = check_positive(radius, name="radius", unit="m")
    load = check_positive(load, name="load", unit="N")
    h = check_non_negative(h, name="h", unit="m")
    half_size = check_positive(half_size, name="half_size", unit="m")
    cells = check_positive_int(cells, name="cells", minimum=4)
    if cells > 64:
        raise ParameterError(f"cells must be at most 64 for a dense solve (cells**4 matrix entries), got {cells}")
    spacing = 2.0 * half_size / cells
    period = 64.0 * half_size if period is None else check_positive(period, name="period", unit="m")
    size = max(2 * cells, int(np.ceil(period / spacing / 2.0)) * 2)
    wavenumbers = 2.0 * np.pi * np.fft.fftfreq(size, spacing)
    q1, q2 = np.meshgrid(wavenumbers, wavenumbers, indexing="ij")
    q = np.hypot(q1, q2)
    frequency = -float(velocity) * q1
    q_safe = np.where(q > 0, q, 1.0)
    gap = check_non_negative(gap, name="gap", unit="m")
    layer_shear, substrate_shear = _shear_moduli(layer, frequency), _shear_moduli(substrate, frequency)
    if gap == 0:
        spectrum = compliance_from_moduli(q_safe, h, layer_shear, layer.poisson, substrate_shear, substrate.poisson)
    else:
        spectrum = _stack(q_safe.ravel(), [gap, h], [substrate_shear.ravel(), layer_shear.ravel()],
                          [substrate.poisson, layer.poisson], substrate_shear.ravel(),
                          substrate.poisson).reshape(q.shape)
    cell = np.sinc(q1 * spacing / (2 * np.pi)) * np.sinc(q2 * spacing / (2 * np.pi))
    spectrum = np.where(q > 0, spectrum, 0.0) * cell
    kernel = np.fft.ifft2(spectrum).real
    index = np.arange(cells)
    along = (index[:, None] - index[None, :]) % size
    matrix = kernel[along[:, None, :, None], along[None, :, None, :]].reshape(cells ** 2, cells ** 2)
    centres = (index - (cells - 1) / 2.0) * spacing
    x1, x2 = np.meshgrid(centres, centres, indexing="ij")
    heights = (x1 ** 2 + x2 ** 2) / (2.0 * radius)
    area = spacing ** 2
    start = np.hypot(x1, x2).ravel() < half_size / 2.0
    pressure, approach, _, _, _ = solve_dense_contact(matrix, heights.ravel(), area, load, start)
    pressure = pressure.reshape(cells, cells)
    contact = pressure > 0
    if contact[0].any() or contact[-1].any() or contact[:, 0].any() or contact[:, -1].any():
        raise ParameterError(f"half_size = {half_size} m is too small: the contact reaches the grid's edge")
    friction = np.sign(velocity) * np.sum(pressure * x1) * area / (radius * load) if velocity != 0 else 0.0
    return LayeredSteadySphere(approach=float(approach), friction_coefficient=float(friction),
                               contact_area=float(contact.sum() * area), max_pressure=float(pressure.max()),
                               pressure=pressure)
