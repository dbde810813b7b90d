"""materials.read_dma: DMA sweeps from pyvisco CSV, plain CSV and TRIOS text files.

The reference is pyvisco's raw example file (examples/data/dma), read here
with the csv module alone; every other file is written by the tests from it,
in another format or other units, and must give the same sweeps. The TRIOS
files are synthetic, after the structure TRIOS writes (header lines, then per
step ``[step]``, its name, the variables, the units and the data).
"""
import csv
import math
import os
import pickle
import re
import warnings

import numpy as np
import pytest

from framework import materials
from framework.errors import DataWarning, ParameterError
from framework.materials import DMASweeps, read_dma

DMA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "examples", "data", "dma")
RAW = os.path.join(DMA, "pyvisco_freq_raw.csv")
MASTER = os.path.join(DMA, "pyvisco_freq_master.csv")


def raw_rows():
    """``[(f [Hz], E' [MPa], E'' [MPa], T [degC], set), ...]`` of the pyvisco raw file, as written."""
    with open(RAW, encoding="utf-8-sig") as f:
        rows = list(csv.reader(f))
    assert [cell.strip() for cell in rows[0]] == ["f", "E_stor", "E_loss", "T", "Set"]
    return [tuple(float(cell) for cell in row) for row in rows[2:]]


def write(path, lines):
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def assert_same(sweeps, reference, rel=1e-12):
    assert len(sweeps) == len(reference)
    for (t, (w, modulus)), (t_ref, (w_ref, modulus_ref)) in zip(sweeps.items(), reference.items()):
        assert t == pytest.approx(t_ref, rel=rel)
        np.testing.assert_allclose(w, w_ref, rtol=rel, atol=0)
        np.testing.assert_allclose(modulus, modulus_ref, rtol=rel, atol=0)


# --------------------------------------------------------------------------- pyvisco files

def test_pyvisco_raw_file_reads_21_sweeps_in_si_units():
    sweeps = read_dma(RAW)
    assert isinstance(sweeps, dict) and isinstance(sweeps, DMASweeps)
    assert (sweeps.path, sweeps.format, sweeps.modulus, sweeps.converted, sweeps.poisson, sweeps.dropped,
            sweeps.master) == (RAW, "pyvisco", "tensile", None, None, (), False)
    assert len(sweeps) == 21 and sum(w.size for w, _ in sweeps.values()) == 210
    temperatures = list(sweeps)
    assert temperatures == sorted(temperatures)
    assert -50.1 + 273.15 < temperatures[0] < -49.9 + 273.15 and 99.9 + 273.15 < temperatures[-1] < 100.1 + 273.15
    for w, modulus in sweeps.values():
        assert np.all(np.diff(w) > 0) and np.iscomplexobj(modulus) and w.size == 10
    # first row "0.1,8097.175545,93.07449045,-49.9612,0", last row "100,585.8391184,223.41197,100.001,20"
    w, modulus = sweeps[temperatures[0]]
    assert w[0] == pytest.approx(2 * math.pi * 0.1, rel=1e-15)
    assert modulus[0] == pytest.approx(8097.175545e6 + 93.07449045e6j, rel=1e-15)
    w, modulus = sweeps[temperatures[-1]]
    assert w[-1] == pytest.approx(2 * math.pi * 100, rel=1e-15)
    assert modulus[-1] == pytest.approx(585.8391184e6 + 223.41197e6j, rel=1e-15)
    # a sweep's temperature: the mean of its points', in kelvin
    rows = raw_rows()
    assert temperatures[0] == pytest.approx(np.mean([r[3] for r in rows if r[4] == 0]) + 273.15, rel=1e-14)


def test_pyvisco_master_file_needs_its_reference_temperature():
    with pytest.raises(ParameterError, match=r"pyvisco_freq_master\.csv: temperature .* got temperature=None"):
        read_dma(MASTER)
    sweeps = read_dma(MASTER, temperature=268.15)
    assert sweeps.master and sweeps.format == "pyvisco" and list(sweeps) == [268.15]
    w, modulus = sweeps[268.15]
    assert w.size == 206 and w[0] == pytest.approx(2 * math.pi * 1e-12, rel=1e-15)
    assert modulus[0] == pytest.approx(88.79651575665739e6 + 10.502460140936773e6j, rel=1e-15)
    with pytest.raises(ParameterError, match=r"temperature .* refused .* got temperature=300"):
        read_dma(RAW, temperature=300.0)


