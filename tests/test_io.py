"""Results on disk: exact round trips, checkpoints, and a killed run resumed."""
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import framework as fw
from framework import errors, io
from framework.demo import build

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_save_load_round_trip_is_exact(tmp_path):
    result = build(21).run()
    result.save(tmp_path / "r.h5")
    loaded = fw.load_result(tmp_path / "r.h5")
    assert len(loaded) == len(result)
    for a, b in zip(result.records, loaded.records):
        for name in ("pressure", "displacement", "gap"):
            assert np.array_equal(getattr(a, name), getattr(b, name))
        assert (a.time, a.load, a.approach, a.iterations, a.residual, a.tilt) == \
            (b.time, b.load, b.approach, b.iterations, b.residual, b.tilt)
    for key, value in result.summary().items():
        assert np.array_equal(value, loaded.summary()[key], equal_nan=True), key
    assert loaded.configuration() == result.configuration()
    assert loaded.version == fw.__version__
    assert np.array_equal(loaded.stress(-1), result.stress(-1))


def test_round_trip_of_an_eccentric_run_with_a_height_map_function(tmp_path):
    grid = fw.Grid(shape=(33, 33), size=(2e-3, 2e-3))
    sim = fw.Simulation(grid=grid, material=fw.materials.Elastic(young=1e9, poisson=0.3),
                        indenter=fw.indenters.HeightMap(lambda x1, x2: (x1**2 + 2 * x2**2) / 0.02),
                        schedule=fw.schedules.Eccentric(load=[1.0, 2.0], offset=(1e-4, 0.0), times=[0.0, 1.0]))
    result = sim.run()
    result.save(tmp_path / "e.h5")
    loaded = fw.load_result(tmp_path / "e.h5")
    assert np.array_equal(loaded.tilt, result.tilt)
    assert np.array_equal(loaded.indenter.on_grid(grid), sim.indenter.on_grid(grid))


def test_not_a_result_file(tmp_path):
    (tmp_path / "x.h5").write_text("hello")
    with pytest.raises(errors.ParameterError, match=r"path: '.*x.h5' is not a readable HDF5 file: another kind"):
        fw.load_result(tmp_path / "x.h5")
    with pytest.raises(errors.ParameterError, match="path: no result file at '.*missing.h5'"):
        fw.load_result(tmp_path / "missing.h5")
    h5py = pytest.importorskip("h5py")
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = np.arange(3.0)
    with pytest.raises(errors.FileError, match=r"'.*other.h5' is not a result file of format 1, 2, 3, 4, 5 or 6$"):
        fw.load_result(tmp_path / "other.h5")
    with h5py.File(tmp_path / "other.h5", "a") as f:
        f.attrs["format"] = 7
        f.create_group("series")
    with pytest.raises(errors.FileError, match=r"format 1, 2, 3, 4, 5 or 6 \(format 7: written by a newer framework\)"):
        fw.load_result(tmp_path / "other.h5")


def no_step(*args, **kwargs):
    raise AssertionError("a step was solved before the arguments were checked")


def stray_files(*folders):
    return sorted(name for folder in folders for name in os.listdir(folder) if ".tmp" in name)


@pytest.mark.parametrize("arguments, message", [
    ({"every": 0}, r"every \(steps between checkpoints\) must be an integer >= 1, got 0$"),
    ({"every": -1}, r"every \(steps between checkpoints\) must be an integer >= 1, got -1$"),
    ({"every": 2.5}, r"every \(steps between checkpoints\) must be an integer >= 1, got 2.5$"),
    ({"every": True}, r"every \(steps between checkpoints\) must be an integer >= 1, got True$"),
    ({"every": "10"}, r"every \(steps between checkpoints\) must be an integer >= 1, got '10'$"),
    ({"checkpoint": "FOLDER"}, r"checkpoint: '.*' is a folder; expected the path of a file to write, e.g. '.*h5'"),
    ({"checkpoint": "FOLDER/missing/c.h5"}, r"checkpoint: cannot write '.*missing/c.h5': the folder '.*missing' does "
                                            r"not exist; create it first"),
    ({"checkpoint": 3}, r"checkpoint must be a file path \(a non-empty str or os.PathLike\), got 3"),
    ({"checkpoint": ""}, r"checkpoint must be a file path \(a non-empty str or os.PathLike\), got ''"),
    ({"resume": "FOLDER/missing.h5"}, r"resume: no result file at '.*missing.h5'"),
    ({"resume": "FOLDER/notes.txt"}, r"resume: '.*notes.txt' is not a readable HDF5 file"),
    ({"resume": 3.0}, r"resume must be a file path \(a non-empty str or os.PathLike\), got 3.0"),
    ({"progress": "yes"}, r"progress must be a boolean, true or false, got 'yes'"),
    ({"callback": 3}, r"callback must be callable as callback\(result, record\) or None, got 3"),
])
def test_run_checks_its_arguments_before_the_first_step(tmp_path, monkeypatch, arguments, message):
    (tmp_path / "notes.txt").write_text("not a result")
    arguments = {key: value.replace("FOLDER", str(tmp_path)) if isinstance(value, str) else value
                 for key, value in arguments.items()}
    simulation = build(21)
    monkeypatch.setattr("framework.simulation.solve_normal", no_step)
    with pytest.raises(errors.ParameterError, match=message):
        simulation.run(**arguments)
    assert stray_files(tmp_path, tmp_path.parent) == []  # a folder as checkpoint left FOLDER.tmpNNN beside it


