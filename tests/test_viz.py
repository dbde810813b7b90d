"""viz: ParaView export round trips (pyvista and meshio), streaming, pictures and history plots."""
import json
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

pv = pytest.importorskip("pyvista")
meshio = pytest.importorskip("meshio")
pytest.importorskip("matplotlib")

import framework  # noqa: E402
from framework import Grid, Simulation, indenters, materials, schedules  # noqa: E402
from framework.demo import build  # noqa: E402
from framework.errors import ParameterError  # noqa: E402
from viz import Exporter, export, plot_history, render  # noqa: E402
from viz import meshes  # noqa: E402

STEP = 5


@pytest.fixture(scope="module")
def result():
    """The demo (PMMA creeping under a ball, 17 steps) on 17 x 17 cells."""
    return build(17).run()


@pytest.fixture(scope="module")
def elastic():
    """An elastic ball at two loads on an even grid without layers."""
    sim = Simulation(grid=Grid(shape=(16, 16), size=(1e-3, 1e-3)),
                     material=materials.Elastic(young=2e9, poisson=0.35),
                     indenter=indenters.Sphere(radius=5e-3), schedule=schedules.Static(load=[5.0, 20.0]))
    return sim.run()


@pytest.fixture(scope="module")
def exported(result, tmp_path_factory):
    folder = tmp_path_factory.mktemp("paraview")
    return export(result, folder), folder


@pytest.fixture(scope="module")
def exported_for_meshio(result, tmp_path_factory):
    """The files of step STEP with the text field data as uint8 arrays, which meshio can read."""
    folder = tmp_path_factory.mktemp("meshio")
    return export(result, folder, steps=[STEP], meshio=True), folder


def _centres(mesh):
    """Cell centres of a meshio mesh with one cell block."""
    return mesh.points[mesh.cells[0].data].mean(axis=1)


def test_pvd_collections_carry_the_physical_times(result, exported):
    exporter, folder = exported
    assert set(exporter.collections) == {"surface", "volume", "indenter"}
    for path in exporter.collections.values():
        reader = pv.get_reader(path)
        np.testing.assert_array_equal(reader.time_values, result.times)
    reader = pv.get_reader(exporter.collections["surface"])
    reader.set_active_time_value(result.times[STEP])
    block = reader.read()
    surface = block[0] if isinstance(block, pv.MultiBlock) else block
    np.testing.assert_array_equal(meshes.grid_order(surface.cell_data["pressure"], result.grid.shape),
                                  result.pressure(STEP))
    assert not [name for name in os.listdir(folder) if name.endswith(".tmp")]


