"""Large grids: time and peak memory of an elastic solve on 2048^2 (open) and 4096^2 (periodic), and of
the subsurface stresses on 256^2 x 64 layers under a memory budget; the speed-up of FFT threads.

Each case runs in a process of its own, so that the peak resident size printed is that case's
(``ru_maxrss`` of the child). The elastic cases are the Hertz contact of ``bench/elastic_hertz.py``
(contact radius 0.15 of the side, tolerance 1e-8): the operator, the indenter's heights and the solve,
end to end. The stress case computes ``Result.stress`` of one step, whose kernel spectra (one per
depth) are cached while they fit in ``Result.stress_memory``: below that budget they are rebuilt at
every call.

    .venv/bin/python bench/scale.py [--cases open2048 periodic4096 stress256 stress256_budget threads1024]
"""
import argparse
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

YOUNG, POISSON, RADIUS, SIDE = 1e9, 0.3, 10e-3, 2e-3


def hertz(n, periodic):
    import framework as fw
    from framework import indenters, materials, reference, schedules
    contact_modulus = YOUNG / (1 - POISSON**2)
    exact = reference.HertzSphere.from_contact_radius(RADIUS, 0.15 * SIDE, contact_modulus)
    begin = time.perf_counter()
    grid = fw.Grid(shape=(n, n), size=(SIDE, SIDE), periodic=(periodic, periodic))
    sim = fw.Simulation(grid=grid, material=materials.Elastic(YOUNG, POISSON), indenter=indenters.Sphere(RADIUS),
                        schedule=schedules.Static(load=exact.load), options={"tolerance": 1e-8})
    result = sim.run()
    seconds = time.perf_counter() - begin
    peak = float(result.max_pressure[-1])
    return dict(seconds=seconds, iterations=int(sum(record.iterations for record in result.records)),
                p0_error=peak / exact.max_pressure - 1, cells=n * n)


def stress(n, layers, budget):
    import framework as fw
    from framework import indenters, materials, schedules
    grid = fw.Grid(shape=(n, n), size=(SIDE, SIDE), depth=0.5 * SIDE, layers=layers)
    sim = fw.Simulation(grid=grid, material=materials.Elastic(YOUNG, POISSON), indenter=indenters.Sphere(RADIUS),
                        schedule=schedules.Static(load=[5.0, 10.0]))
    result = sim.run()
    result.stress_memory = budget
    timings = []
    for step in range(2):                   # the second step finds the cached spectra (if they fit)
        begin = time.perf_counter()
        field = result.stress(step=step)
        timings.append(time.perf_counter() - begin)
    return dict(first=timings[0], second=timings[1], field_bytes=field.nbytes, budget=budget)


def threads(n):
    """The same open Hertz solve with one FFT thread and with every core (``FRAMEWORK_FFT_THREADS=auto``)."""
    from framework import fft
    out = {}
    for name, count in (("one", 1), ("auto", fft.available_cores())):
        fft.set_threads(count)
        hertz(n, False)                      # plans for this thread count
        out[name] = min(hertz(n, False)["seconds"] for _ in range(2))
    out["cores"] = fft.available_cores()
    return out


CASES = {
    "open2048": lambda: hertz(2048, False),
    "periodic4096": lambda: hertz(4096, True),
    "stress256": lambda: stress(256, 64, 2 * 1024**3),
    "stress256_budget": lambda: stress(256, 64, 64 * 1024**2),
    "threads1024": lambda: threads(1024),
}


def child(name):
    import resource
    out = CASES[name]()
    out["peak_gib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    print(json.dumps(out))


def measure(name):
    """Run one case in a process of its own; its figures as a dict (``peak_gib`` its peak memory)."""
    run = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", name], capture_output=True, text=True)
    if run.returncode:
        raise RuntimeError(run.stderr[-2000:])
    return json.loads(run.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.child)
        return
    from elastic_hertz import machine
    print(machine())
    for name in args.cases:
        try:
            out = measure(name)
        except RuntimeError as error:
            print(f"{name}: failed\n{error}")
            continue
        if "cores" in out:
            print(f"{name:>17}: 1024^2 open solve end to end, 1 FFT thread {out['one']:.2f} s, {out['cores']} threads "
                  f"(auto) {out['auto']:.2f} s: speed-up {out['one'] / out['auto']:.2f}")
        elif "iterations" in out:
            print(f"{name:>17}: {out['cells'] / 1e6:.1f} M cells, end to end {out['seconds']:.1f} s, "
                  f"{out['iterations']} iterations, p0 error {out['p0_error']:+.1e}, peak memory {out['peak_gib']:.2f} GiB")
        else:
            print(f"{name:>17}: 256^2 x 64 layers ({out['field_bytes'] / 2**20:.0f} MiB of stress), budget "
                  f"{out['budget'] / 2**20:.0f} MiB: first step {out['first']:.1f} s, second {out['second']:.1f} s, "
                  f"peak memory {out['peak_gib']:.2f} GiB")


if __name__ == "__main__":
    main()