def test_pyvisco_shear_file_is_converted_with_poisson(tmp_path):
    """G_stor, G_loss in kPa, omega in rad/s, T in K: E* = 2 (1 + nu) G*."""
    rows = raw_rows()
    lines = ["\ufeffomega,G_stor,G_loss,T,Set,tan_del", "rad/s, kPa, kPa, K, -, -"]
    lines += [f"{2 * math.pi * f!r},{e * 1e3 / 3!r},{l * 1e3 / 3!r},{t + 273.15!r},{s:g},{l / e!r}"
              for f, e, l, t, s in rows]
    path = write(tmp_path / "shear.csv", lines)
    with pytest.raises(ParameterError, match=r"shear\.csv: .* need poisson .* got poisson=None"):
        read_dma(path)
    sweeps = read_dma(path, poisson=0.5)
    assert sweeps.modulus == "shear" and sweeps.poisson == 0.5 and sweeps.format == "pyvisco"
    assert sweeps.converted == "shear moduli G converted to tensile with E* = 2 (1 + nu) G*, nu = 0.5"
    assert_same(sweeps, read_dma(RAW))      # G = E/3 with nu = 1/2
    g = read_dma(path, poisson=0.35)
    for (w, e), (_, e_half) in zip(g.values(), sweeps.values()):
        np.testing.assert_allclose(e, e_half * 2 * 1.35 / 3, rtol=1e-14)


# --------------------------------------------------------------------------- plain CSV

CELSIUS = {"degC": lambda t: t, "°C": lambda t: t, "K": lambda t: t + 273.15, "F": lambda t: t * 9 / 5 + 32}
PASCALS = {"MPa": 1.0, "GPa": 1e-3, "kPa": 1e3, "Pa": 1e6}


@pytest.mark.parametrize("units_in", ["row", "brackets", "parentheses"])
@pytest.mark.parametrize("pressure, temperature, delimiter, storage, loss, modulus", [
    ("MPa", "degC", ",", "E'", "E''", None), ("GPa", "K", ";", "storage modulus", "loss modulus", "tensile"),
    ("kPa", "F", "\t", "Tensile storage modulus", "tensile loss modulus", None), ("Pa", "°C", ",", "E'", "E\"", None)])
def test_plain_csv_with_units_gives_the_pyvisco_sweeps(tmp_path, units_in, pressure, temperature, delimiter, storage,
                                                       loss, modulus):
    """Names E', E'' say tensile; "storage modulus" alone needs modulus="tensile"."""
    names = ["frequency", storage, loss, "temperature", "step"]
    units = ["Hz", pressure, pressure, temperature, ""]
    scale, kelvin = PASCALS[pressure], CELSIUS[temperature]
    lines = ["# written by the test from pyvisco_freq_raw.csv", "# a comment line"]
    if units_in == "row":
        lines += [delimiter.join(names), delimiter.join(units)]
    else:
        brackets = "[{}]" if units_in == "brackets" else "({})"
        lines += [delimiter.join(f"{n} {brackets.format(u)}" if u else n for n, u in zip(names, units))]
    lines += [delimiter.join([repr(f), repr(e * scale), repr(l * scale), repr(kelvin(t)), f"{s:g}"])
              for f, e, l, t, s in raw_rows()]
    sweeps = read_dma(write(tmp_path / "plain.csv", lines), modulus=modulus)
    assert sweeps.format == "csv" and sweeps.modulus == "tensile"
    assert_same(sweeps, read_dma(RAW))


def test_plain_csv_without_set_column_groups_by_temperature_and_takes_tan_delta(tmp_path):
    """No step column: points within 0.5 K form a sweep; E'' = E' tan delta; omega [rad/s]; E' names say tensile."""
    lines = ["omega [rad/s],E' [MPa],tan delta,T [C]"]
    lines += [f"{2 * math.pi * f!r},{e!r},{l / e!r},{t!r}" for f, e, l, t, _ in raw_rows()]
    sweeps = read_dma(write(tmp_path / "tan.csv", lines))
    assert_same(sweeps, read_dma(RAW), rel=1e-13)


def test_single_temperature_reads_as_one_sweep(tmp_path):
    lines = ["f [Hz],E' [MPa],E'' [MPa],T [degC]"] + [f"{f},{100 * f + 1000},{10 + f},25.0" for f in (1, 2, 5, 10)]
    sweeps = read_dma(write(tmp_path / "one.csv", lines))
    assert list(sweeps) == [298.15] and not sweeps.master
    np.testing.assert_allclose(sweeps[298.15][1].real, [1.1e9, 1.2e9, 1.5e9, 2.0e9], rtol=1e-15)