def test_meshio_reads_quads_and_hexahedra_in_the_documented_order(result, exported_for_meshio):
    _, folder = exported_for_meshio
    grid = result.grid
    n1, n2, n3 = grid.shape + (grid.layers,)
    surface = meshio.read(os.path.join(folder, f"surface_{STEP:04d}.vtu"))
    assert [(c.type, len(c.data)) for c in surface.cells] == [("quad", n1 * n2)]
    assert surface.points.shape == ((n1 + 1) * (n2 + 1), 3)
    pressure = meshes.grid_order(surface.cell_data["pressure"][0], grid.shape)
    np.testing.assert_allclose(pressure, result.pressure(STEP), rtol=1e-12, atol=0)
    np.testing.assert_allclose(meshes.grid_order(surface.cell_data["displacement"][0], grid.shape),
                               result.displacement(STEP), rtol=1e-12, atol=0)
    np.testing.assert_array_equal(meshes.grid_order(surface.cell_data["contact"][0], grid.shape),
                                  result.pressure(STEP) > 0)
    x1, x2 = grid.coordinates()
    centres = meshes.grid_order(_centres(surface)[:, :2], grid.shape)
    np.testing.assert_allclose(centres[..., 0], x1, atol=1e-15)
    np.testing.assert_allclose(centres[..., 1], x2, atol=1e-15)
    # the undeformed surface z = 0; `displacement_vector` leads to the deformed one, z = -u3 at the corners
    corners = meshes.corner_average(result.displacement(STEP))
    assert np.all(surface.points[:, 2] == 0.0)
    warped = surface.points + surface.point_data["displacement_vector"]
    np.testing.assert_allclose(warped[:, 2], -corners.ravel(order="F"), rtol=1e-12)
    np.testing.assert_array_equal(warped[:, :2], surface.points[:, :2])

    volume = meshio.read(os.path.join(folder, f"volume_{STEP:04d}.vtu"))
    assert [(c.type, len(c.data)) for c in volume.cells] == [("hexahedron", n1 * n2 * n3)]
    stress = result.stress(STEP)
    zz = meshes.grid_order(volume.cell_data["stress_zz"][0], (n1, n2, n3))
    np.testing.assert_allclose(zz, stress[..., 2], rtol=1e-12, atol=1e-12 * np.abs(stress).max())
    # VTK's tensor order xx yy zz xy yz xz, z up: xy = sigma_12, yz = -sigma_23, xz = -sigma_13
    tensor = meshes.grid_order(volume.cell_data["stress"][0], (n1, n2, n3))
    np.testing.assert_allclose(tensor, stress[..., [0, 1, 2, 5, 3, 4]] * [1, 1, 1, 1, -1, -1], rtol=1e-12,
                               atol=1e-12 * np.abs(stress).max())
    for c, name in enumerate(("xx", "yy", "zz", "xy", "yz", "xz")):
        np.testing.assert_array_equal(volume.cell_data["stress_" + name][0], volume.cell_data["stress"][0][:, c])
    np.testing.assert_allclose(meshes.grid_order(volume.cell_data["von_mises"][0], (n1, n2, n3)),
                               result.von_mises(STEP), rtol=1e-12)
    principal = volume.cell_data["principal_stress"][0]
    assert principal.shape == (n1 * n2 * n3, 3) and np.all(np.diff(principal, axis=1) <= 0)
    np.testing.assert_allclose(volume.cell_data["tresca"][0], principal[:, 0] - principal[:, 2], rtol=1e-12)
    np.testing.assert_allclose(principal.sum(axis=1), tensor[..., :3].sum(axis=-1).transpose(2, 1, 0).ravel(),
                               atol=1e-8 * np.abs(stress).max())
    centres = meshes.grid_order(_centres(volume), (n1, n2, n3))
    np.testing.assert_allclose(centres[..., 2], -np.broadcast_to(grid.x3, (n1, n2, n3)), atol=1e-15)
    np.testing.assert_allclose(centres[..., 0], np.broadcast_to(grid.x1[:, None, None], (n1, n2, n3)), atol=1e-15)

    indenter = meshio.read(os.path.join(folder, f"indenter_{STEP:04d}.vtu"))
    assert [(c.type, len(c.data)) for c in indenter.cells] == [("quad", n1 * n2)]
    heights = result.indenter.on_grid(grid)
    np.testing.assert_allclose(meshes.grid_order(indenter.cell_data["height"][0], grid.shape), heights)
    np.testing.assert_allclose(indenter.points[:, 2],
                               (meshes.corner_average(heights) - result.approach[STEP]).ravel(order="F"))


def _vtk_principal(mesh):
    """VTK's own principal values (largest first) and directions of the cell tensor ``stress``."""
    from vtkmodules.vtkFiltersTensor import vtkTensorPrincipalInvariants
    invariants = vtkTensorPrincipalInvariants()
    invariants.SetInputData(mesh)
    invariants.SetInputArrayToProcess(0, 0, 0, 1, "stress")  # port 0, connection 0, cell data
    invariants.Update()
    out = pv.wrap(invariants.GetOutput())
    values = np.column_stack([out.cell_data[f"stress - Sigma {i}"] for i in (1, 2, 3)])
    directions = np.stack([out.cell_data[f"stress - Sigma {i} (Vector)"] for i in (1, 2, 3)], axis=1)
    return values, directions


def test_vtk_reads_the_exported_stress_tensor(exported):
    """ParaView's tensor filters read `stress` as XX YY ZZ XY YZ XZ: their principal stresses must be ours."""
    _, folder = exported
    volume = pv.read(os.path.join(folder, f"volume_{STEP:04d}.vtu"))
    values, _ = _vtk_principal(volume)
    ours = np.asarray(volume.cell_data["principal_stress"])
    scale = np.abs(ours).max(axis=1, keepdims=True)
    assert scale.min() > 0
    np.testing.assert_allclose(values / scale, ours / scale, rtol=0, atol=1e-10)


