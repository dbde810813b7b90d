"""A ball pressed on steel over a hard, a soft and a tilted inhomogeneity at several depths.

A rigid ball (R = 10 mm; a steel ball on steel with the framework's rigid
indenters: the half-space takes all the compliance) is pressed with W = 50 N
on a steel half-space (E = 210 GPa, nu = 0.3): homogeneous Hertz radius
a = 0.118 mm, peak pressure p0 = 1.73 GPa, a / R = 1.2 % (small strains).
Below the axis lies one elastic inhomogeneity (THEORY.md sec. 8), its centre
at the depths 0.75, 1, 1.5 and 2 a:

* ``stiff``: a tungsten-carbide sphere (E = 600 GPa, nu = 0.22) of radius 0.4 a;
* ``soft``: an aluminium sphere (E = 70 GPa, nu = 0.33) of radius 0.4 a (its
  shear modulus is 0.33 times the steel's; the solver's floor,
  :data:`framework.inclusions.field.MIN_STIFFNESS_RATIO`, is 0.05);
* ``tilted``: an alumina ellipsoid (E = 380 GPa, nu = 0.22; a typical
  non-metallic inclusion of bearing steels), semi-axes 0.7 a x 0.4 a x 0.4 a,
  its long axis turned by 30 degrees from x1 towards x3 (about x2).

A stiff inhomogeneity raises the pressure above it, a soft one lowers it; the
effect fades with depth roughly like the volume over the depth cubed. Cells
are cubes of a / 8 (the inhomogeneities' semi-axes span 3.2 to 5.6 cells);
the grid is ``cells`` cells square (49 by default: 6.1 a) and 3 a deep.

Writes to ``--out``: ``inhomogeneity_pressure.csv`` (pressure along x1 through
the axis, every case and depth, and the homogeneous run),
``inhomogeneity_peaks.csv`` (peak pressure, contact radius, approach and
coupling iterations against the depth, relative to the homogeneous run on the
same grid) and, with matplotlib, ``inhomogeneity_pressure.png``,
``inhomogeneity_peaks.png`` and ``inhomogeneity_von_mises.png`` (von Mises
stress in the x1-x3 plane through the inhomogeneity, centre depth 1 a, with
the eigenstrains' fields, and the ellipsoid's outline). Prints a table.

    python examples/inhomogeneity_under_contact.py [--cells 49] [--out out/examples]
"""
import argparse
import csv
import os
import time

import numpy as np

import framework as fw
from framework import inclusions, indenters, materials, reference, schedules
from framework.result import von_mises

STEEL = materials.Elastic(young=210e9, poisson=0.3)
RADIUS, LOAD = 10e-3, 50.0                                   # ball [m], load [N]
HERTZ = reference.HertzSphere(radius=RADIUS, load=LOAD, contact_modulus=STEEL.contact_modulus)
A = HERTZ.contact_radius                                     # 0.118 mm
CELL = A / 8                                                 # cube side [m]
DEPTHS = (0.75, 1.0, 1.5, 2.0)                               # centre depth / a
#: Centre depth / a of the von Mises slices.
SLICE_DEPTH = 1.0
TILT = np.radians(30.0)

#: name: (label, material, semi-axes / a, orientation)
CASES = {
    "stiff": ("tungsten carbide sphere, E = 600 GPa", materials.Elastic(young=600e9, poisson=0.22),
              (0.4, 0.4, 0.4), None),
    "soft": ("aluminium sphere, E = 70 GPa", materials.Elastic(young=70e9, poisson=0.33), (0.4, 0.4, 0.4), None),
    # turning about -x2 brings the long axis x1 down towards +x3 (the depth)
    "tilted": ("alumina ellipsoid 0.7a x 0.4a x 0.4a, 30 deg", materials.Elastic(young=380e9, poisson=0.22),
               (0.7, 0.4, 0.4), inclusions.axis_angle_orientation((0.0, -1.0, 0.0), TILT)),
}


def grid_of(cells):
    """``cells`` square cells of a / 8 on the surface, 3 a deep in cubes."""
    return fw.Grid(shape=(cells, cells), size=(cells * CELL, cells * CELL), depth=3 * A, layers=24)


def inhomogeneity(name, depth):
    """The case ``name``'s ellipsoid with its centre at ``depth`` contact radii below the axis."""
    _, material, semi_axes, orientation = CASES[name]
    return inclusions.Ellipsoid(center=(0.0, 0.0, depth * A), semi_axes=tuple(s * A for s in semi_axes),
                                material=material, orientation=orientation)


def press(grid, inclusion=None):
    """One static step at W; returns the result and its wall time [s]."""
    begin = time.perf_counter()
    result = fw.Simulation(grid=grid, material=STEEL, indenter=indenters.Sphere(radius=RADIUS),
                           schedule=schedules.Static(load=[LOAD]),
                           inclusions=None if inclusion is None else [inclusion]).run()
    return result, time.perf_counter() - begin


