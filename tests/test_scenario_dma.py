"""Scenario materials fitted to a DMA file: ``material = {dma = "sweeps.csv", reference, poisson, ...}``.

The reference is the pipeline called by hand on the same measured file
(pyvisco's 21 sweeps, -50 to 100 degC, ``examples/data/dma``): a scenario must
give exactly the solid ``master_curve(read_dma(path), T).fit_prony(...)``
gives, taken to ``temperature`` by the law fitted to the same curve, and its
file must lie in the scenario file's folder.
"""
import os
import re
import shutil

import numpy as np
import pytest

from framework import io, materials, scenario
from framework.errors import DataWarning, ParameterError

from cli_helpers import cli as main_in_process

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "examples", "data", "dma")
CSV = "pyvisco_freq_raw.csv"
#: [K] The temperature the instrument read for the -5 degC sweep (the mean of its points').
SWEEP = 268.3883
W = np.geomspace(1e-3, 1e3, 7)   # rad/s

#: A tiny static Hertz case: the fitted solid is ~5-7 GPa between 300 and 268 K, so 10 N on a 5 mm sphere gives a
#: contact radius of ~0.17-0.2 mm, three cells of the 16 x 16 grid of 1 mm.
SCENARIO = """
material = {{{material}}}
[grid]
shape = [16, 16]
size = [1e-3, 1e-3]
[indenter]
type = "Sphere"
radius = 5e-3
[schedule]
load = 10.0
times = [0.0, 1.0]
[output]
vtu = false
history = []
"""


def scenario_file(folder, material, data=CSV):
    """A scenario in ``folder`` with ``material = {...}`` (a TOML inline table's contents) and the DMA file copied
    to ``folder/data`` (with its licence notice)."""
    target = folder / data
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(os.path.join(DATA, CSV), target)
    shutil.copy(os.path.join(DATA, "README.md"), target.parent / "README.md")
    path = folder / "dma.toml"
    path.write_text(SCENARIO.format(material=material))
    return str(path)


@pytest.fixture(scope="module")
def pipeline():
    """``(sweeps, curve, fit)`` of the data file at the -5 degC sweep, by hand."""
    sweeps = materials.read_dma(os.path.join(DATA, CSV))
    reference = min(sweeps, key=lambda t: abs(t - SWEEP))
    assert abs(reference - SWEEP) < 1e-3
    curve = materials.master_curve(sweeps, reference)
    return sweeps, curve, curve.fit_prony(poisson=0.35)


def test_the_fitted_solid_is_the_pipeline_s(tmp_path, pipeline):
    """reference = 268.39 names the sweep read at 268.3883 K; the solid is the fit at it, to round-off."""
    _, _, fit = pipeline
    path = scenario_file(tmp_path, 'dma = "pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.35')
    material = scenario.read(path).simulation.material
    assert isinstance(material, materials.Viscoelastic)
    np.testing.assert_allclose(material.storage_modulus(1.0), fit.material.storage_modulus(1.0), rtol=1e-12)
    np.testing.assert_allclose(material.complex_modulus(W), fit.material.complex_modulus(W), rtol=1e-12)
    assert material.poisson == 0.35 and material.temperature is None and material.shift is None


def test_a_temperature_takes_the_solid_there_with_the_fitted_law(tmp_path, pipeline):
    _, curve, fit = pipeline
    expected = fit.material.at(330.0, curve.fit_shift())
    path = scenario_file(tmp_path, 'dma = "pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.35, '
                                   'temperature = 330.0')
    material = scenario.read(path).simulation.material
    assert material == expected   # terms, temperature and shift
    np.testing.assert_allclose(material.complex_modulus(W), expected.complex_modulus(W), rtol=1e-12)
    assert material.temperature == 330.0 and material.shift.reference == curve.reference


