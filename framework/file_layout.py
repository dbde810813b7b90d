"""The layout of result files: what each format holds, and the checks of a file's structure before its data are read.

A file's *structure* is every group and dataset below the root with its shape, dtype, chunks,
HDF5 filters and attributes: what HDF5 keeps in the file's metadata, apart from the stored
numbers. Formats 4 and 5 write it as the JSON attribute ``manifest``, under the file's checksum, and the
reader compares it with the structure it finds. A flipped bit in a dataset's name, a dimension or
an attribute then fails the comparison instead of dropping a dataset: ``series/inclusion_start``
read as ``series/inclusion_stbrt`` would lose the inhomogeneities' positions and shift their
stresses on the grid. The manifest lists the optional datasets the file holds (those of the
inhomogeneities, the checkpoint's state) under ``optional``; every other dataset is required.

Files of formats 1 to 3 have no manifest: their structure is checked against the names,
attributes, shapes and dtypes their format allows, so a name that no format writes is refused too.

Whatever its format, a file that would take data from elsewhere is refused: links (external,
soft or user-defined: the framework writes none), external storage, virtual datasets, and HDF5
filters other than gzip, shuffle and Fletcher-32 (another filter would load a plugin).
"""
import json

SERIES = ("index", "time", "load", "approach", "iterations", "residual", "success", "tilt")
FIELDS = ("pressure", "displacement", "gap")
#: Written only for a run with inhomogeneities (all its records carry them); format 3 and later.
INCLUSION_SERIES = ("couplings", "inclusion_start")
INCLUSION_FIELDS = ("eigenstrain", "inclusion_stress")
INCLUSION = frozenset({f"series/{key}" for key in INCLUSION_SERIES} | {f"fields/{key}" for key in INCLUSION_FIELDS})
#: The estimated time-stepping error of each step (``Result.time_error``): format 4 and later, optional (files
#: written before it lack it and read as NaN).
TIME_ERROR = "series/time_error"
#: The eigenstrains under the matrix's relaxation modulus (``StepRecord.relaxed_eigenstrain``, a viscoelastic
#: matrix's): format 5 and later, optional (the eigenstrains' datasets with it).
RELAXED = "fields/relaxed_eigenstrain"
#: The groups and datasets every result file holds; the others (the inhomogeneities', the state) are optional.
REQUIRED = frozenset({"series", "fields"} | {f"series/{key}" for key in SERIES} | {f"fields/{key}" for key in FIELDS})
#: The HDF5 filters a result file may use: gzip (deflate), shuffle and Fletcher-32.
FILTERS = {1: "gzip", 2: "shuffle", 3: "fletcher32"}
FLETCHER32 = 3
#: The file attributes of each format.
ROOT_ATTRIBUTES = {1: {"format", "framework_version", "configuration"},
                   2: {"format", "framework_version", "configuration", "checksum"},
                   3: {"format", "framework_version", "configuration", "checksum"},
                   4: {"format", "framework_version", "configuration", "manifest", "checksum"},
                   5: {"format", "framework_version", "configuration", "manifest", "checksum"},
                   6: {"format", "framework_version", "configuration", "manifest", "checksum"}}
#: The first format whose inhomogeneity fields lie on the inhomogeneities' cuboids, ``(steps, N, 6)`` (the box's
#: cuboids :func:`framework.inclusions.field.body_cuboids` names); before it on their box, ``(steps, m1, m2, m3, 6)``.
CUBOID_FIELDS = 6
#: File attributes of a sweep's point (the point, the wall time of its run), allowed in every format: from format 5
#: on written by :func:`framework.io.save` under the file's checksum; before, added after writing, outside it.
ANNOTATIONS = frozenset({"sweep_point", "sweep_wall_time"})
#: dtype kinds of each dataset (NumPy's ``dtype.kind``); the state's arrays are numbers of any kind.
KINDS = {"index": "iu", "iterations": "iu", "couplings": "iu", "inclusion_start": "iu", "success": "b"}
NUMBERS = "biuf"


