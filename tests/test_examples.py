"""Every example runs on a small grid, and the demo writes what it promises."""
import glob
import os
import runpy
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = sorted(glob.glob(os.path.join(ROOT, "examples", "*.py")))


@pytest.mark.parametrize("path", EXAMPLES, ids=os.path.basename)
def test_example_runs_on_a_small_grid(path, tmp_path):
    module = runpy.run_path(path)
    rows = module["main"](cells=41, out=str(tmp_path))
    assert rows and len(os.listdir(tmp_path)) >= 1


def test_demo_command_writes_its_outputs(tmp_path):
    completed = subprocess.run([sys.executable, "-m", "framework", "demo", "--out", str(tmp_path), "--cells", "41"],
                               cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert completed.returncode == 0, completed.stderr
    assert {"summary.csv", "summary.txt", "fields.npz"} <= set(os.listdir(tmp_path))
    assert "max von Mises" in completed.stdout
