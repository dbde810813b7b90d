"""The default scenario: a steel sphere pressed on an elastic half-space (Hertz).

Writes to the output folder: ``summary.csv`` (one row per step),
``summary.txt`` (the comparison with Hertz), ``fields.npz`` (pressure,
displacement and gap per step; stress and von Mises of the last step with the
grid coordinates).
"""
import csv
import os
import time

import numpy as np

from . import Grid, Simulation, indenters, materials, reference, schedules


def build(n=129):
    """The demo simulation on an ``n x n`` grid (a ramp of five loads)."""
    material = materials.Elastic(young=210e9, poisson=0.3)
    sphere = indenters.Sphere(radius=10e-3)
    loads = np.linspace(20.0, 100.0, 5)  # N
    grid = Grid(shape=(n, n), size=(1.2e-3, 1.2e-3), depth=0.6e-3, layers=24)
    return Simulation(grid=grid, material=material, indenter=sphere,
                      schedule=schedules.Static(load=loads, times=np.arange(loads.size, dtype=float)))


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
    contact_modulus = sim.material.contact_modulus
    lines = [f"Sphere R = {sim.indenter.radius * 1e3:g} mm on E = {sim.material.young / 1e9:g} GPa, "
             f"nu = {sim.material.poisson:g}; grid {sim.grid.shape} cells over {sim.grid.size} m, "
             f"{elapsed:.2f} s",
             f"{'load N':>8} {'a um':>8} {'a Hertz':>8} {'p0 MPa':>9} {'p0 Hertz':>9} {'delta um':>9} "
             f"{'d Hertz':>8} {'iter':>5}"]
    for k, load in enumerate(result.load):
        exact = reference.HertzSphere(radius=sim.indenter.radius, load=load, contact_modulus=contact_modulus)
        lines.append(f"{load:8.1f} {result.contact_radius[k] * 1e6:8.2f} {exact.contact_radius * 1e6:8.2f} "
                     f"{result.max_pressure[k] / 1e6:9.1f} {exact.max_pressure / 1e6:9.1f} "
                     f"{result.approach[k] * 1e6:9.4f} {exact.approach * 1e6:8.4f} {result.iterations[k]:5d}")
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
