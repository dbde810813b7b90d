"""One point of a sweep, as a worker runs it: build, run, save under a temporary name; and a point read back."""
import contextlib
import json
import os
import re
import time
import uuid

from .. import io
from ..errors import ParameterError
from .points import plain

#: Temporary files of a point being written (see :func:`run_point`), and those of Result.save inside them.
PARTIAL = r"\.{stem}\.[0-9a-f]{{8}}\.partial\.h5(\.tmp\d+)?"
#: Longest reason kept in the table for a failed point or a damaged file (the rest is cut, marked "...").
REASON_LENGTH = 300


def one_line(exc):
    """``"Type: message"`` of an exception on one line, at most :data:`REASON_LENGTH` characters."""
    text = f"{type(exc).__name__}: {' '.join(str(exc).split())}"
    return text if len(text) <= REASON_LENGTH else text[:REASON_LENGTH - 3] + "..."


def failed(reason):
    """The outcome of a point that did not run to the end."""
    return {"status": "failed", "error": reason, "file": "", "wall_time": None, "steps": None, "series": {}}


def last_values(result):
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


def run_point(build, point, folder, name):
    """Build, run and save one point; never raises (a failure is returned as a row).

    Returns ``{"status", "error", "file", "wall_time", "steps", "series"}``
    with ``series`` the last step's value of every summary series. The file
    (:func:`framework.io.save`, with the point's JSON and the wall time of its
    run as the annotations ``sweep_point`` and ``sweep_wall_time``) is written
    to a hidden temporary name and renamed when complete.
    """
    from ..simulation import Simulation
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
        try:   # the point and its wall time under the file's checksum (framework.io, format 5)
            io.save(result, temporary, annotations={
                "sweep_point": json.dumps(plain(point), sort_keys=True, default=repr), "sweep_wall_time": wall_time})
            os.replace(temporary, path)
        finally:
            remove_partials(folder, re.escape(stem))  # ours, and any of Result.save's own, if it failed
        return {"status": "done", "error": "", "file": path, "wall_time": wall_time, "steps": len(result),
                "series": last_values(result)}
    except Exception as exc:  # noqa: BLE001 - reported in the table, the other points go on
        return failed(one_line(exc))


def read_point(path):
    """The row of a point already done (``status = "skipped"``), read back with :func:`framework.load_result`.

    A damaged file (truncated, a flipped bit: its checksums fail) raises what
    :func:`framework.load_result` raises; the sweep then runs the point again.
    """
    from .. import load_result
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
            "series": last_values(result)}
