"""Off-screen animations of a recorded series: one :func:`viz.render` picture per step, into a GIF or an MP4.

Every frame is drawn by :func:`viz.render.draw`, the code behind
:func:`viz.render` (same kinds, fields, axes, titles and inhomogeneity
outlines), with ONE colour range and, for the deformed surface, one
exaggeration for all frames, so that a colour (a height) means the same in
every frame. Each frame's title names the step and the time, and for a
rolling body the distance it has rolled.

The GIF is written with Pillow (installed with matplotlib), the MP4 (H.264)
with imageio and the ffmpeg binary that ``imageio-ffmpeg`` bundles; both come
with the ``viz`` extra. A path without a suffix gets ``.mp4`` where
imageio-ffmpeg is installed (smooth colours, small files), else ``.gif``
(:func:`default_suffix`). A GIF holds 256 colours a frame: its frames draw the
colour map in :data:`GIF_LEVELS` levels and every frame's palette holds them
all, exactly, the rest of the palette going to the text and the shading, so
the colour bar and the field do not band. The file is written under a temporary name beside
``path`` and renamed when the last frame is in, with the mode ``0o666`` less
the umask like every output of :mod:`viz`: an animation that fails leaves no
file behind.
"""
import importlib.util
import numbers
import os
from dataclasses import dataclass

import numpy as np

from framework.errors import ParameterError
from framework.io import check_target

from . import _deps
from .checks import as_result, check_options
from .export import _replacing
from .fields import shown_values
from .render import draw
from .scales import automatic_warp, colour_limits

#: Levels of the colour map in a GIF's frames: each frame's 256-colour palette holds them all.
GIF_LEVELS = 128


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
            show_indenter=False, plane="x2", origin=0.0, clip=False, window_size=None, font_size=18):
    """Render recorded steps of a result off screen into an animated ``.gif`` or ``.mp4``.

    Parameters
    ----------
    result : framework.Result or str or path
        The run (at least one recorded step), or a saved result file
        (``result.h5``) to load.
    path : str or path
        Output file; its suffix, ``.gif`` or ``.mp4``, picks the format;
        without a suffix, :func:`default_suffix` is added (``.mp4`` where
        imageio-ffmpeg is installed). Its folder must exist and accept new
        files.
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
        :func:`viz.scales.colour_limits` does for one picture.
    cmap, show_indenter, plane, origin, clip, font_size
        As in :func:`viz.render`.
    window_size : tuple of int, optional
        Frame size in pixels, as in :func:`viz.render`; default: the size
        :func:`viz.render` gives the first frame (a map or slice sized to the
        field's aspect), kept for every frame.
    warp : float, optional
        Exaggeration of the deformation (``kind="surface"``); default: the
        :func:`viz.scales.automatic_warp` of the deepest point over the frames.

    Returns
    -------
    Animation
        The file (``path``, its suffix added when it had none), the steps,
        the shared colour range and each frame's :class:`viz.Rendering`.

    Raises
    ------
    framework.errors.ParameterError
        Found before any frame is drawn: ``path`` without a ``.gif`` or
        ``.mp4`` suffix, or in a missing or closed folder; an empty result;
        unknown ``kind``, ``field`` or ``cmap``; ``steps`` empty or out of
        range; ``fps`` not a positive number; a bad ``clim``, ``warp``,
        ``plane``, ``origin``, ``window_size`` or ``font_size``; a result
        file that cannot be loaded.
    ImportError
        A package of the ``viz`` extra is missing (``pip install 'viscocontact[viz]'``).
    """
    result = as_result(result)
    if isinstance(path, (str, os.PathLike)) and not os.path.splitext(os.fspath(path))[1] \
            and not os.path.isdir(path):
        path = os.fspath(path) + default_suffix()
    path = check_target(path, name="path")
    suffix = os.path.splitext(path)[1].lower()
    if suffix not in WRITERS:
        raise ParameterError(f"path must end in {' or '.join(WRITERS)} (the suffix picks the format), got {path!r}")
    if len(result) == 0:
        raise ParameterError("result has no recorded steps; expected a run with at least one step to animate")
    field, clim, cmap, window_size, font_size = check_options(
        result, kind, field, clim=clim, cmap=cmap, warp=warp, plane=plane, origin=origin,
        window_size=window_size, font_size=font_size)
    steps = _check_steps(steps, len(result))
    if not (isinstance(fps, numbers.Real) and not isinstance(fps, bool) and np.isfinite(fps) and fps > 0):
        raise ParameterError(f"fps must be a positive number of frames per second, got {fps!r}")
    packages, write, levels = WRITERS[suffix]
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
        size = window_size
        for k in steps:
            plotter, rendering = draw(result, field, k, kind=kind, clim=clim, cmap=cmap, warp=warp,
                                      show_indenter=show_indenter, plane=plane, origin=origin, clip=clip,
                                      window_size=size, font_size=font_size, n_colors=levels)
            size = rendering.window_size  # every frame the first one's size
            try:
                image = plotter.screenshot(None, return_img=True)
            finally:
                plotter.close()
            renderings.append(rendering)
            sizes.append(image.shape[1::-1])
            yield np.ascontiguousarray(image[..., :3]), rendering.colours

    with _replacing(path, suffix) as temporary:
        write(temporary, frames(), float(fps))
    return Animation(path=path, kind=kind, field=field, steps=steps, fps=float(fps), clim=renderings[0].clim,
                     warp=renderings[0].warp, size=tuple(int(n) for n in sizes[0]), frames=renderings)


