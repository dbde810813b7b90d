"""The default scenario: a steel ball creeping into PMMA under a constant load (Lee & Radok).

Writes to the output folder: ``summary.csv`` (one row per step),
``summary.txt`` (the comparison with Hertz), ``fields.npz`` (pressure,
displacement and gap per step; stress and von Mises of the last step with the
grid coordinates).
"""
import csv
import os
import time

import numpy as np

from . import Grid, Simulation, indenters, loads, materials, reference, schedules


LOAD = 20.0  # N


def build(n=129):
    """The demo simulation on an ``n x n`` grid: 20 N held for 1000 s on seed 001's PMMA."""
    sphere = indenters.Sphere(radius=5e-3)
    times = np.concatenate([[0.0], np.geomspace(0.1, 1000.0, 16)])
    grid = Grid(shape=(n, n), size=(1.2e-3, 1.2e-3), depth=0.6e-3, layers=24)
    return Simulation(grid=grid, material=materials.PMMA, indenter=sphere,
                      schedule=schedules.Static(load=loads.Step(LOAD), times=times))


def write_summary(result, folder):
    """Write ``summary.csv`` and return its path."""
    table = result.summary()
    path = os.path.join(folder, "summary.csv")
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(table)
        writer.writerows(zip(*table.values()))
    return path


def main(folder="out", n=129):
    """Run the demo, print the summary and list what was written."""
    os.makedirs(folder, exist_ok=True)
    sim = build(n)
    start = time.perf_counter()
    result = sim.run(progress=True)
    elapsed = time.perf_counter() - start
    written = [write_summary(result, folder)]
    material = sim.material
    exact_a, exact_delta = reference.lee_radok_step_load(result.times, sim.indenter.radius, LOAD, material.creep,
                                                         material.poisson)
    lines = [f"Ball R = {sim.indenter.radius * 1e3:g} mm under {LOAD:g} N on PMMA (seed 001, nu = "
             f"{material.poisson:g}); grid {sim.grid.shape} cells over {sim.grid.size} m; {elapsed:.2f} s",
             f"{'t s':>8} {'a um':>8} {'a L&R':>8} {'delta um':>9} {'d L&R':>8} {'p max MPa':>10} {'iter':>5}"]
    for k, t in enumerate(result.times):
        lines.append(f"{t:8.3g} {result.contact_radius[k] * 1e6:8.2f} {exact_a[k] * 1e6:8.2f} "
                     f"{result.approach[k] * 1e6:9.4f} {exact_delta[k] * 1e6:8.4f} "
                     f"{result.max_pressure[k] / 1e6:10.2f} {result.iterations[k]:5d}")
    von_mises = result.von_mises(-1)
    i, j, k = np.unravel_index(np.argmax(von_mises), von_mises.shape)
    lines.append(f"max von Mises at the last step: {von_mises.max() / 1e6:.1f} MPa at depth "
                 f"{result.grid.x3[k] * 1e6:.1f} um (layer centre)")
    text = "\n".join(lines)
    print(text)
    path = os.path.join(folder, "summary.txt")
    with open(path, "w") as f:
        f.write(text + "\n")
    written.append(path)
    path = os.path.join(folder, "fields.npz")
    np.savez_compressed(path, times=result.times, x1=result.grid.x1, x2=result.grid.x2, x3=result.grid.x3,
                        pressure=np.array([result.pressure(s) for s in range(len(result))]),
                        displacement=np.array([result.displacement(s) for s in range(len(result))]),
                        gap=np.array([result.gap(s) for s in range(len(result))]),
                        stress_last=result.stress(-1), von_mises_last=von_mises)
    written.append(path)
    print("wrote:\n  " + "\n  ".join(written))
    return result
