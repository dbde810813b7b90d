"""Command line.

    python -m framework run SCENARIO.toml --out DIR     run a scenario file
        [--animate FIELD]                                and animate a field over the steps (DIR/FIELD.gif)
    python -m framework demo [--out DIR]                 run the built-in default scenario
    python -m framework check SCENARIO.toml              check a scenario file without running it
    python -m framework sweep SWEEP.toml [--scheduler ADDRESS] [--folder DIR]
                                                         run a parametric sweep on Dask

The numerical core never imports ``viz``; this entry point does, when a
scenario asks for VTU files or pictures, and to check the names of its
pictures and plots against viz's own tables.

Every bad input (scenario file, argument, output folder) is one line
``error: ...`` with exit code 2, found before anything is written: ``check``
validates everything ``run`` needs. Steps are numbered from 0 everywhere, as in
the file names (``surface_0000.vtu``).
"""
import argparse
import csv
import os
import re
import sys
import time

from . import io
from .errors import FrameworkError
from .result import SERIES_UNITS
from .scenario import ScenarioError, picture_file


def write_summary(result, path):
    """``summary.csv``: one row per finished step, SI units in the header."""
    table = result.summary()
    temporary = io.temporary(path)
    with open(temporary, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow([f"{key} [{SERIES_UNITS[key]}]" for key in table])
        writer.writerows(zip(*table.values()))
    os.replace(temporary, path)


def print_table(result, rows=12):
    """The per-step figures a user looks at first (first and last steps of long runs).

    The contact's size is its radius, or its half-width on a line contact; a
    rolling run shows its friction coefficient where others show the tilt; a
    run with inhomogeneities adds the coupling iterations of each step.
    """
    coupled = bool(getattr(result, "inclusions", None))
    line = result.line_contact
    rolling = getattr(result.schedule, "velocity", None) is not None
    size, size_name = (result.half_width, "half-width m") if line else (result.contact_radius, "radius m")
    last, last_name = (result.friction_coefficient, "friction") if rolling else (result.tilt[:, 0], "tilt rad")
    print(f"{'step':>5} {'time s':>10} {'load N':>10} {'approach m':>12} {size_name:>12} {'p max Pa':>11} "
          f"{last_name:>10} {'iter':>5}" + (f" {'coupl':>5}" if coupled else ""))
    steps = range(len(result))
    if len(result) > rows:
        steps = list(range(rows // 2)) + [None] + list(range(len(result) - rows // 2, len(result)))
    for k in steps:
        if k is None:
            print(f"{'...':>5}")
            continue
        print(f"{k:5d} {result.times[k]:10.4g} {result.load[k]:10.4g} {result.approach[k]:12.5g} "
              f"{size[k]:12.4g} {result.max_pressure[k]:11.4g} {last[k]:10.3g} {result.iterations[k]:5d}"
              + (f" {result.couplings[k]:5d}" if coupled else ""))


def _viz():
    try:
        import viz
    except ImportError as exc:
        raise FrameworkError(f"this scenario writes VTU files or pictures, which need the viz extra: "
                             f"pip install 'viscocontact[viz]' ({exc})") from exc
    return viz


def _has_stresses(grid):
    """Subsurface stresses exist on a grid with layers."""
    return grid.layers > 0


def animation_kind(field, grid):
    """The picture kind of ``--animate FIELD``: ``map`` for a surface field, ``slice`` for a stress; or FrameworkError."""
    _viz()
    from viz.render import KINDS
    if field in KINDS["map"]:
        return "map"
    if field not in KINDS["slice"]:
        raise FrameworkError(f"--animate: expected a surface field {list(KINDS['map'])} or a stress "
                             f"{list(KINDS['slice'])}, got {field!r}")
    if not _has_stresses(grid):
        raise FrameworkError(f"--animate {field}: a stress needs [grid] layers and depth, got layers = {grid.layers}")
    return "slice"


def check_output(scenario):
    """Check the names in ``[output]`` against what :mod:`viz` draws, before anything runs.

    The names belong to viz (its field, kind and series tables); ``framework``
    never imports viz, this entry point does, so the lists are not copied.
    """
    output, grid = scenario.output, scenario.simulation.grid
    if not (output.pictures or output.history):
        return
    _viz()  # a clear message if it is missing
    from viz.plot import QUANTITIES as series
    from viz.render import KINDS as kinds
    for i, picture in enumerate(output.pictures):
        kind, field, where = picture.get("kind", "map"), picture["field"], f"output.pictures[{i}]"
        if kind not in kinds:
            raise ScenarioError(f"{scenario.source}: {where}.kind: expected one of {sorted(kinds)}, got {kind!r}")
        if field not in kinds[kind]:
            raise ScenarioError(f"{scenario.source}: {where}.field: expected one of {list(kinds[kind])} for "
                                f"kind {kind!r}, got {field!r}")
        if kind == "slice" and not _has_stresses(grid):
            raise ScenarioError(f"{scenario.source}: {where}: a slice shows subsurface stresses, which need "
                                f"[grid] layers and depth, got layers = {grid.layers}")
    unknown = [name for name in output.history if name not in series]
    if unknown:
        raise ScenarioError(f"{scenario.source}: output.history: unknown series {unknown}; expected some of "
                            f"{list(series)}")


def prepare_folder(out, source):
    """Create the output folder (or check an existing one is a writable folder) and mark the run incomplete."""
    if os.path.exists(out) and not os.path.isdir(out):
        raise FrameworkError(f"--out {out!r} is a file; expected a folder for the results")
    try:
        os.makedirs(out, exist_ok=True)
        if not os.access(out, os.W_OK | os.X_OK):
            raise PermissionError(13, "Permission denied")
        marker = os.path.join(out, "INCOMPLETE")
        with open(marker, "w") as f:
            f.write(f"run of {source} in progress or failed; the files here hold the finished steps only\n")
    except OSError as exc:
        raise FrameworkError(f"--out {out!r}: cannot write the results there ({exc.strerror or exc})") from exc
    return marker


def run_scenario(scenario, out, *, progress=True, resume=False, every=10, animate=None):
    """Run a parsed scenario, writing as each step finishes; returns (result, files written, seconds).

    ``checkpoint.h5`` is rewritten every ``every`` steps; at the end ``result.h5``
    replaces it. ``resume`` continues from ``checkpoint.h5``. ``animate``: a
    field to animate over the steps into ``out/FIELD.gif`` (its pressure-map
    or slice frames share one colour range, see :func:`viz.animate`).
    """
    output = scenario.output
    viz = _viz() if output.vtu or output.pictures or output.history or animate else None
    check_output(scenario)
    kind = animation_kind(animate, scenario.simulation.grid) if animate else None
    checkpoint = os.path.join(out, "checkpoint.h5")
    if resume and not os.path.isfile(checkpoint):
        raise FrameworkError(f"--resume: no checkpoint to resume in {out!r} (expected {checkpoint})")
    marker = prepare_folder(out, scenario.source)
    summary = os.path.join(out, "summary.csv")
    total = len(scenario.simulation.output_times)

    def resolve(steps):
        return None if steps == "all" else {step % total for step in steps}

    exporters = []
    if output.vtu:
        exporters.append((viz.Exporter(out, volume=False), resolve(output.steps)))
        if _has_stresses(scenario.simulation.grid):
            exporters.append((viz.Exporter(out, surface=False, indenter=False, volume=True, single=output.single),
                              resolve(output.volume_steps)))

    def on_step(result, record):
        for exporter, wanted in exporters:
            if wanted is None or record.index in wanted:
                exporter.write(result, record.index)
        write_summary(result, summary)

    start = time.perf_counter()
    result = scenario.simulation.run(progress=progress, callback=on_step, checkpoint=checkpoint, every=every,
                                     resume=checkpoint if resume else None)
    elapsed = time.perf_counter() - start
    if resume:  # the steps finished before the interruption
        for exporter, wanted in exporters:
            for record in result.records:
                if (wanted is None or record.index in wanted) and record.index not in exporter.steps:
                    exporter.write(result, record.index)
        write_summary(result, summary)
    written = [summary, os.path.join(out, "result.h5")] + [path for exporter, _ in exporters for path in exporter.files]
    result.save(written[1])
    os.remove(checkpoint)
    for picture in output.pictures:
        written.append(os.path.join(out, picture_file(picture)))
        viz.render(result, written[-1], field=picture["field"], step=picture.get("step", -1),
                   kind=picture.get("kind", "map"))
    if output.history:
        written.append(os.path.join(out, "history.png"))
        viz.plot_history(result, written[-1], list(output.history))
    if animate:
        written.append(os.path.join(out, f"{animate}.gif"))
        viz.animate(result, written[-1], animate, kind=kind)
    os.remove(marker)
    return result, sorted(set(written)), elapsed


def describe_files(paths):
    """Lines ``count  kind  size`` of files grouped by kind: ``surface_NNNN.vtu``, ``*.png``, ``result.h5``."""
    groups = {}
    for path in paths:
        name = os.path.basename(path)
        kind = re.sub(r"_\d{4}\.vtu$", "_NNNN.vtu", name)
        if kind == name and name.endswith((".png", ".pvd")):
            kind = "*" + os.path.splitext(name)[1]
        count, size = groups.get(kind, (0, 0))
        groups[kind] = (count + 1, size + os.path.getsize(path))
    return [f"{count:5d}  {kind:<18} {_size(size)}" for kind, (count, size) in sorted(groups.items())]


def _size(size):
    return f"{size / 1e6:6.1f} MB" if size >= 1e5 else f"{size / 1e3:6.1f} kB"


class _Parser(argparse.ArgumentParser):
    """argparse whose usage errors are one line ``error: ...`` (exit code 2), like every other bad input."""

    def error(self, message):
        self.exit(2, f"error: {message} (see {self.prog} -h)\n")


def _integer(minimum):
    """An argparse type: an integer >= ``minimum``."""
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {text!r}")
        return value
    return parse


def main(argv=None):
    """The command line (see the module docstring); returns the exit code."""
    try:
        return _main(argv)
    except BrokenPipeError:  # the reader went away (``... | head``): stop quietly, as a pipeline expects
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


def _main(argv):
    from . import scenario as scenarios
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["sweep"]:
        from .sweep import main as sweep_main
        return sweep_main(argv[1:])
    parser = _Parser(prog="python -m framework", description=__doc__,
                     formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", required=True)
    run = commands.add_parser("run", help="run a scenario file")
    run.add_argument("scenario", help="scenario file (TOML)")
    run.add_argument("--out", default="out", help="output folder (default: out)")
    demo = commands.add_parser("demo", help="run the built-in default scenario")
    demo.add_argument("--out", default="out", help="output folder (default: out)")
    check = commands.add_parser("check", help="check a scenario file without running it")
    check.add_argument("scenario")
    for command in (run, demo, check):
        command.add_argument("--cells", type=_integer(3), default=None,
                             help="replace the grid by CELLS x CELLS cells of the same size (a quick look)")
    for command in (run, demo):
        command.add_argument("--quiet", action="store_true", help="no progress lines")
    run.add_argument("--resume", action="store_true", help="continue a killed run from DIR/checkpoint.h5")
    run.add_argument("--every", type=_integer(1), default=10, help="steps between checkpoints (default: 10)")
    for command in (run, demo):
        command.add_argument("--animate", metavar="FIELD", default=None,
                             help="also write DIR/FIELD.gif: FIELD (pressure, gap, displacement, contact: a map; "
                                  "von_mises, stress_xx, ...: a slice x2 = 0) over the steps")
    commands.add_parser("sweep", help="run a parametric sweep on Dask (python -m framework sweep -h)")
    args = parser.parse_args(argv)
    try:
        path = scenarios.demo_path() if args.command == "demo" else args.scenario
        scenario = scenarios.read(path, cells=getattr(args, "cells", None))
        if args.command == "check":   # run_scenario checks the same before it writes anything
            check_output(scenario)
            print(f"{path}: ok ({len(scenario.simulation.output_times)} steps on a "
                  f"{scenario.simulation.grid.shape} grid)")
            return 0
        result, written, elapsed = run_scenario(scenario, args.out, progress=not args.quiet,
                                                resume=getattr(args, "resume", False),
                                                every=getattr(args, "every", 10), animate=args.animate)
    except FrameworkError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print_table(result)
    total = sum(os.path.getsize(path) for path in written)
    print(f"{len(result)} steps (0 to {len(result) - 1}) in {elapsed:.1f} s; wrote {len(written)} files, "
          f"{_size(total).strip()}, to {args.out}{os.sep}:")
    for line in describe_files(written):
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
