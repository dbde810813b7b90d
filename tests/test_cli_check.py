"""`check` finds what `run` would fail on: missing extras, memory, bad physics; and prints the run's estimate."""
import glob
import math
import os
import re
import sys
import tomllib

import pytest

from framework import extras, loads, resources, scenario
from framework.errors import ParameterError

from cli_helpers import GOOD, cli, one_error

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
QUIET = "[output]\nvtu = false\nhistory = []\n"
INCLUSION = """
[[inclusions]]
center = [0.0, 0.0, 0.2e-3]
semi_axes = [0.1e-3, 0.1e-3, 0.1e-3]
material = { young = 70e9, poisson = 0.22 }
"""


def write(tmp_path, text, name="scenario.toml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


# --------------------------------------------------------------------------- the extras a run needs


@pytest.mark.parametrize("hidden, extra, what", [
    ("h5py", "io", r"h5py \(for result.h5\)"),
    ("pyvista", "viz", r"pyvista \(for VTU files, history.png\)|pyvista \(for VTU files\)"),
    ("vtkmodules", "viz", r"vtk \(for VTU files"),
    ("matplotlib", "viz", r"matplotlib \(for history.png\)"),
])
def test_check_names_a_missing_extra_in_one_line(capsys, tmp_path, monkeypatch, hidden, extra, what):
    """As if the package were not installed: check and run say so, with the command; run writes nothing."""
    path = write(tmp_path, GOOD)   # the default [output]: VTU files, history.png, result.h5
    monkeypatch.setitem(sys.modules, hidden, None)
    code, out, err = cli(capsys, "check", path)
    one_error(code, err, r"scenario.toml: run needs packages that are not installed: .*" + what)
    assert f"pip install 'viscocontact[{extra}]'" in err and "ok" not in out
    code, _, err = cli(capsys, "run", path, "--out", str(tmp_path / "out"), "--quiet")
    one_error(code, err, f"pip install 'viscocontact\\[{extra}\\]'")
    assert not (tmp_path / "out").exists()


def test_several_missing_extras_give_one_command(capsys, tmp_path, monkeypatch):
    path = write(tmp_path, GOOD)
    for hidden in ("h5py", "pyvista"):
        monkeypatch.setitem(sys.modules, hidden, None)
    code, _, err = cli(capsys, "check", path)
    one_error(code, err, r"h5py \(for result.h5\); pyvista \(for VTU files\); install them with: "
                         r"pip install 'viscocontact\[io,viz\]'$")


def test_only_what_the_outputs_use_is_needed(capsys, tmp_path, monkeypatch):
    """Without VTU files, pictures or plots, the viz packages are not needed; result.h5 still needs h5py."""
    path = write(tmp_path, GOOD + QUIET)
    for hidden in ("pyvista", "vtkmodules", "matplotlib", "PIL"):
        monkeypatch.setitem(sys.modules, hidden, None)
    code, out, err = cli(capsys, "check", path)
    assert code == 0 and "ok (1 steps" in out, err
    assert extras.scenario_needs(scenario.read(path).output) == {"result.h5": ("h5py",)}


def test_every_optional_package_has_its_extra_in_pyproject():
    with open(os.path.join(ROOT, "pyproject.toml"), "rb") as f:
        declared = tomllib.load(f)["project"]["optional-dependencies"]
    for package, extra in extras.EXTRAS.items():
        name = extras.DISTRIBUTIONS.get(package, package)
        assert any(re.search(rf"\b{re.escape(name)}\b", requirement, re.I) for requirement in declared[extra]), \
            (package, extra)


# --------------------------------------------------------------------------- memory, time, files


def test_check_prints_the_estimate_of_memory_time_and_files(capsys):
    code, out, err = cli(capsys, "check", os.path.join(ROOT, "examples", "hertz_elastic.toml"))
    lines = out.strip().splitlines()
    assert code == 0 and lines[0].endswith("ok (3 steps on a (129, 129) grid)"), err
    assert re.fullmatch(r"estimate: about [\d.]+ MB of memory \(this machine: [\d.]+ GiB\), [\d.]+ s on one core, "
                        r"[\d.]+ MB of files \(result.h5, 3 surface steps, 1 volume, 1 picture, history.png\)",
                        lines[1]), lines[1]


def test_the_file_estimate_is_near_what_a_run_writes(capsys, tmp_path):
    """The demo on a coarse grid: the files written are within a factor 1.5 of the estimate (models of VTU sizes)."""
    out = tmp_path / "demo"
    code, _, err = cli(capsys, "demo", "--out", str(out), "--cells", "25", "--quiet")
    assert code == 0, err
    written = sum(os.path.getsize(path) for path in glob.glob(str(out / "*")))
    demo = scenario.read(scenario.demo_path(), cells=25)
    estimate = resources.for_simulation(demo.simulation, demo.output)
    assert estimate.disk / 1.5 < written < 1.5 * estimate.disk, (written, estimate.files)


def test_a_grid_beyond_the_machine_memory_fails_in_check_and_run(capsys, tmp_path):
    """[12000, 12000] passed check and died in run with ArrayMemoryError: refused at once, nothing allocated."""
    path = write(tmp_path, GOOD.replace("[16, 16]", "[12000, 12000]"))
    code, _, err = cli(capsys, "check", path)
    one_error(code, err, r"scenario.toml: the run needs about [\d.]+ GiB of memory \(the contact solver: [\d.]+ GiB\), "
                         r"more than this machine's [\d.]+ GiB; expected a run that fits")
    code, _, err = cli(capsys, "run", path, "--out", str(tmp_path / "out"), "--quiet")
    one_error(code, err, r"more than this machine's")
    assert not (tmp_path / "out").exists()


def test_a_huge_box_of_inclusions_fails_in_check_without_a_traceback(capsys, tmp_path):
    """[8192, 8192] x 4096 layers with an inclusion gave a traceback in check itself (a 32.8 GiB indicator)."""
    text = GOOD.replace("[16, 16]", "[8192, 8192]").replace("[grid]", "[grid]\ndepth = 0.5e-3\nlayers = 4096")
    code, _, err = cli(capsys, "check", write(tmp_path, text + INCLUSION))
    one_error(code, err, r"the run needs about [\d.]+ [TP]iB of memory \(the inhomogeneities' box: ")


def test_check_warns_above_half_the_memory(capsys, tmp_path, monkeypatch):
    path = write(tmp_path, GOOD + QUIET)
    needs = resources.for_simulation(scenario.read(path).simulation, scenario.read(path).output).memory
    monkeypatch.setattr(resources, "machine_memory", lambda: 1.5 * needs)
    code, out, err = cli(capsys, "check", path)
    assert code == 0 and "ok" in out
    # (the 16-cell grid's contact is also warned of, in a line of its own: framework.resolution)
    assert re.search(r"^warning: .*scenario.toml: the run needs about .* of memory \(.*\), more than 50% of this "
                     r"machine's [^\n]*$", err, re.M), err
    monkeypatch.setattr(resources, "machine_memory", lambda: 0.9 * needs)
    one_error(*cli(capsys, "check", path)[::2], r"more than this machine's")


def test_the_estimate_grows_with_what_the_run_keeps():
    from framework import Grid, materials
    grid = Grid(shape=(64, 64), size=(1e-3, 1e-3), depth=0.5e-3, layers=8)
    elastic = materials.Elastic(young=1e9, poisson=0.3)
    one = resources.estimate(grid, elastic)
    assert resources.estimate(grid, elastic, steps=10).memory > one.memory          # the records
    assert resources.estimate(grid, materials.PMMA).memory > one.memory           # the history
    periodic = Grid(shape=(64, 64), size=(1e-3, 1e-3), periodic=(True, True))
    assert resources.estimate(periodic, elastic).memory < resources.estimate(Grid(shape=(64, 64), size=(1e-3, 1e-3)),
                                                                            elastic).memory
    assert list(one.parts)[0] == "the contact solver" and one.files == {"result.h5": (1, 64 * 64 * 10)}
    assert resources.size(3 * 2**40) == "3 TiB" and resources.size(2.5e6) == "2.5 MB"
    assert resources.duration(30) == "30 s" and resources.duration(3 * 3600) == "3 h"
    assert resources.machine_memory() > 2**28


def test_the_estimate_holds_the_inclusions_stress_field_when_stresses_are_written():
    """Volumes (or slices) of a run with inhomogeneities need their field on the whole grid
    (EigenstrainField, kernels spanning the grid): its memory model, the box anywhere on the grid, is a part of the
    estimate; without stresses written it is not."""
    from framework import Grid, inclusions, materials
    from framework.operators.eigenstrain_field import field_bytes
    grid = Grid(shape=(64, 48), size=(1.6e-3, 1.2e-3), depth=0.5e-3, layers=20)
    glass = inclusions.Ellipsoid(center=(0.0, 0.0, 0.2e-3), semi_axes=(0.1e-3,) * 3, material=materials.Elastic(70e9, 0.22))
    elastic = materials.Elastic(young=3e9, poisson=0.35)
    written = resources.estimate(grid, elastic, inclusions=[glass], output=scenario.Output(vtu=True))
    quiet = resources.estimate(grid, elastic, inclusions=[glass], output=scenario.Output(vtu=False))
    start, shape, _ = resources._box(grid, [glass], None)
    expected = field_bytes(grid, start, shape, [(0, 0), (64 - shape[0], 48 - shape[1])])
    assert written.parts["the inhomogeneities' stress field"] == expected > field_bytes(grid, start, shape)
    assert "the inhomogeneities' stress field" not in quiet.parts
    assert written.memory - quiet.memory >= expected


@pytest.mark.parametrize("count, cells, measured", [(100, 320, 3.18), (300, 480, 8.26)])
def test_the_estimate_of_a_large_dispersion_is_near_its_measured_peak(count, cells, measured, monkeypatch):
    """The inclusion box's memory stops growing at INCLUSION a cuboid once the solver's caps are reached: the
    estimate of bench/dispersion.py's runs (glass spheres of radius 0.1 mm at 10 % in a slab 1-7 radii deep, 8 cuboids
    a radius, 2 Prony terms, 40 steps unrecorded) lies between their measured peak resident memory (README: 3.18 and
    8.26 GiB; their cuboids are square in x1, x2, half the kernels stored) and 1.5 times it; INCLUSION alone put the
    300 spheres at 35 GB, above this 24 GB machine. A box that stores every kernel is estimated higher (4.24 and
    10.80 GiB measured so)."""
    import numpy as np
    from framework import Grid, inclusions, materials
    radius, cell = 1e-4, 1e-4 / 8
    side = np.sqrt(count * 4.0 / 3.0 * np.pi * radius ** 3 / 0.1 / (6 * radius))
    ahead = 20 * cell
    slab = ((-side / 2 + ahead, side / 2 + ahead), (-side / 2, side / 2), (radius, 7 * radius))
    bodies = inclusions.random_dispersion(0.1, slab, radius, materials.Elastic(70e9, 0.22), gap=0.25 * radius, seed=0)
    grid = Grid(shape=(cells, cells), size=(cells * cell, cells * cell), depth=64 * cell, layers=64)
    matrix = materials.Viscoelastic.from_prony(e_inf=1e9, terms=[(1e9, 0.02), (1e9, 0.2)], poisson=0.35)
    estimate = resources.estimate(grid, matrix, inclusions=bodies, steps=1, solves=41)
    assert measured * 2**30 <= estimate.memory <= 1.5 * measured * 2**30
    box = math.prod(resources._box(grid, bodies, None)[1])
    assert box * resources.INCLUSION > 2 * estimate.memory
    # the box is square (half its kernels): a box that stores them all grows by INCLUSION_LARGE a cuboid
    monkeypatch.setattr(resources, "INCLUSION_LARGE_SQUARE", resources.INCLUSION_LARGE)
    every = resources.estimate(grid, matrix, inclusions=bodies, steps=1, solves=41)
    assert every.memory - estimate.memory == pytest.approx(box * (1500 - 1100), rel=1e-9)


# --------------------------------------------------------------------------- physics refused at once


def test_an_incompressible_matrix_with_inclusions_is_refused_in_check(capsys, tmp_path):
    """poisson = 0.5 with [[inclusions]]: a ZeroDivisionError in check before; not a removable singularity."""
    text = GOOD.replace("[16, 16]", "[64, 64]").replace("poisson = 0.3", "poisson = 0.5")
    text = text.replace("[grid]", "[grid]\ndepth = 0.5e-3\nlayers = 32") + INCLUSION
    code, _, err = cli(capsys, "check", write(tmp_path, text))
    one_error(code, err, r"material.poisson \(the matrix around the inclusions\) = 0.5, an incompressible solid: "
                         r"not supported with inclusions.*expected poisson < 0.5")


def test_a_cyclic_load_that_dips_below_zero_is_refused(capsys, tmp_path):
    """Output times on the crests only (0 and 1 s) passed; the trough at 0.75 s is checked where it is known."""
    text = GOOD.replace("load = 1.0", "load = { type = \"Cyclic\", mean = 1.0, amplitude = 2.0, period = 1.0 }\n"
                                      "times = [0.0, 1.0]")
    code, _, err = cli(capsys, "check", write(tmp_path, text))
    one_error(code, err, r"schedule.load: Cyclic dips to mean - amplitude = 1.0 - 2.0 = -1.0 at its troughs, and a "
                         r"load must be >= 0 at every time \(an approach too\); expected amplitude <= mean")
    with pytest.raises(ParameterError, match="expected amplitude <= mean"):
        loads.Cyclic(mean=0.0, amplitude=1e-9, period=1.0, shape="triangle")
    assert loads.Cyclic(mean=2.0, amplitude=2.0, period=1.0)(0.75) == pytest.approx(0.0, abs=1e-12)


# --------------------------------------------------------------------------- files named, files written


def test_control_characters_in_names_are_refused(capsys, tmp_path):
    text = GOOD + '[output]\npictures = [{ field = "pressure", file = "map\\u001b[2J.png" }]\n'
    code, _, err = cli(capsys, "check", write(tmp_path, text))
    one_error(code, err, r"output.pictures\[0\].file: 'map\\x1b\[2J.png' holds the control character '\\x1b' at "
                         r"position 3; expected a file name of printable characters")
    code, _, err = cli(capsys, "run", write(tmp_path, GOOD + QUIET), "--out", str(tmp_path / "a\nb"), "--quiet")
    one_error(code, err, r"--out: '.*a\\nb' holds the control character '\\n'")
    assert not (tmp_path / "a\nb").exists()


def test_run_on_a_sweep_file_names_the_command(capsys):
    path = os.path.join(ROOT, "examples", "sweep_sphere.toml")
    code, _, err = cli(capsys, "run", path, "--out", "nowhere", "--quiet")
    one_error(code, err, r"sweep_sphere.toml: a sweep file .* run it with python -m framework sweep .*sphere.toml")


@pytest.mark.parametrize("path", sorted(p for p in glob.glob(os.path.join(ROOT, "examples", "*.toml"))
                                        if not os.path.basename(p).startswith("sweep_")) + [scenario.demo_path()],
                         ids=os.path.basename)
def test_examples_write_volumes_at_a_few_steps(path):
    """The README's promise: example files write subsurface volumes at a few steps (one wrote 645 MB in 49)."""
    example = scenario.read(path)
    output, grid = example.output, example.simulation.grid
    if output.vtu and grid.layers:
        assert output.volume_steps != "all" and len(output.volume_steps) <= 4, output.volume_steps
    estimate = resources.for_simulation(example.simulation, output)
    assert estimate.disk < 150e6, estimate.files