def main(cells=49, out="out/examples", depths=None):
    """Run the homogeneous half-space and every case at every depth; write the files; return the peak rows.

    Parameters
    ----------
    cells : int
        Cells per side of the surface grid (cubes of a / 8; odd puts a row of cells on the axis).
    out : str
        Output folder.
    depths : sequence of float, optional
        Centre depths / a (default :data:`DEPTHS`; 1 and 2 on grids under 45 cells: a quick look).
    """
    os.makedirs(out, exist_ok=True)
    depths = DEPTHS if depths is None else tuple(depths)
    if cells < 45 and depths == DEPTHS:
        depths = (1.0, 2.0)
    grid = grid_of(cells)
    homogeneous, _ = press(grid)
    p_ref, a_ref, d_ref = homogeneous.max_pressure[0], homogeneous.contact_radius[0], homogeneous.approach[0]
    print(f"homogeneous on {cells}x{cells} cells of a/8: peak {p_ref / 1e9:.4g} GPa (Hertz {HERTZ.max_pressure / 1e9:.4g}),"
          f" contact radius {a_ref * 1e3:.4g} mm (Hertz {A * 1e3:.4g}), approach {d_ref * 1e6:.4g} um "
          f"(Hertz {HERTZ.approach * 1e6:.4g})")
    middle = int(np.argmin(np.abs(grid.x2)))
    profiles = {("homogeneous", 0.0): homogeneous.pressure(0)[:, middle]}
    rows, slices = [], {}
    print(f"{'case':>7} {'depth/a':>7} {'p_max/p_hom':>11} {'a/a_hom':>8} {'delta/delta_hom':>15} {'couplings':>9} "
          f"{'s':>5}")
    for name in CASES:
        for depth in depths:
            inclusion = inhomogeneity(name, depth)
            result, elapsed = press(grid, inclusion)
            profiles[name, depth] = result.pressure(0)[:, middle]
            rows.append({"case": name, "centre_depth_over_a": depth, "centre_depth_m": depth * A,
                         "max_pressure_Pa": result.max_pressure[0], "homogeneous_max_pressure_Pa": p_ref,
                         "hertz_max_pressure_Pa": HERTZ.max_pressure,
                         "max_pressure_ratio": result.max_pressure[0] / p_ref,
                         "contact_radius_ratio": result.contact_radius[0] / a_ref,
                         "approach_ratio": result.approach[0] / d_ref,
                         "couplings": result.records[0].couplings, "time_s": elapsed})
            row = rows[-1]
            print(f"{name:>7} {depth:>7.2f} {row['max_pressure_ratio']:>11.5f} {row['contact_radius_ratio']:>8.4f} "
                  f"{row['approach_ratio']:>15.5f} {row['couplings']:>9} {elapsed:>5.1f}", flush=True)
            if depth == SLICE_DEPTH:
                slices[name] = (inclusion, von_mises_slice(result))
    write_csv(os.path.join(out, "inhomogeneity_peaks.csv"), rows)
    write_csv(os.path.join(out, "inhomogeneity_pressure.csv"), [
        {"case": name, "centre_depth_over_a": depth, "x1_m": x, "pressure_Pa": p}
        for (name, depth), profile in profiles.items() for x, p in zip(grid.x1, profile)])
    plot(grid, profiles, rows, slices, out)
    return rows


def von_mises_slice(result):
    """Von Mises stress [Pa] at the cuboid centres of the plane x2 = 0 within |x1| <= 2 a, x3 <= 2.5 a.

    With the eigenstrains' fields everywhere (direct sums); at cuboid centres, where the
    stress is consistent with the cuboids the solver put in the inhomogeneity (between
    centres the staircase boundary and the exact ellipsoid disagree).

    Returns
    -------
    x1, x3 : ndarray
        Centre coordinates [m].
    field : ndarray
        Shape (x3, x1) [Pa].
    """
    grid = result.grid
    x1 = grid.x1[np.abs(grid.x1) <= 2 * A]
    x3 = grid.x3[grid.x3 <= 2.5 * A]
    x2 = grid.x2[int(np.argmin(np.abs(grid.x2)))]
    mesh1, mesh3 = np.meshgrid(x1, x3)
    points = np.column_stack([mesh1.ravel(), np.full(mesh1.size, x2), mesh3.ravel()])
    return x1, x3, von_mises(result.stress_at(0, points)).reshape(mesh1.shape)


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("wrote", path)


def plot(grid, profiles, rows, slices, out):
    try:
        from matplotlib.figure import Figure
    except ImportError:
        print("matplotlib not installed (pip install 'viscocontact[viz]'): no pictures")
        return
    names = [plot_profiles(Figure, grid, profiles, out), plot_peaks(Figure, rows, out),
             plot_slices(Figure, slices, out)]
    print("wrote the pictures", ", ".join(os.path.join(out, name) for name in names))


