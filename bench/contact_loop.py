"""Cost of a contact iteration against the FFTs it needs, and iterations per viscoelastic step.

This project alone. Prints the machine, then

1. per grid (N x N, open: DC-FFT on a zero-padded 2N x 2N grid and the
   windowed product on a box around the contact; doubly periodic) a Hertz
   solve (contact radius 0.15 of the side, tolerance ``--tolerance``): the time
   per iteration (best of ``--repeat`` solves, FFT plans warm), the time of the
   FFT pairs it ran (every product and every preconditioning of the solve
   recorded with its FFT shape, in order; after each solve the same sequence
   of forward + inverse pairs replayed alone, on plans and buffers of their
   own) per iteration, and their ratio; the time the solve spent in its
   products (the pairs with the copies into the FFT buffers and the spectral
   multiplications, called from the loop: what the iteration costs with no
   pass of its own); for the fused loop with
   the passes in use (compiled by numba when installed), preconditioned by
   the surface stiffness as :class:`framework.Simulation` runs it, and, for
   comparison, the same loop unpreconditioned (``plain``), with the numpy
   passes and the reference loop as numpy expressions
   (``solver._iterate_reference``); each repeat times the solve and then its
   FFT pairs, the best of each kept;
2. the mean contact iterations per viscoelastic step after the first,
   with the predicted warm start and with the previous pressure as the warm
   start: a ball creeping into the standard-linear-like solid of
   ``visco_indentation.py`` (its 256^2 case, 50 log-spaced output times) and a
   PMMA ball under a step load (128^2, 50 log-spaced output times, as the demo);
   and the time of both runs (after a first run that makes the FFT plans).

    .venv/bin/python bench/contact_loop.py [--sizes 512 1024] [--repeat 3] [--tolerance 1e-10] [--visco 256]
"""
import argparse
import contextlib
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import framework as fw  # noqa: E402
from framework import _fused, fft, indenters, loads, materials, reference, schedules, simulation, solver  # noqa: E402
from framework.operators import SurfaceCompliance, SurfaceStiffness  # noqa: E402
from elastic_hertz import POISSON, RADIUS, SIDE, YOUNG, machine  # noqa: E402
import visco_indentation  # noqa: E402


def replay(shapes, pairs):
    """Time [s] of the forward + inverse real FFT pairs of ``shapes``, in that order, alone: each shape's pair
    from ``pairs`` (made here when missing: plans and buffers warm for the next call)."""
    for shape in set(shapes) - set(pairs):
        pairs[shape] = fft.RealFFTPair(shape)
        pairs[shape].real_in[...] = np.random.default_rng(0).random(shape)
    start = time.perf_counter()
    for shape in shapes:
        pair = pairs[shape]
        pair.forward()
        pair.inverse()
    return time.perf_counter() - start


@contextlib.contextmanager
def loop(kind):
    """``fused`` (the passes in use), ``numpy`` (fused loop, numpy passes), ``reference`` (the loop as plain
    numpy expressions), all preconditioned; ``plain``: the fused loop without the preconditioner."""
    with contextlib.ExitStack() as stack:
        if kind == "numpy":
            stack.enter_context(_fused.use_compiled(False))
        if kind == "reference":
            saved = solver._iterate
            solver._iterate = solver._iterate_reference
            stack.callback(setattr, solver, "_iterate", saved)
        yield


def hertz(n, periodic, tolerance, repeat, kind):
    """Per iteration: time [s], time of its FFT pairs alone [s]; iterations, peak pressure error, and the time
    per iteration spent in the products [s]."""
    grid = fw.Grid(shape=(n, n), size=(SIDE, SIDE), periodic=(periodic, periodic))
    operator = SurfaceCompliance(grid)
    heights = indenters.Sphere(radius=RADIUS).on_grid(grid)
    modulus = YOUNG / (1 - POISSON**2)
    exact = reference.HertzSphere.from_contact_radius(RADIUS, 0.15 * SIDE, modulus)
    compliance = 1 / modulus
    shapes, inside = [], [0.0]   # the FFT shape of every product, in order; the time spent in the products

    def timed(product):
        def run(*args, **keywords):
            start = time.perf_counter()
            out = product(*args, **keywords)
            inside[0] += time.perf_counter() - start
            return out
        return run

    @timed
    def apply(p):
        shapes.append(operator._convolution.fft_shape)
        return operator.apply(p, compliance, copy=False)

    @timed
    def apply_window(field, box):
        out = operator.apply_window(field, box, compliance, copy=False)
        whole = box == (slice(None), slice(None))
        shapes.append(operator._convolution.fft_shape if whole else operator._windows[np.shape(field)].fft_shape)
        return out

    class Recorded(SurfaceStiffness):   # the preconditioner, recording the shape of each FFT pair it runs
        @timed
        def apply(self, field, copy=True):
            shapes.append(np.shape(field))
            return super().apply(field, copy)
    precondition = Recorded(grid)

    def solve():
        return solver.solve_normal(apply, heights, cell_area=grid.cell_area, load=exact.load,
                                   options=fw.SolverOptions(tolerance=tolerance, preconditioned=kind != "plain"),
                                   window=operator.window, apply_window=apply_window, precondition=precondition)

    # On a busy machine the speed changes from one second to the next: each repeat times the solve and
    # then replays its FFT pairs alone (as many, in the same order, over as long), and the best of each is kept.
    best, transforms, products, pairs = np.inf, np.inf, np.inf, {}
    with loop(kind):
        for _ in range(repeat):
            shapes.clear()
            inside[0] = 0.0
            start = time.perf_counter()
            solution = solve()
            best = min(best, time.perf_counter() - start)
            products = min(products, inside[0])
            transforms = min(transforms, replay(shapes, pairs))
    iterations = solution.iterations
    return (best / iterations, transforms / iterations, iterations, solution.pressure.max() / exact.max_pressure - 1,
            products / iterations)


