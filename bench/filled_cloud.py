"""Scale separation without contact: a ball filled with small stiff spheres against Mori-Tanaka (issue 26).

A spherical cloud of ``count`` glass spheres (E = 70 GPa, nu = 0.22) at a volume fraction of 10 % in a
PMMA-like matrix (E = 3 GPa, nu = 0.35), deep in the half-space (centre depth 3 cloud radii), is solved by
``fw.solve_inclusions`` under uniform applied strains. The cloud acts as one Eshelby sphere of the effective
material: over the cloud's ball the mean stress and the mean strain relate by the effective stiffness
(Hill's condition ``<sigma> = C* <eps>``). The mean strain comes from the eigenstrains: in every cuboid
``sigma = C_M : (eps - e*)``, so ``<eps> = C_M^-1 : <sigma> + <e*>``. The means are volume means over the
ball, the cuboids its boundary cuts weighted by the share of their volume inside it (4^3 sub-points).

- ``--loads six`` (default): the six unit strains give six pairs of means, ``C* = <Sigma> <E>^-1`` (Mandel),
  and its isotropic projection ``K* = C_iijj / 9``, ``G* = (C_ijij - 3 K*) / 10``: a finite cloud is
  anisotropic (a 25-sphere cloud's G along an x1 stretch, e23 and e12: 2.3, 1.4 and 0.1 % above
  Mori-Tanaka; projected: 1.3 %).
- ``--loads two`` (a third of the time): ``K* = <sigma_m> / <eps_v>`` under a hydrostatic strain and
  ``G* = <s> : <e> / (2 <e> : <e>)`` (the deviators of the means) under an isochoric stretch along x1.

An independent second estimate reads the moduli from the mean strain alone, as the dilute concentration of an
Eshelby sphere of C* in the matrix (infinite space: the free surface two radii above the cloud is neglected),
``<E> = A E0``, ``A = [I + S C_M^-1 (C* - C_M)]^-1``; with two loads

    <eps_v> / eps0_v = 1 / (1 + alpha (K* / K_M - 1)),   alpha = (1 + nu) / (3 (1 - nu)),
    <e> / e0         = 1 / (1 + beta (G* / G_M - 1)),    beta = 2 (4 - 5 nu) / (15 (1 - nu)).

Placement (:func:`ball_cloud`): random sequential addition of equal spheres wholly inside the ball, each
pair at least ``gap`` apart (one cuboid: no two spheres share a cuboid), seeded. The fraction reached is
counted on the cuboids (the staircase holds a sphere of 4 cuboids per radius with a volume a few percent off
4/3 pi a^3): Mori-Tanaka is evaluated at that fraction.

    OMP_NUM_THREADS=1 .venv/bin/python bench/filled_cloud.py [--counts 50 100 200] [--cells 8]
        [--geometry staircase] [--loads six] [--fraction 0.1] [--seed 1]

prints one row per case: particles, cuboids per diameter, geometry, the solve's box, fraction reached,
K*/K_MT - 1, G*/G_MT - 1 (Hill), the same by the concentration, GMRES iterations (least-most over the loads),
time of the solves and the process's peak resident size (``ru_maxrss``, which only grows: cases run in
increasing size).
"""
import argparse
import os
import resource
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import framework as fw  # noqa: E402
from framework import inclusions, materials  # noqa: E402
from framework.errors import InclusionError, ParameterError, ResolutionWarning  # noqa: E402
from framework.reference import mori_tanaka  # noqa: E402

#: PMMA-like matrix and glass beads [Pa, -].
MATRIX = materials.Elastic(3.0e9, 0.35)
GLASS = materials.Elastic(70.0e9, 0.22)
#: Cuboid size [m] (cubes).
CELL = 1.0e-5
#: Applied strains [-]: hydrostatic, and deviatoric (an isochoric stretch along x1).
HYDROSTATIC = np.eye(3) * 1e-3
DEVIATORIC = np.diag([1e-3, -0.5e-3, -0.5e-3])
#: Centre depth of the cloud in cloud radii.
DEPTH = 3.0
#: Mandel weights of the tensor-shear Voigt vectors (xx yy zz yz xz xy).
MANDEL = np.array([1.0, 1.0, 1.0, np.sqrt(2.0), np.sqrt(2.0), np.sqrt(2.0)])
#: Mandel projector on the hydrostatic strains (``J``; ``I - J`` the deviatoric ones).
HYDROSTATIC_PROJECTOR = np.pad(np.full((3, 3), 1.0 / 3.0), ((0, 3), (0, 3)))
#: Index pairs of the Voigt order.
PAIRS = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))


