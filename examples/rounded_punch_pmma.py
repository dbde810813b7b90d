"""Seed 001's reference case: a rounded flat punch creeping into PMMA (Spinu & Cerlinca).

Flat radius b = 0.2a, 0.5a and 0.8a with b + Rc = a, a the contact radius at
t = 0; the load comes from Ciavarella's relation (1999) with the instantaneous
modulus so that the three punches share the initial contact radius. The PMMA
relaxation modulus is seed 001's two-term Prony series (`materials.PMMA`).

Writes to ``--out``: ``rounded_punch_pmma.csv`` (time, contact area, maximum
and central pressure per case) and, with matplotlib, ``pmma_pressure.png``
(profiles at several times over the mean pressure), ``pmma_area.png`` and
``pmma_pressures.png`` (normalised by their values at t = 0).

    python examples/rounded_punch_pmma.py [--cells 121] [--steps 30] [--out out/examples]
"""
import argparse
import csv
import os

import numpy as np

import framework as fw
from framework import indenters, materials, reference, schedules

RATIOS = (0.2, 0.5, 0.8)
CONTACT_RADIUS = 1e-3  # m, at t = 0
PROFILE_TIMES = (0.0, 10.0, 100.0, 1000.0)  # s


def run_case(ratio, cells, steps):
    """One punch: returns the result and its Ciavarella load."""
    a = CONTACT_RADIUS
    b, rc = ratio * a, (1 - ratio) * a
    pmma = materials.PMMA
    glassy = reference.RoundedFlatPunch(flat_radius=b, edge_radius=rc, contact_modulus=pmma.contact_modulus)
    load = glassy.load(a)
    times = np.unique(np.concatenate([[0.0], np.geomspace(0.1, 1000.0, steps), PROFILE_TIMES]))
    grid = fw.Grid(shape=(cells, cells), size=(3 * a, 3 * a))
    sim = fw.Simulation(grid=grid, material=pmma, indenter=indenters.RoundedFlatPunch(flat_radius=b, edge_radius=rc),
                        schedule=schedules.Static(load=load, times=times))
    return sim.run(), load


def main(cells=121, steps=30, out="out/examples"):
    os.makedirs(out, exist_ok=True)
    rows, results = [], {}
    for ratio in RATIOS:
        result, load = run_case(ratio, cells, steps)
        results[ratio] = (result, load)
        centre = np.unravel_index(np.argmin(np.hypot(*result.grid.coordinates())), result.grid.shape)
        for k, t in enumerate(result.times):
            rows.append({"flat_ratio": ratio, "time_s": t, "load_N": load, "contact_area_m2": result.contact_area[k],
                         "max_pressure_Pa": result.max_pressure[k],
                         "central_pressure_Pa": result.pressure(k)[centre], "approach_m": result.approach[k]})
        first, last = rows[-len(result.times)], rows[-1]
        print(f"b = {ratio}a: W = {load:.1f} N; over 1000 s the area grows by "
              f"{last['contact_area_m2'] / first['contact_area_m2'] - 1:+.1%}, the maximum pressure changes by "
              f"{last['max_pressure_Pa'] / first['max_pressure_Pa'] - 1:+.1%}, the central one by "
              f"{last['central_pressure_Pa'] / first['central_pressure_Pa'] - 1:+.1%}")
    path = os.path.join(out, "rounded_punch_pmma.csv")
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("wrote", path)
    plot(results, out)
    return rows


def plot(results, out):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed (pip install 'viscocontact[viz]'): no pictures")
        return
    a = CONTACT_RADIUS
    fig, axes = plt.subplots(1, len(RATIOS), figsize=(12, 3.8), sharey=True)
    for ax, ratio in zip(axes, RATIOS):
        result, load = results[ratio]
        grid = result.grid
        row = np.argmin(np.abs(grid.x2))
        mean_pressure = load / (np.pi * a**2)
        for t in PROFILE_TIMES:
            k = int(np.argmin(np.abs(result.times - t)))
            ax.plot(grid.x1 / a, result.pressure(k)[:, row] / mean_pressure, label=f"$t$ = {result.times[k]:g} s")
        ax.set(title=f"flat radius {ratio}$a$", xlabel="$x_1 / a$", xlim=(-1.3, 1.3))
    axes[0].set_ylabel(r"$p \,/\, p_\mathrm{mean}$")
    axes[-1].legend()
    fig.suptitle("Rounded flat punch on PMMA: pressure along $x_1$")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "pmma_pressure.png"), dpi=110)
    for name, quantity, ylabel in (("pmma_area.png", "area", "$A(t) \\,/\\, A(0)$"),
                                   ("pmma_pressures.png", "pressure", "$p(t) \\,/\\, p(0)$")):
        fig, ax = plt.subplots(figsize=(6, 4))
        for ratio in RATIOS:
            result, _ = results[ratio]
            times = result.times[1:]
            if quantity == "area":
                ax.semilogx(times, result.contact_area[1:] / result.contact_area[0], label=f"$b$ = {ratio}$a$")
            else:
                centre = np.unravel_index(np.argmin(np.hypot(*result.grid.coordinates())), result.grid.shape)
                central = np.array([result.pressure(k)[centre] for k in range(len(result))])
                line, = ax.semilogx(times, result.max_pressure[1:] / result.max_pressure[0], label=f"max, $b$ = {ratio}$a$")
                ax.semilogx(times, central[1:] / central[0], "--", color=line.get_color(), label=f"centre, $b$ = {ratio}$a$")
        ax.set(xlabel="time $t$ [s]", ylabel=ylabel, title=f"Rounded punch on PMMA: {quantity} vs time")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, name), dpi=110)
    print("wrote", ", ".join(os.path.join(out, n) for n in ("pmma_pressure.png", "pmma_area.png", "pmma_pressures.png")))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=121)
    parser.add_argument("--steps", type=int, default=30)
    parser.add_argument("--out", default="out/examples")
    main(**vars(parser.parse_args()))
