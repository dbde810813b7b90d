"""Sweep files on the command line: every point checked before any cluster, folders confined, one-line errors."""
import csv
import importlib
import os
import re
import socket
import sys
import threading

import pytest

from framework import resources
from framework.errors import FrameworkError

from cli_helpers import cli, one_error

distributed = pytest.importorskip("distributed", reason="sweeps need the cluster extra: pip install "
                                                        "'viscocontact[cluster]'")
sw = importlib.import_module("framework.sweep")
cluster = importlib.import_module("framework.sweep.cluster")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BASE = """
[scenario.grid]
shape = [16, 16]
size = [1.2e-3, 1.2e-3]
[scenario.material]
type = "Elastic"
young = 210e9
poisson = 0.3
[scenario.indenter]
type = "Sphere"
radius = 10e-3
[scenario.schedule]
load = 50.0
[scenario.output]
vtu = false
history = []
"""


def sweep_file(tmp_path, body, top=""):
    """A sweep file of the scenario BASE: ``top`` holds its top-level keys (folder), ``body`` its points."""
    path = tmp_path / "sweep.toml"
    path.write_text(top + BASE + body)
    return str(path)


@pytest.fixture
def no_cluster(monkeypatch):
    """Fail the test if a cluster is started or a point is sent to one."""
    def refuse(*args, **kwargs):
        raise AssertionError("a cluster was started")
    monkeypatch.setattr(cluster, "_connect", refuse)


# --------------------------------------------------------------------------- argument errors


@pytest.mark.parametrize("args, message", [
    (["sweep"], r"error: the following arguments are required: SWEEP.toml \(see python -m framework sweep -h\)"),
    (["sweep", "x.toml", "--frobnicate"], r"error: unrecognized arguments: --frobnicate \(see python -m framework "
                                          r"sweep -h\)"),
    (["sweep", "--scheduler"], r"error: argument --scheduler: expected one argument"),
    (["check"], r"error: the following arguments are required: FILE \(see python -m framework check -h\)"),
    (["check", "x.toml", "--frobnicate"], r"error: unrecognized arguments: --frobnicate"),
    (["run"], r"error: the following arguments are required: scenario \(see python -m framework run -h\)"),
    (["run", "x.toml", "--every"], r"error: argument --every: expected one argument \(see python -m framework run"),
    (["demo", "--cells", "two"], r"error: argument --cells: expected an integer >= 3, got 'two' \(see python -m "
                                 r"framework demo -h\)"),
    (["demo", "extra"], r"error: unrecognized arguments: extra"),
    ([], r"error: the following arguments are required: command \(see python -m framework -h\)"),
])
def test_argument_errors_are_one_line_and_a_hint(capsys, args, message):
    code, out, err = cli(capsys, *args)
    one_error(code, err, message)
    assert out == "" and "usage:" not in err


# --------------------------------------------------------------------------- every point, before any cluster


def test_check_takes_a_sweep_file(capsys, no_cluster):
    for args in (["check", os.path.join(ROOT, "examples", "sweep_sphere.toml")],
                 ["sweep", os.path.join(ROOT, "examples", "sweep_sphere.toml"), "--check"]):
        code, out, err = cli(capsys, *args)
        lines = out.strip().splitlines()
        assert code == 0 and err == "", err
        assert re.fullmatch(r".*sweep_sphere.toml: ok \(4 points of .*hertz_elastic.toml, into sweep/\)", lines[0])
        assert re.fullmatch(r"estimate: each point needs up to about [\d.]+ MB of memory \(this machine: [\d.]+ GiB\); "
                            r"[\d.]+ s on one core in all, [\d.]+ kB of files", lines[1]), lines[1]