def bulk_shear(material):
    """Bulk and shear moduli [Pa] of an isotropic :class:`~framework.materials.Elastic`."""
    young, poisson = material.young, material.poisson
    return young / (3.0 * (1.0 - 2.0 * poisson)), young / (2.0 * (1.0 + poisson))


def ball_cloud(count, radius, fraction, gap, seed, max_attempts=200_000):
    """Centres ``(count, 3)`` [m] of equal spheres filling a ball at ``fraction``, relative to its centre.

    Random sequential addition: centres drawn uniformly in the ball of radius ``cloud - radius`` (each sphere
    wholly inside the cloud), kept when at least ``2 radius + gap`` from every kept centre.

    Parameters
    ----------
    count : int
        Number of spheres.
    radius : float
        Sphere radius [m].
    fraction : float
        Volume fraction of the spheres in the cloud [-]: the cloud's radius is ``radius (count / fraction)^(1/3)``.
    gap : float
        Least distance between two spheres [m].
    seed : int
        Seed of the random generator.

    Returns
    -------
    centres : numpy.ndarray
        ``(count, 3)`` [m].
    cloud : float
        The cloud's radius [m].
    """
    cloud = radius * (count / fraction) ** (1.0 / 3.0)
    rng = np.random.default_rng(seed)
    centres = np.empty((0, 3))
    attempts = 0
    while len(centres) < count:
        attempts += 1
        if attempts > max_attempts:
            raise InclusionError(f"count = {count} spheres of radius {radius:g} m at fraction {fraction:g} with gap "
                                 f"{gap:g} m: placed {len(centres)} in {max_attempts} draws; expected a fraction "
                                 f"below random sequential addition's jamming (about 0.38, less with a gap)")
        point = rng.uniform(-1.0, 1.0, 3) * (cloud - radius)
        if point @ point > (cloud - radius) ** 2:
            continue
        if len(centres) and np.min(np.sum((centres - point) ** 2, axis=1)) < (2.0 * radius + gap) ** 2:
            continue
        centres = np.vstack([centres, point])
    return centres, cloud


def cloud_case(centres, radius, cloud, cell, filler=GLASS):
    """The grid, the bodies and the cloud's centre of a cloud at a depth of :data:`DEPTH` cloud radii.

    Parameters
    ----------
    centres : numpy.ndarray
        ``(n, 3)`` sphere centres relative to the cloud's centre [m].
    radius, cloud : float
        Sphere and cloud radii [m].
    cell : float
        Cuboid size [m] (cubes).
    filler : framework.materials.Elastic
        The spheres' material.

    Returns
    -------
    grid : framework.Grid
        Just wide and deep enough for the cloud (the solve's box follows the bodies, not the grid).
    bodies : framework.inclusions.InclusionSet
    middle : numpy.ndarray
        The cloud's centre (3,) [m].
    """
    margin = cell * 2
    half = int(np.ceil((cloud + margin) / cell)) + 2
    centre_depth = DEPTH * cloud
    layers = int(np.ceil((centre_depth + cloud + 2 * margin) / cell))
    grid = fw.Grid(shape=(2 * half, 2 * half), size=(2 * half * cell, 2 * half * cell), depth=layers * cell,
                   layers=layers)
    middle = np.array([0.0, 0.0, centre_depth])
    bodies = inclusions.InclusionSet([inclusions.Ellipsoid(center=tuple(middle + c), semi_axes=(radius,) * 3,
                                                           material=filler) for c in centres])
    return grid, bodies, middle


