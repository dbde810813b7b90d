"""A scenario file's run as the command line makes it: checked first, then run, writing its files as it goes.

:func:`preflight` is everything ``check`` verifies beyond the file itself,
and ``run`` verifies before it writes anything: the packages the outputs
need (:mod:`framework.extras`), the names of pictures and series against
:mod:`viz`'s tables, and the memory the run will take
(:mod:`framework.resources`). :func:`run_scenario` writes ``summary.csv`` and
the VTU files step by step, then ``result.h5``, the pictures and the plots.

Like the rest of the command line, this module imports :mod:`viz`, only when a
scenario writes VTU files or pictures; the numerical core never does.
"""
import csv
import os
import re
import sys
import time

from . import io, resources
from .errors import FrameworkError
from .extras import require, scenario_needs
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
    """The picture kind of ``--animate FIELD``: ``map`` (a surface field), ``slice`` (a stress); or FrameworkError."""
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


def preflight(scenario, *, animate=None, memory=None):
    """Everything a run of ``scenario`` needs besides the file itself: found before anything is written.

    The packages of its outputs (one :class:`~framework.extras.MissingExtraError`
    line naming the extra to install), its pictures' and series' names
    (:func:`check_output`), the field of ``--animate``, and its memory: above
    ``memory`` [bytes] (default: this machine's) the run is refused.

    Returns
    -------
    tuple
        ``(estimate, warning)``: the :class:`~framework.resources.Estimate` and
        the text of a warning when the run needs more than half the memory (else None).
    """
    grid = scenario.simulation.grid
    require(scenario_needs(scenario.output, layers=grid.layers, animate=animate), what=f"{scenario.source}: run")
    check_output(scenario)
    if animate:
        animation_kind(animate, grid)
    estimate = resources.for_simulation(scenario.simulation, scenario.output, animate)
    try:
        warning = resources.check_memory(estimate, resources.machine_memory() if memory is None else memory)
    except FrameworkError as exc:
        raise ScenarioError(f"{scenario.source}: {exc}") from exc
    return estimate, warning


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
    _, warning = preflight(scenario, animate=animate)
    if warning:
        print(f"warning: {scenario.source}: {warning}", file=sys.stderr)
    viz = _viz() if output.vtu or output.pictures or output.history or animate else None
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
    return [f"{count:5d}  {kind:<18} {size_text(size)}" for kind, (count, size) in sorted(groups.items())]


def size_text(size):
    return f"{size / 1e6:6.1f} MB" if size >= 1e5 else f"{size / 1e3:6.1f} kB"
