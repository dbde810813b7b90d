"""An elastic layer bonded to an elastic half-space: its surface compliance and a rigid sphere pressed on it.

The homogenised reference of a subsurface filled to a depth ``h`` (issue 26): the filled depth is a layer of the
effective material, perfectly bonded to the matrix below, which carries part of the approach.

Surface compliance
------------------
A normal surface pressure ``p cos(q x1)`` (frictionless) on a layer of thickness ``h`` (shear modulus ``G1``,
``kappa1 = 3 - 4 nu1``) bonded to a half-space (``G2``, ``kappa2``) is a plane-strain problem in the direction of
the wave vector, so the compliance depends on ``|q|`` only. With ``u1 = i U(x3) e^{i q x1}``,
``u3 = W(x3) e^{i q x1}`` (x3 the depth), Navier's equations have the decaying and growing solutions

    U = (a + B q x3) e^{-q x3},  W = -(a + kappa B + B q x3) e^{-q x3},
    U = (c - D q x3) e^{+q x3},  W =  (c + kappa D - D q x3) e^{+q x3},

(the second is the first reflected in x3), with the tractions on planes x3 = const
``sigma_33 = G q (2 a + (kappa + 1) B + 2 B q x3) e^{-q x3}``,
``sigma_13 / i = G q (-2 a + (1 - kappa) B - 2 B q x3) e^{-q x3}`` (and reflected). The layer takes both (four
constants), the half-space the decaying one (two); the surface conditions (``sigma_33 = -p``, ``sigma_13 = 0``)
and the continuity of the two displacements and two tractions at ``x3 = h`` give six linear equations whose
elimination yields (Chen & Engel, Int. J. Solids Struct. 8 (1972) 1257; O'Sullivan & King, J. Tribol. 110
(1988) 235; in this form Perriot & Barthel, J. Mater. Res. 19 (2004) 600, eq. 6)

    W(0) / p = 2 / (E1* q) * (1 + 4 b t e^{-2t} - a b e^{-4t}) / (1 - (a + b + 4 b t^2) e^{-2t} + a b e^{-4t}),

    t = q h,  alpha = G1 / G2,  a = (alpha kappa2 - kappa1) / (1 + alpha kappa2),  b = (alpha - 1) / (alpha + kappa1),

``E1* = E1 / (1 - nu1^2) = 4 G1 / (1 + kappa1)``. Limits: ``t -> inf`` gives the layer's ``2 / (E1* q)``;
``t -> 0`` the ratio ``(1 - a b) / ((1 - a)(1 - b)) = alpha (1 + kappa2) / (1 + kappa1) = E1* / E2*``, the
substrate's ``2 / (E2* q)``; equal materials ``a = b = 0``, the half-space's. The form is stable at every ``t``
(only decaying exponentials). ``tests/test_layered.py`` checks it against the six-equation system solved
numerically (a transfer matrix), to 1e-10. Complex moduli are accepted (:func:`compliance_from_moduli`): the
correspondence principle for a viscoelastic layer or substrate.

Contact of a rigid sphere
-------------------------
:func:`layered_sphere_contact` solves the frictionless contact of a rigid sphere under a load on a square grid
of uniform-pressure cells, independently of ``framework.solver``: the influence coefficients are Love's
(1929) closed form for a uniformly loaded rectangle on a half-space of the layer's material plus the
layered correction, the kernel ``g(r) = (1 / 2 pi) int_0^inf [C(q) - 2 / (E1* q)] D(q) J0(q r) q dq`` times the
cell's area, ``D(q)`` the transform of a uniform disc of the cell's area (smooth on the scale ``h``: it wants
cells below ``h``). The correction's
``q -> 0`` limit ``c0 = 2 (1/E2* - 1/E1*)`` (the far field of the substrate minus the layer) is taken out in
closed form, ``int_0^inf c0 e^{-q h} J0(q r) dq = c0 / sqrt(r^2 + h^2)``; the rest decays as ``e^{-q h}`` and is
integrated by Gauss-Legendre panels on a radial table, interpolated by a cubic spline. The discrete convolution
is the exact linear one (zero-padded FFT, Liu, Wang & Liu, Wear 243 (2000) 101); the contact problem is solved
by Polonsky & Keer's (Wear 231 (1999) 206) conjugate gradient under a given load.

Stacks and steady rolling
-------------------------
:func:`stack_compliance` stacks any layers (a bare matrix gap above a filled layer) by an impedance recursion of
the same Navier solutions. :func:`~framework.reference.layered_rolling.layered_steady_sphere` rolls a rigid sphere steadily over a viscoelastic
layer on a viscoelastic half-space: by the correspondence principle in the body's frame the compliance at
``(q1, q2)`` is the elastic one with the complex moduli at the frequency ``-V q1`` the material sees.
"""
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.special import j0, j1

