"""Scenario files: every example runs from the CLI on a small grid; bad files fail cleanly."""
import glob
import os
import subprocess
import sys

import numpy as np
import pytest

from framework import scenario

from cli_helpers import GOOD
from cli_helpers import cli as main_in_process

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = sorted(p for p in glob.glob(os.path.join(ROOT, "examples", "*.toml"))
                  if not os.path.basename(p).startswith("sweep_")) + [scenario.demo_path()]


def cli(*args):
    return subprocess.run([sys.executable, "-m", "framework", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=600)


#: Scenario files whose bodies a coarse grid cannot resolve: run at their own resolution, with the slow studies.
FULL = {"rolling_over_inhomogeneity.toml"}


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow) if os.path.basename(p) in FULL else p
                                  for p in EXAMPLES], ids=os.path.basename)
def test_example_scenario_runs_from_the_cli(path, tmp_path):
    coarse = [] if os.path.basename(path) in FULL else ["--cells", "21"]
    completed = cli("run", path, "--out", str(tmp_path), *coarse, "--quiet")
    assert completed.returncode == 0, completed.stderr
    names = set(os.listdir(tmp_path))
    assert "summary.csv" in names and "INCOMPLETE" not in names
    assert "surface.pvd" in names and "history.png" in names
    with open(tmp_path / "summary.csv") as f:
        rows = f.read().strip().splitlines()
    parsed = scenario.read(path)
    assert len(rows) == 1 + len(parsed.simulation.output_times)


def test_demo_command(tmp_path):
    completed = cli("demo", "--out", str(tmp_path), "--cells", "25", "--quiet")
    assert completed.returncode == 0, completed.stderr
    assert {"summary.csv", "surface.pvd", "volume.pvd", "history.png"} <= set(os.listdir(tmp_path))
    assert "wrote" in completed.stdout


@pytest.mark.parametrize("change, message", [
    (("[grid]", "[grid]\ncolour = 'red'"), r"grid: unknown key\(s\) \['colour'\]"),
    (("[indenter]", "[indentor]"), r"unknown table\(s\) \['indentor'\]"),
    (("young = 1e9", "young = 'stiff'"), r"material: young must be a finite real number, got 'stiff'"),
    (("radius = 5e-3\n", ""), r"indenter: missing required key\(s\) \['radius'\] for Sphere"),
    (("type = \"Elastic\"\nyoung = 1e9\npoisson = 0.3", "preset = \"PMMX\""),
     r"material.preset: unknown preset 'PMMX'; expected one of \['PMMA'\]"),
    (("size = [1e-3, 1e-3]", "size = [1e-3, -1e-3]"), r"grid: size\[1\] must be positive \[m\], got -0.001"),
    (("type = \"Sphere\"", "type = \"Sphre\""), r"indenter.type: unknown type 'Sphre'"),
    (("load = 1.0", "load = { type = \"Step\", valu = 1.0 }"), r"schedule.load: unknown key\(s\) \['valu'\]"),
    (("load = 1.0", "load = 1.0\ntimes = { start = 1, stop = 0.5, count = 3, spacing = 'linear' }"),
     r"times must be strictly increasing"),
    (("shape = [16, 16]", "shape = [16, 16"), r"not valid TOML"),
])
def test_bad_scenarios_fail_with_one_clear_message(tmp_path, change, message):
    path = tmp_path / "bad.toml"
    path.write_text(GOOD.replace(*change))
    out = tmp_path / "out"
    completed = cli("run", str(path), "--out", str(out))
    assert completed.returncode == 2
    assert completed.stderr.startswith("error: ") and "Traceback" not in completed.stderr
    assert len(completed.stderr.strip().splitlines()) == 1
    import re
    assert re.search(message, completed.stderr), completed.stderr
    assert not out.exists()  # nothing written, nothing half-written presented as complete


def test_missing_table_and_missing_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(GOOD.split("[schedule]")[0])
    with pytest.raises(scenario.ScenarioError, match=r"missing required table \[schedule\]"):
        scenario.read(str(path))
    with pytest.raises(scenario.ScenarioError, match="no such scenario file"):
        scenario.read(str(tmp_path / "nowhere.toml"))


