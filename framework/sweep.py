"""Parametric studies on Dask distributed: one simulation per point, one file per point.

    rows = sweep(build, {"radius": [5e-3, 1e-2], "young": [1e9, 2e9]}, folder="study")

runs ``build(**point).run()`` for every point of the Cartesian product on a
Dask cluster, saves each result to ``study/point_<index>_<hash>.h5`` and the
last step's scalars of every point to ``study/sweep.csv`` (the parameters under
their own names, the outputs as ``final.<series>``). A rerun skips the points
whose file is there, so a killed sweep is finished by running it again.

Scenario sweeps: :class:`ScenarioBuilder` turns a scenario file (or its
tables) into a picklable ``build`` whose keyword arguments are dotted keys
(``"material.young"``, ``"schedule.load.value"``), and :func:`read_sweep`
reads a sweep file::

    scenario = "hertz_elastic.toml"      # relative to this file; or an inline [scenario] table
    folder = "out/hertz_sweep"           # optional, relative to this file
    [parameters]                         # Cartesian product, the last key varying fastest
    "indenter.radius" = [5e-3, 10e-3]
    "material.young" = [70e9, 210e9]
    # or explicit points instead of [parameters]:
    # [[points]]
    # "indenter.radius" = 5e-3

Command line: ``python -m framework sweep SWEEP.toml [--scheduler ADDRESS]
[--folder DIR] [--quiet]`` (:func:`main`).

Dask and distributed are imported only here; without them :func:`sweep`
raises :class:`MissingExtraError` naming ``pip install 'viscocontact[cluster]'``.
"""
import argparse
import contextlib
import copy
import csv
import hashlib
import itertools
import json
import logging
import math
import os
import re
import sys
import time
import uuid
import warnings

from . import io
from .errors import FrameworkError, ParameterError
from .scenario import ARRAYS, TABLES, ScenarioError, parse, tomllib

EXTRA = "pip install 'viscocontact[cluster]'"
DEFAULT_FOLDER = "sweep"
TABLE_FILE = "sweep.csv"
NETCDF_FILE = "sweep.nc"
STATUS = ("done", "skipped", "failed")
#: Columns of every row besides the parameters and the outputs (reserved: no parameter may take these names).
BOOKKEEPING = ("index", "status", "error", "file", "wall_time", "steps")
#: The last step's value of a series is the column ``final.<series>`` (``final.load``): a dotted name, which
#: no keyword argument of a ``build`` function and no scenario key (``material.young``: a table first) can be.
OUTPUT_PREFIX = "final."
#: Temporary files of a point being written (see :func:`run_point`), and those of Result.save inside them.
PARTIAL = r"\.{stem}\.[0-9a-f]{{8}}\.partial\.h5(\.tmp\d+)?"
SWEEP_KEYS = ("scenario", "parameters", "points", "folder")


class MissingExtraError(FrameworkError, ImportError):
    """An optional dependency of this feature is not installed: the message names the extra."""


# --------------------------------------------------------------------------- points


def expand(parameters):
    """The list of points (dicts) of ``parameters``, in the order the sweep numbers them.

    A dict of value lists gives the Cartesian product in the dict's order, the
    last key varying fastest (``itertools.product``); a list of dicts is taken
    as the points themselves.
    """
    if isinstance(parameters, dict):
        if not parameters:
            raise ParameterError("parameters: expected at least one parameter with a list of values, got {}")
        keys, values = list(parameters), []
        for key in keys:
            _check_name(key)
            value = parameters[key]
            if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__iter__"):
                raise ParameterError(f"parameters[{key!r}]: expected a list of values, got {value!r}")
            value = list(value)
            if not value:
                raise ParameterError(f"parameters[{key!r}]: expected a non-empty list of values, got []")
            values.append(value)
        return [dict(zip(keys, combination)) for combination in itertools.product(*values)]
    if isinstance(parameters, (list, tuple)):
        if not parameters:
            raise ParameterError("parameters: expected at least one point, got an empty list")
        points = []
        for i, point in enumerate(parameters):
            if not isinstance(point, dict):
                raise ParameterError(f"parameters[{i}]: expected a dict of parameter values, got {point!r}")
            for key in point:
                _check_name(key)
            points.append(dict(point))
        return points
    raise ParameterError(f"parameters: expected a dict of value lists or a list of dicts, got "
                         f"{type(parameters).__name__}")


