"""A rigid sphere rolling over a viscoelastic half-space that holds an elastic inhomogeneity (seed 000).

A rigid sphere (R = 10 mm, W = 20 N) rolls at V = 0.25 mm/s along +x1 over a polymer-like standard
linear solid (E(0) = 3 GPa relaxing to E(inf) = 1 GPa with tau = 0.2 s, nu = 0.35; its creep
retardation time lambda = tau E(0)/E(inf) = 0.6 s makes a wake V lambda = 0.15 mm, near the
friction peak for a contact radius a ~ 0.2-0.3 mm). Below the track lies one glass inhomogeneity
(E = 70 GPa, nu = 0.22), its centre 0.25 mm deep and 0.6 mm ahead of the body at the start:

* ``sphere``: radius 0.1 mm;
* ``tilted``: an ellipsoid 0.15 x 0.1 x 0.1 mm, its long axis turned 30 degrees from x1 towards x3;
* ``PMMA sphere``: the same glass sphere in PMMA (:data:`framework.materials.PMMA`, seed 001: E(0) =
  2.49 GPa relaxing to 1.97 GPa with tau = 8.9 s and 118 s), rolled at V = 2 um/s so that the
  wake of its slow term, V lambda = 0.27 mm (lambda = 134 s), is again comparable to the contact
  radius (and three of them fit on the grid behind the body, which a transient run needs);

and the homogeneous runs for reference. The body first indents at rest (the glassy response), then
rolls 1.2 mm, past the inhomogeneity. With the default ``cells`` = 48 (cells across the grid,
25 um cubes: 4 a radius of the glass sphere), the runs take 7 s together (0.1-2.7 s each; 14 s with the
pictures). At ``--cells 96`` (8 a radius; 99 s, 2.1 GB) the friction's changes move by 0-4 % (the sphere's
+0.000358 and -0.000308 -> +0.000346 and -0.000295) and the peak pressure's ratios by 1 %: the default resolves
what the surface sees. The slice shows, at both, the stress concentrations of the staircase the cuboids make of
the body's surface, reaching into the body: its interior stress converges more slowly (the mean within 2 % of
Eshelby's at 8 cuboids a radius, ``tests/test_inclusions.py``); read it at 96 cells or finer.

What happens: as the body approaches a stiff inhomogeneity, it lies ahead of the contact's centre,
where the sphere's surface slopes against the motion: the extra pressure it draws there adds to
the resisting force, and the friction coefficient rises. Once the body has passed, it lies behind,
where the slope pushes the body on: the friction drops below the homogeneous value, then recovers
as the inhomogeneity leaves the wake. The peak pressure rises by tens of percent while the body is
above it.

Writes to ``--out``: ``rolling_inhomogeneity.csv`` (per step and case: position, friction
coefficient, torque, peak pressure, contact area, couplings) and, with matplotlib,
``rolling_inhomogeneity.png`` (friction, torque and peak pressure against the position relative to
the inhomogeneity), ``rolling_inhomogeneity_slice.png`` (von Mises in the x1-x3 plane as the body
passes over the sphere, with its outline) and ``rolling_inhomogeneity.gif`` (the animation of that
slice along the run). A Dask study over the modulus ratio, the depth and the tilt is
``examples/sweep_rolling_inclusion.toml``; the sphere's run alone is
``examples/rolling_over_inhomogeneity.toml``.

    python examples/rolling_over_inhomogeneity.py [--cells 48] [--out out/examples] [--sweep N]

``--sweep N`` also runs the first ``N`` points of ``examples/sweep_rolling_inclusion.toml`` (all 10,
one parameter at a time around a base case: 7 s on two cores; Dask spreads them over a
cluster with ``python -m framework sweep``) and draws ``rolling_inhomogeneity_sweep.png``: the friction
coefficient and peak pressure with the body above the inhomogeneity against each swept parameter, one
line per value of the others (a single point where only one parameter differs from the base case).
"""
import argparse
import os
import time

import numpy as np

import framework as fw
from framework import inclusions, indenters, materials, schedules
from framework.sweep import write_table