def test_a_given_shift_shifts_the_sweeps_and_goes_with_the_solid(tmp_path, pipeline):
    """With a known law whose reference is not the scenario's, the solid at the reference is still the fit there."""
    sweeps, _, _ = pipeline
    law = materials.WLF(c1=18.0, c2=104.0, reference=290.0)
    fit = materials.master_curve(sweeps, 270.0, shift=law).fit_prony(poisson=0.35)
    shift = 'shift = {type = "WLF", c1 = 18.0, c2 = 104.0, reference = 290.0}'
    path = scenario_file(tmp_path, f'dma = "pyvisco_freq_raw.csv", reference = 270.0, poisson = 0.35, {shift}')
    material = scenario.read(path).simulation.material
    assert material.temperature == 270.0 and material.shift == law
    np.testing.assert_allclose(material.complex_modulus(W), fit.material.complex_modulus(W), rtol=1e-12)
    path = scenario_file(tmp_path, f'dma = "pyvisco_freq_raw.csv", reference = 270.0, poisson = 0.35, {shift}, '
                                   f'temperature = 280.0')
    warm = scenario.read(path).simulation.material
    factor = law.factor(280.0) / law.factor(270.0)
    np.testing.assert_allclose(warm.complex_modulus(W / factor), fit.material.complex_modulus(W), rtol=1e-12)


def test_a_path_in_a_subfolder(tmp_path, pipeline):
    _, _, fit = pipeline
    path = scenario_file(tmp_path, 'dma = "data/dma/pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.35, '
                                   'terms = 6', data=f"data/dma/{CSV}")
    material = scenario.read(path).simulation.material
    assert len(material.terms) <= 6   # terms whose modulus came out zero are dropped


def test_a_single_sweep_is_its_own_reference(tmp_path):
    """A file of one sweep needs no reference; it has no shift factors, so a temperature needs a shift."""
    lines = open(os.path.join(DATA, CSV), encoding="utf-8-sig").read().splitlines()
    one = [line for line in lines[2:] if line.endswith(",8")]
    assert len(one) == 10
    (tmp_path / "one.csv").write_text("\n".join(lines[:2] + one) + "\n")
    shutil.copy(os.path.join(DATA, "README.md"), tmp_path / "README.md")
    path = tmp_path / "one.toml"
    path.write_text(SCENARIO.format(material='dma = "one.csv", poisson = 0.35'))
    sweeps = materials.read_dma(tmp_path / "one.csv")
    expected = materials.master_curve(sweeps, *sweeps).fit_prony(poisson=0.35).material
    material = scenario.read(str(path)).simulation.material
    np.testing.assert_allclose(material.complex_modulus(W), expected.complex_modulus(W), rtol=1e-12)
    path.write_text(SCENARIO.format(material='dma = "one.csv", poisson = 0.35, temperature = 300.0'))
    with pytest.raises(scenario.ScenarioError, match=r"material.temperature: one sweep gives no shift factors"):
        scenario.read(str(path))


def test_a_master_curve_file_is_read_at_its_reference(tmp_path):
    """A file without a temperature column is one curve at ``reference``, which it cannot do without."""
    lines = open(os.path.join(DATA, CSV), encoding="utf-8-sig").read().splitlines()
    rows = [",".join(line.split(",")[:3]) for line in lines if line.endswith(",8")]
    (tmp_path / "master.csv").write_text("f,E_stor,E_loss\nHz,MPa,MPa\n" + "\n".join(rows) + "\n")
    shutil.copy(os.path.join(DATA, "README.md"), tmp_path / "README.md")
    path = tmp_path / "master.toml"
    path.write_text(SCENARIO.format(material='dma = "master.csv", poisson = 0.35, reference = 273.15'))
    sweeps = materials.read_dma(tmp_path / "master.csv", temperature=273.15)
    expected = materials.master_curve(sweeps, 273.15).fit_prony(poisson=0.35).material
    material = scenario.read(str(path)).simulation.material
    np.testing.assert_allclose(material.complex_modulus(W), expected.complex_modulus(W), rtol=1e-12)
    path.write_text(SCENARIO.format(material='dma = "master.csv", poisson = 0.35'))
    refused(str(path), r"material: missing required key 'reference' with dma: '.*master.csv' is a master curve "
                       r"\(no temperature column\); expected reference = its temperature \[K\]")


