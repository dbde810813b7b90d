"""Sphere creep under a step load on N x N: this project against Tamaas' MaxwellViscoelastic.

Same material in both (E(t) = 1 + 1.5 exp(-t/1 s) + 1 exp(-t/30 s) GPa, nu = 0.3),
same grid (DC-FFT in both), same output times; errors against Lee & Radok
(a^3 = 3 R W C*(t)/4, delta = a^2/R) at every step. Then this project alone
with 100 and 400 steps over the same window (cost should grow at most
linearly: O(n_steps) with the Prony recursions).

    .venv/bin/python bench/visco_indentation.py [--n 256] [--steps 50] [--tolerance 1e-8]
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import framework as fw  # noqa: E402
from framework import indenters, loads, materials, schedules  # noqa: E402
from elastic_hertz import machine  # noqa: E402

E_INF, TERMS, POISSON = 1e9, [(1.5e9, 1.0), (1e9, 30.0)], 0.3
RADIUS, SIDE = 10e-3, 2e-3
MATERIAL = materials.Viscoelastic.from_prony(e_inf=E_INF, terms=TERMS, poisson=POISSON)
FINAL_RADIUS = 0.25 * SIDE
LOAD = 4 * FINAL_RADIUS**3 / (3 * RADIUS * MATERIAL.contact_compliance().relaxed)


def output_times(steps):
    return np.concatenate([[0.0], np.geomspace(0.01, 300.0, steps - 1)])


def lee_radok(times):
    a = (0.75 * RADIUS * LOAD * MATERIAL.contact_compliance()(times)) ** (1 / 3)
    return a, a**2 / RADIUS


def ours(n, steps, tolerance):
    grid = fw.Grid(shape=(n, n), size=(SIDE, SIDE))
    sim = fw.Simulation(grid=grid, material=MATERIAL, indenter=indenters.Sphere(radius=RADIUS),
                        schedule=schedules.Static(load=loads.Step(LOAD), times=output_times(steps)),
                        options={"tolerance": tolerance})
    start = time.perf_counter()
    result = sim.run()
    return dict(time=time.perf_counter() - start, iterations=int(result.iterations.sum()),
                contact_radius=result.contact_radius, approach=result.approach)


def theirs(n, steps, tolerance):
    import _tamaas
    out = _tamaas.maxwell_creep(n, SIDE, RADIUS, LOAD, E_INF, TERMS, POISSON, output_times(steps), tolerance)
    iterations = out.get("iterations")
    out["iterations"] = None if iterations is None else int(np.sum(iterations))
    return out


def errors(row, times):
    a, delta = lee_radok(times)
    return np.abs(row["contact_radius"] / a - 1).max(), np.abs(row["approach"] / delta - 1).max()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=int, default=256)
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--tolerance", type=float, default=1e-8)
    args = parser.parse_args()
    print(machine())
    print(f"Step load W = {LOAD:.4g} N on a sphere R = {RADIUS} m, grid {args.n}^2 over {SIDE} m, "
          f"final contact radius {FINAL_RADIUS:.3g} m, tolerance {args.tolerance:g}")
    times = output_times(args.steps)
    start = time.perf_counter()
    ours(args.n, 2, args.tolerance)  # kernel spectra and FFT plans, as Tamaas' time leaves its setup out
    print(f"setup of this project (a 2-step run): {time.perf_counter() - start:.2f} s")
    rows = {"this": ours(args.n, args.steps, args.tolerance)}
    try:
        rows["tamaas"] = theirs(args.n, args.steps, args.tolerance)
    except ImportError:
        print("  (tamaas not installed: pip install tamaas)")
    print(f"{'code':>8} {'steps':>6} {'time s':>8} {'iterations':>11} {'max a err':>10} {'max d err':>10} {'ratio':>6}")
    for name, row in rows.items():
        a_err, d_err = errors(row, times)
        ratio = row["time"] / rows["tamaas"]["time"] if "tamaas" in rows else float("nan")
        print(f"{name:>8} {args.steps:>6} {row['time']:>8.2f} {str(row['iterations']):>11} {a_err:>10.2e} "
              f"{d_err:>10.2e} {ratio:>6.2f}")
    print("this project alone, same window:")
    cost = {}
    for steps in (100, 400):
        row = ours(args.n, steps, args.tolerance)
        cost[steps] = row["time"]
        a_err, d_err = errors(row, output_times(steps))
        print(f"{'this':>8} {steps:>6} {row['time']:>8.2f} {row['iterations']:>11} {a_err:>10.2e} {d_err:>10.2e}")
    print(f"400 steps / 100 steps: {cost[400] / cost[100]:.2f} x the time")


if __name__ == "__main__":
    main()