MATRIX = materials.StandardLinearSolid(e_inf=1e9, e_1=2e9, tau=0.2, poisson=0.35)
GLASS = materials.Elastic(young=70e9, poisson=0.22)
RADIUS, LOAD, SPEED = 10e-3, 20.0, 0.25e-3            # m, N, m/s
LENGTH, WIDTH, DEPTH = 2.4e-3, 1.2e-3, 0.5e-3          # grid [m]: 3 wakes and the contact behind the axis
#: [m] PMMA's grid: behind the axis its contact at rest (0.41 mm) and 3 of its wakes (0.80 mm) at every resolution
#: (2.4 mm left it 0.009 mm short at 96 cells, where the contact is resolved a little wider)
PMMA_LENGTH = 2.5e-3
AHEAD, CENTRE_DEPTH, DISTANCE = 0.6e-3, 0.25e-3, 1.2e-3
TILT = inclusions.axis_angle_orientation((0.0, 1.0, 0.0), np.radians(30.0))
SPHERE = dict(semi_axes=(0.1e-3, 0.1e-3, 0.1e-3), orientation=None)
PMMA_SPEED = 2e-6                                      # m/s: V lambda = 0.27 mm for PMMA's lambda = 134 s
#: case: (matrix, rolling speed [m/s], inhomogeneity shape or None, the homogeneous case it is compared with)
CASES = {
    "homogeneous": (MATRIX, SPEED, None, "homogeneous"),
    "sphere": (MATRIX, SPEED, SPHERE, "homogeneous"),
    "tilted": (MATRIX, SPEED, dict(semi_axes=(0.15e-3, 0.1e-3, 0.1e-3), orientation=TILT), "homogeneous"),
    "PMMA homogeneous": (materials.PMMA, PMMA_SPEED, None, "PMMA homogeneous"),
    "PMMA sphere": (materials.PMMA, PMMA_SPEED, SPHERE, "PMMA homogeneous"),
}


def simulation(case, cells):
    """The rolling run of one case on a grid of ``cells`` cubes across (x2), ``LENGTH`` or ``PMMA_LENGTH`` long."""
    matrix, speed, shape, _ = CASES[case]
    cell = WIDTH / cells
    n1 = int(round((PMMA_LENGTH if matrix is materials.PMMA else LENGTH) / cell))
    grid = fw.Grid(shape=(n1, cells), size=(n1 * cell, WIDTH), depth=DEPTH, layers=int(round(DEPTH / cell)))
    bodies = None if shape is None else [inclusions.Ellipsoid(center=(AHEAD, 0.0, CENTRE_DEPTH), material=GLASS,
                                                              **shape)]
    return fw.Simulation(grid=grid, material=matrix, indenter=indenters.Sphere(radius=RADIUS),
                         schedule=schedules.Rolling(load=LOAD, velocity=(speed, 0.0), distance=DISTANCE),
                         inclusions=bodies)


def main(cells=48, out="out/examples", sweep=0):
    os.makedirs(out, exist_ok=True)
    if sweep:
        parameter_study(out, sweep)
    cases = list(CASES) if cells >= 45 else ["homogeneous", "sphere"]   # a quick look
    results, rows = {}, []
    runs = {case: simulation(case, cells) for case in cases}     # every case checked before the first runs
    for case in cases:
        begin = time.perf_counter()
        results[case] = result = runs.pop(case).run()
        print(f"{case:>12}: {len(result)} steps in {time.perf_counter() - begin:.1f} s, friction at the end "
              f"{result.friction_coefficient[-1]:.4g}, peak pressure up to {result.max_pressure.max() / 1e6:.1f} MPa")
        for k, record in enumerate(result.records):
            rows.append(dict(case=case, step=k, position=result.position[k, 0],
                             relative_position=result.position[k, 0] - AHEAD,
                             friction_coefficient=result.friction_coefficient[k], torque=result.torque[k],
                             max_pressure=result.max_pressure[k], contact_area=result.contact_area[k],
                             couplings=record.couplings))
    for case in results:
        base = results[CASES[case][3]]
        if CASES[case][2] is not None:
            change = results[case].friction_coefficient - base.friction_coefficient
            k_max, k_min = int(np.argmax(change)), int(np.argmin(change))
            print(f"{case:>12}: friction change {change[k_max]:+.3g} at {(base.position[k_max, 0] - AHEAD) * 1e3:+.2f} mm "
                  f"(body before it), {change[k_min]:+.3g} at {(base.position[k_min, 0] - AHEAD) * 1e3:+.2f} mm (after); "
                  f"peak pressure x{(results[case].max_pressure / base.max_pressure).max():.3f}")
    path = os.path.join(out, "rolling_inhomogeneity.csv")
    write_table(rows, path)
    print("wrote", path)
    pictures(results, out)
    return rows


