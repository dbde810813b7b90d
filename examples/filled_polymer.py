"""A rigid sphere rolling over a glass-filled polymer: rolling friction and peak von Mises stress against the filler
fraction, for glass beads and short glass fibres (aligned and random), against the homogenised material (issue 26).

The case (cell h = 10 um, cubic cuboids):

* matrix: a PMMA-like glassy polymer, E(0) = 3 GPa relaxing to E(inf) = 1 GPa over two Prony terms (1 GPa each,
  0.02 and 0.2 s), nu = 0.35 (PMMA's glassy modulus and Poisson ratio, in its lossy range). Not
  :data:`framework.materials.PMMA` itself: seed 001's PMMA relaxes by 21 % only, its steady rolling friction on this
  contact peaks at 6.5e-4 (steady solver, 0.8 um/s), the size of what the particles alone do to the friction (a few
  1e-4 either way over an elastic matrix, ``--elastic``); this matrix peaks at 3.6e-3;
* body: a rigid sphere R = 5 mm under W = 0.3 N, rolling at V = 0.1 mm/s along +x1 (the steady friction of the
  plain matrix is 2.84e-3 there, 79 % of its peak 3.6e-3 at 0.25 mm/s; the wake of the slow term is 6 cells, so the
  transient from rest has reached 95 % of steady after 11 cells); contact radius about 9.5 cells (95 um, a/R = 0.02:
  small strains), peak pressure about 15 MPa on the plain matrix;
* filler: glass (E = 70 GPa, nu = 0.22) in a slab under the rolling path, 10 um to 310 um deep, 300 um across
  (|x2| < 150 um), 400 um long centred on the body's mean position over the friction's window (2.1 contact radii either
  side: as many particles ahead as behind on average), placed by
  :func:`framework.inclusions.random_dispersion` (gap 0; every body wholly inside the slab): ``beads`` (spheres of
  radius 30 um), ``aligned fibres`` and ``random fibres`` (prolate spheroids 90 x 30 x 30 um, aspect 3, along x1 or
  isotropic). 3 cuboids per semi-axis across: the framework's floor (it warns below 4: up to 23 % on one body's
  centre stress; the example silences that warning, which would repeat for every body);
* fractions 0, 10 and 20 % by default (``--fractions 0 0.05 0.1 0.15 0.2`` for the issue's five, about twice the
  time), seeds 1, 2, 3 each (10 %: 32 beads or 11 fibres, 20 %: 64 or 21).

Each run indents at rest, then rolls ``--steps`` cells (12) with the body over the slab all the way; its friction is
the mean over the last ``--window`` steps (4: the plain matrix's transient at 91-97 % of steady) and its spread
the standard deviation over those steps; the peak von Mises stress is the largest over the grid (matrix and
particles) at the last step, and separately in the matrix alone.

The homogenised curve: the same run over a homogeneous half-space of ``reference.mori_tanaka(matrix, glass,
fraction, aspect)`` (the correspondence principle, fitted back to a Prony series). It assumes the whole half-space
homogenised, while the filled runs hold the filler in the slab only: the matrix below 310 um (3.3 contact radii,
where the contact's normal stress is down to 8 % of the peak pressure) and beside it is unfilled, which makes the filled
runs slightly softer than the reference. At 0 % both are the same matrix: their difference is printed and is zero.
The framework has no anisotropic viscoelastic material, so aligned fibres have no homogenised run of their own;
their panel shows the random fibres' curve (same aspect and fraction), for orientation only.

Writes to ``--out`` (default ``filled_polymer_output``): ``filled_polymer.csv`` (one row per run: kind, fraction,
seed, bodies, friction, friction_spread, von_mises_peak, von_mises_matrix, the homogenised friction and peak von
Mises at that fraction, time), ``friction_vs_fraction.png`` and ``von_mises_vs_fraction.png`` (mean and standard
deviation over the seeds per kind and fraction, each seed as a dot, the homogenised curve dashed) and
``filled_polymer_slice.png`` (von Mises in the x1-x3 plane through the axis of the body at the last step of the
last random-fibre run, the highest fraction and the last seed, particles outlined). ``--elastic`` runs each filled
case again over an elastic matrix of the glassy modulus (column ``elastic_friction``, NaN without it): the friction
the particles make alone, by shifting the pressure towards the stiff spots ahead of or behind the axis.

    python examples/filled_polymer.py [--out filled_polymer_output] [--fractions 0 0.1 0.2] [--seeds 1 2 3]
        [--steps 12] [--window 4] [--kinds ...] [--elastic] [--quick]

Measured (default run; mean +- standard deviation over the 3 seeds, friction in 1e-3): at 0 % friction 2.678 and peak
von Mises 9.42 MPa, filled and homogenised alike (difference 0). Beads 10 / 20 %: friction 2.73 +- 0.35 / 2.53 +-
0.33 (homogenised 2.59 / 2.48); aligned fibres 2.92 +- 0.63 / 2.82 +- 0.54 and random fibres 3.16 +- 0.56 / 3.12
+- 0.53 (random-fibre homogenised 2.57 / 2.44). The spread is the particles' size: beads a third of the contact
radius, fibres as long as the contact is wide. Over an elastic matrix (``--kinds beads --elastic``) the beads alone
make +0.23 +- 0.20 / +0.17 +- 0.20 of friction, seed by seed much of the deviation from the homogenised value; the
filled friction less that share is 2.50 +- 0.16 / 2.36 +- 0.14, 3.3 / 4.8 % below Mori-Tanaka. Peak von Mises:
beads 50 +- 12 / 49 +- 1 MPa, aligned fibres 49 +- 7 / 44 +- 10, random fibres 89 +- 67 / 88 +- 57 (one seed's fibre
tip under the contact, 183 and 167 MPa), against 10.9-13.0 MPa homogenised; in the matrix alone 21-27 MPa.

``--quick``: beads only, 0 and 10 %, seed 1, 8 steps (window 4), for the tests. Measured on the 2-core AMD EPYC
(one thread): the default run 244 s (4.1 min; a filled run 9-17 s, the homogenised ones 0.2-0.3 s; 548 s with
other work running before the preconditioner solved the bodies' system in its filled cell), ``--quick`` 24 s
then; the total is printed at the end.
"""
import argparse
import os
import time
import warnings

