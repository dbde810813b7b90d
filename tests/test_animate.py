"""viz.animate: GIF and MP4 of a recorded series, one colour range for all frames, input checks, no half files."""
import os
import re
import sys

import numpy as np
import pytest

pytest.importorskip("pyvista")
Image = pytest.importorskip("PIL.Image")

import framework as fw  # noqa: E402
from framework import Grid, Simulation, indenters, materials, schedules  # noqa: E402
from framework.errors import ParameterError  # noqa: E402
from viz import animate, render  # noqa: E402

animation = sys.modules["viz.animate"]  # the module (viz.animate is the function)

LOADS = [2.0, 5.0, 10.0, 20.0]
SIZE = (640, 480)  # small frames: the tests stay fast
OPTIONS = {"window_size": SIZE, "font_size": 10}


@pytest.fixture(scope="module")
def static():
    """An elastic ball pressed at 4 loads, 24 x 24 cells x 4 layers."""
    sim = Simulation(grid=Grid(shape=(24, 24), size=(1e-3, 1e-3), depth=0.4e-3, layers=4),
                     material=materials.Elastic(young=2e9, poisson=0.35),
                     indenter=indenters.Sphere(radius=5e-3), schedule=schedules.Static(load=LOADS))
    return sim.run()


@pytest.fixture(scope="module")
def gif(static, tmp_path_factory):
    path = tmp_path_factory.mktemp("gif") / "press.gif"
    return animate(static, path, kind="map", fps=4, **OPTIONS)


def _frames(path):
    """The frames of a GIF as RGB arrays."""
    with Image.open(path) as image:
        frames = []
        for i in range(image.n_frames):
            image.seek(i)
            frames.append(np.asarray(image.convert("RGB"), dtype=float) / 255)
        return frames, image.info.get("duration")


def test_gif_has_one_frame_per_step(static, gif):
    with Image.open(gif.path) as image:
        assert (image.n_frames, image.size) == (len(static), SIZE)
    frames, duration = _frames(gif.path)
    assert duration == 250  # 4 frames per second
    for a, b in zip(frames, frames[1:]):
        assert np.mean(np.any(np.abs(a - b) > 0.1, axis=-1)) > 0.01  # the contact grows
    assert gif.steps == (0, 1, 2, 3)
    assert [frame.step for frame in gif.frames] == [0, 1, 2, 3]
    for k, frame in enumerate(gif.frames):
        assert f"step {k}, t = {static.times[k]:.4g} s, load {LOADS[k]:.4g} N" in frame.title


def test_frames_share_the_colour_range_of_all_steps(static, gif, tmp_path):
    """Every frame uses 0 .. the largest pressure over the steps, not its own largest."""
    top = max(float(np.max(static.pressure(k))) for k in range(len(static)))
    assert gif.clim == pytest.approx((0.0, top), rel=1e-12)
    assert {frame.clim for frame in gif.frames} == {gif.clim}
    assert len({frame.bar_labels for frame in gif.frames}) == 1
    # the first frame (2 N) looks like its picture drawn with that range, not like its picture with its own
    first = _frames(gif.path)[0][0]
    shared = render(static, tmp_path / "shared.png", step=0, clim=(0.0, top), **OPTIONS)
    own = render(static, tmp_path / "own.png", step=0, **OPTIONS)
    assert own.clim[1] < 0.5 * top

    def differing(path):
        png = np.asarray(Image.open(path).convert("RGB"), dtype=float) / 255
        return np.mean(np.any(np.abs(png - first) > 0.1, axis=-1))

    assert differing(shared.path) < 0.001  # palette quantisation only
    assert differing(own.path) > 0.01


def test_given_colour_range_and_steps(static, tmp_path):
    result = animate(static, tmp_path / "two.gif", "gap", steps=[-1, 0], clim=(0.0, 1e-5), **OPTIONS)
    assert result.steps == (3, 0)
    assert [frame.clim for frame in result.frames] == [(0.0, 1e-5)] * 2
    with Image.open(result.path) as image:
        assert image.n_frames == 2


