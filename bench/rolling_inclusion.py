"""A sphere rolling over a viscoelastic half-space that holds an elastic inhomogeneity, timed.

This project alone: no peer code couples rolling contact with inhomogeneities. The accuracy is
checked in ``tests/test_inclusions_rolling.py`` and ``tests/test_inclusions_viscoelastic.py``;
here only the cost. A rigid sphere R = 10 mm, W = 30 N rolls at 0.5 mm/s along x1 over a
polymer-like matrix (E(0) = 3 GPa, E(inf) = 1 GPa, nu = 0.35: a = 0.4 mm at the glassy modulus)
on a 128 x 128 grid of 25 um cells (40 layers, 1 mm deep), over a glass sphere (E = 70 GPa,
nu = 0.22) of 20 cells per diameter whose centre lies 0.4 mm deep and 0.5 mm ahead of the body;
the body rolls 8 cells by default (8 steps, one per cell: 0.2 mm, the inhomogeneity under the
contact's leading half; ``--cells 40`` rolls it past, about 15 minutes per matrix). The matrix's relaxation is spread over 2 or 8 Prony
terms (relaxation times 0.02-0.2 s; the longest retardation time, 0.6 s, makes a wake of 0.3 mm). Prints the machine, then per
matrix: steps per second, the time per step split into the contact solves (Polonsky-Keer), the
equivalent-inclusion solves (GMRES) and the rest of the coupling (contact stress at the box,
the eigenstrains' surface displacement, histories), the coupling and GMRES iterations per step,
and the memory (peak resident size).

    .venv/bin/python bench/rolling_inclusion.py [--cells 8] [--terms 2 8]
"""
import argparse
import os
import resource
import sys
import time
from unittest import mock

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import framework as fw  # noqa: E402
from framework import inclusions, indenters, materials, schedules, simulation  # noqa: E402
from framework.inclusions import equivalent  # noqa: E402
from elastic_hertz import machine  # noqa: E402
from rolling import libraries  # noqa: E402

CELL = 25e-6
GLASS = materials.Elastic(70e9, 0.22)


def matrix(terms):
    """E(0) = 3 GPa relaxing to 1 GPa over ``terms`` equal Prony terms, times 0.02-0.2 s."""
    times = np.geomspace(0.02, 0.2, terms)
    return materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(2e9 / terms, float(t)) for t in times], poisson=0.35)


class Timer:
    """Cumulative wall time and calls of a wrapped function."""

    def __init__(self, function):
        self.function, self.seconds, self.calls, self.iterations = function, 0.0, 0, 0

    def __call__(self, *args, **kwargs):
        begin = time.perf_counter()
        out = self.function(*args, **kwargs)
        self.seconds += time.perf_counter() - begin
        self.calls += 1
        if isinstance(out, tuple):            # solve_for: (eigenstrain, disturbance, iterations, ...)
            self.iterations += out[2]
        return out


def case(terms, cells):
    grid = fw.Grid(shape=(128, 128), size=(128 * CELL, 128 * CELL), depth=40 * CELL, layers=40)
    body = inclusions.Ellipsoid(center=(0.5e-3, 0.0, 0.4e-3), semi_axes=(10 * CELL,) * 3, material=GLASS)
    begin = time.perf_counter()
    sim = fw.Simulation(grid=grid, material=matrix(terms), indenter=indenters.Sphere(radius=10e-3),
                        schedule=schedules.Rolling(load=30.0, velocity=(0.5e-3, 0.0), distance=cells * CELL),
                        inclusions=[body])
    build = time.perf_counter() - begin
    contact = Timer(simulation.solve_normal)
    inner = Timer(equivalent.EquivalentInclusionProblem.solve_for)

    def solve_for(self, *args, **kwargs):
        return inner(self, *args, **kwargs)

    with mock.patch.object(simulation, "solve_normal", contact), \
            mock.patch.object(equivalent.EquivalentInclusionProblem, "solve_for", solve_for):
        begin = time.perf_counter()
        result = sim.run()
        run = time.perf_counter() - begin
    steps = len(result) - 1                     # the rest indentation, then one step per cell
    couplings = np.array([r.couplings for r in result.records])
    problem = sim._inclusion_problem
    return dict(build=build, run=run, steps=steps, contact=contact.seconds, inner=inner.seconds,
                gmres=inner.iterations, couplings=couplings, box=problem.shape,
                cells=int(np.count_nonzero(problem.indicator)),
                friction=float(result.friction_coefficient[-1]), peak=float(result.max_pressure.max()),
                rss=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=8, help="cells rolled (one step each)")
    parser.add_argument("--terms", type=int, nargs="+", default=[2, 8], help="Prony terms of the matrix")
    args = parser.parse_args()
    print(machine())
    print(libraries())
    print()
    for terms in args.terms:
        out = case(terms, args.cells)
        total = out["run"]
        other = total - out["contact"] - out["inner"]
        print(f"{terms} Prony terms: box {out['box']} cuboids, {out['cells']} in the sphere; "
              f"construction {out['build']:.2f} s")
        print(f"   {out['steps'] + 1} steps in {total:.1f} s: {(out['steps'] + 1) / total:.2f} steps/s; per step "
              f"contact {out['contact'] / (out['steps'] + 1):.3f} s, inclusion {out['inner'] / (out['steps'] + 1):.3f} s, "
              f"coupling rest {other / (out['steps'] + 1):.3f} s")
        print(f"   couplings per step {out['couplings'].mean():.1f} (max {out['couplings'].max()}), GMRES iterations "
              f"per step {out['gmres'] / (out['steps'] + 1):.1f}; friction at the end {out['friction']:.4g}, "
              f"peak pressure {out['peak'] / 1e6:.1f} MPa; peak RSS {out['rss']:.2f} GiB")


if __name__ == "__main__":
    main()
