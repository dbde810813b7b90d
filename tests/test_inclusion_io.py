"""Runs with inhomogeneities on disk: saved results and checkpoints carry the eigenstrains and the bodies."""
import numpy as np
import pytest

import framework as fw
from framework import errors, inclusions, io, materials

pytest.importorskip("h5py")


def simulation(loads=(20.0, 40.0, 60.0)):
    """A 24 x 24 x 16 grid, a tilted stiff ellipsoid under a sphere, rising loads at t = 1, 2, ... s."""
    grid = fw.Grid(shape=(24, 24), size=(1e-3, 1e-3), depth=0.5e-3, layers=16)
    body = inclusions.Ellipsoid(center=(0.0, 0.0, 0.22e-3), semi_axes=(0.15e-3, 0.13e-3, 0.13e-3),
                                material=materials.Elastic(600e9, 0.25),
                                orientation=inclusions.euler_orientation(0.3, 0.2, 0.1))
    return fw.Simulation(grid=grid, material=materials.Elastic(200e9, 0.3), indenter=fw.indenters.Sphere(radius=10e-3),
                         schedule=fw.schedules.Static(load=list(loads), times=[1.0 + k for k in range(len(loads))]),
                         inclusions=[body])


@pytest.fixture(scope="module")
def whole():
    return simulation().run()


def test_saved_result_answers_like_the_original(whole, tmp_path):
    whole.save(tmp_path / "r.h5")
    loaded = fw.load_result(tmp_path / "r.h5")
    assert loaded.configuration() == whole.configuration()
    assert loaded.inclusions == whole.inclusions   # members compared exactly, the orientation to the bit
    assert [r.couplings for r in loaded.records] == [r.couplings for r in whole.records]
    assert max(r.couplings for r in whole.records) > 1   # the coupling did iterate: the count is not a default
    points = np.array([[0.0, 0.0, 0.22e-3], [1e-4, -5e-5, 0.1e-3], [3e-4, 0.0, 0.4e-3]])
    for step in range(len(whole)):
        a, b = whole.records[step], loaded.records[step]
        assert np.array_equal(a.eigenstrain, b.eigenstrain) and np.array_equal(a.inclusion_stress, b.inclusion_stress)
        assert np.array_equal(loaded.eigenstrain(step), whole.eigenstrain(step))
        assert np.array_equal(loaded.inhomogeneity(step), whole.inhomogeneity(step))
        assert np.array_equal(loaded.stress(step), whole.stress(step))
        assert np.array_equal(loaded.stress_at(step, points), whole.stress_at(step, points))
    assert np.abs(loaded.eigenstrain(-1)).max() > 0


def test_file_layout_and_older_formats(whole, tmp_path):
    h5py = pytest.importorskip("h5py")
    whole.save(tmp_path / "r.h5")
    with h5py.File(tmp_path / "r.h5", "r") as f:
        assert f.attrs["format"] == io.FORMAT == 6
        assert f["fields/eigenstrain"].shape == (3,) + whole.records[0].eigenstrain.shape
        assert f["fields/eigenstrain"].fletcher32 and f["fields/inclusion_stress"].fletcher32
        assert list(f["series/couplings"][()]) == [r.couplings for r in whole.records]


def test_a_flipped_byte_in_the_eigenstrains_is_found(whole, tmp_path, flip_byte):
    whole.save(tmp_path / "r.h5")
    flip_byte(tmp_path / "r.h5", "fields/eigenstrain", 1)
    with pytest.raises(errors.ParameterError, match=r"dataset 'fields/eigenstrain' fails its checksum"):
        fw.load_result(tmp_path / "r.h5")


def test_resume_gives_the_uninterrupted_result(whole, tmp_path, stop_after):
    """Stopped after the first step, resumed from the checkpoint (which holds the last eigenstrains): bit-equal."""
    stop_after(simulation(), 1, tmp_path / "c.h5")
    configuration, records, state = io.read(tmp_path / "c.h5")
    assert len(records) == 1 and "inclusion_eigenstrain" in state
    assert np.array_equal(state["inclusion_eigenstrain"], whole.records[0].eigenstrain)
    resumed = simulation().run(resume=tmp_path / "c.h5")
    assert len(resumed) == len(whole)
    for a, b in zip(resumed.records, whole.records):
        assert np.array_equal(a.pressure, b.pressure) and a.approach == b.approach and a.couplings == b.couplings
        assert np.array_equal(a.eigenstrain, b.eigenstrain)


