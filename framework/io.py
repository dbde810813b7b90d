"""Results on disk: HDF5 files that hold everything, and the checkpoints of long runs.

Layout, ``format = 6`` (the file attribute ``format``, an integer raised at
every change of layout): file attributes ``framework_version``, ``format``,
``configuration`` (JSON of :meth:`Result.configuration`), ``manifest`` (JSON:
the file's structure, see :mod:`framework.file_layout`), the optional
annotations a sweep passes to :func:`save` (``sweep_point``, the point's JSON,
and ``sweep_wall_time`` [s]) and ``checksum`` (CRC-32 of the UTF-8 text
``framework_version + "\\n" + configuration + "\\n" + manifest + "\\n" +
annotations``, ``annotations`` the JSON object of those present, ``{}``
without them); group ``series`` (one dataset per step series: ``index``,
``time``, ``load``, ``approach``, ``iterations``, ``residual``, ``success``,
``tilt``);
group ``fields`` (``pressure``, ``displacement``, ``gap``, each ``(steps, n1,
n2)``, one gzip chunk per step); for a run with inhomogeneities also
``series/couplings``, ``series/inclusion_start`` and ``fields/eigenstrain``,
``fields/inclusion_stress`` (each ``(steps, N, 6)`` on the inhomogeneities'
``N`` cuboids of their box, :func:`~framework.inclusions.field.body_cuboids`,
see :class:`~framework.result.StepRecord`; formats 3 to 5 held them on the
whole box, ``(steps, m1, m2, m3, 6)``, which reading cuts to those cuboids; with a
viscoelastic matrix, optional, ``fields/relaxed_eigenstrain`` of that shape) with the
inhomogeneities in the configuration (key ``inclusions``); and, in a
checkpoint, group ``state`` (the time stepper's history and the next station,
and the last eigenstrains). The manifest lists those optional datasets.

Nothing is read unchecked. The manifest (names, shapes, dtypes, chunks,
filters and attributes of every group and dataset) is compared with the
structure found, so a flipped bit in a name or a dimension is found before any
data are read; every dataset is chunked and carries HDF5's Fletcher-32
checksum filter, which HDF5 verifies at every read; and the file is written
with HDF5's 1.10 file format, whose metadata blocks (superblock, object
headers, B-trees, heap headers) carry HDF5's own checksums. The texts are
fixed-length UTF-8 strings, kept in the root's object header under its
checksum, and nothing is stored as a variable-length string: those live in
HDF5's global heap, which has no checksum, and a flipped bit in the size of a
heap collection makes HDF5 2.0 loop forever while it reads the string (format
4 wrote its texts so). From format 5 on, the type of a text attribute is
checked before its value is read. (Texts longer than 64 KiB, e.g. the
configuration of many inhomogeneities, are moved by HDF5 out of the header
into its dense attribute storage; there only the file's CRC-32 guards their
bytes, which are read as plain bytes: nothing to hang on.) The shapes must agree with the configuration's grid. A file that takes data from
elsewhere (links, external storage, virtual datasets, filters that load
plugins) is refused. Every failure raises :class:`~framework.errors.FileError`
(a :class:`ParameterError`) naming the file and what is wrong, on one line. A
scalar (a stepper's time, the next station) is stored as a one-element dataset
with the attribute ``scalar = 1``, as chunked datasets need a dimension.

Older formats are read, with every check their files have data for:

- format 4 is format 5 with the texts as variable-length strings (in HDF5's
  global heap: a flipped bit there can hang HDF5 before any check of ours
  runs; load and save such a file to rewrite it in format 5) and the checksum
  over ``framework_version + "\\n" + configuration + "\\n" + manifest``; a sweep
  added ``sweep_point`` and ``sweep_wall_time`` after writing, outside the
  checksum.
- format 3 is format 4 without the manifest (its state group lists its
  datasets in the attribute ``keys``; ``series/inclusion_start`` may be
  absent); format 2 is format 3 without the inhomogeneities' datasets (added
  with format 3, so that an older framework refuses a file whose
  inhomogeneities it would drop). Their checksum covers ``framework_version +
  "\\n" + configuration``, their structure is checked against the names,
  attributes, shapes and dtypes the format allows.
- format 1 (files written before the checksums: the same groups and names,
  datasets without the filter, scalars stored as such, no ``checksum``
  attribute) is read with an :class:`~framework.errors.UncheckedFileWarning`:
  its checksums are missing by design. A file claiming format 1 that holds
  anything a later format writes (a ``checksum`` or ``manifest`` attribute, a
  Fletcher-32 filter, the attributes ``scalar`` or ``keys``, inhomogeneities)
  is refused: its format attribute is damaged or forged, and reading it would
  turn its checks off.

A format above 5 was written by a newer framework and is refused.

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
import warnings
import zlib

import numpy as np

from . import file_layout
from .errors import FileError, FrameworkError, ParameterError, UncheckedFileWarning
from .file_layout import FIELDS, INCLUSION_FIELDS, INCLUSION_SERIES, SERIES  # noqa: F401 (the layout's names)

FORMAT = 6
READABLE = (1, 2, 3, 4, 5, 6)
#: The first format whose texts are fixed-length strings (none in HDF5's global heap) and whose checksum covers the
#: annotations.
FIXED_TEXTS = 5
#: HDF5's file format written (lowest, highest): 1.10's, whose metadata blocks carry checksums that HDF5
#: verifies when it reads them (the 1.0 format's have none); HDF5 1.10 (2018) and later read it.
LIBVER = ("v110", "v110")
#: The exceptions h5py, NumPy and JSON raise on damaged metadata (a wrong type, size or text where a file's
#: own data should be): each becomes a one-line FileError naming the file.
DAMAGE = (OSError, KeyError, RuntimeError, ValueError, TypeError, IndexError, OverflowError, MemoryError)


def _h5py():
    try:
        import h5py
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise FrameworkError("saving results needs h5py: pip install 'viscocontact[io]'") from exc
    return h5py


def _reason(exc):
    """An OS or HDF5 error on one line, without the errno prefix (undecodable bytes escaped: it can be printed)."""
    text = " ".join(str(getattr(exc, "strerror", None) or exc).split())
    return text.encode("utf-8", "backslashreplace").decode("utf-8")


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


def _type_name(kind):
    """An HDF5 datatype (``h5py.h5t.TypeID``) in words: "a fixed-length string", "an integer", ..."""
    import h5py
    if isinstance(kind, h5py.h5t.TypeStringID):
        return "a variable-length string" if kind.is_variable_str() else "a fixed-length string"
    names = {h5py.h5t.TypeIntegerID: "an integer", h5py.h5t.TypeFloatID: "a float"}
    return names.get(type(kind), f"of the HDF5 type class {kind.get_class()}")


def _checksum(*texts):
    """CRC-32 of the UTF-8 texts joined by newlines (text read from damaged bytes: those bytes)."""
    return zlib.crc32("\n".join(texts).encode("utf-8", "surrogateescape"))


def _store_text(attributes, key, text):
    """``text`` as a fixed-length UTF-8 string attribute: in the object header, under HDF5's checksum.

    A ``str`` attribute would be a variable-length string, kept in HDF5's global heap, which has no checksum (a
    flipped bit in its collection's size hangs HDF5 2.0 when the string is read).
    """
    import h5py
    data = text.encode("utf-8", "surrogateescape")
    attributes.create(key, np.array(data, dtype=h5py.string_dtype("utf-8", max(len(data), 1))))


def _annotations(annotations):
    """The annotations :func:`save` writes, checked: ``{"sweep_point": str, "sweep_wall_time": float}`` (either)."""
    if annotations is None:
        return {}
    if not isinstance(annotations, dict) or not set(annotations) <= file_layout.ANNOTATIONS:
        raise ParameterError(f"annotations must be a dict with some of the keys "
                             f"{sorted(file_layout.ANNOTATIONS)}, got {annotations!r:.200}")
    out = {}
    if "sweep_point" in annotations:
        point = annotations["sweep_point"]
        if not isinstance(point, str):
            raise ParameterError(f"annotations['sweep_point'] must be a str (the point's JSON), got {point!r:.200}")
        out["sweep_point"] = point
    if "sweep_wall_time" in annotations:
        wall_time = annotations["sweep_wall_time"]
        if not (isinstance(wall_time, (int, float, np.integer, np.floating)) and not isinstance(wall_time, bool)
                and np.isfinite(wall_time) and wall_time >= 0):
            raise ParameterError(f"annotations['sweep_wall_time'] must be a finite number of seconds >= 0, got "
                                 f"{wall_time!r}")
        out["sweep_wall_time"] = float(wall_time)
    return out


def _annotation_text(annotations):
    """The checksummed text of the annotations (floats as their shortest exact repr)."""
    return json.dumps(annotations, sort_keys=True, separators=(",", ":"))


def _dataset(group, name, data, **options):
    """A chunked dataset with the Fletcher-32 checksum (a scalar as one element marked ``scalar``)."""
    data = np.asarray(data)
    scalar = data.ndim == 0
    dataset = group.create_dataset(name, data=data.reshape(1) if scalar else data, fletcher32=True,
                                   **{"chunks": True, **options})
    if scalar:
        dataset.attrs["scalar"] = 1


def save(result, path, state=None, *, name="path", annotations=None):
    """Write ``result`` (and a stepper ``state`` for a checkpoint) to the HDF5 file ``path``.

    ``annotations``: ``{"sweep_point": JSON text, "sweep_wall_time": seconds}``
    (either, or None), written as file attributes under the file's checksum.
    Raises :class:`ParameterError` naming ``name`` when ``path`` is a folder or
    its folder is missing or not writable (see :func:`check_target`), naming
    ``annotations`` when they are not such a dict.
    """
    h5py = _h5py()
    annotations = _annotations(annotations)
    path = check_target(path, name=name)
    writing = temporary(path)
    records = result.records
    configuration = json.dumps(result.configuration())
    try:
        with h5py.File(writing, "w", libver=LIBVER) as f:
            f.attrs["format"] = FORMAT
            _store_text(f.attrs, "framework_version", result.version)
            _store_text(f.attrs, "configuration", configuration)
            if "sweep_point" in annotations:
                _store_text(f.attrs, "sweep_point", annotations["sweep_point"])
            if "sweep_wall_time" in annotations:
                f.attrs["sweep_wall_time"] = annotations["sweep_wall_time"]
            series = f.create_group("series")
            for key in SERIES:
                values = [getattr(r, key) for r in records]
                _dataset(series, key, np.array(values, dtype=float if key == "tilt" else None) if values
                         else np.zeros((0, 2) if key == "tilt" else 0))
            _dataset(series, "time_error", np.array([r.time_error for r in records], dtype=float))  # optional
            fields = f.create_group("fields")
            shape = (len(records),) + tuple(result.grid.shape)
            for key in FIELDS:
                data = np.array([getattr(r, key) for r in records]) if records else np.zeros(shape)
                _dataset(fields, key, data, compression="gzip", compression_opts=1, shuffle=True,
                         chunks=(1,) + shape[1:] if records else True)  # one chunk per step
            if records and records[0].eigenstrain is not None:
                for key in INCLUSION_SERIES:
                    _dataset(series, key, np.array([getattr(r, key) for r in records]))
                relaxed = ("relaxed_eigenstrain",) if all(r.relaxed_eigenstrain is not None for r in records) else ()
                for key in INCLUSION_FIELDS + relaxed:
                    data = np.array([getattr(r, key) for r in records])
                    _dataset(fields, key, data, compression="gzip", compression_opts=1, shuffle=True,
                             chunks=(1,) + data.shape[1:])
            if state is not None:
                group = f.create_group("state")
                for key, value in state.items():
                    _dataset(group, key, value)
            manifest = file_layout.manifest(file_layout.structure(f, refuse=FileError))
            _store_text(f.attrs, "manifest", manifest)
            f.attrs["checksum"] = _checksum(result.version, configuration, manifest, _annotation_text(annotations))
        os.replace(writing, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(writing)
        raise


class _Reader:
    """Reads the parts of an open result file; every failure is a one-line FileError naming the file."""

    def __init__(self, f, path, name):
        self.file, self.path, self.name = f, path, name
        self.format = None

    def fail(self, what):
        return FileError(f"{self.name}: {self.path!r} is damaged: {what}")

    def refuse(self, what):
        return FileError(f"{self.name}: {self.path!r} is refused: {what}; a result file holds all its data itself, "
                         f"so links, external storage and plugin filters are not followed")

    def forged(self, what):
        return FileError(f"{self.name}: {self.path!r} is damaged or forged: it claims format 1 (written before "
                         f"checksums) but has {what}, which only later formats write; it is not read unchecked")

    def stored_type(self, key):
        """The HDF5 type of the root's attribute ``key``, from the object header (its value is not read)."""
        return self.file.attrs.get_id(key).get_type()

    def text(self, key):
        """A text attribute of the root as ``str`` (undecodable bytes kept as surrogates for the checksum).

        From format 5 on, its type is checked before its value is read: only a fixed-length string is read, as a
        variable-length one would be read from HDF5's global heap, which no checksum guards.
        """
        if key not in self.file.attrs:
            raise self.fail(f"attribute {key!r} of '/' is missing")
        if self.format >= FIXED_TEXTS:
            kind = self.stored_type(key)
            if _type_name(kind) != "a fixed-length string":
                raise self.fail(f"attribute {key!r} of '/' is {_type_name(kind)}; format {self.format} stores its "
                                f"texts as fixed-length strings")
        value = self.file.attrs[key]
        if isinstance(value, bytes):
            value = value.decode("utf-8", "surrogateescape")
        if not isinstance(value, str):
            raise self.fail(f"attribute {key!r} of '/' is not text, got a {type(value).__name__}")
        return value

    def number(self, key, kind):
        """The root's attribute ``key``, one number of ``kind`` ("an integer" or "a float"), its type checked first."""
        found = _type_name(self.stored_type(key))
        if found != kind:
            raise self.fail(f"attribute {key!r} of '/' is {found}; expected {kind}")
        value = self.file.attrs[key]
        if np.shape(value) != ():
            raise self.fail(f"attribute {key!r} of '/' has the shape {np.shape(value)}; expected one number")
        return value

    def annotations(self):
        """The annotations of a file of format 5 or later (checked by the file's checksum), as :func:`save` got them."""
        out = {}
        if "sweep_point" in self.file.attrs:
            out["sweep_point"] = self.text("sweep_point")
        if "sweep_wall_time" in self.file.attrs:
            out["sweep_wall_time"] = float(self.number("sweep_wall_time", "a float"))
        return out

    def check_format(self):
        value = self.file.attrs.get("format") if "format" in self.file.attrs \
            and _type_name(self.stored_type("format")) == "an integer" else None   # no string read unchecked
        if isinstance(value, np.ndarray) and value.shape in ((), (1,)):
            value = value.reshape(-1)[0]
        if not isinstance(value, (int, np.integer)) or isinstance(value, (bool, np.bool_)) or value not in READABLE:
            newer = isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)) and value > FORMAT
            raise FileError(f"{self.name}: {self.path!r} is not a result file of format "
                            f"{', '.join(map(str, READABLE[:-1]))} or {READABLE[-1]}"
                            + (f" (format {value}: written by a newer framework)" if newer else ""))
        self.format = int(value)

    def dataset(self, key):
        dataset = self.file[key]
        try:
            value = dataset[()]
        except OSError as exc:
            raise self.fail(f"dataset {key!r} fails its checksum or cannot be decompressed ({_reason(exc)})") \
                from exc
        return value[0] if dataset.attrs.get("scalar") == 1 and value.shape == (1,) else value

    def contents(self):
        """``(configuration, series, fields, state)`` with every check of the file's format passed."""
        f = self.file
        self.check_format()
        file_layout.check_root(self.format, set(f.attrs), self.fail, self.forged)
        version, text = self.text("framework_version"), self.text("configuration")
        texts = {"framework_version": version, "configuration": text}
        if self.format >= 4:
            texts["manifest"] = self.text("manifest")
        annotations = self.annotations() if self.format >= FIXED_TEXTS else None
        if self.format >= 2:
            stored = self.number("checksum", "an integer")
            if _checksum(*texts.values(), *([] if annotations is None else [_annotation_text(annotations)])) != stored:
                names = list(texts) + sorted(annotations or ())
                raise self.fail(f"the attributes {', '.join(map(repr, names[:-1]))} and {names[-1]!r} fail their "
                                f"checksum")
        manifest = texts.get("manifest")
        configuration = json.loads(text)
        if not isinstance(configuration, dict):
            raise self.fail(f"its configuration is not a JSON object, got a {type(configuration).__name__}")
        objects = file_layout.structure(f, self.refuse)
        if manifest is not None:    # first: it names what is missing and what is not the writer's
            file_layout.check_manifest(objects, manifest, self.fail)
        state_keys = file_layout.check_layout(objects, self.format, self.fail, self.forged)
        file_layout.check_shapes(objects, configuration, self.fail, self.format)
        if self.format == 1:
            warnings.warn(UncheckedFileWarning(
                f"{self.name}: {self.path!r} is of format 1, written before result files had checksums: its "
                f"checksums are missing by design, so it is read without any check of its bytes and damage to it "
                f"would go unnoticed (save it again to add them)"), stacklevel=4)
        series = {key: self.dataset(path) for path in objects if path.startswith("series/")
                  for key in [path[len("series/"):]]}
        fields = {key: self.dataset(path) for path in objects if path.startswith("fields/")
                  for key in [path[len("fields/"):]]}
        state = None if state_keys is None else {key: self.dataset(f"state/{key}") for key in state_keys}
        return configuration, series, fields, state


