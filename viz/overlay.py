"""Text and lines drawn over the scene in window pixels: the title, the axes with their ticks, the colour bar.

Sizes are measured with VTK's text renderer before anything is placed, so the
layout holds in the picture: ticks fall on round values (1, 2 or 5 times a
power of ten), as many as fit the axis's length on screen without their labels
touching, with as many decimals as the tick spacing needs; a label that would
touch one of another axis (at a shared corner) is left out. Text uses
matplotlib's DejaVu Sans when matplotlib is installed (VTK's own font
otherwise), and mathtext (``$x_1$``) is drawn by matplotlib through VTK
(:mod:`viz.labels`; plain Unicode without matplotlib).
"""
import functools

import numpy as np

from . import _deps, labels
from .scales import format_tick, nice_ticks

#: Colour bar: width of its colour strip, and the gap from the plot to it [font sizes].
BAR_WIDTH, BAR_GAP = 1.5, 2.0

#: Font sizes of the picture's texts relative to the base font size (the tick labels').
TITLE_SCALE, AXIS_TITLE_SCALE, BAR_LABEL_SCALE, BAR_TITLE_SCALE = 1.35, 1.1, 1.15, 1.2


@functools.lru_cache(maxsize=1)
def font_file():
    """DejaVu Sans from matplotlib (brackets, µ, ×), or None for VTK's own font when matplotlib is missing."""
    try:
        from matplotlib import font_manager
        return font_manager.findfont("DejaVu Sans", fallback_to_default=False)
    except (ImportError, ValueError):
        return None


def boxes_touch(a, b, gap):
    """True when the boxes ``(x0, y0, x1, y1)`` come closer than ``gap`` pixels."""
    return a[0] < b[2] + gap and b[0] < a[2] + gap and a[1] < b[3] + gap and b[1] < a[3] + gap


