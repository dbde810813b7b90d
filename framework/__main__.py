"""Command line.

    python -m framework run SCENARIO.toml --out DIR     run a scenario file
        [--animate FIELD]                                and animate a field over the steps (DIR/FIELD.gif)
    python -m framework demo [--out DIR]                 run the built-in default scenario
    python -m framework check FILE.toml                  check a scenario or a sweep file without running it
    python -m framework sweep SWEEP.toml [--check] [--scheduler ADDRESS] [--folder DIR]
                                                         run a parametric sweep on Dask

The numerical core never imports ``viz``; the command line does, when a
scenario asks for VTU files or pictures, and to check the names of its
pictures and plots against viz's own tables (:mod:`framework.scenario_run`).

Every bad input (scenario file, argument, output folder) is one line
``error: ...`` with exit code 2, found before anything is written: ``check``
validates everything ``run`` needs: the file, the packages its outputs need
(a missing one is named with the command that installs it), and the memory
the run will take, refused above this machine's (it prints the estimate of
memory, time and file size, and warns above half the memory), and the
resolution: one ``warning:`` line for each body, contact or rolling wake the
run would warn of (:mod:`framework.resolution`; contact and wakes estimated
from Hertz where the indenter and load allow, else not told). A sweep file
is checked point by point. Steps are numbered from 0 everywhere, as in the
file names (``surface_0000.vtu``).
"""
import argparse
import os
import sys
import warnings

from . import resolution, resources
from ._arguments import Parser, integer
from .errors import FrameworkError, ResolutionWarning
from .scenario import check_path
from .scenario_run import describe_files, preflight, print_table, run_scenario, size_text


def main(argv=None):
    """The command line (see the module docstring); returns the exit code."""
    try:
        return _main(argv)
    except BrokenPipeError:  # the reader went away (``... | head``): stop quietly, as a pipeline expects
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


def parser():
    """The parser of ``python -m framework`` (``sweep`` has its own: :func:`framework.sweep.command.parser`)."""
    top = Parser(prog="python -m framework", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = top.add_subparsers(dest="command", required=True)
    run = commands.add_parser("run", help="run a scenario file")
    run.add_argument("scenario", help="scenario file (TOML)")
    run.add_argument("--out", default="out", help="output folder (default: out)")
    demo = commands.add_parser("demo", help="run the built-in default scenario")
    demo.add_argument("--out", default="out", help="output folder (default: out)")
    check = commands.add_parser("check", help="check a scenario or a sweep file without running it, and estimate "
                                              "the memory, time and files of the run")
    check.add_argument("scenario", metavar="FILE", help="scenario file or sweep file (TOML)")
    for command in (run, demo, check):
        command.add_argument("--cells", type=integer(3), default=None,
                             help="replace the grid by CELLS x CELLS cells of the same size (a quick look)")
    for command in (run, demo):
        command.add_argument("--quiet", action="store_true", help="no progress lines")
    run.add_argument("--resume", action="store_true", help="continue a killed run from DIR/checkpoint.h5")
    run.add_argument("--every", type=integer(1), default=10, help="steps between checkpoints (default: 10)")
    for command in (run, demo):
        command.add_argument("--animate", metavar="FIELD", default=None,
                             help="also write DIR/FIELD.gif: FIELD (pressure, gap, displacement, contact: a map; "
                                  "von_mises, stress_xx, ...: a slice x2 = 0) over the steps")
    commands.add_parser("sweep", help="run a parametric sweep on Dask (python -m framework sweep -h)")
    return top


def check(path, cells=None):
    """``python -m framework check FILE``: a scenario file (its run's needs and estimate) or a sweep file."""
    from . import scenario as scenarios
    from .sweep import command as sweeps, is_sweep
    if is_sweep(scenarios.load_tables(path)):
        if cells is not None:
            raise FrameworkError(f"--cells: replaces the grid of a scenario file; {path} is a sweep file, whose "
                                 f"points are checked as they will run")
        with warnings.catch_warnings(record=True) as caught:   # each point's body warnings, one line each
            warnings.simplefilter("always", ResolutionWarning)
            _, _, _, lines = sweeps.check(path)
        told = []
        for caught_warning in caught:
            if not issubclass(caught_warning.category, ResolutionWarning):
                warnings.warn_explicit(caught_warning.message, caught_warning.category, caught_warning.filename,
                                       caught_warning.lineno)
            elif str(caught_warning.message) not in told:
                told.append(str(caught_warning.message))
        lines = list(lines) + [f"warning: {path}: {message}" for message in told]
    else:
        memory = resources.machine_memory()
        with warnings.catch_warnings():   # told below, one line each, with the estimated ones
            warnings.simplefilter("ignore", ResolutionWarning)
            scenario = scenarios.read(path, cells=cells, memory=memory)
        estimate, warning = preflight(scenario, memory=memory)
        simulation = scenario.simulation
        lines = [f"{path}: ok ({len(simulation.output_times)} steps on a {simulation.grid.shape} grid)",
                 f"estimate: {estimate.describe(memory)}"]
        if warning:
            lines.append(f"warning: {path}: {warning}")
        lines += [f"warning: {path}: {message}" for message in resolution.preview_messages(simulation)]
    for line in lines:
        print(line, file=sys.stderr if line.startswith("warning:") else sys.stdout)
    return 0


def _refuse_sweep(path):
    """A sweep file given to ``run``: say which command runs it."""
    from . import scenario as scenarios
    from .sweep import is_sweep
    if os.path.isfile(path) and is_sweep(scenarios.load_tables(path)):
        raise FrameworkError(f"{path}: a sweep file (scenario, parameters or points), not a scenario: run it with "
                             f"python -m framework sweep {path} (check it with python -m framework check {path})")


def _main(argv):
    from . import scenario as scenarios
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["sweep"]:
        from .sweep import main as sweep_main
        return sweep_main(argv[1:])
    args = parser().parse_args(argv)
    try:
        if args.command == "check":
            return check(args.scenario, args.cells)
        check_path(args.out, name="--out")
        path = scenarios.demo_path() if args.command == "demo" else args.scenario
        _refuse_sweep(path)
        scenario = scenarios.read(path, cells=args.cells, memory=resources.machine_memory())
        result, written, elapsed = run_scenario(scenario, args.out, progress=not args.quiet,
                                                resume=getattr(args, "resume", False),
                                                every=getattr(args, "every", 10), animate=args.animate)
    except FrameworkError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print_table(result)
    total = sum(os.path.getsize(path) for path in written)
    print(f"{len(result)} steps (0 to {len(result) - 1}) in {elapsed:.1f} s; wrote {len(written)} files, "
          f"{size_text(total).strip()}, to {args.out}{os.sep}:")
    for line in describe_files(written):
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