from .._validation import check_non_negative, check_positive, check_positive_int
from ..errors import ConvergenceError, ParameterError

__all__ = ["LayeredSphereContact", "compliance_from_moduli", "layered_compliance", "influence_coefficients",
           "layered_point_kernel", "layered_sphere_contact", "stack_compliance"]

#: Gauss-Legendre points per panel of the correction's Hankel integral; the panel is at most a third of the
#: shortest period of J0(q r) on the table and at most h / 4 in q h (the integrand's own scale).
PANEL_POINTS = 8
#: The Hankel integral stops at q h = HANKEL_END: the rest of the correction is below e^{-40} of its start.
HANKEL_END = 40.0
#: Radial table points per layer thickness (cubic spline: its error ~ (spacing / h)^4).
TABLE_PER_THICKNESS = 40
#: Largest q t of one sublayer in :func:`stack_compliance`'s recursion (its transfer matrix's entries stay
#: below e^2, so that no cancellation loses digits).
SUBLAYER = 1.0
#: Largest surface grid side in cells (the padded FFT is twice as wide).
MAX_CELLS = 1024


def _contact_modulus(material):
    return material.young / (1.0 - material.poisson ** 2)


def compliance_from_moduli(q, thickness, layer_shear, layer_poisson, substrate_shear, substrate_poisson):
    """The layered surface compliance from shear moduli and Poisson ratios (complex moduli accepted).

    Parameters
    ----------
    q : array_like
        Wavenumbers |q| [1/m], > 0.
    thickness : float
        Layer thickness h [m], >= 0.
    layer_shear, substrate_shear : complex or float
        Shear moduli G1, G2 [Pa] (complex: the correspondence principle at one frequency).
    layer_poisson, substrate_poisson : float
        Poisson ratios nu1, nu2.

    Returns
    -------
    ndarray
        Surface normal displacement per unit pressure at each |q| [m/Pa] (complex where a modulus is).
    """
    q = np.asarray(q, dtype=float)
    kappa1, kappa2 = 3.0 - 4.0 * layer_poisson, 3.0 - 4.0 * substrate_poisson
    alpha = layer_shear / substrate_shear
    a = (alpha * kappa2 - kappa1) / (1.0 + alpha * kappa2)
    b = (alpha - 1.0) / (alpha + kappa1)
    t = q * thickness
    e2, e4 = np.exp(-2.0 * t), np.exp(-4.0 * t)
    numerator = 1.0 + 4.0 * b * t * e2 - a * b * e4
    denominator = 1.0 - (a + b + 4.0 * b * t ** 2) * e2 + a * b * e4
    with np.errstate(divide="ignore"):
        return (1.0 + kappa1) / (4.0 * layer_shear * q) * numerator / denominator


def layered_compliance(q, h, layer, substrate):
    """Surface normal compliance of an elastic layer bonded to an elastic half-space, per wavenumber.

    Parameters
    ----------
    q : array_like
        Wavenumbers |q| [1/m] (> 0; 0 gives inf, the half-space's long-wave limit).
    h : float
        Layer thickness [m], >= 0 (0: the substrate alone).
    layer, substrate : framework.materials.Elastic
        The layer's and the half-space's materials (``young`` [Pa], ``poisson``).

    Returns
    -------
    ndarray
        The surface displacement per unit pressure at each |q| [m/Pa]; between the layer's 2 / (E1* q)
        (h -> inf) and the substrate's 2 / (E2* q) (h -> 0).

    References
    ----------
    Perriot & Barthel, J. Mater. Res. 19 (2004) 600 (eq. 6); O'Sullivan & King, J. Tribol. 110 (1988) 235.
    """
    h = check_non_negative(h, name="h", unit="m")
    q = np.asarray(q, dtype=float)
    if np.any(q < 0) or not np.all(np.isfinite(q)):
        raise ParameterError(f"q must be finite wavenumbers >= 0 [1/m], got values from {q.min()} to {q.max()}")
    return compliance_from_moduli(q, h, layer.young / (2.0 * (1.0 + layer.poisson)), layer.poisson,
                                  substrate.young / (2.0 * (1.0 + substrate.poisson)), substrate.poisson)