def test_vtk_reads_a_tensor_of_known_principal_stresses(result):
    """Rotated diagonal tensors, one per cell: VTK finds the eigenvalues and (frame z up) the eigenvectors."""
    n1, n2, n3 = result.grid.shape + (result.grid.layers,)
    rng = np.random.default_rng(7)
    eigenvalues = -np.sort(-rng.uniform(-3e8, 1e8, (n1, n2, n3, 3)), axis=-1)  # [Pa], descending
    rotations, _ = np.linalg.qr(rng.normal(size=(n1, n2, n3, 3, 3)))
    full = np.einsum("...ij,...j,...kj->...ik", rotations, eigenvalues, rotations)  # R diag R^T, x3 down
    voigt = full[..., [0, 1, 2, 1, 0, 0], [0, 1, 2, 2, 2, 1]]  # xx yy zz yz xz xy
    volume = meshes.volume_mesh(result, 0, stress=voigt)
    values, directions = _vtk_principal(volume)
    flat = meshes.cell_order(eigenvalues, 3)
    np.testing.assert_allclose(values, flat, rtol=0, atol=1e-10 * 3e8)
    np.testing.assert_allclose(volume.cell_data["principal_stress"], flat, rtol=0, atol=1e-10 * 3e8)
    # eigenvector of the largest value in the exported frame: (v1, v2, -v3), up to its sign
    expected = meshes.cell_order(rotations[..., :, 0], 3) * [1, 1, -1]
    cosine = np.abs(np.sum(directions[:, 0] * expected, axis=1)) / np.linalg.norm(directions[:, 0], axis=1)
    np.testing.assert_allclose(cosine, 1.0, atol=1e-8)


def test_warped_surface_meets_the_indenter(result, exported):
    """Warp By Vector (scale 1) takes the undeformed surface onto the indenter where all four cells touch."""
    _, folder = exported
    surface = pv.read(os.path.join(folder, f"surface_{STEP:04d}.vtu"))
    indenter = pv.read(os.path.join(folder, f"indenter_{STEP:04d}.vtu"))
    assert surface.active_vectors_name == "displacement_vector"  # what Warp By Vector offers first
    assert surface.GetPointData().GetScalars() is None and surface.active_scalars_name == "pressure"
    warped = surface.warp_by_vector("displacement_vector", factor=1.0)
    contact = np.pad(result.pressure(STEP) > 0, 1)
    touching = (contact[:-1, :-1] & contact[1:, :-1] & contact[:-1, 1:] & contact[1:, 1:]).ravel(order="F")
    assert touching.sum() >= 4
    np.testing.assert_allclose(warped.points[touching, 2], indenter.points[touching, 2], rtol=0,
                               atol=1e-8 * np.abs(result.displacement(STEP)).max())  # the solver tolerance
    assert np.all(warped.points[~touching, 2] <= indenter.points[~touching, 2] + 1e-12)  # the ball is above


@pytest.mark.parametrize("umask", [0o022, 0o002, 0o077])
def test_exported_files_honour_the_umask(result, tmp_path, umask):
    """Shared folders: every file gets 0o666 less the umask, like the pictures (not mkstemp's 0600)."""
    previous = os.umask(umask)
    try:
        exporter = export(result, tmp_path, steps=[0, 1])
        render(result, tmp_path / "map.png", step=0)
    finally:
        os.umask(previous)
    names = sorted(os.listdir(tmp_path))
    assert {os.path.basename(f) for f in exporter.files} | {"map.png"} == set(names)
    assert {name: oct(os.stat(tmp_path / name).st_mode & 0o777) for name in names} == \
        {name: oct(0o666 & ~umask) for name in names}


def test_cells_are_well_oriented(exported):
    _, folder = exported
    volume = pv.read(os.path.join(folder, "volume_0000.vtu")).compute_cell_sizes()
    assert volume.celltypes[0] == pv.CellType.HEXAHEDRON
    assert volume.cell_data["Volume"].min() > 0
    surface = pv.read(os.path.join(folder, "surface_0000.vtu"))
    assert surface.celltypes[0] == pv.CellType.QUAD
    normals = surface.extract_surface(algorithm="dataset_surface").compute_normals(
        cell_normals=True, point_normals=False, auto_orient_normals=False, consistent_normals=False)
    assert normals.cell_data["Normals"][:, 2].min() > 0.9  # up, out of the solid


def _vtk_field_data(path):
    """The field data of a VTU or VTP file as VTK's own XML reader gives it: name -> the vtk array."""
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLUnstructuredGridReader
    reader = vtkXMLPolyDataReader() if str(path).endswith(".vtp") else vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    data = reader.GetOutput().GetFieldData()
    return {data.GetAbstractArray(i).GetName(): data.GetAbstractArray(i) for i in range(data.GetNumberOfArrays())}


