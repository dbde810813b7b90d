"""Scale separation without contact: a ball of small glass spheres against Mori-Tanaka (issue 26).

The cloud's effective bulk and shear moduli are read from ``fw.solve_inclusions`` under the six unit strains
(the whole effective stiffness, projected isotropically; the fast case: a hydrostatic and one deviatoric
strain) by Hill's condition over the cloud's ball (``<sigma> = C* <eps>``, the mean strain from the
eigenstrains, ``<eps> = C_M^-1 <sigma> + <e*>``) and, independently, from the mean strain alone as the dilute
concentration of an Eshelby sphere (``bench/filled_cloud.py`` holds the placement and the extraction).
References written here: the Mori-Tanaka moduli of spheres in closed form (Benveniste 1987;
equal to the Hashin-Shtrikman bound on the matrix's side, Hashin & Shtrikman 1963) and the upper
Hashin-Shtrikman bound, which the measured moduli must lie between up to the staircase error.

- One sphere of a known material (the 10 % composite's Mori-Tanaka material, 4 cuboids per radius): the
  extraction returns its moduli within the staircase error (measured -0.85 % bulk, -1.24 % shear by Hill).
- 20 spheres of 6 cuboids per diameter, two loads (fast): within 5 % of Mori-Tanaka (one deviatoric
  direction of a small cloud sees its anisotropy: 0.1 to 2.3 % above Mori-Tanaka with the direction).
- 100 spheres of 8 cuboids per diameter (slow, 217 s here): within 3 %.
- The finite-size trend (slow, 254 s here): the same 25-sphere cloud at 6, 8 and 12 cuboids per
  diameter; the excess over Mori-Tanaka shrinks with the cuboid size; its straight line meets zero size at
  about +1 % in shear and +0.25 % in bulk.
"""
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "bench"))

import filled_cloud as cloud  # noqa: E402
from framework import materials  # noqa: E402
from framework.reference import mori_tanaka  # noqa: E402


def moduli(material):
    """Bulk and shear moduli [Pa] of an isotropic elastic material, written out."""
    return material.young / (3 * (1 - 2 * material.poisson)), material.young / (2 * (1 + material.poisson))


def mori_tanaka_spheres(matrix, filler, fraction):
    """Mori-Tanaka (Benveniste 1987) bulk and shear moduli [Pa] of spheres, closed form."""
    k0, g0 = moduli(matrix)
    k1, g1 = moduli(filler)
    zeta = g0 * (9 * k0 + 8 * g0) / (6 * (k0 + 2 * g0))
    bulk = k0 + fraction * (k1 - k0) * (3 * k0 + 4 * g0) / (3 * k0 + 4 * g0 + 3 * (1 - fraction) * (k1 - k0))
    shear = g0 + fraction * (g1 - g0) * (g0 + zeta) / (g0 + zeta + (1 - fraction) * (g1 - g0))
    return bulk, shear


def hashin_shtrikman_upper(matrix, filler, fraction):
    """Upper Hashin-Shtrikman bounds (Hashin & Shtrikman 1963) [Pa] for a filler stiffer than the matrix."""
    k0, g0 = moduli(matrix)
    k1, g1 = moduli(filler)
    bulk = k1 + (1 - fraction) / (1 / (k0 - k1) + 3 * fraction / (3 * k1 + 4 * g1))
    shear = g1 + (1 - fraction) / (1 / (g0 - g1) + 6 * fraction * (k1 + 2 * g1) / (5 * g1 * (3 * k1 + 4 * g1)))
    return bulk, shear


def check_against_mori_tanaka(row, tolerance):
    """Hill's moduli within ``tolerance`` of Mori-Tanaka at the fraction reached, inside the HS band."""
    reference = mori_tanaka_spheres(cloud.MATRIX, cloud.GLASS, row["fraction"])
    upper = hashin_shtrikman_upper(cloud.MATRIX, cloud.GLASS, row["fraction"])
    for name, measured, expected, bound in zip(("bulk", "shear"), row["hill"], reference, upper):
        assert abs(measured / expected - 1) < tolerance, (name, measured / expected - 1)
        assert measured < bound, (name, measured, bound)
    # the two extractions read the same ball: Hill's ratio and Eshelby's concentration agree
    np.testing.assert_allclose(row["concentration"], row["hill"], rtol=0.005)


def test_mori_tanaka_reference_is_the_closed_form():
    """framework.reference.mori_tanaka of spheres equals the closed form here to 1e-10 (the study's reference)."""
    effective = mori_tanaka(cloud.MATRIX, cloud.GLASS, 0.1)
    np.testing.assert_allclose(moduli(effective), mori_tanaka_spheres(cloud.MATRIX, cloud.GLASS, 0.1), rtol=1e-10)


