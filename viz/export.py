"""ParaView export: VTU files per step and PVD time collections.

Layout of the output folder (``NNNN`` is the step index, zero padded to 4 digits)::

    surface.pvd   surface_NNNN.vtu    undeformed surface + displacement vector, quads
    volume.pvd    volume_NNNN.vtu     subsurface stresses, hexahedra (only with layers)
    indenter.pvd  indenter_NNNN.vtu   the indenter's surface at its position, quads
    configuration.json                result.configuration() with the framework version
    inclusions.vtp                    the inhomogeneities' surfaces, triangles (only for a run with them)

Open a ``.pvd`` in ParaView: its time steps carry the PHYSICAL time [s] of each
step. The z axis points up, the solid occupies ``z <= 0`` (see
:mod:`viz.meshes` for the geometry, the cell numbering and the stress frame).
The surface is written undeformed: Warp By Vector ``displacement_vector``
(scale factor 1) shows the deformed surface. A rolling run's grid moves with
the body; the files draw it at the body's position in the material frame
(``result.position``), so the body and its contact travel over the material. The 6-component ``stress`` (and
``eigenstrain``) is a symmetric tensor in VTK's order ``XX YY ZZ XY YZ XZ``,
which ParaView's tensor filters expect (the framework's
:meth:`~framework.Result.stress` is in Voigt order ``xx yy zz yz xz xy``); the
components are also written one by one (``stress_xx`` ...).

Every VTU file carries the field data ``framework_version`` and
``configuration`` (JSON of ``result.configuration()``) as VTK string arrays,
which ParaView shows as text (``Exporter(..., meshio=True)`` stores them as
UTF-8 uint8 arrays instead: meshio refuses a file holding a string array;
:func:`viz.meshes.decode_text` reads both), plus ``time`` [s], ``TimeValue``
[s] and ``step``. ``inclusions.vtp`` (polygonal data, the same for every step: the
inhomogeneities do not move) carries ``framework_version`` and
``configuration`` only, and the cell data ``inhomogeneity`` (``k + 1`` on
the ``k``-th, as in the volume files), ``young`` and ``poisson`` (see
:func:`viz.meshes.inclusion_mesh`); open it beside ``volume.pvd``.
Files are binary (raw appended data, zlib compressed, float64) and
readable by ParaView and pyvista/VTK, and with ``meshio=True`` by meshio.

Each file is written under a temporary name in the same folder and moved into
place with :func:`os.replace`, and the collections are rewritten after every
step, so an interrupted run leaves every finished step readable. Every file gets
the mode ``0o666`` less the umask (0644 with the usual umask 022), like the
pictures and any file ``open`` creates.
"""
import contextlib
import json
import os
import secrets
import warnings
from xml.sax.saxutils import quoteattr

import numpy as np

from framework.errors import ParameterError

from . import _deps, meshes

COLLECTIONS = ("surface", "volume", "indenter")


@contextlib.contextmanager
def _replacing(path, suffix=""):
    """Yield a new temporary file name next to ``path``, ending in ``suffix``; on success move it onto ``path``.

    ``suffix`` serves writers that take the format from the name (``".mp4"``).

    The file is created with mode ``0o666`` less the process umask, like any
    file ``open`` makes (``tempfile.mkstemp`` would give 0600 and the results
    would be private in a shared folder). Removed if the block fails.
    """
    folder = os.path.dirname(os.path.abspath(path))
    while True:
        tmp = os.path.join(folder, f".{os.path.basename(path)}.{secrets.token_hex(4)}.tmp{suffix}")
        try:
            os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            break
        except FileExistsError:
            continue
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def _write_vtu(mesh, path, compress=True):
    """Write ``mesh`` (a vtkUnstructuredGrid, or a vtkPolyData to a ``.vtp``) to ``path`` atomically."""
    vtk_io = _deps.require("vtkmodules.vtkIOXML")
    with _replacing(path) as tmp:
        polygons = path.endswith(".vtp")
        writer = vtk_io.vtkXMLPolyDataWriter() if polygons else vtk_io.vtkXMLUnstructuredGridWriter()
        writer.SetFileName(tmp)
        writer.SetInputData(mesh)
        writer.SetDataModeToAppended()
        writer.EncodeAppendedDataOff()
        writer.SetHeaderTypeToUInt64()
        if compress:
            writer.SetCompressorTypeToZLib()
        else:
            writer.SetCompressorTypeToNone()
        if writer.Write() != 1:
            raise OSError(f"VTK could not write {path!r}")