import numpy as np

import framework as fw
from framework import inclusions, indenters, materials, reference, schedules
from framework.errors import ParameterError, ResolutionWarning
from framework.options import Options
from framework.sweep import write_table

CELL = 10e-6                                        # cuboid edge [m]
MATRIX = materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(1e9, 0.02), (1e9, 0.2)], poisson=0.35)
GLASS = materials.Elastic(young=70e9, poisson=0.22)
RADIUS, LOAD, SPEED = 5e-3, 0.3, 0.1e-3            # rigid sphere [m], load [N], speed [m/s]
PARTICLE = 3 * CELL                                 # semi-axis across a bead or a fibre [m]
FIBRE_ASPECT = 3.0
#: kind: (aspect, orientation, the homogenised curve it is drawn against)
KINDS = {"beads": (1.0, "random", "beads"),
         "aligned fibres": (FIBRE_ASPECT, "aligned", "random fibres"),
         "random fibres": (FIBRE_ASPECT, "random", "random fibres")}
#: The slab reaches this far [m] either side of the middle of the friction's window along x1 (2.1 contact radii):
#: symmetric, so that particles ahead of the body and behind it are as many on average. (Ending 1 contact radius
#: ahead, the slab biased the friction: over an elastic matrix, where particles alone make it, -2.7e-4 and -3.8e-4
#: in the window for two seeds of 10 % beads.)
SLAB_REACH = 20 * CELL
SLAB_HALF_WIDTH = 15 * CELL
SLAB_DEPTHS = (1 * CELL, 31 * CELL)
SHAPE = (96, 48)                                    # surface cells: the contact, its wake and the slab's ends
LAYERS = 34
#: Relative change of the particles' surface displacement that ends a step's coupling. From 1e-8 (the framework's
#: default) to this, the quick run's 10 % beads: friction 2e-5 and peak von Mises 1e-3 of themselves apart, 92
#: products against 181, 12.3 s against 15.7 s.
COUPLING_TOLERANCE = 1e-5


def simulation(material, steps, bodies=None, cells=SHAPE[1]):
    """The rolling run over ``material`` (with ``bodies`` or none) on a grid ``2 cells x cells`` cubes of ``CELL``."""
    n2 = cells
    grid = fw.Grid(shape=(2 * n2, n2), size=(2 * n2 * CELL, n2 * CELL), depth=LAYERS * CELL, layers=LAYERS)
    return fw.Simulation(grid=grid, material=material, indenter=indenters.Sphere(radius=RADIUS),
                         schedule=schedules.Rolling(load=LOAD, velocity=(SPEED, 0.0), distance=steps * CELL),
                         inclusions=bodies, options=Options(coupling_tolerance=COUPLING_TOLERANCE))


def slab(steps, window):
    """The filled region ((x1 lo, hi), (x2 lo, hi), (x3 lo, hi)) [m] in the material's frame (body at x1 = 0 at rest):
    :data:`SLAB_REACH` either side of the body's mean position over the last ``window`` of ``steps`` cells."""
    middle = (steps - (window - 1) / 2.0) * CELL
    return ((middle - SLAB_REACH, middle + SLAB_REACH), (-SLAB_HALF_WIDTH, SLAB_HALF_WIDTH), SLAB_DEPTHS)


