"""``python -m framework sweep SWEEP.toml [--check] [--scheduler ADDRESS] [--folder DIR] [--quiet]``.

Every point is parsed before any cluster starts (:func:`check_points`), so a
misspelt key or a bad value is one ``error:`` line, not a failed cluster job;
``--check`` stops there (``python -m framework check SWEEP.toml`` does the
same).
"""
import os
import sys
import time

from .. import resources
from .._arguments import Parser
from ..errors import FrameworkError, ParameterError
from ..scenario import check_path
from .cluster import DEFAULT_FOLDER, import_distributed, sweep
from .reader import check_points, read_sweep
from .table import TABLE_FILE, count, format_table

PROG = "python -m framework sweep"


def check(path, folder=None, *, local=True):
    """Check a sweep file, every point and the packages a sweep needs, before anything runs.

    ``folder`` replaces the file's own (``--folder``). With ``local`` (no
    scheduler: the points run on this machine) a point that needs more than
    this machine's memory is refused.

    Returns
    -------
    tuple
        ``(builder, parameters, folder, lines)``: what :func:`sweep` takes, and
        the lines ``check`` prints (the first ``PATH: ok (...)``, then the
        estimate, then any warning).

    Raises
    ------
    FrameworkError
        One line: the file, the first refused point, a point too large for this
        machine, or the missing cluster extra.
    """
    available = resources.machine_memory() if local else None
    builder, parameters, own = read_sweep(path)
    scenarios = check_points(path, builder, parameters, memory=available)
    import_distributed()
    folder = folder or own or DEFAULT_FOLDER
    estimates = [resources.for_simulation(scenario.simulation) for scenario in scenarios]
    largest = max(range(len(estimates)), key=lambda k: estimates[k].memory)
    try:
        warning = resources.check_memory(estimates[largest], available)
    except ParameterError as exc:
        raise ParameterError(f"{path}: point {largest}: {exc}") from exc
    seconds = sum(estimate.seconds for estimate in estimates)
    disk = sum(estimate.disk for estimate in estimates)
    machine = "" if available is None else f" (this machine: {resources.size(available)})"
    lines = [f"{path}: ok ({len(scenarios)} points of {builder.source}, into {folder}{os.sep})",
             f"estimate: each point needs up to about {resources.size(estimates[largest].memory)} of memory"
             f"{machine}; {resources.duration(seconds)} on one core in all, {resources.size(disk)} of files"]
    if warning:
        lines.append(f"warning: point {largest}: {warning}")
    return builder, parameters, folder, lines


def parser():
    """The argument parser of ``python -m framework sweep``."""
    command = Parser(prog=PROG, description="run a parametric sweep (a sweep file) on Dask distributed; every "
                                            "point is checked before any cluster starts")
    command.add_argument("sweep_file", metavar="SWEEP.toml",
                         help="sweep file (TOML): scenario, [parameters] or [[points]], folder")
    command.add_argument("--check", action="store_true",
                         help="check the file and every point, print the estimate, run nothing")
    command.add_argument("--scheduler", default=None,
                         help="address of a running Dask scheduler (default: a local cluster on this machine)")
    command.add_argument("--folder", default=None,
                         help=f"output folder (default: the file's 'folder', else ./{DEFAULT_FOLDER})")
    command.add_argument("--quiet", action="store_true", help="no line per finished point")
    return command


def main(argv=None):
    """``python -m framework sweep SWEEP.toml [--check] [--scheduler ADDRESS] [--folder DIR] [--quiet]``.

    ``argv`` holds the arguments after ``sweep``. Returns the exit code: 0 when
    every point is done, skipped or recomputed, 1 when some failed (the table
    says why), 2 for a bad sweep file, a refused point or a missing package
    (one ``error: ...`` line on stderr). A usage error (no file, an unknown
    option) is one ``error:`` line too, with the hint ``(see ... -h)``.
    """
    args = parser().parse_args(sys.argv[1:] if argv is None else argv)
    try:
        if args.folder is not None:
            check_path(args.folder, name="--folder")
        builder, parameters, folder, lines = check(args.sweep_file, args.folder, local=args.scheduler is None)
        for line in lines if args.check else lines[2:]:  # a run prints its warnings only
            print(line, file=sys.stderr if line.startswith("warning:") else sys.stdout)
        if args.check:
            return 0
        start = time.perf_counter()
        rows = sweep(builder, parameters, client=args.scheduler, folder=folder, progress=not args.quiet)
    except FrameworkError as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    elapsed = time.perf_counter() - start
    counts = count(rows)
    print(format_table(rows))
    recomputed = f"{counts['recomputed']} recomputed (their files were damaged), " if counts["recomputed"] else ""
    print(f"{len(rows)} points in {elapsed:.1f} s: {counts['done']} done, {counts['skipped']} skipped, "
          f"{recomputed}{counts['failed']} failed; table: {os.path.join(folder, TABLE_FILE)}")
    return 1 if counts["failed"] else 0
