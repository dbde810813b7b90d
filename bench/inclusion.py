"""Elastic inhomogeneities: one coupled contact step, and the equivalent-inclusion solve on large boxes, timed.

This project alone: Tamaas, the peer of ``elastic_hertz.py``, has no
inhomogeneities. Their accuracy is checked in the tests (Eshelby's interior
solution, the half-space references); here only their cost. Prints the
machine, then

1. one coupled static step (``Simulation(..., inclusions=[...])``): a rigid
   sphere R = 10 mm, W = 50 N on steel (E = 210 GPa, nu = 0.3; Hertz radius
   a = 0.118 mm) over a tungsten-carbide sphere (E = 600 GPa, nu = 0.22) of
   20 cells per diameter, centre depth a, under a 128 x 128 contact grid of
   cubes a / 16 (32 layers, 2 a deep), the default box margin (half a
   semi-axis); the construction (the eigenstrain operator's spectra), the run,
   the coupling iterations, the eigenstrain-operator products and the memory; one
   product beside its FFTs replayed alone (``rolling_inclusion.py``'s floor), and the
   same steps without the inhomogeneity;
2. ``solve_inclusions``'s two stages on boxes of n^3 cuboids (n = 64, and 128
   with ``--large``): a sphere of diameter n cells, margin 0, so the box is
   the sphere's bounding block, under a uniform uniaxial strain 1e-3 along
   x1; build = ``InclusionProblem`` (operator spectra, indicator,
   preconditioner), solve = the GMRES solve at tolerance 1e-10, memory, and one
   product beside its FFTs alone (best of 3).

Memory: the process's peak resident size (``ru_maxrss``: it only grows, so
each case reports the peak so far, cases in increasing size) and the peak of
the Python-tracked allocations (numpy arrays) during the case (tracemalloc,
reset per case) with ``--traced`` only: tracing slows the stages it watches
(the 64^3 build by about a second), so the timed runs go untraced.

    .venv/bin/python bench/inclusion.py [--sizes 64] [--large] [--skip-contact] [--traced]
"""
import argparse
import os
import resource
import sys
import time
import tracemalloc

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import framework as fw  # noqa: E402
from framework import inclusions, indenters, materials, reference, schedules  # noqa: E402
from framework.inclusions.field import InclusionProblem, strain_vector  # noqa: E402
from elastic_hertz import machine  # noqa: E402
from rolling import libraries  # noqa: E402
from rolling_inclusion import product_and_floor  # noqa: E402

STEEL = materials.Elastic(young=210e9, poisson=0.3)
CARBIDE = materials.Elastic(young=600e9, poisson=0.22)
RADIUS, LOAD = 10e-3, 50.0
A = reference.HertzSphere(radius=RADIUS, load=LOAD, contact_modulus=STEEL.contact_modulus).contact_radius


