"""The eigenstrain operator of a dispersion at a cost that follows its bodies: particle mesh against the box.

Issue 26's "cost that follows the bodies": :class:`framework.operators.particle_mesh.ParticleMeshEigenstrain` (a
coarse box at half the resolution plus exact near-field tables, unknowns on the bodies' cuboids only) beside
:class:`framework.operators.eigenstrain.HalfSpaceEigenstrain` on the box around the bodies (what the coupled runs use
today), on the dispersions of ``bench/dispersion.py`` (glass spheres of radius r at ``--fraction`` in a slab 1-7 r
deep; ``--cells-per-radius`` cuboids per radius). Each operator is built and applied in its own child process (its
peak RSS its own). Prints the machine, then per count:

- bodies, body cuboids, the box (cuboids);
- the box operator: build, a product (median of 3), peak RSS;
- with ``--solve``, the equivalent-inclusion system under a uniform strain (1e-3, 0, -1e-3; an elastic matrix, E = 3
  GPa, nu = 0.35) solved to 1e-7 on the box (``InclusionProblem``, its Fourier preconditioner) and on the bodies
  (``solve_on_bodies``, each body in its filled cell): products, seconds, peak RSS, the eigenstrains' difference
  (largest over the largest, rms over rms, and the bodies' means: largest difference over the largest mean);
- the particle mesh for each ``--near`` radius: build (of which the near tables), a product (median of 3) split
  into the coarse box's product and the near sums, the coarse box's own FFT floor (its six forward and six inverse
  transforms replayed alone), peak RSS, memory per million body cuboids, and its error against the box operator:
  the largest difference over the largest strain, for random eigenstrains and for a uniform one (1e-3 along x1,
  5e-4 shear x1 x2) in every body.

    OMP_NUM_THREADS=1 .venv/bin/python bench/particle_mesh.py [--bodies 10 100] [--cells-per-radius 8]
        [--near 8 10] [--fraction 0.1] [--seed 0] [--solve]
"""
import argparse
import multiprocessing
import os
import resource
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import framework as fw  # noqa: E402
from framework import inclusions, materials  # noqa: E402
from framework.inclusions.field import layout  # noqa: E402
from framework.operators.eigenstrain import HalfSpaceEigenstrain  # noqa: E402
from framework.operators.particle_mesh import ParticleMeshEigenstrain  # noqa: E402
from dispersion import DEPTH, GAP, GLASS, MARGIN, RADIUS, region  # noqa: E402
from elastic_hertz import machine  # noqa: E402

POISSON = 0.35
APPLIED = np.diag([1e-3, 0.0, -1e-3])


def case(count, cells_per_radius, fraction, seed):
    """The grid, the box ``(start, shape)`` and the body cuboids ``(n, 3)`` (grid indices) of a dispersion."""
    cell = RADIUS / cells_per_radius
    side, slab = region(count, fraction)
    n = int(np.ceil((side + MARGIN * RADIUS) / cell / 32.0)) * 32
    layers = int(round(DEPTH * cells_per_radius))
    grid = fw.Grid(shape=(n, n), size=(n * cell, n * cell), depth=layers * cell, layers=layers)
    bodies = inclusions.random_dispersion(fraction, slab, RADIUS, GLASS, gap=GAP * RADIUS, seed=seed)
    start, shape, indicator = layout(grid, bodies, 0.0)
    cells = np.argwhere(indicator > 0) + np.array(start)
    return grid, start, shape, cells


def eigenstrains(count, seed=1):
    rng = np.random.default_rng(seed)
    uniform = np.tile([1e-3, 0.0, 0.0, 0.0, 0.0, 5e-4], (count, 1))
    return {"random": rng.standard_normal((count, 6)), "uniform": uniform}


def timed(function, repeat=3):
    times, out = [], None
    for _ in range(repeat):
        begin = time.perf_counter()
        out = function()
        times.append(time.perf_counter() - begin)
    return float(np.median(times)), out


def box_run(args, path):
    grid, start, shape, cells = case(*args)
    begin = time.perf_counter()
    operator = HalfSpaceEigenstrain(grid, POISSON, start, shape, folded=False)
    build = time.perf_counter() - begin
    local = tuple((cells - np.array(start)).T)
    out = {}
    for name, values in eigenstrains(len(cells)).items():
        field = np.zeros((*shape, 6))
        field[local] = values
        seconds, strain = timed(lambda: operator.strain(field))
        out[name] = seconds
        np.save(os.path.join(path, f"{name}.npy"), strain[local])
    return dict(build=build, product=out["random"], rss=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
                cells=len(cells), box=shape)


