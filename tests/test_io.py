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
    with pytest.raises(errors.ParameterError, match="is not an HDF5 result file"):
        fw.load_result(tmp_path / "x.h5")
    with pytest.raises(errors.ParameterError, match="no result file at"):
        fw.load_result(tmp_path / "missing.h5")


def test_resume_refuses_another_configuration(tmp_path):
    build(21).run(checkpoint=str(tmp_path / "c.h5"))
    with pytest.raises(errors.ParameterError, match=r"another configuration \(grid differ\)"):
        build(23).run(resume=str(tmp_path / "c.h5"))


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
