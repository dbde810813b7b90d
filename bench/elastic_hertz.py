"""Hertz solve on N x N: this project against Tamaas' PolonskyKeerRey (DC-FFT), same run.

Prints the machine, then per N the solve time (best of ``--repeat``), the
iterations and the peak-pressure and contact-radius errors against Hertz. The
setup (kernel spectrum, FFT plans) is timed apart for both codes; the
solve times compare like with like (operator built, solver started cold).

    .venv/bin/python bench/elastic_hertz.py [--sizes 256 512] [--tolerance 1e-10]
"""
import argparse
import os
import platform
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import framework as fw  # noqa: E402
from framework import fft, indenters, materials, reference  # noqa: E402
from framework.operators import SurfaceCompliance, SurfaceStiffness  # noqa: E402
from framework.solver import SolverOptions, solve_normal  # noqa: E402

YOUNG, POISSON, RADIUS, SIDE = 1e9, 0.3, 10e-3, 2e-3


def machine():
    cpu = platform.processor() or "?"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return (f"{platform.node()} | {cpu} | {os.cpu_count()} cores | Python {platform.python_version()} | "
            f"numpy {np.__version__} | FFT backend {fft.get_backend()} with {fft.THREADS} threads | "
            f"FFTW wisdom {wisdom()} | load average {os.getloadavg()[0]:.2f}")


def wisdom():
    """Where FFTW's wisdom comes from (a process's first plans are measured without it): the file and its size."""
    path = fft.WISDOM.path
    if fft.get_backend() != "pyfftw" or path is None:
        return "off"
    return f"{path} ({os.path.getsize(path)} bytes)" if os.path.isfile(path) else f"{path} (none yet)"


def errors_against_hertz(pressure, cell_area, exact):
    radius = np.sqrt(np.count_nonzero(pressure > 0) * cell_area / np.pi)
    return pressure.max() / exact.max_pressure - 1, radius / exact.contact_radius - 1


def ours(n, load, tolerance, repeat, periodic=False, preconditioned=True):
    """Our solve as :class:`framework.Simulation` runs it (windowed products, preconditioned unless told not)."""
    grid = fw.Grid(shape=(n, n), size=(SIDE, SIDE), periodic=(periodic, periodic))
    material = materials.Elastic(young=YOUNG, poisson=POISSON)
    start = time.perf_counter()
    operator = SurfaceCompliance(grid)
    stiffness = SurfaceStiffness(grid)
    heights = indenters.Sphere(radius=RADIUS).on_grid(grid)
    setup = time.perf_counter() - start
    compliance = 1 / material.contact_modulus
    options = SolverOptions(tolerance=tolerance, preconditioned=preconditioned)
    best = np.inf
    for _ in range(repeat):
        start = time.perf_counter()
        solution = solve_normal(lambda p: operator.apply(p, compliance, copy=False), heights,
                                cell_area=grid.cell_area, load=load, options=options, window=operator.window,
                                apply_window=lambda f, box: operator.apply_window(f, box, compliance, copy=False),
                                precondition=stiffness)
        best = min(best, time.perf_counter() - start)
    return dict(time=best, setup=setup, iterations=solution.iterations, pressure=solution.pressure,
                cell_area=grid.cell_area)


def theirs(n, load, tolerance, repeat, method="dcfft"):
    import _tamaas
    best, out = np.inf, None
    for _ in range(repeat):
        out = _tamaas.hertz(n, SIDE, RADIUS, load, YOUNG, POISSON, tolerance, method=method)
        best = min(best, out["time"])
    out["time"] = best
    out["cell_area"] = (SIDE / n) ** 2
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[256, 512])
    parser.add_argument("--tolerance", type=float, default=1e-10)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--threads", type=int, default=fft.THREADS, help="FFT threads of this project")
    args = parser.parse_args()
    fft.set_threads(args.threads)
    print(machine())
    contact_modulus = YOUNG / (1 - POISSON**2)
    exact = reference.HertzSphere.from_contact_radius(RADIUS, 0.15 * SIDE, contact_modulus)
    print(f"Hertz: R = {RADIUS} m, a = 0.15 L = {exact.contact_radius:.3g} m, W = {exact.load:.4g} N, "
          f"tolerance {args.tolerance:g}")
    print(f"{'N':>5} {'code':>8} {'solve s':>9} {'setup s':>8} {'iter':>5} {'p0 err':>10} {'a err':>10} {'time ratio':>10}")
    for n in args.sizes:
        rows = {"this": ours(n, exact.load, args.tolerance, args.repeat)}
        try:
            rows["tamaas"] = theirs(n, exact.load, args.tolerance, args.repeat)
        except ImportError:
            print("  (tamaas not installed: pip install tamaas)")
        for name, row in rows.items():
            p_err, a_err = errors_against_hertz(row["pressure"], row["cell_area"], exact)
            ratio = row["time"] / rows["tamaas"]["time"] if "tamaas" in rows else float("nan")
            setup = row.get("setup", float("nan"))
            print(f"{n:>5} {name:>8} {row['time']:>9.3f} {setup:>8.3f} {str(row['iterations']):>5} "
                  f"{p_err:>10.2e} {a_err:>10.2e} {ratio:>10.2f}")


if __name__ == "__main__":
    main()