@pytest.mark.parametrize("body, message", [
    ('[parameters]\n"material.yung" = [70e9, 210e9]\n',
     r"sweep.toml: 2 of 2 points are refused; the first, point 0 \(material.yung = 70000000000.0\): material: "
     r"unknown key\(s\) \['yung'\]"),
    ('[parameters]\n"indenter.radius" = [5e-3, -1e-3]\n',
     r"sweep.toml: point 1 \(indenter.radius = -0.001\): indenter: radius must be positive"),
    ('[[points]]\n"material.young" = 70e9\n[[points]]\n"material.poisson" = 0.7\n',
     r"sweep.toml: point 1 \(material.poisson = 0.7\): material: poisson"),
    ('[parameters]\n"grid.shape" = [[16, 16], [12000, 12000]]\n',
     r"sweep.toml: point 1 \(grid.shape = \[12000, 12000\]\): the run needs about [\d.]+ GiB of memory \(the contact "
     r"solver: [\d.]+ GiB\), more than this machine's"),
])
def test_every_point_is_checked_before_any_cluster_starts(capsys, tmp_path, no_cluster, body, message):
    """A misspelt key or a bad value was found on the workers, after the cluster had started."""
    path = sweep_file(tmp_path, body)
    for args in (["check", path], ["sweep", path, "--check"], ["sweep", path, "--folder", str(tmp_path / "out")]):
        one_error(*cli(capsys, *args)[::2], message)
    assert not (tmp_path / "out").exists()


def test_the_api_sends_no_refused_point_to_the_cluster(tmp_path, no_cluster):
    """fw.sweep with a ScenarioBuilder: refused points are failed rows at once, and with none left no cluster starts."""
    builder, _, _ = sw.read_sweep(sweep_file(tmp_path, '[parameters]\n"material.young" = [1.0]\n'))
    rows = sw.sweep(builder, [{"material.yung": 70e9}, {"indenter.radius": -1e-3}], folder=tmp_path / "out")
    assert [row["status"] for row in rows] == ["failed", "failed"]
    assert re.match(r"ScenarioError: .* with material.yung = 70000000000.0: material: unknown key\(s\) \['yung'\]",
                    rows[0]["error"]), rows[0]["error"]
    assert "indenter: radius must be positive" in rows[1]["error"]


