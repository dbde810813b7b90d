"""Damaged, forged and foreign result files: each ends in one line naming the file, or loads equal to the original.

The bit-flip campaign flips bits in the names and the metadata of a saved result and of a checkpoint
(a static elastic run with one inhomogeneity) and counts each flip as detected (a one-line
FileError naming the file) or harmless (the file loads equal to the original, array by array).
By default it flips a deterministic sample of one bit per byte; ``FRAMEWORK_FLIP_CAMPAIGN=full``
flips every bit of every byte outside the stored numbers (minutes). The loads run in a child process
(tests/bit_flips.py) under a timeout: a flip that hangs HDF5 fails the test instead of hanging it.
"""
import json
import os
import zlib

import numpy as np
import pytest

import framework as fw
from framework import errors, io
from bit_flips import campaign_flips, flip_in_child, same_records, simulation

h5py = pytest.importorskip("h5py")

FULL = os.environ.get("FRAMEWORK_FLIP_CAMPAIGN") == "full"


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


def text(value):
    return value.decode("utf-8", "surrogateescape") if isinstance(value, bytes) else value


def set_text(f, key, value):
    """Write the root attribute ``key`` as format 5 does: a fixed-length UTF-8 string, in the root's header."""
    data = value.encode("utf-8", "surrogateescape") if isinstance(value, str) else value
    f.attrs.create(key, np.array(data, dtype=h5py.string_dtype("utf-8", len(data))))


def checksum(f):
    """The CRC-32 the file's format defines (see framework/io.py), computed here from the attributes found."""
    texts = [text(f.attrs[key]) for key in ("framework_version", "configuration")]
    texts += [text(f.attrs["manifest"])] if f.attrs["format"] >= 4 else []
    if f.attrs["format"] >= 5:
        annotations = {key: text(f.attrs[key]) if key == "sweep_point" else float(f.attrs[key])
                       for key in ("sweep_point", "sweep_wall_time") if key in f.attrs}
        texts.append(json.dumps(annotations, sort_keys=True, separators=(",", ":")))
    return zlib.crc32("\n".join(texts).encode("utf-8", "surrogateescape"))


def rewrite_checksum(path):
    """Sign ``path`` again after an edit, as a forger would: the checksum then passes."""
    with h5py.File(path, "a") as f:
        f.attrs["checksum"] = checksum(f)


def resign(path):
    """Rewrite the manifest and the checksum after an edit of the structure: only the other checks can object."""
    from framework import file_layout
    with h5py.File(path, "a") as f:
        set_text(f, "manifest", file_layout.manifest(file_layout.structure(f, refuse=AssertionError)))
    rewrite_checksum(path)


def box_field(result, step, key):
    """A record's inhomogeneity field on its whole box, as formats 3 to 5 held it: the eigenstrains zero in the
    matrix, the stress there what ``Result.stress`` gives (the field the run's box stress equalled to its tolerance)."""
    record = result.records[step]
    if key == "inclusion_stress":
        return result.stress(step)[result._inclusion_box(record)]
    return result._box_field(getattr(record, key))


def to_box_fields(f, result):
    """Rewrite the inhomogeneities' fields of an open file of ``result`` on their box (formats 3 to 5)."""
    from framework.io import _dataset
    for key in ("eigenstrain", "inclusion_stress", "relaxed_eigenstrain"):
        if f"fields/{key}" in f:
            data = np.array([box_field(result, k, key) for k in range(len(f[f"fields/{key}"]))])
            del f[f"fields/{key}"]
            _dataset(f["fields"], key, data, compression="gzip", compression_opts=1, shuffle=True,
                     chunks=(1,) + data.shape[1:])