def _navier(shear, poisson):
    """d/d(q x3) of [U, W, T/q, S/q] for u1 = i U e^{i q x1}, u3 = W e^{i q x1}, sigma_13 = i T, sigma_33 = S
    (stresses in Pa), one 4 x 4 matrix per shear modulus [Pa] in ``shear`` (complex accepted): in these scaled
    variables it does not depend on q."""
    if poisson >= 0.5:
        raise ParameterError(f"stack_compliance needs poisson < 0.5 in every layer (a finite Lame constant), "
                             f"got {poisson!r}")
    shear = np.asarray(shear)
    lame = 2.0 * shear * poisson / (1.0 - 2.0 * poisson)
    longitudinal = lame + 2.0 * shear
    out = np.zeros(shear.shape + (4, 4), dtype=np.result_type(shear, float))
    out[..., 0, 1], out[..., 0, 2] = -1.0, 1.0 / shear
    out[..., 1, 0], out[..., 1, 3] = lame / longitudinal, 1.0 / longitudinal
    out[..., 2, 0], out[..., 2, 3] = longitudinal - lame ** 2 / longitudinal, -lame / longitudinal
    out[..., 3, 2] = 1.0
    return out


#: The Hermite interpolation at the eigenvalues +-1 (each double) of the scaled Navier matrix: exp(M s) =
#: c0 + c1 M + c2 M^2 + c3 M^3 with c = _HERMITE^-1 [e^s, s e^s, e^-s, s e^-s] (values and slopes of e^{x s}).
_HERMITE = np.array([[1.0, 1.0, 1.0, 1.0], [0.0, 1.0, 2.0, 3.0], [1.0, -1.0, 1.0, -1.0], [0.0, 1.0, -2.0, 3.0]])


def stack_compliance(q, thicknesses, layers, substrate):
    """Surface normal compliance of a stack of bonded elastic layers on an elastic half-space, per wavenumber.

    The impedance recursion: the half-space's traction-displacement stiffness at its top (its decaying
    solutions, see the module's docstring) is carried up through each layer in sublayers of q t <= SUBLAYER by
    the layer's transfer matrix ``exp(M q t)`` (M the scaled Navier matrix, whose eigenvalues are +-1, each
    double: the exponential is the cubic Hermite polynomial in M); the top's stiffness gives the displacement
    under a unit pressure. Used for a matrix gap above a filled layer; with one layer it equals
    :func:`layered_compliance` (checked to 1e-10).

    Parameters
    ----------
    q : array_like
        Wavenumbers |q| [1/m], > 0.
    thicknesses : sequence of float
        Layer thicknesses from the surface down [m], >= 0.
    layers : sequence of framework.materials.Elastic
        Their materials (Poisson ratio < 0.5).
    substrate : framework.materials.Elastic
        The half-space below.

    Returns
    -------
    ndarray
        The surface displacement per unit pressure [m/Pa].
    """
    q = np.atleast_1d(np.asarray(q, dtype=float))
    if np.any(q <= 0) or not np.all(np.isfinite(q)):
        raise ParameterError(f"q must be finite wavenumbers > 0 [1/m], got values from {q.min()} to {q.max()}")
    if len(thicknesses) != len(layers):
        raise ParameterError(f"thicknesses and layers must pair up, got {len(thicknesses)} thicknesses and "
                             f"{len(layers)} layers")
    thicknesses = [check_non_negative(t, name=f"thicknesses[{i}]", unit="m") for i, t in enumerate(thicknesses)]
    shears = [np.full(q.shape, m.young / (2.0 * (1.0 + m.poisson))) for m in layers]
    return _stack(q, thicknesses, shears, [m.poisson for m in layers],
                  np.full(q.shape, substrate.young / (2.0 * (1.0 + substrate.poisson))), substrate.poisson)


