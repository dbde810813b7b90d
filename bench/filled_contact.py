"""A rigid sphere pressed on a half-space filled with glass beads to a depth, against its homogenised references.

Issue 26, "Then under contact": as the beads shrink, the approach and the contact radius must tend to those of the
homogenised material. The filled depth is a layer: the matrix below it carries part of the approach, so the
homogenised reference is a Mori-Tanaka layer of the filled depth bonded to the matrix half-space
(``framework.reference.layered``, solved on its own grid, independently of the framework's solver).

The case, in units of ``a``, the Hertz contact radius on the matrix (a = 0.5 mm: R = 10 mm, W = 57 N):

- matrix PMMA-like elastic (E = 3 GPa, nu = 0.35), glass beads (E = 70 GPa, nu = 0.22) of radius ``r``, placed by
  ``inclusions.random_dispersion`` at the volume ``--fraction`` (seeded, at least ``GAP`` r apart) in the box
  ``|x1|, |x2| <= WIDTH a``, depths ``r <= x3 <= r + DEPTH a``: a top gap of one bead radius of bare matrix (the
  beads' centres lie at least 2 r deep), filled to ``DEPTH a`` below it;
- the grid: cubic cuboids of ``a / --cells-per-radius`` (the same cell for every bead size, so that the contact's
  discretisation is the same and only the beads change: 3 cuboids per bead radius at r = a/5 with the default 15),
  the surface ``2 (WIDTH + MARGIN) a`` wide, the layers down to the filled region's floor;
- the references: (i) Hertz on the matrix, (ii) Hertz on the Mori-Tanaka material (the whole half-space
  homogenised), (iii) the layered contact: a Mori-Tanaka layer of thickness ``DEPTH a`` at the surface, bonded to
  the matrix half-space, which carries the approach below the filled depth (``layered_sphere_contact``, 128 cells
  over 3 a: within 2e-5 of converged in the approach, tests/test_layered.py): the limit as the beads, and with
  them the top gap, shrink; (iv) "gapped": the same layer under a bare matrix gap of one bead radius (the filled
  box's top; ``stack_compliance``), the homogenised picture of the filled box at the bead size run;
- the framework's discretisation: the same grid without beads against Hertz on the matrix (approach -2.3e-4,
  contact radius +6.4e-3 at a/15); each filled result is divided by that grid's ratio before the comparison.

Prints per bead radius and seed: the bodies, the reached fraction (of the analytic volumes and of the staircase),
the time, the approach and the contact radius, their differences from (i) to (iv); then per radius the mean and
the spread over the seeds. Measured (6 seeds, approach / contact radius against the layered reference, %):
a/3 +1.2 / +5.1, a/4 +0.5 / +4.2, a/5 -0.7 / +3.0, a/6 (cuboids a/18) -0.4 / +2.3; against the gapped one
-1.1 / -0.6, -1.1 / -0.6, -2.0 / -0.8, -1.5 / -1.1; 17-31 s a solve (2-core AMD EPYC, beside other runs). The
finite width: the beads of one +-3 a dispersion kept within +-1.5, 2, 2.5, 3 a (3 seeds of a/3) give +2.4,
+0.9, +0.2, -0.1 % against the layered reference: the box of +-2 a costs about +1.2 % of the approach.

    OMP_NUM_THREADS=2 .venv/bin/python bench/filled_contact.py [--radii 3 4 5] [--seeds 0 1 2]
        [--fraction 0.2] [--cells-per-radius 15] [--width 2.0] [--depth 2.0]
    OMP_NUM_THREADS=2 .venv/bin/python bench/filled_contact.py --roll --radii 3 --seeds 0 --cells-per-radius 10

``--roll``: the same beads (box +-2 a across, from -2 a to 7 a along the roll) in a viscoelastic matrix (E(0) =
3 GPa relaxing to 1 GPa over 0.02 and 0.2 s, nu = 0.35), a sphere (R = 10 mm, W = 19 N: relaxed a = 0.5 mm)
rolling 5 a at 1 mm/s (V lambda_max = 0.82 a: the transient fades as exp(-6)); its last friction coefficient,
divided by the plain roll's ratio to ``reference.steady_sphere``, against the steady references: the matrix's, the
Mori-Tanaka half-space's, the Mori-Tanaka layer's on the matrix (``layered_steady_sphere``), bare and under the
gap. Measured: steady 0.00905 (matrix), 0.00791 (Mori-Tanaka half-space), 0.00806 (layer), 0.00821 / 0.00816
(under a gap of a/3 / a/4); the plain roll ends 0.45 % (a/10) and 0.20 % (a/12) below the matrix's steady value;
93 beads of a/3 (a/10, seed 0, 15 min) and 220 of a/4 (a/12, seed 0, 14 min) swing by +-3 % as beads pass, their
means after the first 2 a 3.9 % and 3.2 % below the layered reference (the bench prints that mean).

Beads of a/2 (12 of them at 20 %) stopped while the equivalent-inclusion preconditioner took the glass's whole
contrast for up to 16 bodies (no convergence in 100 couplings, residual 5e-3); with a share of it for any two bodies
or more (``equivalent.FOURIER_BODIES = 1``) they converge, 10 s a solve: 2 seeds, +1.8 / +6.3 % against the layered
reference (spread 1 %), -1.8 / -1.1 % against the gapped one, which continues the trend of the smaller beads.
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import framework as fw  # noqa: E402
from framework import inclusions, indenters, loads, materials, schedules  # noqa: E402
from framework.reference import HertzSphere, mori_tanaka  # noqa: E402
from framework.reference.layered import layered_sphere_contact  # noqa: E402

MATRIX = materials.Elastic(3e9, 0.35)          # PMMA-like, elastic
GLASS = materials.Elastic(70e9, 0.22)
RADIUS = 10e-3                                 # rigid sphere [m]
CONTACT = 0.5e-3                               # Hertz contact radius on the matrix, a [m]
LOAD = 4 * MATRIX.young / (1 - MATRIX.poisson ** 2) * CONTACT ** 3 / (3 * RADIUS)   # 57.0 N
WIDTH = 2.0                                    # the filled box's half-width [a]
DEPTH = 2.0                                    # filled depth below the top gap [a]
GAP = 0.1                                      # least distance between two beads [bead radius]
MARGIN = 0.25                                  # bare surface beyond the box on each side [a]
REFERENCE_CELLS = 128                          # the layered reference's grid over 3 a


def contact_modulus(material):
    """E / (1 - nu^2) [Pa]."""
    return material.young / (1 - material.poisson ** 2)


def references(fraction, depth=DEPTH):
    """The three homogenised references: Hertz on the matrix, Hertz on Mori-Tanaka, the layered contact
    (Mori-Tanaka layer ``depth`` a thick on the matrix); each (approach [m], contact radius [m])."""
    effective = mori_tanaka(MATRIX, GLASS, fraction)
    matrix = HertzSphere(radius=RADIUS, load=LOAD, contact_modulus=contact_modulus(MATRIX))
    homogenised = HertzSphere(radius=RADIUS, load=LOAD, contact_modulus=contact_modulus(effective))
    layered = layered_sphere_contact(RADIUS, LOAD, depth * CONTACT, effective, MATRIX, side=3 * CONTACT,
                                     cells=REFERENCE_CELLS)
    return dict(matrix=(matrix.approach, matrix.contact_radius),
                homogenised=(homogenised.approach, homogenised.contact_radius),
                layered=(layered.approach, layered.contact_radius), effective=effective)


def gapped(bead, fraction, depth=DEPTH):
    """The layered reference with the filled region's bare top: a matrix gap of one bead radius above the
    Mori-Tanaka layer ``depth`` a thick, on the matrix: (approach [m], contact radius [m])."""
    out = layered_sphere_contact(RADIUS, LOAD, depth * CONTACT, mori_tanaka(MATRIX, GLASS, fraction), MATRIX,
                                 side=3 * CONTACT, cells=REFERENCE_CELLS, gap=bead)
    return out.approach, out.contact_radius


def grid_for(bead, cells_per_radius, width=WIDTH, depth=DEPTH):
    """The grid [m] for beads of radius ``bead`` [m]: cubic cuboids of a / cells_per_radius, the surface over the
    box and MARGIN, the layers down to the filled region's floor (top gap + depth)."""
    cell = CONTACT / cells_per_radius
    n = int(np.ceil(2 * (width + MARGIN) * CONTACT / cell / 8.0)) * 8
    layers = int(np.ceil((bead + depth * CONTACT) / cell))
    return fw.Grid(shape=(n, n), size=(n * cell, n * cell), depth=layers * cell, layers=layers)


