"""Pictures as a paper prints them: the figure sized to the field, the colour bar beside it no taller than it,
typeset labels, slices in the plane asked for, a one-step history as values, colour bars that do not band."""
import numpy as np
import pytest

pytest.importorskip("pyvista")
pytest.importorskip("matplotlib")
Image = pytest.importorskip("PIL.Image")

from framework import Grid, Simulation, indenters, materials, schedules  # noqa: E402
from viz import animate, plot_history, render  # noqa: E402
from viz import fields, labels, layout, slices  # noqa: E402
from viz.animate import GIF_LEVELS, gif_frame  # noqa: E402


@pytest.fixture(scope="module")
def strip():
    """A wide thin block: 2.4 mm x 0.4 mm, 0.3 mm deep, on an even grid (no row of centres at x2 = 0)."""
    sim = Simulation(grid=Grid(shape=(32, 6), size=(2.4e-3, 0.4e-3), depth=0.3e-3, layers=4),
                     material=materials.Elastic(young=2e9, poisson=0.35),
                     indenter=indenters.Sphere(radius=5e-3), schedule=schedules.Static(load=[0.2, 0.5]))
    return sim.run()


def _pixels(path):
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"))


def test_a_wide_thin_slice_fills_a_picture_sized_to_it(strip, tmp_path):
    picture = render(strip, tmp_path / "slice.png", "von_mises", kind="slice")
    width, height = picture.window_size
    left, bottom, right, top = picture.field_box
    assert (right - left) / (top - bottom) == pytest.approx(2.4 / 0.3, rel=1e-6)  # the aspect kept
    assert right - left > 0.75 * width and (right - left) * (top - bottom) > 0.3 * width * height
    assert height < 0.5 * width
    assert _pixels(picture.path).shape[:2] == (height, width)
    # the colour bar spans the field's height, not more
    bar = picture.bar_box
    assert (bar[1], bar[3]) == pytest.approx((bottom, top), abs=1e-9) and bar[0] > right
    # the same field in a 4:3 window the caller asks for: kept, the bar still no taller than the field
    boxed = render(strip, tmp_path / "boxed.png", "von_mises", kind="slice", window_size=(1200, 900))
    assert boxed.window_size == (1200, 900)
    assert boxed.bar_box[3] - boxed.bar_box[1] == pytest.approx(boxed.field_box[3] - boxed.field_box[1])


def test_flat_layout_sizes():
    """Square fields keep 900 pixels of height; a thin one widens the window; a tall one narrows it."""
    square = layout.flat_layout((1.0, 1.0), 18, 2, 180)
    assert square.size[1] == 900 and square.size[0] < 1200
    thin = layout.flat_layout((20.0, 1.0), 18, 2, 180)
    assert thin.size[0] == layout.WIDEST * layout.FLAT_WIDTH and thin.size[1] < 400
    wide = layout.flat_layout((3.0, 1.0), 18, 2, 180)
    assert wide.size[0] == layout.FLAT_WIDTH
    assert all(n % 2 == 0 for n in square.size + thin.size + wide.size)  # H.264 frames
    assert layout.flat_layout((3.0, 1.0), 18, 2, 180, window_size=(640, 480)).size == (640, 480)


def test_the_slice_is_in_the_plane_asked_for(strip, tmp_path):
    """x2 = 0 on an even grid lies between two rows of centres: the stresses are interpolated there."""
    grid = strip.grid
    assert np.min(np.abs(grid.x2)) > 0.3 * grid.spacing[1]  # no centre on the plane
    middle = grid.shape[1] // 2
    stress = strip.stress(1)
    between = 0.5 * (stress[:, middle - 1] + stress[:, middle])
    picture = render(strip, tmp_path / "mid.png", "von_mises", 1, kind="slice")
    expected = fields.stress_field(between, "von_mises")
    assert picture.scalar_range == pytest.approx((expected.min(), expected.max()), rel=1e-12)
    assert picture.plane_position == 0.0 and "plane $x_2$ = 0\n" in picture.title
    # on a plane of centres: exactly the cells' values
    on_centres = render(strip, tmp_path / "centre.png", "stress_xx", 1, kind="slice", origin=float(grid.x2[1]))
    xx = -0.0 + stress[:, 1, :, 0]
    assert on_centres.scalar_range == (xx.min(), xx.max())
    assert on_centres.plane_position == grid.x2[1]
    assert f"plane $x_2$ = {grid.x2[1] / 1e-6:.4g} \u00b5m" in on_centres.title
    # beyond the outermost centres: the outermost cells, and the title names their plane
    edge = slices.locate(grid, "x2", grid.size[1] / 2)
    assert (edge.first, edge.second, edge.position) == (grid.shape[1] - 1, grid.shape[1] - 1, grid.x2[-1])
    quarter = slices.locate(grid, "x2", grid.x2[2] + 0.25 * grid.spacing[1])
    assert (quarter.first, quarter.second) == (2, 3) and quarter.weight == pytest.approx(0.25)