def test_dropped_points_reach_the_user(tmp_path):
    path = scenario_file(tmp_path, 'dma = "pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.35')
    data = tmp_path / CSV
    lines = data.read_text(encoding="utf-8-sig").splitlines()
    lines[2] = lines[2].replace("8097.175545", "-1.0")   # a negative storage modulus: dropped
    data.write_text("\n".join(lines) + "\n")
    with pytest.warns(DataWarning, match=r"1 of 210 points of measured data were dropped: line 3"):
        scenario.read(path)


def refused(path, message):
    """``scenario.read`` raises a ScenarioError from a ParameterError, its message matching ``message``."""
    with pytest.raises(scenario.ScenarioError, match=message) as caught:
        scenario.read(path)
    assert isinstance(caught.value.__cause__, ParameterError)
    return str(caught.value)


@pytest.mark.parametrize("material, message", [
    (f'dma = "{os.path.join(DATA, CSV)}", reference = 268.39, poisson = 0.35',
     r"material.dma: expected a DMA file relative to the scenario file's folder '.*', got the absolute path '/"),
    ('dma = "missing.csv", reference = 268.39, poisson = 0.35',
     r"material.dma: expected a DMA file in the scenario file's folder '.*', got 'missing.csv': no such file"),
    ('dma = "data", reference = 268.39, poisson = 0.35', r"material.dma: .*got 'data': a folder"),
    ('dma = "", reference = 268.39, poisson = 0.35',
     r"material.dma: expected a DMA file relative to the scenario file's folder, got ''"),
    ('dma = 3, reference = 268.39, poisson = 0.35',
     r"material.dma: expected a DMA file relative to the scenario file's folder, got 3"),
    ('dma = "sweeps\\t.csv", reference = 268.39, poisson = 0.35',
     r"material.dma: 'sweeps\\t.csv' holds the control character '\\t' at position 6"),
    ('dma = "pyvisco_freq_raw.csv", reference = 273.4, poisson = 0.35',
     r"material.reference: expected one of the sweeps' temperatures \[223.24, .*268.39, .*373.14\] K \(within "
     r"0.5 K\), whose shift factors are fitted, got 273.4"),
    ('dma = "pyvisco_freq_raw.csv", poisson = 0.35',
     r"material: missing required key 'reference' with dma: the file holds 21 sweeps"),
    ('dma = "pyvisco_freq_raw.csv", reference = 268.39',
     r"material: missing required key 'poisson' with dma; expected the Poisson ratio"),
    ('dma = "pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.35, young = 1e9',
     r"material: unknown key\(s\) \['young'\] with dma; expected some of \['dma', 'reference', 'poisson', "
     r"'temperature', 'terms', 'modulus', 'shift'\]"),
    ('dma = "pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.7',
     r"material: poisson must lie in \(-1, 0.5\], got 0.7"),
    ('dma = "pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.35, terms = 0',
     r"material.terms must be an integer >= 1, got 0"),
    ('dma = "pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.35, modulus = "bulk"',
     r"material: modulus must be 'tensile' or 'shear', got 'bulk'"),
    ('dma = "pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.35, shift = 3.0',
     r"material.shift: expected a WLF or Arrhenius table .*got 3.0"),
    ('dma = "pyvisco_freq_raw.csv", reference = "cold", poisson = 0.35',
     r"material.reference must be a finite real number, got 'cold'"),
])
def test_bad_dma_materials_are_named(tmp_path, material, message):
    (tmp_path / "data").mkdir()
    refused(scenario_file(tmp_path, material), message)