def read(path, *, name="path"):
    """``(configuration dict, records, state or None)`` from a file written by :func:`save`.

    ``name`` is the parameter named in messages (``"resume"`` for a
    checkpoint). A missing, foreign, damaged, truncated or refused file raises
    :class:`~framework.errors.FileError` naming the file (and the dataset).
    A file of format 1 gives an :class:`~framework.errors.UncheckedFileWarning`.
    """
    h5py = _h5py()
    path = _path(path, name=name)
    if not os.path.isfile(path):
        raise FileError(f"{name}: no result file at {path!r}")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise FileError(f"{name}: {path!r} is not a readable HDF5 file: another kind of file, or damaged "
                        f"or truncated ({_reason(exc)})") from exc
    reader = _Reader(f, path, name)
    try:
        with f:
            configuration, series, fields, state = reader.contents()
        return configuration, _records(series, fields), state
    except FrameworkError:
        raise
    except DAMAGE as exc:   # HDF5 metadata, JSON, or values of the wrong type
        raise reader.fail(f"{type(exc).__name__}: {_reason(exc)}") from exc


def _records(series, fields):
    """The step records of the arrays read (their shapes checked)."""
    from .result import StepRecord
    inclusions = "eigenstrain" in fields
    return [StepRecord(index=int(series["index"][k]), time=series["time"][k], load=series["load"][k],
                       approach=series["approach"][k], pressure=fields["pressure"][k],
                       displacement=fields["displacement"][k], gap=fields["gap"][k],
                       iterations=int(series["iterations"][k]), residual=series["residual"][k],
                       success=bool(series["success"][k]), tilt=tuple(series["tilt"][k]),
                       time_error=float(series["time_error"][k]) if "time_error" in series else float("nan"),
                       **({} if not inclusions else dict(
                           eigenstrain=fields["eigenstrain"][k], inclusion_stress=fields["inclusion_stress"][k],
                           relaxed_eigenstrain=(fields["relaxed_eigenstrain"][k] if "relaxed_eigenstrain" in fields
                                                else None),
                           couplings=int(series["couplings"][k]),
                           inclusion_start=(tuple(int(v) for v in series["inclusion_start"][k])
                                            if "inclusion_start" in series else None))))
            for k in range(len(series["time"]))]


