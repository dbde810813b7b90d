"""Figure layout: the window's size and where the field goes in it.

A flat picture (a map, a slice) is sized to the field's aspect
(:func:`flat_layout`): the field fills the width between the axis labels and
the colour bar, and the window is as tall as the field needs plus the title
and the labels, so a wide thin slice gets a wide short picture, not a strip in
a 4:3 canvas; the colour bar then spans the field's height. 3-D views use
:data:`VIEW_SIZE` and a perspective camera (:func:`camera_3d`). A
``window_size`` the caller gives is kept, and the field fitted into it.
"""
from dataclasses import dataclass

import numpy as np

from .overlay import AXIS_TITLE_SCALE, BAR_TITLE_SCALE, TITLE_SCALE

#: Window of a 3-D view [px].
VIEW_SIZE = (1200, 900)

#: Width of a flat picture sized to its field [px]; see :func:`flat_layout`.
FLAT_WIDTH = 1200

#: Height of the field in a flat picture [font sizes]: at least enough for a colour bar with 3 to 5
#: labels, at most what keeps the window within :data:`VIEW_SIZE`'s height.
LEAST_HEIGHT = 12.0

#: Widest window a thin field may widen a flat picture to, over :data:`FLAT_WIDTH`: beyond, it is fitted.
WIDEST = 1.5

#: Least width of a flat picture [font sizes]: room for a title of two lines.
NARROWEST = 54.0

#: Spacing of the lines of a title [line heights per font size].
LINE_SPACING = 1.25


@dataclass(frozen=True)
class FlatLayout:
    """Where a flat picture's field goes.

    Attributes
    ----------
    size : tuple of int
        Window width and height [px].
    box : tuple of float
        ``(left, bottom, right, top)`` of the room for the field, fractions
        of the window: it is centred in it, its aspect kept.
    """

    size: tuple
    box: tuple


def margins(font_size, title_lines, bar_room):
    """Room [px] around a flat field: ``(left, bottom, right, top)``.

    Left: the upright axis's tick labels and title; bottom: the horizontal
    axis's; right: the colour bar (``bar_room``); top: the title's lines,
    the colour bar's title and half a tick label.
    """
    f = float(font_size)
    left = 8.0 * f
    bottom = (0.4 + 0.35 + 1.3 + 0.7 + AXIS_TITLE_SCALE * 1.3 + 0.9) * f
    top = (0.6 + TITLE_SCALE * LINE_SPACING * title_lines + 0.8 + BAR_TITLE_SCALE * 1.3 + 0.8) * f
    return left, bottom, float(bar_room) + 0.6 * f, top


def flat_layout(extent, font_size, title_lines, bar_room, window_size=None):
    """Window size and field box of a flat picture of a field ``extent = (width, height)`` (any length unit).

    Parameters
    ----------
    extent : tuple of float
        The field's width and height on screen (same unit, positive).
    font_size : int
        Base font size [px].
    title_lines : int
        Lines of the title.
    bar_room : float
        Width the colour bar takes right of the field [px].
    window_size : tuple of int, optional
        Keep this size. Default: sized to the field: :data:`FLAT_WIDTH`
        wide, the field as tall as its aspect makes it, at least
        :data:`LEAST_HEIGHT` font sizes (a thinner field widens the window,
        up to :data:`WIDEST` times) and at most what keeps the window
        :data:`VIEW_SIZE` tall (a taller field narrows it, down to
        :data:`NARROWEST` font sizes).

    Returns
    -------
    FlatLayout
    """
    left, bottom, right, top = margins(font_size, title_lines, bar_room)
    if window_size is None:
        aspect = extent[1] / extent[0]
        field_width = FLAT_WIDTH - left - right
        least, tallest = LEAST_HEIGHT * font_size, max(VIEW_SIZE[1] - top - bottom, LEAST_HEIGHT * font_size)
        height = field_width * aspect
        if height < least:  # thin: widen the window to give the field its least height
            field_width = min(least / aspect, WIDEST * FLAT_WIDTH - left - right)
            height = field_width * aspect
        elif height > tallest:  # tall: narrow it
            height = tallest
            field_width = height / aspect
        width = max(left + field_width + right, NARROWEST * font_size)
        window_size = (_even(width), _even(bottom + height + top))
    width, height = window_size
    box = (left / width, bottom / height, 1.0 - right / width, 1.0 - top / height)
    if box[2] - box[0] < 0.1 or box[3] - box[1] < 0.1:  # a small window: keep some room for the field
        box = (min(box[0], 0.12), min(box[1], 0.13), max(box[2], 0.79), max(box[3], 0.6))
    return FlatLayout(size=(int(width), int(height)), box=box)


