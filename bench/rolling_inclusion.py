"""A sphere rolling over a viscoelastic half-space that holds an elastic inhomogeneity, timed beside its floor.

This project alone: no peer code couples rolling contact with inhomogeneities. The accuracy is
checked in ``tests/test_inclusions_rolling.py``, ``tests/test_inclusions_viscoelastic.py`` and
``tests/test_inclusions_speed.py``; here only the cost. A rigid sphere R = 10 mm, W = 30 N rolls at
0.5 mm/s along x1 over a polymer-like matrix (E(0) = 3 GPa, E(inf) = 1 GPa, nu = 0.35: a = 0.4 mm at
the glassy modulus) on a 128 x 128 grid of 25 um cells (40 layers, 1 mm deep), over a glass sphere
(E = 70 GPa, nu = 0.22) of 20 cells per diameter whose centre lies 0.4 mm deep and 0.5 mm ahead of
the body; the body rolls 8 cells by default (8 steps, one per cell: 0.2 mm, the inhomogeneity under
the contact's leading half; ``--cells 40`` rolls it past). The matrix's relaxation is spread over 2
or 8 Prony terms (relaxation times 0.02-0.2 s; the longest retardation time, 0.6 s, makes a wake of
0.3 mm). Prints the machine, then

1. one eigenstrain-operator product on the box (30 x 31 x 30 cuboids), best of ``--repeat``, beside
   its floor (the two taken in turns, so that a drift of the machine's speed falls on both): the same FFTs
   replayed alone, in the same order (the pruned 3-D transforms of the six
   components on the padded box, :mod:`framework.operators.box_fft`, and the pruned surface transforms
   of the Boussinesq correction);
   and one forward plus inverse real 3-D FFT of the box doubled in each direction (60 x 62 x 60),
   the unit of the step's cost below (an "FFT pair");
2. per matrix: the time per step split into the contact solves, the eigenstrain products, the
   preconditioner and the rest; products and coupling iterations per step (the steps after the
   first, whose box has moved: the first solves from nothing); the step in FFT pairs; the same
   rolling step without the inhomogeneity; peak memory;
3. the figures before this version (README's table of the earlier bench), for comparison.

    .venv/bin/python bench/rolling_inclusion.py [--cells 8] [--terms 2 8] [--repeat 10]
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
from framework import fft, inclusions, indenters, materials, schedules, simulation  # noqa: E402
from framework.inclusions import equivalent  # noqa: E402
from framework.operators import eigenstrain  # noqa: E402
from elastic_hertz import machine  # noqa: E402
from rolling import libraries  # noqa: E402

CELL = 25e-6
GLASS = materials.Elastic(70e9, 0.22)
#: The bench before this version (README, stop 20's table; same machine kind): per step with 2 / 8 terms.
BEFORE = {"step": "17.5-20 s (9.5 s measured again here at the start of this version)", "products": 54,
          "couplings": 6.8, "product": "0.17-0.23 s (0.159 s measured again)", "rss": 1.06}


def matrix(terms):
    """E(0) = 3 GPa relaxing to 1 GPa over ``terms`` equal Prony terms, times 0.02-0.2 s."""
    times = np.geomspace(0.02, 0.2, terms)
    return materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(2e9 / terms, float(t)) for t in times], poisson=0.35)


def grid():
    return fw.Grid(shape=(128, 128), size=(128 * CELL, 128 * CELL), depth=40 * CELL, layers=40)


def best(function, repeat):
    times = []
    for _ in range(repeat):
        begin = time.perf_counter()
        function()
        times.append(time.perf_counter() - begin)
    return min(times)


def product_and_floor(operator, repeat):
    """Best time of one product and of its FFTs replayed alone (same transforms, same order)."""
    field = np.random.default_rng(0).normal(size=(*operator.shape, 6))
    operator.strain(field)                                   # plans made, kernels warm
    box = operator._box_fft()
    surface = operator._surface

    def transforms():
        box.transforms_alone()                               # the box's pruned 3-D transforms
        for _ in range(surface.layers):                      # the traction's pruned forward transforms
            surface._rows()
            surface._columns()
        surface._plane_inverse()                             # cut to the patch, and back
        surface._plane_forward()
        for _ in range(surface.layers):                      # the correction's pruned inverse transforms
            surface._back_columns()
            surface._back_rows()
    # taken in turns, each the best of its repeats: a drift of the machine's speed (10 % on this VM) falls on both
    products, floors = [], []
    for _ in range(repeat):
        products.append(best(lambda: operator.strain(field), 1))
        floors.append(best(transforms, 1))
    return min(products), min(floors)


def pair_time(shape, repeat):
    """One forward and one inverse real 3-D FFT of ``shape`` (planned as the operator plans its own)."""
    real, spectrum = fft.zeros(shape), fft.zeros((*shape[:2], shape[2] // 2 + 1), complex)
    effort = "FFTW_MEASURE" if np.prod(shape) <= eigenstrain.MEASURED_FFT_POINTS else "FFTW_ESTIMATE"
    real[...] = np.random.default_rng(1).random(shape)
    forward = fft.Transform(real, spectrum, axes=(0, 1, 2), effort=effort)
    back = fft.Transform(spectrum, real, axes=(0, 1, 2), effort=effort)
    return best(lambda: (forward(), back()), repeat)


class Timer:
    """Cumulative wall time and calls of a wrapped function."""

    def __init__(self, function):
        self.function, self.seconds, self.calls = function, 0.0, 0

    def __call__(self, *args, **kwargs):
        begin = time.perf_counter()
        out = self.function(*args, **kwargs)
        self.seconds += time.perf_counter() - begin
        self.calls += 1
        return out


def case(terms, cells, with_body=True):
    body = inclusions.Ellipsoid(center=(0.5e-3, 0.0, 0.4e-3), semi_axes=(10 * CELL,) * 3, material=GLASS)
    begin = time.perf_counter()
    sim = fw.Simulation(grid=grid(), material=matrix(terms), indenter=indenters.Sphere(radius=10e-3),
                        schedule=schedules.Rolling(load=30.0, velocity=(0.5e-3, 0.0), distance=cells * CELL),
                        inclusions=[body] if with_body else None)
    build = time.perf_counter() - begin
    contact = Timer(simulation.solve_normal)
    boxed = Timer(simulation.boxed_solve.solve_boxed)      # (an open grid's solves go through the boxed solver)
    product = Timer(eigenstrain.HalfSpaceEigenstrain.strain)
    precondition = Timer(equivalent.EquivalentInclusionProblem._precondition)
    times = []

    def strain(self, *args, **kwargs):
        return product(self, *args, **kwargs)

    def precondition_(self, *args):
        return precondition(self, *args)

    with mock.patch.object(simulation, "solve_normal", contact), \
            mock.patch.object(simulation.boxed_solve, "solve_boxed", boxed), \
            mock.patch.object(eigenstrain.HalfSpaceEigenstrain, "strain", strain), \
            mock.patch.object(equivalent.EquivalentInclusionProblem, "_precondition", precondition_):
        begin = time.perf_counter()
        records = []
        for record in sim.steps():
            times.append(time.perf_counter() - begin)
            records.append(record)
            begin = time.perf_counter()
    out = dict(build=build, steps=np.array(times), contact=contact.seconds + boxed.seconds, records=records,
               product=product.seconds, products=product.calls, precondition=precondition.seconds,
               rss=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20)
    if with_body:
        problem = sim._inclusion_problem
        out.update(box=problem.shape, cells=int(np.count_nonzero(problem.indicator)),
                   couplings=np.array([r.couplings for r in records]), operator=problem.operator)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=8, help="cells rolled (one step each)")
    parser.add_argument("--terms", type=int, nargs="+", default=[2, 8], help="Prony terms of the matrix")
    parser.add_argument("--repeat", type=int, default=10, help="repeats of the product and its floor")
    args = parser.parse_args()
    print(machine())
    print(libraries())
    print()
    for k, terms in enumerate(args.terms):
        out = case(terms, args.cells)
        operator = out["operator"]
        if k == 0:
            product, floor = product_and_floor(operator, args.repeat)
            doubled = tuple(2 * m for m in operator.shape)
            pair = pair_time(doubled, args.repeat)
            print(f"1. one eigenstrain-operator product, box {operator.shape} cuboids (padded {operator.fft_shape}, "
                  f"surface grid {operator._surface.fft_shape}): {product * 1e3:.1f} ms; its FFTs replayed alone "
                  f"{floor * 1e3:.1f} ms: ratio {product / floor:.2f} (goal <= 1.5); before: {BEFORE['product']}")
            print(f"   one FFT pair of the box doubled ({'x'.join(map(str, doubled))}): {pair * 1e3:.2f} ms\n")
        steps = out["steps"]
        later = slice(2, None)                      # the rest indentation and the first roll solve from nothing
        per_step = float(np.median(steps[later]))    # (a step that plans a new FFT window costs 0.4 s once)
        couplings = out["couplings"]
        n = len(steps)
        plain = float(np.median(case(terms, args.cells, with_body=False)["steps"][later]))
        print(f"2. {terms} Prony terms: box {out['box']} cuboids, {out['cells']} in the sphere; construction "
              f"{out['build']:.2f} s")
        print(f"   {n} steps in {steps.sum():.1f} s; a step one cell on (median of steps 2-{n - 1}): {per_step:.2f} s "
              f"= {per_step / pair:.0f} FFT pairs (goal about 150); the same step without the inhomogeneity "
              f"{plain * 1e3:.0f} ms")
        print(f"   whole run: products {out['product']:.1f} s ({out['products']} products, "
              f"{out['product'] / max(out['products'], 1) * 1e3:.0f} ms each), preconditioner "
              f"{out['precondition']:.1f} s, contact solves {out['contact']:.1f} s, rest "
              f"{steps.sum() - out['product'] - out['precondition'] - out['contact']:.1f} s")
        print(f"   coupling iterations (one product each) per step: {' '.join(map(str, couplings))}; mean one "
              f"cell on {couplings[later].mean():.1f} (goal <= 10)")
        record = out["records"][-1]
        g = grid()
        friction = float((record.pressure * g.coordinates()[0]).sum() * g.cell_area / (10e-3 * 30.0))
        print(f"   at the end: friction {friction:.5f}, peak pressure {record.pressure.max() / 1e6:.2f} MPa; peak RSS "
              f"{out['rss']:.2f} GiB")
        print(f"   before this version: {BEFORE['step']} a step, {BEFORE['products']} products and "
              f"{BEFORE['couplings']} couplings a step, peak RSS {BEFORE['rss']} GiB\n", flush=True)


if __name__ == "__main__":
    main()
