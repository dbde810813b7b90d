"""What a picture can colour: the field names, their labels and units, and the values drawn.

Labels are typeset with mathtext (``$u_3$``, ``$\\sigma_{xz}$``), which VTK
draws through matplotlib; stress components are in the frame z up of the
files (see :mod:`viz.meshes`).
"""
import numpy as np

from . import meshes, slices

#: Surface fields: name -> (label, SI unit).
SURFACE_FIELDS = {
    "pressure": ("pressure", "Pa"),
    "displacement": ("normal displacement $u_3$", "m"),
    "gap": ("gap", "m"),
    "contact": ("contact", ""),
}

#: Subsurface fields for ``kind="slice"``: name -> (label, SI unit). Components in the z-up frame.
VOLUME_FIELDS = {
    "von_mises": ("von Mises stress", "Pa"),
    "tresca": ("Tresca stress", "Pa"),
    "principal_1": ("max principal stress $\\sigma_1$", "Pa"),
    "principal_2": ("middle principal stress $\\sigma_2$", "Pa"),
    "principal_3": ("min principal stress $\\sigma_3$", "Pa"),
    **{name: (("normal" if name[-1] == name[-2] else "shear") + f" stress $\\sigma_{{{name[-2:]}}}$", "Pa")
       for name in meshes.STRESS_COMPONENTS},
}

#: Picture kind -> the fields it can show.
KINDS = {"map": SURFACE_FIELDS, "surface": SURFACE_FIELDS, "slice": VOLUME_FIELDS}

#: Picture kind -> the field it shows when none is named.
DEFAULT_FIELD = {"map": "pressure", "surface": "pressure", "slice": "von_mises"}


def surface_field(result, k, field):
    """The surface field ``(n1, n2)`` of step ``k`` [SI unit]; ``contact`` is 1 where the pressure is positive."""
    if field == "pressure":
        return np.asarray(result.pressure(k), dtype=float)
    if field == "displacement":
        return np.asarray(result.displacement(k), dtype=float)
    if field == "gap":
        return np.asarray(result.gap(k), dtype=float)
    return (np.asarray(result.pressure(k)) > 0).astype(float)


def stress_field(stress, field):
    """A subsurface field [Pa] of Voigt stresses ``(..., 6)`` (the framework's order and frame)."""
    if field in meshes.STRESS_COMPONENTS:
        return meshes.vtk_tensor(stress)[..., meshes.STRESS_COMPONENTS.index(field)]
    measures = meshes.stress_measures(stress)
    if field.startswith("principal_"):
        return measures["principal_stress"][..., int(field[-1]) - 1]
    return measures[field]


def shown_values(result, k, kind, field, *, plane="x2", origin=0.0, clip=False):
    """The values a picture of step ``k`` colours [SI unit]: what its colour range is taken from.

    Parameters
    ----------
    result : framework.Result
        The run.
    k : int
        Step index (non-negative).
    kind, field, plane, origin, clip
        As in :func:`viz.render` (``field`` not None).

    Returns
    -------
    ndarray
        ``kind="map"`` or ``"surface"``: the surface field ``(n1, n2)``.
        ``kind="slice"``: the field in the plane ``plane = origin``
        (:mod:`viz.slices`: interpolated between the centres either side),
        ``(n1, layers)`` for ``plane="x2"`` (``(n2, layers)`` for ``"x1"``);
        with ``clip`` the block of cells from the one holding the plane on,
        ``(n1, n2 - index, layers)`` (``(n1 - index, n2, layers)``).
    """
    if kind != "slice":
        return surface_field(result, k, field)
    if not clip:
        return stress_field(slices.plane_stress(result, k, slices.locate(result.grid, plane, origin)), field)
    values = stress_field(np.asarray(result.stress(k), dtype=float), field)
    index = slices.plane_index(result.grid, plane, origin)
    return values[:, index:] if plane == "x2" else values[index:]
