"""Measured DMA frequency sweeps read from a file, ready for :func:`~framework.materials.master_curve`.

Three formats are read, each by one small parser into the same table (column
names, units, and the data rows with their line numbers), from which one step
converts the units, drops unusable points and groups the sweeps:

- pyvisco CSV (NREL's pyvisco, Springer 2022; its input and master-curve
  files): a row of names (``f`` or ``omega``, ``E_stor``/``E_loss`` or
  ``G_stor``/``G_loss``, ``T``, ``Set``), a row of units, often a UTF-8
  byte-order mark;
- plain CSV: comma, semicolon or tab separated, one row of names with the
  units in a second row or in the names (``frequency [Hz]``, ``E' (MPa)``),
  ``#`` comment lines;
- TA Instruments TRIOS text export (tab separated): ``key<TAB>value`` header
  lines, then per procedure step a line ``[step]``, the step's name, a row of
  variable names, a row of units and the data rows; one step is one isotherm.

Netzsch and Gabo Eplexor Excel workbooks (.xls, .xlsx) are not read: no
library among the framework's dependencies (numpy, scipy) reads them; export
the sheet to CSV.

The points are grouped into sweeps by the set/step column (pyvisco's ``Set``)
or the TRIOS step when there is one, otherwise by temperature: sorted, points
within :data:`SAME_TEMPERATURE` of their neighbour form one sweep. A sweep's
temperature is the mean of its points'. A file without a temperature column
is a master curve: one sweep, at the reference temperature the caller gives.
"""
import csv
import math
import os
import re
import warnings

import numpy as np

from .._validation import check_poisson
from ..errors import DataWarning, ParameterError
from .fitting import MAX_LOSS_TANGENT
from .temperature import check_temperature

__all__ = ["DMASweeps", "read_dma"]

#: [K] Points (sorted by temperature) this close to their neighbour form one sweep when the file has no set column:
#: an instrument holds an isotherm within ~0.1 K, and isotherms are set several kelvin apart.
SAME_TEMPERATURE = 0.5

#: Column names recognised, lower case with ``_`` read as a space: ``name: (quantity, modulus)``, where the
#: modulus is "E" (tensile), "G" (shear) or None (either: TRIOS writes "Storage modulus" for both).
COLUMNS = {
    **dict.fromkeys(("f", "freq", "frequency"), ("frequency", None)),
    **dict.fromkeys(("omega", "w", "ω", "angular frequency"), ("angular frequency", None)),
    **dict.fromkeys(("e'", "e stor", "e storage", "tensile storage modulus"), ("storage", "E")),
    **dict.fromkeys(("g'", "g stor", "g storage", "shear storage modulus"), ("storage", "G")),
    **dict.fromkeys(("storage", "storage modulus"), ("storage", None)),
    **dict.fromkeys(("e''", 'e"', "e loss", "tensile loss modulus"), ("loss", "E")),
    **dict.fromkeys(("g''", 'g"', "g loss", "shear loss modulus"), ("loss", "G")),
    **dict.fromkeys(("loss", "loss modulus"), ("loss", None)),
    **dict.fromkeys(("tan delta", "tan del", "tan(delta)", "tan δ", "tan(δ)", "loss factor"), ("tan delta", None)),
    **dict.fromkeys(("t", "temp", "temperature"), ("temperature", None)),
    **dict.fromkeys(("set", "step", "sweep"), ("set", None)),
}
_PSI = 0.45359237 * 9.80665 / 0.0254**2   # pound-force per square inch [Pa], from its exact definition
_MODULUS_UNITS = {"Pa": (1.0, 0.0), "kPa": (1e3, 0.0), "MPa": (1e6, 0.0), "GPa": (1e9, 0.0), "psi": (_PSI, 0.0)}
#: Units accepted (read in any case, spaces ignored): ``unit: (factor, offset)`` to rad/s, Pa, K
#: (``value * factor + offset``). ``1/s`` is refused: files use it for both Hz and rad/s.
UNITS = {
    "frequency": {"Hz": (2 * math.pi, 0.0), "rad/s": (1.0, 0.0)},
    "angular frequency": {"rad/s": (1.0, 0.0)},
    "storage": _MODULUS_UNITS,
    "loss": _MODULUS_UNITS,
    "temperature": {"K": (1.0, 0.0), **dict.fromkeys(("°C", "degC", "C", "℃"), (1.0, 273.15)),
                    **dict.fromkeys(("°F", "degF", "F"), (5 / 9, 273.15 - 32 * 5 / 9))},
}
#: Two columns of one quantity (TRIOS's "Frequency" and "Angular frequency") must agree to this relative precision,
#: that of the digits instruments write.
AGREE = 1e-3
#: Words of a TRIOS header's instrument and geometry lines that say which modulus the instrument measures.
TENSILE_WORDS = {"RSA", "DMA", "TENSION", "CANTILEVER", "BENDING"}
SHEAR_WORDS = {"DHR", "ARES", "AR", "HR", "TORSION", "PLATE", "CONE"}


