"""Scenario files: every example runs from the CLI on a small grid; bad files fail cleanly."""
import glob
import os
import subprocess
import sys

import pytest

from framework import scenario

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = sorted(p for p in glob.glob(os.path.join(ROOT, "examples", "*.toml"))
                  if not os.path.basename(p).startswith("sweep_")) + [scenario.demo_path()]


def cli(*args):
    return subprocess.run([sys.executable, "-m", "framework", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=600)


@pytest.mark.parametrize("path", EXAMPLES, ids=os.path.basename)
def test_example_scenario_runs_from_the_cli(path, tmp_path):
    completed = cli("run", path, "--out", str(tmp_path), "--cells", "21", "--quiet")
    assert completed.returncode == 0, completed.stderr
    names = set(os.listdir(tmp_path))
    assert "summary.csv" in names and "INCOMPLETE" not in names
    assert "surface.pvd" in names and "history.png" in names
    with open(tmp_path / "summary.csv") as f:
        rows = f.read().strip().splitlines()
    parsed = scenario.read(path)
    assert len(rows) == 1 + len(parsed.simulation.schedule.times)


def test_demo_command(tmp_path):
    completed = cli("demo", "--out", str(tmp_path), "--cells", "25", "--quiet")
    assert completed.returncode == 0, completed.stderr
    assert {"summary.csv", "surface.pvd", "volume.pvd", "history.png"} <= set(os.listdir(tmp_path))
    assert "wrote" in completed.stdout


GOOD = """
[grid]
shape = [16, 16]
size = [1e-3, 1e-3]
[material]
type = "Elastic"
young = 1e9
poisson = 0.3
[indenter]
type = "Sphere"
radius = 5e-3
[schedule]
load = 1.0
"""


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
