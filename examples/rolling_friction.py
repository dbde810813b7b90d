"""Rolling friction of a rigid sphere and a rigid cylinder on viscoelastic solids (seed 000).

A rigid body rolling, or sliding without friction, at the speed V over a
viscoelastic half-space is resisted: the material ahead of it is pressed
faster than it creeps, the material behind it recovers late, so the pressure
shifts ahead of the axis and pushes against the motion. The apparent friction
coefficient ``mu = F_t / W`` (positive when it resists) is zero on the relaxed
solid (V -> 0) and on the glassy one (V -> inf) and peaks where the wake
``V T`` is about the contact size.

Cases (R = 10 mm; small strains: relaxed contact size a0/R = 3 to 5 %):

* ``sphere_sls``: sphere, W = 0.2 N, on the standard linear solid
  E(t) = 10 + 90 exp(-t / 1 s) MPa, nu = 0.5 (a rubber-like solid, glassy
  modulus 10 times the relaxed one; one retardation time T = 10 s):
  relaxed Hertz radius a0 = 0.483 mm, glassy 0.224 mm.
* ``cylinder_sls``: cylinder, W' = 100 N/m, same solid: relaxed half-width
  b0 = 0.309 mm (a line contact: a grid periodic along the cylinder's axis).
* ``sphere_pmma``: sphere, W = 8 N, on PMMA (seed 001's two-term Prony series,
  E(t) = 1973 + 254.8 exp(-t/8.93 s) + 263.7 exp(-t/117.96 s) MPa, nu = 0.35):
  a0 = 0.299 mm, relaxed peak pressure 43 MPa. Its creep compliance has two
  retardation times, 9.94 s and 133.9 s; T = lambda_2 = 133.9 s, the longer
  one, whose term is the larger (5.33e-11 against 3.93e-11 1/Pa) and carries
  95 % of the low-speed friction (sum c_k lambda_k). The short one adds a
  shoulder at V T / a0 ~ 13.5.
* ``cylinder_pmma``: cylinder, W' = 16 kN/m, on PMMA: b0 = 0.301 mm.

What it computes (``cells`` cells per side of the steady grid, which is
3 a0 square for the sphere, 3 b0 long for the cylinder; 96 by default, where
the friction coefficient at the peak is converged to 0.1 %,
tests/test_rolling_convergence.py):

1. Steady solves at log-spaced speeds over the whole curve (4 per decade,
   1 on grids coarser than 64 cells), V T / a0 = 1e-3 to 1e4 (the grid holds
   the contact only: the wake is in the steady operator): friction coefficient, contact size,
   peak pressure, pressure centre, torque and dissipated power; the low-speed
   slope ``mu = V sum c_k lambda_k / (R C*(inf))`` (sphere and cylinder) and
   the sphere's high-speed asymptote
   ``mu = (4/5) a_g**2 / (R c0) sum c_k / (lambda_k V)`` (a_g the glassy Hertz
   radius; both derived in :mod:`framework.reference.rolling`) as dashed and
   dotted lines.
2. Pressure maps (sphere) and profiles (cylinder) at three speeds: a decade
   below the friction peak, at it, and a decade above.
3. The transient from rest (the load applied at t = 0, then rolling at the
   sphere-on-SLS peak speed for 5 a0): friction, contact area and peak
   pressure against the distance rolled, with the steady values on the same
   grid.

Writes to ``--out``: ``rolling_friction.csv`` (one row per case and speed),
``rolling_transient.csv`` and, with matplotlib, ``rolling_friction.png``,
``rolling_pressure_maps.png``, ``rolling_pressure_profiles.png`` and
``rolling_transient.png``.

    python examples/rolling_friction.py [--cells 96] [--per-decade 4] [--out out/examples]
"""
import argparse
import csv
import math
import os
from dataclasses import dataclass

import numpy as np

import framework as fw
from framework import indenters, materials, reference, schedules