# --------------------------------------------------------------------------- TRIOS

def trios(path, header, steps, variables="Angular frequency\tStorage modulus\tLoss modulus\tTan(delta)\tTemperature"
          "\tStep time", units="rad/s\tPa\tPa\t\t°C\ts"):
    """A TRIOS text export: ``header`` lines, then one block per ``(name, rows)`` of ``steps``."""
    lines = ["Filename\ttest", *header]
    for name, rows in steps:
        lines += ["", "[step]", name, variables, units]
        lines += ["\t".join(repr(value) for value in row) for row in rows]
    return write(path, lines)


def steps_of(rows):
    """The pyvisco sweeps as TRIOS steps ``(name, rows)``; a row: w [rad/s], E', E'' [Pa], tan d, T [°C], time [s]."""
    steps = {}
    for f, e, l, t, s in rows:
        steps.setdefault(s, []).append((2 * math.pi * f, e * 1e6, l * 1e6, l / e, t, 10.0 * len(steps.get(s, []))))
    return [(f"Frequency sweep ({round(step[0][4]):.1f} °C)", step) for step in steps.values()]


def test_trios_tensile_by_column_name(tmp_path):
    path = trios(tmp_path / "rsa.txt", ["Instrument type\tunknown"], steps_of(raw_rows()),
                 variables="Angular frequency\tE'\tE''\tTan(delta)\tTemperature\tStep time")
    sweeps = read_dma(path)
    assert sweeps.format == "trios" and sweeps.modulus == "tensile"
    assert_same(sweeps, read_dma(RAW))


@pytest.mark.parametrize("encoding", ["utf-8", "utf-16", "cp1252"])
def test_trios_encodings_and_agreeing_frequency_columns(tmp_path, encoding):
    """TRIOS may add "Frequency" [Hz] beside "Angular frequency": read, checked to agree, the first kept."""
    steps = [(name, [(w / (2 * math.pi), round(w, 4), *rest) for w, *rest in rows])
             for name, rows in steps_of(raw_rows())]
    path = trios(tmp_path / "both.txt", ["Instrument type\tDMA 850", "Geometry name\tTension film"], steps,
                 variables="Frequency\tAngular frequency\tStorage modulus\tLoss modulus\tTan(delta)\tTemperature"
                 "\tStep time", units="Hz\trad/s\tPa\tPa\t\t°C\ts")
    path.write_text(path.read_text(encoding="utf-8"), encoding=encoding)
    sweeps = read_dma(path)
    assert sweeps.modulus == "tensile" and sweeps.format == "trios"
    assert_same(sweeps, read_dma(RAW))


def test_trios_shear_by_geometry_header(tmp_path):
    steps = [(name, [(w, e / 3, l / 3, d, t, s) for w, e, l, d, t, s in rows]) for name, rows in steps_of(raw_rows())]
    path = trios(tmp_path / "dhr.txt", ["Instrument type\tDHR-3", "Geometry name\t8 mm parallel plate"], steps)
    sweeps = read_dma(path, poisson=0.5)
    assert sweeps.modulus == "shear" and sweeps.converted.endswith("nu = 0.5")
    assert_same(sweeps, read_dma(RAW))
    with pytest.raises(ParameterError, match=r"dhr\.txt: .*shear moduli .* need poisson"):
        read_dma(path)


def test_trios_without_temperature_column_takes_the_step_name(tmp_path):
    steps = [(f"Frequency sweep ({t:.1f} °C)", [(w, 1e9 + w, 1e8, 0.1) for w in (1.0, 10.0, 100.0)])
             for t in (20.0, 40.0)]
    path = trios(tmp_path / "names.txt", ["Instrument type\tRSA-G2"], steps,
                 variables="Angular frequency\tStorage modulus\tLoss modulus\tTan(delta)", units="rad/s\tPa\tPa\t")
    sweeps = read_dma(path)
    assert list(sweeps) == [293.15, 313.15] and sweeps.modulus == "tensile"