def test_ball_cloud_placement():
    """Seeded placement: the asked count, wholly inside the ball, every pair at least the gap apart, reproducible."""
    radius, gap = 4e-5, 1e-5
    centres, ball = cloud.ball_cloud(40, radius, 0.1, gap, seed=3)
    assert ball == pytest.approx(radius * 400 ** (1 / 3), rel=1e-12)
    assert centres.shape == (40, 3)
    assert np.max(np.linalg.norm(centres, axis=1)) <= ball - radius
    distances = np.linalg.norm(centres[:, None] - centres[None], axis=2) + np.eye(40) * 1e9
    assert distances.min() >= 2 * radius + gap
    np.testing.assert_array_equal(cloud.ball_cloud(40, radius, 0.1, gap, seed=3)[0], centres)


def test_extraction_on_one_sphere():
    """One Eshelby sphere of a known material (the composite's Mori-Tanaka one, 4 cuboids per radius, staircase)
    returns its bulk and shear moduli within 2 % from the six loads (measured: Hill -0.85 %, -1.24 %;
    concentration -0.83 %, -1.06 %; two loads: -0.52 / -0.75 % at 8 per radius, -0.43 / -0.62 % at 12)."""
    bulk, shear = mori_tanaka_spheres(cloud.MATRIX, cloud.GLASS, 0.1)
    known = materials.Elastic(9 * bulk * shear / (3 * bulk + shear), (3 * bulk - 2 * shear) / (2 * (3 * bulk + shear)))
    radius = 4 * cloud.CELL
    grid, bodies, middle = cloud.cloud_case(np.zeros((1, 3)), radius, radius, cloud.CELL, filler=known)
    out = cloud.effective_moduli(grid, cloud.MATRIX, bodies, middle, radius)
    expected = moduli(known)
    np.testing.assert_allclose(out["hill"], expected, rtol=0.02)
    np.testing.assert_allclose(out["concentration"], expected, rtol=0.02)
    # the matrix's moduli are far (12 % and 22 % away): the check tells the filler from the matrix
    assert abs(out["hill"][1] / moduli(cloud.MATRIX)[1] - 1) > 0.15


def test_small_cloud_against_mori_tanaka():
    """20 glass spheres of 6 cuboids per diameter at 10 % in PMMA: Hill's K* and G* within 5 % of Mori-Tanaka
    (measured +0.56 %, +2.49 %), below the upper Hashin-Shtrikman bound; the concentration agrees within 0.5 %."""
    row = cloud.cloud_study(20, 6, seed=1, loads="two")
    assert abs(row["fraction"] - 0.1) < 0.01
    check_against_mori_tanaka(row, 0.05)


@pytest.mark.slow
def test_cloud_of_100_against_mori_tanaka():
    """100 glass spheres of 8 cuboids per diameter at 10 %, six loads (box 85 x 83 x 88, 217 s):
    K* and G* within 3 % of Mori-Tanaka (measured +0.50 %, +1.27 %; 25 and 50 spheres: +0.50 / +1.29 %,
    +0.47 / +1.20 %: no trend with the count). One glass sphere of 4 cuboids per radius stiffens the matrix
    3.3 % (bulk) and 6.7 % (shear) more than Eshelby's (its staircase volume times its mean strain): 0.4 % and
    1.2 % of K* and G* at 10 %, the size of the excess."""
    row = cloud.cloud_study(100, 8, seed=1)
    assert abs(row["fraction"] - 0.1) < 0.005
    check_against_mori_tanaka(row, 0.03)


@pytest.mark.slow
def test_excess_over_mori_tanaka_with_the_cuboid():
    """One 25-sphere cloud (the same centres in radii) at 6, 8 and 12 cuboids per diameter, six loads (254 s):
    Hill's excess over Mori-Tanaka falls as the cuboid shrinks (measured shear +1.31, +1.29,
    +1.13 %, bulk +0.56, +0.50, +0.40 %); its straight line in the cuboid size meets zero size at +0.97 % in
    shear and +0.25 % in bulk, below 1.5 % and 0.5 % (Mori-Tanaka is the Hashin-Shtrikman lower bound, below a
    random composite's modulus at second order in the fraction). The split is not settled: one glass sphere's
    dilute excess (3, 4, 6 cuboids per radius: shear +8.1, +6.7, +4.1 % of Eshelby's) would give +1.46,
    +1.2, +0.74 %, a steeper fall than the cloud's."""
    cells = np.array([6, 8, 12])
    excess = []
    for n in cells:
        row = cloud.cloud_study(25, int(n), seed=1)
        excess.append(np.array(row["hill"]) / np.array(mori_tanaka_spheres(cloud.MATRIX, cloud.GLASS,
                                                                             row["fraction"])) - 1)
    excess = np.array(excess)
    assert np.all(np.diff(excess, axis=0) < 0), excess
    limit = np.polyfit(1.0 / cells, excess, 1)[1]
    assert 0 < limit[0] < 0.005 and 0 < limit[1] < 0.015, limit