class DMASweeps(dict):
    """The sweeps of a DMA file (:func:`read_dma`): ``{T [K]: (w [rad/s], E' + i E'' [Pa])}``, T ascending.

    A ``dict`` (so :func:`~framework.materials.master_curve` takes it as it is):
    each temperature maps to the angular frequencies, ascending, and the
    tensile complex moduli. Its attributes, read-only, say where the data came
    from and what was done to them.

    Attributes
    ----------
    path : str
        The file read.
    format : str
        ``"pyvisco"``, ``"csv"`` or ``"trios"``.
    modulus : str
        ``"tensile"`` or ``"shear"``: the moduli the file holds.
    converted : str or None
        How shear moduli were converted to tensile, or None.
    poisson : float or None
        The Poisson ratio given.
    dropped : tuple
        ``((location, reason), ...)`` of every point dropped (``"line 57"``, ``"step 3 line 12"``).
    master : bool
        True when the file is a master curve (no temperature column).
    """

    def __init__(self, sweeps, *, path, format, modulus, converted, poisson, dropped, master):
        super().__init__(sweeps)
        self._about = dict(path=path, format=format, modulus=modulus, converted=converted, poisson=poisson,
                           dropped=tuple(dropped), master=master)

    path = property(lambda self: self._about["path"])
    format = property(lambda self: self._about["format"])
    modulus = property(lambda self: self._about["modulus"])
    converted = property(lambda self: self._about["converted"])
    poisson = property(lambda self: self._about["poisson"])
    dropped = property(lambda self: self._about["dropped"])
    master = property(lambda self: self._about["master"])

    def __repr__(self):
        points = sum(w.size for w, _ in self.values())
        span = f"{min(self):.2f} .. {max(self):.2f} K, " if self else ""
        return (f"DMASweeps({len(self)} sweeps, {points} points, {span}{self.format} file {self.path!r}, "
                f"{self.modulus} data, {len(self.dropped)} dropped)")


def _normalise(name):
    return " ".join(name.lower().replace("_", " ").replace("′", "'").replace("″", "''").split())


def _is_number(cell):
    try:
        float(cell)
    except ValueError:
        return False
    return True


def _lines(path):
    """The file's lines, its byte-order mark removed; a ParameterError naming the path if there is no such file."""
    if os.path.isdir(path):
        raise ParameterError(f"{path}: is a directory; expected a DMA data file (CSV or TRIOS text export)")
    if not os.path.isfile(path):
        raise ParameterError(f"{path}: no such file; expected a DMA data file (CSV or TRIOS text export)")
    if path.lower().endswith((".xls", ".xlsx")):
        raise ParameterError(f"{path}: Excel workbooks (Netzsch, Eplexor) are not read; export the sheet to CSV "
                             f"(a row of column names, the units in a second row or in the names) and read that")
    with open(path, "rb") as f:
        raw = f.read()
    utf16 = raw.startswith((b"\xff\xfe", b"\xfe\xff"))
    try:
        text = raw.decode("utf-16" if utf16 else "utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")   # older instrument software writes "°C" in Windows-1252
    lines = text.splitlines()
    if not any(line.strip() and not line.lstrip().startswith("#") for line in lines):
        raise ParameterError(f"{path}: the file is empty; expected column names and rows of DMA data")
    return lines


def _read_csv(path, lines):
    """``(format, blocks, {})``: a pyvisco or plain CSV file is one block ``(None, names, units, rows, None)``."""
    kept = [(n, line) for n, line in enumerate(lines, 1) if line.strip() and not line.lstrip().startswith("#")]
    header = kept[0][1]
    delimiter = "\t" if "\t" in header else ";" if ";" in header else ","
    cells = csv.reader((line for _, line in kept), delimiter=delimiter)
    rows = [(f"line {n}", [cell.strip() for cell in row]) for (n, _), row in zip(kept, cells)]
    names, rows, units = rows[0][1], rows[1:], None
    if rows and not any(_is_number(cell) for cell in rows[0][1]):
        units, rows = rows[0][1], rows[1:]
    known = {_normalise(name) for name in names}
    pyvisco = units is not None and any({f"{m} stor", f"{m} loss"} <= known for m in "eg")
    return "pyvisco" if pyvisco else "csv", [(None, names, units, rows, None)], {}