def _names(paths, limit=3):
    paths = sorted(paths)
    return ", ".join(map(repr, paths[:limit])) + (f" and {len(paths) - limit} more" if len(paths) > limit else "")


def _plain(value):
    """An attribute's value as JSON data (a NumPy scalar or array as numbers or lists, bytes as text)."""
    if hasattr(value, "tolist"):
        value = value.tolist()
    if isinstance(value, bytes):
        return value.decode("utf-8", "surrogateescape")
    if isinstance(value, list):
        return [_plain(item) for item in value]
    return value


def structure(file, refuse):
    """``{path: description}`` of every group and dataset below the root of an open h5py ``file``.

    Reads metadata only, no stored numbers. ``refuse(what)`` returns the exception raised for a
    link, external storage, a virtual dataset or a foreign filter. Groups are looked into one level
    deep (a result file's groups hold datasets only); a deeper group is described, not entered.
    """
    import h5py
    objects = {}

    def walk(group, prefix, depth):
        for key in group:
            path = prefix + key
            link = group.get(key, getlink=True)
            if isinstance(link, h5py.ExternalLink):
                raise refuse(f"{path!r} is an external link to {link.path!r} in the file {link.filename!r}")
            if isinstance(link, h5py.SoftLink):
                raise refuse(f"{path!r} is a soft link to {link.path!r}")
            if not isinstance(link, h5py.HardLink):
                raise refuse(f"{path!r} is a user-defined link")
            item = group[key]
            if isinstance(item, h5py.Group):
                objects[path] = {"kind": "group", "attributes": _attributes(item)}
                if depth == 0:
                    walk(item, path + "/", 1)
            elif isinstance(item, h5py.Dataset):
                objects[path] = _dataset(item, path, refuse)
            else:
                objects[path] = {"kind": type(item).__name__}
    walk(file, "", 0)
    return objects


def _attributes(item):
    return {key: _plain(item.attrs[key]) for key in item.attrs}


def _dataset(dataset, path, refuse):
    if dataset.is_virtual:
        raise refuse(f"dataset {path!r} is virtual: its data are in other files")
    if dataset.external:
        raise refuse(f"dataset {path!r} stores its data in the external file(s) "
                     f"{_names(str(name) for name, *_ in dataset.external)}")
    properties = dataset.id.get_create_plist()
    filters = [properties.get_filter(k)[0] for k in range(properties.get_nfilters())]
    foreign = [code for code in filters if code not in FILTERS]
    if foreign:
        raise refuse(f"dataset {path!r} uses the HDF5 filter(s) {foreign}; a result file uses only "
                     f"{', '.join(FILTERS.values())}")
    shape = dataset.shape
    return {"kind": "dataset", "shape": None if shape is None else list(shape), "dtype": dataset.dtype.str,
            "chunks": list(dataset.chunks) if dataset.chunks else None, "filters": filters,
            "attributes": _attributes(dataset)}


def manifest(objects):
    """The ``manifest`` attribute of a file of the current format whose structure is ``objects``."""
    optional = sorted(set(objects) - REQUIRED)
    return json.dumps({"objects": objects, "optional": optional}, sort_keys=True, separators=(",", ":"))


def _later_format_marks(objects):
    """What, in a file claiming format 1, only a later format writes (the file attributes aside)."""
    marks = [f"a Fletcher-32 checksum on {path!r}" for path, item in objects.items()
             if FLETCHER32 in item.get("filters", ())]
    marks += [f"the attribute {key!r} on {path!r}" for path, item in objects.items()
              for key in item.get("attributes", ()) if key in ("scalar", "keys")]
    return marks + [f"the dataset {path!r}" for path in sorted(INCLUSION & set(objects))]


def check_root(format, root, fail, forged):
    """The file attributes ``root`` (a set of names) of a file claiming ``format``."""
    expected = ROOT_ATTRIBUTES[format]
    for key in ("configuration", "framework_version", "checksum", "manifest"):
        if key in expected and key not in root:
            raise fail(f"attribute {key!r} of '/' is missing")
    if format == 1 and root & {"checksum", "manifest"}:
        raise forged(f"the file attribute(s) {_names(root & {'checksum', 'manifest'})}")
    extra = root - expected - ANNOTATIONS
    if extra:
        raise fail(f"it has the file attribute(s) {_names(extra)}, which no file of format {format} has")


