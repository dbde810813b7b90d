"""A rigid sphere rolling over a viscoelastic half-space with a random dispersion of glass spheres below it.

Issue 26's benchmark: how a coupled rolling step grows with the number of bodies. The accuracy of the dispersion
path is checked in ``tests/test_dispersion.py`` (one body in a dispersion gives the one-body run bit for bit) and
the coupled physics in ``tests/test_inclusions_rolling.py``; here only the cost.

The case, in units of the glass spheres' radius r = 0.1 mm (E = 70 GPa, nu = 0.22), so that every resolution
solves the same bodies: ``inclusions.random_dispersion`` places ``count`` spheres (``--seed``, at least 0.25 r
apart) in a slab from 1 r to 7 r deep, square across, of the volume that holds exactly ``count`` spheres at the
volume ``--fraction`` (count * 4/3 pi r^3 / fraction); the slab's centre lies half the rolling distance ahead of
the contact, so the body rolls over its middle. The matrix is polymer-like (E(0) = 3 GPa relaxing to 1 GPa over
2 Prony terms, 0.02-0.2 s, nu = 0.35: bench/rolling_inclusion.py's ``matrix(2)``). The grid's cell is
r / ``--cells-per-radius`` (cubic cuboids: layers of one cell, 8 r deep), its surface the slab plus the rolling
distance plus 8 r of margin (at least twice the contact's reach behind its axis plus 3 wake lengths, 0.49 mm),
rounded up to a multiple of 32 cells. A rigid sphere R = 5 mm under W = 8 N (Hertz contact radius 0.21 mm =
2.1 r at the glassy modulus, a / R = 0.04: small strains) rolls at 0.25 mm/s along x1 for ``--steps`` cells, one
step per cell. Each case runs in a child process (its own peak memory). Prints the machine, then per count:

- bodies, cuboids inside the bodies, the inclusion box (shape, cuboids), the surface grid;
- construction time (the dispersion, the Simulation with its box operator);
- per-step time: the median of the steps after the first two (the rest indentation and the first roll solve
  from nothing), and every step's time;
- eigenstrain-operator products per step (``problem.products`` differences) and coupling iterations per step;
- peak RSS of the child process;
- the same rolling step without the bodies (median of its steps after the first two);
- or, where a step's coupling does not converge (``ConvergenceError``), that step, its time and products;
- with ``--static``, the products of the equivalent-inclusion system alone on the same bodies (a uniform strain in
  an elastic matrix, solved to 1e-7): how the system's difficulty grows with the count, without the contact.

    OMP_NUM_THREADS=1 .venv/bin/python bench/dispersion.py [--bodies 10 100 300] [--cells-per-radius 8]
        [--steps 40] [--fraction 0.1] [--seed 0] [--coupling-tolerance 1e-6] [--static] [--no-plain]
        [--operator particle_mesh]

Measured (README, "Cost of a rolling step over a dispersion"): 10, 30, 60 and 100 bodies at 4 cuboids per radius
run at the default tolerances, 1.3-13 s a step and 18-22 products; the last version 100 bodies at 4 and 8 cuboids per
radius 1.33 and 6.32 GiB (22 and 24 products a step), 300 at 4 2.75 GiB; this version, with the coupling's histories
and the records on the bodies' cuboids, 100 at 8 4.84 GiB over 4 recorded steps (this bench keeps no records). Before the Fourier preconditioner took a
share of the contrast for several bodies (equivalent.DISPERSION_CONTRAST; for more than 16 at first, now for two or
more), its system alone took 19, 21, 70 and 120 products for 10, 30, 60 and 100 bodies and the rolling runs over 60
and 100 stopped at 100 couplings. With the preconditioner solving the bodies' system in its filled periodic cell
(equivalent.EquivalentInclusionProblem._inner_solve), 10 to 100 bodies at 4 cuboids per radius take 7.4-8.0 products
a step (18-22 before) and 0.78-6.2 s (1.3-13 s). 300 bodies at 8 cuboids per radius (box 7.75 M cuboids) had their
preconditioner's matrices above equivalent.FOURIER_BYTES and solved each cuboid alone, 32 products and 542 s a step;
with FOURIER_CUBOID_BYTES a box cuboid, 9 products and 175 s a step, 10.8 GiB. On the bodies' cuboids alone
(``--operator particle_mesh``, README "Many fine bodies"): 10 / 100 / 300 bodies at 8 cuboids per radius 2.15 / 23.0 /
91 s a step, 7.0 / 7.9 / 10.2 products, 0.55 / 1.76 / 4.35 GiB (the box: 2.71 / 33.3 / 131 s, 0.81 / 3.13 / 8.04 GiB).
"""
import argparse
import multiprocessing
import os
import resource
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import framework as fw  # noqa: E402
from framework import indenters, inclusions, materials, options as run_options, schedules  # noqa: E402
from framework.errors import ConvergenceError  # noqa: E402
from framework.inclusions.field import InclusionProblem, strain_vector  # noqa: E402
from elastic_hertz import machine  # noqa: E402
from rolling import libraries  # noqa: E402
from rolling_inclusion import matrix  # noqa: E402

