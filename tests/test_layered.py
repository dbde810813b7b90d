"""An elastic layer bonded to an elastic half-space (framework/reference/layered.py), against independent solutions.

- The closed-form surface compliance against the same boundary-value problem solved numerically here: Navier's
  equations for a wave ``e^{i q x1}`` as a first-order system in depth (state: the two displacements and the two
  tractions on planes x3 = const), the layer's transfer matrix ``expm(M1 h)``, the half-space's decaying
  solutions as the null space of ``(M2 + q)^2``, and the four surface and interface conditions solved as a 4 x 4
  system: 1e-10 at q h from 0.05 to 3 for three material pairs (measured: 1.4e-14 at most).
- The stack of layers (the impedance recursion, used for a bare matrix gap above a filled layer): one layer, the
  layer cut in two, and a gap of zero thickness equal the closed form to 1e-10 (measured 1e-13); a matrix gap
  above the layer tends to the matrix's half-space at large q t and to the closed form at small q t.
- The limits: h = 0 the substrate's ``2 / (E2* q)``, q h = 60 the layer's, layer = substrate the half-space's
  (1e-12).
- The contact solve with layer = substrate against Hertz, converging with the grid (32, 64, 128 cells over 3 a:
  approach -2.8e-4, -6.2e-5, -2.2e-5; peak pressure -1.7e-3, -4.2e-4, -1.1e-4, second order).
- The grid's layered influence coefficients against the Hankel integral of the closed form: the displacement
  under the centre of a Hertz pressure (h = a/20 to a), to the grid's error of the plain half-space (2e-4 at
  128 cells).
- Thin layer: the approach's change from the substrate's Hertz grows as h (first-order perturbation: a Winkler
  term ``C2 s q h``, so ``d delta = s h p0 / E2*``; measured 0.92-0.93 of it at h = a/20 to a/5, the rest higher
  order); thick layer: the approach tends to the layer's Hertz plus ``W g(0)``, the substrate's share of a point
  load's displacement, to 1.3 % at h = 5 a and 0.4 % at h = 10 a (an (a/h)^2 remainder).
- Steady rolling on a viscoelastic stack (correspondence principle at w = -V q1, periodic spectral kernel, dense
  active set): layer = substrate against ``reference.steady_sphere`` (Love's cells with the hereditary filter by
  quadrature): friction coefficient within 0.6 % (measured +0.35 %), peak pressure 0.5 % (+0.08 %) at 24 cells;
  under a gap of the substrate (complex moduli through the stack) the closed form at a vanishing gap (1e-6);
  elastic materials: no friction (1e-12) and the static layered contact's peak pressure (8e-5 apart).
"""
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import expm, null_space

from framework.errors import ParameterError
from framework.materials import Elastic, Viscoelastic
from framework.reference import HertzSphere, steady_sphere
from framework.reference.layered import (influence_coefficients, layered_compliance, layered_sphere_contact,
                                        stack_compliance)
from framework.reference.layered_rolling import layered_steady_sphere

MATRIX = Elastic(3e9, 0.35)                   # PMMA-like
LAYER = Elastic(4.2e9, 0.33)                  # a filled layer, stiffer
PAIRS = [(LAYER, MATRIX), (Elastic(200e9, 0.3), Elastic(3e9, 0.45)), (Elastic(1e9, 0.49), Elastic(70e9, 0.22))]
RADIUS, LOAD = 10e-3, 50.0                    # sphere [m], load [N]: a = 0.48 mm on the matrix


def contact_modulus(material):
    return material.young / (1 - material.poisson ** 2)


