"""Parametric sweeps on Dask: the numbers of serial runs, failures reported, reruns skipped, the CLI."""
import csv
import importlib
import itertools
import math
import os
import pickle
import subprocess
import sys

import numpy as np
import pytest

import framework as fw
from framework.errors import ParameterError
from framework.result import Result
from framework.scenario import ScenarioError

distributed = pytest.importorskip("distributed", reason="sweeps need the cluster extra: pip install "
                                                        "'viscocontact[cluster]'")
sw = importlib.import_module("framework.sweep")  # the package, also once fw.sweep is the function
cluster = importlib.import_module("framework.sweep.cluster")  # where sweep() looks up _connect

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLE = os.path.join(ROOT, "examples", "sweep_sphere.toml")
BASE = {"grid": {"shape": [33, 33], "size": [1.2e-3, 1.2e-3]},
        "material": {"type": "Elastic", "young": 210e9, "poisson": 0.3},
        "indenter": {"type": "Sphere", "radius": 10e-3},
        "schedule": {"load": [25.0, 50.0, 100.0], "times": [0.0, 1.0, 2.0]}}
PARAMETERS = {"indenter.radius": [5e-3, 10e-3], "material.young": [70e9, 210e9]}
POINTS = [{"indenter.radius": 5e-3, "material.young": 70e9}, {"indenter.radius": -1e-3, "material.young": 70e9},
          {"indenter.radius": 10e-3, "material.young": 70e9}, {"indenter.radius": 10e-3, "material.young": 210e9}]


def test_result_files_are_available():
    """Sweeps save each point with framework.io.save (what Result.save calls) and read reruns with load_result."""
    assert hasattr(Result, "save") and hasattr(fw, "load_result")


@pytest.fixture(scope="module")
def client():
    # scipy's FFT on the workers as in the serial runs below: pyFFTW's measured plans may differ from one process
    # to the next, and with them the last bits (the solver's residual moves by 1e-5 relative)
    cluster = distributed.LocalCluster(processes=True, n_workers=2, threads_per_worker=1, dashboard_address=None,
                                       env={"FRAMEWORK_FFT_BACKEND": "scipy"},
                                       scheduler_kwargs={"dashboard_address": "127.0.0.1:0"})  # 8787 may be taken
    client = distributed.Client(cluster)
    yield client
    client.close()
    cluster.close()


def h5_files(folder):
    return sorted(name for name in os.listdir(folder) if name.endswith(".h5"))


def same(a, b, scale):
    """Equal to 1e-12 (relative, or of ``scale`` for values that are rounding noise around zero); NaN equals NaN."""
    return a == b or (math.isnan(a) and math.isnan(b)) or abs(a - b) <= 1e-12 * max(abs(a), abs(b), scale)


def comparable(row):
    """A row without its status, NaN (a series undefined for the contact, e.g. half_width) as a string."""
    return {k: "nan" if isinstance(v, float) and math.isnan(v) else v for k, v in row.items() if k != "status"}