def test_trios_ambiguous_instrument_needs_modulus(tmp_path):
    path = trios(tmp_path / "which.txt", ["Instrument type\tSomething", "Geometry name\tFixture 1"],
                 steps_of(raw_rows()))
    with pytest.raises(ParameterError, match=r"which\.txt: cannot tell whether .* modulus='tensile' or "
                                             r"modulus='shear'"):
        read_dma(path)
    assert_same(read_dma(path, modulus="tensile"), read_dma(RAW))
    shear = read_dma(path, poisson=0.4, modulus="shear")
    assert shear.modulus == "shear"
    for (_, e_shear), (_, e) in zip(shear.values(), read_dma(RAW).values()):
        np.testing.assert_allclose(e_shear, 2.8 * e, rtol=1e-14)


# --------------------------------------------------------------------------- unusable points

def test_bad_points_are_dropped_with_one_warning(tmp_path):
    lines = ["f,E',E'',T,Set", "Hz,MPa,MPa,degC,-"] + [f"{f!r},{e!r},{l!r},{t!r},{s:g}" for f, e, l, t, s in
                                                         raw_rows()]
    lines[3] = "0.215443,8576.843825,-118.1934952,-49.9617,0"     # line 4: negative E''
    lines[14] = "0.215443,7000,140000,-42.5,1"                    # line 15: tan delta 20
    path = write(tmp_path / "bad.csv", lines)
    with pytest.warns(DataWarning) as record:
        sweeps = read_dma(path)
    assert len(record) == 1
    message = str(record[0].message)
    assert message.startswith(f"{path}: 2 of 210 points of measured data were dropped")
    assert "line 4: loss modulus -1.18193e+08 Pa is not positive" in message
    assert "line 15: loss factor E''/E' = 20 exceeds 10" in message
    assert sweeps.dropped == (("line 4", "loss modulus -1.18193e+08 Pa is not positive"),
                              ("line 15", "loss factor E''/E' = 20 exceeds 10"))
    assert sum(w.size for w, _ in sweeps.values()) == 208


def test_repeated_frequency_and_short_sweep_are_dropped(tmp_path):
    lines = ["f [Hz],E' [MPa],E'' [MPa],T [K]", "1,1000,100,300", "2,1100,110,300", "1,999,99,300",
             "", "1,900,90,320", "2,,95,320", "5,950,nan,320"]
    path = write(tmp_path / "short.csv", lines)
    with pytest.warns(DataWarning, match=r"4 of 6 points") as record:
        sweeps = read_dma(path)
    assert len(record) == 1 and list(sweeps) == [300.0]
    assert sweeps.dropped == (("line 4", "frequency 6.28319 rad/s repeats line 2 in its sweep"),
                              ("line 6", "its sweep at 320.00 K kept 1 point, fewer than the 2 a sweep needs"),
                              ("line 7", "storage modulus missing or not finite (nan)"),
                              ("line 8", "loss modulus missing or not finite (nan)"))


# --------------------------------------------------------------------------- bad files

BAD = {
    "no column": (["time [s],force [N]", "1,2"], r"no frequency, storage, loss \(or tan delta\) column among "
                                                  r"\['time \[s\]', 'force \[N\]'\]"),
    "no loss": (["f [Hz],E' [MPa],T [K]", "1,2,300"], r"no loss \(or tan delta\) column"),
    "unknown unit": (["f [Hz],E' [bar],E'' [MPa],T [K]", "1,2,3,300"],
                     r"column \"E' \[bar\]\" \(storage\) has unit 'bar'; expected one of Pa, kPa, MPa, GPa, psi"),
    "1/s": (["f [1/s],E' [MPa],E'' [MPa],T [K]", "1,2,3,300"], r"unit '1/s' \(ambiguous: .*expected one of Hz, rad/s"),
    "omega in Hz": (["omega [Hz],E' [MPa],E'' [MPa],T [K]", "1,2,3,300"], r"has unit 'Hz'; expected one of rad/s"),
    "no unit": (["f,E' [MPa],E'' [MPa],T [K]", "1,2,3,300"], r"column 'f' \(frequency\) has no unit"),
    "E and G": (["f [Hz],E' [MPa],G'' [MPa],T [K]", "1,2,3,300"], r"both tensile \(E\) and shear \(G\)"),
    "two frequencies": (["f [Hz],omega [rad/s],E' [MPa],E'' [MPa],T [K]", "1,6.2832,2,3,300", "2,12.6,2,3,300"],
                        r"line 3: columns 'f' and 'omega' both hold the frequency and disagree"),
    "not a number": (["f [Hz],E' [MPa],E'' [MPa],T [K]", "1,2,3,300", "2,2.5,3.1,300", "3,abc,3,300"],
                     r"line 4: column \"E'\" holds 'abc'; expected a number"),
    "below 0 K": (["f [Hz],E' [MPa],E'' [MPa],T [K]", "1,2,3,-20"], r"line 2: temperature -20 K is below absolute"),
    "storage unnamed": (["f [Hz],storage modulus [MPa],loss modulus [MPa],T [K]", "1,2,3,300"],
                        r"cannot tell whether the moduli are tensile"),
    "comments only": (["# nothing", "   "], r"the file is empty"),
    "no data rows": (["f [Hz],E' [MPa],E'' [MPa],T [K]"], r"no sweep of 2 usable points or more among the 0 points"),
    "two sweeps at one T": (["f [Hz],E' [MPa],E'' [MPa],T [K],Set", "1,2,0.3,300,0", "2,2,0.3,300,0",
                             "1,2,0.3,300,1", "2,2,0.3,300,1"], r"two sweeps at 300.0 K; expected one sweep"),
}


