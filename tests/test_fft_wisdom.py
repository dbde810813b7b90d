"""FFTW's wisdom kept between processes (``framework.fft``, ``FRAMEWORK_FFT_WISDOM``).

Each case runs fresh Python processes: the wisdom is read before a process's first plan and
written at its exit. Whether a plan came from the file is asked of FFTW itself: a plan made with
``FFTW_WISDOM_ONLY`` exists only where the wisdom holds that transform.
"""
import os
import stat
import subprocess
import sys

import numpy as np
import pytest

from framework import fft

pytestmark = pytest.mark.skipif(fft.pyfftw is None, reason="FFTW's wisdom needs pyFFTW")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

#: Asks FFTW whether its wisdom holds the forward transform of a RealFFTPair (the contact solver's transforms) of
#: an odd shape no other code here plans (a plan made with FFTW_WISDOM_ONLY exists only then), then plans that pair
#: and prints its transform's sum: ``known <sum>`` or ``unknown <sum>``.
PLAN = """
import numpy as np
import pyfftw
from framework import fft
fft.WISDOM.load()
a = pyfftw.empty_aligned((46, 38), dtype="float64")
b = pyfftw.empty_aligned((46, 20), dtype="complex128")
try:
    pyfftw.FFTW(a, b, axes=(-2, -1), flags=("FFTW_MEASURE", "FFTW_WISDOM_ONLY"), threads=fft.THREADS)
    known = "known"
except RuntimeError:
    known = "unknown"
pair = fft.RealFFTPair((46, 38))
pair.real_in[...] = np.arange(46 * 38).reshape(46, 38) % 7
pair.forward()
print(known, repr(float(np.abs(pair.spectrum).sum())))
"""


def run(wisdom):
    """``(known, sum)`` of :data:`PLAN` run in a fresh process with ``FRAMEWORK_FFT_WISDOM=wisdom``."""
    env = dict(os.environ, FRAMEWORK_FFT_WISDOM=str(wisdom), PYTHONPATH=ROOT)
    env.pop("FRAMEWORK_FFT_BACKEND", None)
    done = subprocess.run([sys.executable, "-c", PLAN], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stderr == "", done.stderr
    known, total = done.stdout.split()
    return known, float(total)


def test_a_process_writes_its_wisdom_and_the_next_plans_from_it(tmp_path):
    path = tmp_path / "cache" / "fftw-wisdom"          # its folder made at exit
    known, first = run(path)
    assert known == "unknown" and path.is_file()
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~mask
    assert not [p for p in path.parent.iterdir() if p.name != path.name]     # no temporary file left
    known, second = run(path)
    assert known == "known"                             # the plan is known from the file alone
    assert second == pytest.approx(first, rel=1e-14)    # the same numbers, whichever plan runs


def test_off_keeps_no_file_and_plans_without_one(tmp_path, monkeypatch):
    for value in ("off", "0", "none", "false", "OFF"):
        assert fft.wisdom_path(value) is None
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))     # where the default would write
    assert run("off")[0] == "unknown"
    assert list(tmp_path.iterdir()) == []


def test_a_damaged_file_is_ignored_and_replaced(tmp_path):
    path = tmp_path / "fftw-wisdom"
    path.write_bytes(bytes(np.random.default_rng(0).integers(0, 256, 4000, dtype=np.uint8)))
    assert run(path)[0] == "unknown"
    assert run(path)[0] == "known"                      # written back whole


def test_an_unwritable_place_costs_nothing_but_the_wisdom(unwritable_folder):
    path = os.path.join(unwritable_folder, "sub", "fftw-wisdom")
    assert run(path)[0] == "unknown"
    assert not os.path.exists(path)


def test_the_default_place_is_the_users_cache(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert fft.wisdom_path(None) == os.path.join(str(tmp_path), "viscocontact", "fftw-wisdom")
    assert fft.wisdom_path("  ") == fft.wisdom_path(None)
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path))
    assert fft.wisdom_path("") == os.path.join(str(tmp_path), ".cache", "viscocontact", "fftw-wisdom")
    assert fft.wisdom_path("~/w") == os.path.join(str(tmp_path), "w")
    assert fft.wisdom_path("rel/w") == os.path.abspath("rel/w")
