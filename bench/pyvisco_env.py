"""Own virtual environment for the pyvisco peer, and a runner for it (stdlib only).

pyvisco (M. Springer, NREL 2022, BSD-3-Clause; https://github.com/NREL/pyvisco,
PyPI ``pyvisco``) is the DMA -> Prony-series tool the benchmark compares with.
It is kept out of the project's own environment: ``ensure_env`` builds a venv
(default ``.bench/pyvisco-venv`` at the repository root) with pinned versions,
and ``run_peer`` runs ``bench/_pyvisco_peer.py`` under it and returns its JSON.

pyvisco 2.1.3 declares its notebook GUI stack (jupyterlab, voila, ipywidgets,
ipympl, ...) as hard requirements, but ``import pyvisco`` and every function the
peer calls need only numpy, pandas, scipy and matplotlib (``inter``/``styles``,
the GUI modules, are not imported).  So pyvisco goes in with ``--no-deps`` next
to the pinned scientific stack below: a small, quick install.

    python bench/pyvisco_env.py                      # build (or reuse) the venv
    python bench/pyvisco_env.py RAW_CSV [--reference DEGC] [--shift CSV]
"""

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_PATH = ROOT / ".bench" / "pyvisco-venv"
PEER = Path(__file__).resolve().with_name("_pyvisco_peer.py")
PYVISCO = "pyvisco==2.1.3"
PINS = [  # resolved by pip for CPython 3.11 and checked with the peer (pyvisco needs >= 3.11)
    "numpy==2.4.6", "pandas==3.1.1", "scipy==1.17.1", "matplotlib==3.11.2",
    "contourpy==1.3.3", "cycler==0.12.1", "fonttools==4.68.0", "kiwisolver==1.5.1",
    "packaging==26.4", "pillow==13.0.0", "pyparsing==3.3.3", "python-dateutil==4.0.0",
    "tzdata==2026.6",
]
MARKER = ".pyvisco-pins.json"


def _base_python():
    """An interpreter >= 3.11 to make the venv from: this one, else /usr/bin/python3."""
    return sys.executable if sys.version_info >= (3, 11) else "/usr/bin/python3"


def venv_python(path=DEFAULT_PATH):
    return Path(path) / "bin" / "python"


def ensure_env(path=DEFAULT_PATH, quiet=True):
    """Create the pyvisco venv at ``path`` unless its marker already lists the same pins.

    Returns the path of the venv's python.  Idempotent: the marker file is written only
    after the install and an import check succeeded.
    """
    path, py = Path(path), venv_python(path)
    want = {"pyvisco": PYVISCO, "pins": PINS}
    marker = path / MARKER
    if py.exists() and marker.exists():
        try:
            if json.loads(marker.read_text()) == want:
                return py
        except ValueError:
            pass
    q = ["-q"] if quiet else []
    subprocess.run([_base_python(), "-m", "venv", "--clear", str(path)], check=True)
    pip = [str(py), "-m", "pip", "install", "--disable-pip-version-check", *q]
    subprocess.run([*pip, *PINS], check=True)
    subprocess.run([*pip, "--no-deps", PYVISCO], check=True)
    subprocess.run([str(py), "-I", "-c", "import matplotlib; matplotlib.use('Agg'); import pyvisco"],
                   check=True)
    marker.write_text(json.dumps(want))
    return py


def run_peer(raw_csv, reference_degc=None, shift_csv=None, path=DEFAULT_PATH, timeout=900):
    """Run pyvisco's workflow on ``raw_csv`` in its venv; return the peer's JSON as a dict."""
    py = ensure_env(path)
    cmd = [str(py), "-I", str(PEER), str(raw_csv)]
    if reference_degc is not None:
        cmd += ["--reference", str(reference_degc)]
    if shift_csv is not None:
        cmd += ["--shift", str(shift_csv)]
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["MPLBACKEND"] = "Agg"
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
    if res.returncode != 0:
        raise RuntimeError(f"pyvisco peer failed ({res.returncode}):\n{res.stderr[-3000:]}")
    return json.loads(res.stdout)


def main(argv=None):
    ap = argparse.ArgumentParser(description="Build the pyvisco venv; optionally run the peer.")
    ap.add_argument("raw_csv", nargs="?")
    ap.add_argument("--path", default=str(DEFAULT_PATH))
    ap.add_argument("--reference", type=float)
    ap.add_argument("--shift", metavar="CSV")
    args = ap.parse_args(argv)
    py = ensure_env(args.path, quiet=False)
    if args.raw_csv is None:
        print(py)
        return
    json.dump(run_peer(args.raw_csv, args.reference, args.shift, args.path), sys.stdout)
    print()


if __name__ == "__main__":
    main()