def _read_trios(path, lines):
    """``("trios", blocks, header)``: one block ``(step name, names, units, rows, step)`` per ``[step]``."""
    starts = [i for i, line in enumerate(lines) if line.strip().lower() == "[step]"]
    header = dict(line.split("\t", 1) for line in lines[:starts[0]] if "\t" in line)
    blocks = []
    for step, (start, end) in enumerate(zip(starts, starts[1:] + [len(lines)]), 1):
        body = [(n, line.split("\t")) for n, line in enumerate(lines[start + 1:end], start + 2) if line.strip()]
        if len(body) < 3:
            raise ParameterError(f"{path}: step {step} (line {start + 1}) has {len(body)} line(s) after [step]; "
                                 f"expected the step's name, a row of variable names, a row of units, then data")
        (_, name), (_, names), (_, units), *data = body
        rows = [(f"step {step} line {n}", [cell.strip() for cell in row]) for n, row in data]
        blocks.append((f"step {step} ({name[0].strip()})", [cell.strip() for cell in names], units, rows, step))
    return "trios", blocks, {key.strip().lower(): value.strip() for key, value in header.items()}


def _columns(path, names, units):
    """``{quantity: [(name, index, factor, offset, modulus), ...]}`` of the recognised columns, units checked."""
    found = {}
    for index, cell in enumerate(names):
        name, unit = cell, (units[index].strip() if units is not None and index < len(units) else "")
        split = re.fullmatch(r"(.*?)\s*[\[(]([^\[\]()]*)[\])]", cell)
        if _normalise(cell) not in COLUMNS and split:
            name, unit = split[1], split[2].strip()
        quantity, modulus = COLUMNS.get(_normalise(name), (None, None))
        if quantity is None:
            continue
        factor, offset = 1.0, 0.0                # tan delta and the set are dimensionless: their unit is ignored
        if quantity in UNITS:
            accepted = {known.lower(): value for known, value in UNITS[quantity].items()}
            key = unit.lower().replace(" ", "")
            if key not in accepted:
                got = f"unit {unit!r}" if unit else "no unit (in its name or in a second row)"
                why = " (ambiguous: cycles or radians per second?)" if key == "1/s" else ""
                raise ParameterError(f"{path}: column {cell!r} ({quantity}) has {got}{why}; expected one of "
                                     f"{', '.join(UNITS[quantity])}")
            factor, offset = accepted[key]
        quantity = "frequency" if quantity == "angular frequency" else quantity
        found.setdefault(quantity, []).append((name, index, factor, offset, modulus))
    return found


class _Table:
    """One block's points in SI units: ``w`` [rad/s], ``storage``, ``loss`` [Pa], ``temperature`` [K] and ``sets``
    (None without such a column), ``where`` (their locations), ``moduli`` (the E/G the names say). A TRIOS step
    (``step`` given) is one set, at the temperature of its name when it has no temperature column."""

    def __init__(self, path, label, names, units, rows, step):
        found = _columns(path, names, units)
        missing = [q for q in ("frequency", "storage") if q not in found] + \
            (["loss (or tan delta)"] if "loss" not in found and "tan delta" not in found else [])
        if missing:
            raise ParameterError(f"{path}: {label + ': ' if label else ''}no {', '.join(missing)} column among "
                                 f"{names}; expected f/freq/frequency [Hz] or omega/angular frequency [rad/s], "
                                 f"E'/E_stor/storage modulus (or G'), E''/E_loss/loss modulus (or G'', or tan delta)")

        self.moduli = {column[4] for q in ("storage", "loss") for column in found.get(q, ())} - {None}
        if len(self.moduli) > 1:
            raise ParameterError(f"{path}: both tensile (E) and shear (G) modulus columns among {names}; expected "
                                 f"one kind in a file")
        self.where = [where for where, _ in rows]

        def read(name, index, factor, offset, _):
            values = np.full(len(rows), np.nan)
            for k, (where, cells) in enumerate(rows):
                cell = cells[index] if index < len(cells) else ""
                if cell and not _is_number(cell):
                    raise ParameterError(f"{path}: {where}: column {name!r} holds {cell!r}; expected a number "
                                         f"(an empty cell for a missing value)")
                values[k] = float(cell) * factor + offset if cell else np.nan
            return values

        def column(quantity):
            """The first column of ``quantity`` (None without one), checked against the others."""
            if quantity not in found:
                return None
            (first, *_), values = found[quantity][0], read(*found[quantity][0])
            for name, *rest in found[quantity][1:]:
                differ = ~np.isclose(read(name, *rest), values, rtol=AGREE, atol=0, equal_nan=True)
                if np.any(differ):
                    raise ParameterError(f"{path}: {self.where[np.argmax(differ)]}: columns {first!r} and {name!r} "
                                         f"both hold the {quantity} and disagree; expected one column, or columns "
                                         f"that agree within {AGREE:g}")
            return values

        self.w, self.storage, self.temperature, self.sets = (column(q) for q in ("frequency", "storage",
                                                                                  "temperature", "set"))
        self.loss = column("loss") if "loss" in found else self.storage * column("tan delta")
        if self.temperature is not None and np.any(self.temperature <= 0):
            k = int(np.argmax(self.temperature <= 0))
            raise ParameterError(f"{path}: {self.where[k]}: temperature {self.temperature[k]:g} K is below absolute "
                                 f"zero; expected the unit of column {found['temperature'][0][0]!r} to be the one "
                                 f"written")
        if step is not None:
            self.sets = np.full(len(rows), float(step))
            if self.temperature is None:
                self.temperature = np.full(len(rows), _step_temperature(path, label))