def measure(result, window):
    """Friction (mean over the last ``window`` steps), its standard deviation there, and the peak von Mises stress
    [Pa] at the last step over the whole grid and in the matrix alone."""
    friction = result.friction_coefficient[-window:]
    von_mises = result.von_mises(-1)
    matrix = von_mises
    if result.inclusions is not None:
        matrix = von_mises[result.inhomogeneity(-1) == 0]
    return float(friction.mean()), float(friction.std()), float(von_mises.max()), float(matrix.max())


def filled_fraction(bodies, region):
    """Volume of the bodies over the slab's [-]."""
    volume = sum(4.0 / 3.0 * np.pi * np.prod(body.semi_axes) for body in bodies)
    return float(volume / np.prod([high - low for low, high in region]))


def main(cells=SHAPE[1], out="filled_polymer_output", fractions=(0.0, 0.1, 0.2), seeds=(1, 2, 3), steps=12,
         window=4, kinds=tuple(KINDS), elastic=False, quick=False):
    """Run every kind, fraction and seed and the homogenised runs; write the CSV and the pictures; return the rows.

    ``cells`` (cells across the grid, x2) below 45, as the example test gives, means ``quick``: beads only, 0 and
    10 %, seed 1, 8 steps (window 4). ``elastic``: each filled run also over an elastic matrix of the glassy modulus
    (column ``elastic_friction``, the friction the particles make alone; zero without them)."""
    begin_all = time.perf_counter()
    quick = quick or cells < 45
    unknown = [kind for kind in kinds if kind not in KINDS]
    if unknown:
        raise ParameterError(f"kinds = {unknown!r}: expected some of {list(KINDS)}")
    kinds = list(kinds)
    if quick:
        kinds, fractions, seeds, steps, window = ["beads"], (0.0, 0.1), (1,), 8, 4
    os.makedirs(out, exist_ok=True)
    warnings.filterwarnings("ignore", category=ResolutionWarning)   # 3 cuboids per semi-axis: said in the docstring
    region = slab(steps, window)
    print(f"matrix E(0) {MATRIX.instantaneous_modulus / 1e9:g} GPa -> {MATRIX.relaxed_modulus / 1e9:g} GPa, glass "
          f"70 GPa; sphere R = {RADIUS * 1e3:g} mm, W = {LOAD:g} N, V = {SPEED * 1e3:g} mm/s, {steps} steps of "
          f"{CELL * 1e6:g} um (friction over the last {window}); slab {SLAB_DEPTHS[0] * 1e6:g}-"
          f"{SLAB_DEPTHS[1] * 1e6:g} um deep, {2 * SLAB_HALF_WIDTH * 1e6:g} um across", flush=True)

    homogenised, last = {}, {}
    for name in dict.fromkeys(KINDS[kind][2] for kind in kinds):
        aspect = KINDS["beads" if name == "beads" else "random fibres"][0]
        for fraction in fractions:
            material = reference.mori_tanaka(MATRIX, GLASS, fraction, aspect)
            result = simulation(material, steps, cells=cells).run()
            homogenised[name, fraction] = measure(result, window)
            print(f"homogenised {name:>13} {fraction:4.0%}: E(0) {material.instantaneous_modulus / 1e9:.3f} GPa, "
                  f"friction {homogenised[name, fraction][0]:.4e}, peak von Mises "
                  f"{homogenised[name, fraction][2] / 1e6:.2f} MPa", flush=True)

    rows, plain = [], None
    for kind in kinds:
        aspect, orientation, reference_name = KINDS[kind]
        for fraction in fractions:
            for seed in seeds:
                begin = time.perf_counter()
                if fraction == 0.0:
                    if plain is None:                    # no bodies: one run serves every kind and seed
                        plain = measure(simulation(MATRIX, steps, cells=cells).run(), window), \
                            time.perf_counter() - begin
                    # over a homogeneous elastic matrix the friction is zero: nothing is late to recover
                    control = 0.0 if elastic else float("nan")
                    figures, seconds, count, reached = plain[0], plain[1], 0, 0.0
                else:
                    bodies = inclusions.random_dispersion(fraction, region, PARTICLE, GLASS, aspect=aspect,
                                                          orientation=orientation, seed=seed)
                    result = simulation(MATRIX, steps, bodies, cells=cells).run()
                    figures, seconds = measure(result, window), time.perf_counter() - begin
                    count, reached = len(bodies), filled_fraction(bodies, region)
                    last[kind] = result, fraction, seed
                    control = float("nan")
                    if elastic:
                        glassy = materials.Elastic(MATRIX.instantaneous_modulus, MATRIX.poisson)
                        control = measure(simulation(glassy, steps, bodies, cells=cells).run(), window)[0]
                reference_figures = homogenised[reference_name, fraction]
                rows.append(dict(kind=kind, fraction=fraction, seed=seed, bodies=count, fraction_placed=reached,
                                 friction=figures[0], friction_spread=figures[1], von_mises_peak=figures[2],
                                 von_mises_matrix=figures[3], homogenised_friction=reference_figures[0],
                                 homogenised_von_mises=reference_figures[2], elastic_friction=control,
                                 time=seconds))
                print(f"{kind:>14} {fraction:4.0%} seed {seed}: {count:3d} bodies, friction {figures[0]:.4e} "
                      f"+- {figures[1]:.1e} (homogenised {reference_figures[0]:.4e}), peak von Mises "
                      f"{figures[2] / 1e6:.2f} MPa (matrix {figures[3] / 1e6:.2f}; homogenised "
                      f"{reference_figures[2] / 1e6:.2f}), {seconds:.1f} s"
                      + (f"; elastic matrix: friction {control:.2e}" if elastic else ""), flush=True)
    zero = [row for row in rows if row["fraction"] == 0.0]
    if zero:
        print(f"at 0 %: filled minus homogenised friction {zero[0]['friction'] - zero[0]['homogenised_friction']:.1e}, "
              f"peak von Mises {zero[0]['von_mises_peak'] - zero[0]['homogenised_von_mises']:.1e} Pa")
    path = os.path.join(out, "filled_polymer.csv")
    write_table(rows, path)
    print("wrote", path)
    pictures(rows, homogenised, last, kinds, out)
    print(f"total {time.perf_counter() - begin_all:.0f} s")
    return rows