RADIUS = 10e-3                                       # m, sphere and cylinder
#: Default cells per side of the steady grid: the friction at the peak is converged to 0.1 % there.
CELLS = 96
SLS = materials.StandardLinearSolid(e_inf=1e7, e_1=9e7, tau=1.0, poisson=0.5)
#: Tight solver tolerances: the solver error must stay far below the discretisation error.
OPTIONS = {"residual_tolerance": 1e-9, "tolerance": 1e-10}
#: Dimensionless speeds V T / a0 of the friction curves: the decades they span, sphere and cylinder.
DECADES = {"sphere": (-3, 4), "cylinder": (-3, 4)}
#: Steady grid: this many relaxed contact sizes (a0 or b0) along the motion (and across, sphere).
GRID_SIZES = 3.0
#: Cells across the periodic axis of a line contact (the body is uniform along it).
LINE_CELLS = 4


@dataclass(frozen=True)
class Case:
    """A body on a material under a load.

    Parameters
    ----------
    name : str
        Short name (CSV and legends).
    label : str
        Legend text.
    material : framework material
        The half-space.
    body : str
        ``"sphere"`` or ``"cylinder"`` (axis along x2, a line contact).
    load : float
        Sphere: load W [N]; cylinder: load per length W' [N/m].
    """

    name: str
    label: str
    material: object
    body: str
    load: float

    @property
    def series(self):
        return self.material.contact_compliance()

    @property
    def retardation_time(self):
        """T [s]: the longest retardation time (the one of the largest term for both materials here)."""
        return float(max(self.series.times))

    @property
    def line(self):
        return self.body == "cylinder"

    @property
    def material_name(self):
        return "PMMA" if self.material is materials.PMMA else "SLS"

    def hertz(self, compliance):
        """Hertz contact with the contact compliance ``compliance`` [1/Pa] (relaxed: C*(inf), glassy: c0)."""
        if self.line:
            return reference.HertzCylinder(radius=RADIUS, load_per_length=self.load, contact_modulus=1 / compliance)
        return reference.HertzSphere(radius=RADIUS, load=self.load, contact_modulus=1 / compliance)

    def size(self, compliance):
        """Hertz radius or half-width [m] with the compliance ``compliance`` [1/Pa]."""
        hertz = self.hertz(compliance)
        return hertz.half_width if self.line else hertz.contact_radius

    @property
    def a0(self):
        """Relaxed contact size [m]: the Hertz radius or half-width with C*(inf)."""
        return self.size(self.series.relaxed)

    def speed(self, dimensionless):
        """Speed V [m/s] at the dimensionless speed ``V T / a0``."""
        return dimensionless * self.a0 / self.retardation_time

    def grid(self, cells, length=None):
        """Grid centred on the body's axis with cells of ``GRID_SIZES a0 / cells``, ``length`` [m] along x1.

        Square cells; the sphere's grid is ``GRID_SIZES a0`` across, the
        cylinder's ``LINE_CELLS`` cells, periodic (a line contact).
        """
        dx = GRID_SIZES * self.a0 / cells
        n1 = cells if length is None else 2 * math.ceil(length / (2 * dx))
        n2 = LINE_CELLS if self.line else cells
        return fw.Grid(shape=(n1, n2), size=(n1 * dx, n2 * dx), periodic=(False, self.line))

    def indenter(self):
        return indenters.Cylinder(radius=RADIUS, axis=1) if self.line else indenters.Sphere(radius=RADIUS)

    def total_load(self, grid):
        """Load on the grid [N]: W, or W' times the grid's length along the cylinder."""
        return self.load * grid.size[1] if self.line else self.load

    def low_speed_slope(self):
        """``d mu / dV`` [s/m] at V = 0: ``sum c_k lambda_k / (R C*(inf))`` (sphere and cylinder alike)."""
        return reference.low_speed_friction_slope(self.material, RADIUS)

    def high_speed_coefficient(self):
        """``mu V`` [m/s] as V -> inf (sphere): ``(4/5) a_g**2 / (R c0) sum c_k / lambda_k``."""
        return reference.high_speed_sphere_friction(self.material, RADIUS, self.load, 1.0)


