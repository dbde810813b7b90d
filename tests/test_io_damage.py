"""Damaged, forged and foreign result files: each ends in one line naming the file, or loads equal to the original.

The bit-flip campaign flips bits in the names and the metadata of a saved result and of a checkpoint
(a static elastic run with one inhomogeneity) and counts each flip as detected (a one-line
FileError naming the file) or harmless (the file loads equal to the original, array by array).
By default it flips a deterministic sample of one bit per byte; ``FRAMEWORK_FLIP_CAMPAIGN=full``
flips every bit of every byte outside the stored numbers (minutes).
"""
import json
import os
import warnings
import zlib

import numpy as np
import pytest

import framework as fw
from framework import errors, inclusions, io, materials

h5py = pytest.importorskip("h5py")

FULL = os.environ.get("FRAMEWORK_FLIP_CAMPAIGN") == "full"
#: Flips of the sampled campaign, per file: bytes of names, and bytes of the other metadata.
NAME_FLIPS, METADATA_FLIPS = 250, 250


def simulation():
    """A 16 x 16 x 8 grid, a stiff sphere under a spherical indenter, two loads (about 1 s)."""
    grid = fw.Grid(shape=(16, 16), size=(1e-3, 1e-3), depth=0.5e-3, layers=8)
    body = inclusions.Ellipsoid(center=(0.0, 0.0, 0.25e-3), semi_axes=(0.2e-3, 0.2e-3, 0.2e-3),
                                material=materials.Elastic(600e9, 0.25))
    return fw.Simulation(grid=grid, material=materials.Elastic(200e9, 0.3), indenter=fw.indenters.Sphere(radius=10e-3),
                         schedule=fw.schedules.Static(load=[20.0, 40.0], times=[1.0, 2.0]), inclusions=[body])


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """``(simulation, result, folder)``: ``r.h5`` the saved result, ``c.h5`` the checkpoint of the same run."""
    folder = tmp_path_factory.mktemp("damage")
    sim = simulation()
    result = sim.run(checkpoint=folder / "c.h5")
    result.save(folder / "r.h5")
    return sim, result, folder


@pytest.fixture(scope="module")
def plain(files):
    """The same run without the inhomogeneity (a few milliseconds)."""
    result = files[1]
    return fw.Simulation(grid=result.grid, material=result.material, indenter=result.indenter,
                         schedule=result.schedule).run()


@pytest.fixture
def copy(files, tmp_path):
    """``copy(name)``: a fresh copy of ``r.h5`` or ``c.h5`` in this test's folder."""
    def copy(name):
        target = tmp_path / name
        target.write_bytes((files[2] / name).read_bytes())
        return target
    return copy


def one_line(caught, path):
    message = str(caught.value)
    assert isinstance(caught.value, errors.FileError) and "\n" not in message and repr(str(path)) in message
    return message


def rewrite_checksum(path):
    """Sign ``path`` again after an edit, as a forger would: the checksum then passes."""
    with h5py.File(path, "a") as f:
        texts = [f.attrs["framework_version"], f.attrs["configuration"]] + \
            ([f.attrs["manifest"]] if f.attrs["format"] >= 4 else [])
        f.attrs["checksum"] = zlib.crc32("\n".join(texts).encode())


def resign(path):
    """Rewrite the manifest and the checksum after an edit of the structure: only the other checks can object."""
    from framework import file_layout
    with h5py.File(path, "a") as f:
        f.attrs["manifest"] = file_layout.manifest(file_layout.structure(f, refuse=AssertionError))
    rewrite_checksum(path)


# --------------------------------------------------------------------------- names and the manifest