def test_checkpoint_in_a_folder_closed_to_new_files(unwritable_folder, monkeypatch):
    monkeypatch.setattr("framework.simulation.solve_normal", no_step)
    with pytest.raises(errors.ParameterError, match=r"checkpoint: cannot create files in the folder '.*' \(.+\); "
                                                    r"expected a writable folder"):
        build(21).run(checkpoint=os.path.join(unwritable_folder, "c.h5"))


def test_resume_refuses_a_saved_result_that_is_not_a_checkpoint(tmp_path, monkeypatch):
    result = build(21).run()
    result.records = result.records[:2]  # a run that failed part-way, saved from exc.partial_result
    result.save(tmp_path / "partial.h5")
    monkeypatch.setattr("framework.simulation.solve_normal", no_step)
    with pytest.raises(errors.ParameterError, match=r"resume: '.*partial.h5' holds 2 of the 17 steps and no stepper "
                                                    r"state: it is a saved result, not a checkpoint"):
        build(21).run(resume=tmp_path / "partial.h5")


def test_save_into_a_folder_that_cannot_hold_the_file(tmp_path, unwritable_folder):
    result = build(5).run()
    with pytest.raises(errors.ParameterError, match=r"path: '.*' is a folder; expected the path of a file"):
        result.save(tmp_path)
    with pytest.raises(errors.ParameterError, match=r"path: cannot write '.*nowhere/r.h5': the folder '.*nowhere' "
                                                    r"does not exist"):
        result.save(tmp_path / "nowhere" / "r.h5")
    with pytest.raises(errors.ParameterError, match=r"path: cannot create files in the folder"):
        result.save(os.path.join(unwritable_folder, "r.h5"))
    assert stray_files(tmp_path, tmp_path.parent) == [] and os.listdir(tmp_path) == []


# --------------------------------------------------------------------------- damaged files


@pytest.fixture
def checkpoint(tmp_path):
    path = tmp_path / "c.h5"
    build(21).run(checkpoint=path, every=4)
    return path


@pytest.mark.parametrize("dataset, step", [("series/approach", 0), ("series/time", 0), ("fields/pressure", 9),
                                            ("fields/displacement", 16), ("state/fields", 0), ("state/time", 0)])
def test_a_flipped_byte_is_found_when_read(checkpoint, monkeypatch, flip_byte, dataset, step):
    flip_byte(checkpoint, dataset, step)
    damaged = rf"'.*c.h5' is damaged: dataset '{dataset}' fails its checksum or cannot be decompressed"
    with pytest.raises(errors.ParameterError, match="path: " + damaged) as caught:
        fw.load_result(checkpoint)
    assert "\n" not in str(caught.value)
    monkeypatch.setattr("framework.simulation.solve_normal", no_step)
    with pytest.raises(errors.ParameterError, match="resume: " + damaged):
        build(21).run(resume=checkpoint)


def test_a_changed_configuration_is_found_when_read(checkpoint):
    """The configuration is an attribute in the root's object header: HDF5's header checksum guards its bytes in
    the file, and the file's CRC-32 the text HDF5 was given to write."""
    h5py = pytest.importorskip("h5py")
    whole = checkpoint.read_bytes()
    data = bytearray(whole)
    at = data.index(b'"shape": [21, 21]') + len(b'"shape": [')
    data[at] = ord("3")  # 21 x 21 -> 31 x 21: a valid configuration, for other fields
    checkpoint.write_bytes(bytes(data))
    with pytest.raises(errors.FileError, match=r"is damaged: \w+Error: .*incorrect metadata checksum"):
        fw.load_result(checkpoint)
    checkpoint.write_bytes(whole)
    with h5py.File(checkpoint, "a") as f:
        changed = f.attrs["configuration"].replace(b'"shape": [21, 21]', b'"shape": [31, 21]')
        f.attrs.create("configuration", np.array(changed, dtype=h5py.string_dtype("utf-8", len(changed))))
    with pytest.raises(errors.FileError, match=r"is damaged: the attributes 'framework_version', 'configuration' "
                                               r"and 'manifest' fail their checksum$"):
        fw.load_result(checkpoint)