def _stack(q, thicknesses, shears, poissons, substrate_shear, substrate_poisson):
    """:func:`stack_compliance` from shear moduli given per wavenumber (arrays like ``q``, complex accepted)."""
    kappa = 3.0 - 4.0 * substrate_poisson
    # the half-space's top: U = a, W = -a - kappa B; T/q = G (-2 a + (1 - kappa) B), S/q = G (2 a + (1 + kappa) B)
    to_constants = np.array([[1.0, 0.0], [-1.0 / kappa, -1.0 / kappa]])       # (a, B) from (U, W)
    tractions = np.array([[-2.0, 1.0 - kappa], [2.0, 1.0 + kappa]])
    stiffness = np.asarray(substrate_shear)[:, None, None] * (tractions @ to_constants)[None]
    inverse = np.linalg.inv(_HERMITE)
    for thickness, shear, poisson in reversed(list(zip(thicknesses, shears, poissons))):
        m = _navier(shear, poisson)
        powers = np.stack([np.broadcast_to(np.eye(4), m.shape), m, m @ m, m @ m @ m], axis=1)
        count = max(1, int(np.ceil(q.max() * thickness / SUBLAYER)))
        s = q * thickness / count
        values = np.stack([np.exp(s), s * np.exp(s), np.exp(-s), s * np.exp(-s)], axis=1)
        propagate = np.einsum("nk,nkij->nij", values @ inverse.T, powers)   # y(bottom) = P y(top) per q
        p11, p12, p21, p22 = (propagate[:, :2, :2], propagate[:, :2, 2:], propagate[:, 2:, :2],
                              propagate[:, 2:, 2:])
        for _ in range(count):
            # tau_b = K_b u_b, u_b = P11 u + P12 tau, tau_b = P21 u + P22 tau:
            # tau = (K_b P12 - P22)^-1 (P21 - K_b P11) u
            stiffness = np.linalg.solve(stiffness @ p12 - p22, p21 - stiffness @ p11)
    unit = np.linalg.solve(stiffness, np.broadcast_to(np.array([0.0, -1.0]), (q.size, 2))[..., None])[..., 0]
    return unit[:, 1] / q