def _write_text(text, path):
    """Write ``text`` to ``path`` atomically."""
    with _replacing(path) as tmp, open(tmp, "w", encoding="utf-8") as f:
        f.write(text)


def pvd_text(entries, comment=None):
    """The XML of a VTK collection (``.pvd``).

    Parameters
    ----------
    entries : iterable of (float, str)
        ``(time [s], file name relative to the .pvd)`` per step, in order.
    comment : str, optional
        Written as an XML comment after the declaration.

    Returns
    -------
    str
        The document.
    """
    lines = ['<?xml version="1.0"?>']
    if comment:
        lines.append("<!-- " + comment.replace("--", "- -") + " -->")
    lines += ['<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">', "  <Collection>"]
    for time, name in entries:
        lines.append(f'    <DataSet timestep="{float(time)!r}" group="" part="0" file={quoteattr(name)}/>')
    lines += ["  </Collection>", "</VTKFile>", ""]
    return "\n".join(lines)


class Exporter:
    """Streaming ParaView export: one call of :meth:`write` per finished step.

    Each :meth:`write` writes the step's VTU files and at once rewrites the
    ``.pvd`` collections, so the folder is readable after every step (use it
    while a run goes on, or to keep the finished steps of a run that fails).

    Parameters
    ----------
    folder : str or path
        Output folder (created if missing). Existing files of the same names
        are replaced; the collections list only the steps written by this
        exporter.
    surface : bool
        Write ``surface_NNNN.vtu`` (default True).
    volume : bool or None
        Write ``volume_NNNN.vtu``; None (default): when the grid has layers
        and a stress operator (otherwise a warning, once).
    indenter : bool
        Write ``indenter_NNNN.vtu`` (default True).
    compress : bool
        zlib-compress the VTU data (default True).
    single : bool
        Write the volume's cell data as float32 (about half the size, relative
        rounding 6e-8; default False: float64, the exact values). With 24
        layers on 129 x 129 cells a volume file holds 400k hexahedra, about
        50 MB in float64.
    meshio : bool
        Store the text field data (``framework_version``, ``configuration``)
        as UTF-8 uint8 arrays, so that meshio (5.3), which refuses a file
        holding a VTK string array, reads the files; ParaView then shows the
        text as numbers. Default False: VTK string arrays, shown as text.

    Attributes
    ----------
    folder : str
        The output folder.
    files : list of str
        Every file written so far (data files and collections).
    steps : list of int
        Step indices written, in the order of writing.

    Examples
    --------
    Export while the run goes on::

        sim = framework.demo.build(65)
        result = framework.Result(sim.grid, sim.material, sim.indenter, sim.schedule, sim.options)
        exporter = Exporter("out/paraview")
        for record in sim.steps():
            result.append(record)
            exporter.write(result, len(result) - 1)
    """

    def __init__(self, folder, *, surface=True, volume=None, indenter=True, compress=True, single=False,
                 meshio=False):
        self.folder = os.fspath(folder)
        os.makedirs(self.folder, exist_ok=True)
        self._enabled = {"surface": bool(surface), "volume": volume, "indenter": bool(indenter)}
        self.compress = bool(compress)
        self.single = bool(single)
        self.strings = not meshio
        self._entries = {name: {} for name in COLLECTIONS}
        self._configuration = None
        self.files = []
        self.steps = []

    @property
    def collections(self):
        """Paths of the ``.pvd`` files written so far, by name (``surface``, ``volume``, ``indenter``)."""
        return {name: os.path.join(self.folder, name + ".pvd") for name in COLLECTIONS if self._entries[name]}

    def _volume_wanted(self, result):
        wanted = self._enabled["volume"]
        if wanted is None:
            wanted = bool(result.grid.layers)
        return wanted

    def write(self, result, step):
        """Write one step and update the collections.

        Parameters
        ----------
        result : framework.Result
            The run (may still be growing).
        step : int
            Step index (negative counts from the end).

        Returns
        -------
        list of str
            The files written by this call.
        """
        k = meshes.step_index(result, step)
        time = float(result.times[k])
        if self._configuration is None:
            self._configuration = meshes.configuration_json(result)
            path = os.path.join(self.folder, "configuration.json")
            _write_text(json.dumps(json.loads(self._configuration), indent=2) + "\n", path)
            self._remember(path)
            if getattr(result, "inclusions", None):
                mesh = meshes.inclusion_mesh(result.inclusions)
                meshes.add_text(mesh, "framework_version", str(result.version), self.strings)
                meshes.add_text(mesh, "configuration", self._configuration, self.strings)
                path = os.path.join(self.folder, "inclusions.vtp")
                _write_vtu(mesh, path, self.compress)
                self._remember(path)
        written = []
        builders = []
        if self._enabled["surface"]:
            builders.append(("surface", meshes.surface_mesh))
        if self._volume_wanted(result):
            builders.append(("volume", meshes.volume_mesh))
        if self._enabled["indenter"]:
            builders.append(("indenter", meshes.indenter_mesh))
        for name, build in builders:
            try:
                mesh = build(result, k)
            except ParameterError as exc:
                if name == "volume" and self._enabled["volume"] is None:
                    warnings.warn(f"no volume export: {exc}", stacklevel=2)
                    self._enabled["volume"] = False
                    continue
                raise
            if name == "volume" and self.single:
                for key in list(mesh.cell_data.keys()):
                    if mesh.cell_data[key].dtype == np.float64:
                        mesh.cell_data[key] = mesh.cell_data[key].astype(np.float32)
            meshes.to_material_frame(mesh, result, k)
            meshes.attach_metadata(mesh, result, k, self._configuration, self.strings)
            filename = f"{name}_{k:04d}.vtu"
            path = os.path.join(self.folder, filename)
            _write_vtu(mesh, path, self.compress)
            self._entries[name][k] = (time, filename)
            written.append(path)
        for name, _ in builders:
            if self._entries[name]:
                path = os.path.join(self.folder, name + ".pvd")
                entries = [self._entries[name][s] for s in sorted(self._entries[name])]
                _write_text(pvd_text(entries, f"viscocontact framework {result.version}: {name}, "
                                              f"time in seconds"), path)
                written.append(path)
        for path in written:
            self._remember(path)
        if k not in self.steps:
            self.steps.append(k)
        return written

    def _remember(self, path):
        if path not in self.files:
            self.files.append(path)


def export(result, folder, steps=None, **options):
    """Write a result as ParaView files (see the module docstring for the layout).

    Parameters
    ----------
    result : framework.Result
        The run.
    folder : str or path
        Output folder (created if missing).
    steps : int or sequence of int, optional
        Step indices to write (negative count from the end); all by default.
    **options
        ``surface``, ``volume``, ``indenter``, ``compress``, ``single``, ``meshio``: see :class:`Exporter`.

    Returns
    -------
    Exporter
        ``.collections`` maps ``surface``/``volume``/``indenter`` to the
        ``.pvd`` paths; ``.files`` lists every file written.
    """
    if steps is None:
        steps = range(len(result))
    elif isinstance(steps, (int, np.integer)):
        steps = [steps]
    indices = [meshes.step_index(result, s) for s in steps]
    exporter = Exporter(folder, **options)
    for k in sorted(set(indices)):
        exporter.write(result, k)
    return exporter
