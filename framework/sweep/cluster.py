"""The sweep on Dask: one task per point to run, the points already done read back, the table at the end.

Dask and distributed are imported only here; without them :func:`sweep`
raises :class:`MissingExtraError` naming ``pip install 'viscocontact[cluster]'``.
"""
import contextlib
import logging
import os
import threading
import uuid

from .. import io
from ..errors import FrameworkError, ParameterError
from ..extras import MissingExtraError
from .points import BOOKKEEPING, OUTPUT_PREFIX, expand, plain, point_file, series_names
from .table import NETCDF_FILE, TABLE_FILE, write_netcdf, write_table
from .worker import failed, one_line, read_point, remove_partials, run_point

EXTRA = "pip install 'viscocontact[cluster]'"
DEFAULT_FOLDER = "sweep"
#: [s] How long a scheduler address may take to answer as a Dask scheduler. Dask's own timeout does not
#: bound every way a server that speaks another protocol can stall (an HTTP server waits for a request
#: line forever), so the client is made in a thread that is abandoned after this long.
CONNECT_TIMEOUT = 20.0


def import_distributed():
    """The ``distributed`` module, or :class:`MissingExtraError` naming the extra (h5py too: points are HDF5)."""
    try:
        import dask  # noqa: F401
        import distributed
        import h5py  # noqa: F401 - every point is saved to an HDF5 file
    except ImportError as exc:
        raise MissingExtraError(f"sweeps run on Dask distributed and save HDF5 files, and a package is not "
                                f"installed ({exc}): {EXTRA}") from exc
    return distributed


def connect(distributed, address, timeout=None):
    """A ``distributed.Client`` of the scheduler at ``address``, or one :class:`FrameworkError` line.

    Anything that is not a Dask scheduler (a web server, another service, a
    closed port) fails here, within ``timeout`` seconds (default
    :data:`CONNECT_TIMEOUT`), whatever the exception Dask raises on the
    bytes it received.
    """
    timeout = CONNECT_TIMEOUT if timeout is None else timeout
    box = {}

    def make():
        try:
            box["client"] = distributed.Client(address, timeout=f"{timeout}s")
        except BaseException as exc:  # noqa: BLE001 - reported below, on one line
            box["error"] = exc

    thread = threading.Thread(target=make, name="dask-connect", daemon=True)
    thread.start()
    thread.join(timeout + 1.0)  # a second for Dask to raise its own timeout first
    hint = "expected the address of a running Dask scheduler, e.g. tcp://host:8786 (dask scheduler prints it)"
    if thread.is_alive():  # abandoned: a daemon thread, and Dask's loop thread is one too
        raise FrameworkError(f"cannot connect to the Dask scheduler at {address!r}: no Dask answer within "
                             f"{timeout:g} s; {hint}")
    if "error" in box:
        exc = box["error"]
        if isinstance(exc, (KeyboardInterrupt, SystemExit)):
            raise exc
        raise FrameworkError(f"cannot connect to the Dask scheduler at {address!r}: {one_line(exc)}; "
                             f"{hint}") from exc
    return box["client"]


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
        ours = connect(distributed, os.fspath(client))
        try:
            yield ours
        finally:
            ours.close()
    elif isinstance(client, distributed.Client):
        yield client
    else:
        raise ParameterError(f"client must be None, a scheduler address or a distributed.Client, got "
                             f"{type(client).__name__}")


