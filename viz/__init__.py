"""Visualisation layer: reads framework results, never the other way round.

The core (``framework``) does not import this package, and importing it needs
none of the optional packages: vtk/pyvista, meshio and matplotlib are imported
when a function needs them (``pip install 'viscocontact[viz]'``).

* :func:`export` / :class:`Exporter` (:mod:`viz.export`): ParaView files, per
  step ``surface_NNNN.vtu`` (the undeformed surface, quads, with the point
  vector ``displacement_vector`` for Warp By Vector), ``volume_NNNN.vtu``
  (subsurface stresses, hexahedra) and ``indenter_NNNN.vtu``, with
  ``surface.pvd``, ``volume.pvd`` and ``indenter.pvd`` time collections in
  physical time, and for a run with inhomogeneities ``inclusions.vtp`` (their
  surfaces); the version and configuration as text (VTK string arrays);
  :class:`Exporter` streams step by step.
* :func:`render` (:mod:`viz.render`): off-screen PNG pictures of one step, a
  pressure map, the deformed surface in 3-D or a subsurface stress slice; a
  map or slice sized to the field's aspect. Its parts, one module each:
  :mod:`viz.fields` (what can be coloured), :mod:`viz.slices` (the plane a
  slice shows), :mod:`viz.scales` (colour ranges, units, ticks),
  :mod:`viz.labels` (titles and axis names, mathtext), :mod:`viz.layout`
  (window size, cameras), :mod:`viz.overlay` (title, axes and colour bar in
  pixels), :mod:`viz.outlines` (contact edge, inhomogeneities, indenter),
  :mod:`viz.checks` (the arguments' checks).
* :func:`animate` (:mod:`viz.animate`): the recorded steps as an off-screen
  ``.mp4`` or ``.gif``, every frame a :func:`render` picture with one colour
  range. Both take a result or the path of a saved result file.
* :func:`plot_history` (:mod:`viz.plot`): per-step series against time, load
  or approach (matplotlib).
* :mod:`viz.meshes`: the same meshes in memory (pyvista), with the geometry,
  cell numbering and stress frame conventions.

Geometry: z points UP out of the solid (the solid is ``z <= 0``), layer
centres at ``z = -x3``, the deformed surface at ``z = -u3``; SI units. Tensors
in the files are in VTK's order ``XX YY ZZ XY YZ XZ`` (see :mod:`viz.meshes`).
"""
from .animate import Animation, animate
from .export import Exporter, export
from .plot import plot_history
from .render import Rendering, render

__all__ = ["export", "Exporter", "render", "Rendering", "animate", "Animation", "plot_history"]