def region_for(bead, width=WIDTH, depth=DEPTH):
    """The filled box ((x1 lo, hi), (x2 lo, hi), (x3 lo, hi)) [m]: a top gap of one bead radius."""
    half = width * CONTACT
    return ((-half, half), (-half, half), (bead, bead + depth * CONTACT))


def press(grid, bodies):
    """The framework's static contact: approach [m], contact radius [m], peak pressure [Pa], and the count of
    cuboids inside the bodies (their staircase)."""
    simulation = fw.Simulation(grid=grid, material=MATRIX, indenter=indenters.Sphere(radius=RADIUS),
                               schedule=schedules.Static(load=loads.Step(LOAD), times=[1.0]), inclusions=bodies)
    problem = simulation._inclusion_problem
    cuboids = 0 if problem is None else int(np.count_nonzero(problem.indicator))
    result = simulation.run()
    return float(result.approach[-1]), float(result.contact_radius[-1]), float(result.max_pressure[-1]), cuboids


def filled(bead, seed, fraction, cells_per_radius, width=WIDTH, depth=DEPTH):
    """One filled case: a dict of the bodies, the reached fraction, the framework's results and the seconds."""
    grid = grid_for(bead, cells_per_radius, width, depth)
    region = region_for(bead, width, depth)
    bodies = inclusions.random_dispersion(fraction, region, bead, GLASS, gap=GAP * bead, seed=seed)
    volume = np.prod([hi - lo for lo, hi in region])
    reached = len(bodies) * 4 / 3 * np.pi * bead ** 3 / volume
    begin = time.perf_counter()
    approach, contact_radius, peak, cuboids = press(grid, bodies)
    staircase = cuboids * (CONTACT / cells_per_radius) ** 3 / volume
    return dict(bead=bead, seed=seed, bodies=len(bodies), fraction=reached, staircase=staircase, approach=approach,
                contact_radius=contact_radius, peak=peak, seconds=time.perf_counter() - begin, grid=grid)