def test_a_renamed_dataset_is_refused_not_dropped(copy):
    """``series/inclusion_start`` -> ``series/inclusion_stbrt``: once lost the bodies' positions, now refused."""
    path = copy("r.h5")
    with h5py.File(path, "a") as f:   # HDF5 rewrites its own header checksums: only the manifest can tell
        f.move("series/inclusion_start", "series/inclusion_stbrt")
    with pytest.raises(errors.FileError) as caught:
        fw.load_result(path)
    assert one_line(caught, path).endswith(
        "is damaged: dataset 'series/inclusion_start' is missing; it holds 'series/inclusion_stbrt', which is not "
        "in its manifest (the structure found differs from the one its manifest lists)")
    resign(path)   # a manifest of the renamed file: the format's own list of names refuses it
    with pytest.raises(errors.FileError, match=r"is damaged: it holds 'series/inclusion_stbrt', which no result "
                                               r"file of format 4 has$"):
        fw.load_result(path)


def test_a_flipped_bit_in_a_name_fails_hdf5s_header_checksum(copy):
    path = copy("r.h5")
    data = bytearray(path.read_bytes())
    at = data.index(b"\x0finclusion_start") + 1   # the link's name (15 bytes) in the group's header, not the manifest
    data[at + 10] ^= 0x01  # 'inclusion_start' -> 'inclusion_stbrt'
    path.write_bytes(bytes(data))
    with pytest.raises(errors.FileError, match=r"is damaged: RuntimeError: .*incorrect metadata checksum") as caught:
        fw.load_result(path)
    one_line(caught, path)


@pytest.mark.parametrize("edit, message", [
    (lambda f: f["series/time"].attrs.create("unit", "s"),
     r"'series/time' has the attribute\(s\) 'unit', which no file of format 4 has"),
    (lambda f: f["series"].create_dataset("extra", data=np.zeros(3)),
     r"it holds 'series/extra', which no result file of format 4 has"),
    (lambda f: f.create_group("more"), r"it holds 'more', which no result file of format 4 has"),
    (lambda f: f["state/station"].attrs.modify("scalar", 2), r"'state/station' has the attribute 'scalar' = 2"),
    (lambda f: f.attrs.create("comment", "x"),
     r"it has the file attribute\(s\) 'comment', which no file of format 4 has"),
])
def test_what_no_format_writes_is_refused(copy, edit, message):
    path = copy("c.h5")
    with h5py.File(path, "a") as f:
        edit(f)
    resign(path)
    with pytest.raises(errors.FileError, match="resume: .* is damaged: " + message) as caught:
        io.read(path, name="resume")
    one_line(caught, path)


def test_the_attributes_a_sweep_adds_are_allowed(copy, files):
    path = copy("r.h5")
    with h5py.File(path, "a") as f:
        f.attrs["sweep_point"] = json.dumps({"load": 20.0})
        f.attrs["sweep_wall_time"] = 1.5
    assert same_records(fw.load_result(path).records, files[1].records)


def test_the_manifest_records_names_shapes_dtypes_attributes_and_optional_datasets(copy):
    path = copy("c.h5")
    with h5py.File(path, "r") as f:
        manifest = json.loads(f.attrs["manifest"])
    objects, optional = manifest["objects"], manifest["optional"]
    assert objects["fields/pressure"]["shape"] == [2, 16, 16] and objects["fields/pressure"]["dtype"] == "<f8"
    assert objects["state/station"]["attributes"] == {"scalar": 1} and 3 in objects["series/time"]["filters"]
    assert {"series/couplings", "series/inclusion_start", "fields/eigenstrain", "fields/inclusion_stress", "state",
            "state/station"} <= set(optional)
    assert not {"series/time", "fields/gap", "series", "fields"} & set(optional)
    with h5py.File(path, "a") as f:   # a dtype changed behind the manifest's back
        data = f["series/couplings"][()]
        del f["series/couplings"]
        f["series"].create_dataset("couplings", data=data.astype(np.int32), chunks=True, fletcher32=True)
    rewrite_checksum(path)
    with pytest.raises(errors.FileError, match=r"'series/couplings' differs from its manifest \(dtype '<i4' in "
                                               r"the file, '<i8' in the manifest\)"):
        io.read(path)


# --------------------------------------------------------------------------- one line for every damage