RADIUS = 0.1e-3                 # glass sphere radius [m]
GLASS = materials.Elastic(70e9, 0.22)
TOP, THICKNESS = 1.0, 6.0       # the slab: from 1 r deep, 6 r thick (see the docstring)
DEPTH = 8.0                     # grid depth [r]
GAP = 0.25                      # least distance between two spheres [r]
MARGIN = 8.0                    # surface grid beyond the box and the roll, in all [r]
INDENTER, LOAD, SPEED = 5e-3, 8.0, 0.25e-3  # rigid sphere radius [m], load [N], speed [m/s]
WAKE = 0.65                     # longest retardation time [s]: matrix(2) 0.41 s, matrix(8) 0.6 s, rounded up
BEHIND = 2.5                    # the contact at rest reaches this far behind the axis [r], rounded up


def region(count, fraction):
    """The slab ((x1 lo, hi), (x2 lo, hi), (x3 lo, hi)) [m] of the volume that holds ``count`` spheres at ``fraction``,
    centred on x2 = 0 and on x1 = 0 (shifted ahead by the caller)."""
    volume = count * 4.0 / 3.0 * np.pi * RADIUS ** 3 / fraction
    thickness = THICKNESS * RADIUS
    side = np.sqrt(volume / thickness)
    return side, ((-side / 2, side / 2), (-side / 2, side / 2), (TOP * RADIUS, TOP * RADIUS + thickness))


def setup(count, cells_per_radius, steps, fraction, seed, tolerance=None, with_bodies=True, operator="box"):
    """The Simulation of one case, its bodies (or None) and its grid; ``tolerance``: the coupling's (None: default);
    ``operator``: ``Options.inclusion_operator``."""
    cell = RADIUS / cells_per_radius
    side, slab = region(count, fraction)
    ahead = steps * cell / 2                            # the slab's centre: half the roll ahead of the contact
    slab = ((slab[0][0] + ahead, slab[0][1] + ahead), slab[1], slab[2])
    needed = max(side + steps * cell + MARGIN * RADIUS, 2 * (BEHIND * RADIUS + 3 * SPEED * WAKE))   # and the wake
    n = int(np.ceil(needed / cell / 32.0)) * 32
    layers = int(round(DEPTH * cells_per_radius))
    grid = fw.Grid(shape=(n, n), size=(n * cell, n * cell), depth=layers * cell, layers=layers)
    bodies = None
    if with_bodies:
        bodies = inclusions.random_dispersion(fraction, slab, RADIUS, GLASS, gap=GAP * RADIUS, seed=seed)
    sim = fw.Simulation(grid=grid, material=matrix(2), indenter=indenters.Sphere(radius=INDENTER),
                        schedule=schedules.Rolling(load=LOAD, velocity=(SPEED, 0.0), distance=steps * cell),
                        inclusions=bodies,
                        options=run_options.Options(inclusion_operator=operator,
                                                    **({} if tolerance is None else {"coupling_tolerance": tolerance})))
    return sim, bodies, grid


def run(count, cells_per_radius, steps, fraction, seed, tolerance=None, with_bodies=True, operator="box"):
    """One case, timed; returns plain figures (it runs in a child process)."""
    begin = time.perf_counter()
    sim, bodies, grid = setup(count, cells_per_radius, steps, fraction, seed, tolerance, with_bodies, operator)
    build = time.perf_counter() - begin
    problem = sim._inclusion_problem
    times, products, couplings = [], [], []
    done, failure, peak = 0, None, float("nan")
    begin = time.perf_counter()
    try:
        for record in sim.steps():
            times.append(time.perf_counter() - begin)
            if problem is not None:
                products.append(problem.problem.products - done)
                done = problem.problem.products
                couplings.append(int(record.couplings))
            peak = float(record.pressure.max())
            begin = time.perf_counter()
    except ConvergenceError as error:       # reported, with the step and the time it took, instead of the figures
        failure = (len(times), time.perf_counter() - begin, problem.problem.products - done, str(error))
    out = dict(build=build, steps=times, products=products, couplings=couplings, grid=grid.shape,
               layers=grid.layers, peak=peak, failure=failure,
               rss=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20)
    if problem is not None:
        boxed = getattr(problem, "indicator", None) is not None      # the bodies' problem has no box
        out.update(bodies=len(bodies), box=tuple(int(m) for m in problem.shape) if boxed else (len(problem.body), 1, 1),
                   cells=int(np.count_nonzero(problem.indicator)) if boxed else len(problem.body))
    return out