def test_every_file_carries_version_and_configuration_as_text(result, exported):
    """ParaView shows text for VTK string arrays (numbers for a uint8 array): VTK's reader finds strings."""
    exporter, folder = exported
    configuration = meshes.configuration_json(result)
    for name in ("surface", "volume", "indenter"):
        path = os.path.join(folder, f"{name}_{STEP:04d}.vtu")
        arrays = _vtk_field_data(path)
        for key, text in (("framework_version", framework.__version__), ("configuration", configuration)):
            array = arrays[key]
            assert array.GetClassName() == "vtkStringArray" and array.GetNumberOfValues() == 1
            assert array.GetValue(0) == text
        assert arrays["time"].GetValue(0) == result.times[STEP] and arrays["step"].GetValue(0) == STEP
        assert arrays["TimeValue"].GetValue(0) == result.times[STEP]
        mesh = pv.read(path)
        assert json.loads(meshes.decode_text(mesh.field_data["configuration"]))["grid"]["layers"] == result.grid.layers
        with open(path, "rb") as f:
            assert b'<Array type="String" Name="configuration"' in f.read(4096)
    assert json.loads(configuration) == json.loads(json.dumps(result.configuration()))
    with open(os.path.join(folder, "configuration.json")) as f:
        assert json.load(f)["framework_version"] == framework.__version__


def test_meshio_reads_version_configuration_time_and_step(result, exported_for_meshio):
    _, folder = exported_for_meshio
    expected = json.loads(json.dumps(result.configuration()))
    for name in ("surface", "volume", "indenter"):
        path = os.path.join(folder, f"{name}_{STEP:04d}.vtu")
        data = meshio.read(path).field_data
        assert meshes.decode_text(data["framework_version"]) == framework.__version__
        assert json.loads(meshes.decode_text(data["configuration"])) == expected
        assert float(np.ravel(data["time"])[0]) == result.times[STEP]
        assert int(np.ravel(data["step"])[0]) == STEP
        assert _vtk_field_data(path)["configuration"].GetDataTypeAsString() == "unsigned char"


def test_streaming_leaves_the_finished_steps_readable(result, tmp_path):
    exporter = Exporter(tmp_path)
    for step in (0, 1):
        written = exporter.write(result, step)
        assert os.path.join(str(tmp_path), f"surface_{step:04d}.vtu") in written
    for name in ("surface", "volume", "indenter"):
        path = tmp_path / f"{name}.pvd"
        datasets = ET.parse(path).getroot().findall("./Collection/DataSet")
        assert [d.get("file") for d in datasets] == [f"{name}_0000.vtu", f"{name}_0001.vtu"]
        np.testing.assert_array_equal(pv.get_reader(str(path)).time_values, result.times[:2])
    assert pv.read(tmp_path / "volume_0001.vtu").celltypes[0] == pv.CellType.HEXAHEDRON
    assert not list(tmp_path.glob("*.tmp")) and not list(tmp_path.glob("volume_0002*"))
    exporter.write(result, 2)
    np.testing.assert_array_equal(pv.get_reader(str(tmp_path / "surface.pvd")).time_values, result.times[:3])


def test_export_of_chosen_steps_and_of_a_grid_without_layers(elastic, tmp_path):
    exporter = export(elastic, tmp_path, steps=[-1])
    assert set(exporter.collections) == {"surface", "indenter"}
    assert exporter.steps == [1]
    assert sorted(os.listdir(tmp_path)) == ["configuration.json", "indenter.pvd", "indenter_0001.vtu",
                                            "surface.pvd", "surface_0001.vtu"]
    with pytest.raises(ParameterError, match="step"):
        export(elastic, tmp_path, steps=[7])


def test_corner_average_wraps_on_periodic_axes():
    field = np.arange(12.0).reshape(3, 4)
    corners = meshes.corner_average(field)
    assert corners.shape == (4, 5)
    assert corners[0, 0] == field[0, 0] and corners[1, 1] == field[:2, :2].mean()
    periodic = meshes.corner_average(field, (True, True))
    assert periodic[0, 0] == periodic[-1, -1] == field[[0, 0, -1, -1], [0, -1, 0, -1]].mean()


def _colours(path):
    from matplotlib.image import imread
    image = imread(path)[..., :3]
    return image, len(np.unique((image * 255).round().astype(np.uint8).reshape(-1, 3), axis=0))


