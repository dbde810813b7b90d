"""A sphere rolling over a standard linear solid: steady-state solves and transient steps, timed.

This project alone: Tamaas, the peer of ``elastic_hertz.py`` and
``visco_indentation.py``, has no rolling (or frictionless sliding) contact and
no viscoelastic steady state in 3-D, so there is no side-by-side run. The
accuracy of these solves is checked in ``tests/test_rolling.py`` (dense
references, Hertz limits, low-speed expansion); here only their cost.

Problem as in ``tests/test_rolling.py``: E(t) = 10 + 90 exp(-t/1 s) MPa,
nu = 0.5 (contact retardation time lambda = 10 s), rigid sphere R = 10 mm,
W = 0.2 N: relaxed Hertz radius a0 = 0.483 mm. Every grid covers 12 a0 along
the motion (x1) and 6 a0 across with square cells (256 x 128: 21 cells per
a0). Default solver options (complementarity residual 1e-6). Prints the
machine, then

1. steady states (``Rolling(steady=True)``) at V lambda / a0 = 0.1, 1, 10
   (below, near and above the friction peak, which lies near 1.2): the time to
   build the operator (the kernel with the exponential filter, its spectrum)
   and to solve (best of ``--repeat`` runs, FFT plans warm), the operator
   products (GMRES and active-set updates: ``Result.iterations``), the
   active-set iterations and the time and conjugate-gradient iterations of the
   symmetric start (counted by wrapping functions of
   ``framework.steady_solver`` from outside), the contact cells and the
   friction coefficient;
2. a transient roll from rest over ``--cells`` cells at V lambda / a0 = 1:
   steps per second and Polonsky-Keer iterations per step;
3. the steady build and solve times against the number of cells at
   V lambda / a0 = 1, from 128 x 64 to 1024 x 512, and the fitted exponents.

    .venv/bin/python bench/rolling.py [--sizes 256 512] [--scaling 128 256 512 1024] [--repeat 3] [--cells 50]
"""
import argparse
import contextlib
import os
import sys
import time
from unittest import mock

import numpy as np
import scipy

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import framework as fw  # noqa: E402
from framework import indenters, materials, schedules, simulation, steady_solver  # noqa: E402
from elastic_hertz import machine  # noqa: E402

MATERIAL = materials.StandardLinearSolid(e_inf=1e7, e_1=9e7, tau=1.0, poisson=0.5)
SERIES = MATERIAL.contact_compliance()
RETARDATION = float(SERIES.times[0])                             # 10 s
RADIUS, LOAD = 10e-3, 0.2
A0 = (0.75 * LOAD * RADIUS * SERIES.relaxed) ** (1 / 3)          # relaxed Hertz radius [m]
ALONG, ACROSS = 12 * A0, 6 * A0                                  # grid sides [m]
WAKES = (0.1, 1.0, 10.0)                                         # V lambda / a0
PEAK = 1.0