def mesh_run(args, near, path):
    grid, _, _, cells = case(*args)
    begin = time.perf_counter()
    operator = ParticleMeshEigenstrain(grid, POISSON, cells, near=near)
    build = time.perf_counter() - begin
    out = dict(build=build, coarse_box=operator.coarse.shape, tables=operator.table.nbytes, held=operator.nbytes)
    for name, values in eigenstrains(len(cells)).items():
        seconds, strain = timed(lambda: operator.strain(values))
        reference = np.load(os.path.join(path, f"{name}.npy"))
        out[f"{name} error"] = float(np.abs(strain - reference).max() / np.abs(reference).max())
        out[f"{name} time"] = seconds
    values = eigenstrains(len(cells))["random"]
    out["coarse"] = timed(lambda: operator.coarse.strain(values))[0]
    out["near"] = timed(lambda: operator.near_strain(values))[0]
    # the coarse box's FFT floor: its pruned transforms with nothing between them
    transforms = operator.coarse.operator._box_fft()
    field = np.zeros((*operator.coarse.shape, 6))
    out["floor"] = timed(lambda: transforms.apply(field, lambda *a, **k: None))[0]
    out["rss"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    return out


def box_solve(args, path):
    from framework.inclusions.field import InclusionProblem, strain_vector
    grid, start, shape, cells = case(*args)
    bodies = inclusions.random_dispersion(args[2], region(args[0], args[2])[1], RADIUS, GLASS, gap=GAP * RADIUS,
                                          seed=args[3])
    begin = time.perf_counter()
    problem = InclusionProblem(grid, materials.Elastic(3e9, POISSON), bodies, margin=0.0)
    solution = problem.problem.solve(strain_vector(APPLIED, name="applied strain"), tolerance=1e-7)
    seconds = time.perf_counter() - begin
    np.save(os.path.join(path, "solve.npy"), solution.eigenstrain[tuple((cells - np.array(start)).T)])
    return dict(seconds=seconds, products=problem.problem.products,
                rss=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20)


def mesh_solve(args, near, path):
    from framework.inclusions.dispersed import solve_on_bodies
    grid, start, shape, cells = case(*args)
    bodies = inclusions.random_dispersion(args[2], region(args[0], args[2])[1], RADIUS, GLASS, gap=GAP * RADIUS,
                                          seed=args[3])
    begin = time.perf_counter()
    solution = solve_on_bodies(grid, materials.Elastic(3e9, POISSON), bodies, APPLIED, tolerance=1e-7, near=near)
    seconds = time.perf_counter() - begin
    reference = np.load(os.path.join(path, "solve.npy"))
    difference = solution.eigenstrain - reference          # both in the grid's C order
    body = solution.body
    count = np.bincount(body)
    means = [np.stack([np.bincount(body, weights=v[:, c]) / count for c in range(6)], axis=1)
             for v in (difference, reference)]
    error = dict(largest=np.abs(difference).max() / np.abs(reference).max(),
                 rms=np.sqrt((difference ** 2).mean() / (reference ** 2).mean()),
                 means=np.abs(means[0]).max() / np.abs(means[1]).max())
    return dict(seconds=seconds, products=solution.products, iterations=solution.iterations, error=error,
                rss=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20)


def child(function, *args):
    with multiprocessing.get_context("fork").Pool(1) as pool:
        return pool.apply(function, args)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bodies", type=int, nargs="+", default=[10, 100], help="counts of glass spheres")
    parser.add_argument("--cells-per-radius", type=int, default=8, help="cuboids per sphere radius")
    parser.add_argument("--near", type=float, nargs="+", default=[8.0, 10.0], help="near-field radii [cuboids]")
    parser.add_argument("--fraction", type=float, default=0.1, help="volume fraction of the slab")
    parser.add_argument("--seed", type=int, default=0, help="seed of the dispersion")
    parser.add_argument("--solve", action="store_true", help="also solve the equivalent-inclusion system both ways")
    args = parser.parse_args()
    print(machine())
    print(f"glass spheres, {args.cells_per_radius} cuboids per radius, fraction {args.fraction:.2f}, seed {args.seed}, "
          f"poisson {POISSON}; OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}\n", flush=True)
    for count in args.bodies:
        options = (count, args.cells_per_radius, args.fraction, args.seed)
        with tempfile.TemporaryDirectory() as path:
            box = child(box_run, options, path)
            cells, shape = box["cells"], box["box"]
            print(f"{count} bodies: {cells / 1e6:.3f} M body cuboids, box {shape[0]} x {shape[1]} x {shape[2]} = "
                  f"{np.prod(shape) / 1e6:.3f} M cuboids")
            print(f"  box operator: build {box['build']:.1f} s, product {box['product']:.3f} s, peak RSS "
                  f"{box['rss']:.2f} GiB ({box['rss'] / (cells / 1e6):.1f} GiB per million body cuboids)", flush=True)
            for near in args.near:
                mesh = child(mesh_run, options, near, path)
                c = mesh["coarse_box"]
                print(f"  particle mesh, near {near:g}: build {mesh['build']:.1f} s; product {mesh['random time']:.3f} s "
                      f"= coarse box {c[0]} x {c[1]} x {c[2]} {mesh['coarse']:.3f} s (its FFTs alone "
                      f"{mesh['floor']:.3f} s) + near sums {mesh['near']:.3f} s; tables {mesh['tables'] / 2**20:.0f} "
                      f"MiB (with the stencils and the near sums' layout {mesh['held'] / 2**20:.0f} MiB); peak RSS {mesh['rss']:.2f} GiB ({mesh['rss'] / (cells / 1e6):.1f} GiB per million body "
                      f"cuboids); error: random {mesh['random error']:.1e}, uniform {mesh['uniform error']:.1e}",
                      flush=True)
            if args.solve:
                solved = child(box_solve, options, path)
                print(f"  system on the box (Fourier preconditioner), to 1e-7: {solved['products']} products, "
                      f"{solved['seconds']:.1f} s, peak RSS {solved['rss']:.2f} GiB", flush=True)
                for near in args.near:
                    mesh = child(mesh_solve, options, near, path)
                    print(f"  system on the bodies (particle mesh near {near:g}, body by body), to 1e-7: "
                          f"{mesh['products']} products ({mesh['iterations']} GMRES iterations), {mesh['seconds']:.1f} s "
                          f"(its build included), peak RSS {mesh['rss']:.2f} GiB; eigenstrains against the box's: largest "
                          f"difference {mesh['error']['largest']:.1e} of the largest, rms {mesh['error']['rms']:.1e}, "
                          f"bodies' means {mesh['error']['means']:.1e}", flush=True)
        print(flush=True)


if __name__ == "__main__":
    main()
