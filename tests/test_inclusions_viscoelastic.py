"""Inhomogeneities in a viscoelastic matrix (THEORY.md sec. 8): the matrix's memory at the inhomogeneities."""
import numpy as np
import pytest

import framework as fw
from framework import inclusions, indenters, loads, materials, schedules

NU = 0.3
GLASSY, RELAXED, TAU = 200e9, 100e9, 1.0
CARBIDE = materials.Elastic(600e9, 0.22)


def run(matrix, times, history="recursive", body=CARBIDE, load=loads.Step(40.0)):
    """A rigid ball (R = 10 mm) held on the matrix over a sphere (r = 0.06 mm, centre 0.12 mm deep)."""
    grid = fw.Grid(shape=(40, 40), size=(0.8e-3, 0.8e-3), depth=0.4e-3, layers=20)
    bodies = [inclusions.Ellipsoid(center=(0.0, 0.0, 0.12e-3), semi_axes=(0.06e-3,) * 3, material=body)]
    simulation = fw.Simulation(grid=grid, material=matrix, indenter=indenters.Sphere(radius=10e-3),
                               schedule=schedules.Static(load=load, times=times), inclusions=bodies,
                               options={"tolerance": 1e-10, "history": history})
    return simulation.run()


SOLID = materials.StandardLinearSolid(e_inf=RELAXED, e_1=GLASSY - RELAXED, tau=TAU, poisson=NU)


def test_constant_modulus_matrix_reproduces_the_elastic_result():
    elastic = run(materials.Elastic(GLASSY, NU), times=[1.0])
    constant = run(materials.Viscoelastic.from_prony(e_inf=GLASSY, terms=[], poisson=NU), times=[1.0])
    assert np.abs(constant.pressure(-1) - elastic.pressure(-1)).max() <= 1e-10 * elastic.max_pressure[-1]
    assert np.abs(constant.eigenstrain(-1) - elastic.eigenstrain(-1)).max() <= 1e-9 * np.abs(elastic.eigenstrain(-1)).max()
    assert np.abs(constant.stress(-1) - elastic.stress(-1)).max() <= 1e-9 * np.abs(elastic.stress(-1)).max()


@pytest.mark.slow
def test_held_load_goes_from_the_glassy_to_the_relaxed_elastic_solution():
    """At t = 0 the glassy matrix answers; after 30 relaxation times the relaxed one (same inhomogeneity).

    20 geometric steps: the pressure is taken linear within a step, which one step over 30 tau
    would get 2 % wrong at the centre (the homogeneous half-space alike).
    """
    held = run(SOLID, times=np.concatenate([[0.0], np.geomspace(0.01, 30, 20)]) * TAU)
    for step, modulus in ((0, GLASSY), (-1, RELAXED)):
        elastic = run(materials.Elastic(modulus, NU), times=[1.0])
        scale = elastic.max_pressure[-1]
        assert np.abs(held.pressure(step) - elastic.pressure(-1)).max() <= 0.01 * scale, (step, modulus)
        assert held.approach[step] == pytest.approx(elastic.approach[-1], rel=0.01)
        inside = held.inhomogeneity(step) > 0
        assert np.abs(held.stress(step)[inside] - elastic.stress(-1)[inside]).max() \
            <= 0.01 * np.abs(elastic.stress(-1)[inside]).max()
    # the contrast grows from 3 to 6 as the matrix relaxes: the sphere raises the peak pressure more
    grid = fw.Grid(shape=(40, 40), size=(0.8e-3, 0.8e-3), depth=0.4e-3, layers=20)
    plain = fw.Simulation(grid=grid, material=SOLID, indenter=indenters.Sphere(radius=10e-3),
                          schedule=schedules.Static(load=loads.Step(40.0), times=held.times)).run()
    raised = held.max_pressure / plain.max_pressure
    assert raised[-1] > raised[0] > 1


@pytest.mark.slow
def test_recursive_and_hereditary_histories_agree():
    ramp = loads.Ramp(end=40.0, duration=TAU)
    times = np.linspace(0.25, 3.0, 6) * TAU
    recursive = run(SOLID, times=times, load=ramp)
    hereditary = run(SOLID, times=times, load=ramp, history="hereditary")
    for step in range(len(times)):
        assert np.abs(recursive.pressure(step) - hereditary.pressure(step)).max() \
            <= 1e-7 * recursive.max_pressure[step]
        assert np.abs(recursive.eigenstrain(step) - hereditary.eigenstrain(step)).max() \
            <= 1e-7 * np.abs(recursive.eigenstrain(step)).max()


def held_carbide():
    """A carbide sphere under a held load on the standard linear solid, four output times."""
    grid = fw.Grid(shape=(32, 32), size=(0.8e-3, 0.8e-3), depth=0.4e-3, layers=16)
    bodies = [inclusions.Ellipsoid(center=(0.0, 0.0, 0.12e-3), semi_axes=(0.08e-3,) * 3, material=CARBIDE)]
    return fw.Simulation(grid=grid, material=SOLID, indenter=indenters.Sphere(radius=10e-3),
                         schedule=schedules.Static(load=loads.Step(40.0), times=[0.1, 0.5, 1.0, 2.0]),
                         inclusions=bodies)