def ball_weights(grid, middle, cloud, sub=4):
    """Share ``(n1, n2, layers)`` of each cuboid inside the ball (``sub``^3 sub-points in the cuboids it cuts)."""
    spacing = np.array([*grid.spacing, grid.layer_thickness])
    axes = [grid.x1 - middle[0], grid.x2 - middle[1], grid.x3 - middle[2]]
    r = np.sqrt(axes[0][:, None, None] ** 2 + axes[1][None, :, None] ** 2 + axes[2][None, None, :] ** 2)
    weights = (r < cloud).astype(float)
    cut = np.abs(r - cloud) < 0.5 * np.linalg.norm(spacing)
    offsets = (np.arange(sub) + 0.5) / sub - 0.5
    sub_points = np.stack(np.meshgrid(offsets, offsets, offsets, indexing="ij"), -1).reshape(-1, 3) * spacing
    for index in np.argwhere(cut):
        centre = np.array([axes[k][index[k]] for k in range(3)])
        weights[tuple(index)] = np.mean(np.sum((centre + sub_points) ** 2, axis=1) < cloud ** 2)
    return weights


def means(solution, grid, matrix, weights):
    """Volume means ``(<sigma>, <eps>)`` over the weighted cuboids, (6,) each (tensor shears, Voigt order).

    ``solution.stress`` lives on the box ``solution.box``; the ball must lie inside it.
    """
    box_weights = weights[solution.box]
    if not np.isclose(box_weights.sum(), weights.sum()):
        raise ParameterError(f"margin: the ball reaches {weights.sum() - box_weights.sum():.4g} cuboids beyond the "
                             f"solution's box; expected the box to hold it: grow the margin")
    total = box_weights.sum()
    stress = np.einsum("ijk,ijkc->c", box_weights, solution.stress) / total
    eigenstrain = np.einsum("ijk,ijkc->c", box_weights, solution.eigenstrain[solution.box]) / total
    bulk, shear = bulk_shear(matrix)
    mean_stress = stress[:3].mean()
    # C_M^-1 on tensor shears: e = s / (2 G) - (3K - 2G) / (18 K G) tr(s) I (isotropic compliance)
    strain = stress / (2.0 * shear)
    strain[:3] += mean_stress * (1.0 / (3.0 * bulk) - 1.0 / (2.0 * shear))
    return stress, strain + eigenstrain


def deviator(vector):
    """Deviator of a (6,) tensor-shear vector."""
    out = vector.copy()
    out[:3] -= vector[:3].mean()
    return out


def contract(a, b):
    """Double contraction ``a : b`` of two (6,) tensor-shear vectors."""
    return float(a[:3] @ b[:3] + 2.0 * a[3:] @ b[3:])


def hill_bulk(stress, strain):
    """Bulk modulus [Pa] from mean stress and strain: ``<sigma_m> / <eps_v>``."""
    return stress[:3].mean() / strain[:3].sum()


def hill_shear(stress, strain):
    """Shear modulus [Pa] from the deviators of the mean stress and strain: ``s : e / (2 e : e)``."""
    s, e = deviator(stress), deviator(strain)
    return contract(s, e) / (2.0 * contract(e, e))


def concentration_bulk(strain, applied, matrix):
    """Bulk modulus [Pa] of the Eshelby sphere whose mean volumetric strain is ``strain``'s under ``applied``."""
    bulk, _ = bulk_shear(matrix)
    alpha = (1.0 + matrix.poisson) / (3.0 * (1.0 - matrix.poisson))
    ratio = np.trace(applied) / strain[:3].sum()
    return bulk * (1.0 + (ratio - 1.0) / alpha)


def concentration_shear(strain, applied, matrix):
    """Shear modulus [Pa] of the Eshelby sphere whose mean deviatoric strain is ``strain``'s under ``applied``."""
    _, shear = bulk_shear(matrix)
    nu = matrix.poisson
    beta = 2.0 * (4.0 - 5.0 * nu) / (15.0 * (1.0 - nu))
    e0 = deviator(np.array([applied[0, 0], applied[1, 1], applied[2, 2], applied[1, 2], applied[0, 2],
                            applied[0, 1]]))
    e = deviator(strain)
    ratio = contract(e0, e0) / contract(e, e0)
    return shear * (1.0 + (ratio - 1.0) / beta)