def test_labels_are_typeset(strip, tmp_path):
    picture = render(strip, tmp_path / "map.png", "displacement")
    assert set(picture.axis_labels) == {"$x_1$ [mm]", "$x_2$ [mm]"}
    assert picture.bar_title == "normal displacement $u_3$ [\u00b5m]"
    assert labels.plain("$x_1$ [\u00b5m], $\\sigma_{xz}$, $\\mu$ = 0.2") == "x\u2081 [\u00b5m], \u03c3xz, \u03bc = 0.2"
    assert labels.length(12.5e-6) == "12.5 \u00b5m" and labels.length(1.44e-3) == "1.44 mm"


def test_a_single_step_history_shows_the_values(tmp_path):
    one = Simulation(grid=Grid(shape=(16, 16), size=(1e-3, 1e-3)), material=materials.Elastic(young=2e9, poisson=0.35),
                     indenter=indenters.Sphere(radius=5e-3), schedule=schedules.Static(load=[4.0])).run()
    import matplotlib
    import xml.etree.ElementTree as ET
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        path = plot_history(one, tmp_path / "one.svg", ["contact_radius", "max_pressure", "center"])
    texts = " | ".join(" ".join("".join(n.itertext()).split()) for n in ET.parse(path).getroot().iter()
                       if n.tag.endswith("text"))
    assert "1 step" in texts and "1 steps" not in texts and "no history to plot" in texts
    from viz.plot import value_text
    radius = one.contact_radius[0]
    assert value_text(one, "contact_radius") == f"contact radius $a$ = {radius / 1e-6:.4g} \u00b5m"
    assert value_text(one, "center") == "load centre ($x_1$, $x_2$) = (0, 0) \u00b5m"
    assert value_text(one, "max_pressure").endswith(" MPa")


def test_gif_frames_keep_every_colour_of_the_map():
    """The colour map's levels map to themselves; text greys and other colours get the rest of the palette."""
    rng = np.random.default_rng(1)
    colours = np.column_stack([np.arange(GIF_LEVELS), 255 - np.arange(GIF_LEVELS), np.full(GIF_LEVELS, 40)])
    frame = np.full((60, 200, 3), 255, dtype=np.uint8)
    frame[:, :GIF_LEVELS] = colours[None, :, :]
    frame[:, GIF_LEVELS:] = rng.integers(0, 256, size=(60, 200 - GIF_LEVELS, 1))  # greys of text
    back = np.asarray(gif_frame(frame, colours).convert("RGB"))
    np.testing.assert_array_equal(back[:, :GIF_LEVELS], frame[:, :GIF_LEVELS])
    assert np.abs(back[:, GIF_LEVELS:].astype(int) - frame[:, GIF_LEVELS:]).max() <= 2


def test_animated_colour_bar_does_not_band(strip, tmp_path):
    movie = animate(strip, tmp_path / "strip.gif", "von_mises", kind="slice")
    assert {frame.window_size for frame in movie.frames} == {movie.size}
    frame = movie.frames[-1]
    with Image.open(movie.path) as image:
        image.seek(len(movie.frames) - 1)
        pixels = np.asarray(image.convert("RGB"))
    left, bottom, right, top = frame.bar_box
    height = pixels.shape[0]
    strip_pixels = pixels[int(height - top) + 2:int(height - bottom) - 2, int((left + right) / 2)]
    kept = {tuple(c) for c in frame.colours}
    shown = {tuple(c) for c in strip_pixels} & kept  # (and blends of neighbours where the bands meet)
    assert len(frame.colours) == GIF_LEVELS and len(strip_pixels) > GIF_LEVELS
    assert len(shown) >= GIF_LEVELS - 8  # every level, not the 64 bands VTK draws by default, nor fewer