def peak_rss():
    """Peak resident set size of this process so far [GiB] (Linux reports kiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


class traced:
    """Peak tracemalloc allocation [GiB] during the ``with`` block (``self.peak``)."""

    def __enter__(self):
        tracemalloc.reset_peak()
        return self

    def __exit__(self, *_):
        self.peak = tracemalloc.get_traced_memory()[1] / 2**30 if tracemalloc.is_tracing() else float("nan")


def coupled_step(cells=128, diameter=20, with_body=True):
    """Coupled static steps (the load, then 1.2 and 1.4 times it); their times, couplings, products, memory, and one
    product of the box's operator beside its FFTs alone (best of 10, in turns); ``with_body=False``: the same steps
    without the inhomogeneity (their times only).

    The first step carries what a process does once (numba's compiled passes loaded from its cache, FFTW's
    plans measured, the Fourier preconditioner's matrices): the further steps cost what a step costs.
    Untraced (tracemalloc slows the loading of the compiled passes twofold): memory is the peak RSS.
    """
    cell = A / 16
    grid = fw.Grid(shape=(cells, cells), size=(cells * cell, cells * cell), depth=2 * A, layers=32)
    sphere = inclusions.Ellipsoid(center=(0.0, 0.0, A), semi_axes=(diameter * cell / 2,) * 3, material=CARBIDE)
    begin = time.perf_counter()
    sim = fw.Simulation(grid=grid, material=STEEL, indenter=indenters.Sphere(radius=RADIUS),
                        schedule=schedules.Static(load=[LOAD, 1.2 * LOAD, 1.4 * LOAD]),
                        inclusions=[sphere] if with_body else None)
    build = time.perf_counter() - begin
    steps, records = [], []
    begin = time.perf_counter()
    for record in sim.steps():
        steps.append(time.perf_counter() - begin)
        records.append(record)
        begin = time.perf_counter()
    if not with_body:
        return dict(steps=steps)
    problem = sim._inclusion_problem
    product, floor = product_and_floor(problem.operator, 10)
    return dict(build=build, steps=steps, couplings=[r.couplings for r in records], products=problem.problem.products,
                product=product, floor=floor,
                contact_iterations=int(records[0].iterations), box=problem.shape,
                cells=int(np.count_nonzero(problem.indicator)), rss=peak_rss(), pressure=float(records[0].pressure.max()))


def box_solve(n):
    """``solve_inclusions``'s build and solve on an n^3 box filled by a sphere of diameter n cells."""
    cell = 1e-6
    radius = n * cell / 2
    # the box is the sphere's bounding block: start it one layer down, leave a cell of grid around it
    grid = fw.Grid(shape=(n + 2, n + 2), size=((n + 2) * cell, (n + 2) * cell), depth=(n + 2) * cell,
                   layers=n + 2)
    sphere = inclusions.Ellipsoid(center=(0.0, 0.0, cell + radius), semi_axes=(radius * (1 - 1e-9),) * 3,
                                  material=CARBIDE)
    applied = strain_vector(np.diag([1e-3, 0.0, 0.0]), name="applied_strain")
    with traced() as memory:
        begin = time.perf_counter()
        problem = InclusionProblem(grid, STEEL, inclusions.InclusionSet([sphere]), margin=0.0, recycle=False)
        build = time.perf_counter() - begin
        begin = time.perf_counter()
        solution = problem.problem.solve(applied, tolerance=1e-10)
        solve = time.perf_counter() - begin
    product, floor = product_and_floor(problem.problem.operator, 3)
    return dict(box=problem.shape, cells=int(np.count_nonzero(problem.indicator)), build=build, solve=solve,
                iterations=solution.iterations, residual=solution.residual, traced=memory.peak, rss=peak_rss(),
                product=product, floor=floor)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[64], help="box sides n (cuboids) of part 2")
    parser.add_argument("--large", action="store_true", help="add the 128^3 box (minutes, several GiB)")
    parser.add_argument("--skip-contact", action="store_true", help="leave out part 1")
    parser.add_argument("--traced", action="store_true",
                        help="also trace part 2's numpy allocations (tracemalloc: slows it by about a second at 64^3)")
    args = parser.parse_args()
    sizes = sorted(set(args.sizes + ([128] if args.large else [])))
    print(machine())
    print(libraries())
    if not args.skip_contact:
        row = coupled_step()
        steps = row["steps"]
        print(f"\n1. coupled step: rigid sphere R = {RADIUS * 1e3:g} mm, W = {LOAD:g} N on steel (a = {A * 1e3:.4g} mm),"
              f" WC sphere of 20 cells per diameter at depth a, contact grid 128 x 128 of cubes a/16")
        print(f"   box {row['box']} cuboids, {row['cells']} in the inhomogeneity ({6 * row['cells']} unknowns)")
        print(f"   construction {row['build']:.2f} s; first step {steps[0]:.2f} s (with the process's one-time loading "
              f"and planning), a further step (1.2 W, 1.4 W) {min(steps[1:]):.2f} s (goal <= 1.5 s; before this "
              f"version 5.9 s and 7.6 s); couplings per step {row['couplings']}, {row['products']} eigenstrain "
              f"products in all, contact (PK) iterations {row['contact_iterations']}")
        plain = coupled_step(with_body=False)["steps"]
        print(f"   one product {1e3 * row['product']:.1f} ms, its FFTs alone {1e3 * row['floor']:.1f} ms (ratio "
              f"{row['product'] / row['floor']:.2f}); the same further step without the inhomogeneity "
              f"{1e3 * min(plain[1:]):.0f} ms")
        print(f"   peak RSS {row['rss']:.3f} GiB; p_max {row['pressure'] / 1e9:.4g} GPa", flush=True)
    if args.traced:
        tracemalloc.start()
    print("\n2. solve_inclusions on n^3 boxes (sphere of diameter n cells, WC in steel, uniaxial 1e-3); goals: 64^3 "
          "build + solve <= 5 s, 128^3 <= 90 s and <= 3 GiB; before this version 64^3: 17 s + 15 s, 2.1 GiB; "
          "128^3: 105 s + 328 s, 13.9 GiB")
    print(f"{'box':>14} {'incl. cells':>11} {'unknowns':>9} {'build s':>8} {'solve s':>8} {'GMRES':>6} "
          f"{'residual':>9} {'traced GiB':>10} {'RSS GiB':>8} {'product s':>9} {'its FFTs s':>10}")
    for n in sizes:
        row = box_solve(n)
        print(f"{'x'.join(map(str, row['box'])):>14} {row['cells']:>11} {6 * row['cells']:>9} {row['build']:>8.2f} "
              f"{row['solve']:>8.2f} {row['iterations']:>6} {row['residual']:>9.2e} {row['traced']:>10.3f} "
              f"{row['rss']:>8.3f} {row['product']:>9.3f} {row['floor']:>10.3f}", flush=True)


if __name__ == "__main__":
    main()