def to_format_4(path, result):
    """Rewrite a file of format 6 of ``result`` as format 4 wrote it (framework/io.py at 4d07b09): the texts as
    variable-length strings, in HDF5's global heap, the checksum without the annotations (which stay, outside it)
    and the inhomogeneities' fields on their box."""
    from framework import file_layout
    with h5py.File(path, "a") as f:
        to_box_fields(f, result)
        set_text(f, "manifest", file_layout.manifest(file_layout.structure(f, refuse=AssertionError)))
        for key in ("framework_version", "configuration", "manifest", "sweep_point"):
            if key in f.attrs:
                value = text(f.attrs[key])
                del f.attrs[key]
                f.attrs[key] = value      # a str: a variable-length string
        f.attrs["format"] = 4
        f.attrs["checksum"] = checksum(f)


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
                                               r"file of format 6 has$"):
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
     r"'series/time' has the attribute\(s\) 'unit', which no file of format 6 has"),
    (lambda f: f["series"].create_dataset("extra", data=np.zeros(3)),
     r"it holds 'series/extra', which no result file of format 6 has"),
    (lambda f: f.create_group("more"), r"it holds 'more', which no result file of format 6 has"),
    (lambda f: f["state/station"].attrs.modify("scalar", 2), r"'state/station' has the attribute 'scalar' = 2"),
    (lambda f: f.attrs.create("comment", "x"),
     r"it has the file attribute\(s\) 'comment', which no file of format 6 has"),
    (lambda f: f["fields"].create_dataset("relaxed_eigenstrain", data=np.zeros((len(f["series/time"]), 1, 1, 1, 6)),
                                          chunks=True, fletcher32=True),
     r"dataset 'fields/relaxed_eigenstrain' has shape \(\d+, 1, 1, 1, 6\); expected \(\d+, \d+, 6\)"),
])
def test_what_no_format_writes_is_refused(copy, edit, message):
    path = copy("c.h5")
    with h5py.File(path, "a") as f:
        edit(f)
    resign(path)
    with pytest.raises(errors.FileError, match="resume: .* is damaged: " + message) as caught:
        io.read(path, name="resume")
    one_line(caught, path)


def test_a_sweeps_annotations_are_written_under_the_checksum(files, copy, tmp_path):
    """Format 5: ``save`` writes ``sweep_point`` and ``sweep_wall_time`` under the file's CRC-32; format 4 files had
    them added after writing, outside it, and still load."""
    result = files[1]
    path = tmp_path / "point.h5"
    io.save(result, path, annotations={"sweep_point": '{"load": 20.0}', "sweep_wall_time": 1.5})
    with h5py.File(path, "r") as f:
        assert f.attrs["sweep_point"] == b'{"load": 20.0}' and f.attrs["sweep_wall_time"] == 1.5
        expected = "\n".join([result.version, json.dumps(result.configuration()), text(f.attrs["manifest"]),
                              '{"sweep_point":"{\\"load\\": 20.0}","sweep_wall_time":1.5}'])
        assert f.attrs["checksum"] == zlib.crc32(expected.encode())
    assert same_records(fw.load_result(path).records, result.records)
    whole = path.read_bytes()
    for key, value in (("sweep_point", '{"load": 40.0}'), ("sweep_wall_time", 1.25)):
        path.write_bytes(whole)
        with h5py.File(path, "a") as f:   # changed behind the checksum's back (HDF5 rewrites its header checksum)
            set_text(f, key, value) if key == "sweep_point" else f.attrs.modify(key, value)
        with pytest.raises(errors.FileError, match=r"is damaged: the attributes 'framework_version', 'configuration', "
                                                   r"'manifest', 'sweep_point' and 'sweep_wall_time' fail their "
                                                   r"checksum$") as caught:
            fw.load_result(path)
        one_line(caught, path)
    path = copy("r.h5")
    with h5py.File(path, "a") as f:   # added after writing, as sweeps did before format 5
        set_text(f, "sweep_point", '{"load": 20.0}')
    with pytest.raises(errors.FileError, match=r"the attributes 'framework_version', 'configuration', 'manifest' and "
                                               r"'sweep_point' fail their checksum$"):
        fw.load_result(path)
    path = copy("r.h5")
    to_format_4(path, result)
    with h5py.File(path, "a") as f:
        f.attrs["sweep_point"] = json.dumps({"load": 20.0})
        f.attrs["sweep_wall_time"] = 1.5
    assert same_records(fw.load_result(path).records, result.records)