def test_undecodable_metadata_is_a_checksum_failure_not_a_unicode_error(copy):
    """A flipped high bit in the configuration's text made ``io._checksum`` raise UnicodeEncodeError."""
    path = copy("c.h5")
    data = bytearray(path.read_bytes())
    at = data.index(b'"grid"') + 2
    data[at] ^= 0x80
    path.write_bytes(bytes(data))
    for load, name in ((fw.load_result, "path"), (lambda p: simulation().run(resume=p), "resume")):
        with pytest.raises(errors.FileError, match=rf"^{name}: .* is damaged: the attributes 'framework_version', "
                                                   r"'configuration' and 'manifest' fail their checksum$") as caught:
            load(path)
        one_line(caught, path)


def test_resume_from_a_checkpoint_without_its_couplings(copy):
    """Once ``KeyError: 'couplings'``."""
    path = copy("c.h5")
    with h5py.File(path, "a") as f:
        del f["series/couplings"]
    with pytest.raises(errors.FileError, match=r"^resume: .* is damaged: dataset 'series/couplings' is missing "
                                               r"\(the structure found differs from the one its manifest lists\)$") \
            as caught:
        simulation().run(resume=path)
    one_line(caught, path)


SCENARIO = """
[grid]
shape = [21, 21]
size = [1.2e-3, 1.2e-3]
[material]
type = "Elastic"
young = 210e9
poisson = 0.3
[indenter]
type = "Sphere"
radius = 10e-3
[schedule]
load = [25.0, 50.0]
times = [0.0, 1.0]
[output]
vtu = false
"""