class Overlay:
    """Text and lines in window pixels drawn over the scene of ``plotter``: titles, axes, colour bar.

    ``label_boxes`` collects the boxes of the axis tick labels drawn.
    """

    def __init__(self, plotter, font_size):
        self.plotter = plotter
        self.renderer = plotter.renderer
        self.width, self.height = plotter.window_size
        self.font_size = int(font_size)
        self.tick = 0.4 * self.font_size  # length of the tick marks
        self.pad = 0.35 * self.font_size  # between a tick and its label
        self.label_boxes = []
        self._measure = _deps.require("vtkmodules.vtkRenderingCore").vtkTextRenderer()
        _deps.require("vtkmodules.vtkRenderingFreeType")  # the text renderer's backend
        self._mathtext = labels.mathtext_available()  # imports VTK's matplotlib backend when it is there

    def resize(self, width, height):
        """The window's new size [px] (set on the plotter before anything is placed)."""
        self.plotter.window_size = (int(width), int(height))
        self.width, self.height = int(width), int(height)

    def _property(self, size, rotation=0.0, left=False, top=False):
        vtk_core = _deps.require("vtkmodules.vtkRenderingCore")
        prop = vtk_core.vtkTextProperty()
        prop.SetFontSize(int(round(size)))
        prop.SetColor(0.0, 0.0, 0.0)
        prop.SetOrientation(rotation)
        font = font_file()
        if font:
            prop.SetFontFamily(vtk_core.vtkTextProperty.GetFontFamilyFromString("File"))
            prop.SetFontFile(font)
        else:
            prop.SetFontFamilyToArial()
        prop.SetJustification(0 if left else 1)  # VTK_TEXT_LEFT, VTK_TEXT_CENTERED
        prop.SetVerticalJustification(2 if top else 1)  # VTK_TEXT_TOP, VTK_TEXT_CENTERED
        return prop

    def _typeset(self, text):
        return text if self._mathtext else labels.plain(text)

    def size(self, text, size):
        """Width and height [px] of ``text`` at font size ``size`` [px]."""
        return self._size(text, self._property(size))

    def _size(self, text, prop):
        box = [0, 0, 0, 0]
        self._measure.GetBoundingBox(prop, self._typeset(text), box, self.plotter.render_window.GetDPI())
        return box[1] - box[0], box[3] - box[2]

    def _text(self, text, position, prop):
        actor = _deps.require("vtkmodules.vtkRenderingCore").vtkTextActor()
        actor.SetInput(self._typeset(text))
        actor.SetTextProperty(prop)
        actor.SetPosition(float(position[0]), float(position[1]))
        self.renderer.AddActor(actor)
    def _lines(self, segments, width=1.2):
        """Straight lines ``[(start, end), ...]`` in window pixels."""
        vtk_core = _deps.require("vtkmodules.vtkRenderingCore")
        pv = _deps.pyvista(rendering=True)
        points = np.array([[x, y, 0.0] for segment in segments for x, y in segment])
        poly = pv.PolyData(points, lines=np.column_stack([np.full(len(segments), 2),
                                                          np.arange(0, 2 * len(segments), 2),
                                                          np.arange(1, 2 * len(segments), 2)]).ravel())
        mapper = vtk_core.vtkPolyDataMapper2D()
        mapper.SetInputData(poly)
        actor = vtk_core.vtkActor2D()
        actor.SetMapper(mapper)
        actor.GetProperty().SetColor(0.0, 0.0, 0.0)
        actor.GetProperty().SetLineWidth(width)
        self.renderer.AddActor(actor)

    def project(self, point):
        """Window pixels ``(x, y)`` of a point of the scene (display length unit)."""
        self.renderer.SetWorldPoint(float(point[0]), float(point[1]), float(point[2]), 1.0)
        self.renderer.WorldToDisplay()
        return np.array(self.renderer.GetDisplayPoint()[:2])

    def title(self, text):
        """The picture's title at the top left; returns the window height [px] just below it."""
        prop = self._property(TITLE_SCALE * self.font_size, left=True, top=True)
        top = self.height - 0.6 * self.font_size
        self._text(text, (0.015 * self.width, top), prop)
        return top - self._size(text, prop)[1]

    def _label_box(self, text, prop, anchor, outward):
        """Box of ``text`` placed just beyond ``anchor`` in the direction ``outward`` (a unit vector)."""
        w, h = self._size(text, prop)
        centre = anchor + outward * (abs(outward[0]) * w / 2 + abs(outward[1]) * h / 2)
        return (centre[0] - w / 2, centre[1] - h / 2, centre[0] + w / 2, centre[1] + h / 2)

    def axes(self, bounds, titles, frame=False):
        """Axes with round ticks along edges of the box ``bounds`` (display length unit).

        Parameters
        ----------
        bounds : sequence of float
            ``(x0, x1, y0, y1, z0, z1)`` of the mesh.
        titles : dict
            Axis index (0, 1, 2) -> title, in drawing order.
        frame : bool
            Also draw the two edges opposite the axes (a flat 2-D picture).

        Returns
        -------
        dict
            Title -> the tick labels drawn.
        """
        b = np.asarray(bounds, dtype=float).reshape(3, 2)
        centre = self.project(b.mean(axis=1))
        prop = self._property(self.font_size)
        drawn = {}
        segments = []
        for axis, title in titles.items():
            start, end, outward, upright = self._edge(b, axis, centre)
            segments.append((start, end))
            kept = self._ticks(b[axis], start, end, outward, prop)
            for value, _, _ in kept:
                point = start + (end - start) * (value - b[axis, 0]) / (b[axis, 1] - b[axis, 0])
                segments.append((point, point + outward * self.tick))
            for _, text, box in kept:
                self._text(text, ((box[0] + box[2]) / 2, (box[1] + box[3]) / 2), prop)
            self.label_boxes += [box for _, _, box in kept]
            drawn[title] = tuple(text for _, text, _ in kept)
            # the title beyond the labels, turned along an upright axis
            title_prop = self._property(AXIS_TITLE_SCALE * self.font_size, rotation=90.0 if upright else 0.0)
            depth = max([abs(outward[0]) * (box[2] - box[0]) + abs(outward[1]) * (box[3] - box[1])
                         for _, _, box in kept] + [0.0])
            anchor = (start + end) / 2 + outward * (self.tick + 2 * self.pad + depth)
            box = self._label_box(title, title_prop, anchor, outward)
            self._text(title, ((box[0] + box[2]) / 2, (box[1] + box[3]) / 2), title_prop)
        if frame:
            shown = list(titles)
            corners = []
            for u, v in ((0, 0), (1, 0), (1, 1), (0, 1)):
                point = b[:, 0].copy()
                point[shown[0]], point[shown[1]] = b[shown[0], u], b[shown[1], v]
                corners.append(self.project(point))
            segments += [(corners[i], corners[(i + 1) % 4]) for i in range(4)]
        self._lines(segments)
        return drawn

    def _edge(self, b, axis, centre):
        """The box edge along ``axis`` to draw it on: the lowest on screen, or the leftmost for an upright axis.

        An axis is upright when it is z in a 3-D view or within about 18 degrees
        of the vertical on screen. Returns the edge's ends in window pixels, the
        unit vector pointing away from the box and whether the axis is upright.
        """
        others = [i for i in range(3) if i != axis]
        edges = []
        for u in b[others[0]]:
            for v in b[others[1]]:
                low, high = np.empty(3), np.empty(3)
                low[others], high[others] = (u, v), (u, v)
                low[axis], high[axis] = b[axis]
                edges.append((self.project(low), self.project(high)))
        along = edges[0][1] - edges[0][0]
        upright = abs(along[1]) > 3 * abs(along[0]) or (axis == 2 and abs(along[1]) > abs(along[0]))
        start, end = min(edges, key=lambda e: (e[0][0] + e[1][0]) if upright else (e[0][1] + e[1][1]))
        along = end - start
        outward = np.array([-along[1], along[0]]) / max(np.linalg.norm(along), 1e-30)
        if np.dot(outward, (start + end) / 2 - centre) < 0:
            outward = -outward
        return start, end, outward, upright

    def _ticks(self, limits, start, end, outward, prop):
        """``(value, label, box)`` of the ticks of one axis.

        The most round ticks (at most 7) whose labels keep apart: a font size
        along a horizontal axis, a third of it along an upright one, and half
        a font size from the labels of the axes drawn before (at a shared
        corner the later axis gives way). When not even two fit, one label.
        """
        low, high = limits
        if not high > low:
            return []
        along = (end - start) / max(np.linalg.norm(end - start), 1e-30)
        gap = self.font_size * (abs(along[0]) + abs(along[1]) / 3)
        single = []
        for most in range(7, 1, -1):
            values, decimals = nice_ticks(low, high, most)
            anchors = [start + (end - start) * (v - low) / (high - low) + outward * (self.tick + self.pad)
                       for v in values]
            placed = [(v, format_tick(v, decimals), anchor) for v, anchor in zip(values, anchors)]
            placed = [(v, text, self._label_box(text, prop, anchor, outward)) for v, text, anchor in placed]
            placed = [item for item in placed
                      if not any(boxes_touch(item[2], other, 0.5 * self.font_size) for other in self.label_boxes)]
            single = placed[:1] or single  # the coarsest ticks give the roundest lone label
            if len(placed) >= 2 and not any(boxes_touch(a[2], b[2], gap) for a, b in zip(placed, placed[1:])):
                return placed
        return single


    def colour_bar(self, lookup_table, low, high, title, left, bottom, top, ticks=None):
        """Vertical colour bar with round ticks (display unit) and ``title`` above it; returns the tick labels.

        ``left``: the strip's left edge [px]; ``bottom``, ``top``: its ends
        [px], those of the plot beside it (a flat picture) so that the bar is
        never taller than the field it explains.
        """
        vtk_annotation = _deps.require("vtkmodules.vtkRenderingAnnotation")
        vtk_common = _deps.require("vtkmodules.vtkCommonCore")
        bar = vtk_annotation.vtkScalarBarActor()
        bar.SetLookupTable(lookup_table)
        bar.SetMaximumNumberOfColors(lookup_table.GetNumberOfColors())  # VTK draws 64 bands by default
        bar.SetOrientationToVertical()
        # the actor's box holds the strip (BarRatio of its width) and the labels right of it
        strip = BAR_WIDTH * self.font_size
        bar.SetBarRatio(0.375)
        bar.GetPositionCoordinate().SetCoordinateSystemToDisplay()
        bar.GetPositionCoordinate().SetValue(float(left), float(bottom))
        bar.GetPosition2Coordinate().SetCoordinateSystemToDisplay()
        bar.GetPosition2Coordinate().SetValue(strip / 0.375, float(top - bottom))
        bar.SetTitle("")
        bar.SetTextPad(int(round(0.3 * self.font_size)))
        bar.UnconstrainedFontSizeOn()
        bar.SetLabelTextProperty(self._property(BAR_LABEL_SCALE * self.font_size))
        bar.GetLabelTextProperty().SetJustificationToLeft()
        if ticks is None:
            values, decimals = nice_ticks(low, high, max(2, min(7, int((top - bottom) / (2.2 * self.font_size)))))
        else:
            values, decimals = np.asarray(ticks, dtype=float), 0
        custom = vtk_common.vtkDoubleArray()
        for value in values:
            custom.InsertNextValue(float(value))
        bar.SetUseCustomLabels(True)
        bar.SetCustomLabels(custom)
        bar.SetLabelFormat(f"%.{decimals}f")
        self.renderer.AddActor(bar)
        prop = self._property(BAR_TITLE_SCALE * self.font_size, left=True)
        w, h = self._size(title, prop)
        x = min(float(left), self.width - 0.6 * self.font_size - w)
        self._text(title, (x, top + 0.8 * self.font_size + h / 2), prop)
        return tuple(format_tick(v, decimals) for v in values)

    def bar_room(self, low, high, ticks=None):
        """Width [px] the colour bar takes right of the plot: the gap, the strip and its widest label."""
        if ticks is None:
            values, decimals = nice_ticks(low, high, 7)
        else:
            values, decimals = np.asarray(ticks, dtype=float), 0
        widest = max(self.size(format_tick(v, decimals), BAR_LABEL_SCALE * self.font_size)[0] for v in values)
        return (BAR_GAP + BAR_WIDTH + 0.3 + 1.0) * self.font_size + widest