def grid_of(n):
    return fw.Grid(shape=(n, n // 2), size=(ALONG, ACROSS))


def speed(wake):
    return wake * A0 / RETARDATION


@contextlib.contextmanager
def instrumented():
    """Time the operator build and the steady solve, count active-set iterations, without touching the code.

    ``solve_steady`` calls ``_gmres`` twice per active-set iteration and
    ``solve_normal`` once for its symmetric start (module globals, so wrapping
    them here sees every call).
    """
    counts = dict(build=0.0, solve=0.0, krylov=0, start=0.0, start_iterations=0)
    build_operator, solve, krylov, start = (simulation.SteadyRollingCompliance, simulation.solve_steady,
                                            steady_solver._gmres, steady_solver.solve_normal)

    def timed(function, key):
        def wrapper(*args, **kwargs):
            begin = time.perf_counter()
            out = function(*args, **kwargs)
            counts[key] += time.perf_counter() - begin
            return out
        return wrapper

    def counted_krylov(*args, **kwargs):
        counts["krylov"] += 1
        return krylov(*args, **kwargs)

    def counted_start(*args, **kwargs):
        begin = time.perf_counter()
        out = start(*args, **kwargs)
        counts["start"] += time.perf_counter() - begin
        counts["start_iterations"] += out.iterations
        return out

    with mock.patch.object(simulation, "SteadyRollingCompliance", timed(build_operator, "build")), \
            mock.patch.object(simulation, "solve_steady", timed(solve, "solve")), \
            mock.patch.object(steady_solver, "_gmres", counted_krylov), \
            mock.patch.object(steady_solver, "solve_normal", counted_start):
        yield counts


def steady(n, wake, repeat):
    """Best build and solve times of ``repeat`` steady runs (a fresh Simulation each), and what the last gave."""
    best = dict(build=np.inf, solve=np.inf, start=np.inf)
    for _ in range(repeat):
        sim = fw.Simulation(grid=grid_of(n), material=MATERIAL, indenter=indenters.Sphere(radius=RADIUS),
                            schedule=schedules.Rolling(load=LOAD, velocity=(speed(wake), 0.0), steady=True))
        with instrumented() as counts:
            result = sim.run()
        best = {key: min(value, counts[key]) for key, value in best.items()}
    return dict(best, products=int(result.iterations[0]), active=counts["krylov"] // 2,
                start_iterations=counts["start_iterations"], cells=int(np.count_nonzero(result.pressure(0))),
                mu=float(result.friction_coefficient[0]))


def transient(n, cells):
    """A roll from rest (the load applied at t = 0) over ``cells`` cells at the peak speed."""
    grid = grid_of(n)
    begin = time.perf_counter()
    sim = fw.Simulation(grid=grid, material=MATERIAL, indenter=indenters.Sphere(radius=RADIUS),
                        schedule=schedules.Rolling(load=LOAD, velocity=(speed(PEAK), 0.0),
                                                   distance=cells * grid.spacing[0]))
    setup = time.perf_counter() - begin      # with the wake check: one static solve at rest
    begin = time.perf_counter()
    result = sim.run()
    elapsed = time.perf_counter() - begin
    return dict(setup=setup, time=elapsed, steps=len(result), rest_iterations=int(result.iterations[0]),
                iterations=float(result.iterations[1:].mean()), total_iterations=int(result.iterations.sum()),
                mu=float(result.friction_coefficient[-1]))


def libraries():
    """scipy, pyfftw, the BLAS and its threads (GMRES's dot products go through it)."""
    pyfftw = sys.modules.get("pyfftw")
    try:
        blas = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
        blas = f"{blas['name']} {blas['version']}"
    except (TypeError, KeyError):
        blas = "?"
    threads = next((f"{name}={os.environ[name]}" for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")
                    if name in os.environ), "all cores")
    return (f"scipy {scipy.__version__} | pyfftw {pyfftw.__version__ if pyfftw else 'absent'} | "
            f"BLAS {blas} with threads: {threads}")


def exponent(cells, values):
    return float(np.polyfit(np.log(cells), np.log(values), 1)[0])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[256, 512], help="n1 of the n1 x n1/2 grids")
    parser.add_argument("--scaling", type=int, nargs="+", default=[128, 256, 512, 1024],
                        help="n1 of the grids of the growth fit (those also in --sizes are not solved again)")
    parser.add_argument("--repeat", type=int, default=3, help="steady runs per case below 1024 cells along x1")
    parser.add_argument("--cells", type=int, default=50, help="cells (steps) of the transient roll")
    args = parser.parse_args()
    print(machine())
    print(libraries())
    print(f"Sphere R = {RADIUS} m, W = {LOAD} N on E(t) = 10 + 90 exp(-t/1 s) MPa, nu = 0.5: lambda = "
          f"{RETARDATION:g} s, relaxed Hertz radius a0 = {A0:.4g} m; grids n x n/2 over {ALONG / A0:g} a0 x "
          f"{ACROSS / A0:g} a0 (n/12 cells per a0); default tolerances. No peer: Tamaas has no 3-D rolling.")

    print(f"\nsteady state: build = operator (filtered kernel, spectrum), solve = solve_steady "
          f"(best of {args.repeat}), start = its symmetric CG start (part of solve)")
    print(f"{'grid':>10} {'V lam/a0':>8} {'build s':>8} {'solve s':>8} {'start s':>8} {'products':>8} "
          f"{'act.set':>7} {'CG start':>8} {'contact':>7} {'mu':>8}")
    rows = {}
    for n in args.sizes:
        for wake in WAKES:
            row = rows[n, wake] = steady(n, wake, args.repeat if n < 1024 else 1)
            print(f"{f'{n}x{n // 2}':>10} {wake:>8g} {row['build']:>8.3f} {row['solve']:>8.3f} {row['start']:>8.3f} "
                  f"{row['products']:>8} {row['active']:>7} {row['start_iterations']:>8} {row['cells']:>7} "
                  f"{row['mu']:>8.5f}", flush=True)

    print(f"\ntransient roll from rest over {args.cells} cells at V lam/a0 = {PEAK:g} "
          f"(setup: construction with the wake check; steps: the rest indentation and one per cell)")
    print(f"{'grid':>10} {'setup s':>8} {'run s':>8} {'steps':>6} {'steps/s':>8} {'PK it/step':>10} "
          f"{'rest it':>7} {'ms/PK it':>8} {'mu end':>8}")
    for n in args.sizes:
        row = transient(n, args.cells)
        print(f"{f'{n}x{n // 2}':>10} {row['setup']:>8.2f} {row['time']:>8.2f} {row['steps']:>6} "
              f"{row['steps'] / row['time']:>8.2f} {row['iterations']:>10.1f} {row['rest_iterations']:>7} "
              f"{1e3 * row['time'] / row['total_iterations']:>8.2f} {row['mu']:>8.5f}", flush=True)

    print(f"\nsteady growth with the grid at V lam/a0 = {PEAK:g} (1024 x 512: one run)")
    print(f"{'grid':>10} {'cells':>8} {'build s':>8} {'solve s':>8} {'products':>8} {'act.set':>7} {'mu':>8}")
    sizes = sorted(set(args.scaling))
    for n in sizes:
        if (n, PEAK) not in rows:
            rows[n, PEAK] = steady(n, PEAK, args.repeat if n < 1024 else 1)
        row = rows[n, PEAK]
        print(f"{f'{n}x{n // 2}':>10} {n * (n // 2):>8} {row['build']:>8.3f} {row['solve']:>8.3f} "
              f"{row['products']:>8} {row['active']:>7} {row['mu']:>8.5f}", flush=True)
    if len(sizes) > 1:
        cells = [n * (n // 2) for n in sizes]
        fits = {key: exponent(cells, [rows[n, PEAK][key] for n in sizes]) for key in ("build", "solve", "products")}
        print(f"fitted exponents (time ~ cells^k): build {fits['build']:.2f}, solve {fits['solve']:.2f}, "
              f"products {fits['products']:.2f}")


if __name__ == "__main__":
    main()