def test_a_run_that_fails_midway_is_marked_incomplete(tmp_path):
    """A load the grid cannot carry at step 2: the finished step is on disk, INCOMPLETE says so."""
    path = tmp_path / "late.toml"
    path.write_text(GOOD.replace("load = 1.0", "load = [1.0, 5000.0]\ntimes = [0.0, 1.0]")
                    + "[output]\nvtu = true\nhistory = []\n")
    completed = cli("run", str(path), "--out", str(tmp_path / "out"), "--quiet")
    assert completed.returncode == 2 and "grid edge" in completed.stderr
    names = set(os.listdir(tmp_path / "out"))
    assert "INCOMPLETE" in names and "summary.csv" in names and "surface.pvd" in names


# --------------------------------------------------------------------------- the command line, in process

def refused(capsys, tmp_path, text, message, *extra, command="run"):
    """``check`` and ``run`` both refuse the file with one line naming the problem; run writes nothing."""
    path = tmp_path / "bad.toml"
    path.write_bytes(text) if isinstance(text, bytes) else path.write_text(text)
    out = tmp_path / "out"
    for args in (["check", str(path)], [command, str(path), "--out", str(out), "--quiet", *extra]):
        code, _, err = main_in_process(capsys, *args)
        assert code == 2 and err.startswith("error: ") and len(err.strip().splitlines()) == 1, err
        import re
        assert re.search(message, err), err
        assert not out.exists()


SLICE = GOOD + "[output]\npictures = [{ field = 'von_mises', kind = 'slice' }]\n"


