"""viz.render and viz.animate: every bad argument is a ParameterError naming it, before VTK allocates anything;
a saved result file is accepted in place of a result."""
import os
import sys

import numpy as np
import pytest

pytest.importorskip("pyvista")
Image = pytest.importorskip("PIL.Image")

from framework import Grid, Simulation, indenters, materials, schedules  # noqa: E402
from framework.errors import ParameterError  # noqa: E402
from viz import animate, render  # noqa: E402
from viz.checks import check_window_size  # noqa: E402

animation = sys.modules["viz.animate"]  # the module (viz.animate is the function)
rendering = sys.modules["viz.render"]
SMALL = {"window_size": (320, 240), "font_size": 8}


@pytest.fixture(scope="module")
def pressed():
    """An elastic ball at two loads, 12 x 12 cells x 2 layers."""
    sim = Simulation(grid=Grid(shape=(12, 12), size=(1e-3, 1e-3), depth=0.3e-3, layers=2),
                     material=materials.Elastic(young=2e9, poisson=0.35),
                     indenter=indenters.Sphere(radius=5e-3), schedule=schedules.Static(load=[2.0, 5.0]))
    return sim.run()


@pytest.fixture
def no_drawing(monkeypatch):
    """Drawing anything fails the test: the checks must come first (a huge window aborts the interpreter)."""
    def refuse(*args, **kwargs):
        raise AssertionError("VTK was asked to draw")

    monkeypatch.setattr(animation, "draw", refuse)
    monkeypatch.setattr(rendering.Overlay, "__init__", refuse)
    import pyvista
    monkeypatch.setattr(pyvista, "Plotter", refuse)


BAD = [
    (dict(window_size=(0, 0)), r"window_size must be two whole numbers of pixels \(width, height\), each in "
                               r"\[16, 8192\].*got \(0, 0\)"),
    (dict(window_size=(100000, 100000)), r"window_size .*at most 16777216 pixels .*got \(100000, 100000\)"),
    (dict(window_size=(8192, 8192)), r"window_size .*got \(8192, 8192\)"),  # each side allowed, not the area
    (dict(window_size=(640,)), r"window_size .*got \(640,\)"),
    (dict(window_size=(640.5, 480)), r"window_size .*got \(640\.5, 480\)"),
    (dict(window_size=(True, 480)), r"window_size .*got \(True, 480\)"),
    (dict(window_size="640x480"), r"window_size .*got '640x480'"),
    (dict(font_size="big"), r"font_size must be a number of pixels in \[4, 200\] .*got 'big'"),
    (dict(font_size=0), r"font_size must be .*got 0"),
    (dict(font_size=1e6), r"font_size must be .*got 1000000\.0"),
    (dict(font_size=float("nan")), r"font_size must be .*got nan"),
    (dict(font_size=True), r"font_size must be .*got True"),
    (dict(cmap="notacmap"), r"cmap must be the name of a matplotlib colour map such as 'viridis'.*got 'notacmap'"),
    (dict(cmap=3), r"cmap must be .*got 3"),
    (dict(kind="slice", origin="middle"), r"origin of the x2 slice must lie in .*got 'middle'"),
    (dict(clim=(1e9, 0)), r"clim must be \(low, high\) with low < high .*got \(1000000000.0, 0\).*never silently"),
    (dict(clim=(5.0, 5.0)), r"clim must be \(low, high\) with low < high"),
]


@pytest.mark.parametrize("change, message", BAD, ids=[repr(c) for c, _ in BAD])
def test_animate_and_render_refuse_bad_options_before_drawing(pressed, tmp_path, no_drawing, change, message):
    with pytest.raises(ParameterError, match=message):
        animate(pressed, tmp_path / "a.gif", **change)
    with pytest.raises(ParameterError, match=message):
        render(pressed, tmp_path / "a.png", **change)
    assert os.listdir(tmp_path) == []


def test_window_sizes_within_the_bounds_are_kept():
    assert check_window_size((8192, 2048)) == (8192, 2048)
    assert check_window_size((16, 16)) == (16, 16)
    assert check_window_size(np.array([640.0, 480.0])) == (640, 480)
    assert check_window_size(None) is None


def test_good_options_draw(pressed, tmp_path):
    picture = render(pressed, tmp_path / "a.png", cmap="magma", font_size=9.6, window_size=(330, 250))
    assert picture.cmap == "magma" and picture.window_size == (330, 250)
    with Image.open(picture.path) as image:
        assert image.size == (330, 250)


def test_a_result_file_is_loaded(pressed, tmp_path):
    """animate("result.h5", ...) and render("result.h5", ...) read the file with framework.load_result."""
    saved = tmp_path / "result.h5"
    pressed.save(saved)
    movie = animate(str(saved), tmp_path / "press.gif", fps=2, **SMALL)
    assert movie.steps == (0, 1)
    with Image.open(movie.path) as image:
        assert image.n_frames == 2
    same = animate(pressed, tmp_path / "again.gif", fps=2, **SMALL)
    assert movie.clim == same.clim and [f.title for f in movie.frames] == [f.title for f in same.frames]
    picture = render(saved, tmp_path / "map.png", step=0, **SMALL)
    assert picture.scalar_range == (pressed.pressure(0).min(), pressed.pressure(0).max())


def test_a_bad_result_is_named(pressed, tmp_path, no_drawing):
    with pytest.raises(ParameterError, match=r"result: cannot load the result file: no result file at .*missing\.h5"):
        animate(tmp_path / "missing.h5", tmp_path / "a.gif")
    (tmp_path / "notes.h5").write_text("not a result")
    with pytest.raises(ParameterError, match=r"result: cannot load the result file: .*notes\.h5.*not a readable HDF5"):
        render(str(tmp_path / "notes.h5"), tmp_path / "a.png")
    with pytest.raises(ParameterError, match=r"result must be a framework\.Result or the path of a saved result "
                                             r"file \(result\.h5\), got int: 42"):
        animate(42, tmp_path / "a.gif")
    assert os.listdir(tmp_path) == ["notes.h5"]


def test_a_path_without_suffix_gets_the_best_format(pressed, tmp_path):
    """MP4 where imageio-ffmpeg is installed (no palette banding), else GIF."""
    movie = animate(pressed, tmp_path / "press", steps=[1], **SMALL)
    expected = ".mp4" if all(__import__("importlib").util.find_spec(m) for m in ("imageio", "imageio_ffmpeg")) \
        else ".gif"
    assert animation.default_suffix() == expected
    assert movie.path == str(tmp_path / "press") + expected and os.listdir(tmp_path) == ["press" + expected]
