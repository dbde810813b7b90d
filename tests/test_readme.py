"""The README's scripting examples run as written.

A block whose first line names a file (``# study.py: ...``) is a script: it is
written to that file and run as ``python study.py`` from an empty folder, as a
user would (a Dask sweep without ``if __name__ == "__main__":`` fails there,
as its workers import the script again). The other blocks run one after the
other in one namespace, as in a notebook.
"""
import csv
import os
import re
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = re.compile(r"# (\w+\.py)\b")


def readme_blocks():
    with open(os.path.join(ROOT, "README.md")) as f:
        return re.findall(r"```python\n(.*?)```", f.read(), re.S)


def test_readme_python_blocks_run(tmp_path, monkeypatch):
    blocks = [block for block in readme_blocks() if not SCRIPT.match(block)]
    assert len(blocks) >= 2
    # the README is read at the repository's root: the example data it names are where it says
    shutil.copytree(os.path.join(ROOT, "examples", "data"), tmp_path / "examples" / "data")
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for block in blocks:
        exec(compile(block, "README.md", "exec"), namespace)
    assert (tmp_path / "out" / "run" / "surface.pvd").exists() and (tmp_path / "run.h5").exists()
    assert namespace["same"].approach[-1] == namespace["result"].approach[-1]


def test_readme_scripts_run_as_scripts(tmp_path):
    pytest.importorskip("distributed", reason="the README's study needs the cluster extra")
    scripts = {SCRIPT.match(block).group(1): block for block in readme_blocks() if SCRIPT.match(block)}
    assert all(SCRIPT.match(block) for block in readme_blocks() if "fw.sweep(" in block), \
        "a block that runs a sweep must be a script (Dask's worker processes import it)"
    assert "study.py" in scripts
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [ROOT, os.environ.get("PYTHONPATH")])))
    printed = {}
    for name, code in scripts.items():
        (tmp_path / name).write_text(code)
        completed = subprocess.run([sys.executable, name], cwd=tmp_path, env=env, capture_output=True, text=True,
                                   timeout=300)
        assert completed.returncode == 0, f"python {name} failed:\n{completed.stderr[-4000:]}"
        printed[name] = completed.stdout
    with open(tmp_path / "study" / "sweep.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert [(float(row["load"]), float(row["radius"])) for row in table] == \
        [(20.0, 5e-3), (20.0, 1e-2), (80.0, 5e-3), (80.0, 1e-2)]
    for row in table:  # Hertz's contact radius, to the grid's resolution (36 um cells)
        load, radius = float(row["load"]), float(row["radius"])
        hertz = (3 * load * radius / (4 * 210e9 / (1 - 0.3**2))) ** (1 / 3)
        assert row["status"] == "done" and abs(float(row["final.contact_radius"]) - hertz) < 36e-6
        assert float(row["final.load"]) == pytest.approx(load, rel=1e-9)
    assert len(printed["study.py"].splitlines()) == 4  # one line per point