def plot_profiles(Figure, grid, profiles, out):
    figure = Figure(figsize=(14, 4.4), layout="constrained")
    axes = figure.subplots(1, len(CASES), sharey=True)
    x = grid.x1 / A
    fine = np.linspace(-1.5, 1.5, 601)
    for ax, (name, (label, *_)) in zip(axes, CASES.items()):
        ax.plot(fine, HERTZ.pressure(np.abs(fine) * A) / HERTZ.max_pressure, "k:", linewidth=1, label="Hertz")
        ax.step(x, profiles["homogeneous", 0.0] / HERTZ.max_pressure, "k", where="mid", linewidth=1,
                label="homogeneous, this grid")
        for (case, depth), profile in profiles.items():
            if case == name:
                ax.step(x, profile / HERTZ.max_pressure, where="mid", label=f"centre depth {depth:g} $a$")
        ax.set(xlim=(-1.5, 1.5), xlabel="$x_1 / a$", title=label)
        ax.legend(fontsize=8, loc="lower center")
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("$p / p_0$ (Hertz)")
    figure.suptitle(f"Pressure along $x_1$ through the axis: rigid ball $R$ = {RADIUS * 1e3:g} mm, $W$ = {LOAD:g} N "
                    f"on steel, $a$ = {A * 1e3:.3g} mm, $p_0$ = {HERTZ.max_pressure / 1e9:.3g} GPa", fontsize=10)
    return _save(figure, out, "inhomogeneity_pressure.png")


def plot_peaks(Figure, rows, out):
    figure = Figure(figsize=(6.5, 4.4), layout="constrained")
    ax = figure.subplots()
    for name, (label, *_) in CASES.items():
        mine = [row for row in rows if row["case"] == name]
        ax.plot([row["centre_depth_over_a"] for row in mine], [row["max_pressure_ratio"] - 1 for row in mine],
                "o-", label=label)
    ax.axhline(0.0, color="k", linewidth=0.8)
    ax.set(xlabel="centre depth / $a$", ylabel=r"$p_\mathrm{max} \,/\, p_\mathrm{max}^\mathrm{hom} - 1$",
           title="Peak pressure against the inhomogeneity's depth")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return _save(figure, out, "inhomogeneity_peaks.png")


def plot_slices(Figure, slices, out):
    figure = Figure(figsize=(14, 4.2), layout="constrained")
    axes = figure.subplots(1, len(slices), sharey=True)
    top = max(field.max() for _, (_, _, field) in slices.values()) / HERTZ.max_pressure
    for ax, (name, (inclusion, (x1, x3, field))) in zip(np.atleast_1d(axes), slices.items()):
        image = ax.pcolormesh(x1 / A, x3 / A, field / HERTZ.max_pressure, shading="nearest", cmap="magma", vmin=0, vmax=top)
        ax.plot(*outline(inclusion), "c-", linewidth=1.2)
        ax.set(xlabel="$x_1 / a$", title=f"{CASES[name][0]}\ncentre depth {SLICE_DEPTH:g} $a$, "
               f"max {field.max() / HERTZ.max_pressure:.3f} $p_0$", aspect="equal")
        ax.title.set_fontsize(9)
    axes[0].set_ylabel("depth $x_3 / a$")
    axes[0].invert_yaxis()
    figure.colorbar(image, ax=list(np.atleast_1d(axes)), label="von Mises stress / $p_0$", shrink=0.9)
    figure.suptitle("Von Mises stress at the cuboid centres of the plane $x_2$ = 0 (with the eigenstrains' fields); "
                    "cyan: the inhomogeneity (homogeneous half-space: peak 0.62 $p_0$ at 0.48 $a$)", fontsize=10)
    return _save(figure, out, "inhomogeneity_von_mises.png")


def outline(inclusion):
    """The ellipsoid's section by the plane x2 = 0, in units of a: (x1, x3), for an axis in that plane or along x2."""
    angle = np.linspace(0, 2 * np.pi, 200)
    rotation, semi, centre = inclusion.orientation, np.asarray(inclusion.semi_axes), np.asarray(inclusion.center)
    # the semi-axes whose directions lie in the x1-x3 plane span the section through the centre
    plane = [k for k in range(3) if abs(rotation[1, k]) < 1e-12]
    u, v = (semi[k] * rotation[:, k] for k in plane[:2])
    section = centre[:, None] + np.outer(u, np.cos(angle)) + np.outer(v, np.sin(angle))
    return section[0] / A, section[2] / A


def _save(figure, out, name):
    figure.savefig(os.path.join(out, name), dpi=110)
    return name


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=49, help="cells per side of the surface grid (cubes of a / 8)")
    parser.add_argument("--depths", type=float, nargs="+", default=None, help="centre depths / a")
    parser.add_argument("--out", default="out/examples")
    main(**vars(parser.parse_args()))