@pytest.mark.parametrize("text, message", [
    (GOOD + "[output]\npictures = [{ field = 'presure' }]\n",
     r"output.pictures\[0\].field: expected one of \['pressure', 'displacement', 'gap', 'contact'\] for kind "
     r"'map', got 'presure'"),
    (GOOD + "[output]\npictures = [{ field = 'pressure', kind = 'contour' }]\n",
     r"output.pictures\[0\].kind: expected one of \['map', 'slice', 'surface'\], got 'contour'"),
    (GOOD + "[output]\npictures = [{ field = 'pressure', kind = 'slice' }]\n",
     r"output.pictures\[0\].field: expected one of \['von_mises', .*for kind 'slice', got 'pressure'"),
    (SLICE, r"output.pictures\[0\]: a slice shows subsurface stresses, which need \[grid\] layers .*got layers = 0"),
    (GOOD + "[output]\npictures = [{ field = 3 }]\n", r"output.pictures\[0\].field: expected a name, got 3"),
    (GOOD + "[output]\nhistory = ['radius', 'load']\n",
     r"output.history: unknown series \['radius'\]; expected some of \['load', 'approach'"),
    (GOOD + "[output]\npictures = [{ field = 'pressure', file = '/tmp/pressure.png' }]\n",
     r"output.pictures\[0\].file: expected a .png file name inside the output folder \(no folder part\), got "
     r"'/tmp/pressure.png'"),
    (GOOD + "[output]\npictures = [{ field = 'pressure', file = '../pressure.png' }]\n",
     r"output.pictures\[0\].file: expected a .png file name inside .*got '../pressure.png'"),
    (GOOD + "[output]\npictures = [{ field = 'pressure', file = 'maps/pressure.png' }]\n",
     r"output.pictures\[0\].file: .*got 'maps/pressure.png'"),
    (GOOD + "[output]\npictures = [{ field = 'pressure', file = '..' }]\n", r"output.pictures\[0\].file: .*got '..'"),
    (GOOD + "[output]\npictures = [{ field = 'pressure', file = 'result.h5' }]\n",
     r"output.pictures\[0\].file: .*got 'result.h5'"),
    (GOOD + "[output]\npictures = [{ field = 'pressure', file = 7 }]\n", r"output.pictures\[0\].file: .*got 7"),
    (GOOD + "[output]\npictures = [{ field = 'pressure', file = 'history.png' }]\n",
     r"output.pictures\[0\].file: 'history.png' is already written by output.history"),
    (GOOD + "[output]\npictures = [{ field = 'pressure' }, { field = 'pressure', step = 0 }]\n",
     r"output.pictures\[1\].file: 'pressure_map.png' is already written by output.pictures\[0\]"),
    (GOOD + "[output]\nvtu = 'yes'\n", r"output.vtu must be a boolean, true or false, got 'yes'"),
    (GOOD + "[output]\npictures = [{ field = 'pressure', step = true }]\n",
     r"output.pictures\[0\].step: expected an index in \[-1, 1\), got True"),
    (GOOD + "[output]\nsummary = false\n", r"output: unknown key\(s\) \['summary'\]"),
    (GOOD + "[output]\nsteps = [true]\n", r"output.steps: expected \"all\" or a list of step indices, got \[True\]"),
    (GOOD + "[options]\ntolerance = 0.0\n", r"bad.toml: options: tolerance must lie in \[1e-15, 1\)"),
    (GOOD + "[options]\nmax_iterations = -1\n", r"options: max_iterations must be an integer >= 1, got -1"),
    (GOOD + "[options]\ncheck_edges = 'no'\n", r"options: check_edges must be a boolean, true or false, got 'no'"),
    (GOOD + "[options]\ntolerence = 1e-6\n", r"options: unknown option\(s\) \['tolerence'\]"),
    (GOOD.replace("shape = [16, 16]", "shape = [1, 1]"), r"grid: shape\[0\] must be >= 3 along the non-periodic"),
    (GOOD.replace("shape = [16, 16]", "shape = [16, 16]\nlayers = 4"), r"depth is missing: layers = 4"),
    (GOOD.replace("load = 1.0", "load = 1.0\ntype = 'Eccentric'\noffset = [0.4e-3, 0.0]")
     .replace("type = \"Sphere\"\nradius = 5e-3", "type = \"FlatPunch\"\nradius = 1e-4"),
     r"bad.toml: offset \(0.0004, 0.0\) m lies outside the area the indenter can touch"),
    (GOOD.replace("type = \"Sphere\"\nradius = 5e-3", "type = \"HeightMap\"\nheights = [[0.0, 0.0], [0.0, 0.0]]"),
     r"bad.toml: heights has shape \(2, 2\), the grid has shape \(16, 16\)"),
    (GOOD.replace("load = 1.0", "load = []"), r"schedule: load is empty"),
    (GOOD.replace("load = 1.0", "load = [1.0, 'a']"), r"schedule: load must be a number, a sequence of numbers"),
    (GOOD.replace("load = 1.0", "load = { value = 1.0 }"), r"schedule: load must be a number, .*got \{'value': 1.0\}"),
    (GOOD.replace("load = 1.0", "load = 1.0\ntimes = { start = 0.1, stop = 1, count = 3, zero = 'no' }"),
     r"schedule.times.zero must be a boolean, true or false, got 'no'"),
    (GOOD.replace("load = 1.0", "load = 1.0\ntimes = { start = 0.1, stop = 1, count = true }"),
     r"schedule.times.count must be an integer >= 1, got True"),
    (GOOD.replace("load = 1.0", "load = 1.0\ntimes = { start = 0.0, stop = 1, count = 3 }"),
     r"schedule.times: geometric spacing needs start and stop > 0, got 0.0 and 1.0"),
    (GOOD.replace("radius = 5e-3", "radius = 5e300"), r"indenter: radius must lie between 1e-12 and 1e\+06 m"),
    (GOOD.replace("radius = 5e-3", "radius = 5e-3\nexact = 'no'"), r"indenter: exact must be a boolean"),
    (GOOD.replace("young = 1e9", "young = 1e-300"), r"material: young must lie between 0.001 and 1e\+15 Pa"),
    (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe", r"bad.toml: not a UTF-8 text file \(byte 0x89 at offset 0\)"),
    (GOOD.encode("utf-16"), r"not a UTF-8 text file \(byte 0xff at offset 0\)"),
    ("[grid]\nshape = [16, 16]\x00", r"not valid TOML"),
])
def test_check_refuses_what_run_would_refuse(capsys, tmp_path, text, message):
    """Each of these passed `check` (or gave a traceback) and failed in `run`, some after writing result.h5."""
    refused(capsys, tmp_path, text, message)


def test_a_byte_order_mark_is_accepted(capsys, tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + GOOD.encode())
    code, out, err = main_in_process(capsys, "check", str(path))
    assert code == 0 and "ok (1 steps on a (16, 16) grid)" in out, err


@pytest.mark.parametrize("args, message", [
    (["--every", "0"], r"error: argument --every: expected an integer >= 1, got '0' \(see python -m framework run -h\)"),
    (["--every", "-2"], r"argument --every: expected an integer >= 1, got '-2'"),
    (["--every", "ten"], r"argument --every: expected an integer >= 1, got 'ten'"),
    (["--cells", "1"], r"argument --cells: expected an integer >= 3, got '1'"),
    (["--cells", "0"], r"argument --cells: expected an integer >= 3, got '0'"),
    (["--frobnicate"], r"error: unrecognized arguments: --frobnicate"),
])
def test_bad_command_line_arguments(capsys, tmp_path, args, message):
    path = tmp_path / "good.toml"
    path.write_text(GOOD)
    out = tmp_path / "out"
    code, _, err = main_in_process(capsys, "run", str(path), "--out", str(out), *args)
    assert code == 2 and len(err.strip().splitlines()) == 1
    import re
    assert re.search(message, err), err
    assert not out.exists()


def test_no_command_and_unknown_command(capsys):
    for args in ([], ["frobnicate"]):
        code, _, err = main_in_process(capsys, *args)
        assert code == 2 and err.startswith("error: ") and len(err.strip().splitlines()) == 1, err


def test_scenario_path_that_is_a_folder(capsys, tmp_path):
    code, _, err = main_in_process(capsys, "check", str(tmp_path))
    assert code == 2 and err.strip() == f"error: {tmp_path}: is a folder, not a scenario file"


def test_out_that_cannot_hold_results(capsys, tmp_path, monkeypatch):
    path = tmp_path / "good.toml"
    path.write_text(GOOD + "[output]\nvtu = false\nhistory = []\n")
    a_file = tmp_path / "taken"
    a_file.write_text("not a folder")
    cases = [(a_file, r"--out '.*taken' is a file; expected a folder for the results"),
             (a_file / "sub", r"--out '.*taken/sub': cannot write the results there \(Not a directory\)")]
    for out, message in cases:
        code, _, err = main_in_process(capsys, "run", str(path), "--out", str(out), "--quiet")
        import re
        assert code == 2 and len(err.strip().splitlines()) == 1 and re.search(message, err), err
    assert a_file.read_text() == "not a folder"
    # a read-only folder (chmod does not stop root, so the permission test is simulated)
    monkeypatch.setattr(os, "access", lambda *args: False)
    out = tmp_path / "readonly"
    out.mkdir()
    code, _, err = main_in_process(capsys, "run", str(path), "--out", str(out), "--quiet")
    assert code == 2 and re.search(r"--out '.*readonly': cannot write the results there \(Permission denied\)", err)
    assert os.listdir(out) == []


def test_run_summary_table_and_numbering(capsys, tmp_path):
    """One 0-based numbering (progress, table, file names), a '...' row where rows are skipped, files by kind."""
    path = tmp_path / "steps.toml"
    path.write_text(GOOD.replace("load = 1.0", "load = 1.0\ntimes = { start = 1, stop = 14, count = 14, "
                                 "spacing = 'linear' }") + "[output]\nhistory = []\n")
    code, out, err = main_in_process(capsys, "run", str(path), "--out", str(tmp_path / "out"))
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0].startswith("step 0/13  t = 1 s") and lines[13].startswith("step 13/13  t = 14 s")
    header = next(i for i, line in enumerate(lines) if "time s" in line)
    rows = [line.split()[0] for line in lines[header + 1:header + 14]]
    assert rows == ["0", "1", "2", "3", "4", "5", "...", "8", "9", "10", "11", "12", "13"]
    assert "14 steps (0 to 13)" in out and "wrote 33 files" in out
    names = set(os.listdir(tmp_path / "out"))
    assert {"surface_0000.vtu", "surface_0013.vtu"} <= names and "surface_0014.vtu" not in names
    assert " 14  surface_NNNN.vtu" in out and "  1  result.h5" in out
    assert len(out.splitlines()) < 40  # no list of every file