def _check_name(key):
    if not isinstance(key, str) or not key:
        raise ParameterError(f"parameter names must be non-empty strings, got {key!r}")
    if key in BOOKKEEPING or key.startswith(OUTPUT_PREFIX):
        raise ParameterError(f"parameter name {key!r} is taken by the table: {list(BOOKKEEPING)} and "
                             f"'{OUTPUT_PREFIX}<series>' are its own columns; rename the parameter")


def _plain(value):
    """``value`` as plain data (numbers, strings, lists, dicts): what the table and the hash see."""
    from .config import describe
    return describe(value)


def point_hash(point):
    """Short stable hash (8 hex digits) of a point: the same values give the same hash in every process."""
    text = json.dumps(_plain(point), sort_keys=True, separators=(",", ":"), default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:8]


def point_file(index, point):
    """File name of a point's result: ``point_<index:04d>_<hash>.h5``."""
    return f"point_{index:04d}_{point_hash(point)}.h5"


def series_names():
    """Names of the scalar series of :meth:`Result.summary`, in its order."""
    from .grid import Grid
    from .result import Result
    return list(Result(Grid(shape=(1, 1), size=(1.0, 1.0)), None, None, None, None).summary())


# --------------------------------------------------------------------------- one point (on a worker)


def _last_values(result):
    """The last step's value of every summary series, keyed by the series' name."""
    out = {}
    for key, values in result.summary().items():
        value = values[-1] if len(values) else float("nan")
        out[key] = value.item() if hasattr(value, "item") else value
    return out


def remove_partials(folder, stem=r"point_\d+_[0-9a-f]{8}"):
    """Remove the temporary files of points (all, or those of ``stem``) left in ``folder`` by killed writes."""
    pattern = re.compile(PARTIAL.format(stem=stem))
    with contextlib.suppress(OSError):
        for entry in os.listdir(folder):
            if pattern.fullmatch(entry):
                with contextlib.suppress(OSError):
                    os.remove(os.path.join(folder, entry))


def _message(exc):
    return f"{type(exc).__name__}: {' '.join(str(exc).split())}"


def _stamp(path, point, wall_time):
    """Record the point and its wall time in the file's attributes (best effort)."""
    try:
        import h5py
        with h5py.File(path, "a") as f:
            f.attrs["sweep_point"] = json.dumps(_plain(point), sort_keys=True, default=repr)
            f.attrs["sweep_wall_time"] = wall_time
    except Exception:  # noqa: BLE001 - metadata only; the result itself is written
        pass


def run_point(build, point, folder, name):
    """Build, run and save one point; never raises (a failure is returned as a row).

    Returns ``{"status", "error", "file", "wall_time", "steps", "series"}``
    with ``series`` the last step's value of every summary series. The file is
    written to a hidden temporary name and renamed when complete.
    """
    from .simulation import Simulation
    path = os.path.join(folder, name)
    stem = name[:-len(".h5")]
    temporary = os.path.join(folder, f".{stem}.{uuid.uuid4().hex[:8]}.partial.h5")
    try:
        simulation = build(**point)
        if not isinstance(simulation, Simulation):
            raise ParameterError(f"build(**point) must return a framework.Simulation, got "
                                 f"{type(simulation).__name__}")
        start = time.perf_counter()
        result = simulation.run()
        wall_time = time.perf_counter() - start
        os.makedirs(folder, exist_ok=True)
        remove_partials(folder, re.escape(stem))  # left by a killed run of this point (e.g. a worker that died)
        try:
            result.save(temporary)
            _stamp(temporary, point, wall_time)
            os.replace(temporary, path)
        finally:
            remove_partials(folder, re.escape(stem))  # ours, and any of Result.save's own, if it failed
        return {"status": "done", "error": "", "file": path, "wall_time": wall_time, "steps": len(result),
                "series": _last_values(result)}
    except Exception as exc:  # noqa: BLE001 - reported in the table, the other points go on
        return {"status": "failed", "error": _message(exc), "file": "", "wall_time": None, "steps": None,
                "series": {}}