def check_records(records, grid, inclusions, options, *, path, name):
    """The inhomogeneities' fields of ``records`` against the box the configuration places them in.

    The box's shape follows from the grid, the inhomogeneities and ``options.inclusion_margin``;
    each record's box must lie on the grid. Raises :class:`~framework.errors.FileError` naming
    ``path`` (read as parameter ``name``).
    """
    def fail(what):
        return FileError(f"{name}: {path!r} is damaged: {what}")
    holding = [record.eigenstrain is not None for record in records]
    if not records or not any(holding):
        if records and inclusions:
            raise fail("its configuration has inhomogeneities, but it holds no eigenstrains")
        return
    if not inclusions or not all(holding):
        raise fail("it holds eigenstrains, but its configuration has no inhomogeneities")
    from .inclusions.field import body_cuboids, layout
    placed = layout(grid, inclusions, options.inclusion_margin)
    start, shape, _ = placed
    cells = body_cuboids(grid, inclusions, placed, options.inclusion_geometry)
    needed = (cells[0].size, 6)
    limits = (*grid.shape, grid.layers)
    for record in records:
        fields = ("eigenstrain", "inclusion_stress") + (("relaxed_eigenstrain",) if record.relaxed_eigenstrain
                                                         is not None else ())
        shapes = {np.shape(getattr(record, key)) for key in fields}
        if shapes == {(*shape, 6)}:     # formats 3 to 5: on the whole box; the records keep the cuboids
            for key in fields:
                setattr(record, key, np.asarray(getattr(record, key))[cells])
        elif shapes != {needed}:
            raise fail(f"step {record.index}: its eigenstrains have shape {np.shape(record.eigenstrain)}; the "
                       f"configuration's inhomogeneities need {needed} (their cuboids) or, in files before format "
                       f"{file_layout.CUBOID_FIELDS}, {(*shape, 6)} (their box)")
        first = start if record.inclusion_start is None else record.inclusion_start
        if any(s < 0 or s + m > n for s, m, n in zip(first, shape, limits)):
            raise fail(f"step {record.index}: the inhomogeneities' box of {shape} cuboids from cuboid "
                       f"{tuple(first)} leaves the grid of {limits} cuboids")