def refused_points(build, points):
    """``{index: reason}`` of the points (``{index: point}``) a :class:`ScenarioBuilder` refuses.

    Found here, before any task runs. Other ``build`` callables are not called
    here (they may be costly): their points fail on the workers if they must.
    """
    from .builder import ScenarioBuilder
    if not isinstance(build, ScenarioBuilder):
        return {}
    refused = {}
    for index, point in points.items():
        try:
            build.scenario(**point)
        except Exception as exc:  # noqa: BLE001 - each point's own reason, in its row
            refused[index] = one_line(exc)
    return refused


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
        A string: the address of a running scheduler (``tcp://host:8786``);
        one that does not answer as a Dask scheduler within
        :data:`CONNECT_TIMEOUT` seconds raises :class:`FrameworkError`.
        A ``Client``: used as is and left open (one made with
        ``security=distributed.security.Security(...)`` for a TLS scheduler).
        With workers on other machines ``folder`` must be on a file system
        they all share.
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
        :func:`framework.load_result`, ``"recomputed"``: its file was there
        but damaged (truncated, a flipped bit) and the point was run again,
        ``"failed"``: build or run raised), ``error`` (``"Type: message"`` of
        a failed point; ``"damaged: Type: message"``, what was wrong with the
        file, for a recomputed one; else ``""``), ``file`` (the result file,
        ``""`` if failed), ``wall_time`` [s] of ``run()``, ``steps``, and the
        LAST step's value of each series as ``final.<series>``:
        ``final.time`` [s], ``final.load`` [N], ``final.approach`` [m],
        ``final.contact_area`` [m^2], ``final.contact_radius`` [m],
        ``final.max_pressure`` [Pa], ``final.center_x1``, ``final.center_x2``
        [m], ``final.tilt_x1``, ``final.tilt_x2`` [rad], ...,
        ``final.iterations``, ``final.residual``; None where a failed point
        has no value. So a swept ``load`` (a parameter) and the load reached
        (``final.load``) are two columns. The names in ``BOOKKEEPING`` and
        those starting with ``final.`` cannot be parameters
        (:class:`ParameterError`).

    Files
    -----
    ``folder/point_<index:04d>_<hash>.h5``: each point's full result
    (:meth:`Result.save`'s file, with the point's JSON and the wall time of
    its run as the attributes ``sweep_point`` and ``sweep_wall_time`` under
    the file's checksum), written under a hidden temporary name and renamed
    when complete, so a killed sweep leaves no half file: rerun it and the
    points with a file are skipped. The hash is of the point's values only: a
    changed ``build`` or base scenario is not detected, use a new folder.
    ``folder/sweep.csv``: the table (lists as JSON, missing values empty).
    ``folder/sweep.nc``: the same table as NetCDF, only if ``xarray`` is
    importable (it is not a dependency of the framework). The hidden
    temporary files that killed writes left in ``folder`` are removed when a
    sweep starts there: run one sweep at a time in a folder.

    With a :class:`ScenarioBuilder`, every point is parsed here first: a
    point the scenario refuses (a misspelt key, a bad value) is reported as
    failed without being sent to the cluster, and no cluster starts when no
    point is left to run. A point whose build or run raises is reported as
    failed and the others go on; Dask does not retry it (a point whose
    worker process dies is retried once on another worker of a cluster
    started here, then reported as ``KilledWorker``). Scripts that start a
    local cluster need the ``if __name__ == "__main__":`` guard (the workers
    are new processes).
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
    distributed = import_distributed()
    # the table is written after every point ran: make sure it can be
    folder = io.check_folder(DEFAULT_FOLDER if folder is None else folder, name="folder", create=True)
    table = os.path.join(folder, TABLE_FILE)
    if os.path.isdir(table):
        raise ParameterError(f"folder: {table!r} is a folder; the sweep writes its table there")
    remove_partials(folder)

    files = [point_file(index, point) for index, point in enumerate(points)]
    outcomes = [None] * len(points)
    damaged = {}   # index: what was wrong with the file found there
    for index, name in enumerate(files):
        path = os.path.join(folder, name)
        if os.path.isfile(path):
            try:
                outcomes[index] = read_point(path)
            except Exception as exc:  # noqa: BLE001 - unreadable: run the point again, the rename replaces the file
                damaged[index] = one_line(exc)
    waiting = {index: point for index, point in enumerate(points) if outcomes[index] is None}
    for index, reason in refused_points(build, waiting).items():
        outcomes[index] = failed(reason if index not in damaged else
                                 f"{reason} (its earlier file was damaged: {damaged[index]})")
    todo = [index for index in range(len(points)) if outcomes[index] is None]
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
                    outcome = failed(one_line(exc))
                finally:
                    future.release()
                if index in damaged:
                    outcome = _after_damage(outcome, damaged[index])
                outcomes[index] = outcome
                if progress:
                    _report(index, len(points), files[index], outcome)

    rows = []
    for index, (point, outcome) in enumerate(zip(points, outcomes)):
        row = {"index": index}
        row.update({key: plain(point[key]) if key in point else None for key in keys})
        row.update({key: outcome[key] for key in BOOKKEEPING[1:]})
        row.update({OUTPUT_PREFIX + key: outcome["series"].get(key) for key in selected})
        rows.append(row)
    write_table(rows, table)
    write_netcdf(rows, os.path.join(folder, NETCDF_FILE))
    return rows


def _after_damage(outcome, reason):
    """The outcome of a point whose file was damaged: ``recomputed`` with the reason, or failed saying so too."""
    if outcome["status"] == "done":
        return dict(outcome, status="recomputed", error=f"damaged: {reason}")
    return dict(outcome, error=f"{outcome['error']} (its earlier file was damaged: {reason})")


def _report(index, total, name, outcome):
    status = outcome["status"]
    if status == "failed":
        detail = outcome["error"]
    else:
        detail = "" if outcome["wall_time"] is None else f"run {outcome['wall_time']:.3g} s"
        if status == "recomputed":
            detail = f"({outcome['error']}) {detail}"
    print(f"[{index + 1}/{total}] {name}: {status} {detail}".rstrip(), flush=True)