def layered_point_kernel(r, h, layer, substrate, cell=0.0, gap=0.0):
    """The layered correction to a unit load's surface displacement [m/N] at distances ``r`` [m].

    ``g(r) = (1 / 2 pi) int_0^inf [C(q) - 2 / (E_top* q)] D(q) J0(q r) q dq``: the layered half-space's
    displacement minus that of a half-space of the top material (the layer's; the substrate's under a ``gap``
    [m] of the substrate's material above the layer, :func:`stack_compliance`), for the load spread uniformly
    over a disc of the area ``cell**2`` (``D = 2 J1(q rho) / (q rho)``, ``pi rho^2 = cell^2``; ``cell = 0``: a
    point load). Smooth on the scale of the top thickness; ``c0 / (2 pi r)`` far away,
    ``c0 = 2 (1/E2* - 1/E_top*)`` (0 under a gap: the same material above and below).
    """
    r = np.asarray(r, dtype=float)
    h = check_positive(h, name="h", unit="m")
    gap = check_non_negative(gap, name="gap", unit="m")
    top = layer if gap == 0 else substrate
    scale = h if gap == 0 else min(gap, h)
    e1, e2 = _contact_modulus(top), _contact_modulus(substrate)
    c0 = 2.0 * (1.0 / e2 - 1.0 / e1)
    r_max = float(np.max(r)) if r.size else 0.0
    # Gauss-Legendre panels in t = q scale over [0, HANKEL_END]
    width = min(0.25, np.pi / 3.0 / max(r_max / scale, 1e-12))
    panels = int(np.ceil(HANKEL_END / width))
    nodes, weights = np.polynomial.legendre.leggauss(PANEL_POINTS)
    edges = np.linspace(0.0, HANKEL_END, panels + 1)
    half = np.diff(edges) / 2.0
    t = ((edges[:-1] + half)[:, None] + half[:, None] * nodes[None, :]).ravel()
    w = (half[:, None] * weights[None, :]).ravel()
    q = t / scale
    rho = check_non_negative(cell, name="cell", unit="m") / np.sqrt(np.pi)
    disc = 2.0 * j1(q * rho) / (q * rho) if rho > 0 else 1.0
    if gap == 0:
        compliance = layered_compliance(q, h, layer, substrate)
    else:
        compliance = stack_compliance(q, [gap, h], [substrate, layer], substrate)
    rest = (compliance - 2.0 / (e1 * q)) * q * disc - c0 * np.exp(-q * h)
    flat = r.ravel()
    chunk = max(1, 4_000_000 // q.size)
    values = np.empty(flat.size)
    for start in range(0, flat.size, chunk):
        part = flat[start:start + chunk]
        values[start:start + chunk] = j0(np.outer(part, q)) @ (rest * w) / scale
    return (values.reshape(r.shape) + c0 / np.sqrt(r ** 2 + h ** 2)) / (2.0 * np.pi)


def _love_rectangle(x, y, half, contact_modulus):
    """Love's (1929) surface displacement [m/Pa] at (x, y) of a unit pressure on the square |x|, |y| <= half."""
    def antiderivative(u, v):
        # u ln(v + r) + v ln(u + r) less the terms in u or v alone, which the corners' differences cancel
        with np.errstate(divide="ignore", invalid="ignore"):
            first = np.where(u == 0, 0.0, u * np.arcsinh(v / np.where(u == 0, 1.0, np.abs(u))))
            second = np.where(v == 0, 0.0, v * np.arcsinh(u / np.where(v == 0, 1.0, np.abs(v))))
        return first + second
    total = (antiderivative(x + half, y + half) - antiderivative(x + half, y - half)
             - antiderivative(x - half, y + half) + antiderivative(x - half, y - half))
    return total / (np.pi * contact_modulus)


@dataclass(frozen=True)
class LayeredSphereContact:
    """A rigid sphere pressed on a layered half-space (:func:`layered_sphere_contact`).

    Attributes
    ----------
    approach : float
        Rigid-body approach of the sphere [m] (the surface displacement under its apex).
    contact_radius : float
        Radius of the disc of the contact's area [m].
    max_pressure : float
        Peak pressure [Pa].
    pressure : ndarray
        Pressure on the grid [Pa], ``(cells, cells)``, cell-centred on ``(-side/2, side/2)^2``.
    spacing : float
        The grid's cell [m].
    iterations : int
        Conjugate-gradient iterations.
    """

    approach: float
    contact_radius: float
    max_pressure: float
    pressure: np.ndarray
    spacing: float
    iterations: int


def influence_coefficients(cells, spacing, h, layer, substrate, gap=0.0):
    """Displacement [m/Pa] at cell offsets (i, j) in -(cells-1)..cells-1 of a unit pressure on one cell,
    wrapped for a zero-padded FFT of side 2 cells (offset -k at index 2 cells - k; index cells is zero);
    ``gap`` [m]: a top layer of the substrate's material above the layer."""
    offsets = np.arange(-(cells - 1), cells) * spacing
    x, y = np.meshgrid(offsets, offsets, indexing="ij")
    kernel = _love_rectangle(x, y, spacing / 2.0, _contact_modulus(layer if gap == 0 else substrate))
    if h > 0 and (layer.young != substrate.young or layer.poisson != substrate.poisson):
        r = np.hypot(x, y)
        scale = h if gap == 0 else min(h, gap)
        table = np.linspace(0.0, r.max() * (1 + 1e-9), max(64, int(np.ceil(r.max() / scale * TABLE_PER_THICKNESS))))
        spline = CubicSpline(table, layered_point_kernel(table, h, layer, substrate, cell=spacing, gap=gap))
        kernel = kernel + spline(r) * spacing ** 2
    padded = np.zeros((2 * cells, 2 * cells))
    index = np.arange(-(cells - 1), cells) % (2 * cells)
    padded[np.ix_(index, index)] = kernel
    return padded


def layered_sphere_contact(radius, load, h, layer, substrate, *, side, cells=128, gap=0.0, tolerance=1e-10,
                           max_iterations=2000):
    """Frictionless contact of a rigid sphere with an elastic layer bonded to an elastic half-space.

    Parameters
    ----------
    radius : float
        Sphere radius R [m].
    load : float
        Normal load W [N].
    h : float
        Layer thickness [m], >= 0 (0: the substrate alone).
    layer, substrate : framework.materials.Elastic
        The layer's and the half-space's materials.
    side : float
        Side of the square surface grid [m], centred on the sphere's axis; it must hold the contact.
    cells : int
        Cells along a side (the spacing is ``side / cells``); the layered correction wants cells below
        ``h`` (and ``gap``).
    gap : float
        Thickness [m] of a top layer of the substrate's material above the layer (0: the layer at the surface):
        a filled layer's bare top (:func:`stack_compliance`).
    tolerance : float
        Polonsky-Keer stopping rule: the relative change of the pressure, sum |dp| / sum p.
    max_iterations : int
        Conjugate-gradient iterations allowed.

    Returns
    -------
    LayeredSphereContact

    Raises
    ------
    ParameterError
        For a non-positive radius, load or side, or a contact that reaches the grid's edge.
    ConvergenceError
        When the conjugate gradient does not meet ``tolerance`` in ``max_iterations``.
    """
    radius = check_positive(radius, name="radius", unit="m")
    load = check_positive(load, name="load", unit="N")
    h = check_non_negative(h, name="h", unit="m")
    side = check_positive(side, name="side", unit="m")
    cells = check_positive_int(cells, name="cells", minimum=8)
    if cells > MAX_CELLS:
        raise ParameterError(f"cells must be at most {MAX_CELLS}, got {cells}")
    spacing = side / cells
    centres = (np.arange(cells) - (cells - 1) / 2.0) * spacing
    x, y = np.meshgrid(centres, centres, indexing="ij")
    profile = (x ** 2 + y ** 2) / (2.0 * radius)
    gap = check_non_negative(gap, name="gap", unit="m")
    spectrum = np.fft.rfft2(influence_coefficients(cells, spacing, h, layer, substrate, gap))

    def displacement(pressure):
        padded = np.zeros((2 * cells, 2 * cells))
        padded[:cells, :cells] = pressure
        return np.fft.irfft2(np.fft.rfft2(padded) * spectrum, s=padded.shape)[:cells, :cells]

    area = spacing ** 2
    pressure = np.where(profile < profile.max() / 16.0, 1.0, 0.0)
    pressure *= load / (pressure.sum() * area)
    direction = np.zeros_like(pressure)
    previous_norm, restart = 1.0, True
    for iteration in range(1, max_iterations + 1):
        contact = pressure > 0
        gap = displacement(pressure) + profile
        gap -= gap[contact].mean()
        norm = float(np.sum(gap[contact] ** 2))
        direction = np.where(contact, gap + (0.0 if restart else norm / previous_norm) * direction, 0.0)
        previous_norm = norm
        response = displacement(direction)
        response -= response[contact].mean()
        step = float(np.sum(gap[contact] * direction[contact]) / np.sum(response[contact] * direction[contact]))
        old = pressure.copy()
        pressure = np.maximum(pressure - step * direction, 0.0)
        overlap = (pressure == 0) & (gap < 0)
        restart = bool(overlap.any())
        pressure[overlap] -= step * gap[overlap]
        pressure *= load / (pressure.sum() * area)
        change = float(np.abs(pressure - old).sum() / pressure.sum())
        if change < tolerance:
            break
    else:
        raise ConvergenceError(f"the layered sphere contact did not converge in {max_iterations} iterations "
                               f"(relative pressure change {change:.2e}, tolerance {tolerance:.1e})")
    contact = pressure > 0
    edge = contact[0].any() or contact[-1].any() or contact[:, 0].any() or contact[:, -1].any()
    if edge:
        raise ParameterError(f"side = {side} m is too small: the contact reaches the grid's edge; expected a side "
                             f"about 3 contact radii or more")
    approach = float(np.mean((displacement(pressure) + profile)[contact]))
    return LayeredSphereContact(approach=approach, contact_radius=float(np.sqrt(contact.sum() * area / np.pi)),
                                max_pressure=float(pressure.max()), pressure=pressure, spacing=spacing,
                                iterations=iteration)