def read_point(path):
    """The row of a point already done (``status = "skipped"``), read back with :func:`framework.load_result`."""
    from . import load_result
    result = load_result(path)
    wall_time = None
    try:
        import h5py
        with h5py.File(path, "r") as f:
            if "sweep_wall_time" in f.attrs:
                wall_time = float(f.attrs["sweep_wall_time"])
    except Exception:  # noqa: BLE001 - metadata only
        pass
    return {"status": "skipped", "error": "", "file": path, "wall_time": wall_time, "steps": len(result),
            "series": _last_values(result)}


# --------------------------------------------------------------------------- the sweep


def _import_distributed():
    try:
        import dask  # noqa: F401
        import distributed
    except ImportError as exc:
        raise MissingExtraError(f"sweeps run on Dask distributed, which is not installed ({exc}): {EXTRA}") from exc
    return distributed


@contextlib.contextmanager
def _connect(distributed, client, n_points):
    """A client for the sweep: ours (closed at the end) or the caller's (left open)."""
    if client is None:
        import dask
        from dask.system import CPU_COUNT
        with dask.config.set({"distributed.scheduler.allowed-failures": 1}):  # a crashing point fails, once
            cluster = distributed.LocalCluster(n_workers=max(1, min(n_points, CPU_COUNT or 1)), threads_per_worker=1,
                                               processes=True, dashboard_address=None,
                                               silence_logs=logging.ERROR,
                                               # no dashboard; its bare HTTP server on a free local port
                                               scheduler_kwargs={"dashboard_address": "127.0.0.1:0"})
        try:
            with distributed.Client(cluster) as ours:
                yield ours
        finally:
            cluster.close()
    elif isinstance(client, (str, os.PathLike)):
        address = os.fspath(client)
        try:
            ours = distributed.Client(address, timeout="20s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise FrameworkError(f"cannot connect to the Dask scheduler at {address!r}: {exc}") from exc
        try:
            yield ours
        finally:
            ours.close()
    elif isinstance(client, distributed.Client):
        yield client
    else:
        raise ParameterError(f"client must be None, a scheduler address or a distributed.Client, got "
                             f"{type(client).__name__}")


def sweep(build, parameters, client=None, folder=None, *, outputs=None, progress=False):
    """Run ``build(**point).run()`` for every point on Dask; one result file per point and a table.

    Parameters
    ----------
    build : callable
        ``build(**point)`` returns a :class:`framework.Simulation`. It is sent to
        the workers: a module-level function, a :class:`ScenarioBuilder`, a
        ``functools.partial`` or a closure (cloudpickle) all work.
    parameters : dict of lists or list of dicts
        Value lists (their Cartesian product in the dict's order, the last key
        varying fastest) or explicit points. Values should be plain data
        (numbers, strings, lists): they name the point's file and its row.
    client : None, str or distributed.Client
        None: a ``LocalCluster`` of processes with one thread each,
        ``min(points to run, cores)`` workers, no dashboard, closed at the end.
        A string: the address of a running scheduler (``tcp://host:8786``).
        A ``Client``: used as is and left open. With workers on other machines
        ``folder`` must be on a file system they all share.
    folder : str, optional
        Where the files go (default ``"sweep"``, created if needed). It is
        checked to accept new files before any point runs.
    outputs : list of str, optional
        The scalar series in the table (default: all of :meth:`Result.summary`),
        by their names in :meth:`Result.summary` (``"load"``, ``"max_pressure"``).
    progress : bool
        Print one line per finished point.

    Returns
    -------
    list of dict
        One row per point, in point order, with the keys ``index``, the
        point's parameters under their own names, ``status`` (``"done"``,
        ``"skipped"``: its file was already there and was read back with
        :func:`framework.load_result`, ``"failed"``: build or run raised),
        ``error`` (``"Type: message"`` of a failed point, else ``""``), ``file``
        (the result file, ``""`` if failed), ``wall_time`` [s] of ``run()``,
        ``steps``, and the LAST step's value of each series as
        ``final.<series>``: ``final.time`` [s], ``final.load`` [N],
        ``final.approach`` [m], ``final.contact_area`` [m^2],
        ``final.contact_radius`` [m], ``final.max_pressure`` [Pa],
        ``final.center_x1``, ``final.center_x2`` [m], ``final.tilt_x1``,
        ``final.tilt_x2`` [rad], ..., ``final.iterations``,
        ``final.residual``; None where a failed point has no value. So a
        swept ``load`` (a parameter) and the load reached (``final.load``)
        are two columns. The names in ``BOOKKEEPING`` and those starting
        with ``final.`` cannot be parameters (:class:`ParameterError`).

    Files
    -----
    ``folder/point_<index:04d>_<hash>.h5``: each point's full result
    (:meth:`Result.save`, plus the attributes ``sweep_point`` and
    ``sweep_wall_time``), written under a hidden temporary name and renamed
    when complete, so a killed sweep leaves no half file: rerun it and the
    points with a file are skipped. The hash is of the point's values only: a
    changed ``build`` or base scenario is not detected, use a new folder.
    ``folder/sweep.csv``: the table (lists as JSON, missing values empty).
    ``folder/sweep.nc``: the same table as NetCDF, only if ``xarray`` is
    importable (it is not a dependency of the framework). The hidden
    temporary files that killed writes left in ``folder`` are removed when a
    sweep starts there: run one sweep at a time in a folder.

    A point whose build or run raises is reported as failed and the others go
    on; Dask does not retry it (a point whose worker process dies is retried
    once on another worker of a cluster started here, then reported as
    ``KilledWorker``). Scripts that start a local cluster need the
    ``if __name__ == "__main__":`` guard (the workers are new processes).
    """
    if not callable(build):
        raise ParameterError(f"build must be callable (build(**point) -> Simulation), got {type(build).__name__}")
    points = expand(parameters)
    names = series_names()
    if outputs is None:
        selected = names
    else:
        if isinstance(outputs, str) or not all(isinstance(o, str) for o in outputs):
            raise ParameterError(f"outputs must be a list of series names, got {outputs!r}")
        unknown = [o for o in outputs if o not in names]
        if unknown:
            raise ParameterError(f"outputs: unknown series {unknown}; expected some of {names}")
        selected = list(outputs)
    keys = list(dict.fromkeys(key for point in points for key in point))
    distributed = _import_distributed()
    # the table is written after every point ran: make sure it can be
    folder = io.check_folder(DEFAULT_FOLDER if folder is None else folder, name="folder", create=True)
    table = os.path.join(folder, TABLE_FILE)
    if os.path.isdir(table):
        raise ParameterError(f"folder: {table!r} is a folder; the sweep writes its table there")
    remove_partials(folder)

    files = [point_file(index, point) for index, point in enumerate(points)]
    outcomes = [None] * len(points)
    todo = []
    for index, name in enumerate(files):
        path = os.path.join(folder, name)
        if os.path.isfile(path):
            try:
                outcomes[index] = read_point(path)
            except Exception:  # noqa: BLE001 - unreadable: run the point again, the rename replaces the file
                todo.append(index)
        else:
            todo.append(index)
    for index in range(len(points)):
        if outcomes[index] is not None and progress:
            _report(index, len(points), files[index], outcomes[index])

    if todo:
        token = uuid.uuid4().hex[:8]
        with _connect(distributed, client, len(todo)) as connection:
            futures = {connection.submit(run_point, build, points[index], folder, files[index], pure=False,
                                         retries=0, key=f"{files[index][:-3]}-{token}"): index for index in todo}
            for future in distributed.as_completed(futures):
                index = futures[future]
                try:
                    outcome = future.result()
                except (KeyboardInterrupt, SystemExit):
                    raise
                except BaseException as exc:  # noqa: BLE001 - e.g. KilledWorker: the point failed
                    outcome = {"status": "failed", "error": _message(exc), "file": "", "wall_time": None,
                               "steps": None, "series": {}}
                finally:
                    future.release()
                outcomes[index] = outcome
                if progress:
                    _report(index, len(points), files[index], outcome)

    rows = []
    for index, (point, outcome) in enumerate(zip(points, outcomes)):
        row = {"index": index}
        row.update({key: _plain(point[key]) if key in point else None for key in keys})
        row.update({key: outcome[key] for key in BOOKKEEPING[1:]})
        row.update({OUTPUT_PREFIX + key: outcome["series"].get(key) for key in selected})
        rows.append(row)
    write_table(rows, table)
    _write_netcdf(rows, os.path.join(folder, NETCDF_FILE))
    return rows


def _report(index, total, name, outcome):
    status = outcome["status"]
    detail = outcome["error"] if status == "failed" else \
        "" if outcome["wall_time"] is None else f"run {outcome['wall_time']:.3g} s"
    print(f"[{index + 1}/{total}] {name}: {status} {detail}".rstrip(), flush=True)


def _cell(value):
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (list, dict)):
        return json.dumps(value)
    return str(value)