def default_suffix():
    """``".mp4"`` where imageio and imageio-ffmpeg are installed (the ``viz`` extra), else ``".gif"``."""
    found = all(importlib.util.find_spec(name) is not None for name in ("imageio", "imageio_ffmpeg"))
    return ".mp4" if found else ".gif"


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
    """Frames (RGB arrays, with their colour maps) into a looping GIF, each with its own palette (:func:`gif_frame`)."""
    image = _deps.require("PIL.Image")
    pictures = [gif_frame(frame, colours, image) for frame, colours in frames]
    pictures[0].save(path, format="GIF", save_all=True, append_images=pictures[1:], duration=1000.0 / fps,
                     loop=0)


def gif_frame(frame, colours, image=None):
    """An RGB frame as a 256-colour picture whose palette holds every colour of ``colours`` exactly.

    Parameters
    ----------
    frame : ndarray
        ``(height, width, 3)`` uint8.
    colours : ndarray
        ``(n, 3)`` uint8 colours to keep exact (the colour map drawn, ``n <= 256``).
    image : module, optional
        ``PIL.Image``.

    Returns
    -------
    PIL.Image.Image
        Mode ``"P"``: the colour map's colours mapped to themselves, the
        other pixels (text, outlines, shading) to the nearest of them or of
        up to ``256 - n`` colours chosen by median cut among those pixels.
        Without dithering: flat fields stay flat.
    """
    image = image or _deps.require("PIL.Image")
    frame = np.ascontiguousarray(frame[..., :3], dtype=np.uint8)
    kept = np.unique(np.asarray(colours, dtype=np.uint8).reshape(-1, 3), axis=0)[:256]
    codes = (frame[..., 0].astype(np.int32) << 16) | (frame[..., 1].astype(np.int32) << 8) | frame[..., 2]
    kept_codes = (kept[:, 0].astype(np.int32) << 16) | (kept[:, 1].astype(np.int32) << 8) | kept[:, 2]
    rest = frame[~np.isin(codes, kept_codes)]
    room = 256 - len(kept)
    extra = np.zeros((0, 3), dtype=np.uint8)
    if rest.size and room:
        others = image.fromarray(rest.reshape(1, -1, 3)).quantize(room, method=image.Quantize.MEDIANCUT,
                                                                  dither=image.Dither.NONE)
        extra = np.asarray(others.getpalette()[:3 * room], dtype=np.uint8).reshape(-1, 3)
    palette = np.concatenate([kept, extra])
    # nearest palette colour of each distinct colour (Pillow's own palette mapping rounds colours: not exact)
    distinct, inverse = np.unique(codes.ravel(), return_inverse=True)
    rgb = np.stack([distinct >> 16, (distinct >> 8) & 255, distinct & 255], axis=-1).astype(np.int32)
    entries = palette.astype(np.int32)
    nearest = np.concatenate([np.argmin(((chunk[:, None, :] - entries[None]) ** 2).sum(axis=-1), axis=1)
                              for chunk in np.array_split(rgb, max(1, len(rgb) // 4096))])
    picture = image.fromarray(nearest[inverse].reshape(codes.shape).astype(np.uint8), mode="P")
    picture.putpalette(np.concatenate([palette.ravel(), np.zeros(768 - palette.size, dtype=np.uint8)]).tolist())
    return picture


def _write_mp4(path, frames, fps):
    """Frames (RGB arrays) into an H.264 MP4 through imageio's ffmpeg writer, streamed (no frame kept)."""
    imageio = _deps.require("imageio.v2")
    # yuv420p (what players read) needs even sizes: 2, not 16, keeps 1200 x 900 as it is
    with imageio.get_writer(path, format="FFMPEG", mode="I", fps=fps, codec="libx264", quality=8,
                            pixelformat="yuv420p", macro_block_size=2) as writer:
        for frame, _ in frames:
            writer.append_data(frame)


#: Output suffix -> (the packages its writer needs, the writer ``(path, frames, fps)``, the colour map's levels).
WRITERS = {".gif": (("PIL.Image",), _write_gif, GIF_LEVELS),
           ".mp4": (("imageio.v2", "imageio_ffmpeg"), _write_mp4, 256)}