def test_surface_frames_share_one_exaggeration(static, tmp_path):
    result = animate(static, tmp_path / "surface.gif", kind="surface", steps=[0, 3], **OPTIONS)
    deepest = float(np.max(np.abs(static.displacement(3))))
    # the largest round factor (1, 2, 5 x 10^n) keeping the deepest dent within 25 % of the 1 mm side
    assert deepest * result.warp <= 0.25e-3 < deepest * result.warp * 2.5
    assert [frame.warp for frame in result.frames] == [result.warp] * 2


def test_mp4_is_readable(static, tmp_path):
    imageio = pytest.importorskip("imageio.v2")
    pytest.importorskip("imageio_ffmpeg")
    result = animate(static, tmp_path / "slice.mp4", kind="slice", fps=2.5, **OPTIONS)
    reader = imageio.get_reader(result.path)
    try:
        assert reader.count_frames() == len(static)
        meta = reader.get_meta_data()
        assert (tuple(meta["size"]), meta["fps"]) == (SIZE, 2.5)
        first, last = reader.get_data(0), reader.get_data(len(static) - 1)
    finally:
        reader.close()
    assert first.shape == (SIZE[1], SIZE[0], 3) and np.mean(np.abs(first / 255 - last / 255)) > 0.01
    assert os.listdir(tmp_path) == ["slice.mp4"]


def test_rolling_frames_say_where_the_body_is(tmp_path):
    solid = materials.StandardLinearSolid(e_inf=1e7, e_1=9e7, tau=1.0, poisson=0.5)
    grid = Grid(shape=(24, 24), size=(2e-3, 2e-3))
    schedule = schedules.Rolling(load=0.2, velocity=(1e-5, 0.0), distance=3 * grid.spacing[0])
    rolled = Simulation(grid=grid, material=solid, indenter=indenters.Sphere(radius=10e-3),
                        schedule=schedule).run()
    result = animate(rolled, tmp_path / "roll.gif", **OPTIONS)
    assert len(result.frames) == len(rolled) == 4
    titles = [frame.title for frame in result.frames]
    assert "rolled 0," in titles[0]
    for k in range(1, 4):
        assert f"rolled {k * grid.spacing[0] / 1e-6:.4g} \u00b5m" in titles[k]  # a cell per step


@pytest.mark.parametrize("umask", [0o077])
def test_file_honours_the_umask(static, tmp_path, umask):
    previous = os.umask(umask)
    try:
        animate(static, tmp_path / "a.gif", steps=[0, 1], **OPTIONS)
    finally:
        os.umask(previous)
    assert oct(os.stat(tmp_path / "a.gif").st_mode & 0o777) == oct(0o666 & ~umask)


def test_a_failed_animation_leaves_no_file(static, tmp_path, monkeypatch):
    (tmp_path / "old.gif").write_bytes(b"an older animation")
    drawn = []

    def failing(*args, **kwargs):
        if drawn:
            raise RuntimeError("the renderer died")
        drawn.append(1)
        return real(*args, **kwargs)

    real = animation.draw
    monkeypatch.setattr(animation, "draw", failing)
    with pytest.raises(RuntimeError, match="renderer died"):
        animate(static, tmp_path / "new.gif", **OPTIONS)
    with pytest.raises(RuntimeError, match="renderer died"):
        animate(static, tmp_path / "old.gif", **OPTIONS)
    assert os.listdir(tmp_path) == ["old.gif"]
    assert (tmp_path / "old.gif").read_bytes() == b"an older animation"