@pytest.mark.parametrize("case", BAD)
def test_bad_csv_files_name_the_file_and_the_fault(tmp_path, case):
    lines, message = BAD[case]
    path = write(tmp_path / "bad.csv", lines)
    with pytest.raises(ParameterError, match=rf"{re.escape(str(path))}: .*{message}"):
        read_dma(path)


def test_bad_paths(tmp_path):
    for path, message in ((tmp_path / "nowhere.csv", r"nowhere\.csv: no such file"),
                          (tmp_path, r": is a directory; expected a DMA data file"),
                          (write(tmp_path / "empty.csv", []), r"empty\.csv: the file is empty"),
                          (write(tmp_path / "eplexor.xlsx", ["x"]), r"eplexor\.xlsx: Excel .* export the sheet to "
                                                                    r"CSV")):
        with pytest.raises(ParameterError, match=message):
            read_dma(path)
    with pytest.raises(ParameterError, match=r"path must be a file path, got 3"):
        read_dma(3)


def test_bad_arguments():
    with pytest.raises(ParameterError, match=r"modulus must be 'tensile' or 'shear', got 'E'"):
        read_dma(RAW, modulus="E")
    with pytest.raises(ParameterError, match=r"poisson must lie in \(-1, 0.5\], got 0.7"):
        read_dma(RAW, poisson=0.7)
    assert read_dma(RAW, poisson=0.35).poisson == 0.35 and read_dma(RAW, poisson=0.35).converted is None


def test_trios_step_cut_short(tmp_path):
    path = write(tmp_path / "cut.txt", ["Filename\tcut", "[step]", "Frequency sweep (25.0 °C)"])
    with pytest.raises(ParameterError, match=r"cut\.txt: step 1 \(line 2\) has 1 line\(s\) after \[step\]; expected "
                                             r"the step's name, a row of variable names, a row of units"):
        read_dma(path)


def test_trios_step_without_the_modulus(tmp_path):
    steps = steps_of(raw_rows())[:2]
    path = trios(tmp_path / "mixed.txt", ["Instrument type\tRSA-G2"], steps[:1])
    with open(path, "a", encoding="utf-8") as f:
        f.write("\n[step]\nFrequency sweep (-42.5 °C)\nAngular frequency\tTemperature\nrad/s\t°C\n1.0\t-42.5\n")
    with pytest.raises(ParameterError, match=r"mixed\.txt: step 2 \(Frequency sweep \(-42\.5 °C\)\): no storage, "
                                             r"loss \(or tan delta\) column among \['Angular frequency', "):
        read_dma(path)


# --------------------------------------------------------------------------- the result

def test_result_is_read_only_picklable_and_feeds_master_curve():
    sweeps = read_dma(RAW)
    with pytest.raises(AttributeError):
        sweeps.modulus = "shear"
    copy = pickle.loads(pickle.dumps(sweeps))
    assert type(copy) is DMASweeps and copy.format == "pyvisco" and copy.path == RAW
    assert_same(copy, sweeps, rel=0)
    assert repr(sweeps).startswith("DMASweeps(21 sweeps, 210 points, 223.24 .. 373.14 K, pyvisco file")
    reference = min(sweeps, key=lambda t: abs(t - 268.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataWarning)
        curve = materials.master_curve(sweeps, reference)
    assert curve.reference == reference and curve.frequencies.size == 210
    assert curve.temperatures.tolist() == list(sweeps)
