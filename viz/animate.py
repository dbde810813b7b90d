"""Off-screen animations of a recorded series: one :func:`viz.render` picture per step, into a GIF or an MP4.

Every frame is drawn by :func:`viz.render.draw`, the code behind
:func:`viz.render` (same kinds, fields, axes, titles and inhomogeneity
outlines), with ONE colour range and, for the deformed surface, one
exaggeration for all frames, so that a colour (a height) means the same in
every frame. Each frame's title names the step and the time, and for a
rolling body the distance it has rolled.

The GIF is written with Pillow (installed with matplotlib), the MP4 (H.264)
with imageio and the ffmpeg binary that ``imageio-ffmpeg`` bundles; both come
with the ``viz`` extra. The file is written under a temporary name beside
``path`` and renamed when the last frame is in, with the mode ``0o666`` less
the umask like every output of :mod:`viz`: an animation that fails leaves no
file behind.
"""
import numbers
import os
from dataclasses import dataclass

import numpy as np

from framework.errors import ParameterError
from framework.io import check_target

from . import _deps
from .export import _replacing
from .render import KINDS, automatic_warp, check_clim, check_picture, colour_limits, draw, shown_values


@dataclass
class Animation:
    """What :func:`animate` wrote.

    Attributes
    ----------
    path : str
        The ``.gif`` or ``.mp4`` file.
    kind, field : str
        Picture kind and field name.
    steps : tuple of int
        The step of each frame (non-negative indices).
    fps : float
        Frames per second.
    clim : tuple of float
        Colour range of every frame [SI unit of the field].
    warp : float or None
        Exaggeration of the deformation in every frame (``kind="surface"``).
    size : tuple of int
        Frame width and height [pixels].
    frames : list of Rendering
        What each frame shows (``path`` None): colour range, bar labels, title data.
    """

    path: str
    kind: str
    field: str
    steps: tuple
    fps: float
    clim: tuple
    warp: float
    size: tuple
    frames: list


