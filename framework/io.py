"""Results on disk: HDF5 files that hold everything, and the checkpoints of long runs.

Layout (``format = 1``): file attributes ``framework_version``, ``format`` and
``configuration`` (JSON of :meth:`Result.configuration`); group ``series``
(one dataset per step series: ``index``, ``time``, ``load``, ``approach``,
``iterations``, ``residual``, ``success``, ``tilt``); group ``fields``
(``pressure``, ``displacement``, ``gap``, each ``(steps, n1, n2)``); and, in a
checkpoint, group ``state`` (the time stepper's history and the next station).
Arrays are stored as they are in memory: a round trip is exact to the bit.
Files are written under a temporary name and renamed, so a killed process
never leaves a half-written file under the final name.
"""
import json
import os

import numpy as np

from .errors import FrameworkError, ParameterError

FORMAT = 1
SERIES = ("index", "time", "load", "approach", "iterations", "residual", "success", "tilt")
FIELDS = ("pressure", "displacement", "gap")


def _h5py():
    try:
        import h5py
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise FrameworkError("saving results needs h5py: pip install 'viscocontact[io]'") from exc
    return h5py


def save(result, path, state=None):
    """Write ``result`` (and a stepper ``state`` for a checkpoint) to the HDF5 file ``path``."""
    h5py = _h5py()
    temporary = f"{path}.tmp{os.getpid()}"
    records = result.records
    with h5py.File(temporary, "w") as f:
        f.attrs["format"] = FORMAT
        f.attrs["framework_version"] = result.version
        f.attrs["configuration"] = json.dumps(result.configuration())
        series = f.create_group("series")
        for name in SERIES:
            values = [getattr(r, name) for r in records]
            series.create_dataset(name, data=np.array(values, dtype=float if name == "tilt" else None)
                                  if values else np.zeros((0, 2) if name == "tilt" else 0))
        fields = f.create_group("fields")
        shape = (len(records),) + tuple(result.grid.shape)
        for name in FIELDS:
            data = np.array([getattr(r, name) for r in records]) if records else np.zeros(shape)
            fields.create_dataset(name, data=data, compression="gzip", compression_opts=1, shuffle=True)
        if state is not None:
            group = f.create_group("state")
            for key, value in state.items():
                group.create_dataset(key, data=np.asarray(value))
    os.replace(temporary, path)


def read(path):
    """``(configuration dict, records, state or None)`` from a file written by :func:`save`."""
    from .result import StepRecord
    h5py = _h5py()
    if not os.path.isfile(path):
        raise ParameterError(f"path: no result file at {path!r}")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise ParameterError(f"path: {path!r} is not an HDF5 result file ({exc})") from exc
    with f:
        if f.attrs.get("format") != FORMAT or "series" not in f:
            raise ParameterError(f"path: {path!r} is not a result file of format {FORMAT}")
        configuration = json.loads(f.attrs["configuration"])
        series = {name: f["series"][name][()] for name in SERIES}
        fields = {name: f["fields"][name][()] for name in FIELDS}
        state = {key: value[()] for key, value in f["state"].items()} if "state" in f else None
    records = [StepRecord(index=int(series["index"][k]), time=series["time"][k], load=series["load"][k],
                          approach=series["approach"][k], pressure=fields["pressure"][k],
                          displacement=fields["displacement"][k], gap=fields["gap"][k],
                          iterations=int(series["iterations"][k]), residual=series["residual"][k],
                          success=bool(series["success"][k]), tilt=tuple(series["tilt"][k]))
               for k in range(len(series["time"]))]
    return configuration, records, state


def load_result(path):
    """The :class:`Result` saved in ``path`` (with its configuration rebuilt)."""
    from .config import build
    from .result import Result
    from .simulation import Options
    configuration, records, _ = read(path)
    parts = {key: build(configuration[key], name=key) for key in ("grid", "material", "indenter", "schedule")}
    options = build(configuration["options"], name="options") if configuration.get("options") else Options()
    result = Result(parts["grid"], parts["material"], parts["indenter"], parts["schedule"], options)
    result.version = configuration.get("framework_version", result.version)
    for record in records:
        result.append(record)
    return result