def check_layout(objects, format, fail, forged):
    """The names, attributes and filters of ``objects`` (see :func:`structure`) against ``format``.

    Returns the names of the state's datasets (None without a state group).
    """
    marks = _later_format_marks(objects) if format == 1 else []
    if marks:
        raise forged(marks[0])
    allowed = REQUIRED | {"state"} | (INCLUSION if format >= 3 else set()) | ({TIME_ERROR} if format >= 4 else set()) \
        | ({RELAXED} if format >= 5 else set())
    for path, item in objects.items():
        group = path.split("/")[0]
        if path not in allowed and not (group == "state" and path.count("/") == 1):
            raise fail(f"it holds {path!r}, which no result file of format {format} has")
        kind = "group" if "/" not in path else "dataset"
        if item["kind"] != kind:
            raise fail(f"{path!r} is a {item['kind']}, not a {kind}")
    for path in sorted(REQUIRED):
        if path not in objects:
            raise fail(f"{'group' if '/' not in path else 'dataset'} {path!r} is missing")
    present = INCLUSION & set(objects)
    needed = {"fields/eigenstrain", "fields/inclusion_stress", "series/couplings"} \
        | ({"series/inclusion_start"} if format >= 4 else set())   # format 3 wrote the box's start later
    if present and needed - present:
        raise fail(f"it holds {_names(present)} of the inhomogeneities' datasets but not {_names(needed - present)}")
    if RELAXED in objects and not present:
        raise fail(f"it holds {RELAXED!r} but none of the inhomogeneities' datasets")
    for path, item in objects.items():
        allowed_attributes = ({"keys"} if path == "state" and format in (2, 3) else set()) if item["kind"] == "group" \
            else ({"scalar"} if format >= 2 else set())
        extra = set(item["attributes"]) - allowed_attributes
        if extra:
            raise fail(f"{path!r} has the attribute(s) {_names(extra)}, which no file of format {format} has")
        if item["attributes"].get("scalar", 1) != 1:
            raise fail(f"{path!r} has the attribute 'scalar' = {item['attributes']['scalar']!r}; expected 1")
        if format >= 2 and item["kind"] == "dataset" and (FLETCHER32 not in item["filters"] or not item["chunks"]):
            raise fail(f"dataset {path!r} has no checksum (every dataset of format {format} has one)")
    if "state" not in objects:
        return None
    names = [path[len("state/"):] for path in objects if path.startswith("state/")]
    if format in (2, 3):
        keys = objects["state"]["attributes"].get("keys")
        if not isinstance(keys, list) or not all(isinstance(key, str) for key in keys):
            raise fail(f"the attribute 'keys' of 'state' is missing or not a list of names, got {keys!r}")
        for key in keys:
            if key not in names:
                raise fail(f"dataset {'state/' + key!r} is missing")
        extra = set(names) - set(keys)
        if extra:
            raise fail(f"it holds {_names('state/' + key for key in extra)}, which 'state' does not list")
        return list(keys)
    return names


def check_manifest(objects, text, fail):
    """The structure ``objects`` against the ``manifest`` attribute ``text`` (already under the file's checksum)."""
    try:
        listed = json.loads(text)
        recorded, optional = listed["objects"], listed["optional"]
        if not (isinstance(recorded, dict) and all(isinstance(item, dict) for item in recorded.values())
                and isinstance(optional, list)):
            raise TypeError("not an object and a list")
    except (ValueError, TypeError, KeyError) as exc:
        raise fail(f"its manifest cannot be read ({type(exc).__name__}: {exc})") from exc
    found = json.loads(json.dumps(objects))     # tuples as lists, as in the manifest
    if found != recorded:
        differences = [f"{recorded[path].get('kind', 'object')} {path!r} is missing"
                       for path in sorted(set(recorded) - set(found))]
        differences += [f"it holds {path!r}, which is not in its manifest"
                        for path in sorted(set(found) - set(recorded))]
        differences += [f"{path!r} differs from its manifest ({_difference(found[path], recorded[path])})"
                        for path in sorted(set(found) & set(recorded)) if found[path] != recorded[path]]
        raise fail("; ".join(differences[:3]) + (f"; and {len(differences) - 3} more" if len(differences) > 3 else "")
                   + " (the structure found differs from the one its manifest lists)")
    unlisted = set(found) - REQUIRED - set(optional)
    if unlisted or set(optional) - set(found):
        raise fail(f"its manifest's optional datasets {optional} do not match those it holds")