def plain(cells_per_radius, bead, width=WIDTH, depth=DEPTH):
    """The same grid without beads: (approach [m], contact radius [m]) for the grid's own error."""
    return press(grid_for(bead, cells_per_radius, width, depth), None)[:2]


def compare(row, base, refs):
    """Differences of one filled row: relative to each reference, raw and divided by the plain grid's ratio."""
    out = {}
    for name in ("matrix", "homogenised", "layered", "gapped"):
        approach, radius = refs[name]
        grid_approach = base[0] / refs["matrix"][0]        # the framework grid's own approach error, as a factor
        grid_radius = base[1] / refs["matrix"][1]
        out[name] = (row["approach"] / grid_approach / approach - 1, row["contact_radius"] / grid_radius / radius - 1)
    return out


# --------------------------------------------------------------------------- rolling over a viscoelastic matrix

#: The viscoelastic matrix of the rolling case: E(0) = 3 GPa relaxing to 1 GPa over 0.02 and 0.2 s, nu = 0.35
#: (bench/rolling_inclusion.py's ``matrix(2)``).
VISCOUS = materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(1e9, 0.02), (1e9, 0.2)], poisson=0.35)
#: Rolling load [N]: the relaxed Hertz contact radius is a = 0.5 mm.
ROLL_LOAD = 4 * VISCOUS.relaxation_terms[0] / (1 - 0.35 ** 2) * CONTACT ** 3 / (3 * RADIUS)
#: Rolling speed [m/s]: 1 mm/s, V lambda = 0.82 a for the slowest retardation time (0.41 s): 5 a of rolling reach
#: the steady state to exp(-6).
SPEED = CONTACT / 0.5
#: Rolling distance [a].
ROLL_DISTANCE = 5.0