def test_pressure_map_colour_range_follows_the_load(elastic, tmp_path):
    pictures = []
    for step in (0, 1):
        picture = render(elastic, tmp_path / f"map_{step}.png", "pressure", step)
        pressure = elastic.pressure(step)
        assert picture.scalar_range == (pressure.min(), pressure.max()) == picture.clim
        assert picture.display_unit == "MPa" and picture.time == elastic.times[step]
        image, colours = _colours(picture.path)
        assert image.shape[:2] == picture.window_size[::-1] and colours > 50
        left, bottom, right, top = picture.field_box  # a square field drawn square
        assert right - left == pytest.approx(top - bottom, abs=1.0)
        pictures.append((picture, image))
    (low, image_low), (high, image_high) = pictures
    assert high.scalar_range[1] > 1.5 * low.scalar_range[1]
    assert np.abs(image_high - image_low).max() > 0.1
    fixed = render(elastic, tmp_path / "fixed.png", "pressure", 0, clim=high.clim)
    assert fixed.clim == high.clim and fixed.scalar_range == low.scalar_range


@pytest.mark.parametrize("kind, field, options", [
    ("surface", "displacement", {"show_indenter": True}),
    ("slice", "von_mises", {}),
    ("slice", "stress_zz", {"clip": True, "plane": "x1"}),
])
def test_other_pictures_are_not_blank(result, tmp_path, kind, field, options):
    picture = render(result, tmp_path / "picture.png", field, STEP, kind=kind, **options)
    assert os.path.getsize(picture.path) > 10_000 and _colours(picture.path)[1] > 50
    if kind == "surface":
        assert picture.warp > 1
    if kind == "slice" and not options:
        middle = result.von_mises(STEP)[:, result.grid.shape[1] // 2, :]
        assert picture.scalar_range == (middle.min(), middle.max())


def test_history_plot(result, tmp_path):
    path = plot_history(result, tmp_path / "history.png", ["contact_radius", "max_pressure", "center", "tilt"])
    with open(path, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    assert os.path.getsize(path) > 20_000
    assert os.path.exists(plot_history(result, tmp_path / "load.png", "approach", against="load"))


def test_bad_names_raise_parameter_errors(result, elastic, tmp_path):
    with pytest.raises(ParameterError, match="'strain'.*von_mises"):
        render(result, tmp_path / "x.png", "strain", kind="slice")
    with pytest.raises(ParameterError, match="'stress_zz'"):
        render(result, tmp_path / "x.png", "stress_zz", kind="map")
    with pytest.raises(ParameterError, match="'side'"):
        render(result, tmp_path / "x.png", kind="side")
    with pytest.raises(ParameterError, match="layers"):
        render(elastic, tmp_path / "x.png", kind="slice")
    with pytest.raises(ParameterError, match="clim"):
        render(elastic, tmp_path / "x.png", clim=(1.0,))
    with pytest.raises(ParameterError, match="step"):
        render(elastic, tmp_path / "x.png", step=2)
    with pytest.raises(ParameterError, match="'area'"):
        plot_history(result, tmp_path / "x.png", ["load", "area"])
    with pytest.raises(ParameterError, match="'force'"):
        plot_history(result, tmp_path / "x.png", against="force")
    assert not list(tmp_path.iterdir())


def test_missing_extra_is_named(result, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyvista", None)
    with pytest.raises(ImportError, match=r"viscocontact\[viz\]"):
        render(result, tmp_path / "x.png")
    with pytest.raises(ImportError, match=r"viscocontact\[viz\]"):
        export(result, tmp_path, steps=0)


def test_indenter_mesh_carries_the_tilt():
    """Eccentric flat punch: the exported indenter face is the plane h - (delta + alpha . x)."""
    import framework as fw
    from viz import meshes
    grid = fw.Grid(shape=(31, 31), size=(3e-3, 3e-3))
    result = fw.Simulation(grid=grid, material=fw.materials.Elastic(young=1e9, poisson=0.3),
                           indenter=fw.indenters.FlatPunch(radius=1e-3),
                           schedule=fw.schedules.Eccentric(load=5.0, offset=(2e-4, -1e-4))).run()
    mesh = meshes.indenter_mesh(result, 0)
    points = np.asarray(mesh.points)
    face = np.hypot(points[:, 0], points[:, 1]) < 0.8e-3
    slopes = np.tan(result.tilt[0])
    expected = -(result.approach[0] + slopes[0] * points[face, 0] + slopes[1] * points[face, 1])
    assert np.allclose(points[face, 2], expected, rtol=0, atol=1e-12)
    assert slopes[0] > 0 and slopes[1] < 0


def test_colour_limits_snap_round_off_and_centre_signed_fields():
    """Round-off ends (below 1e-6 of the range) print as 0; a field of both signs gets symmetric limits."""
    from viz.render import colour_limits, nice_ticks
    assert colour_limits(-7.62e-15, 5.2e-5) == (0.0, 5.2e-5)  # a gap: -7.6e-15 m is round-off
    assert colour_limits(-2.17e9, -1.6e3) == (-2.17e9, 0.0)  # sigma_zz outside the contact
    assert colour_limits(-2.17e9, -2.2e3) == (-2.17e9, -2.2e3)  # 1.01e-6 of the range: kept
    assert colour_limits(-3.0, 5.0) == (-5.0, 5.0)
    assert colour_limits(2.0, 5.0) == (2.0, 5.0)
    values, decimals = nice_ticks(0.0, 92.2, 7)
    assert values.tolist() == [0, 20, 40, 60, 80] and decimals == 0
    values, decimals = nice_ticks(-0.25, 0.25, 7)  # step 0.05 would give 11 ticks
    assert values.tolist() == pytest.approx([-0.2, -0.1, 0.0, 0.1, 0.2]) and decimals == 1
    values, decimals = nice_ticks(0.0, 1.3, 7)
    assert values.tolist() == pytest.approx([0.0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.2]) and decimals == 1


def test_signed_fields_get_a_diverging_map_centred_on_zero(result, tmp_path):
    middle = result.grid.shape[1] // 2  # the cells holding the plane x2 = 0
    shear = -result.stress(STEP)[:, middle, :, 4]  # sigma_xz, z up
    picture = render(result, tmp_path / "xz.png", "stress_xz", STEP, kind="slice")
    assert shear.min() < 0 < shear.max() and picture.scalar_range == (shear.min(), shear.max())
    top = np.abs(shear).max()
    assert picture.cmap == "coolwarm" and picture.clim == (-top, top)
    assert picture.bar_title == "shear stress $\\sigma_{xz}$ [MPa]" and picture.display_unit == "MPa"
    ticks = [float(label) for label in picture.bar_labels]
    assert 0.0 in ticks and ticks == [-t for t in reversed(ticks)]
    mises = render(result, tmp_path / "mises.png", "von_mises", STEP, kind="slice")
    assert mises.cmap == "viridis" and mises.clim == mises.scalar_range
    assert mises.bar_title == "von Mises stress [MPa]"
    assert render(result, tmp_path / "own.png", "stress_xz", STEP, kind="slice", cmap="magma").cmap == "magma"
    assert render(result, tmp_path / "fixed.png", "stress_xz", STEP, kind="slice", clim=(-1e6, 3e7)).cmap == "viridis"


def test_round_off_limits_print_as_zero(result, tmp_path):
    """The gap is -4e-14 m somewhere in the contact: round-off, so the bar starts at a plain 0."""
    gap = result.gap(STEP)
    assert -1e-9 * gap.max() < gap.min() < 0
    picture = render(result, tmp_path / "gap.png", "gap", STEP)
    assert picture.scalar_range[0] == gap.min() and picture.clim == (0.0, gap.max())
    assert picture.cmap == "viridis" and picture.bar_title == "gap [\u00b5m]"
    assert picture.bar_labels[0] == "0" and not any("e" in label for label in picture.bar_labels)


def _apart(boxes):
    """No two label boxes (x0, y0, x1, y1) overlap."""
    return all(a[2] <= b[0] or b[2] <= a[0] or a[3] <= b[1] or b[3] <= a[1]
               for i, a in enumerate(boxes) for b in boxes[i + 1:])


def test_tick_labels_never_overlap(result, tmp_path):
    """Square map, slice, 3-D views and an 8:1 strip 0.5 mm wide: labels apart, round, enough of them."""
    strip = Simulation(grid=Grid(shape=(64, 8), size=(4e-3, 0.5e-3), depth=0.25e-3, layers=4),
                       material=materials.Elastic(young=2e9, poisson=0.35),
                       indenter=indenters.Sphere(radius=5e-3), schedule=schedules.Static(load=[2.0])).run()
    pictures = [render(result, tmp_path / "map.png", "pressure", STEP),
                render(result, tmp_path / "slice.png", "von_mises", STEP, kind="slice"),
                render(result, tmp_path / "surface.png", "displacement", STEP, kind="surface"),
                render(result, tmp_path / "clip.png", "tresca", STEP, kind="slice", clip=True),
                render(strip, tmp_path / "strip.png", "pressure", 0, window_size=(1200, 900)),
                render(strip, tmp_path / "strip_slice.png", "stress_yz", 0, kind="slice", plane="x1")]
    for picture in pictures:
        assert _apart(picture.label_boxes), picture.path
        assert len(picture.label_boxes) == sum(len(v) for v in picture.axis_labels.values())
        for title, labels in picture.axis_labels.items():
            assert len(labels) >= 2 and len(set(labels)) == len(labels), (picture.path, title, labels)
            assert all(len(label.split(".")[-1]) <= 2 for label in labels)
    square, strip_map = pictures[0], pictures[4]
    assert set(square.axis_labels["$x_1$ [mm]"]) >= {"-0.4", "0.0", "0.4"}
    # in a 1200 x 900 window the strip's 0.5 mm side is about 110 pixels tall: five labels, not eight piled up
    assert strip_map.field_box[3] - strip_map.field_box[1] < 120
    assert strip_map.axis_labels["$x_2$ [mm]"] == ("-0.2", "-0.1", "0.0", "0.1", "0.2")
    assert strip_map.axis_labels["$x_1$ [mm]"] == ("-2", "-1", "0", "1", "2")


def test_history_plot_uses_readable_units(result, tmp_path):
    """Radius in um, pressure in MPa (no x1e-4 offsets); the load centre's 1e-14 m round-off plots flat."""
    import matplotlib
    assert np.abs(result.center).max() < 1e-12  # the demo is symmetric
    with matplotlib.rc_context({"svg.fonttype": "none"}):  # text stays text in the SVG
        path = plot_history(result, tmp_path / "history.svg", ["contact_radius", "max_pressure", "center"])
    root = ET.parse(path).getroot()
    texts = [" ".join("".join(node.itertext()).split()) for node in root.iter() if node.tag.endswith("text")]
    texts = [t if "[" in t else t.replace(" ", "") for t in texts]  # tick labels come as one glyph a line
    squeezed = [t.replace(" ", "") for t in texts]  # mathtext labels come as spaced glyphs, symbols last
    assert any("contactradius[\u00b5m]" in t for t in squeezed) and "load centre [\u00b5m]" in texts
    assert any("peakpressure" in t and "[MPa]" in t for t in squeezed)
    assert not any("10^" in t or "\u00d710" in t or "e-" in t for t in texts), texts
    centre_ticks = [t for t in texts if t.lstrip("\u2212-").replace(".", "").isdigit()]
    assert any(t.startswith(("\u2212", "-")) and float(t.lstrip("\u2212-")) >= 5 for t in centre_ticks)


# --------------------------------------------------------------------------- inhomogeneities

@pytest.fixture(scope="module")
def inhomogeneous():
    """A stiff ellipsoid turned about x3 and x1 (shear eigenstrains) under a ball, 24 x 24 cells x 16 layers."""
    from framework import inclusions
    body = inclusions.Ellipsoid(center=(0.0, 0.0, 0.22e-3), semi_axes=(0.15e-3, 0.13e-3, 0.13e-3),
                                material=materials.Elastic(600e9, 0.25),
                                orientation=inclusions.euler_orientation(0.5, 0.4, 0.0))
    sim = Simulation(grid=Grid(shape=(24, 24), size=(1e-3, 1e-3), depth=0.5e-3, layers=16),
                     material=materials.Elastic(200e9, 0.3), indenter=indenters.Sphere(radius=10e-3),
                     schedule=schedules.Static(load=[50.0]), inclusions=[body])
    return sim.run()


def test_eigenstrain_is_exported_in_vtk_tensor_order(inhomogeneous, result, exported, tmp_path):
    grid = inhomogeneous.grid
    n1, n2, n3 = grid.shape + (grid.layers,)
    export(inhomogeneous, tmp_path)
    volume = pv.read(tmp_path / "volume_0000.vtu")
    eigenstrain, indicator = inhomogeneous.eigenstrain(0), inhomogeneous.inhomogeneity(0)
    i, j, k = np.unravel_index(np.argmax(np.abs(eigenstrain[..., 3])), eigenstrain.shape[:3])  # largest e23
    e11, e22, e33, e23, e13, e12 = eigenstrain[i, j, k]
    assert indicator[i, j, k] == 1 and min(abs(e23), abs(e13), abs(e12)) > 0
    cell = i + n1 * (j + n2 * k)  # the documented cell numbering, x1 fastest, layers from the top
    # XX YY ZZ XY YZ XZ in the frame z = -x3: the shears with one index 3 change sign
    np.testing.assert_array_equal(volume.cell_data["eigenstrain"][cell], [e11, e22, e33, e12, -e23, -e13])
    assert volume.cell_data["inhomogeneity"][cell] == 1
    assert volume.cell_data["inhomogeneity"].sum() == np.count_nonzero(indicator)
    np.testing.assert_array_equal(volume.cell_data["stress_xx"][cell], inhomogeneous.stress(0)[i, j, k, 0])
    # a run without inhomogeneities has neither array, nor an inclusions.vtp
    _, folder = exported
    assert "eigenstrain" not in pv.read(os.path.join(folder, f"volume_{STEP:04d}.vtu")).cell_data
    assert "inhomogeneity" not in meshes.volume_mesh(result, 0).cell_data
    assert not os.path.exists(os.path.join(folder, "inclusions.vtp"))


def test_inhomogeneity_surface_encloses_the_ellipsoid(inhomogeneous, tmp_path):
    from vtkmodules.vtkFiltersCore import vtkMassProperties
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    exporter = export(inhomogeneous, tmp_path)
    path = os.path.join(tmp_path, "inclusions.vtp")
    assert path in exporter.files
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    surface = pv.wrap(reader.GetOutput())
    assert surface.is_all_triangles and surface.n_open_edges == 0
    assert json.loads(meshes.decode_text(surface.field_data["configuration"])) == inhomogeneous.configuration()
    text = _vtk_field_data(path)["configuration"]
    assert text.GetClassName() == "vtkStringArray" and text.GetValue(0) == meshes.configuration_json(inhomogeneous)
    body = inhomogeneous.inclusions[0]
    a1, a2, a3 = body.semi_axes
    exact = 4.0 / 3.0 * np.pi * a1 * a2 * a3
    mass = vtkMassProperties()
    mass.SetInputData(surface)
    mass.Update()
    # an inscribed polyhedron of 48 meridians and 24 parallels: a little smaller, by about (pi/24)^2 / 2
    assert 0.99 * exact < mass.GetVolume() < exact
    # every vertex on the ellipsoid (x - c)^T R diag(a^-2) R^T (x - c) = 1, with x3 = -z
    local = (np.asarray(surface.points) * [1, 1, -1] - body.center) @ body.orientation / body.semi_axes
    np.testing.assert_allclose(np.linalg.norm(local, axis=1), 1.0, rtol=1e-12)
    # normals point out of it
    normals = surface.compute_normals(cell_normals=True, point_normals=False, auto_orient_normals=False)
    outward = normals.cell_centers().points - np.multiply(body.center, [1, 1, -1])
    assert np.all(np.einsum("ij,ij->i", normals.cell_data["Normals"], outward) > 0)
    assert set(surface.cell_data["inhomogeneity"]) == {1} and surface.cell_data["young"][0] == 600e9


@pytest.mark.parametrize("clip", [False, pytest.param(True, marks=pytest.mark.slow)])
def test_slices_outline_the_inhomogeneities(inhomogeneous, tmp_path, clip):
    """The same slice with and without the bodies: the pixels that differ hold the black outline."""
    import copy
    import dataclasses
    plain = copy.copy(inhomogeneous)          # the same stresses without the bodies (and without their fields)
    plain.inclusions = None
    plain.records = [dataclasses.replace(record, inclusion_stress=None) for record in inhomogeneous.records]
    plain._stress_cache = (None, None)
    with_bodies = render(inhomogeneous, tmp_path / "with.png", "von_mises", 0, kind="slice", clip=clip)
    without = render(plain, tmp_path / "without.png", "von_mises", 0, kind="slice", clip=clip, clim=with_bodies.clim)
    image, _ = _colours(with_bodies.path)
    other, _ = _colours(without.path)
    changed = np.any(np.abs(image - other) > 0.1, axis=-1)
    assert changed.sum() > 500
    assert np.count_nonzero(image[changed].max(axis=-1) < 0.15) > 200   # black curve pixels