def write_table(rows, path):
    """Write ``rows`` (dicts with the same keys) to the CSV file ``path`` (temporary name, then rename)."""
    columns = list(rows[0]) if rows else list(BOOKKEEPING)
    temporary = io.temporary(path)
    with open(temporary, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(columns)
        for row in rows:
            writer.writerow([_cell(row.get(key)) for key in columns])
    os.replace(temporary, path)


def _write_netcdf(rows, path):
    try:
        import xarray
    except ImportError:
        return
    try:
        variables = {}
        for key in rows[0]:
            values = [row[key] for row in rows]
            if all(isinstance(v, (int, float)) and not isinstance(v, bool) or v is None for v in values):
                values = [math.nan if v is None else float(v) for v in values]
            else:
                values = ["" if v is None else _cell(v) for v in values]
            variables[key] = ("point", values)
        xarray.Dataset(variables).to_netcdf(path)
    except Exception as exc:  # noqa: BLE001 - the CSV table is the reference output
        warnings.warn(f"{path} not written: {exc}", stacklevel=3)


# --------------------------------------------------------------------------- scenario sweeps


def _load_toml(path, what):
    if not os.path.isfile(path):
        raise ScenarioError(f"{path}: no such {what} file")
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from exc


class ScenarioBuilder:
    """A scenario as a picklable ``build`` for :func:`sweep`: dotted keys replace its values.

    ``ScenarioBuilder("base.toml")(**{"material.young": 2e9, "indenter.radius": 5e-3})``
    is the :class:`Simulation` of ``base.toml`` with those values. A key names
    a table and a key in it, through nested tables and list indices
    (``"schedule.load.value"``, ``"schedule.load.segments.0.end"``); a key with
    the table alone (``"material"``) replaces the whole table. The tables on
    the way must exist in the base scenario; the last key may be new (a value
    left at its default there) and is checked when the scenario is parsed. Any
    mistake raises :class:`ScenarioError` naming the key.

    The file is read once, here: the builder carries its tables, so workers
    need no access to it, except to a file the scenario names (a ``dma``
    material, read relative to the scenario's folder by each point). The base
    scenario is checked at once.
    """

    def __init__(self, path_or_data, *, source=None):
        if isinstance(path_or_data, (str, os.PathLike)):
            path = os.fspath(path_or_data)
            self.data = _load_toml(path, "scenario")
            self.source = source or path
            self.folder = os.path.dirname(os.path.abspath(path))
        elif isinstance(path_or_data, dict):
            self.data = copy.deepcopy(path_or_data)
            self.source = source or "<scenario>"
            self.folder = None
        else:
            raise ScenarioError(f"ScenarioBuilder: expected a scenario file path or a dict of tables, got "
                                f"{type(path_or_data).__name__}")
        parse(copy.deepcopy(self.data), source=self.source, folder=self.folder)

    def __repr__(self):
        return f"ScenarioBuilder({self.source!r})"

    def __eq__(self, other):
        return isinstance(other, ScenarioBuilder) and (self.data, self.source, self.folder) == (
            other.data, other.source, other.folder)

    __hash__ = None

    def check(self, key):
        """Raise :class:`ScenarioError` unless ``key`` can be set (its table and the tables on the way exist)."""
        self._place(copy.deepcopy(self.data), key, None)

    def tables(self, **overrides):
        """The scenario's tables with ``overrides`` applied (a new dict)."""
        data = copy.deepcopy(self.data)
        for key, value in overrides.items():
            self._place(data, key, copy.deepcopy(value))
        return data

    def scenario(self, **overrides):
        """The :class:`framework.scenario.Scenario` with ``overrides`` applied."""
        source = self.source
        if overrides:
            source += " with " + ", ".join(f"{key} = {value!r}" for key, value in overrides.items())
        return parse(self.tables(**overrides), source=source, folder=self.folder)

    def __call__(self, **overrides):
        return self.scenario(**overrides).simulation

    def _place(self, data, key, value):
        if not isinstance(key, str) or not key or not all(key.split(".")):
            raise ScenarioError(f"{self.source}: {key!r}: expected a dotted key like 'material.young'")
        parts = key.split(".")
        table = parts[0]
        if table not in TABLES | ARRAYS:
            raise ScenarioError(f"{self.source}: {key}: unknown table {table!r}; expected one of "
                                f"{sorted(TABLES | ARRAYS)}")
        if len(parts) == 1:
            data[table] = value
            return
        node = data.setdefault(table, {})
        for depth, part in enumerate(parts[1:], start=1):
            where = ".".join(parts[:depth])
            if isinstance(node, list):
                if not part.lstrip("-").isdigit() or not -len(node) <= int(part) < len(node):
                    raise ScenarioError(f"{self.source}: {key}: {where} is a list of {len(node)}; "
                                        f"{part!r} is not an index in it")
                part = int(part)
            elif not isinstance(node, dict):
                raise ScenarioError(f"{self.source}: {key}: {where} is {node!r}, not a table: "
                                    f"it has no key {part!r}")
            if depth == len(parts) - 1:
                node[part] = value
                return
            if isinstance(node, dict) and part not in node:
                raise ScenarioError(f"{self.source}: {key}: unknown key {'.'.join(parts[:depth + 1])!r} "
                                    f"(the base scenario's {where} has {sorted(node)})")
            node = node[part]


def _flatten(table, prefix=""):
    """Nested tables to dotted keys; a table with a ``type`` (an object) stays a value."""
    out = {}
    for key, value in table.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict) and "type" not in value:
            out.update(_flatten(value, name + "."))
        else:
            out[name] = value
    return out