def test_cli_resume_from_a_damaged_checkpoint_prints_one_line(tmp_path, capsys):
    from framework.__main__ import main
    (tmp_path / "s.toml").write_text(SCENARIO)
    command = ["run", str(tmp_path / "s.toml"), "--out", str(tmp_path / "out"), "--quiet"]
    assert main(command) == 0
    data = bytearray((tmp_path / "out" / "result.h5").read_bytes())
    at = data.index(b'"material"') + 3
    data[at] ^= 0x80   # an undecodable byte in the configuration
    (tmp_path / "out" / "checkpoint.h5").write_bytes(bytes(data))
    capsys.readouterr()
    assert main(command + ["--resume"]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and error.startswith("error: resume: ")
    assert "checkpoint.h5' is damaged: the attributes 'framework_version', 'configuration' and 'manifest' fail" in error


# --------------------------------------------------------------------------- links and external storage


def replace(path, key, make):
    with h5py.File(path, "a") as f:
        data = f[key][()]
        del f[key]
        make(f, key, data)


@pytest.mark.parametrize("make, message", [
    (lambda f, key, data: f.__setitem__(key, h5py.ExternalLink("other.h5", "/x")),
     r"'series/time' is an external link to '/x' in the file 'other.h5'"),
    (lambda f, key, data: f.__setitem__(key, h5py.SoftLink("/series/load")), r"'series/time' is a soft link to "
                                                                              r"'/series/load'"),
    (lambda f, key, data: f.__setitem__(key, h5py.SoftLink("/elsewhere")), r"'series/time' is a soft link"),
    (lambda f, key, data: f.create_dataset(key, data=data, external=[(f.filename + ".raw", 0, h5py.h5f.UNLIMITED)]),
     r"dataset 'series/time' stores its data in the external file\(s\) '.*r.h5.raw'"),
])
@pytest.mark.parametrize("format", [4, 1])
def test_links_and_external_storage_are_refused(copy, plain, make, message, format):
    """Format 1, without checksums, must not let data come from elsewhere either."""
    from test_io import write_format_1
    path = copy("r.h5")
    if format == 1:
        write_format_1(plain, path)
    (path.parent / "other.h5").write_bytes(path.read_bytes())
    replace(path, "series/time", make)
    with pytest.raises(errors.FileError, match=r"^path: '.*r.h5' is refused: " + message) as caught:
        fw.load_result(path)
    one_line(caught, path)


def test_virtual_datasets_and_plugin_filters_are_refused(copy, tmp_path):
    path = copy("r.h5")
    source = tmp_path / "source.h5"
    with h5py.File(source, "w") as f:
        f["x"] = np.arange(2.0)

    def virtual(f, key, data):
        layout = h5py.VirtualLayout(shape=(2,), dtype=float)
        layout[:] = h5py.VirtualSource(str(source), "x", shape=(2,))
        f.create_virtual_dataset(key, layout)
    replace(path, "series/time", virtual)
    with pytest.raises(errors.FileError, match=r"is refused: dataset 'series/time' is virtual: its data are in "
                                               r"other files") as caught:
        fw.load_result(path)
    one_line(caught, path)
    path = copy("r.h5")
    replace(path, "series/time", lambda f, key, data: f.create_dataset(key, data=data, compression="lzf"))
    with pytest.raises(errors.FileError, match=r"is refused: dataset 'series/time' uses the HDF5 filter\(s\) "
                                               r"\[32000\]; a result file uses only gzip, shuffle, fletcher32"):
        fw.load_result(path)


# --------------------------------------------------------------------------- format 1


def test_a_file_claiming_format_1_keeps_its_checks(copy):
    """``format = 1`` once turned every checksum off: on a later layout it is refused."""
    path = copy("r.h5")
    with h5py.File(path, "a") as f:
        f.attrs["format"] = 1
    with pytest.raises(errors.FileError, match=r"is damaged or forged: it claims format 1 \(written before "
                                               r"checksums\) but has the file attribute\(s\) 'checksum', 'manifest'"):
        fw.load_result(path)
    with h5py.File(path, "a") as f:
        del f.attrs["checksum"], f.attrs["manifest"]
    with pytest.raises(errors.FileError, match=r"claims format 1 .* but has a Fletcher-32 checksum on '.*'") as caught:
        fw.load_result(path)
    one_line(caught, path)


def test_a_genuine_format_1_file_loads_with_a_warning(plain, tmp_path):
    from test_io import write_format_1
    write_format_1(plain, tmp_path / "old.h5")
    with pytest.warns(errors.UncheckedFileWarning, match=r"is of format 1, written before result files had "
                                                         r"checksums: its checksums are missing by design"):
        loaded = fw.load_result(tmp_path / "old.h5")
    assert np.array_equal(loaded.records[-1].pressure, plain.records[-1].pressure)


# --------------------------------------------------------------------------- older formats


def write_format_3(result, path, state=None):
    """A file of format 3 as the framework wrote it before the manifest (framework/io.py at 7dcfd30)."""
    from framework.io import _dataset
    with h5py.File(path, "w") as f:
        f.attrs["format"] = 3
        f.attrs["framework_version"] = result.version
        configuration = json.dumps(result.configuration())
        f.attrs["configuration"] = configuration
        f.attrs["checksum"] = zlib.crc32(f"{result.version}\n{configuration}".encode())
        series, fields = f.create_group("series"), f.create_group("fields")
        for key in io.SERIES + io.INCLUSION_SERIES:
            _dataset(series, key, np.array([getattr(r, key) for r in result.records],
                                           dtype=float if key == "tilt" else None))
        for key in io.FIELDS + io.INCLUSION_FIELDS:
            _dataset(fields, key, np.array([getattr(r, key) for r in result.records]), compression="gzip",
                     chunks=(1,) + np.shape(getattr(result.records[0], key)))
        if state is not None:
            group = f.create_group("state")
            group.attrs["keys"] = list(state)
            for key, value in state.items():
                _dataset(group, key, value)


def test_format_3_files_load_and_their_names_are_checked(files, tmp_path):
    sim, result, folder = files
    _, _, state = io.read(folder / "c.h5")
    path = tmp_path / "old.h5"
    write_format_3(result, path, state)
    loaded = fw.load_result(path)
    assert loaded.configuration() == result.configuration()
    for a, b in zip(loaded.records, result.records):
        assert np.array_equal(a.eigenstrain, b.eigenstrain) and a.inclusion_start == b.inclusion_start
    _, _, read_state = io.read(path, name="resume")
    assert list(read_state) == list(state)
    with h5py.File(path, "a") as f:
        f.move("series/inclusion_start", "series/inclusion_stbrt")
    with pytest.raises(errors.FileError, match=r"it holds 'series/inclusion_stbrt', which no result file of format 3"):
        fw.load_result(path)
    write_format_3(result, path, state)
    with h5py.File(path, "a") as f:
        f.move("state/pressure", "state/pressurf")
    with pytest.raises(errors.FileError, match=r"^resume: .* is damaged: dataset 'state/pressure' is missing$"):
        io.read(path, name="resume")


# --------------------------------------------------------------------------- shapes against the configuration


def test_a_grid_shape_that_does_not_match_the_fields_is_refused_on_load(copy):
    path = copy("r.h5")
    with h5py.File(path, "a") as f:
        configuration = json.loads(f.attrs["configuration"])
        configuration["grid"]["shape"] = [31, 16]
        f.attrs["configuration"] = json.dumps(configuration)
    rewrite_checksum(path)
    with pytest.raises(errors.FileError, match=r"^path: .* is damaged: dataset 'fields/eigenstrain' has shape "
                                               r"\(2, \d+, \d+, \d+, 6\); expected \(steps, m1, m2, m3, 6\) with a box "
                                               r"of at most 31 x 16 x 8 cuboids|dataset 'fields/\w+' has shape "
                                               r"\(2, 16, 16\); expected \(2, 31, 16\) \(the configuration's grid has "
                                               r"31 x 16 cells and 'series/time' 2 steps\)$") as caught:
        fw.load_result(path)
    one_line(caught, path)


def test_fields_and_boxes_that_do_not_fit_are_refused(copy):
    path = copy("r.h5")
    with h5py.File(path, "a") as f:
        for key in ("pressure", "displacement", "gap"):
            data = f[f"fields/{key}"][()][:, :, :8]
            del f[f"fields/{key}"]
            f["fields"].create_dataset(key, data=data, chunks=True, fletcher32=True)
    resign(path)
    with pytest.raises(errors.FileError, match=r"dataset 'fields/\w+' has shape \(2, 16, 8\); expected \(2, 16, 16\)"):
        fw.load_result(path)
    path = copy("r.h5")
    with h5py.File(path, "a") as f:
        f["series/inclusion_start"][0] = (14, 0, 0)
    with pytest.raises(errors.FileError, match=r"step 0: the inhomogeneities' box of \(\d+, \d+, \d+\) cuboids from "
                                               r"cuboid \(14, 0, 0\) leaves the grid of \(16, 16, 8\) cuboids"):
        fw.load_result(path)
    path = copy("r.h5")
    with h5py.File(path, "a") as f:
        configuration = json.loads(f.attrs["configuration"])
        configuration["inclusions"]["inclusions"][0]["semi_axes"] = [0.15e-3] * 3
        f.attrs["configuration"] = json.dumps(configuration)
    rewrite_checksum(path)
    with pytest.raises(errors.FileError, match=r"step 0: its eigenstrains have shape \(\d+, \d+, \d+, 6\); the "
                                               r"configuration's box around the inhomogeneities needs"):
        fw.load_result(path)
    path = copy("c.h5")
    with h5py.File(path, "a") as f:
        f["state/station"][0] = -1
    with pytest.raises(errors.FileError, match=r"^resume: .* is damaged: its state has no station \(an integer >= 0\)"):
        simulation().run(resume=path)


# --------------------------------------------------------------------------- the bit-flip campaign


def stored_numbers(path):
    """Byte ranges of the datasets' stored data (their chunks): what Fletcher-32 guards."""
    ranges = []
    with h5py.File(path, "r") as f:
        def visit(name, item):
            if isinstance(item, h5py.Dataset):
                for k in range(item.id.get_num_chunks()):
                    info = item.id.get_chunk_info(k)
                    ranges.append((info.byte_offset, info.byte_offset + info.size))
        f.visititems(visit)
    return ranges


def regions(path):
    """``(names, metadata)``: offsets of the bytes of every group, dataset and attribute name, and of every other
    byte outside the stored numbers (superblock, object headers, B-trees, heaps, the attributes' text)."""
    whole = path.read_bytes()
    numbers = np.zeros(len(whole), bool)
    for start, stop in stored_numbers(path):
        numbers[start:stop] = True
    labels = set()
    with h5py.File(path, "r") as f:
        labels.update(f.attrs)
        f.visititems(lambda name, item: labels.update(name.split("/")) or labels.update(item.attrs))
    names = set()
    for label in labels:
        start = whole.find(label.encode())
        while start >= 0:
            names.update(range(start, start + len(label)))
            start = whole.find(label.encode(), start + 1)
    names = np.array(sorted(at for at in names if not numbers[at]), dtype=int)
    metadata = np.setdiff1d(np.flatnonzero(~numbers), names)
    return names, metadata


def sample(offsets, count):
    """``(offset, bit)`` pairs: every bit of every offset (full campaign), else ``count`` offsets evenly spread,
    one bit each, the bit turning with the offset's rank."""
    if FULL:
        return [(int(at), bit) for at in offsets for bit in range(8)]
    chosen = offsets[np.unique(np.linspace(0, len(offsets) - 1, min(count, len(offsets))).astype(int))]
    return [(int(at), rank % 8) for rank, at in enumerate(chosen)]


def same_arrays(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def same_records(first, second):
    return len(first) == len(second) and all(
        same_arrays(getattr(a, key), getattr(b, key)) for a, b in zip(first, second)
        for key in a.__dataclass_fields__)


def campaign(path, load, equal):
    """Flip each sampled bit of ``path`` in turn; returns ``(tried, detected, harmless, failures)``."""
    whole = path.read_bytes()
    names, metadata = regions(path)
    target = path.parent / ("flipped-" + path.name)
    tried = detected = harmless = 0
    failures = []
    for offset, bit in sample(names, NAME_FLIPS) + sample(metadata, METADATA_FLIPS):
        data = bytearray(whole)
        data[offset] ^= 1 << bit
        target.write_bytes(bytes(data))
        tried += 1
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error")    # a warning (format 1, ...) would be a failure
                loaded = load(target)
        except errors.FrameworkError as exc:
            message = str(exc)
            if isinstance(exc, errors.FileError) and "\n" not in message and repr(str(target)) in message:
                detected += 1
            else:
                failures.append((offset, bit, f"{type(exc).__name__}: {message}"))
        except Exception as exc:  # noqa: BLE001 - a raw error is what the campaign looks for
            failures.append((offset, bit, f"{type(exc).__name__}: {exc}"))
        else:
            if equal(loaded):
                harmless += 1
            else:
                failures.append((offset, bit, "loaded, and differs from the original"))
    return tried, detected, harmless, failures


def test_bit_flip_campaign_over_names_and_metadata(files):
    """Every flip of a name's or a metadata byte's bit is detected in one line or loads equal to the original."""
    sim, result, folder = files
    configuration, records, state = io.read(folder / "c.h5")

    def equal_result(loaded):
        return loaded.configuration() == result.configuration() and same_records(loaded.records, result.records)

    def resume(path):
        resumed = sim.run(resume=path)   # the run is finished: nothing is solved
        return resumed, io.read(path, name="resume")

    def equal_checkpoint(loaded):
        resumed, (again, stored, kept) = loaded
        return same_records(resumed.records, result.records) and again == configuration \
            and same_records(stored, records) and list(kept) == list(state) \
            and all(same_arrays(kept[key], state[key]) for key in state)

    report = []
    for name, load, equal in (("r.h5", fw.load_result, equal_result), ("c.h5", resume, equal_checkpoint)):
        tried, detected, harmless, failures = campaign(folder / name, load, equal)
        report.append(f"{name}: {tried} flips, {detected} detected, {harmless} harmless")
        assert failures == [], f"{name}: {len(failures)} of {tried} flips neither detected nor harmless, e.g. " \
                               f"{failures[:5]}"
        assert tried == detected + harmless and detected > harmless
    print("bit-flip campaign" + (" (full)" if FULL else "") + ": " + "; ".join(report))