def test_missing_parts_and_truncated_files_name_the_file(checkpoint, tmp_path):
    h5py = pytest.importorskip("h5py")
    whole = checkpoint.read_bytes()
    for part, message in [("fields/gap", "dataset 'fields/gap' is missing"),
                          ("series", "group 'series' is missing"),
                          ("state/pressure", "dataset 'state/pressure' is missing")]:
        checkpoint.write_bytes(whole)
        with h5py.File(checkpoint, "a") as f:
            del f[part]
        if part.startswith("state"):
            with pytest.raises(errors.ParameterError, match=rf"resume: '.*c.h5' is damaged: {message}"):
                build(21).run(resume=checkpoint)
            continue
        with pytest.raises(errors.ParameterError, match=rf"path: '.*c.h5' is damaged: {message}"):
            fw.load_result(checkpoint)
    for key in ("checksum", "configuration", "framework_version"):
        checkpoint.write_bytes(whole)
        with h5py.File(checkpoint, "a") as f:
            del f.attrs[key]
        with pytest.raises(errors.ParameterError, match=rf"c.h5' is damaged: attribute '{key}' of '/' is missing"):
            fw.load_result(checkpoint)
    for size in (len(whole) // 2, len(whole) - 100):
        checkpoint.write_bytes(whole[:size])
        with pytest.raises(errors.ParameterError, match=r"path: '.*c.h5' is not a readable HDF5 file: .* or "
                                                        r"truncated \(.*truncated file: eof = "):
            fw.load_result(checkpoint)


def write_format_1(result, path):
    """A file of format 1 as the framework wrote it before the checksums (framework/io.py at 686b0ac)."""
    import json
    h5py = pytest.importorskip("h5py")
    with h5py.File(path, "w") as f:
        f.attrs["format"] = 1
        f.attrs["framework_version"] = result.version
        f.attrs["configuration"] = json.dumps(result.configuration())
        series = f.create_group("series")
        for name in io.SERIES:
            series.create_dataset(name, data=np.array([getattr(r, name) for r in result.records],
                                                      dtype=float if name == "tilt" else None))
        fields = f.create_group("fields")
        for name in io.FIELDS:
            fields.create_dataset(name, data=np.array([getattr(r, name) for r in result.records]),
                                  compression="gzip", compression_opts=1, shuffle=True)


def test_files_of_format_1_still_load(tmp_path):
    result = build(21).run()
    write_format_1(result, tmp_path / "old.h5")
    with pytest.warns(errors.UncheckedFileWarning, match=r"'.*old.h5' is of format 1, written before result files "
                                                         r"had checksums: its checksums are missing by design"):
        loaded = fw.load_result(tmp_path / "old.h5")
    assert loaded.configuration() == result.configuration() and len(loaded) == len(result)
    for a, b in zip(result.records, loaded.records):
        assert np.array_equal(a.pressure, b.pressure) and (a.time, a.approach, a.tilt) == (b.time, b.approach, b.tilt)


def test_every_dataset_is_chunked_with_a_checksum(checkpoint):
    h5py = pytest.importorskip("h5py")
    datasets = []
    with h5py.File(checkpoint, "r") as f:
        f.visititems(lambda name, item: datasets.append((name, item.chunks, item.fletcher32))
                     if isinstance(item, h5py.Dataset) else None)
        assert f.attrs["format"] == io.FORMAT
    # state: time, pressure, fields, integral, station, index and the predicted warm start's times and pressures,
    # and the time-step control's four (framework.time_error); series: and the optional time_error
    assert len(datasets) == len(io.SERIES) + 1 + len(io.FIELDS) + 8 + 4
    assert [name for name, chunks, checked in datasets if not chunks or not checked] == []


def test_leftovers_of_killed_writes_are_removed_by_the_next_run(tmp_path):
    """``c.h5.tmp<pid>`` of a process that is gone goes; one of a live process, and other files, stay."""
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait()
    alive = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        names = [f"c.h5.tmp{gone.pid}", f"c.h5.tmp{alive.pid}", "c.h5.tmpx", f"d.h5.tmp{gone.pid}", "c.h5.tmp"]
        for name in names:
            (tmp_path / name).write_bytes(b"half a file")
        build(5).run(checkpoint=tmp_path / "c.h5")
        assert sorted(os.listdir(tmp_path)) == sorted(["c.h5"] + names[1:])
    finally:
        alive.kill()
        alive.wait()


def test_resume_refuses_another_configuration(tmp_path):
    build(21).run(checkpoint=str(tmp_path / "c.h5"))
    with pytest.raises(errors.ParameterError, match=r"another configuration \(grid differ\)"):
        build(23).run(resume=str(tmp_path / "c.h5"))


def test_resume_names_the_options_that_differ(tmp_path):
    """Options that differ are named with both values; one an earlier version's checkpoint lacks is named with
    the value that behaves as that version did (time_tolerance=None: the output times are the steps)."""
    from framework.simulation import _differences
    build(21).run(checkpoint=str(tmp_path / "c.h5"))
    tighter = build(21)
    tighter.options = fw.Options(time_tolerance=1e-4)
    with pytest.raises(errors.ParameterError, match=r"another configuration \(options.time_tolerance: 0.0001 here, "
                                                    r"0.001 in the checkpoint\)"):
        tighter.run(resume=str(tmp_path / "c.h5"))
    mine = {"grid": 1, "options": {"time_tolerance": 1e-3, "tolerance": 1e-8}}
    older = {"grid": 2, "options": {"tolerance": 1e-8}}
    assert _differences(mine, older, ["grid", "options"]) == (
        "grid differ; options.time_tolerance: the checkpoint predates it; give time_tolerance=None to resume it")


def test_resume_of_a_finished_run_returns_it(tmp_path):
    first = build(21).run(checkpoint=str(tmp_path / "c.h5"))
    again = build(21).run(resume=str(tmp_path / "c.h5"))
    assert np.array_equal(again.approach, first.approach)


SCRIPT = """
import sys
from framework.demo import build
build(41).run(checkpoint=sys.argv[1], every=1, callback=lambda r, rec: __import__('time').sleep(0.3))
"""


def test_killed_run_resumes_to_the_uninterrupted_result(tmp_path):
    """SIGKILL mid-way, resume from the checkpoint: equal to an uninterrupted run (scipy FFT: to the bit)."""
    env = dict(os.environ, FRAMEWORK_FFT_BACKEND="scipy", PYTHONPATH=ROOT)
    checkpoint = tmp_path / "c.h5"
    process = subprocess.Popen([sys.executable, "-c", SCRIPT, str(checkpoint)], env=env, cwd=ROOT)
    deadline = time.time() + 120
    while time.time() < deadline:
        if checkpoint.exists() and len(io.read(str(checkpoint))[1]) >= 6:
            break
        time.sleep(0.1)
    process.send_signal(signal.SIGKILL)
    process.wait()
    finished = len(io.read(str(checkpoint))[1])
    assert 6 <= finished < 17
    resume = f"from framework.demo import build; build(41).run(resume={str(checkpoint)!r}).save({str(tmp_path / 'resumed.h5')!r})"
    whole = f"from framework.demo import build; build(41).run().save({str(tmp_path / 'whole.h5')!r})"
    for code in (resume, whole):
        subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT, check=True)
    resumed, whole = fw.load_result(tmp_path / "resumed.h5"), fw.load_result(tmp_path / "whole.h5")
    assert len(resumed) == len(whole) == 17
    for a, b in zip(resumed.records, whole.records):
        assert np.array_equal(a.pressure, b.pressure) and a.approach == b.approach


def test_cli_resume(tmp_path):
    """The CLI writes checkpoint.h5 as it goes and result.h5 at the end; --resume finishes a killed run."""
    out = tmp_path / "out"
    env = dict(os.environ, FRAMEWORK_FFT_BACKEND="scipy")
    scenario = os.path.join(ROOT, "examples", "hertz_elastic.toml")
    completed = subprocess.run([sys.executable, "-m", "framework", "run", scenario, "--out", str(out), "--cells",
                                "21", "--quiet", "--every", "1"], env=env, cwd=ROOT, capture_output=True, text=True)
    assert completed.returncode == 0, completed.stderr
    names = set(os.listdir(out))
    assert "result.h5" in names and "checkpoint.h5" not in names
    completed = subprocess.run([sys.executable, "-m", "framework", "run", scenario, "--out", str(out), "--resume"],
                               env=env, cwd=ROOT, capture_output=True, text=True)
    assert completed.returncode == 2 and "no checkpoint to resume" in completed.stderr