def read_sweep(path):
    """``(builder, parameters, folder)`` from a sweep file (see the module's docstring).

    ``scenario`` is a path relative to the sweep file (or absolute) or an
    inline table of scenario tables; ``[parameters]`` maps dotted keys to value
    lists (their Cartesian product), or ``[[points]]`` lists the points (nested
    tables become dotted keys, except tables with a ``type``, which are
    values); ``folder`` is relative to the sweep file, None when absent.
    Mistakes raise :class:`ScenarioError` naming the file and the key.
    """
    path = os.fspath(path)
    data = _load_toml(path, "sweep")
    unknown = sorted(set(data) - set(SWEEP_KEYS))
    if unknown:
        raise ScenarioError(f"{path}: unknown key(s) {unknown}; expected some of {list(SWEEP_KEYS)}")
    base = os.path.dirname(os.path.abspath(path))
    if "scenario" not in data:
        raise ScenarioError(f"{path}: missing 'scenario' (a scenario file's path, or a [scenario] table)")
    scenario = data["scenario"]
    if isinstance(scenario, str):
        builder = ScenarioBuilder(os.path.join(base, scenario))
    elif isinstance(scenario, dict):
        builder = ScenarioBuilder(scenario, source=f"{path} [scenario]")
    else:
        raise ScenarioError(f"{path}: scenario: expected a path or a table, got {scenario!r}")
    if ("parameters" in data) == ("points" in data):
        raise ScenarioError(f"{path}: expected either a [parameters] table (value lists) or [[points]], "
                            f"{'not both' if 'points' in data else 'found neither'}")
    if "parameters" in data:
        if not isinstance(data["parameters"], dict):
            raise ScenarioError(f"{path}: parameters: expected a table of value lists")
        parameters = _flatten(data["parameters"])
        if not parameters:
            raise ScenarioError(f"{path}: [parameters] is empty")
        for key, values in parameters.items():
            if not isinstance(values, list) or not values:
                raise ScenarioError(f"{path}: parameters.{key}: expected a non-empty list of values, got {values!r}")
        keys = list(parameters)
    else:
        points = data["points"]
        if not isinstance(points, list) or not points or not all(isinstance(p, dict) for p in points):
            raise ScenarioError(f"{path}: points: expected an array of tables [[points]], got {points!r}")
        parameters = [_flatten(point) for point in points]
        keys = list(dict.fromkeys(key for point in parameters for key in point))
    for key in keys:
        try:
            builder.check(key)
        except ScenarioError as exc:
            raise ScenarioError(f"{path}: {exc}") from exc
    folder = data.get("folder")
    if folder is not None:
        if not isinstance(folder, str) or not folder:
            raise ScenarioError(f"{path}: folder: expected a path, got {folder!r}")
        folder = os.path.join(base, folder)
    return builder, parameters, folder