def navier_matrix(material, unit_shear):
    """d/dx3 [U, W, T, S] = M [U, W, T, S] for u1 = i U e^{i x1}, u3 = W e^{i x1}, sigma_13 = i T e^{i x1},
    sigma_33 = S e^{i x1} (q = 1: lengths in 1/q; stresses in ``unit_shear``)."""
    shear = material.young / (2 * (1 + material.poisson)) / unit_shear
    lame = 2 * shear * material.poisson / (1 - 2 * material.poisson)
    longitudinal = lame + 2 * shear
    return np.array([[0.0, -1.0, 1.0 / shear, 0.0],
                     [lame / longitudinal, 0.0, 0.0, 1.0 / longitudinal],
                     [longitudinal - lame ** 2 / longitudinal, 0.0, 0.0, -lame / longitudinal],
                     [0.0, 0.0, 1.0, 0.0]])


def transfer_compliance(qh, layer, substrate):
    """Surface displacement per unit pressure [1 / (G2 q)] by the transfer matrix: y(0) = [U0, W0, 0, -1]."""
    unit = substrate.young / (2 * (1 + substrate.poisson))
    propagate = expm(navier_matrix(layer, unit) * qh)
    shifted = navier_matrix(substrate, unit) + np.eye(4)
    decaying = null_space(shifted @ shifted)             # the half-space's solutions ~ e^{-q x3}: two of them
    assert decaying.shape == (4, 2)
    system = np.column_stack([propagate[:, 0], propagate[:, 1], -decaying[:, 0], -decaying[:, 1]])
    unknowns = np.linalg.solve(system, propagate[:, 3])     # propagate @ y(0) = decaying @ c
    return unknowns[1]


@pytest.mark.parametrize("pair", range(len(PAIRS)))
def test_compliance_against_transfer_matrix(pair):
    """The closed form equals the 4 x 4 transfer-matrix solve to 1e-10 at q h = 0.05, 0.3, 1, 3 (any q: the
    problem scales with q)."""
    layer, substrate = PAIRS[pair]
    unit = substrate.young / (2 * (1 + substrate.poisson))
    for q in (1e2, 1e4):
        for qh in (0.05, 0.3, 1.0, 3.0):
            closed = layered_compliance(q, qh / q, layer, substrate) * unit * q
            assert closed == pytest.approx(transfer_compliance(qh, layer, substrate), rel=1e-10)


def test_compliance_limits():
    """h = 0: the substrate's 2 / (E2* q); q h = 60: the layer's; layer = substrate: the half-space's (1e-12)."""
    q = np.logspace(1, 5, 9)
    for layer, substrate in PAIRS:
        np.testing.assert_allclose(layered_compliance(q, 0.0, layer, substrate), 2 / (contact_modulus(substrate) * q),
                                   rtol=1e-12)
        for one in q:
            thick = layered_compliance(one, 60 / one, layer, substrate)
            assert thick == pytest.approx(2 / (contact_modulus(layer) * one), rel=1e-12)
        np.testing.assert_allclose(layered_compliance(q, 3e-4, layer, layer), 2 / (contact_modulus(layer) * q),
                                   rtol=1e-12)
    # in between it lies between the two, monotone in h for a stiffer layer
    values = [layered_compliance(1e3, h, LAYER, MATRIX) for h in (1e-4, 1e-3, 1e-2)]
    assert 2 / (contact_modulus(MATRIX) * 1e3) > values[0] > values[1] > values[2] > 2 / (contact_modulus(LAYER) * 1e3)


@pytest.mark.parametrize("pair", range(len(PAIRS)))
def test_stack_against_closed_form(pair):
    """stack_compliance: one layer, the layer in two pieces, a zero gap above it: the closed form to 1e-10 from
    q h = 0.01 to 100; a gap t of the substrate's material above: the substrate's 2 / (E2* q) at q t = 40
    (1e-12) and the closed form at q t = 1e-6 (1e-5)."""
    layer, substrate = PAIRS[pair]
    h = 1e-3
    q = np.logspace(1, 5, 13)
    expected = layered_compliance(q, h, layer, substrate)
    np.testing.assert_allclose(stack_compliance(q, [h], [layer], substrate), expected, rtol=1e-10)
    np.testing.assert_allclose(stack_compliance(q, [h / 3, 2 * h / 3], [layer, layer], substrate), expected, rtol=1e-10)
    np.testing.assert_allclose(stack_compliance(q, [0.0, h], [substrate, layer], substrate), expected, rtol=1e-10)
    for one in q:
        assert stack_compliance(one, [40 / one, h], [substrate, layer], substrate)[0] == pytest.approx(
            2 / (contact_modulus(substrate) * one), rel=1e-12)
        assert stack_compliance(one, [1e-6 / one, h], [substrate, layer], substrate)[0] == pytest.approx(
            layered_compliance(one, h, layer, substrate), rel=1e-5)