def _even(pixels):
    """Whole even pixels: the H.264 frames of an MP4 need even sizes."""
    return int(2 * np.ceil(pixels / 2))


def fit_2d(plotter, mesh, axes, box):
    """Parallel projection placing the mesh's extent along ``axes`` (horizontal, vertical) in ``box``.

    ``box`` = (left, bottom, right, top) as fractions of the window: room for
    the axes' labels, the colour bar on the right and the title on top.
    Returns the mesh's left, bottom, right and top in window pixels.
    """
    plotter.enable_parallel_projection()
    width, height = plotter.window_size
    b = np.asarray(mesh.bounds).reshape(3, 2)
    (h0, h1), (v0, v1) = b[axes[0]], b[axes[1]]
    per_pixel = max((h1 - h0) / ((box[2] - box[0]) * width), (v1 - v0) / ((box[3] - box[1]) * height), 1e-30)
    camera = plotter.camera
    direction = np.subtract(camera.position, camera.focal_point)
    direction = direction / np.linalg.norm(direction)
    centre = b.mean(axis=1)
    # the mesh centre must land at the box centre: shift the focal point the other way
    shift_h = ((box[0] + box[2]) / 2 - 0.5) * width * per_pixel
    shift_v = ((box[1] + box[3]) / 2 - 0.5) * height * per_pixel
    focal = centre.copy()
    focal[axes[0]] -= shift_h
    focal[axes[1]] -= shift_v
    distance = np.linalg.norm(np.subtract(camera.position, camera.focal_point))
    camera.focal_point = tuple(focal)
    camera.position = tuple(focal + distance * direction)
    camera.parallel_scale = per_pixel * height / 2
    plotter.renderer.ResetCameraClippingRange()
    middle_h, middle_v = (box[0] + box[2]) / 2 * width, (box[1] + box[3]) / 2 * height
    half_h, half_v = (h1 - h0) / per_pixel / 2, (v1 - v0) / per_pixel / 2
    return middle_h - half_h, middle_v - half_v, middle_h + half_h, middle_v + half_v


def camera_3d(plotter, mesh, azimuth, elevation, zoom, shift=0.07):
    """Perspective view from ``azimuth`` / ``elevation`` [deg] (z up), the scene shifted left of the colour bar."""
    az, el = np.radians(azimuth), np.radians(elevation)
    direction = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    centre = np.asarray(mesh.center)
    camera = plotter.camera
    camera.focal_point = tuple(centre)
    camera.position = tuple(centre + direction)
    camera.up = (0.0, 0.0, 1.0)
    plotter.reset_camera()
    camera.zoom(zoom)
    distance = np.linalg.norm(np.subtract(camera.position, camera.focal_point))
    width, height = plotter.window_size
    visible = 2 * distance * np.tan(np.radians(camera.view_angle) / 2) * width / height
    right = np.cross(-direction, (0.0, 0.0, 1.0))
    right /= np.linalg.norm(right)
    move = right * shift * visible
    camera.focal_point = tuple(np.add(camera.focal_point, move))
    camera.position = tuple(np.add(camera.position, move))
    plotter.renderer.ResetCameraClippingRange()