@pytest.mark.parametrize("annotations, message", [
    ({"sweep_pont": "{}"}, r"annotations must be a dict with some of the keys \['sweep_point', 'sweep_wall_time'\], "
                           r"got \{'sweep_pont': '\{\}'\}"),
    ("{}", r"annotations must be a dict with some of the keys .*, got '\{\}'"),
    ({"sweep_point": {"load": 1.0}}, r"annotations\['sweep_point'\] must be a str \(the point's JSON\), got "
                                     r"\{'load': 1.0\}"),
    ({"sweep_wall_time": -1.0}, r"annotations\['sweep_wall_time'\] must be a finite number of seconds >= 0, got -1.0"),
    ({"sweep_wall_time": float("nan")}, r"annotations\['sweep_wall_time'\] must be .*, got nan"),
    ({"sweep_wall_time": "1.5"}, r"annotations\['sweep_wall_time'\] must be .*, got '1.5'"),
])
def test_bad_annotations_are_refused_before_writing(files, tmp_path, annotations, message):
    with pytest.raises(errors.ParameterError, match=message):
        io.save(files[1], tmp_path / "point.h5", annotations=annotations)
    assert list(tmp_path.iterdir()) == []


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
    """A flipped high bit in the configuration's text made ``io._checksum`` raise UnicodeEncodeError.

    In the file, the root's object header checksum (HDF5's) finds such a flip first; written through HDF5, as a
    bit flipped in memory before the write would be, only the file's own CRC-32 can.
    """
    path = copy("c.h5")
    whole = path.read_bytes()
    data = bytearray(whole)
    data[data.index(b'"grid"') + 2] ^= 0x80
    path.write_bytes(bytes(data))
    with pytest.raises(errors.FileError, match=r"^path: .* is damaged: \w+Error: .*incorrect metadata "
                                               r"checksum") as caught:
        fw.load_result(path)
    one_line(caught, path)
    path.write_bytes(whole)
    with h5py.File(path, "a") as f:
        configuration = bytearray(f.attrs["configuration"])
        configuration[configuration.index(b'"grid"') + 2] ^= 0x80
        set_text(f, "configuration", bytes(configuration))
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
    checkpoint = tmp_path / "out" / "checkpoint.h5"
    checkpoint.write_bytes((tmp_path / "out" / "result.h5").read_bytes())
    with h5py.File(checkpoint, "a") as f:   # an undecodable byte in the configuration
        configuration = bytearray(f.attrs["configuration"])
        configuration[configuration.index(b'"material"') + 3] ^= 0x80
        set_text(f, "configuration", bytes(configuration))
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
        for key in io.FIELDS:
            _dataset(fields, key, np.array([getattr(r, key) for r in result.records]), compression="gzip",
                     chunks=(1,) + np.shape(getattr(result.records[0], key)))
        for key in io.INCLUSION_FIELDS:     # on their box
            data = np.array([box_field(result, k, key) for k in range(len(result))])
            _dataset(fields, key, data, compression="gzip", chunks=(1,) + data.shape[1:])
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


def test_format_4_files_load_and_keep_their_checks(files, copy):
    """Format 4 wrote its texts as variable-length strings and its checksum without the annotations."""
    sim, result, folder = files
    path = copy("c.h5")
    to_format_4(path, result)
    with h5py.File(path, "r") as f:
        assert f.attrs.get_id("configuration").get_type().is_variable_str() and b"GCOL" in path.read_bytes()
    _, records, state = io.read(path, name="resume")
    _, _, original = io.read(folder / "c.h5", name="resume")
    assert records[0].eigenstrain.shape == (*result._layout()[1], 6)     # read as written: on the box
    assert same_records(fw.load_result(path).records, result.records) and list(state) == list(original)
    assert same_records(sim.run(resume=path).records, result.records)
    with h5py.File(path, "a") as f:
        f.move("series/inclusion_start", "series/inclusion_stbrt")
    with pytest.raises(errors.FileError, match=r"dataset 'series/inclusion_start' is missing; it holds "
                                               r"'series/inclusion_stbrt', which is not in its manifest"):
        io.read(path)
    path = copy("r.h5")
    to_format_4(path, result)
    with h5py.File(path, "a") as f:
        f.attrs["format"] = 5     # format 5 reads no variable-length string: not even to check it
    with pytest.raises(errors.FileError, match=r"^path: .* is damaged: attribute 'framework_version' of '/' is a "
                                               r"variable-length string; format 5 stores its texts as fixed-length "
                                               r"strings$") as caught:
        fw.load_result(path)
    one_line(caught, path)


# --------------------------------------------------------------------------- shapes against the configuration


def test_a_grid_shape_that_does_not_match_the_fields_is_refused_on_load(copy):
    path = copy("r.h5")
    with h5py.File(path, "a") as f:
        configuration = json.loads(f.attrs["configuration"])
        configuration["grid"]["shape"] = [31, 16]
        set_text(f, "configuration", json.dumps(configuration))
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
        set_text(f, "configuration", json.dumps(configuration))
    rewrite_checksum(path)
    with pytest.raises(errors.FileError, match=r"step 0: its eigenstrains have shape \(\d+, 6\); the "
                                               r"configuration's inhomogeneities need \(\d+, 6\) \(their cuboids\) or, "
                                               r"in files before format 6, \(\d+, \d+, \d+, 6\) \(their box\)$"):
        fw.load_result(path)
    path = copy("c.h5")
    with h5py.File(path, "a") as f:
        f["state/station"][0] = -1
    with pytest.raises(errors.FileError, match=r"^resume: .* is damaged: its state has no station \(an integer >= 0\)"):
        simulation().run(resume=path)


