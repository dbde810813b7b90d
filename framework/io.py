"""Results on disk: HDF5 files that hold everything, and the checkpoints of long runs.

Layout, ``format = 3`` (the file attribute ``format``, an integer raised at
every change of layout): file attributes ``framework_version``, ``format``,
``configuration`` (JSON of :meth:`Result.configuration`) and ``checksum``
(CRC-32 of the UTF-8 text ``framework_version + "\\n" + configuration``);
group ``series`` (one dataset per step series: ``index``, ``time``, ``load``,
``approach``, ``iterations``, ``residual``, ``success``, ``tilt``); group
``fields`` (``pressure``, ``displacement``, ``gap``, each ``(steps, n1, n2)``,
one gzip chunk per step); for a run with inhomogeneities also ``series/couplings``
and ``fields/eigenstrain``, ``fields/inclusion_stress`` (each ``(steps, m1, m2,
m3, 6)`` on the inhomogeneities' box, see :class:`~framework.result.StepRecord`)
with the inhomogeneities in the configuration (key ``inclusions``); and, in a
checkpoint, group ``state`` (the time stepper's history and the next station,
and the last eigenstrains; its attribute ``keys`` lists them).

Every dataset is chunked and carries HDF5's Fletcher-32 checksum filter,
which HDF5 verifies at every read: a flipped byte in stored numbers, a
damaged gzip chunk, a truncated file or a missing dataset or attribute
raises :class:`ParameterError` naming the file (and the dataset) instead of
giving wrong numbers. A scalar (a stepper's time, the next station) is stored
as a one-element dataset with the attribute ``scalar = 1``, as chunked
datasets need a dimension.

Format 2 is format 3 without the inhomogeneities' datasets (they were
added with format 3, so that an older framework refuses a file whose
inhomogeneities it would drop); it is read as such.
Format 1 (files written before the checksums: the same groups and names,
contiguous datasets without the filter, scalars stored as such, no
``checksum`` attribute) is still read, without the checks it has no data for.
A format above 3 was written by a newer framework and is refused.

Arrays are stored as they are in memory: a round trip is exact to the bit.
Files are written under the temporary name ``{path}.tmp{pid}`` and renamed,
so a killed process never leaves a half-written file under the final name;
the next write to the same path removes such leftovers whose process is gone
(a path is written by one process at a time).
"""
import contextlib
import json
import os
import re
import tempfile
import zlib

import numpy as np

from .errors import FrameworkError, ParameterError

FORMAT = 3
READABLE = (1, 2, 3)
SERIES = ("index", "time", "load", "approach", "iterations", "residual", "success", "tilt")
FIELDS = ("pressure", "displacement", "gap")
#: Written only for a run with inhomogeneities (all its records carry them).
INCLUSION_SERIES = ("couplings", "inclusion_start")
INCLUSION_FIELDS = ("eigenstrain", "inclusion_stress")


def _h5py():
    try:
        import h5py
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise FrameworkError("saving results needs h5py: pip install 'viscocontact[io]'") from exc
    return h5py


def _reason(exc):
    """An OS or HDF5 error on one line, without the errno prefix."""
    return " ".join(str(getattr(exc, "strerror", None) or exc).split())


def _path(path, *, name):
    """``path`` as a non-empty ``str`` (from a ``str`` or ``os.PathLike``)."""
    text = os.fspath(path) if isinstance(path, (str, os.PathLike)) else None
    if not isinstance(text, str) or not text:
        raise ParameterError(f"{name} must be a file path (a non-empty str or os.PathLike), got {path!r}")
    return text


def _probe(folder, *, name):
    """Create (and drop) an anonymous file in ``folder``: the only sure test that files can be written there."""
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise ParameterError(f"{name}: cannot create files in the folder {folder!r} ({_reason(exc)}); "
                             f"expected a writable folder") from exc


def check_folder(folder, *, name, create=False):
    """``folder`` as a ``str`` once files can be created in it; else :class:`ParameterError` naming ``name``.

    With ``create`` the folder (and its parents) is made when missing.
    """
    folder = _path(folder, name=name)
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise ParameterError(f"{name}: {folder!r} is a file; expected a folder")
    if create:
        try:
            os.makedirs(folder, exist_ok=True)
        except OSError as exc:
            raise ParameterError(f"{name}: cannot create the folder {folder!r} ({_reason(exc)})") from exc
    elif not os.path.isdir(folder):
        raise ParameterError(f"{name}: the folder {folder!r} does not exist; create it first")
    _probe(folder, name=name)
    return folder