def test_sweep_on_two_workers_equals_the_points_run_one_by_one(client, tmp_path):
    builder = sw.ScenarioBuilder(BASE)
    rows = sw.sweep(builder, PARAMETERS, client=client, folder=tmp_path)
    assert [row["index"] for row in rows] == [0, 1, 2, 3]
    assert [(row["indenter.radius"], row["material.young"]) for row in rows] == \
        list(itertools.product(*PARAMETERS.values()))
    assert [row["status"] for row in rows] == ["done"] * 4 and all(row["error"] == "" for row in rows)
    assert h5_files(tmp_path) == sorted(os.path.basename(row["file"]) for row in rows)
    scales = {"center_x1": 1e-3, "center_x2": 1e-3, "tilt_x1": 1.0, "tilt_x2": 1.0}
    for row in rows:
        with fw.fft.use_backend("scipy"):
            serial = builder(**{key: row[key] for key in PARAMETERS}).run()
        for key, values in serial.summary().items():
            value = row["final." + key]
            assert same(value, values[-1].item(), scales.get(key, 0.0)), (key, value, values[-1])
        assert row["steps"] == len(serial) == 3 and row["wall_time"] > 0
        saved = fw.load_result(row["file"])
        assert saved.configuration() == serial.configuration()
        for step in range(len(serial)):
            np.testing.assert_allclose(saved.pressure(step), serial.pressure(step), rtol=1e-12,
                                       atol=1e-12 * serial.pressure(step).max())
    with open(tmp_path / "sweep.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert len(table) == 4 and [line["status"] for line in table] == ["done"] * 4
    for line, row in zip(table, rows):
        assert float(line["final.max_pressure"]) == row["final.max_pressure"] and line["file"] == row["file"]
        assert float(line["material.young"]) == row["material.young"]
    assert "final.time" in table[0] and "final.iterations" in table[0] and "wall_time" in table[0]


def test_a_failing_point_is_reported_and_the_others_finish(client, tmp_path):
    def build(radius, young):  # a closure: sent to the workers by value
        return fw.Simulation(grid=fw.Grid(shape=(33, 33), size=(1.2e-3, 1.2e-3)),
                             material=fw.materials.Elastic(young=young, poisson=0.3),
                             indenter=fw.indenters.Sphere(radius=radius),
                             schedule=fw.schedules.Static(load=[50.0, 100.0], times=[0.0, 1.0]))

    points = [{"radius": point["indenter.radius"], "young": point["material.young"]} for point in POINTS]
    rows = sw.sweep(build, points, client=client, folder=tmp_path, outputs=["load", "max_pressure"])
    assert [row["status"] for row in rows] == ["done", "failed", "done", "done"]
    failed = rows[1]
    assert failed["error"].startswith("ParameterError: ") and "radius must be positive" in failed["error"]
    assert failed["file"] == "" and failed["final.max_pressure"] is None and failed["wall_time"] is None
    assert all(row["final.load"] == pytest.approx(100.0) for row in rows if row["status"] == "done")
    assert set(rows[0]) == {"index", "radius", "young", "status", "error", "file", "wall_time", "steps",
                            "final.load", "final.max_pressure"}
    assert len(h5_files(tmp_path)) == 3 and sorted(os.listdir(tmp_path)) == sorted(h5_files(tmp_path) + ["sweep.csv"])
    with open(tmp_path / "sweep.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert table[1]["status"] == "failed" and "radius must be positive" in table[1]["error"]
    assert table[1]["final.max_pressure"] == ""


def test_rerun_skips_the_done_points_without_running_them(client, tmp_path):
    builder = sw.ScenarioBuilder(BASE, source="base")
    first = sw.sweep(builder, POINTS, client=client, folder=tmp_path)
    assert [row["status"] for row in first] == ["done", "failed", "done", "done"]
    assert "ScenarioError: base with indenter.radius = -0.001" in first[1]["error"]
    stamps = {name: os.stat(tmp_path / name).st_mtime_ns for name in h5_files(tmp_path)}
    again = sw.sweep(builder, POINTS, client=client, folder=tmp_path)
    assert [row["status"] for row in again] == ["skipped", "failed", "skipped", "skipped"]
    assert {name: os.stat(tmp_path / name).st_mtime_ns for name in h5_files(tmp_path)} == stamps
    for a, b in zip(first, again):
        if a["status"] == "done":  # read back from the files, to the bit, with the wall time of the first run
            assert comparable(a) == comparable(b)
    # another value is another point: it runs, the others are still skipped
    changed = POINTS[:3] + [{"indenter.radius": 10e-3, "material.young": 200e9}]
    third = sw.sweep(builder, changed, client=client, folder=tmp_path)
    assert [row["status"] for row in third] == ["skipped", "failed", "skipped", "done"]
    assert len(h5_files(tmp_path)) == 4


def no_cluster(*args, **kwargs):
    raise AssertionError("the points were sent to run")


def hertz_radius(load, radius, young, poisson=0.3):
    """Hertz's contact radius of a sphere on an elastic half-space [m]."""
    return (3 * load * radius / (4 * young / (1 - poisson**2))) ** (1 / 3)


def test_a_swept_load_and_the_load_reached_are_two_columns(client, tmp_path):
    """The load is the first thing users sweep: the parameter keeps its name, the output is final.load."""
    def build(load, radius):
        return fw.Simulation(grid=fw.Grid(shape=(33, 33), size=(1.2e-3, 1.2e-3)),
                             material=fw.materials.Elastic(young=210e9, poisson=0.3),
                             indenter=fw.indenters.Sphere(radius=radius), schedule=fw.schedules.Static(load=load))

    points = [{"load": 20.0, "radius": 10e-3}, {"load": 80.0, "radius": 10e-3}]
    rows = sw.sweep(build, points, client=client, folder=tmp_path)
    assert [row["status"] for row in rows] == ["done", "done"]
    for point, row in zip(points, rows):
        assert row["load"] == point["load"] and row["final.load"] == pytest.approx(point["load"], rel=1e-9)
        # Hertz, to the grid's resolution (36 um cells)
        assert row["final.contact_radius"] == pytest.approx(hertz_radius(point["load"], 10e-3, 210e9), abs=36e-6)
    with open(tmp_path / "sweep.csv", newline="") as f:
        header = next(csv.reader(f))
    assert header[:4] == ["index", "load", "radius", "status"] and "final.load" in header
    table = sw.format_table(rows).splitlines()
    assert table[0].split() == ["#", "load", "radius", "status", "final.load", "final.contact_radius",
                                "final.max_pressure", "final.friction_coefficient", "wall_time"]
    assert table[2].split()[:5] == ["1", "80", "0.01", "done", "80"]


def test_the_folder_is_checked_before_any_point_runs(tmp_path, unwritable_folder, monkeypatch, capsys):
    """A folder that cannot take the files fails at once, not after every point was computed."""
    monkeypatch.setattr(cluster, "_connect", no_cluster)
    (tmp_path / "a file").write_text("")
    (tmp_path / "table" / "sweep.csv").mkdir(parents=True)
    for folder, message in [
        (tmp_path / "a file", r"folder: '.*a file' is a file; expected a folder"),
        (tmp_path / "a file" / "sub", r"folder: cannot create the folder '.*a file/sub' \(Not a directory\)"),
        (unwritable_folder, r"folder: cannot create files in the folder '.*' \(.+\); expected a writable folder"),
        (tmp_path / "table", r"folder: '.*table/sweep.csv' is a folder; the sweep writes its table there"),
    ]:
        with pytest.raises(ParameterError, match=message):
            sw.sweep(sw.ScenarioBuilder(BASE), PARAMETERS, folder=folder)
    assert sw.main([EXAMPLE, "--folder", str(tmp_path / "a file")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: folder: ") and "is a file" in err and len(err.splitlines()) == 1


def test_leftovers_of_killed_writes_are_removed_at_the_next_sweep(tmp_path, monkeypatch):
    """Partial point files stay when their point is not run again (its file is there): the next sweep removes them."""
    builder = sw.ScenarioBuilder(BASE)
    point = {"indenter.radius": 5e-3}
    name = sw.point_file(0, point)
    assert sw.run_point(builder, point, str(tmp_path), name)["status"] == "done"
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait()
    leftovers = [f".{name[:-3]}.0badc0de.partial.h5", f".{name[:-3]}.0badc0de.partial.h5.tmp{gone.pid}",
                 f".point_0007_{sw.point_hash({'a': 1})}.12345678.partial.h5", f"sweep.csv.tmp{gone.pid}"]
    kept = [".notes.partial.h5", "point_0000.partial.h5", "sweep.csv.tmpx"]
    for leftover in leftovers + kept:
        (tmp_path / leftover).write_bytes(b"half a file")
    monkeypatch.setattr(cluster, "_connect", no_cluster)  # the one point is skipped
    rows = sw.sweep(builder, [point], folder=tmp_path)
    assert [row["status"] for row in rows] == ["skipped"]
    assert sorted(os.listdir(tmp_path)) == sorted([name, "sweep.csv"] + kept)


def test_a_damaged_point_file_is_run_again_and_said_so(client, tmp_path, flip_byte, capsys):
    """A flipped bit and a truncated file: each point runs again, its row says its file was damaged."""
    builder = sw.ScenarioBuilder(BASE)
    first = sw.sweep(builder, PARAMETERS, client=client, folder=tmp_path)
    flip_byte(first[2]["file"], "series/approach")
    with open(first[3]["file"], "r+b") as f:
        f.truncate(os.path.getsize(first[3]["file"]) // 2)
    again = sw.sweep(builder, PARAMETERS, client=client, folder=tmp_path, progress=True)
    assert [row["status"] for row in again] == ["skipped", "skipped", "recomputed", "recomputed"]
    assert [row["error"] for row in again[:2]] == ["", ""]
    for row in again[2:]:
        assert row["error"].startswith("damaged: ") and "\n" not in row["error"], row["error"]
        assert row["file"] and os.path.basename(row["file"]) in row["error"]  # the reason names the file
    assert again[2]["final.approach"] == first[2]["final.approach"]
    assert fw.load_result(again[2]["file"]).approach[-1] == first[2]["final.approach"]
    out = capsys.readouterr().out
    assert out.count(": recomputed (damaged: ") == 2, out
    with open(tmp_path / "sweep.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert [line["status"] for line in table] == ["skipped", "skipped", "recomputed", "recomputed"]
    assert table[3]["error"] == again[3]["error"]
    third = sw.sweep(builder, PARAMETERS, client=client, folder=tmp_path)  # repaired: all read back now
    assert [row["status"] for row in third] == ["skipped"] * 4


def test_a_killed_point_leaves_no_half_file(tmp_path, monkeypatch):
    builder = sw.ScenarioBuilder(BASE)
    point = {"indenter.radius": 5e-3}
    name = sw.point_file(0, point)
    stale = tmp_path / f".{name[:-3]}.0badc0de.partial.h5"  # as left by a run killed while writing
    stale.write_bytes(b"half")
    row = sw.run_point(builder, point, str(tmp_path), name)
    assert row["status"] == "done" and os.listdir(tmp_path) == [name]

    def broken_save(result, path, state=None, **options):
        with open(path, "wb") as f:
            f.write(b"half a file")
        raise OSError("disk full")

    monkeypatch.setattr("framework.io.save", broken_save)
    row = sw.run_point(builder, point, str(tmp_path / "other"), name)
    assert row == {"status": "failed", "error": "OSError: disk full", "file": "", "wall_time": None, "steps": None,
                   "series": {}}
    assert os.listdir(tmp_path / "other") == []


def test_a_point_file_holds_its_point_and_wall_time_under_its_checksum(tmp_path):
    """Written by framework.io.save as fixed-length attributes under the file's CRC-32 (once added after writing,
    as variable-length strings in HDF5's unchecksummed global heap)."""
    h5py = pytest.importorskip("h5py")
    point = {"indenter.radius": 5e-3}
    row = sw.run_point(sw.ScenarioBuilder(BASE), point, str(tmp_path), sw.point_file(0, point))
    with h5py.File(row["file"], "r") as f:
        assert f.attrs["sweep_point"] == b'{"indenter.radius": 0.005}' and f.attrs["format"] == 6
        assert not f.attrs.get_id("sweep_point").get_type().is_variable_str()
        assert f.attrs["sweep_wall_time"] == row["wall_time"] > 0
    assert sw.read_point(row["file"])["wall_time"] == row["wall_time"]
    with h5py.File(row["file"], "a") as f:
        f.attrs.modify("sweep_wall_time", 2 * row["wall_time"])
    with pytest.raises(fw.errors.FileError, match=r"the attributes 'framework_version', 'configuration', 'manifest', "
                                                  r"'sweep_point' and 'sweep_wall_time' fail their checksum$"):
        sw.read_point(row["file"])


def test_a_point_that_kills_its_worker_fails_once_on_a_local_cluster(tmp_path):
    """client=None starts (and closes) a local cluster; a dying worker is not retried forever."""
    def exit_on_negative_young(**point):
        if point["material.young"] < 0:
            os._exit(3)  # the worker process dies
        return sw.ScenarioBuilder(BASE)(**point)

    points = [{"material.young": 70e9}, {"material.young": -1.0}]
    rows = sw.sweep(exit_on_negative_young, points, folder=tmp_path)
    assert [row["status"] for row in rows] == ["done", "failed"]
    assert rows[1]["error"].startswith("KilledWorker")


def test_the_command_runs_the_example_sweep_and_skips_on_rerun(tmp_path, capsys, client):
    folder = str(tmp_path / "out")
    assert sw.main([EXAMPLE, "--folder", folder]) == 0
    out = capsys.readouterr().out
    assert "4 points" in out and "4 done, 0 skipped, 0 failed" in out and "[4/4]" in out
    with open(os.path.join(folder, "sweep.csv"), newline="") as f:
        table = list(csv.DictReader(f))
    assert [line["status"] for line in table] == ["done"] * 4 and len(h5_files(folder)) == 4
    assert {(line["indenter.radius"], line["material.young"]) for line in table} == \
        {("0.005", "70000000000.0"), ("0.005", "210000000000.0"), ("0.01", "70000000000.0"),
         ("0.01", "210000000000.0")}
    assert {line["grid.shape"] for line in table} == {"[33, 33]"}
    radii = {(float(line["indenter.radius"]), float(line["material.young"])): float(line["final.contact_radius"])
             for line in table}
    for (radius, young), a in radii.items():  # Hertz, to the coarse grid's resolution (37 um cells)
        hertz = (3 * 100.0 * radius / (4 * young / (1 - 0.3**2))) ** (1 / 3)
        assert a == pytest.approx(hertz, abs=40e-6)
    address = client.scheduler.address
    assert sw.main([EXAMPLE, "--folder", folder, "--scheduler", address, "--quiet"]) == 0
    assert "0 done, 4 skipped, 0 failed" in capsys.readouterr().out


def test_the_command_fails_cleanly(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text('scenario = "nowhere.toml"\n[parameters]\n"material.young" = [1e9]\n')
    assert sw.main([str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and "nowhere.toml: no such scenario file" in err and len(err.splitlines()) == 1
    path.write_text(f'scenario = {os.path.join(ROOT, "examples", "hertz_elastic.toml")!r}\n'
                    '[parameters]\n"materail.young" = [1e9]\n')
    assert sw.main([str(path), "--folder", str(tmp_path / "out")]) == 2
    assert "unknown table 'materail'" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_missing_dask_names_the_extra(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(sw.MissingExtraError, match=r"pip install 'viscocontact\[cluster\]'"):
        sw.sweep(sw.ScenarioBuilder(BASE), PARAMETERS, folder=tmp_path)
    assert sw.main([EXAMPLE, "--folder", str(tmp_path)]) == 2
    assert "viscocontact[cluster]" in capsys.readouterr().err


def test_points_are_numbered_deterministically():
    assert sw.expand({"a": [1, 2], "b": [3, 4]}) == [{"a": 1, "b": 3}, {"a": 1, "b": 4}, {"a": 2, "b": 3},
                                                     {"a": 2, "b": 4}]
    assert sw.expand([{"a": 1}, {"b": 2}]) == [{"a": 1}, {"b": 2}]
    assert sw.point_file(7, {"b": 2, "a": (1.5, 2)}) == sw.point_file(7, {"a": [1.5, 2], "b": 2})
    assert sw.point_file(7, {"a": np.float64(1.5)}) == sw.point_file(7, {"a": 1.5}) == "point_0007_3b1cb40b.h5"
    assert sw.point_file(0, {"a": 1.5}) != sw.point_file(0, {"a": 1.6})
    for bad, message in [({"a": 1.0}, "expected a list of values"), ({"a": []}, "non-empty"), ([], "at least one"),
                         ([{"a": 1}, 3], r"parameters\[1\]"), ("a", "expected a dict")]:
        with pytest.raises(ParameterError, match=message):
            sw.expand(bad)
    for name in ("status", "steps", "final.load"):
        with pytest.raises(ParameterError, match=rf"parameter name '{name}' is taken by the table: \['index', "
                                                 rf"'status', 'error', 'file', 'wall_time', 'steps'\] and "
                                                 rf"'final.<series>' are its own columns; rename the parameter"):
            sw.sweep(sw.ScenarioBuilder(BASE), {name: [1.0]})
    with pytest.raises(ParameterError, match=r"outputs: unknown series \['presure'\]"):
        sw.sweep(sw.ScenarioBuilder(BASE), PARAMETERS, outputs=["presure"])


def test_scenario_builder_replaces_dotted_keys():
    builder = sw.ScenarioBuilder(os.path.join(ROOT, "examples", "hertz_elastic.toml"))
    simulation = builder(**{"material.young": 2e9, "indenter.radius": 5e-3, "grid.shape": [17, 17],
                            "schedule.load.2": 60.0})
    assert simulation.material.young == 2e9 and simulation.indenter.radius == 5e-3
    assert simulation.grid.shape == (17, 17) and simulation.grid.size == (1.2e-3, 1.2e-3)
    assert simulation.schedule.history(2.0) == 60.0
    assert builder().material.young == 210e9  # the base is left as it was
    copy = pickle.loads(pickle.dumps(builder))
    assert copy == builder and copy(**{"material.young": 2e9}).material.young == 2e9
    stepped = sw.ScenarioBuilder(dict(BASE, schedule={"load": {"type": "Step", "value": 1.0}}))
    assert stepped(**{"schedule.load.value": 3.0}).schedule.history(0.0) == 3.0
    assert stepped(**{"options.tolerance": 1e-6}).options.solver.tolerance == 1e-6  # a table absent in the base
    assert stepped(**{"material": {"type": "Elastic", "young": 1e9, "poisson": 0.25}}).material.poisson == 0.25


@pytest.mark.parametrize("key, value, message", [
    ("materail.young", 1e9, r"materail.young: unknown table 'materail'; expected one of"),
    ("material.yuong", 1e9, r"material: unknown key\(s\) \['yuong'\]"),
    ("schedule.lod.value", 1.0, r"schedule.lod.value: unknown key 'schedule.lod'"),
    ("schedule.load.value", 1.0, r"schedule.load.value: schedule.load is a list of 3; 'value' is not an index"),
    ("grid.shape.0.x", 1, r"grid.shape.0 is 33, not a table: it has no key 'x'"),
    ("schedule.load.5", 1.0, r"schedule.load is a list of 3; '5' is not an index"),
    ("indenter.radius", -1e-3, r"with indenter.radius = -0.001: indenter: radius must be positive"),
    ("material..young", 1e9, r"expected a dotted key"),
])
def test_scenario_builder_errors_name_the_key(key, value, message):
    with pytest.raises(ScenarioError, match=message):
        sw.ScenarioBuilder(BASE, source="base.toml")(**{key: value})


def test_read_sweep_file(tmp_path):
    (tmp_path / "cases").mkdir()
    (tmp_path / "cases" / "sweep.toml").write_text(
        'scenario = "../base.toml"\nfolder = "results"\n[parameters]\nmaterial.young = [1e9, 2e9]\n'
        '"indenter.radius" = [1e-3]\n')
    (tmp_path / "base.toml").write_text(
        '[grid]\nshape = [17, 17]\nsize = [1e-3, 1e-3]\n[material]\ntype = "Elastic"\nyoung = 1e9\npoisson = 0.3\n'
        '[indenter]\ntype = "Sphere"\nradius = 5e-3\n[schedule]\nload = 1.0\n')
    builder, parameters, folder = sw.read_sweep(tmp_path / "cases" / "sweep.toml")
    assert parameters == {"material.young": [1e9, 2e9], "indenter.radius": [1e-3]}
    assert os.path.samefile(os.path.dirname(folder), tmp_path / "cases") and folder.endswith("results")
    assert builder(**sw.expand(parameters)[1]).material.young == 2e9
    inline = tmp_path / "inline.toml"
    inline.write_text(
        '[scenario.grid]\nshape = [17, 17]\nsize = [1e-3, 1e-3]\n[scenario.material]\ntype = "Elastic"\n'
        'young = 1e9\npoisson = 0.3\n[scenario.indenter]\ntype = "Sphere"\nradius = 5e-3\n[scenario.schedule]\n'
        'load = 1.0\n[[points]]\nindenter.radius = 1e-3\n[[points]]\n"material.young" = 3e9\n'
        'schedule.load = { type = "Ramp", end = 2.0, duration = 1.0 }\n')
    builder, points, folder = sw.read_sweep(inline)
    assert folder is None and points == [{"indenter.radius": 1e-3}, {
        "material.young": 3e9, "schedule.load": {"type": "Ramp", "end": 2.0, "duration": 1.0}}]
    assert builder(**points[1]).schedule.history(1.0) == 2.0
    for text, message in [
        ('scenario = "base.toml"\n', "either a \\[parameters\\] table"),
        ('scenario = "base.toml"\nfolders = "x"\n[parameters]\n"material.young" = [1e9]\n', "unknown key"),
        ('scenario = "base.toml"\n[parameters]\n"material.young" = 1e9\n', "expected a non-empty list"),
        ('scenario = "base.toml"\n[parameters]\n"grid.shap.x" = [1]\n', "unknown key 'grid.shap'"),
        ('[parameters]\n"material.young" = [1e9]\n', "missing 'scenario'"),
    ]:
        bad = tmp_path / "bad.toml"
        bad.write_text(text)
        with pytest.raises(ScenarioError, match=message):
            sw.read_sweep(bad)


def test_the_rolling_sweep_file_builds_every_point():
    """examples/sweep_rolling.toml: every point is a valid steady rolling simulation (built, not run here)."""
    builder, parameters, _ = sw.read_sweep(os.path.join(ROOT, "examples", "sweep_rolling.toml"))
    points = sw.expand(parameters)
    assert len(points) == 18
    for point in points:
        simulation = builder(**point)
        assert simulation.schedule.steady and simulation.schedule.velocity == tuple(point["schedule.velocity"])
        assert simulation.schedule.loads == (point["schedule.load"],)


def test_the_rolling_inclusion_sweep_file_builds_every_point():
    """examples/sweep_rolling_inclusion.toml: 10 points (stiffness, depth, tilt one at a time), each a valid run."""
    builder, parameters, _ = sw.read_sweep(os.path.join(ROOT, "examples", "sweep_rolling_inclusion.toml"))
    points = sw.expand(parameters)
    assert len(points) == 10
    assert sorted({point["inclusions.0.material.young"] for point in points}) == [0.6e9, 1.5e9, 3e9, 9e9, 15e9, 70e9]
    for point in points[::3]:
        simulation = builder(**point)
        body = simulation.inclusions[0]
        assert body.material.young == point["inclusions.0.material.young"]
        assert body.center == tuple(point["inclusions.0.center"])
        tilt = np.degrees(np.arctan2(body.orientation[0, 2], body.orientation[0, 0]))
        assert abs(tilt) == pytest.approx(point["inclusions.0.euler"][0])