def parameter_study(out, count):
    """Run the first ``count`` points of the sweep file and plot the final friction and peak pressure per parameter."""
    here = os.path.dirname(os.path.abspath(__file__))
    builder, parameters, _ = fw.read_sweep(os.path.join(here, "sweep_rolling_inclusion.toml"))
    from framework.sweep import expand   # the module (fw.sweep is its function)
    points = expand(parameters)[:count]
    names = list(dict.fromkeys(name for point in points for name in point))
    rows = fw.sweep(builder, points, folder=os.path.join(out, "sweep_rolling_inclusion"))
    try:
        from matplotlib.figure import Figure
    except ImportError:
        return rows
    labels = {"inclusions.0.material.young": ("Young's modulus [GPa]", lambda v: v / 1e9),
              "inclusions.0.center": ("centre depth [mm]", lambda v: v[2] * 1e3),
              "inclusions.0.euler": ("tilt in x1-x3 [deg]", lambda v: v[0])}
    figure = Figure(figsize=(13, 7), layout="constrained")
    axes = figure.subplots(2, len(names), squeeze=False)
    for column, name in enumerate(names):
        label, value = labels[name]
        others = [other for other in names if other != name]
        groups = {}
        for row in rows:
            key = tuple(str(row[other]) for other in others)
            groups.setdefault(key, []).append(row)
        for members in groups.values():
            if len(members) < 2:        # varies another parameter: it has its own panel
                continue
            members.sort(key=lambda row: value(row[name]))
            x = [value(row[name]) for row in members]
            axes[0, column].plot(x, [row["final.friction_coefficient"] for row in members], "o-", linewidth=0.8)
            axes[1, column].plot(x, [row["final.max_pressure"] / 1e6 for row in members], "o-", linewidth=0.8)
        axes[1, column].set_xlabel(label)
        if name.endswith("young"):      # ratios 0.2 to 23 of the glassy matrix: a log axis, the matrix marked
            for ax in axes[:, column]:
                ax.set_xscale("log")
                ax.axvline(3.0, color="grey", linewidth=0.8, linestyle=":")
    axes[0, 0].set_ylabel("friction coefficient, body above it")
    axes[1, 0].set_ylabel("peak pressure [MPa], body above it")
    figure.suptitle(f"{len(rows)} points of examples/sweep_rolling_inclusion.toml: one line per value of the "
                    f"other parameters (dotted: the matrix's glassy modulus)", fontsize=10)
    figure.savefig(os.path.join(out, "rolling_inhomogeneity_sweep.png"), dpi=110)
    print("wrote", os.path.join(out, "rolling_inhomogeneity_sweep.png"))
    return rows


def pictures(results, out):
    try:
        from matplotlib.figure import Figure
        import viz
    except ImportError:
        print("matplotlib or pyvista missing (pip install 'viscocontact[viz]'): no pictures")
        return
    matrices = list(dict.fromkeys(CASES[case][3] for case in results))      # one row per matrix
    figure = Figure(figsize=(13, 4 * len(matrices)), layout="constrained")
    axes = figure.subplots(len(matrices), 3, squeeze=False)
    for case, result in results.items():
        row = axes[matrices.index(CASES[case][3])]
        x = (result.position[:, 0] - AHEAD) * 1e3
        for ax, values in zip(row, (result.friction_coefficient, result.torque, result.max_pressure / 1e6)):
            ax.plot(x, values, "k--" if CASES[case][2] is None else "-", label=case)
    for row, base in zip(axes, matrices):
        for ax, label in zip(row, ("friction coefficient $\\mu$", "rolling torque [N m]",
                                   "peak pressure $p_\\mathrm{max}$ [MPa]")):
            ax.set(xlabel="body position relative to the inhomogeneity [mm]", ylabel=label)
            ax.axvline(0.0, color="grey", linewidth=0.8)
            ax.grid(True, alpha=0.3)
        row[0].legend(title=f"{CASES[base][1] * 1e3:g} mm/s")
    figure.suptitle(f"Sphere R = {RADIUS * 1e3:g} mm, W = {LOAD:g} N rolling over a standard linear solid (top) and "
                    f"PMMA (bottom) with a glass inhomogeneity {CENTRE_DEPTH * 1e3:g} mm deep", fontsize=10)
    names = ["rolling_inhomogeneity.png"]
    figure.savefig(os.path.join(out, names[0]), dpi=110)
    sphere = results["sphere"]
    above = int(np.argmin(np.abs(sphere.position[:, 0] - AHEAD)))
    names.append("rolling_inhomogeneity_slice.png")
    viz.render(sphere, os.path.join(out, names[-1]), field="von_mises", step=above, kind="slice")
    names.append("rolling_inhomogeneity.gif")
    viz.animate(sphere, os.path.join(out, names[-1]), field="von_mises", kind="slice",
                steps=range(0, len(sphere), 3), fps=6)
    print("wrote the pictures", ", ".join(os.path.join(out, name) for name in names))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=48,
                        help="cells across the grid (x2); twice as many along x1 (PMMA: 2.5 / 1.2 times)")
    parser.add_argument("--out", default="out/examples")
    parser.add_argument("--sweep", type=int, default=0, help="also run this many points of the parameter study")
    main(**vars(parser.parse_args()))