CASES = (
    Case("sphere_sls", "sphere on SLS", SLS, "sphere", 0.2),
    Case("cylinder_sls", "cylinder on SLS", SLS, "cylinder", 100.0),
    Case("sphere_pmma", "sphere on PMMA", materials.PMMA, "sphere", 8.0),
    Case("cylinder_pmma", "cylinder on PMMA", materials.PMMA, "cylinder", 16e3),
)


def steady(case, dimensionless, cells, grid=None):
    """The steady state at the dimensionless speed ``V T / a0``: a one-record :class:`framework.Result`.

    The default grid is ``GRID_SIZES a0`` long: it holds the contact, the wake lies in the operator.
    """
    if grid is None:
        grid = case.grid(cells)
    schedule = schedules.Rolling(load=case.total_load(grid), velocity=(case.speed(dimensionless), 0.0), steady=True)
    return fw.Simulation(grid=grid, material=case.material, indenter=case.indenter(), schedule=schedule,
                         options=OPTIONS).run()


def transient(case, dimensionless, cells, records=80):
    """Roll from rest (the load applied at t = 0) at ``V T / a0``; returns the run and the steady state on its grid.

    The grid holds the contact and 3.2 wakes ``V T`` behind the axis (the
    stepper drops the history of material leaving it; it asks for 3) and as
    much ahead (it is centred on the body); the body rolls 5 times the larger
    of the wake and a0, which brings it within a fraction of a percent of the
    steady state.
    """
    wake = case.speed(dimensionless) * case.retardation_time
    grid = case.grid(cells, length=2 * (1.2 * case.a0 + 3.2 * wake))
    distance = 5 * max(wake, case.a0)
    speed = case.speed(dimensionless)
    step = grid.spacing[0] / speed                       # the body moves one cell per step
    count = int(round(distance / grid.spacing[0]))
    every = max(1, count // records)
    schedule = schedules.Rolling(load=case.total_load(grid), velocity=(speed, 0.0), distance=distance,
                                 times=step * np.arange(0, count + 1, every))
    rolled = fw.Simulation(grid=grid, material=case.material, indenter=case.indenter(), schedule=schedule).run()
    return rolled, steady(case, dimensionless, cells, grid=grid)


def friction_curve(case, cells, per_decade):
    """Steady states at log-spaced ``V T / a0`` over the case's :data:`DECADES`: ``(speeds, results)``."""
    first, last = DECADES[case.body]
    dimensionless = np.logspace(first, last, (last - first) * per_decade + 1)
    return dimensionless, [steady(case, x, cells) for x in dimensionless]


def friction(results):
    """The friction coefficients of one-record results."""
    return np.array([result.friction_coefficient[0] for result in results])


def csv_row(case, dimensionless, result):
    """One row of ``rolling_friction.csv``: a sphere's totals, a cylinder's values per unit length."""
    per_length = result.grid.size[1]                    # a line contact's load is per this length
    row = {"case": case.name, "body": case.body,
           "material": case.material_name,
           "retardation_time_T_s": case.retardation_time, "relaxed_size_a0_m": case.a0,
           "speed_m_per_s": case.speed(dimensionless), "dimensionless_speed_VT_over_a0": dimensionless,
           "friction_coefficient": result.friction_coefficient[0],
           "contact_radius_m": "" if case.line else result.contact_radius[0],
           "half_width_m": result.half_width[0] if case.line else "",
           "max_pressure_Pa": result.max_pressure[0], "pressure_centre_m": result.center[0, 0]}
    for name, value, sphere, line in (("load", result.load[0], "N", "N_per_m"),
                                      ("torque", result.torque[0], "N_m", "N"),
                                      ("dissipated_power", result.dissipated_power[0], "W", "W_per_m")):
        row[f"{name}_{sphere}"] = "" if case.line else value
        row[f"{name}_per_length_{line}"] = value / per_length if case.line else ""
    return row


def main(cells=CELLS, out="out/examples", per_decade=None):
    """Run every case; write the CSV files and pictures to ``out``; return the steady rows.

    Parameters
    ----------
    cells : int
        Cells per side of the steady grid (``GRID_SIZES`` relaxed contact sizes).
    out : str
        Output folder.
    per_decade : int, optional
        Speeds per decade of the friction curves (default 4, or 1 on grids
        coarser than 64 cells: a quick look).
    """
    os.makedirs(out, exist_ok=True)
    per_decade = per_decade or (4 if cells >= 64 else 1)
    curves, rows = {}, []
    for case in CASES:
        curves[case.name] = dimensionless, results = friction_curve(case, cells, per_decade)
        rows += [csv_row(case, x, result) for x, result in zip(dimensionless, results)]
        mu = friction(results)
        peak = int(np.argmax(mu))
        print(f"{case.label}: a0 = {case.a0 * 1e3:.3f} mm, T = {case.retardation_time:.4g} s; peak mu = "
              f"{mu[peak]:.4g} at V T / a0 = {dimensionless[peak]:.3g} (V = {case.speed(dimensionless[peak]):.3g} "
              f"m/s)")
    write_csv(os.path.join(out, "rolling_friction.csv"), rows)

    case = CASES[0]
    dimensionless, results = curves[case.name]
    peak = float(dimensionless[int(np.argmax(friction(results)))])
    rolled, settled = transient(case, peak, cells)
    distance = rolled.position[:, 0]
    write_csv(os.path.join(out, "rolling_transient.csv"), [
        {"distance_m": d, "time_s": t, "friction_coefficient": f, "contact_area_m2": area, "max_pressure_Pa": p,
         "steady_friction_coefficient": settled.friction_coefficient[0],
         "steady_contact_area_m2": settled.contact_area[0], "steady_max_pressure_Pa": settled.max_pressure[0]}
        for d, t, f, area, p in zip(distance, rolled.times, rolled.friction_coefficient, rolled.contact_area,
                                    rolled.max_pressure)])
    last = {name: getattr(rolled, name)[-1] / getattr(settled, name)[0] - 1
            for name in ("friction_coefficient", "contact_area", "max_pressure")}
    print(f"transient {case.label} at V T / a0 = {peak:.3g}, rolled {distance[-1] / case.a0:.1f} a0: against the "
          "steady state " + ", ".join(f"{name} {value:+.2%}" for name, value in last.items()))
    plot(curves, (case, peak, rolled, settled), out)
    return rows


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("wrote", path)


def plot(curves, transient_run, out):
    try:
        from matplotlib.figure import Figure
    except ImportError:
        print("matplotlib not installed (pip install 'viscocontact[viz]'): no pictures")
        return
    names = [plot_friction(Figure, curves, out), plot_maps(Figure, curves, out), plot_profiles(Figure, curves, out),
             plot_transient(Figure, *transient_run, out)]
    print("wrote the pictures", ", ".join(os.path.join(out, name) for name in names))


def around_peak(dimensionless, results):
    """Indices of the speeds a decade below the friction peak, at it and a decade above (within the curve)."""
    peak = int(np.argmax(friction(results)))
    decade = int(round(1 / np.log10(dimensionless[1] / dimensionless[0])))
    return [max(peak - decade, 0), peak, min(peak + decade, len(results) - 1)]


COLOURS = {"SLS": "tab:blue", "PMMA": "tab:red"}
#: The speeds :func:`around_peak` picks.
WHERE = ("below the peak", "friction peak", "above the peak")


def plot_friction(Figure, curves, out):
    figure = Figure(figsize=(12, 5.2), layout="constrained")
    axes = figure.subplots(1, 2, sharey=True)
    for ax, body in zip(axes, ("sphere", "cylinder")):
        size = "b0" if body == "cylinder" else "a0"
        for case in (c for c in CASES if c.body == body):
            colour = COLOURS[case.material_name]
            dimensionless, results = curves[case.name]
            mu = friction(results)
            ax.loglog(dimensionless, mu, "o-", color=colour, markersize=3.5,
                      label=f"{case.label}: T = {case.retardation_time:.4g} s, {size} = {case.a0 * 1e3:.3g} mm")
            speeds = case.speed(dimensionless)
            low = dimensionless <= 1.0
            ax.loglog(dimensionless[low], case.low_speed_slope() * speeds[low], "--", color=colour, linewidth=1)
            if body == "sphere":
                high = dimensionless >= 30.0
                ax.loglog(dimensionless[high], case.high_speed_coefficient() / speeds[high], ":", color=colour,
                          linewidth=2)
        ax.plot([], [], "k--", linewidth=1, label=r"low speed: $\mu = V \sum_k c_k \lambda_k \,/\, (R\, C^*_\infty)$")
        if body == "sphere":
            ax.plot([], [], "k:", linewidth=2,
                    label=r"high speed: $\mu = \frac{4}{5}\, a_g^2 \sum_k (c_k / \lambda_k) \,/\, (R\, c_0\, V)$")
        ax.set(xlabel=f"dimensionless speed V T / {size}  [-]", title=f"{body}: steady rolling friction",
               ylim=(1e-6, 0.1))
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=8, loc="lower center")
    axes[0].set_ylabel(r"friction coefficient $\mu = F_t / W$ [-]")
    figure.suptitle("Rolling (frictionless sliding) friction on viscoelastic solids, R = 10 mm; a0: relaxed Hertz "
                    "radius, b0: relaxed half-width, T: longest retardation time", fontsize=10)
    return _save(figure, out, "rolling_friction.png")


