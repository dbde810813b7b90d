"""Seed 001, section 5: the rounded flat punch (b = 0.5a) loaded off its axis on PMMA.

Dimensionless eccentricity e = offset / flat_radius = 0.1, 0.3, 0.5 and 1; the
load is Ciavarella's (instantaneous modulus) for the contact radius a = 1 mm of
the centred punch at t = 0, held for 1000 s. The punch tilts; creep lets the
tilt grow and the peak pressure fall.

Writes ``eccentric_punch_pmma.csv`` (time, tilt, approach, maximum pressure,
load centre per e) and, with matplotlib, ``eccentric_pressure.png`` (pressure
along x1 at several times, with the centred t = 0 profile), ``eccentric_tilt.png``
and ``eccentric_max_pressure.png`` (over the mean pressure W / (pi a^2)).

    python examples/eccentric_punch_pmma.py [--cells 141] [--steps 20] [--out out/examples]
"""
import argparse
import csv
import os

import numpy as np

import framework as fw
from framework import indenters, materials, reference, schedules

ECCENTRICITIES = (0.1, 0.3, 0.5, 1.0)
A = 1e-3  # contact radius of the centred punch at t = 0 [m]
FLAT, EDGE = 0.5 * A, 0.5 * A
PROFILE_TIMES = (0.0, 10.0, 100.0, 1000.0)


def load():
    """Ciavarella's load for the contact radius A with the instantaneous modulus [N]."""
    return reference.RoundedFlatPunch(flat_radius=FLAT, edge_radius=EDGE,
                                      contact_modulus=materials.PMMA.contact_modulus).load(A)


def run_case(eccentricity, cells, steps):
    """One eccentricity (None: the centred punch)."""
    times = np.unique(np.concatenate([[0.0], np.geomspace(0.1, 1000.0, steps), PROFILE_TIMES]))
    grid = fw.Grid(shape=(cells, cells), size=(3.5 * A, 3.5 * A))
    offset = (0.0 if eccentricity is None else eccentricity * FLAT, 0.0)
    schedule = schedules.Eccentric(load=load(), offset=offset, times=times) if eccentricity is not None \
        else schedules.Static(load=load(), times=times[:1])
    return fw.Simulation(grid=grid, material=materials.PMMA,
                         indenter=indenters.RoundedFlatPunch(flat_radius=FLAT, edge_radius=EDGE),
                         schedule=schedule).run()


def main(cells=141, steps=20, out="out/examples"):
    os.makedirs(out, exist_ok=True)
    centred = run_case(None, cells, steps)
    results, rows = {}, []
    mean_pressure = load() / (np.pi * A**2)
    for e in ECCENTRICITIES:
        result = results[e] = run_case(e, cells, steps)
        for k, t in enumerate(result.times):
            rows.append({"eccentricity": e, "time_s": t, "tilt_rad": result.tilt[k, 0],
                         "approach_m": result.approach[k], "max_pressure_Pa": result.max_pressure[k],
                         "max_over_mean": result.max_pressure[k] / mean_pressure,
                         "center_x1_m": result.center[k, 0], "contact_area_m2": result.contact_area[k]})
        print(f"e = {e}: tilt {result.tilt[0, 0] * 1e3:.3f} -> {result.tilt[-1, 0] * 1e3:.3f} mrad, "
              f"p_max/p_mean {result.max_pressure[0] / mean_pressure:.3f} -> "
              f"{result.max_pressure[-1] / mean_pressure:.3f}")
    path = os.path.join(out, "eccentric_punch_pmma.csv")
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("wrote", path)
    plot(centred, results, mean_pressure, out)
    return rows


def plot(centred, results, mean_pressure, out):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed (pip install 'viscocontact[viz]'): no pictures")
        return
    grid = centred.grid
    row = int(np.argmin(np.abs(grid.x2)))
    fig, axes = plt.subplots(1, len(ECCENTRICITIES), figsize=(16, 3.8), sharey=True, layout="constrained")
    for ax, e in zip(axes, ECCENTRICITIES):
        result = results[e]
        ax.plot(grid.x1 / A, centred.pressure(0)[:, row] / mean_pressure, "k:", label="centred, $t$ = 0")
        for t in PROFILE_TIMES:
            k = int(np.argmin(np.abs(result.times - t)))
            ax.plot(grid.x1 / A, result.pressure(k)[:, row] / mean_pressure, label=f"$t$ = {result.times[k]:g} s")
        ax.set(title=f"$e$ = {e}", xlabel="$x_1 / a$", xlim=(-1.6, 1.6))
    axes[0].set_ylabel(r"$p \,/\, p_\mathrm{mean}$")
    # beside the panels, not over a curve (the profiles fill every panel's corners)
    fig.legend(*axes[-1].get_legend_handles_labels(), loc="outside right center", fontsize=8)
    fig.suptitle("Eccentric rounded punch on PMMA: pressure along $x_1$")
    fig.savefig(os.path.join(out, "eccentric_pressure.png"), dpi=110)
    for name, values, ylabel, label in (
            ("eccentric_tilt.png", lambda r: r.tilt[:, 0] / r.tilt[0, 0], r"tilt $\alpha(t) \,/\, \alpha(0)$",
             lambda r: f", $\\alpha(0)$ = {r.tilt[0, 0] * 1e3:.1f} mrad"),
            ("eccentric_max_pressure.png", lambda r: r.max_pressure / mean_pressure,
             r"$p_\mathrm{max} \,/\, p_\mathrm{mean}$", lambda r: "")):
        fig, ax = plt.subplots(figsize=(6, 4))
        for e in ECCENTRICITIES:
            result = results[e]
            ax.semilogx(result.times[1:], values(result)[1:], label=f"$e$ = {e}{label(result)}")
        ax.set(xlabel="time $t$ [s]", ylabel=ylabel, title=f"Eccentric rounded punch on PMMA: {ylabel}")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(out, name), dpi=110)
    print("wrote the pictures eccentric_pressure.png, eccentric_tilt.png, eccentric_max_pressure.png")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=141)
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--out", default="out/examples")
    main(**vars(parser.parse_args()))