LINE_ROLLING = """
[grid]
shape = [48, 2]
size = [2.4e-3, 0.1e-3]
periodic = [false, true]
depth = 0.6e-3
layers = 6

[material]
type = "StandardLinearSolid"
e_inf = 1e7
e_1 = 9e7
tau = 1.0
poisson = 0.5

[indenter]
type = "Cylinder"
radius = 10e-3
axis = 1

[schedule]
type = "Rolling"
load = [1e-3, 2e-3]
velocity = [2e-5, 0.0]
steady = true

[output]
history = ["half_width", "friction_coefficient", "torque", "dissipated_power"]
pictures = [{ field = "von_mises", kind = "slice" }, { field = "pressure", kind = "map" }]
"""


def test_a_steady_rolling_line_contact_runs_from_the_cli(tmp_path):
    """Line contacts have stresses (volumes and slices); rolling series reach summary.csv and the plot."""
    path = tmp_path / "line.toml"
    path.write_text(LINE_ROLLING)
    out = tmp_path / "out"
    assert cli("check", str(path)).returncode == 0
    completed = cli("run", str(path), "--out", str(out), "--quiet")
    assert completed.returncode == 0, completed.stderr
    names = set(os.listdir(out))
    assert {"volume.pvd", "von_mises_slice.png", "history.png", "summary.csv"} <= names
    with open(out / "summary.csv") as f:
        header, *rows = [line.split(",") for line in f.read().strip().splitlines()]
    column = {name.split(" [")[0]: i for i, name in enumerate(header)}
    assert header[column["dissipated_power"]] == "dissipated_power [W]"
    assert all(float(row[column["friction_coefficient"]]) > 0 for row in rows)
    assert all(float(row[column["half_width"]]) > 0 for row in rows)