def rolling_references(fraction, bead, depth=DEPTH, cells=32):
    """Steady friction coefficients [-]: the matrix half-space and the Mori-Tanaka half-space
    (``reference.steady_sphere``), the Mori-Tanaka layer ``depth`` a thick on the matrix, bare and under a matrix
    gap ``bead`` [m] (``layered_steady_sphere`` on a periodic grid 24 a wide: the material's memory of its last
    pass, exp(-24 a / 0.82 a), and the images, (1/24)^3, are below 1e-4)."""
    from framework.reference import steady_sphere
    from framework.reference.layered_rolling import layered_steady_sphere
    effective = mori_tanaka(VISCOUS, GLASS, fraction)
    half = 1.5 * CONTACT

    def layered(gap):
        return layered_steady_sphere(RADIUS, ROLL_LOAD, SPEED, depth * CONTACT, effective, VISCOUS, half_size=half,
                                     cells=cells, period=24 * CONTACT, gap=gap).friction_coefficient
    return dict(matrix=steady_sphere(RADIUS, ROLL_LOAD, SPEED, VISCOUS, half, cells).friction_coefficient,
                homogenised=steady_sphere(RADIUS, ROLL_LOAD, SPEED, effective, half, cells).friction_coefficient,
                layered=layered(0.0), gapped=layered(bead))


def roll(bead, seed, fraction, cells_per_radius, distance, with_beads=True, width=WIDTH, depth=DEPTH):
    """The framework's transient roll over beads filling ``|x2| <= width a``, depths ``bead`` to ``bead + depth a``,
    along the material from -width a to distance + width a (the roll's distance [a]); returns the friction
    coefficient per step, the bodies and the seconds."""
    cell = CONTACT / cells_per_radius
    length = (distance + 2 * width) * CONTACT
    n1 = int(np.ceil((2 * length + 2 * MARGIN * CONTACT) / cell / 8.0)) * 8
    n2 = int(np.ceil(2 * (width + MARGIN) * CONTACT / cell / 8.0)) * 8
    layers = int(np.ceil((bead + depth * CONTACT) / cell))
    grid = fw.Grid(shape=(n1, n2), size=(n1 * cell, n2 * cell), depth=layers * cell, layers=layers)
    bodies = None
    if with_beads:
        region = ((-width * CONTACT, (distance + width) * CONTACT), (-width * CONTACT, width * CONTACT),
                  (bead, bead + depth * CONTACT))
        bodies = inclusions.random_dispersion(fraction, region, bead, GLASS, gap=GAP * bead, seed=seed)
    simulation = fw.Simulation(grid=grid, material=VISCOUS, indenter=indenters.Sphere(radius=RADIUS),
                               schedule=schedules.Rolling(load=ROLL_LOAD, velocity=(SPEED, 0.0),
                                                          distance=distance * CONTACT),
                               inclusions=bodies)
    begin = time.perf_counter()
    result = simulation.run()
    return dict(friction=np.asarray(result.friction_coefficient), bodies=0 if bodies is None else len(bodies),
                seconds=time.perf_counter() - begin, grid=grid)


