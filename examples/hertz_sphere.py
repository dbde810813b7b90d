"""Hertz contact of a rigid sphere on an elastic half-space: simulation against theory.

Prints a table of contact radius, peak pressure and approach for several loads
and writes ``hertz_sphere.csv`` and (with matplotlib) ``hertz_sphere.png``,
the pressure along x1 with the Hertz profile.

    python examples/hertz_sphere.py [--cells 129] [--out out/examples]
"""
import argparse
import csv
import os

import numpy as np

import framework as fw
from framework import indenters, materials, reference, schedules


def main(cells=129, out="out/examples"):
    os.makedirs(out, exist_ok=True)
    steel = materials.Elastic(young=210e9, poisson=0.3)
    radius, loads = 10e-3, [25.0, 50.0, 100.0]
    grid = fw.Grid(shape=(cells, cells), size=(1.2e-3, 1.2e-3))
    result = fw.Simulation(grid=grid, material=steel, indenter=indenters.Sphere(radius=radius),
                           schedule=schedules.Static(load=loads)).run()
    rows = []
    for k, load in enumerate(loads):
        exact = reference.HertzSphere(radius=radius, load=load, contact_modulus=steel.contact_modulus)
        rows.append({"load_N": load,
                     "contact_radius_m": result.contact_radius[k], "hertz_contact_radius_m": exact.contact_radius,
                     "max_pressure_Pa": result.max_pressure[k], "hertz_max_pressure_Pa": exact.max_pressure,
                     "approach_m": result.approach[k], "hertz_approach_m": exact.approach,
                     "iterations": int(result.iterations[k])})
    path = os.path.join(out, "hertz_sphere.csv")
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"{'W [N]':>7} {'a err':>9} {'p0 err':>9} {'delta err':>9}")
    for row in rows:
        print(f"{row['load_N']:7.1f} {row['contact_radius_m'] / row['hertz_contact_radius_m'] - 1:9.2e} "
              f"{row['max_pressure_Pa'] / row['hertz_max_pressure_Pa'] - 1:9.2e} "
              f"{row['approach_m'] / row['hertz_approach_m'] - 1:9.2e}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed (pip install 'viscocontact[viz]'): no picture")
        return rows
    fig, ax = plt.subplots(figsize=(6, 4))
    middle = cells // 2
    x = np.linspace(grid.x1[0], grid.x1[-1], 600)
    for k, load in enumerate(loads):
        exact = reference.HertzSphere(radius=radius, load=load, contact_modulus=steel.contact_modulus)
        line, = ax.plot(x * 1e6, exact.pressure(np.abs(x)) / 1e6, lw=1)
        ax.plot(grid.x1 * 1e6, result.pressure(k)[:, middle] / 1e6, "o", ms=2.5, color=line.get_color(),
                label=f"$W$ = {load:g} N")
    ax.set(xlabel="$x_1$ [\u00b5m]", ylabel="pressure $p$ [MPa]",
           title="Sphere on steel: simulation (dots), Hertz (lines)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "hertz_sphere.png"), dpi=120)
    print("wrote", path, "and", os.path.join(out, "hertz_sphere.png"))
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=129)
    parser.add_argument("--out", default="out/examples")
    main(**vars(parser.parse_args()))