def plot_maps(Figure, curves, out):
    spheres = [c for c in CASES if c.body == "sphere"]
    figure = Figure(figsize=(16, 7.6), layout="constrained")
    rows = figure.subplots(len(spheres), 4, width_ratios=(1, 1, 1, 1.4))
    angle = np.linspace(0, 2 * np.pi, 200)
    for row, case in zip(rows, spheres):
        dimensionless, results = curves[case.name]
        p0 = case.hertz(case.series.relaxed).max_pressure
        chosen = around_peak(dimensionless, results)
        top = max(results[k].max_pressure[0] for k in chosen) / p0
        for ax, k, where in zip(row, chosen, WHERE):
            result = results[k]
            grid = result.grid
            extent = np.array([-grid.size[0], grid.size[0], -grid.size[1], grid.size[1]]) / (2 * case.a0)
            image = ax.imshow(result.pressure(0).T / p0, origin="lower", extent=extent, cmap="viridis", vmin=0,
                              vmax=top, interpolation="nearest")
            ax.plot(np.cos(angle), np.sin(angle), "w--", linewidth=0.8)
            ax.plot(0, 0, "P", color="w", markeredgecolor="k", markersize=9)
            ax.plot(result.center[0, 0] / case.a0, 0, "X", color="tab:red", markeredgecolor="w", markersize=9)
            ax.annotate("V", xy=(1.4, -1.3), xytext=(0.8, -1.3), color="w", va="center", ha="right",
                        arrowprops=dict(arrowstyle="->", color="w"))
            ax.set_title(f"{case.label}, {where}\n$V T / a_0$ = {dimensionless[k]:.3g}, $\\mu$ = "
                         f"{result.friction_coefficient[0]:.3g}, centre $x_1$ = "
                         f"{result.center[0, 0] / case.a0:.3f} $a_0$",
                         fontsize=9)
            ax.set(xlabel="$x_1 / a_0$ (along the motion)", ylabel="$x_2 / a_0$")
        figure.colorbar(image, ax=list(row[:3]), label="$p / p_0$ (relaxed Hertz peak)", shrink=0.9)
        middle = int(np.argmin(np.abs(grid.x2)))
        draw_profiles(row[3], case, dimensionless, results, middle)
        row[3].set_title(f"{case.label}: along $x_1$ at $x_2$ = {grid.x2[middle] / case.a0:.2g} $a_0$", fontsize=9)
    figure.suptitle("Sphere: steady pressure in the body's frame; dashed circle: relaxed Hertz contact, white +: "
                    "the axis, red x: the pressure centre", fontsize=10)
    return _save(figure, out, "rolling_pressure_maps.png")


