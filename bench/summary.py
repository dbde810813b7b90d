"""One table of the speed figures of this project against its targets (and Tamaas where it has a peer).

Runs, in this order, and prints the machine and then one row per figure:

1. Hertz solves (contact radius 0.15 of the side): open 1024^2 at 1e-10 against Tamaas' DC-FFT; periodic
   1024^2 at 1e-8 against Tamaas' periodic solve; end to end (the operator's kernel and the heights, built
   once, plus the solve, the best of three) open and periodic at 256^2 and 1024^2, 1e-8, against Tamaas'
   periodic solve (its solve call alone);
2. the viscoelastic creep of ``visco_indentation.py`` (256^2, 50 steps, 1e-8) against Tamaas'
   ``MaxwellViscoelastic``, and the mean iterations per step after the first of it and of a PMMA ball
   under a step load (128^2, 50 log-spaced times);
3. the cost of a contact iteration against the FFT pairs it runs (replayed alone, in the solve's order, in
   the same run), open and periodic, 512^2 and 1024^2 (``contact_loop.py``);
4. large grids and threads (``scale.py``, each case in a process of its own for its peak memory).

Without Tamaas (``pip install tamaas``) the peer columns stay empty. About 12 minutes on 2 cores.

    .venv/bin/python bench/summary.py
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from framework import reference  # noqa: E402

import contact_loop  # noqa: E402
import elastic_hertz  # noqa: E402
import scale  # noqa: E402
import visco_indentation  # noqa: E402
from elastic_hertz import POISSON, RADIUS, SIDE, YOUNG, machine  # noqa: E402

EXACT = reference.HertzSphere.from_contact_radius(RADIUS, 0.15 * SIDE, YOUNG / (1 - POISSON**2))


def ours(n, periodic, tolerance):
    """Hertz (``elastic_hertz.ours``): ``(setup + solve [s], solve [s], iterations)``, the solve the best of three."""
    row = elastic_hertz.ours(n, EXACT.load, tolerance, 3, periodic=periodic)
    return row["setup"] + row["time"], row["time"], row["iterations"]


def tamaas(n, method, tolerance):
    """Tamaas' solve time [s] (``elastic_hertz.theirs``), None without Tamaas."""
    try:
        return elastic_hertz.theirs(n, EXACT.load, tolerance, 1, method=method)["time"]
    except ImportError:
        return None


def main():
    print(machine())
    ours(256, False, 1e-8)          # compiles the fused passes (numba) once, outside every timing
    rows = []

    def row(figure, value, peer=None, goal="", unit="s"):
        ratio = "" if peer is None else f"{value / peer:.2f}"
        peer = "" if peer is None else f"{peer:.3g} {unit}"
        rows.append((figure, f"{value:.3g} {unit}" if unit else f"{value:.3g}", peer, ratio, goal))
        print(f"  {figure}: {rows[-1][1]} {peer} {ratio}", flush=True)

    # 1. elastic
    total, solve, iterations = ours(1024, False, 1e-10)
    row(f"Hertz open 1024^2, 1e-10, solve ({iterations} it.) vs Tamaas DC-FFT", solve, tamaas(1024, "dcfft", 1e-10))
    total, solve, iterations = ours(1024, True, 1e-8)
    row(f"Hertz periodic 1024^2, 1e-8, solve ({iterations} it.) vs Tamaas periodic", solve,
        tamaas(1024, "periodic", 1e-8))
    for n in (256, 1024):
        peer = tamaas(n, "periodic", 1e-8)
        row(f"Hertz open {n}^2, 1e-8, end to end vs Tamaas periodic", ours(n, False, 1e-8)[0], peer, "<= 0.30")
        row(f"Hertz periodic {n}^2, 1e-8, end to end vs Tamaas periodic", ours(n, True, 1e-8)[0], peer, "<= 0.25")
    # 2. viscoelastic
    mine = visco_indentation.ours(256, 50, 1e-8)
    try:
        peer = visco_indentation.theirs(256, 50, 1e-8)["time"]
    except ImportError:
        peer = None
    row("creeping ball 256^2, 50 steps, vs Tamaas MaxwellViscoelastic", mine["time"], peer, "<= 0.25")
    for name, case, n in (("creeping ball 256^2", contact_loop.creeping_ball, 256),
                          ("PMMA ball 128^2, step load", contact_loop.pmma_ball, 128)):
        row(f"{name}: iterations per step after the first", float(case(n).iterations[1:].mean()), goal="<= 12",
            unit="")
    # 3. contact iteration against its FFT pairs
    for n in (512, 1024):
        for periodic in (False, True):
            per, transforms = contact_loop.hertz(n, periodic, 1e-10, 3, "fused")[:2]
            row(f"iteration / its FFT pairs, {'periodic' if periodic else 'open'} {n}^2 (ms)", per * 1e3,
                transforms * 1e3, "<= 1.3", unit="ms")
    # 4. scale and threads
    for name, label in (("open2048", "Hertz open 2048^2, end to end"), ("periodic4096", "Hertz periodic 4096^2, end to end")):
        out = scale.measure(name)
        row(f"{label} ({out['iterations']} it.)", out["seconds"])
        row(f"{label}: peak memory", out["peak_gib"], goal="< 3 GB" if name == "open2048" else "", unit="GiB")
    out = scale.measure("stress256")
    row("stresses 256^2 x 64 layers: the first step (kernels built)", out["first"])
    row("stresses 256^2 x 64 layers: peak memory (2 GiB kernel budget)", out["peak_gib"], unit="GiB")
    out = scale.measure("stress256_budget")
    row("stresses 256^2 x 64 layers: peak memory (64 MiB budget)", out["peak_gib"], unit="GiB")
    out = scale.measure("threads1024")
    row(f"Hertz open 1024^2 end to end, {out['cores']} FFT threads (auto) vs 1", out["auto"], out["one"], unit="s")

    width = max(len(r[0]) for r in rows)
    print()
    print(machine())
    print(f"{'figure':<{width}}  {'this project':>13}  {'peer / other':>13}  {'ratio':>6}  {'goal':>7}")
    for figure, value, peer, ratio, goal in rows:
        print(f"{figure:<{width}}  {value:>13}  {peer:>13}  {ratio:>6}  {goal:>7}")


if __name__ == "__main__":
    main()