def test_bad_inputs_are_refused_before_any_frame(static, tmp_path, unwritable_folder, monkeypatch):
    def no_frame(*args, **kwargs):
        raise AssertionError("a frame was drawn")

    monkeypatch.setattr(animation, "draw", no_frame)
    bad = [
        (dict(path=tmp_path / "a.png"), r"path must end in \.gif or \.mp4.*'.*a\.png'"),
        (dict(path=tmp_path / "missing" / "a.gif"), r"path: cannot write .*missing.*does not exist"),
        (dict(path=os.path.join(unwritable_folder, "a.gif")), r"path: cannot create files in the folder"),
        (dict(path=tmp_path), r"path: .* is a folder"),
        (dict(field="strain"), r"unknown field 'strain' for kind='map'; choose one of \['pressure'"),
        (dict(kind="movie"), r"kind must be one of \['map', 'slice', 'surface'\], got 'movie'"),
        (dict(steps=[0, 4]), r"steps must be a non-empty sequence of step indices in \[-4, 4\) .*got \[0, 4\]"),
        (dict(steps=[]), r"steps must be a non-empty .*got \[\]"),
        (dict(steps=2), r"steps must be .*got 2"),
        (dict(steps=[True]), r"steps must be .*got \[True\]"),
        (dict(fps=0), r"fps must be a positive number of frames per second, got 0"),
        (dict(fps=-2.0), r"fps must be a positive .*got -2\.0"),
        (dict(fps=True), r"fps must be a positive .*got True"),
        (dict(fps="5"), r"fps must be a positive .*got '5'"),
        (dict(fps=float("inf")), r"fps must be a positive .*got inf"),
        (dict(clim=(0.0,)), r"clim must be two finite numbers \(low, high\) in Pa, got \(0\.0,\)"),
        (dict(warp=-1.0, kind="surface"), r"warp must be a positive finite exaggeration factor, got -1\.0"),
        (dict(kind="slice", plane="x3"), r"plane must be 'x1' or 'x2'.*got 'x3'"),
        (dict(kind="slice", origin=1.0), r"origin of the x2 slice must lie in"),
    ]
    for change, message in bad:
        arguments = {"path": tmp_path / "a.gif", **change}
        with pytest.raises(ParameterError, match=message):
            animate(static, **arguments)
    empty = fw.Result(static.grid, static.material, static.indenter, static.schedule, static.options)
    with pytest.raises(ParameterError, match="result has no recorded steps"):
        animate(empty, tmp_path / "a.gif")
    assert os.listdir(tmp_path) == []


def test_missing_mp4_writer_names_the_extra(static, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    monkeypatch.setattr(animation, "draw", None)  # the check comes before any frame
    with pytest.raises(ImportError, match=r"'imageio_ffmpeg'.*pip install 'viscocontact\[viz\]'"):
        animate(static, tmp_path / "a.mp4")
    assert os.listdir(tmp_path) == []


SCENARIO = """
grid = { shape = [16, 16], size = [1e-3, 1e-3] }
material = { type = "Elastic", young = 1e9, poisson = 0.3 }
indenter = { type = "Sphere", radius = 5e-3 }
schedule = { load = [0.5, 1.0, 2.0] }
output = { vtu = false }
"""


def _cli(capsys, *args):
    from framework.__main__ import main
    code = main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_cli_animates_a_field(capsys, tmp_path):
    path = tmp_path / "press.toml"
    path.write_text(SCENARIO)
    code, out, err = _cli(capsys, "run", path, "--out", tmp_path / "out", "--quiet", "--animate", "gap")
    assert code == 0, err
    with Image.open(tmp_path / "out" / "gap.gif") as image:
        assert image.n_frames == 3
    assert "  1  gap.gif" in out
    for field, message in [("strain", r"--animate: expected a surface field \['pressure'.*got 'strain'"),
                           ("von_mises", r"--animate von_mises: a stress needs \[grid\] layers and depth")]:
        code, _, err = _cli(capsys, "run", path, "--out", tmp_path / "bad", "--quiet", "--animate", field)
        assert code == 2 and re.search(message, err), err
        assert not (tmp_path / "bad").exists()