def draw_profiles(ax, case, dimensionless, results, column):
    """Pressure along x1 at the grid column ``column`` across, below, at and above the friction peak, with Hertz's."""
    size = "b0" if case.line else "a0"
    relaxed, glassy = case.hertz(case.series.relaxed), case.hertz(case.series.c0)
    p0 = relaxed.max_pressure
    fine = np.linspace(-1.5, 1.5, 601) * case.a0
    ax.plot(fine / case.a0, relaxed.pressure(fine) / p0, "k:", linewidth=1, label="Hertz, relaxed")
    ax.plot(fine / case.a0, glassy.pressure(fine) / p0, "k--", linewidth=0.8, label="Hertz, glassy")
    top = glassy.max_pressure
    for k, where in zip(around_peak(dimensionless, results), WHERE):
        result = results[k]
        top = max(top, result.max_pressure[0])
        ax.step(result.grid.x1 / case.a0, result.pressure(0)[:, column] / p0, where="mid",
                label=f"$V T / {size[0]}_0$ = {dimensionless[k]:.3g} ({where}), "
                      f"$\\mu$ = {result.friction_coefficient[0]:.3g}")
    ax.set(xlim=(-1.5, 1.5), ylim=(0, 1.5 * top / p0), xlabel=f"$x_1 / {size[0]}_0$ (the body moves towards $+x_1$)",
           ylabel="$p / p_0$ (relaxed Hertz peak) [-]")
    ax.legend(fontsize=7.5, loc="upper left")