# --------------------------------------------------------------------------- command line

SHOWN = ("final.load", "final.contact_radius", "final.max_pressure", "final.friction_coefficient", "wall_time")


def format_table(rows):
    """The table as aligned text: the parameters, the status and a few outputs (or the error)."""
    if not rows:
        return ""
    keys = [k for k in rows[0] if k not in BOOKKEEPING and not k.startswith(OUTPUT_PREFIX)]
    lines = [["#"] + keys + ["status"] + list(SHOWN)]
    for row in rows:
        cells = [str(row["index"])] + [f"{row[k]:.6g}" if isinstance(row[k], float) else _cell(row[k])
                                       for k in keys] + [row["status"]]
        if row["status"] == "failed":
            cells.append(row["error"])
        else:
            cells += ["" if row.get(k) is None else f"{row[k]:.4g}" for k in SHOWN]
        lines.append(cells)
    width = {}
    for line in lines:
        for i, cell in enumerate(line[:-1]):
            width[i] = max(width.get(i, 0), len(cell))
    return "\n".join("  ".join([cell.ljust(width[i]) for i, cell in enumerate(line[:-1])] + [line[-1]]).rstrip()
                     for line in lines)


def main(argv=None):
    """``python -m framework sweep SWEEP.toml [--scheduler ADDRESS] [--folder DIR] [--quiet]``.

    ``argv`` holds the arguments after ``sweep``. Returns the exit code: 0 when
    every point is done or skipped, 1 when some failed (the table says why),
    2 for a bad sweep file or a missing package (one ``error: ...`` line on
    stderr).
    """
    parser = argparse.ArgumentParser(prog="python -m framework sweep",
                                     description="run a parametric sweep (a sweep file) on Dask distributed")
    parser.add_argument("sweep_file", help="sweep file (TOML): scenario, [parameters] or [[points]], folder")
    parser.add_argument("--scheduler", default=None,
                        help="address of a running Dask scheduler (default: a local cluster on this machine)")
    parser.add_argument("--folder", default=None,
                        help=f"output folder (default: the file's 'folder', else ./{DEFAULT_FOLDER})")
    parser.add_argument("--quiet", action="store_true", help="no line per finished point")
    args = parser.parse_args(argv)
    try:
        builder, parameters, folder = read_sweep(args.sweep_file)
        folder = args.folder or folder or DEFAULT_FOLDER
        start = time.perf_counter()
        rows = sweep(builder, parameters, client=args.scheduler, folder=folder, progress=not args.quiet)
    except FrameworkError as exc:
        print(f"error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    elapsed = time.perf_counter() - start
    counts = {status: sum(row["status"] == status for row in rows) for status in STATUS}
    print(format_table(rows))
    print(f"{len(rows)} points in {elapsed:.1f} s: {counts['done']} done, {counts['skipped']} skipped, "
          f"{counts['failed']} failed; table: {os.path.join(folder, TABLE_FILE)}")
    return 1 if counts["failed"] else 0