def test_layer_equal_to_substrate_is_hertz():
    """Layer = substrate: the approach and the peak pressure converge to Hertz with the grid (3 a wide):
    32 / 64 / 128 cells give approach errors 2.8e-4 / 6.2e-5 / 2.2e-5 and peak pressure 1.7e-3 / 4.2e-4 / 1.1e-4
    (order 2); the area's contact radius within 1.5 % (a staircase of cells)."""
    hertz = HertzSphere(radius=RADIUS, load=LOAD, contact_modulus=contact_modulus(MATRIX))
    approach, peak = [], []
    for cells in (32, 64, 128):
        out = layered_sphere_contact(RADIUS, LOAD, 1e-3, MATRIX, MATRIX, side=3 * hertz.contact_radius, cells=cells)
        approach.append(abs(out.approach / hertz.approach - 1))
        peak.append(abs(out.max_pressure / hertz.max_pressure - 1))
        assert out.contact_radius == pytest.approx(hertz.contact_radius, rel=0.015)
    assert approach[-1] < 5e-5 and peak[-1] < 2e-4, (approach, peak)
    assert approach[0] / approach[1] > 2.5 and peak[0] / peak[1] > 3.5 and peak[1] / peak[2] > 3.5, (approach, peak)


@pytest.mark.parametrize("thickness", [0.1, 0.3, 1.0])
def test_influence_coefficients_against_hankel_integral(thickness):
    """The grid's layered coefficients (Love's rectangle plus the Hankel-tabulated correction) applied to a
    Hertz pressure p0 sqrt(1 - r^2/a^2) give the centre's displacement of the Hankel integral
    ``pi p0 a / (2 E1*) + (1 / 2 pi) int (C - 2/(E1* q)) P(q) q dq`` (P: the pressure's Hankel transform,
    2 pi p0 a^2 (sin x - x cos x) / x^3) within 3e-4 at 128 cells over 3 a (the plain half-space's grid error:
    2.0e-4), for h = thickness * a (measured: the same 2.0e-4)."""
    a, p0, cells = 1e-3, 1e8, 128
    h = thickness * a
    spacing = 3 * a / cells
    centres = (np.arange(cells) - (cells - 1) / 2) * spacing
    x, y = np.meshgrid(centres, centres, indexing="ij")
    pressure = p0 * np.sqrt(np.clip(1 - (x ** 2 + y ** 2) / a ** 2, 0, None))
    padded = np.zeros((2 * cells, 2 * cells))
    padded[:cells, :cells] = pressure
    kernel = influence_coefficients(cells, spacing, h, LAYER, MATRIX)
    displacement = np.fft.irfft2(np.fft.rfft2(padded) * np.fft.rfft2(kernel), s=padded.shape)[:cells, :cells]
    centre = displacement[cells // 2 - 1:cells // 2 + 1, cells // 2 - 1:cells // 2 + 1].mean()

    def integrand(q):
        x = q * a
        transform = 2 * np.pi * p0 * a ** 2 * (np.sin(x) - x * np.cos(x)) / x ** 3
        correction = layered_compliance(q, h, LAYER, MATRIX) - 2 / (contact_modulus(LAYER) * q)
        return correction * transform * q / (2 * np.pi)
    # panels of width 1/h: the oscillating integrand in one quad call loses 3 % at small h
    correction = sum(quad(integrand, k / h, (k + 1) / h)[0] for k in range(50))
    expected = np.pi * p0 * a / (2 * contact_modulus(LAYER)) + correction
    assert centre == pytest.approx(expected, rel=3e-4)


def test_thin_layer_trend():
    """h = a/10, a/5 (128 cells over 3 a: h / cell = 4.3, 8.5): the approach falls below the substrate's Hertz
    in proportion to h, 0.9 to 1 of the first-order perturbation ``s h p0 / E2*`` (``s`` the slope of
    C E2* q / 2 in q h at 0; measured 0.917, 0.935, and 0.934 at a/20: the rest is higher order in h; 256 cells
    change them by 4e-3)."""
    hertz = HertzSphere(radius=RADIUS, load=LOAD, contact_modulus=contact_modulus(MATRIX))
    a = hertz.contact_radius
    tiny = 1e-9
    slope = (layered_compliance(1.0, tiny, LAYER, MATRIX) * contact_modulus(MATRIX) / 2 - 1) / tiny
    ratios = []
    for fraction in (0.1, 0.2):
        out = layered_sphere_contact(RADIUS, LOAD, fraction * a, LAYER, MATRIX, side=3 * a, cells=128)
        first_order = slope * fraction * a * hertz.max_pressure / contact_modulus(MATRIX)
        ratios.append((out.approach - hertz.approach) / first_order)
    assert all(0.9 < ratio < 1.0 for ratio in ratios), ratios


def test_thick_layer_trend():
    """h = 2, 5, 10 a (128 cells over 3 a): the approach exceeds the layer's Hertz by the substrate's share of a
    point load's displacement, ``W g(0)``, ``g(0) = (1 / 2 pi) int (C - 2 / (E1* q)) q dq`` (quad here), the
    ratio tending to 1 as (a/h)^2: measured 0.928, 0.987, 0.996."""
    layer_hertz = HertzSphere(radius=RADIUS, load=LOAD, contact_modulus=contact_modulus(LAYER))
    a = HertzSphere(radius=RADIUS, load=LOAD, contact_modulus=contact_modulus(MATRIX)).contact_radius
    misses = []
    for multiple in (2.0, 5.0, 10.0):
        h = multiple * a
        g0 = quad(lambda q: (layered_compliance(q, h, LAYER, MATRIX) - 2 / (contact_modulus(LAYER) * q)) * q,
                  0, 60 / h)[0] / (2 * np.pi)
        out = layered_sphere_contact(RADIUS, LOAD, h, LAYER, MATRIX, side=3 * a, cells=128)
        misses.append(abs((out.approach - layer_hertz.approach) / (LOAD * g0) - 1))
    assert misses[0] > misses[1] > misses[2] and misses[1] < 0.02 and misses[2] < 0.006, misses


def test_gap_of_substrate_above_the_layer():
    """A gap of the substrate's material above the layer (h = 2 a, 96 cells over 3 a): the approach and contact
    radius move from the layered contact's (gap 0) towards the substrate's Hertz as the gap grows (a/5, a/3, a),
    monotonically and inside that range; a gap of 0 is the closed-form path's result to 1e-12."""
    a = HertzSphere(radius=RADIUS, load=LOAD, contact_modulus=contact_modulus(MATRIX)).contact_radius
    hertz = HertzSphere(radius=RADIUS, load=LOAD, contact_modulus=contact_modulus(MATRIX))
    runs = [layered_sphere_contact(RADIUS, LOAD, 2 * a, LAYER, MATRIX, side=3 * a, cells=96, gap=gap * a)
            for gap in (0.0, 0.2, 1 / 3, 1.0)]
    approaches = [run.approach for run in runs]
    radii = [run.contact_radius for run in runs]
    assert approaches == sorted(approaches) and approaches[-1] < hertz.approach, approaches
    assert radii == sorted(radii) and radii[-1] < hertz.contact_radius * 1.01, radii
    plain = layered_sphere_contact(RADIUS, LOAD, 2 * a, LAYER, MATRIX, side=3 * a, cells=96)
    assert plain.approach == pytest.approx(approaches[0], rel=1e-12)


def test_steady_rolling_layer_equal_to_substrate():
    """A viscoelastic layer of the substrate's material (E(0) = 3 GPa relaxing to 1 GPa over 0.02 and 0.2 s) at
    V = 1 mm/s (V lambda_max = 0.82 a): the friction coefficient (0.0090) within 0.6 % of the dense steady
    reference (measured +0.35 %), its peak pressure within 0.5 % (+0.08 %), 24 cells over 3 a."""
    polymer = Viscoelastic.from_prony(e_inf=1e9, terms=[(1e9, 0.02), (1e9, 0.2)], poisson=0.35)
    a, load, speed = 0.5e-3, 19.0, 1e-3
    reference = steady_sphere(RADIUS, load, speed, polymer, 1.5 * a, 24)
    layered = layered_steady_sphere(RADIUS, load, speed, 2 * a, polymer, polymer, half_size=1.5 * a, cells=24)
    assert reference.friction_coefficient > 0.008
    assert layered.friction_coefficient == pytest.approx(reference.friction_coefficient, rel=6e-3)
    assert layered.max_pressure == pytest.approx(reference.max_pressure, rel=5e-3)


def test_steady_rolling_under_a_gap():
    """A stiffer viscoelastic layer (the polymer times 1.5) 2 a deep: a gap of 1e-9 a of the substrate above it
    (the stack's recursion with complex moduli) gives the closed form's friction to 1e-6; a gap of a/3 moves the
    friction from the layer's towards the substrate's, inside that range (16 cells over 3 a, period 12 a)."""
    polymer = Viscoelastic.from_prony(e_inf=1e9, terms=[(1e9, 0.02), (1e9, 0.2)], poisson=0.35)
    stiffer = Viscoelastic.from_prony(e_inf=1.5e9, terms=[(1.5e9, 0.02), (1.5e9, 0.2)], poisson=0.33)
    a, load, speed = 0.5e-3, 19.0, 1e-3

    def friction(layer, gap, h=2 * a):
        return layered_steady_sphere(RADIUS, load, speed, h, layer, polymer, half_size=1.5 * a, cells=16,
                                     period=12 * a, gap=gap).friction_coefficient
    bare = friction(stiffer, 0.0)
    assert friction(stiffer, 1e-9 * a) == pytest.approx(bare, rel=1e-6)
    substrate = friction(polymer, 0.0)
    assert substrate > friction(stiffer, a / 3) > bare


def test_steady_rolling_elastic_is_the_static_contact():
    """Elastic layer and substrate: rolling costs nothing (|mu| < 1e-12) and the peak pressure is the static
    layered contact's (Love plus Hankel kernel, another route) within 1e-3 (measured 8e-5), 32 cells."""
    a = 0.5e-3
    rolling = layered_steady_sphere(RADIUS, LOAD, 1e-3, 2 * a, LAYER, MATRIX, half_size=1.5 * a, cells=32)
    static = layered_sphere_contact(RADIUS, LOAD, 2 * a, LAYER, MATRIX, side=3 * a, cells=32)
    assert abs(rolling.friction_coefficient) < 1e-12
    assert rolling.max_pressure == pytest.approx(static.max_pressure, rel=1e-3)


def test_errors_name_the_parameter():
    """A negative thickness, a grid that cuts the contact: ParameterError naming them."""
    with pytest.raises(ParameterError, match="h"):
        layered_compliance(1e3, -1e-3, LAYER, MATRIX)
    with pytest.raises(ParameterError, match="side"):
        layered_sphere_contact(RADIUS, LOAD, 1e-3, LAYER, MATRIX, side=0.8e-3, cells=32)