def _difference(found, recorded):
    keys = sorted(key for key in set(found) | set(recorded) if found.get(key) != recorded.get(key))
    return "; ".join(f"{key} {found.get(key)!r} in the file, {recorded.get(key)!r} in the manifest" for key in keys)


def grid_shape(configuration, fail):
    """``(n1, n2, layers)`` of the configuration's grid."""
    grid = configuration.get("grid") if isinstance(configuration, dict) else None
    shape = grid.get("shape") if isinstance(grid, dict) else None
    layers = grid.get("layers", 0) if isinstance(grid, dict) else None
    if not (isinstance(shape, list) and len(shape) == 2 and all(_count(n) and n > 0 for n in shape)
            and _count(layers)):
        raise fail(f"its configuration has no grid shape [n1, n2] (and layers) of positive integers, got "
                   f"{grid!r:.200}")
    return shape[0], shape[1], layers


def _count(value):
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def check_shapes(objects, configuration, fail, format):
    """Every dataset's shape and dtype against the configuration's grid and the steps of ``series/time``."""
    n1, n2, layers = grid_shape(configuration, fail)
    time = objects["series/time"]["shape"]
    if not time or len(time) != 1:
        raise fail(f"dataset 'series/time' has shape {time!r}; expected (steps,)")
    steps = time[0]
    why = f"the configuration's grid has {n1} x {n2} cells and 'series/time' {steps} steps"
    expected = {f"series/{key}": [steps] for key in SERIES + INCLUSION_SERIES + ("time_error",)}
    expected.update({"series/tilt": [steps, 2], "series/inclusion_start": [steps, 3]})
    expected.update({f"fields/{key}": [steps, n1, n2] for key in FIELDS})
    box = objects.get("fields/eigenstrain", {}).get("shape")
    if box is not None and format >= CUBOID_FIELDS:
        if not (len(box) == 3 and box[0] == steps and box[2] == 6 and 0 < box[1] <= n1 * n2 * layers):
            raise fail(f"dataset 'fields/eigenstrain' has shape {tuple(box)}; expected (steps, N, 6) with N at most "
                       f"the {n1 * n2 * layers} cuboids of the grid ({why})")
        expected["fields/inclusion_stress"] = expected[RELAXED] = box
    elif box is not None:
        if not (len(box) == 5 and box[0] == steps and box[4] == 6 and 0 < box[1] <= n1 and 0 < box[2] <= n2
                and 0 < box[3] <= layers):
            raise fail(f"dataset 'fields/eigenstrain' has shape {tuple(box)}; expected (steps, m1, m2, m3, 6) "
                       f"with a box of at most {n1} x {n2} x {layers} cuboids ({why})")
        expected["fields/inclusion_stress"] = expected[RELAXED] = box
    for path, item in objects.items():
        if item["kind"] != "dataset":
            continue
        key = path.split("/")[-1]
        kinds = NUMBERS if path.startswith("state/") else KINDS.get(key, "f")
        shape = item["shape"]
        if shape is None or (path in expected and shape != expected[path]):
            raise fail(f"dataset {path!r} has shape {shape if shape is None else tuple(shape)}; expected "
                       f"{tuple(expected.get(path, ()))} ({why})")
        if item["dtype"][1:2] not in tuple(kinds) and 0 not in shape:   # a run of no steps wrote float zeros
            names = dict.fromkeys({"b": "booleans", "i": "integers", "u": "integers", "f": "floats"}[k] for k in kinds)
            raise fail(f"dataset {path!r} has the dtype {item['dtype']!r}; expected {' or '.join(names)}")