def rolling_main(args):
    """The rolling study: per bead radius and seed, the transient roll's last friction coefficient against the
    steady references, and the same roll without beads against the matrix's steady reference."""
    plain_run = roll(CONTACT / args.radii[0], 0, args.fraction, args.cells_per_radius, ROLL_DISTANCE,
                     with_beads=False, width=args.width, depth=args.depth)
    print(f"rolling: R {RADIUS * 1e3} mm, W {ROLL_LOAD:.2f} N, V {SPEED * 1e3:.2f} mm/s, {ROLL_DISTANCE} a of "
          f"rolling, cell a/{args.cells_per_radius}; the plain roll {plain_run['grid'].shape}: last friction "
          f"{plain_run['friction'][-1]:.6f} in {plain_run['seconds']:.0f} s", flush=True)
    for divisor in args.radii:
        bead = CONTACT / divisor
        refs = rolling_references(args.fraction, bead, args.depth)
        print(f"bead r = a/{divisor:g}: steady friction " + ", ".join(f"{k} {v:.6f}" for k, v in refs.items())
              + f"; the plain roll / the matrix's steady {plain_run['friction'][-1] / refs['matrix'] - 1:+.4f}",
              flush=True)
        for seed in args.seeds:
            out = roll(bead, seed, args.fraction, args.cells_per_radius, ROLL_DISTANCE, width=args.width,
                       depth=args.depth)
            start = min(int(2 * args.cells_per_radius), len(out["friction"]) // 2)      # after 2 a of rolling
            settled = out["friction"][start:]
            mean = settled.mean() / (plain_run["friction"][-1] / refs["matrix"])
            print(f"  seed {seed}: {out['bodies']} beads, {out['seconds']:.0f} s; friction after the first 2 a: mean "
                  f"{settled.mean():.6f}, {settled.min():.6f} to {settled.max():.6f}; the mean divided by the plain "
                  f"roll's error: " + "; ".join(f"vs {k} {mean / v - 1:+.4f}" for k, v in refs.items()), flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--radii", type=float, nargs="+", default=[3, 4, 5], help="bead radius as a / these")
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--fraction", type=float, default=0.2)
    parser.add_argument("--cells-per-radius", type=int, default=15, help="cuboids per contact radius a")
    parser.add_argument("--width", type=float, default=WIDTH, help="the filled box's half-width [a]")
    parser.add_argument("--depth", type=float, default=DEPTH, help="the filled depth [a]")
    parser.add_argument("--roll", action="store_true",
                        help="the rolling case instead: a viscoelastic matrix, the steady friction coefficient")
    args = parser.parse_args()
    if args.roll:
        rolling_main(args)
        return
    refs = references(args.fraction, args.depth)
    effective = refs["effective"]
    print(f"matrix E {MATRIX.young / 1e9:.2f} GPa nu {MATRIX.poisson}; glass E {GLASS.young / 1e9:.0f} GPa; fraction "
          f"{args.fraction}; Mori-Tanaka E {effective.young / 1e9:.3f} GPa nu {effective.poisson:.4f}; "
          f"R {RADIUS * 1e3} "
          f"mm, W {LOAD:.2f} N, a {CONTACT * 1e3} mm; box +-{args.width} a, filled {args.depth} a below a top gap of "
          f"one bead radius; cell a/{args.cells_per_radius}")
    for name in ("matrix", "homogenised", "layered"):
        approach, radius = refs[name]
        print(f"  {name:12s} approach {approach * 1e6:.4f} um ({approach / refs['matrix'][0] - 1:+.4f} of the "
              f"matrix's), contact radius {radius * 1e3:.4f} mm ({radius / refs['matrix'][1] - 1:+.4f})")
    for divisor in args.radii:
        bead = CONTACT / divisor
        base = plain(args.cells_per_radius, bead, args.width, args.depth)
        refs["gapped"] = gapped(bead, args.fraction, args.depth)
        print(f"\nbead r = a/{divisor:g} ({args.cells_per_radius / divisor:.2f} cuboids per radius): the plain grid "
              f"{grid_for(bead, args.cells_per_radius, args.width, args.depth).shape} x "
              f"{grid_for(bead, args.cells_per_radius, args.width, args.depth).layers} layers: approach "
              f"{base[0] / refs['matrix'][0] - 1:+.5f}, contact radius {base[1] / refs['matrix'][1] - 1:+.5f} "
              f"from Hertz; the layered reference under a matrix gap of r: approach "
              f"{refs['gapped'][0] / refs['matrix'][0] - 1:+.4f}, contact radius "
              f"{refs['gapped'][1] / refs['matrix'][1] - 1:+.4f} of the matrix's", flush=True)
        rows = []
        for seed in args.seeds:
            row = filled(bead, seed, args.fraction, args.cells_per_radius, args.width, args.depth)
            diff = compare(row, base, refs)
            rows.append(diff)
            print(f"  seed {seed}: {row['bodies']} beads (fraction {row['fraction']:.4f}, of the staircase "
                  f"{row['staircase']:.4f}), {row['seconds']:.0f} s; "
                  f"approach {row['approach'] * 1e6:.4f} um, contact radius {row['contact_radius'] * 1e3:.4f} mm; "
                  + "; ".join(f"vs {name} {d[0]:+.4f} / {d[1]:+.4f}" for name, d in diff.items()), flush=True)
        for name in ("matrix", "homogenised", "layered", "gapped"):
            values = np.array([d[name] for d in rows])
            print(f"  mean vs {name:12s} approach {values[:, 0].mean():+.4f} (spread {np.ptp(values[:, 0]):.4f}), "
                  f"contact radius {values[:, 1].mean():+.4f} (spread {np.ptp(values[:, 1]):.4f})", flush=True)


if __name__ == "__main__":
    main()