def _step_temperature(path, label):
    """The temperature [K] in a TRIOS step's name, e.g. ``Frequency sweep (25.0 °C)``."""
    found = re.search(r"(-?\d+(?:\.\d*)?)\s*(°C|℃|°F|K)(?![A-Za-z])", label)
    if not found:
        raise ParameterError(f"{path}: {label}: no Temperature column and no temperature in the step's name; "
                             f"expected one of the two, e.g. 'Frequency sweep (25.0 °C)'")
    factor, offset = UNITS["temperature"][found[2]]
    return float(found[1]) * factor + offset


def _shear(path, fmt, moduli, header, modulus):
    """True for shear data: from ``modulus``, else the columns' names, else a TRIOS header's instrument."""
    if modulus is not None:
        if modulus not in ("tensile", "shear"):
            raise ParameterError(f"modulus must be 'tensile' or 'shear', got {modulus!r}")
        return modulus == "shear"
    if len(moduli) > 1:
        raise ParameterError(f"{path}: tensile (E) modulus columns in some steps, shear (G) in others; expected one "
                             f"kind in a file")
    if moduli:
        return moduli == {"G"}
    about = " ".join(value for key, value in header.items() if key.startswith(("instrument", "geometry")))
    words = set(re.findall(r"[A-Z]+", about.upper()))
    if fmt == "trios" and bool(words & TENSILE_WORDS) != bool(words & SHEAR_WORDS):
        return bool(words & SHEAR_WORDS)
    raise ParameterError(f"{path}: cannot tell whether the moduli are tensile (E', DMA) or shear (G', rheometer) "
                         f"from the column names or the instrument {about!r}; give modulus='tensile' or "
                         f"modulus='shear'")


def _unusable(w, storage, loss, temperature, group):
    """Why a point cannot be used, or None."""
    for value, what, unit in ((w, "frequency", "rad/s"), (storage, "storage modulus", "Pa"),
                              (loss, "loss modulus", "Pa")):
        if not np.isfinite(value):
            return f"{what} missing or not finite ({value})"
        if value <= 0:
            return f"{what} {value:g} {unit} is not positive"
    if loss / storage > MAX_LOSS_TANGENT:
        return f"loss factor E''/E' = {loss / storage:.4g} exceeds {MAX_LOSS_TANGENT:g}"
    if np.isnan(temperature):
        return "temperature missing"
    return "set/step missing" if np.isnan(group) else None


def _sweeps(path, w, storage, loss, temperatures, groups, where):
    """``({T: (w, E*)}, {point: reason})``: the usable points grouped (``groups`` None: by temperature)."""
    dropped = {k: reason for k in range(w.size) if (reason := _unusable(
        w[k], storage[k], loss[k], temperatures[k], 0.0 if groups is None else groups[k]))}
    usable = np.array([k for k in range(w.size) if k not in dropped], dtype=int)
    if groups is None:
        groups, ordered = np.zeros(w.size), usable[np.argsort(temperatures[usable], kind="stable")]
        groups[ordered] = np.cumsum(np.diff(temperatures[ordered], prepend=-np.inf) > SAME_TEMPERATURE)
    sweeps = {}
    for group in dict.fromkeys(groups[usable]):
        points, first = [], {}
        for k in usable[groups[usable] == group]:
            if w[k] in first:
                dropped[k] = f"frequency {w[k]:g} rad/s repeats {where[first[w[k]]]} in its sweep"
            else:
                first[w[k]] = k
                points.append(k)
        measured = temperatures[points]    # the mean, exact when all are equal (a master curve)
        temperature = float(measured[0] if np.all(measured == measured[0]) else np.mean(measured))
        if len(points) < 2:
            dropped[points[0]] = f"its sweep at {temperature:.2f} K kept 1 point, fewer than the 2 a sweep needs"
            continue
        if temperature in sweeps:
            raise ParameterError(f"{path}: two sweeps at {temperature!r} K; expected one sweep per temperature")
        points = np.array(points)[np.argsort(w[points], kind="stable")]
        sweeps[temperature] = (w[points], storage[points] + 1j * loss[points])
    return sweeps, dropped