# --------------------------------------------------------------------------- the bit-flip campaign

#: Seconds a child process of the campaign may take (about 10 s on 2 busy cores); a hang fails the test.
CAMPAIGN_TIMEOUT = 300
#: The flip of a saved result of format 4 that hung HDF5 2.0: the lowest byte of the size of the global heap's
#: collection (signature GCOL at 2048, version, 3 reserved bytes, then the size, 4096), bit 5: 4096 -> 4128.
HUNG = (2048 + 8, 5)


def test_bit_flip_campaign_over_names_and_metadata(files):
    """Every flip of a name's or a metadata byte's bit is detected in one line or loads equal to the original."""
    folder = files[2]
    report = []
    for name, kind in (("r.h5", "result"), ("c.h5", "checkpoint")):
        flips = campaign_flips(folder / name, full=FULL)
        tried, detected, harmless, failures = flip_in_child(folder / name, kind, flips,
                                                            timeout=CAMPAIGN_TIMEOUT * (100 if FULL else 1))
        report.append(f"{name}: {tried} flips, {detected} detected, {harmless} harmless")
        assert failures == [], f"{name}: {len(failures)} of {tried} flips neither detected nor harmless, e.g. " \
                               f"{failures[:5]}"
        assert tried == detected + harmless == len(flips) and detected > harmless
    print("bit-flip campaign" + (" (full)" if FULL else "") + ": " + "; ".join(report))


def test_the_flip_that_hung_hdf5_reading_format_4_is_found_in_format_5(files, copy):
    """Format 4's texts were variable-length strings in HDF5's global heap, which has no checksum: flipping bit 5 of
    its collection's size (:data:`HUNG`) made HDF5 2.0 loop forever reading the configuration. Format 5 keeps its
    texts in the root's header and writes no global heap: that flip, and every bit of the 16 bytes that held the
    collection's header, end in one line or load unchanged, in a child process that a hang would time out."""
    folder = files[2]
    assert b"GCOL" not in (folder / "r.h5").read_bytes() + (folder / "c.h5").read_bytes()
    flips = [HUNG] + [(at, bit) for at in range(HUNG[0] - 8, HUNG[0] + 8) for bit in range(8)]
    for name, kind in (("r.h5", "result"), ("c.h5", "checkpoint")):
        tried, detected, harmless, failures = flip_in_child(folder / name, kind, flips, timeout=CAMPAIGN_TIMEOUT)
        assert failures == [] and tried == detected + harmless == len(flips), failures[:5]


@pytest.mark.slow
def test_a_flip_that_hangs_hdf5_fails_the_campaign_instead_of_hanging_it(files, tmp_path):
    """The watchdog at work, on the flip that hangs HDF5 2.0 in a saved result of format 4 (drop this test once
    HDF5 no longer hangs there: the flip would then be detected)."""
    import copy
    import dataclasses
    from unittest import mock
    path = tmp_path / "r.h5"
    result = files[1]
    old = copy.copy(result)     # its fields on the box, as format 4 held them
    old.records = [dataclasses.replace(record, **{key: box_field(result, k, key) for key in io.INCLUSION_FIELDS})
                   for k, record in enumerate(result.records)]
    with mock.patch.object(io, "FORMAT", 4), \
            mock.patch.object(io, "_store_text", lambda attributes, key, value: attributes.__setitem__(key, value)):
        io.save(old, path)      # as format 4 wrote it: its texts as str, variable-length strings
    rewrite_checksum(path)
    assert path.read_bytes().index(b"GCOL") == HUNG[0] - 8
    assert flip_in_child(path, "result", [HUNG], timeout=10) == (1, 0, 0, [(*HUNG, "hangs (still loading after "
                                                                                   "the 10 s allowed)")])
    assert os.listdir(tmp_path) == ["r.h5"]


def test_relaxed_eigenstrains_without_the_eigenstrains_are_refused(plain, tmp_path):
    path = tmp_path / "p.h5"
    plain.save(path)
    with h5py.File(path, "a") as f:
        f["fields"].create_dataset("relaxed_eigenstrain", data=np.zeros((len(plain), 2, 2, 2, 6)), chunks=True,
                                   fletcher32=True)
    resign(path)
    with pytest.raises(errors.FileError, match="it holds 'fields/relaxed_eigenstrain' but none of the "
                                               "inhomogeneities' datasets"):
        fw.load_result(path)