def test_resume_refuses_a_checkpoint_without_the_inhomogeneities(tmp_path):
    plain = simulation(loads=[20.0])
    plain = fw.Simulation(grid=plain.grid, material=plain.material, indenter=plain.indenter, schedule=plain.schedule)
    plain.run(checkpoint=tmp_path / "c.h5")
    with pytest.raises(errors.ParameterError, match=r"another configuration \(eigenstrain_operator, inclusions differ\)"):
        simulation(loads=[20.0]).run(resume=tmp_path / "c.h5")
    simulation(loads=[20.0]).run(checkpoint=tmp_path / "d.h5")
    with pytest.raises(errors.ParameterError, match=r"another configuration \(eigenstrain_operator, inclusions differ\)"):
        plain.run(resume=tmp_path / "d.h5")


def test_configuration_names_the_eigenstrain_operator(tmp_path):
    """A run with inhomogeneities records its operator's discretisation (a checkpoint of the collocated
    operator, without the key, is refused on resume); runs without them keep their old configuration."""
    import framework as fw
    from framework import indenters, materials, schedules
    grid = fw.Grid(shape=(32, 32), size=(1e-3, 1e-3), depth=0.5e-3, layers=16)
    plain = fw.Simulation(grid=grid, material=materials.Elastic(200e9, 0.3), indenter=indenters.Sphere(radius=5e-3),
                          schedule=schedules.Static(load=1.0))
    assert "eigenstrain_operator" not in plain.run().configuration()
    from framework import inclusions
    body = inclusions.Ellipsoid(center=(0, 0, 0.25e-3), semi_axes=(0.12e-3,) * 3, material=materials.Elastic(600e9, 0.22))
    sim = fw.Simulation(grid=grid, material=materials.Elastic(200e9, 0.3), indenter=indenters.Sphere(radius=5e-3),
                        schedule=schedules.Static(load=[0.5, 1.0]), inclusions=[body])
    result = sim.run()
    assert result.configuration()["eigenstrain_operator"] == "cell-averaged"
    path = tmp_path / "run.h5"
    result.save(path)
    assert fw.load_result(path).configuration() == result.configuration()


@pytest.mark.parametrize("geometry", ["staircase", "laminate"])
def test_a_loaded_result_finds_the_cuboids_its_fields_lie_on(geometry, tmp_path):
    """The records keep their fields on the cuboids the system solved on (laminate: the cut ones too); a loaded
    result finds them from its configuration (``inclusions.field.body_cuboids``), without the operators."""
    from framework.inclusions.field import body_cuboids, layout
    sim = simulation(loads=[30.0])
    sim = fw.Simulation(grid=sim.grid, material=sim.material, indenter=sim.indenter, schedule=sim.schedule,
                        inclusions=sim.inclusions, options={"inclusion_geometry": geometry})
    result = sim.run()
    cells = sim._inclusion_problem.problem.cells
    found = body_cuboids(result.grid, result.inclusions, layout(result.grid, result.inclusions), geometry=geometry)
    assert all(np.array_equal(a, b) for a, b in zip(found, cells))
    assert result.records[0].eigenstrain.shape == result.records[0].inclusion_stress.shape == (cells[0].size, 6)
    staircase = np.count_nonzero(sim._inclusion_problem.indicator)
    assert (cells[0].size > staircase) if geometry == "laminate" else (cells[0].size == staircase)
    result.save(tmp_path / "r.h5")
    loaded = fw.load_result(tmp_path / "r.h5")
    assert loaded._inclusion_problem is None
    assert np.array_equal(loaded.stress(0), result.stress(0))
    assert np.array_equal(loaded.eigenstrain(0), result.eigenstrain(0))