def test_paths_out_of_the_scenario_folder_are_refused(tmp_path):
    """``..`` and links are followed first: a file outside the folder is refused even where it exists."""
    inside = tmp_path / "scenario"
    inside.mkdir()
    shutil.copy(os.path.join(DATA, CSV), tmp_path / CSV)   # a real file, one level up
    path = scenario_file(inside, f'dma = "../{CSV}", reference = 268.39, poisson = 0.35')
    refused(path, rf"material.dma: expected a DMA file inside the scenario file's folder '.*scenario', got "
                  rf"'../{CSV}', which leads to '.*{CSV}'")
    path = scenario_file(inside, f'dma = "sub/../../{CSV}", reference = 268.39, poisson = 0.35')
    refused(path, r"material.dma: expected a DMA file inside the scenario file's folder")
    os.symlink(tmp_path / CSV, inside / "link.csv")
    path = scenario_file(inside, 'dma = "link.csv", reference = 268.39, poisson = 0.35')
    message = refused(path, r"material.dma: expected a DMA file inside the scenario file's folder .*got 'link.csv'")
    assert re.search(rf"which leads to '{re.escape(str((tmp_path / CSV).resolve()))}'", message)
    os.symlink(inside / CSV, inside / "inner.csv")   # a link inside the folder is followed
    path = scenario_file(inside, 'dma = "inner.csv", reference = 268.39, poisson = 0.35, terms = 4')
    assert isinstance(scenario.read(path).simulation.material, materials.Viscoelastic)


def test_a_loop_of_links_is_named(tmp_path):
    os.symlink(tmp_path / "b", tmp_path / "a")
    os.symlink(tmp_path / "a", tmp_path / "b")
    refused(scenario_file(tmp_path, 'dma = "a/x.csv", reference = 268.39, poisson = 0.35'),
            r"^.*material.dma: cannot follow 'a/x.csv' from '.*': .*[Ll]oop")


def test_tables_from_no_file_cannot_name_one(tmp_path):
    data = scenario.tomllib.loads(SCENARIO.format(material='dma = "pyvisco_freq_raw.csv", poisson = 0.35'))
    with pytest.raises(scenario.ScenarioError, match=r"material.dma: a DMA file is found relative to the scenario "
                                                     r"file's folder, and these tables come from no file"):
        scenario.parse(data)




def test_check_and_run_a_dma_scenario(capsys, tmp_path):
    """A static Hertz contact on the fitted solid; the result records the fitted solid and reads back the same."""
    path = scenario_file(tmp_path, 'dma = "pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.35, '
                                   'temperature = 300.0')
    code, out, err = main_in_process(capsys, "check", path)
    assert code == 0 and "ok (2 steps on a (16, 16) grid)" in out, err
    out_folder = tmp_path / "out"
    code, out, err = main_in_process(capsys, "run", path, "--out", str(out_folder), "--quiet")
    assert code == 0, err
    result = io.load_result(out_folder / "result.h5")
    material = scenario.read(path).simulation.material
    assert result.material == material and result.material.temperature == 300.0
    assert result.configuration()["material"]["type"] == "Viscoelastic"
    radius = result.contact_radius
    assert 2 * 1e-3 / 16 < radius[0] <= radius[1] < 0.4e-3   # a contact a few cells wide, creeping


def test_a_sweep_varies_the_temperature_of_a_dma_material(tmp_path, pipeline):
    """A sweep over ``material.temperature`` of a DMA scenario: each point is the fitted solid at that temperature
    (the file read from the scenario's folder by every point)."""
    from framework.sweep import expand, read_sweep
    _, curve, fit = pipeline
    path = scenario_file(tmp_path, 'dma = "pyvisco_freq_raw.csv", reference = 268.39, poisson = 0.35, '
                                   'temperature = 300.0')
    (tmp_path / "sweep.toml").write_text(f'scenario = "{os.path.basename(path)}"\n[parameters]\n'
                                         '"material.temperature" = [300.0, 330.0]\n')
    builder, parameters, _ = read_sweep(tmp_path / "sweep.toml")
    law = curve.fit_shift()
    for point in expand(parameters):
        material = builder(**point).material
        expected = fit.material.at(point["material.temperature"], law)
        assert material.storage_modulus(W) == pytest.approx(expected.storage_modulus(W), rel=1e-12)