def unit_strains(size=1e-3):
    """The six applied strains (3x3) of the full extraction: Mandel's unit strains times ``size`` [-]."""
    strains = []
    for k, (i, j) in enumerate(PAIRS):
        strain = np.zeros((3, 3))
        strain[i, j] = strain[j, i] = size / MANDEL[k]
        strains.append(strain)
    return strains


def isotropic_moduli(stiffness):
    """Bulk and shear moduli [Pa] of the isotropic projection of a 6x6 Mandel stiffness.

    ``K = C_iijj / 9``, ``G = (C_ijij - 3 K) / 10`` (an isotropic ``3K J + 2G (I - J)`` returns its K and G).
    """
    bulk = stiffness[:3, :3].sum() / 9.0
    return bulk, (np.trace(stiffness) - 3.0 * bulk) / 10.0


def full_moduli(stresses, strains, applied, matrix):
    """Isotropic (bulk, shear) [Pa] by Hill and by the concentration from six independent load cases.

    ``stresses``, ``strains``: (6, 6) mean stresses and strains over the ball (tensor shears), one row per
    case; ``applied``: (6, 6) the applied strains. Hill: ``C* = <Sigma> <E>^-1`` (Mandel). Concentration: the
    mean strain ``<E> = A E0`` of an Eshelby sphere of ``C*``, ``A = [I + S C_M^-1 (C* - C_M)]^-1``, gives
    ``C* = C_M + C_M S^-1 (A^-1 - I)``, ``S^-1 = J / alpha + (I - J) / beta``. Both projected isotropically.
    """
    sigma, eps, eps0 = (np.asarray(v).T * MANDEL[:, None] for v in (stresses, strains, applied))
    hill = sigma @ np.linalg.inv(eps)
    bulk, shear = bulk_shear(matrix)
    nu = matrix.poisson
    alpha, beta = (1.0 + nu) / (3.0 * (1.0 - nu)), 2.0 * (4.0 - 5.0 * nu) / (15.0 * (1.0 - nu))
    hydro = HYDROSTATIC_PROJECTOR
    c_matrix = 3.0 * bulk * hydro + 2.0 * shear * (np.eye(6) - hydro)
    eshelby_inverse = hydro / alpha + (np.eye(6) - hydro) / beta
    concentration = eps @ np.linalg.inv(eps0)
    effective = c_matrix + c_matrix @ eshelby_inverse @ (np.linalg.inv(concentration) - np.eye(6))
    return isotropic_moduli(hill), isotropic_moduli(effective)


def effective_moduli(grid, matrix, bodies, middle, cloud, geometry="staircase", margin=None, loads="six"):
    """Effective (bulk, shear) [Pa] of the ball by Hill and by the concentration, and the solves' figures.

    ``loads="six"``: the six unit strains, the whole effective stiffness, its isotropic projection (a finite
    cloud is anisotropic: one deviatoric direction of a 25-sphere cloud read G 2.3 %, 1.4 % and 0.1 % above
    Mori-Tanaka for an x1 stretch, e23 and e12). ``loads="two"``: one hydrostatic and one deviatoric strain
    (a third of the time; K exact for an isotropic cloud, G along that direction only).

    Returns a dict: ``hill`` (K, G), ``concentration`` (K, G), ``iterations`` (one per load),
    ``fraction`` (bodies' volume over the ball's: cuboids, or the laminate's shares), ``seconds`` (all solves),
    ``box`` (cuboids of the solve's box).
    """
    if loads not in ("six", "two"):
        raise ParameterError(f"loads must be 'six' or 'two', got {loads!r}")
    if margin is None:   # the box around the bodies must hold the ball: grow it by the widest shortfall
        lower, upper = bodies.bounds()
        margin = max(np.max(lower - (middle - cloud)), np.max(middle + cloud - upper), 0.0) + grid.spacing[0]
    applied_strains = unit_strains() if loads == "six" else [HYDROSTATIC, DEVIATORIC]
    weights = None
    out = {"iterations": [], "seconds": 0.0}
    stresses, strains = [], []
    for applied in applied_strains:
        begin = time.perf_counter()
        with warnings.catch_warnings():   # 4 cuboids per radius: at the coarse-body warning's limit
            warnings.simplefilter("ignore", ResolutionWarning)
            solution = fw.solve_inclusions(grid, matrix, bodies, applied, margin=margin, geometry=geometry)
        out["seconds"] += time.perf_counter() - begin
        out["iterations"].append(solution.iterations)
        out["box"] = tuple(int(part.stop - part.start) for part in solution.box)
        if weights is None:
            weights = ball_weights(grid, middle, cloud)
            # the bodies lie wholly inside the ball: their volume (cuboids, or the laminate's shares) over the ball's
            out["fraction"] = float(np.sum(solution.fraction) / np.sum(weights))
        stress, strain = means(solution, grid, matrix, weights)
        stresses.append(stress)
        strains.append(strain)
    if loads == "six":
        applied = [[strain[i, j] for i, j in PAIRS] for strain in applied_strains]
        out["hill"], out["concentration"] = full_moduli(stresses, strains, applied, matrix)
    else:
        out["hill"] = (hill_bulk(stresses[0], strains[0]), hill_shear(stresses[1], strains[1]))
        out["concentration"] = (concentration_bulk(strains[0], HYDROSTATIC, matrix),
                                concentration_shear(strains[1], DEVIATORIC, matrix))
    return out