@contextlib.contextmanager
def previous_pressure():
    """The stepper's warm start without the prediction: the previous step's pressure."""
    saved = simulation._Predictor.guess
    simulation._Predictor.guess = lambda self, time, fallback: fallback
    try:
        yield
    finally:
        simulation._Predictor.guess = saved


def pmma_ball(n, steps=50):
    times = np.concatenate([[0.0], np.geomspace(0.1, 1000.0, steps - 1)])
    return fw.Simulation(grid=fw.Grid(shape=(n, n), size=(1.2e-3, 1.2e-3)), material=materials.PMMA,
                         indenter=indenters.Sphere(radius=5e-3),
                         schedule=schedules.Static(load=loads.Step(20.0), times=times)).run()


def creeping_ball(n, steps=50):
    times = visco_indentation.output_times(steps)
    return fw.Simulation(grid=fw.Grid(shape=(n, n), size=(SIDE, SIDE)), material=visco_indentation.MATERIAL,
                         indenter=indenters.Sphere(radius=visco_indentation.RADIUS),
                         schedule=schedules.Static(load=loads.Step(visco_indentation.LOAD), times=times),
                         options={"tolerance": 1e-8}).run()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[512, 1024])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--tolerance", type=float, default=1e-10)
    parser.add_argument("--visco", type=int, default=256, help="grid of the creeping-ball case (0: skip part 2)")
    parser.add_argument("--loops", nargs="+", default=["fused", "plain", "numpy", "reference"],
                        choices=["fused", "plain", "numpy", "reference"])
    args = parser.parse_args()
    print(machine())
    compiled = _fused.numba_available()
    print(f"fused passes: {'compiled by numba' if compiled else 'numpy (numba not installed: pip install .[jit])'}; "
          f"Hertz, contact radius 0.15 L, tolerance {args.tolerance:g}, best of {args.repeat}")
    print(f"{'N':>5} {'grid':>9} {'loop':>10} {'iter':>5} {'ms/iter':>8} {'FFT ms/iter':>11} {'ratio':>6} "
          f"{'products':>9} {'ratio':>6} {'p0 err':>9}")
    for n in args.sizes:
        for periodic in (False, True):
            for kind in args.loops:
                if kind == "numpy" and not compiled:
                    continue
                per, transforms, iterations, error, products = hertz(n, periodic, args.tolerance, args.repeat, kind)
                print(f"{n:>5} {'periodic' if periodic else 'open':>9} {kind:>10} {iterations:>5} {per * 1e3:>8.2f} "
                      f"{transforms * 1e3:>11.2f} {per / transforms:>6.2f} {products * 1e3:>9.2f} "
                      f"{products / transforms:>6.2f} {error:>9.2e}", flush=True)
    if not args.visco:
        return
    print("viscoelastic steps, 50 log-spaced output times: mean iterations per step after the first")
    print(f"{'case':>34} {'predicted':>10} {'previous p':>11} {'s predicted':>12} {'s previous':>11}")
    for name, case, n in ((f"creeping ball (visco_indentation) {args.visco}^2", creeping_ball, args.visco),
                          ("PMMA ball, step load, 128^2", pmma_ball, 128)):
        case(n)   # FFT plans of every window the run meets, as both timed runs then find them
        start = time.perf_counter()
        predicted = case(n)
        middle = time.perf_counter()
        with previous_pressure():
            previous = case(n)
        end = time.perf_counter()
        print(f"{name:>34} {predicted.iterations[1:].mean():>10.1f} {previous.iterations[1:].mean():>11.1f} "
              f"{middle - start:>12.2f} {end - middle:>11.2f}", flush=True)


if __name__ == "__main__":
    main()