def static(count, cells_per_radius, steps, fraction, seed):
    """The equivalent-inclusion system alone on the same bodies: a uniform strain (1e-3, 0, -1e-3) in an elastic
    matrix (E = 3 GPa, nu = 0.35) solved to 1e-7; returns its products and seconds."""
    _, bodies, grid = setup(count, cells_per_radius, steps, fraction, seed, with_bodies=True)
    begin = time.perf_counter()
    problem = InclusionProblem(grid, materials.Elastic(3e9, 0.35), bodies, margin=0.0)
    problem.problem.solve(strain_vector(np.diag([1e-3, 0.0, -1e-3]), name="applied strain"), tolerance=1e-7)
    return problem.problem.products, time.perf_counter() - begin


def child(*args, **kwargs):
    """``run`` in a fresh forked process: its peak RSS is its own."""
    with multiprocessing.get_context("fork").Pool(1) as pool:
        return pool.apply(run, args, kwargs)


def later(times):
    """Median of the steps after the first two [s] (all of them when there are fewer than three)."""
    times = np.asarray(times)
    return float(np.median(times[2:] if len(times) > 2 else times))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bodies", type=int, nargs="+", default=[10, 100, 300], help="counts of glass spheres")
    parser.add_argument("--cells-per-radius", type=int, default=8, help="cuboids per sphere radius")
    parser.add_argument("--steps", type=int, default=40, help="cells rolled (one step each)")
    parser.add_argument("--fraction", type=float, default=0.1, help="volume fraction of the slab")
    parser.add_argument("--seed", type=int, default=0, help="seed of the dispersion")
    parser.add_argument("--coupling-tolerance", type=float, default=None,
                        help="options.coupling_tolerance (default: the framework's, 1e-8)")
    parser.add_argument("--static", action="store_true",
                        help="also solve the equivalent-inclusion system alone under a uniform strain (its products)")
    parser.add_argument("--no-plain", action="store_true", help="skip the same run without bodies")
    parser.add_argument("--operator", choices=("box", "particle_mesh"), default="box",
                        help="Options.inclusion_operator: the box around the bodies, or their cuboids alone")
    args = parser.parse_args()
    print(machine())
    print(libraries())
    print(f"glass spheres r = {RADIUS * 1e3:.2f} mm, {args.cells_per_radius} cuboids per radius (cell "
          f"{RADIUS / args.cells_per_radius * 1e6:.1f} um), fraction {args.fraction:.2f}, seed {args.seed}, "
          f"{args.steps} steps, coupling tolerance {args.coupling_tolerance or 'default (1e-8)'}; "
          f"OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}\n", flush=True)
    for count in args.bodies:
        options = (count, args.cells_per_radius, args.steps, args.fraction, args.seed, args.coupling_tolerance)
        out = child(*options, operator=args.operator)
        side = region(count, args.fraction)[0]
        box = out["box"]
        print(f"{out['bodies']} bodies ({out['cells']} cuboids inside them) in a slab {side * 1e3:.2f} x "
              f"{side * 1e3:.2f} x {THICKNESS * RADIUS * 1e3:.2f} mm; box {box[0]} x {box[1]} x {box[2]} = "
              f"{np.prod(box) / 1e6:.3f} M cuboids; surface grid {out['grid'][0]} x {out['grid'][1]}, "
              f"{out['layers']} layers")
        if args.static:
            products, seconds = static(*options[:5])
            print(f"  the equivalent-inclusion system alone (uniform strain, elastic matrix, tolerance 1e-7): "
                  f"{products} products, {seconds:.1f} s", flush=True)
        if out["failure"] is not None:
            k, seconds, spent, message = out["failure"]
            print(f"  construction {out['build']:.2f} s; step {k} (0: the rest indentation) stopped after "
                  f"{seconds:.1f} s and {spent} products: {message}")
            print(f"  steps before it [s]: {' '.join(f'{t:.2f}' for t in out['steps'])}; products: "
                  f"{' '.join(map(str, out['products']))}; peak RSS {out['rss']:.2f} GiB\n", flush=True)
            continue
        step = later(out["steps"])
        products = np.asarray(out["products"])
        couplings = np.asarray(out["couplings"])
        tail = slice(2, None) if len(products) > 2 else slice(None)
        print(f"  construction {out['build']:.2f} s; a step (median after the first two) {step:.2f} s; steps "
              f"[s]: {' '.join(f'{t:.2f}' for t in out['steps'])}")
        print(f"  products per step: {' '.join(map(str, products))} (mean after the first two "
              f"{products[tail].mean():.1f}); couplings per step: {' '.join(map(str, couplings))}; "
              f"{step / max(products[tail].mean(), 1):.2f} s a product (the step over its products)")
        print(f"  peak pressure at the end {out['peak'] / 1e6:.1f} MPa; peak RSS {out['rss']:.2f} GiB", flush=True)
        if not args.no_plain:
            plain = child(*options, with_bodies=False)
            print(f"  the same step without the bodies {later(plain['steps']) * 1e3:.0f} ms (peak RSS "
                  f"{plain['rss']:.2f} GiB)", flush=True)
        print(flush=True)


if __name__ == "__main__":
    main()