def cloud_study(count, cells, seed=1, fraction=0.1, geometry="staircase", filler=GLASS, matrix=MATRIX,
                loads="six"):
    """One cloud: ``count`` spheres of ``cells`` cuboids per diameter; the row of the table as a dict."""
    radius = 0.5 * cells * CELL
    centres, cloud = ball_cloud(count, radius, fraction, gap=CELL, seed=seed)
    grid, bodies, middle = cloud_case(centres, radius, cloud, CELL, filler)
    out = effective_moduli(grid, matrix, bodies, middle, cloud, geometry=geometry, loads=loads)
    reference = mori_tanaka(matrix, filler, out["fraction"])
    out["mori_tanaka"] = bulk_shear(reference)
    out.update(count=count, cells=cells, geometry=geometry)
    return out


def peak_rss_mib():
    """Peak resident size of this process so far [MiB] (Linux ru_maxrss is in KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--counts", type=int, nargs="+", default=[50, 100])
    parser.add_argument("--cells", type=int, nargs="+", default=[8], help="cuboids per particle diameter")
    parser.add_argument("--geometry", default="staircase", choices=["staircase", "laminate"])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--fraction", type=float, default=0.1, help="volume fraction asked in the ball")
    parser.add_argument("--loads", default="six", choices=["six", "two"],
                        help="six unit strains (isotropic projection) or a hydrostatic and one deviatoric")
    args = parser.parse_args(argv)
    print(f"matrix E = {MATRIX.young:.3g} Pa nu = {MATRIX.poisson}; glass E = {GLASS.young:.3g} Pa "
          f"nu = {GLASS.poisson}; asked fraction {args.fraction:g}; {args.loads} loads; "
          f"OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS')}")
    print(f"{'particles':>9} {'cells/d':>7} {'geometry':>9} {'box':>11} {'fraction':>8} {'K/K_MT-1':>9} "
          f"{'G/G_MT-1':>9} {'Kc/K_MT-1':>9} {'Gc/G_MT-1':>9} {'iters':>7} {'time s':>7} {'RSS MiB':>8}")
    for cells in args.cells:
        for count in args.counts:
            row = cloud_study(count, cells, seed=args.seed, fraction=args.fraction, geometry=args.geometry,
                              loads=args.loads)
            (k, g), (kc, gc), (km, gm) = row["hill"], row["concentration"], row["mori_tanaka"]
            box = "x".join(map(str, row["box"]))
            iterations = f"{min(row['iterations'])}-{max(row['iterations'])}"
            print(f"{count:>9} {cells:>7} {args.geometry:>9} {box:>11} {row['fraction']:>8.4f} "
                  f"{k / km - 1:>+9.4f} {g / gm - 1:>+9.4f} {kc / km - 1:>+9.4f} {gc / gm - 1:>+9.4f} "
                  f"{iterations:>7} {row['seconds']:>7.1f} {peak_rss_mib():>8.0f}",
                  flush=True)


if __name__ == "__main__":
    main()