def pictures(rows, homogenised, last, kinds, out):
    try:
        from matplotlib.figure import Figure
        import viz
    except ImportError:
        print("matplotlib or pyvista missing (pip install 'viscocontact[viz]'): no pictures")
        return
    names = []
    for column, label, scale, name in (("friction", "rolling friction coefficient $\\mu$", 1.0, "friction"),
                                       ("von_mises_peak", "peak von Mises stress [MPa]", 1e-6, "von_mises")):
        figure = Figure(figsize=(4.2 * len(kinds), 4.2), layout="constrained")
        axes = figure.subplots(1, len(kinds), sharey=True, squeeze=False)[0]
        for ax, kind in zip(axes, kinds):
            mine = [row for row in rows if row["kind"] == kind]
            fractions = sorted({row["fraction"] for row in mine})
            values = [[row[column] * scale for row in mine if row["fraction"] == f] for f in fractions]
            percent = 100 * np.array(fractions)
            for f, group in zip(percent, values):
                ax.plot([f] * len(group), group, ".", color="grey", alpha=0.6)
            ax.errorbar(percent, [np.mean(v) for v in values], yerr=[np.std(v) for v in values], fmt="o-",
                        capsize=4, label="filled slab: mean, std over seeds")
            curve = KINDS[kind][2]
            index = 2 if column == "von_mises_peak" else 0
            ax.plot(percent, [homogenised[curve, f][index] * scale for f in fractions], "k--",
                    label=f"homogenised (Mori-Tanaka, {curve})")
            ax.set(title=kind, xlabel="glass volume fraction in the slab [%]")
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=8)
        axes[0].set_ylabel(label)
        figure.suptitle(f"Sphere R = {RADIUS * 1e3:g} mm, W = {LOAD:g} N, V = {SPEED * 1e3:g} mm/s\nover a "
                        f"glass-filled polymer (E 3 -> 1 GPa)", fontsize=10)
        names.append(os.path.join(out, f"{name}_vs_fraction.png"))
        figure.savefig(names[-1], dpi=110)
    kind = "random fibres" if "random fibres" in last else next(iter(last), None)
    if kind is not None:
        result, fraction, seed = last[kind]
        names.append(os.path.join(out, "filled_polymer_slice.png"))
        viz.render(result, names[-1], field="von_mises", step=-1, kind="slice", plane="x2", origin=0.0,
                   title=f"von Mises, {kind} {fraction:.0%} (seed {seed}), plane x2 = 0, body at x1 = 0")
    print("wrote the pictures", ", ".join(names))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="filled_polymer_output", help="output folder (created)")
    parser.add_argument("--fractions", type=float, nargs="+", default=[0.0, 0.1, 0.2], help="volume fractions")
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3], help="seeds: realisations per fraction")
    parser.add_argument("--steps", type=int, default=12, help="cells rolled, one step each")
    parser.add_argument("--window", type=int, default=4, help="last steps the friction is averaged over")
    parser.add_argument("--kinds", nargs="+", default=list(KINDS), choices=list(KINDS), help="fillers to run")
    parser.add_argument("--elastic", action="store_true",
                        help="also each filled run over an elastic matrix of the glassy modulus (the particles' share)")
    parser.add_argument("--quick", action="store_true", help="beads only, 0 and 10 %%, seed 1, 8 steps")
    main(**vars(parser.parse_args()))