# --------------------------------------------------------------------------- inhomogeneities, [[inclusions]]

LAYERED = GOOD.replace("shape = [16, 16]", "shape = [24, 24]\ndepth = 0.5e-3\nlayers = 16").replace(
    "young = 1e9", "young = 200e9").replace("load = 1.0", "load = 20.0")
INCLUSION = """
[[inclusions]]
center = [0.0, 0.0, 0.22e-3]
semi_axes = [0.15e-3, 0.13e-3, 0.13e-3]
material = { young = 600e9, poisson = 0.25 }
"""


def test_inclusion_tables_become_ellipsoids(tmp_path):
    from framework import inclusions, materials
    path = tmp_path / "good.toml"
    stiffness = [[250e9, 150e9, 150e9, 0, 0, 0], [150e9, 250e9, 150e9, 0, 0, 0], [150e9, 150e9, 250e9, 0, 0, 0],
                 [0, 0, 0, 120e9, 0, 0], [0, 0, 0, 0, 120e9, 0], [0, 0, 0, 0, 0, 120e9]]
    path.write_text(LAYERED + INCLUSION.replace("]\nmaterial", "]\neuler = [90.0, 0.0, 0.0]\nmaterial")
                    + INCLUSION.replace("0.0, 0.0, 0.22e-3", "0.0, 0.3e-3, 0.3e-3")
                    .replace("{ young = 600e9, poisson = 0.25 }", f"{{ stiffness = {stiffness} }}")
                    + "orientation = [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]\n")
    first, second = scenario.read(str(path)).simulation.inclusions
    # z-x-z angles (90, 0, 0) in degrees: a quarter turn about x3, a1 along x2 and a2 along -x1
    np.testing.assert_allclose(first.orientation, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)
    assert first.material == materials.Elastic(600e9, 0.25) and first.center == (0.0, 0.0, 0.22e-3)
    assert second.material == materials.AnisotropicElastic(np.array(stiffness, dtype=float))
    assert np.array_equal(second.orientation, [[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    assert second.semi_axes == (0.15e-3, 0.13e-3, 0.13e-3)
    # the convention names the axes: (90, 0, 0) about x2 first turns a1 to -x3
    path.write_text(LAYERED + INCLUSION + 'euler = [90.0, 0.0, 0.0]\nconvention = "yxy"\n')
    body, = scenario.read(str(path)).simulation.inclusions
    np.testing.assert_allclose(body.orientation[:, 0], [0, 0, -1], atol=1e-15)
    assert isinstance(body, inclusions.Ellipsoid)


@pytest.mark.parametrize("text, message", [
    (INCLUSION.replace("semi_axes", "semiaxes"),
     r"inclusions\[0\]: unknown key\(s\) \['semiaxes'\]; expected some of \['center', 'convention', 'euler'"),
    (INCLUSION.replace("center = [0.0, 0.0, 0.22e-3]\n", ""),
     r"inclusions\[0\]: missing required key\(s\) \['center'\]"),
    (INCLUSION + INCLUSION.replace("0.22e-3]", "-0.1e-3]"),
     r"inclusions\[1\]: center\[2\] \(the depth of the centre\) must be positive \[m\], got -0.0001"),
    (INCLUSION.replace("0.13e-3, 0.13e-3]", "0.13e-3]"),
     r"inclusions\[0\]: semi_axes has shape \(2,\), expected \(3,\)"),
    (INCLUSION.replace("{ young = 600e9, poisson = 0.25 }", "{ young = 600e9 }"),
     r"inclusions\[0\].material: expected the keys young and poisson \(isotropic\) or stiffness"),
    (INCLUSION.replace("{ young = 600e9, poisson = 0.25 }", "'steel'"),
     r"inclusions\[0\].material: expected a table \{young, poisson\} or \{stiffness\}, got 'steel'"),
    (INCLUSION.replace("poisson = 0.25", "poisson = 0.7"), r"inclusions\[0\].material: poisson must lie in"),
    (INCLUSION.replace("{ young = 600e9, poisson = 0.25 }", "{ stiffness = [[1e9, 0], [0, 1e9]] }"),
     r"inclusions\[0\].material: stiffness must be a 6x6 Voigt matrix \[Pa\], got shape \(2, 2\)"),
    (INCLUSION + "euler = [30.0, 0.0]\n",
     r"inclusions\[0\].euler: expected three angles \[phi, theta, psi\] in degrees, got \[30.0, 0.0\]"),
    (INCLUSION + "euler = [30.0, 0.0, 0.0]\nconvention = 'zzx'\n", r"inclusions\[0\].euler: convention must be three"),
    (INCLUSION + "convention = 'zxz'\n", r"inclusions\[0\].convention: names the axes of euler angles"),
    (INCLUSION + "euler = [30.0, 0.0, 0.0]\norientation = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n",
     r"inclusions\[0\]: give orientation \(a 3x3 matrix\) or euler \(angles in degrees\), not both"),
    (INCLUSION + "orientation = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]\n",
     r"inclusions\[0\]: orientation must be a proper rotation \(det = \+1\)"),
    (INCLUSION + "orientation = [[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n",
     r"inclusions\[0\]: orientation must be a rotation matrix"),
    (INCLUSION + "type = 'Cuboid'\n", r"inclusions\[0\].type: expected 'Ellipsoid' \(the only shape\), got 'Cuboid'"),
    (INCLUSION + INCLUSION.replace("0.0, 0.0, 0.22e-3", "0.1e-3, 0.0, 0.25e-3"),
     r"inclusions\[0\] and inclusions\[1\] overlap or touch"),
    (INCLUSION.replace("0.22e-3]", "0.1e-3]"), r"inclusions\[0\] cuts the surface"),
    (INCLUSION.replace("0.15e-3, 0.13e-3, 0.13e-3", "0.15e-3, 0.05e-3, 0.13e-3"),
     r"inclusions\[0\]: semi_axes\[1\] = 5e-05 m spans only 1.2 cuboids"),
    ("[inclusions]\ncenter = [0.0, 0.0, 0.22e-3]\n", r"inclusions: expected an array of tables \(\[\[inclusions\]\] "),
])
def test_bad_inclusion_tables_are_named(capsys, tmp_path, text, message):
    refused(capsys, tmp_path, LAYERED + text, r"bad.toml: " + message)


def test_inclusions_need_an_elastic_or_viscoelastic_solid_matrix(capsys, tmp_path):
    text = LAYERED.replace('type = "Elastic"\nyoung = 200e9\npoisson = 0.3',
                           'type = "Maxwell"\nyoung = 200e9\nrelaxation_time = 1.0\npoisson = 0.3') + INCLUSION
    refused(capsys, tmp_path, text, r"bad.toml: inclusions need an elastic matrix or a viscoelastic solid")


def test_run_with_inclusions_shows_the_couplings(capsys, tmp_path):
    path = tmp_path / "good.toml"
    path.write_text(LAYERED.replace("load = 20.0", "load = [10.0, 20.0]") + INCLUSION
                    + "[output]\nvtu = false\nhistory = []\n")
    code, out, err = main_in_process(capsys, "check", str(path))
    assert code == 0 and "ok (2 steps" in out, err
    code, out, err = main_in_process(capsys, "run", str(path), "--out", str(tmp_path / "out"), "--quiet")
    assert code == 0, err
    header, *rows = out.splitlines()[:3]
    assert header.split()[-2:] == ["iter", "coupl"]
    from framework import load_result
    result = load_result(tmp_path / "out" / "result.h5")
    assert [int(row.split()[-1]) for row in rows] == list(result.couplings) and min(result.couplings) > 1
    assert len(result.inclusions) == 1 and np.abs(result.eigenstrain(-1)).max() > 0