def animate(result, path, field=None, *, kind="map", steps=None, fps=5.0, clim=None, cmap=None, warp=None,
            show_indenter=False, plane="x2", origin=0.0, clip=False, window_size=(1200, 900), font_size=18):
    """Render recorded steps of a result off screen into an animated ``.gif`` or ``.mp4``.

    Parameters
    ----------
    result : framework.Result
        The run (at least one recorded step).
    path : str or path
        Output file; its suffix, ``.gif`` or ``.mp4``, picks the format. Its
        folder must exist and accept new files.
    field : str, optional
        What colours the frames, as in :func:`viz.render` (default:
        ``pressure`` for ``map`` and ``surface``, ``von_mises`` for ``slice``).
    kind : {"map", "surface", "slice"}
        Picture kind, as in :func:`viz.render`: pressure (gap, displacement)
        map, deformed surface, subsurface stress slice with the run's
        inhomogeneities outlined.
    steps : sequence of int, optional
        The steps to show, in order (negative indices count from the end);
        default: every recorded step.
    fps : float
        Frames per second (> 0). A GIF stores frame durations in hundredths
        of a second, so its rate is rounded to that.
    clim : tuple of float, optional
        Colour range of every frame [SI unit]; default: the smallest and
        largest value shown over all the frames, cleaned like
        :func:`viz.render.colour_limits` does for one picture.
    cmap, show_indenter, plane, origin, clip, window_size, font_size
        As in :func:`viz.render`.
    warp : float, optional
        Exaggeration of the deformation (``kind="surface"``); default: the
        :func:`viz.render.automatic_warp` of the deepest point over the frames.

    Returns
    -------
    Animation
        The file, the steps, the shared colour range and each frame's :class:`viz.Rendering`.

    Raises
    ------
    framework.errors.ParameterError
        Found before any frame is drawn: ``path`` without a ``.gif`` or
        ``.mp4`` suffix, or in a missing or closed folder; an empty result;
        unknown ``kind`` or ``field``; ``steps`` empty or out of range;
        ``fps`` not a positive number; a bad ``clim``, ``warp``, ``plane`` or
        ``origin``.
    ImportError
        A package of the ``viz`` extra is missing (``pip install 'viscocontact[viz]'``).
    """
    path = check_target(path, name="path")
    suffix = os.path.splitext(path)[1].lower()
    if suffix not in WRITERS:
        raise ParameterError(f"path must end in {' or '.join(WRITERS)} (the suffix picks the format), got {path!r}")
    if len(result) == 0:
        raise ParameterError("result has no recorded steps; expected a run with at least one step to animate")
    field = check_picture(result, kind, field, plane=plane, origin=origin, warp=warp)
    steps = _check_steps(steps, len(result))
    if not (isinstance(fps, numbers.Real) and not isinstance(fps, bool) and np.isfinite(fps) and fps > 0):
        raise ParameterError(f"fps must be a positive number of frames per second, got {fps!r}")
    unit = KINDS[kind][field][1]
    if clim is not None:
        clim = check_clim(clim, unit)
    packages, write = WRITERS[suffix]
    for package in packages:  # a missing one is named before any frame is drawn
        _deps.require(package)

    if clim is None and field != "contact":  # contact has its fixed two-colour range
        low, high = np.inf, -np.inf
        for k in steps:
            values = shown_values(result, k, kind, field, plane=plane, origin=origin, clip=clip)
            low, high = min(low, float(values.min())), max(high, float(values.max()))
        clim = colour_limits(low, high)
    if kind == "surface" and warp is None:
        warp = automatic_warp(result.grid, max(float(np.max(np.abs(result.displacement(k)))) for k in steps))

    renderings, sizes = [], []

    def frames():
        for k in steps:
            plotter, rendering = draw(result, field, k, kind=kind, clim=clim, cmap=cmap, warp=warp,
                                      show_indenter=show_indenter, plane=plane, origin=origin, clip=clip,
                                      window_size=window_size, font_size=font_size)
            try:
                image = plotter.screenshot(None, return_img=True)
            finally:
                plotter.close()
            renderings.append(rendering)
            sizes.append(image.shape[1::-1])
            yield np.ascontiguousarray(image[..., :3])

    with _replacing(path, suffix) as temporary:
        write(temporary, frames(), float(fps))
    return Animation(path=path, kind=kind, field=field, steps=steps, fps=float(fps), clim=renderings[0].clim,
                     warp=renderings[0].warp, size=tuple(int(n) for n in sizes[0]), frames=renderings)


def _check_steps(steps, n):
    """``steps`` as a tuple of non-negative step indices (all of them when None), or ParameterError."""
    if steps is None:
        return tuple(range(n))
    try:
        chosen = list(steps)
    except TypeError:
        chosen = None
    if not chosen or not all(isinstance(k, (int, np.integer)) and not isinstance(k, bool) and -n <= k < n
                             for k in chosen):
        raise ParameterError(f"steps must be a non-empty sequence of step indices in [-{n}, {n}) (the result has "
                             f"{n} steps), got {steps!r}")
    return tuple(int(k) % n for k in chosen)


def _write_gif(path, frames, fps):
    """Frames (RGB arrays) into a looping GIF; each frame gets its own 256-colour palette."""
    image = _deps.require("PIL.Image")
    pictures = [image.fromarray(frame).quantize(256, dither=image.Dither.NONE) for frame in frames]
    pictures[0].save(path, format="GIF", save_all=True, append_images=pictures[1:], duration=1000.0 / fps,
                     loop=0)


def _write_mp4(path, frames, fps):
    """Frames (RGB arrays) into an H.264 MP4 through imageio's ffmpeg writer, streamed (no frame kept)."""
    imageio = _deps.require("imageio.v2")
    # yuv420p (what players read) needs even sizes: 2, not 16, keeps 1200 x 900 as it is
    with imageio.get_writer(path, format="FFMPEG", mode="I", fps=fps, codec="libx264", quality=8,
                            pixelformat="yuv420p", macro_block_size=2) as writer:
        for frame in frames:
            writer.append_data(frame)


#: Output suffix -> (the packages its writer needs, the writer ``(path, frames, fps)``).
WRITERS = {".gif": (("PIL.Image",), _write_gif), ".mp4": (("imageio.v2", "imageio_ffmpeg"), _write_mp4)}