def check_state(state, *, path, name):
    """A checkpoint's stepper ``state`` (None: a saved result) has the station and step index to continue from."""
    if state is None:
        return
    for key in ("station", "index"):
        value = state.get(key)
        if not (isinstance(value, np.integer) and value >= 0):
            raise FileError(f"{name}: {path!r} is damaged: its state has no {key} (an integer >= 0) to continue "
                            f"from, got {value!r}")


def load_result(path):
    """The :class:`Result` saved in ``path`` (with its configuration rebuilt).

    A missing, damaged or refused file raises :class:`~framework.errors.FileError` naming it.
    """
    from .config import build
    from .result import Result
    from .options import Options
    configuration, records, _ = read(path)
    path = os.fspath(path)
    missing = [key for key in ("grid", "material", "indenter", "schedule") if key not in configuration]
    if missing:
        raise FileError(f"path: {path!r} is damaged: its configuration has no {missing}")
    try:
        parts = {key: build(configuration[key], name=key) for key in ("grid", "material", "indenter", "schedule")}
        options = build(configuration["options"], name="options") if configuration.get("options") else Options()
        inclusions = build(configuration["inclusions"], name="inclusions") if configuration.get("inclusions") \
            else None
    except (FrameworkError, TypeError, ValueError, KeyError, AttributeError) as exc:
        raise FileError(f"path: {path!r} is damaged: its configuration does not describe a run "
                        f"({type(exc).__name__}: {_reason(exc)})") from exc
    check_records(records, parts["grid"], inclusions, options, path=path, name="path")
    result = Result(parts["grid"], parts["material"], parts["indenter"], parts["schedule"], options,
                    inclusions=inclusions)
    result.version = configuration.get("framework_version", result.version)
    for record in records:
        result.append(record)
    return result