def plot_profiles(Figure, curves, out):
    cylinders = [c for c in CASES if c.body == "cylinder"]
    figure = Figure(figsize=(12, 4.6), layout="constrained")
    axes = figure.subplots(1, len(cylinders))
    for ax, case in zip(axes, cylinders):
        dimensionless, results = curves[case.name]
        draw_profiles(ax, case, dimensionless, results, 0)
        ax.set_title(f"{case.label}: W' = {case.load:g} N/m, b0 = {case.a0 * 1e3:.3g} mm, "
                     f"T = {case.retardation_time:.4g} s", fontsize=9)
    figure.suptitle("Cylinder (line contact): steady pressure across the contact", fontsize=10)
    return _save(figure, out, "rolling_pressure_profiles.png")


def plot_transient(Figure, case, dimensionless, rolled, settled, out):
    figure = Figure(figsize=(7.5, 7.5), layout="constrained")
    axes = figure.subplots(3, 1, sharex=True)
    distance = rolled.position[:, 0] / case.a0
    p0 = case.hertz(case.series.relaxed).max_pressure
    area = np.pi * case.a0**2
    for ax, values, steady_value, label in (
            (axes[0], rolled.friction_coefficient, settled.friction_coefficient[0], "friction coefficient [-]"),
            (axes[1], rolled.contact_area / area, settled.contact_area[0] / area, "contact area / (pi a0^2)"),
            (axes[2], rolled.max_pressure / p0, settled.max_pressure[0] / p0, "peak pressure / p0")):
        ax.plot(distance, values, "o-", markersize=2.5, label="transient, from rest")
        ax.axhline(steady_value, color="k", linestyle="--", linewidth=1, label="steady state")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8, loc="lower right")
    axes[-1].set_xlabel("distance rolled / a0  [-]")
    figure.suptitle(f"{case.label}: rolling from rest at V T / a0 = {dimensionless:.3g} (the friction peak)\n"
                    f"a0 = {case.a0 * 1e3:.3g} mm, p0 = {p0 / 1e6:.3g} MPa (relaxed Hertz)", fontsize=10)
    return _save(figure, out, "rolling_transient.png")


def _save(figure, out, name):
    figure.savefig(os.path.join(out, name), dpi=110)
    return name


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=CELLS, help="cells per side of the steady grid (3 a0)")
    parser.add_argument("--per-decade", type=int, default=None, help="speeds per decade (default 4, 1 below 64 cells)")
    parser.add_argument("--out", default="out/examples")
    main(**vars(parser.parse_args()))
