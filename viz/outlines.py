"""What is drawn with a field: the edge of the contact, the inhomogeneities, the indenter.

All take coordinates in the picture's display length unit (``length_scale``
[m per unit]) and add their meshes to a pyvista plotter.
"""
import numpy as np

from . import meshes


def contact_outline(plotter, result, k, length_scale):
    """Black line around the cells in contact (the 0.5 contour of the corner-averaged indicator)."""
    grid = result.grid
    contact = (np.asarray(result.pressure(k)) > 0).astype(float)
    if not contact.any() or contact.all():
        return
    mesh = meshes.quad_mesh(grid, np.full(tuple(n + 1 for n in grid.shape), 1e-6 * max(grid.size)))
    mesh.points[:] /= length_scale
    # zero padding closes the outline along the grid's open edges; a periodic axis wraps (no edge there)
    padded = contact
    for axis, periodic in enumerate(grid.periodic):
        width = [(0, 0), (0, 0)]
        width[axis] = (1, 1)
        padded = np.pad(padded, width, mode="wrap" if periodic else "constant")
    corners = meshes.corner_average(padded, (False, False))[1:-1, 1:-1]
    mesh.point_data["contact"] = corners.ravel(order="F")
    outline = mesh.contour([0.5], scalars="contact")
    if outline.n_points:
        plotter.add_mesh(outline, color="white", line_width=3, lighting=False, label="contact edge")


def inclusions(plotter, result, k, length_scale, plane, cut, toward, surfaces, at=None):
    """The inhomogeneities of step ``k``'s slice picture: their section by the plane ``plane = cut`` [m] as black curves.

    They are material points: under a rolling body (pictures in the body's frame) they
    lie ``result.position[k]`` behind where they started.

    The curves are drawn in the plane ``plane = at`` (default ``cut``: that
    of the coloured cells) moved off it by 0.1 % of the grid side ``toward``
    the camera (+1: along +x2, resp. +x1) so that no cell hides them; with
    ``surfaces`` the ellipsoids are drawn too, translucent (the
    parts inside the drawn cells stay hidden by them).
    """
    if not getattr(result, "inclusions", None):
        return
    mesh = meshes.inclusion_mesh(result.inclusions)
    mesh.points[:, :2] -= np.asarray(result.position[k], dtype=float)
    mesh.points[:] /= length_scale
    axis = 1 if plane == "x2" else 0
    origin = np.zeros(3)
    origin[axis] = cut / length_scale
    outline = mesh.slice(normal=tuple(np.eye(3)[axis]), origin=tuple(origin))
    if surfaces:
        plotter.add_mesh(mesh, color="white", opacity=0.45, smooth_shading=True, show_scalar_bar=False)
    if outline.n_points:
        outline.points[:, axis] = (cut if at is None else at) / length_scale \
            + toward * 1e-3 * max(result.grid.size) / length_scale
        plotter.add_mesh(outline, color="black", line_width=3, lighting=False, label="inhomogeneity")


def indenter(plotter, result, k, warp_factor, length_scale, deepest):
    """The indenter, exaggerated like the surface, shown up to a little above the undeformed plane."""
    grid = result.grid
    mesh = meshes.indenter_mesh(result, k)  # at its position, tilt included
    # lifted by 0.2 % of the grid side: in contact the indenter and the surface coincide (no z-fighting)
    mesh.points[:, 2] = warp_factor * mesh.points[:, 2] + 2e-3 * max(grid.size)
    mesh.points[:] /= length_scale
    mesh.point_data["z"] = mesh.points[:, 2].copy()
    top = max(0.3 * warp_factor * deepest, 0.02 * max(grid.size)) / length_scale
    mesh = mesh.clip_scalar(scalars="z", value=top, invert=True)
    if mesh.n_cells:
        plotter.add_mesh(mesh, color="lightgray", opacity=0.35, show_scalar_bar=False, smooth_shading=True)