def test_a_missing_cluster_extra_fails_the_check(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    one_error(*cli(capsys, "check", os.path.join(ROOT, "examples", "sweep_sphere.toml"))[::2],
              r"sweeps run on Dask distributed .* pip install 'viscocontact\[cluster\]'$")


def test_cells_is_refused_for_a_sweep_file(capsys):
    one_error(*cli(capsys, "check", os.path.join(ROOT, "examples", "sweep_sphere.toml"), "--cells", "8")[::2],
              r"--cells: replaces the grid of a scenario file; .*sweep_sphere.toml is a sweep file")


# --------------------------------------------------------------------------- file names


@pytest.mark.parametrize("folder, message", [
    ("../../x", r"folder: expected a folder inside the sweep file's folder '.*', got '../../x', which leads to '.*' "
                r"\(give --folder on the command line to write elsewhere\)"),
    ("sub/../../x", r"folder: expected a folder inside the sweep file's folder"),
    ("/tmp/x", r"folder: expected a folder relative to the sweep file's folder '.*', got the absolute path '/tmp/x' "
               r"\(give --folder on the command line to write elsewhere\)"),
    ("out\\u0007", r"folder: 'out\\x07' holds the control character '\\x07' at position 3"),
    ("", r"folder: expected a folder relative to the sweep file's folder, got ''"),
])
def test_the_folder_of_a_sweep_file_is_confined_to_its_folder(capsys, tmp_path, no_cluster, folder, message):
    base = tmp_path / "a" / "b"
    base.mkdir(parents=True)
    path = sweep_file(base, '[parameters]\n"material.young" = [70e9]\n', top=f'folder = "{folder}"\n')
    for args in (["check", path], ["sweep", path]):
        one_error(*cli(capsys, *args)[::2], r"sweep.toml: " + message)
    assert sorted(os.listdir(tmp_path)) == ["a"] and sorted(os.listdir(base)) == ["sweep.toml"]


def test_a_link_out_of_the_folder_is_refused_and_inside_is_accepted(capsys, tmp_path, no_cluster):
    (tmp_path / "inside").mkdir()
    (tmp_path / "inside" / "elsewhere").symlink_to(tmp_path)
    path = sweep_file(tmp_path / "inside", '[parameters]\n"material.young" = [70e9]\n', top='folder = "elsewhere/x"\n')
    one_error(*cli(capsys, "check", path)[::2], r"which leads to '.*/x'")
    path = sweep_file(tmp_path / "inside", '[parameters]\n"material.young" = [70e9]\n',
                      top='folder = "out/../results"\n')
    code, out, _ = cli(capsys, "check", path)
    assert code == 0 and f"into {tmp_path / 'inside' / 'out/../results'}{os.sep})" in out


def test_control_characters_in_the_scenario_and_folder_names_are_refused(capsys, tmp_path):
    path = tmp_path / "sweep.toml"
    path.write_text('scenario = "hertz\\n.toml"\n[parameters]\n"material.young" = [70e9]\n')
    one_error(*cli(capsys, "check", str(path))[::2], r"scenario: 'hertz\\n.toml' holds the control character '\\n'")
    good = os.path.join(ROOT, "examples", "sweep_sphere.toml")
    one_error(*cli(capsys, "sweep", good, "--folder", "out\tx")[::2], r"--folder: 'out\\tx' holds the control")


# --------------------------------------------------------------------------- scheduler addresses


def serve(reply):
    """A local TCP server that answers each connection with ``reply`` bytes (None: says nothing); its port."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()
    kept = []

    def loop():
        while True:
            try:
                connection, _ = server.accept()
            except OSError:
                return
            kept.append(connection)
            if reply is not None:
                connection.sendall(reply)

    threading.Thread(target=loop, daemon=True).start()
    return server, server.getsockname()[1]


@pytest.mark.parametrize("reply, message, timeout", [
    (b"\xff" * 64 + b"HTTP/1.1 400 Bad Request\r\n\r\n",
     r"cannot connect to the Dask scheduler at 'tcp://127.0.0.1:\d+': \w+: .*; expected the address of a running Dask "
     r"scheduler", 10.0),
    (None, r"cannot connect to the Dask scheduler at 'tcp://127.0.0.1:\d+': no Dask answer within 1 s; expected the "
           r"address of a running Dask scheduler", 1.0),
], ids=["garbage", "silent"])
def test_an_address_that_does_not_speak_dask_is_one_line(capsys, tmp_path, monkeypatch, reply, message, timeout):
    """Garbage bytes gave a traceback ending in a 3 EiB ArrayMemoryError; a silent server hung past Dask's timeout.
    (The garbage is answered at once, but a busy machine once took more than 1 s: it gets 10 s before timing out.)"""
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", timeout)
    server, port = serve(reply)
    try:
        path = os.path.join(ROOT, "examples", "sweep_sphere.toml")
        code, _, err = cli(capsys, "sweep", path, "--scheduler", f"tcp://127.0.0.1:{port}", "--folder",
                           str(tmp_path / "out"))
        one_error(code, err, message)
        with pytest.raises(FrameworkError, match=message):
            cluster.connect(distributed, f"tcp://127.0.0.1:{port}")
    finally:
        server.close()
    assert not (tmp_path / "out" / "sweep.csv").exists()


def test_the_summary_line_counts_recomputed_points(tmp_path, capsys, monkeypatch):
    """The command's last line says how many files were damaged and recomputed (run in process, no cluster)."""
    path = sweep_file(tmp_path, '[parameters]\n"material.young" = [70e9, 210e9]\n')
    builder, parameters, _ = sw.read_sweep(path)
    folder = tmp_path / "out"
    files = [sw.point_file(k, point) for k, point in enumerate(sw.expand(parameters))]
    for name, point in zip(files, sw.expand(parameters)):
        assert sw.run_point(builder, point, str(folder), name)["status"] == "done"
    (folder / files[1]).write_bytes((folder / files[1]).read_bytes()[:1000])   # truncated

    class Done:
        """A finished task."""
        def __init__(self, value):
            self.value = value

        def result(self):
            return self.value

        def release(self):
            pass

    class Local:
        """Runs the submitted points here, as a cluster would."""
        def submit(self, function, *args, **kwargs):
            return Done(function(*args))

    class Connect:
        def __init__(self, *args):
            pass

        def __enter__(self):
            return Local()

        def __exit__(self, *args):
            return False

    monkeypatch.setattr(distributed, "as_completed", list)
    monkeypatch.setattr(cluster, "_connect", Connect)
    code, out, err = cli(capsys, "sweep", path, "--folder", str(folder))
    assert code == 0, err
    assert re.search(r"\[2/2\] point_0001_\w+.h5: recomputed \(damaged: FileError: .*\) run [\d.e-]+ s", out), out
    assert out.strip().splitlines()[-1].startswith("2 points in ")
    assert "1 done, 1 skipped, 1 recomputed" not in out and \
        "0 done, 1 skipped, 1 recomputed (their files were damaged), 0 failed" in out, out
    with open(folder / "sweep.csv", newline="") as f:
        assert [row["status"] for row in csv.DictReader(f)] == ["skipped", "recomputed"]
    assert resources.machine_memory()