def check_target(path, *, name):
    """``path`` as a ``str`` once an HDF5 file can be written there; else :class:`ParameterError`.

    ``path`` must not be a folder and its folder must exist and accept new
    files. Leftovers of killed writes to ``path`` are removed
    (:func:`remove_leftovers`). ``name`` is the parameter named in messages.
    """
    path = _path(path, name=name)
    if os.path.isdir(path):
        raise ParameterError(f"{name}: {path!r} is a folder; expected the path of a file to write, "
                             f"e.g. {os.path.join(path, 'result.h5')!r}")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise ParameterError(f"{name}: cannot write {path!r}: the folder {folder!r} does not exist; create it first")
    _probe(folder, name=name)
    remove_leftovers(path)
    return path


def _owner_gone(pid):
    """True unless process ``pid`` runs (ours counts as gone: a leftover with our number is from a dead one)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except PermissionError:  # it runs, under another user
        return False
    except (OSError, OverflowError):
        return True
    return False


def remove_leftovers(path):
    """Remove the files ``{path}.tmp<pid>`` left by writes to ``path`` that were killed (their process is gone)."""
    folder, base = os.path.split(os.path.abspath(path))
    pattern = re.compile(re.escape(base) + r"\.tmp(\d+)")
    with contextlib.suppress(OSError):
        for entry in os.listdir(folder):
            match = pattern.fullmatch(entry)
            if match and _owner_gone(int(match.group(1))):
                with contextlib.suppress(OSError):
                    os.remove(os.path.join(folder, entry))


def temporary(path):
    """The name to write ``path`` under before renaming it (this process's; old leftovers removed)."""
    remove_leftovers(path)
    return f"{path}.tmp{os.getpid()}"


def _checksum(version, configuration):
    return zlib.crc32(f"{version}\n{configuration}".encode())


def _dataset(group, name, data, **options):
    """A chunked dataset with the Fletcher-32 checksum (a scalar as one element marked ``scalar``)."""
    data = np.asarray(data)
    scalar = data.ndim == 0
    dataset = group.create_dataset(name, data=data.reshape(1) if scalar else data, fletcher32=True,
                                   **{"chunks": True, **options})
    if scalar:
        dataset.attrs["scalar"] = 1


def save(result, path, state=None, *, name="path"):
    """Write ``result`` (and a stepper ``state`` for a checkpoint) to the HDF5 file ``path``.

    Raises :class:`ParameterError` naming ``name`` when ``path`` is a folder or
    its folder is missing or not writable (see :func:`check_target`).
    """
    h5py = _h5py()
    path = check_target(path, name=name)
    writing = temporary(path)
    records = result.records
    configuration = json.dumps(result.configuration())
    try:
        with h5py.File(writing, "w") as f:
            f.attrs["format"] = FORMAT
            f.attrs["framework_version"] = result.version
            f.attrs["configuration"] = configuration
            f.attrs["checksum"] = _checksum(result.version, configuration)
            series = f.create_group("series")
            for key in SERIES:
                values = [getattr(r, key) for r in records]
                _dataset(series, key, np.array(values, dtype=float if key == "tilt" else None) if values
                         else np.zeros((0, 2) if key == "tilt" else 0))
            fields = f.create_group("fields")
            shape = (len(records),) + tuple(result.grid.shape)
            for key in FIELDS:
                data = np.array([getattr(r, key) for r in records]) if records else np.zeros(shape)
                _dataset(fields, key, data, compression="gzip", compression_opts=1, shuffle=True,
                         chunks=(1,) + shape[1:] if records else True)  # one chunk per step
            if records and records[0].eigenstrain is not None:
                for key in INCLUSION_SERIES:
                    _dataset(series, key, np.array([getattr(r, key) for r in records]))
                for key in INCLUSION_FIELDS:
                    data = np.array([getattr(r, key) for r in records])
                    _dataset(fields, key, data, compression="gzip", compression_opts=1, shuffle=True,
                             chunks=(1,) + data.shape[1:])
            if state is not None:
                group = f.create_group("state")
                group.attrs["keys"] = list(state)
                for key, value in state.items():
                    _dataset(group, key, value)
        os.replace(writing, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(writing)
        raise


class _Reader:
    """Reads the parts of an open result file; every failure is a one-line ParameterError naming the file."""

    def __init__(self, f, path, name):
        self.file, self.path, self.name = f, path, name
        self.format = None

    def fail(self, what):
        return ParameterError(f"{self.name}: {self.path!r} is damaged: {what}")

    def attribute(self, key, group="/"):
        if key not in self.file[group].attrs:
            raise self.fail(f"attribute {key!r} of {group!r} is missing")
        return self.file[group].attrs[key]

    def dataset(self, key):
        h5py = _h5py()
        dataset = self.file.get(key)
        if not isinstance(dataset, h5py.Dataset):
            raise self.fail(f"dataset {key!r} is missing")
        if self.format >= 2 and not dataset.fletcher32:
            raise self.fail(f"dataset {key!r} has no checksum (every dataset of format {self.format} has one)")
        try:
            value = dataset[()]
        except OSError as exc:
            raise self.fail(f"dataset {key!r} fails its checksum or cannot be decompressed ({_reason(exc)})") \
                from exc
        return value[0] if dataset.attrs.get("scalar") == 1 and value.shape == (1,) else value


def read(path, *, name="path"):
    """``(configuration dict, records, state or None)`` from a file written by :func:`save`.

    ``name`` is the parameter named in messages (``"resume"`` for a
    checkpoint). A missing, foreign, damaged or truncated file raises
    :class:`ParameterError` naming the file (and the dataset).
    """
    from .result import StepRecord
    h5py = _h5py()
    path = _path(path, name=name)
    if not os.path.isfile(path):
        raise ParameterError(f"{name}: no result file at {path!r}")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise ParameterError(f"{name}: {path!r} is not a readable HDF5 file: another kind of file, or damaged "
                             f"or truncated ({_reason(exc)})") from exc
    with f:
        reader = _Reader(f, path, name)
        try:
            reader.format = f.attrs.get("format")
            if reader.format not in READABLE:
                newer = isinstance(reader.format, (int, np.integer)) and reader.format > FORMAT
                raise ParameterError(f"{name}: {path!r} is not a result file of format "
                                     f"{', '.join(map(str, READABLE[:-1]))} or {READABLE[-1]}"
                                     + (f" (format {reader.format}: written by a newer framework)" if newer else ""))
            text = reader.attribute("configuration")
            if reader.format >= 2 and _checksum(reader.attribute("framework_version"), text) \
                    != reader.attribute("checksum"):
                raise reader.fail("the attributes 'framework_version' and 'configuration' fail their checksum")
            configuration = json.loads(text)
            series = {key: reader.dataset(f"series/{key}") for key in SERIES}
            fields = {key: reader.dataset(f"fields/{key}") for key in FIELDS}
            if reader.format >= 3 and "fields/eigenstrain" in f:  # a run with inhomogeneities
                series.update({key: reader.dataset(f"series/{key}") for key in INCLUSION_SERIES
                               if f"series/{key}" in f})
                fields.update({key: reader.dataset(f"fields/{key}") for key in INCLUSION_FIELDS})
            state = None
            if "state" in f:
                keys = reader.attribute("keys", "state") if reader.format >= 2 else list(f["state"])
                state = {key: reader.dataset(f"state/{key}") for key in keys}
        except (OSError, KeyError, RuntimeError, json.JSONDecodeError) as exc:  # HDF5 metadata or JSON
            raise reader.fail(_reason(exc)) from exc
        steps = len(series["time"])
        for key, value in list(series.items()) + list(fields.items()):
            if len(value) != steps:
                raise reader.fail(f"{key!r} holds {len(value)} steps, 'series/time' {steps}")
    records = [StepRecord(index=int(series["index"][k]), time=series["time"][k], load=series["load"][k],
                          approach=series["approach"][k], pressure=fields["pressure"][k],
                          displacement=fields["displacement"][k], gap=fields["gap"][k],
                          iterations=int(series["iterations"][k]), residual=series["residual"][k],
                          success=bool(series["success"][k]), tilt=tuple(series["tilt"][k]),
                          **({} if "eigenstrain" not in fields else dict(
                              eigenstrain=fields["eigenstrain"][k], inclusion_stress=fields["inclusion_stress"][k],
                              couplings=int(series["couplings"][k]),
                              inclusion_start=(tuple(int(v) for v in series["inclusion_start"][k])
                                               if "inclusion_start" in series else None))))
               for k in range(steps)]
    return configuration, records, state


def load_result(path):
    """The :class:`Result` saved in ``path`` (with its configuration rebuilt)."""
    from .config import build
    from .result import Result
    from .simulation import Options
    configuration, records, _ = read(path)
    missing = [key for key in ("grid", "material", "indenter", "schedule") if key not in configuration]
    if missing:
        raise ParameterError(f"path: {os.fspath(path)!r} is damaged: its configuration has no {missing}")
    parts = {key: build(configuration[key], name=key) for key in ("grid", "material", "indenter", "schedule")}
    options = build(configuration["options"], name="options") if configuration.get("options") else Options()
    inclusions = build(configuration["inclusions"], name="inclusions") if configuration.get("inclusions") else None
    result = Result(parts["grid"], parts["material"], parts["indenter"], parts["schedule"], options,
                    inclusions=inclusions)
    result.version = configuration.get("framework_version", result.version)
    for record in records:
        result.append(record)
    return result