def read_dma(path, poisson=None, *, modulus=None, temperature=None):
    """Measured DMA sweeps from a pyvisco CSV, plain CSV or TRIOS text file (module docstring).

    Unusable points (a modulus or frequency missing or <= 0, a loss factor
    E''/E' over :data:`~framework.materials.fitting.MAX_LOSS_TANGENT`, a
    temperature missing, a frequency repeated within a sweep: the first is
    kept) are dropped, and so is a sweep left with fewer than two points: one
    :class:`~framework.errors.DataWarning` lists them all, with their line.

    Tensile or shear: from ``modulus`` when given, else the columns' names
    (E' or G'), else, in a TRIOS file, the header's ``Instrument type`` and
    ``Geometry name``: RSA, DMA, tension, cantilever or bending say tensile;
    DHR, ARES, AR, HR, torsion, plate or cone say shear; both or neither: an
    error asking for ``modulus``.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    poisson : float, optional
        Poisson ratio: needed for shear data, converted to tensile by
        ``E* = 2 (1 + nu) G*``; recorded for tensile data.
    modulus : {"tensile", "shear"}, optional
        What the moduli of the file are, overriding the columns and header.
    temperature : float, optional
        Reference temperature [K] of a master-curve file (one without a
        temperature column), required there and refused elsewhere.

    Returns
    -------
    DMASweeps
        ``{T [K]: (w [rad/s] ascending, E' + i E'' [Pa], tensile)}``.
    """
    try:
        path = os.fspath(path)
    except TypeError:
        raise ParameterError(f"path must be a file path, got {path!r}") from None
    lines = _lines(path)
    trios = any(line.strip().lower() == "[step]" for line in lines)
    fmt, blocks, header = (_read_trios if trios else _read_csv)(path, lines)
    tables = [_Table(path, *block) for block in blocks]
    shear = _shear(path, fmt, set().union(*(table.moduli for table in tables)), header, modulus)
    if shear and poisson is None:
        raise ParameterError(f"{path}: the file holds shear moduli G' and G'', which need poisson to be converted "
                             f"to tensile by E* = 2 (1 + nu) G*; got poisson=None")
    poisson = None if poisson is None else check_poisson(poisson)
    master = tables[0].temperature is None
    if master != (temperature is not None):
        raise ParameterError(f"{path}: temperature (the reference temperature [K] of a master curve) is needed for "
                             f"a file without a temperature column and refused for one with it; got "
                             f"temperature={temperature!r} for a file {'without' if master else 'with'} one")
    w, storage, loss = (np.concatenate([getattr(table, part) for table in tables]) for part in ("w", "storage", "loss"))
    if master:
        temperatures, groups = np.full(w.size, check_temperature(temperature)), np.zeros(w.size)
    else:
        temperatures = np.concatenate([table.temperature for table in tables])
        groups = None if tables[0].sets is None else np.concatenate([table.sets for table in tables])
    where = [location for table in tables for location in table.where]
    sweeps, dropped = _sweeps(path, w, storage, loss, temperatures, groups, where)
    dropped = [(where[k], dropped[k]) for k in sorted(dropped)]
    if dropped:
        warnings.warn(f"{path}: {len(dropped)} of {w.size} points of measured data were dropped: "
                      f"{'; '.join(f'{at}: {why}' for at, why in dropped)}", DataWarning, stacklevel=2)
    if not sweeps:
        raise ParameterError(f"{path}: no sweep of 2 usable points or more among the {w.size} points read; "
                             f"expected rows of DMA data")
    factor = 2 * (1 + poisson) if shear else 1.0
    converted = f"shear moduli G converted to tensile with E* = 2 (1 + nu) G*, nu = {poisson:g}" if shear else None
    return DMASweeps({t: (f, factor * e) for t, (f, e) in sorted(sweeps.items())}, path=path, format=fmt,
                     modulus="shear" if shear else "tensile", converted=converted, poisson=poisson, dropped=dropped,
                     master=master)