def test_resume_carries_the_matrix_memory(tmp_path, stop_after):
    """A viscoelastic run stopped after two steps and resumed from its checkpoint equals the whole run."""
    simulation = held_carbide
    whole = simulation().run()

    stop_after(simulation(), 1, tmp_path / "c.h5")
    resumed = simulation().run(resume=tmp_path / "c.h5")
    for a, b in zip(resumed.records, whole.records):
        assert np.array_equal(a.pressure, b.pressure) and np.array_equal(a.eigenstrain, b.eigenstrain)
        assert np.array_equal(a.inclusion_stress, b.inclusion_stress)
        assert np.array_equal(a.relaxed_eigenstrain, b.relaxed_eigenstrain)    # e~'s recursion resumed too


def test_resume_from_a_checkpoint_without_the_weighted_eigenstrain(tmp_path, stop_after, monkeypatch):
    """A checkpoint written before the run carried e~ (no ``inclusion_weighted_*`` arrays) resumes with the same
    pressures and eigenstrains; its later records carry no e~, and ``Result.stress`` replays it from the records."""
    from framework.inclusions.coupling import ContactCoupling
    grid = fw.Grid(shape=(32, 32), size=(0.8e-3, 0.8e-3), depth=0.4e-3, layers=16)
    bodies = [inclusions.Ellipsoid(center=(0.0, 0.0, 0.12e-3), semi_axes=(0.08e-3,) * 3, material=CARBIDE)]

    def simulation():
        return fw.Simulation(grid=grid, material=SOLID, indenter=indenters.Sphere(radius=10e-3),
                             schedule=schedules.Static(load=loads.Step(40.0), times=[0.0, 0.5, 1.0]),
                             inclusions=bodies, options=fw.Options(time_tolerance=None))   # every step recorded

    whole = simulation().run()
    snapshot = ContactCoupling.snapshot
    monkeypatch.setattr(ContactCoupling, "snapshot", lambda self: {
        key: value for key, value in snapshot(self).items() if not key.startswith("inclusion_weighted_")})
    stop_after(simulation(), 1, tmp_path / "c.h5")
    monkeypatch.undo()
    resumed = simulation().run(resume=tmp_path / "c.h5")
    assert resumed.records[0].relaxed_eigenstrain is not None and resumed.records[-1].relaxed_eigenstrain is None
    for a, b in zip(resumed.records, whole.records):
        assert np.array_equal(a.pressure, b.pressure) and np.array_equal(a.eigenstrain, b.eigenstrain)
    # every step recorded: the replay is the carried e~ to rounding
    assert np.abs(resumed.stress(-1) - whole.stress(-1)).max() <= 1e-9 * np.abs(whole.stress(-1)).max()


def test_stress_at_points_is_refused_with_a_viscoelastic_matrix():
    held = run(SOLID, times=[0.5])
    with pytest.raises(fw.errors.ParameterError, match="stress_at: with inhomogeneities in a viscoelastic matrix"):
        held.stress_at(0, np.array([[0.0, 0.0, 0.1e-3]]))


def test_resume_from_a_checkpoint_with_the_histories_on_the_whole_box(tmp_path, stop_after, monkeypatch):
    """A checkpoint written when the histories (the contact strain's, e~'s, the matrix stress's) and the last
    eigenstrain lived on the whole box (any values outside the bodies) resumes on the bodies' cuboids: the same run
    bit for bit."""
    from framework.inclusions.coupling import ContactCoupling
    simulation = held_carbide
    whole = simulation().run()
    snapshot = ContactCoupling.snapshot

    def on_the_box(self):       # the cuboids' arrays written as box fields, as the earlier version did
        out = snapshot(self)
        inner = self.problem.problem
        for key, value in out.items():
            if key.startswith(("inclusion_creep_", "inclusion_weighted_", "inclusion_relaxation_",
                               "inclusion_eigenstrain")) and np.ndim(value) >= 2 \
                    and np.shape(value)[-2:] == (inner.material.size, 6):
                box = np.random.default_rng(1).normal(size=(*np.shape(value)[:-2], *self.problem.shape, 6))
                box[(slice(None),) * (np.ndim(value) - 2) + inner.cells] = value
                out[key] = box
        return out
    monkeypatch.setattr(ContactCoupling, "snapshot", on_the_box)
    stop_after(simulation(), 1, tmp_path / "c.h5")
    monkeypatch.undo()
    resumed = simulation().run(resume=tmp_path / "c.h5")
    for a, b in zip(resumed.records, whole.records):
        assert np.array_equal(a.pressure, b.pressure) and np.array_equal(a.eigenstrain, b.eigenstrain)
        assert np.array_equal(a.relaxed_eigenstrain, b.relaxed_eigenstrain)
