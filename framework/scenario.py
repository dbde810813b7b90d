"""Scenario files (TOML): every public object, checked before anything runs.

A scenario has the tables ``[grid]``, ``[material]``, ``[indenter]``,
``[schedule]`` and optionally ``[options]``, ``[output]`` and any number of
``[[inclusions]]`` (elastic ellipsoidal inhomogeneities, see
:func:`inclusions_from_tables`) and ``[[dispersions]]`` (random particles or
fibres, added to them, see :func:`dispersions_from_tables`). Objects are
written as ``type = "ClassName"`` plus their keyword arguments (the same form
as :func:`framework.config.describe`); a material may instead name a preset
(``preset = "PMMA"``), and a viscoelastic one may take ``temperature`` [K] with
a ``shift`` table (``{type = "WLF", c1, c2, reference}`` or ``{type =
"Arrhenius", activation_energy, reference}``); a viscoelastic one may also be
fitted to a DMA file, ``material = {dma = "sweeps.csv", reference, poisson}``
(:func:`_dma_material`; the file lies in the scenario file's folder). Times are
a list or a range table ``{start, stop, count, spacing = "geometric" |
"linear", zero = true}``. See ``examples/*.toml``.

Any mistake raises :class:`ScenarioError` naming the file, the key and the
problem.
"""
import dataclasses
import os
import pathlib
import re
import unicodedata
import warnings

import numpy as np

from . import materials
from ._validation import check_bool, check_inside, check_positive_int, check_real
from .config import build
from .errors import FrameworkError, InclusionError, ParameterError

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

TABLES = {"grid", "material", "indenter", "schedule", "options", "output"}
ARRAYS = {"inclusions", "dispersions"}   # arrays of tables, [[inclusions]], [[dispersions]]
INCLUSION_KEYS = {"type", "center", "semi_axes", "material", "orientation", "euler", "convention"}
#: Keys of a ``[[dispersions]]`` table: the arguments of :func:`framework.inclusions.random_dispersion`.
DISPERSION_KEYS = ("fraction", "region", "radius", "material", "aspect", "orientation", "gap", "seed")
#: The ones a table must give: ``seed`` too, so that a scenario reads as the same bodies each time (the check of a
#: run and the run itself, every point of a sweep).
DISPERSION_REQUIRED = ("fraction", "region", "radius", "material", "seed")
REQUIRED = ("grid", "material", "indenter", "schedule")
PRESETS = {"PMMA": lambda: materials.PMMA}
OUTPUT_KEYS = {"vtu", "steps", "volume_steps", "single", "pictures", "history"}
PICTURE_KEYS = {"field", "step", "kind", "file"}
#: Keys of a material fitted to a DMA file (``material = {dma = "sweeps.csv", ...}``, :func:`_dma_material`).
DMA_KEYS = ("dma", "reference", "poisson", "temperature", "terms", "modulus", "shift")
#: [K] A DMA material's ``reference`` names the sweep this near it: an instrument holds an isotherm within ~0.1 K
#: and sets them several kelvin apart (the same 0.5 K that groups a file's points into sweeps), so 268.15 K
#: (-5 degC as written) names the sweep the instrument read at 268.39 K; a sweep further away is never taken instead.
SAME_SWEEP = 0.5
#: Files a run writes itself: a picture must not take their names.
RUN_FILES = {"summary.csv", "result.h5", "checkpoint.h5", "INCOMPLETE", "configuration.json"}


class ScenarioError(FrameworkError, ValueError):
    """A scenario file is malformed: the message names the key and the problem."""


@dataclasses.dataclass(frozen=True)
class Output:
    """What a scenario run writes besides ``summary.csv``.

    Parameters
    ----------
    vtu : bool
        VTU/PVD series for ParaView.
    steps : str or list of int
        ``"all"`` or the step indices (negative: from the end) of the surface and indenter files.
    volume_steps : str or list of int
        The same for the subsurface volumes (large: tens of MB per step on fine grids).
    single : bool
        Volumes in float32 (half the size).
    pictures : tuple of dict
        Off-screen pictures: ``{field, step=-1, kind="map", file=None}``; ``file``
        is a ``.png`` file name inside the output folder (no folder part).
    history : tuple of str
        Series for ``history.png`` (empty: no plot).

    The names of fields, kinds and series are the ones :mod:`viz` draws; the
    command line checks them against viz before it runs (``framework`` itself
    does not import viz).
    """

    vtu: bool = True
    steps: object = "all"
    volume_steps: object = "all"
    single: bool = False
    pictures: tuple = ()
    history: tuple = ("contact_radius", "approach", "max_pressure")


@dataclasses.dataclass
class Scenario:
    """A parsed scenario: the simulation to run and what to write."""

    simulation: object
    output: Output
    source: str


def _times(value, name):
    if isinstance(value, dict):
        unknown = set(value) - {"start", "stop", "count", "spacing", "zero"}
        if unknown:
            raise ParameterError(f"{name}: unknown key(s) {sorted(unknown)}; expected start, stop, count, "
                                 f"spacing, zero")
        for key in ("start", "stop", "count"):
            if key not in value:
                raise ParameterError(f"{name}: missing required key {key!r}")
        spacing = value.get("spacing", "geometric")
        if spacing not in ("geometric", "linear"):
            raise ParameterError(f"{name}.spacing: expected 'geometric' or 'linear', got {spacing!r}")
        count = check_positive_int(value["count"], name=f"{name}.count")
        start, stop = (check_real(value[key], name=f"{name}.{key}") for key in ("start", "stop"))
        if spacing == "geometric" and min(start, stop) <= 0:
            raise ParameterError(f"{name}: geometric spacing needs start and stop > 0, got {start!r} and {stop!r}")
        times = (np.geomspace if spacing == "geometric" else np.linspace)(start, stop, count)
        return np.concatenate([[0.0], times]) if check_bool(value.get("zero", False), name=f"{name}.zero") else times
    return value


def _material(table, folder=None):
    """The ``[material]`` table: a described material, a preset, a creep series (``j0``) or a DMA file (``dma``).

    Any viscoelastic one may carry ``temperature`` [K] and ``shift`` (a WLF or
    Arrhenius table, ``{type = "WLF", c1, c2, reference}``): its series is then
    the one at ``shift.reference``, taken to ``temperature`` (as
    :class:`framework.materials.Viscoelastic` reads them, so that a result's
    configuration reads back the same). A DMA file is found in ``folder``, the
    scenario file's (:func:`_dma_material`).
    """
    if "dma" in table:
        return _dma_material(table, folder)
    thermal = {key: build(table[key], name=f"material.{key}") for key in ("temperature", "shift") if key in table}
    if "preset" in table:
        unknown = set(table) - {"preset", "poisson", "temperature", "shift"}
        if unknown:
            raise ParameterError(f"material: unknown key(s) {sorted(unknown)} with a preset; expected poisson, "
                                 f"temperature, shift")
        preset = table["preset"]
        if preset not in PRESETS:
            raise ParameterError(f"material.preset: unknown preset {preset!r}; expected one of {sorted(PRESETS)}")
        material = PRESETS[preset]()
        if "poisson" in table or thermal:
            try:
                material = materials.Viscoelastic(e_inf=material.e_inf, terms=material.terms,
                                                  poisson=table.get("poisson", material.poisson), **thermal)
            except ParameterError as exc:
                raise ParameterError(f"material: {exc}") from exc
        return material
    if table.get("type") == "Viscoelastic" and "j0" in table:
        unknown = set(table) - {"type", "j0", "terms", "poisson", "temperature", "shift"}
        if unknown:
            raise ParameterError(f"material: unknown key(s) {sorted(unknown)}; expected j0, terms, poisson, "
                                 f"temperature, shift")
        try:
            material = materials.Viscoelastic.from_creep(j0=table["j0"], terms=table.get("terms", []),
                                                         poisson=table.get("poisson"))
            return material.at(thermal.get("temperature"), thermal.get("shift")) if thermal else material
        except ParameterError as exc:
            raise ParameterError(f"material: {exc}") from exc
    return build(table, name="material")


def _dma_path(value, folder):
    """The file ``material.dma`` names, as an absolute path: relative to ``folder`` and inside it, links followed."""
    where = "material.dma"
    if folder is None:
        raise ParameterError(f"{where}: a DMA file is found relative to the scenario file's folder, and these tables "
                             f"come from no file; got {value!r} (read the scenario with scenario.read(path), or "
                             f"give parse(..., folder=...))")
    path = check_inside(value, folder, name=where, kind="DMA file", owner="scenario file")
    check_path(value, name=where)
    if not path.is_file():
        what = "a folder" if path.is_dir() else "no such file"
        raise ParameterError(f"{where}: expected a DMA file in the scenario file's folder "
                             f"{str(pathlib.Path(folder).resolve())!r}, got {value!r}: {what}")
    return str(path)


def _read_sweeps(path, poisson, modulus, reference):
    """The sweeps of a DMA file; a master curve (no temperature column) is read at ``reference`` [K]."""
    try:
        return materials.read_dma(path, poisson, modulus=modulus)
    except ParameterError as exc:
        first = exc
    if reference is None:
        try:  # only to say which key is missing: the file's warnings come when it is read with its reference
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                materials.read_dma(path, poisson, modulus=modulus, temperature=300.0)
        except ParameterError:
            raise first from None
        raise ParameterError(f"missing required key 'reference' with dma: {path!r} is a master curve (no "
                             f"temperature column); expected reference = its temperature [K]") from None
    try:
        return materials.read_dma(path, poisson, modulus=modulus, temperature=reference)
    except ParameterError:
        raise first from None


def _reference(sweeps, reference, shift):
    """The master curve's reference temperature [K]: ``material.reference`` (or None), checked against the sweeps."""
    temperatures = sorted(sweeps)
    listed = "[" + ", ".join(f"{t:.2f}" for t in temperatures) + "]"
    if reference is None:
        if shift is not None:
            return shift.reference
        if len(temperatures) > 1:
            raise ParameterError(f"material: missing required key 'reference' with dma: the file holds "
                                 f"{len(temperatures)} sweeps, at {listed} K; expected reference = one of them [K]")
        return temperatures[0]
    if shift is not None:   # known shift factors: any temperature is a reference
        return reference
    nearest = min(temperatures, key=lambda t: abs(t - reference))
    if abs(nearest - reference) > SAME_SWEEP:
        raise ParameterError(f"material.reference: expected one of the sweeps' temperatures {listed} K (within "
                             f"{SAME_SWEEP:g} K), whose shift factors are fitted, got {reference!r}; take the solid "
                             f"to another temperature with material.temperature, or give material.shift")
    return nearest


def _with_shift(material, reference, shift):
    """``material``, fitted at ``reference`` [K], as the solid at ``reference`` carrying ``shift``.

    A :class:`~framework.materials.Viscoelastic` with a shift holds its series
    at ``shift.reference``: the fitted times are divided by ``a_T(reference)``.
    """
    factor = shift.factor(reference)
    terms = tuple((modulus, tau / factor) for modulus, tau in material.terms)
    return materials.Viscoelastic(e_inf=material.e_inf, terms=terms, poisson=material.poisson,
                                  temperature=reference, shift=shift)


def _dma_material(table, folder):
    """``material = {dma = "sweeps.csv", reference, poisson, ...}``: the Prony series fitted to a DMA file.

    The file's sweeps (:func:`framework.materials.read_dma`) are shifted onto
    ``reference`` (:func:`framework.materials.master_curve`) and a Prony series
    is fitted to the master curve (:meth:`MasterCurve.fit_prony`). The keys:

    - ``dma``: the file (pyvisco CSV, plain CSV or TRIOS text), relative to
      the scenario file's folder; absolute paths and paths that lead out of
      that folder (``..``, links) are refused.
    - ``reference`` [K]: without ``shift`` the shift factors are fitted and it
      names one of the sweeps: the sweep within :data:`SAME_SWEEP` (0.5 K) of
      it (``268.15`` names a sweep the instrument read at 268.39 K); a sweep
      further away is never chosen in its place. Optional for a file of one
      sweep (then its temperature) and with ``shift`` (then
      ``shift.reference``); a master-curve file (no temperature column)
      needs it: the curve's temperature.
    - ``poisson``: Poisson ratio of the solid (required; converts shear data).
    - ``temperature`` [K], optional: the solid there, its series taken from
      ``reference`` by ``shift``, or else by the law fitted to the shift
      factors (:meth:`MasterCurve.fit_shift`). Default: at ``reference``.
    - ``terms``, optional: the number of Prony terms (default: automatic).
    - ``modulus``, optional: ``"tensile"`` or ``"shear"``, what the file's
      moduli are when its columns do not say.
    - ``shift``, optional: a known WLF or Arrhenius law (``{type = "WLF", c1,
      c2, reference}``): the sweeps are shifted by it instead of by fitted
      factors, and the solid carries it.

    A :class:`~framework.errors.DataWarning` lists the points the reader
    dropped.

    Parameters
    ----------
    table : dict
        The ``[material]`` table, with a ``dma`` key.
    folder : str or None
        The scenario file's folder (None: tables from no file, which cannot
        name a file).

    Returns
    -------
    framework.materials.Viscoelastic
        The fitted solid: results record it as such (its terms, and its
        temperature and shift when it has them), so that a result's
        configuration reads back the same solid without the file.
    """
    unknown = set(table) - set(DMA_KEYS)
    if unknown:
        raise ParameterError(f"material: unknown key(s) {sorted(unknown)} with dma; expected some of "
                             f"{list(DMA_KEYS)}")
    if "poisson" not in table:
        raise ParameterError("material: missing required key 'poisson' with dma; expected the Poisson ratio of "
                             "the solid, in (-1, 0.5]")
    path = _dma_path(table["dma"], folder)
    terms = check_positive_int(table["terms"], name="material.terms") if "terms" in table else None
    shift = build(table["shift"], name="material.shift") if "shift" in table else None
    if shift is not None and not isinstance(shift, (materials.WLF, materials.Arrhenius, materials.WLFArrhenius)):
        raise ParameterError(f"material.shift: expected a WLF or Arrhenius table ({{type = \"WLF\", c1, c2, "
                             f"reference}}), got {table['shift']!r}")
    temperature = check_real(table["temperature"], name="material.temperature") if "temperature" in table else None
    reference = check_real(table["reference"], name="material.reference") if "reference" in table else None
    try:
        sweeps = _read_sweeps(path, table["poisson"], table.get("modulus"), reference)
    except ParameterError as exc:
        raise ParameterError(f"material: {exc}") from exc
    reference = _reference(sweeps, reference, shift)
    if temperature is not None and shift is None and len(sweeps) < 2:
        raise ParameterError(f"material.temperature: one sweep gives no shift factors to take the solid from "
                             f"{reference:g} K to {temperature!r} K; give material.shift (a WLF or Arrhenius table)")
    try:
        curve = materials.master_curve(sweeps, reference, shift=shift)
        material = curve.fit_prony(n_terms=terms, poisson=table["poisson"]).material
        if shift is not None:
            material = _with_shift(material, reference, shift)
            return material if temperature is None else material.at(temperature)
        return material if temperature is None else material.at(temperature, curve.fit_shift())
    except ParameterError as exc:
        raise ParameterError(f"material: {exc}") from exc


def _inclusion_material(table, name):
    """``{young, poisson}``, ``{stiffness = 6x6}`` or a described material (``type = ...``)."""
    if not isinstance(table, dict):
        raise ParameterError(f"{name}: expected a table {{young, poisson}} or {{stiffness}}, got {table!r}")
    if "type" in table:
        return build(table, name=name)
    keys = {"stiffness"} if "stiffness" in table else {"young", "poisson"}
    unknown, missing = set(table) - keys, sorted(keys - set(table))
    if unknown or missing:
        raise ParameterError(f"{name}: expected the keys young and poisson (isotropic) or stiffness (a 6x6 Voigt "
                             f"matrix [Pa]), got {sorted(table)}")
    return build(dict(table, type="AnisotropicElastic" if keys == {"stiffness"} else "Elastic"), name=name)


def inclusions_from_tables(tables):
    """The ellipsoids of the ``[[inclusions]]`` tables of a scenario.

    Each table holds ``center = [x1, x2, x3]`` and ``semi_axes = [a1, a2, a3]``
    [m] (``x3 > 0`` the depth), ``material = {young, poisson}`` or ``{stiffness
    = 6x6}`` (Voigt, [Pa], in the ellipsoid's own frame), and optionally its
    orientation: ``orientation``, the 3x3 matrix whose columns are the
    semi-axes' directions, or ``euler = [phi, theta, psi]`` in DEGREES, intrinsic
    rotations about the axes of ``convention`` (default ``"zxz"``: ``R = Rz(phi)
    Rx(theta) Rz(psi)``, see :func:`framework.inclusions.euler_orientation`).

    Parameters
    ----------
    tables : list of dict
        The parsed TOML array of tables.

    Returns
    -------
    list of framework.inclusions.Ellipsoid
        Mistakes raise :class:`ParameterError` naming ``inclusions[i].key``.
    """
    from .inclusions import Ellipsoid, euler_orientation
    bodies = []
    required = ("center", "semi_axes", "material")
    for name, table in _array_of_tables(tables, "inclusions", sorted(INCLUSION_KEYS), required):
        if table.get("type", "Ellipsoid") != "Ellipsoid":
            raise ParameterError(f"{name}.type: expected 'Ellipsoid' (the only shape), got {table['type']!r}")
        if "orientation" in table and "euler" in table:
            raise ParameterError(f"{name}: give orientation (a 3x3 matrix) or euler (angles in degrees), not both")
        if "convention" in table and "euler" not in table:
            raise ParameterError(f"{name}.convention: names the axes of euler angles; give euler = [phi, theta, psi] "
                                 f"in degrees too")
        orientation = table.get("orientation")
        if "euler" in table:
            angles = table["euler"]
            if not (isinstance(angles, list) and len(angles) == 3
                    and all(isinstance(a, (int, float)) and not isinstance(a, bool) for a in angles)):
                raise ParameterError(f"{name}.euler: expected three angles [phi, theta, psi] in degrees, "
                                     f"got {angles!r}")
            try:
                orientation = euler_orientation(*np.radians(angles), convention=table.get("convention", "zxz"))
            except ParameterError as exc:
                raise ParameterError(f"{name}.euler: {exc}") from exc
        material = _inclusion_material(table["material"], f"{name}.material")
        try:
            bodies.append(Ellipsoid(center=table["center"], semi_axes=table["semi_axes"], material=material,
                                    orientation=orientation))
        except FrameworkError as exc:  # the message names the key: center, semi_axes[1], orientation...
            raise ParameterError(f"{name}: {exc}") from exc
    return bodies


def _array_of_tables(tables, kind, keys, required):
    """``(name, table)`` of each table of a TOML array of tables ``[[kind]]``, its keys checked: none but ``keys``,
    all of ``required`` (a mistake raises :class:`ParameterError` naming ``kind[i]``)."""
    if not isinstance(tables, list) or not all(isinstance(table, dict) for table in tables):
        raise ParameterError(f"{kind}: expected an array of tables ([[{kind}]] blocks), got {tables!r}")
    for i, table in enumerate(tables):
        name = f"{kind}[{i}]"
        unknown = set(table) - set(keys)
        if unknown:
            raise ParameterError(f"{name}: unknown key(s) {sorted(unknown)}; expected some of {list(keys)}")
        missing = [key for key in required if key not in table]
        if missing:
            raise ParameterError(f"{name}: missing required key(s) {missing}")
        yield name, table


def dispersions_from_tables(tables):
    """The ellipsoids of the ``[[dispersions]]`` tables of a scenario, all tables' bodies in one list.

    Each table holds the arguments of :func:`framework.inclusions.random_dispersion`: ``fraction``, ``region =
    [[x1 lo, hi], [x2 lo, hi], [x3 lo, hi]]`` [m], ``radius`` [m] (or ``[[radius, weight], ...]``), ``material``
    as an ``[[inclusions]]`` table gives it (``{young, poisson}`` or ``{stiffness = 6x6}``), ``seed`` (required:
    the same bodies each time the file is read), and optionally ``aspect``, ``orientation`` (``"random"``,
    ``"planar"``, ``"aligned"`` or ``[d1, d2, d3]``) and ``gap`` [m]. A sweep varies them by dotted keys
    (``"dispersions.0.fraction"``, ``"dispersions.0.seed"``).

    Parameters
    ----------
    tables : list of dict
        The parsed TOML array of tables.

    Returns
    -------
    list of framework.inclusions.Ellipsoid
        Mistakes raise :class:`ParameterError` naming ``dispersions[i].key``.
    """
    return [body for placed in _dispersion_tables(tables) for body in placed]


def _dispersion_tables(tables):
    """The bodies of each ``[[dispersions]]`` table, one list per table."""
    from .inclusions import random_dispersion
    out = []
    for name, table in _array_of_tables(tables, "dispersions", list(DISPERSION_KEYS), DISPERSION_REQUIRED):
        arguments = dict(table, material=_inclusion_material(table["material"], f"{name}.material"))
        try:
            out.append(list(random_dispersion(**arguments)))
        except FrameworkError as exc:  # the message names the argument: fraction, region[2], radius[1][0]...
            raise ParameterError(f"{name}: {exc}") from exc
    return out


def _check_bodies_apart(listed, placed):
    """Raise for bodies of the ``[[inclusions]]`` tables (``listed``) and of the ``[[dispersions]]`` tables (``placed``,
    one list per table) that overlap, naming each by its table (``dispersions[1] body 17``), not by its place in the
    combined list."""
    from .inclusions import InclusionSet
    labels = [f"inclusions[{i}]" for i in range(len(listed))] + [
        f"dispersions[{t}] body {k}" for t, table in enumerate(placed) for k in range(len(table))]
    try:
        InclusionSet(listed + [body for table in placed for body in table])
    except InclusionError as exc:
        raise InclusionError(re.sub(r"inclusions\[(\d+)\]", lambda m: labels[int(m.group(1))], str(exc))) from exc


def _output(table):
    unknown = set(table) - OUTPUT_KEYS
    if unknown:
        raise ParameterError(f"output: unknown key(s) {sorted(unknown)}; expected some of {sorted(OUTPUT_KEYS)}")
    pictures = table.get("pictures", [])
    if not isinstance(pictures, list):
        raise ParameterError(f"output.pictures: expected a list of tables, got {type(pictures).__name__}")
    history = table.get("history", list(Output.history))
    if not isinstance(history, list) or not all(isinstance(h, str) for h in history):
        raise ParameterError(f"output.history: expected a list of series names, got {history!r}")
    names = {"history.png": "output.history"} if history else {}
    for i, picture in enumerate(pictures):
        if not isinstance(picture, dict) or "field" not in picture:
            raise ParameterError(f"output.pictures[{i}]: expected a table with a 'field', got {picture!r}")
        unknown = set(picture) - PICTURE_KEYS
        if unknown:
            raise ParameterError(f"output.pictures[{i}]: unknown key(s) {sorted(unknown)}; expected some of "
                                 f"{sorted(PICTURE_KEYS)}")
        for key in ("field", "kind"):
            if not isinstance(picture.get(key, ""), str):
                raise ParameterError(f"output.pictures[{i}].{key}: expected a name, got {picture[key]!r}")
        name = picture_file(picture)
        where = f"output.pictures[{i}].file"
        if isinstance(name, str):
            check_path(name, name=where)
        if not isinstance(name, str) or not name.endswith(".png") or os.path.basename(name) != name \
                or "\\" in name or name.startswith("."):
            raise ParameterError(f"{where}: expected a .png file name inside the output folder (no folder part), "
                                 f"got {name!r}")
        if name in names or name in RUN_FILES:
            raise ParameterError(f"{where}: {name!r} is already written by {names.get(name, 'the run')}; "
                                 f"give each picture its own file name")
        names[name] = f"output.pictures[{i}]"
    for key in ("steps", "volume_steps"):
        steps = table.get(key, "all")
        if steps != "all" and not (isinstance(steps, list)
                                   and all(isinstance(s, int) and not isinstance(s, bool) for s in steps)):
            raise ParameterError(f"output.{key}: expected \"all\" or a list of step indices, got {steps!r}")
    flags = {key: check_bool(table.get(key, getattr(Output, key)), name=f"output.{key}") for key in ("vtu", "single")}
    return Output(steps=table.get("steps", "all"), volume_steps=table.get("volume_steps", "all"),
                  pictures=tuple(pictures), history=tuple(history), **flags)


def picture_file(picture):
    """File name of a picture of ``[output]``: its ``file``, or ``<field>_<kind>.png``."""
    return picture.get("file") or f"{picture['field']}_{picture.get('kind', 'map')}.png"


def parse(data, source="<scenario>", *, folder=None, memory=None):
    """A :class:`Scenario` from the parsed TOML tables ``data``.

    ``folder`` is the scenario file's folder, where the files it names are
    found (``material.dma``); tables from no file (None) cannot name any.
    ``memory`` [bytes], optional: a scenario whose grid, material and
    inhomogeneities alone need more (:func:`framework.resources.estimate` of
    one step) is refused before the simulation allocates anything; a
    simulation that runs out of memory while it is set up is refused too.
    """
    from .simulation import Options, Simulation
    try:
        unknown = set(data) - TABLES - ARRAYS
        if unknown:
            raise ParameterError(f"unknown table(s) {sorted(unknown)}; expected some of {sorted(TABLES | ARRAYS)}")
        for key in REQUIRED:
            if key not in data:
                raise ParameterError(f"missing required table [{key}]")
        for key in TABLES & set(data):
            if not isinstance(data[key], dict):
                raise ParameterError(f"{key}: expected a table, got {type(data[key]).__name__}")
        grid = build(dict(data["grid"], type="Grid"), name="grid")
        material = _material(data["material"], folder)
        if "type" not in data["indenter"]:
            raise ParameterError("indenter: missing required key 'type' (Sphere, FlatPunch, RoundedFlatPunch, "
                                 "Cylinder, HeightMap)")
        indenter = build(data["indenter"], name="indenter")
        schedule = dict(data["schedule"])
        schedule.setdefault("type", "Static")
        if "times" in schedule:
            schedule["times"] = _times(schedule["times"], "schedule.times")
        if isinstance(schedule.get("start"), dict):  # a rolling run's preload at rest: a Static schedule
            start = dict(schedule["start"])
            start.setdefault("type", "Static")
            if "times" in start:
                start["times"] = _times(start["times"], "schedule.start.times")
            schedule["start"] = start
        for key in ("load", "approach"):
            if key in schedule:
                schedule[key] = build(schedule[key], name=f"schedule.{key}")  # numbers and lists pass through
        schedule = build(schedule, name="schedule")
        try:
            options = Options.from_value(data.get("options"))
        except ParameterError as exc:
            raise ParameterError(f"options: {exc}") from exc
        output = _output(data.get("output", {}))
        bodies = inclusions_from_tables(data["inclusions"]) if "inclusions" in data else None
        if "dispersions" in data:
            placed = _dispersion_tables(data["dispersions"])
            _check_bodies_apart(list(bodies or []), placed)
            bodies = list(bodies or []) + [body for table in placed for body in table]
        if memory is not None:
            _check_memory(grid, material, bodies, options, memory)
        try:
            simulation = Simulation(grid=grid, material=material, indenter=indenter, schedule=schedule,
                                    inclusions=bodies, options=options)
        except MemoryError as exc:  # numpy's "Unable to allocate 32.8 GiB for an array ..."
            raise ParameterError(f"the simulation does not fit in this machine's memory: {exc}; expected a run "
                                 f"that fits: fewer cells or layers, or smaller inhomogeneities") from exc
        total = len(simulation.output_times)
        for key in ("steps", "volume_steps"):
            steps = getattr(output, key)
            if steps != "all" and any(not -total <= step < total for step in steps):
                raise ParameterError(f"output.{key}: step indices must lie in [-{total}, {total}) for the "
                                     f"{total} output times, got {steps!r}")
        for i, picture in enumerate(output.pictures):
            step = picture.get("step", -1)
            if not isinstance(step, int) or isinstance(step, bool) or not -total <= step < total:
                raise ParameterError(f"output.pictures[{i}].step: expected an index in [-{total}, {total}), "
                                     f"got {step!r}")
    except FrameworkError as exc:  # a bad value, a HeightMap's shape, an offset the body cannot carry
        raise ScenarioError(f"{source}: {exc}") from exc
    return Scenario(simulation=simulation, output=output, source=source)


def load_tables(path, what="scenario"):
    """The tables of a TOML file (a scenario or a sweep file), or :class:`ScenarioError` naming the file.

    The file is UTF-8 text (a byte-order mark is accepted and dropped).
    """
    if os.path.isdir(path):
        raise ScenarioError(f"{path}: is a folder, not a {what} file")
    if not os.path.isfile(path):
        raise ScenarioError(f"{path}: no such {what} file")
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot be read: {exc.strerror}") from exc
    try:
        text = raw.decode("utf-8-sig")  # drops a byte-order mark, which TOML itself refuses
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"{path}: not a UTF-8 text file (byte {raw[exc.start]:#04x} at offset {exc.start}); "
                            f"a {what} file is TOML text") from exc
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from exc


def read(path, cells=None, *, memory=None):
    """Read and check a scenario file; ``cells`` replaces the grid's shape by ``cells x cells``.

    The file is UTF-8 text (a byte-order mark is accepted and dropped).
    ``memory`` [bytes]: see :func:`parse`.
    """
    data = load_tables(path, "scenario")
    if cells is not None and isinstance(data.get("grid"), dict):
        data["grid"]["shape"] = [cells, cells]
    return parse(data, source=path, folder=os.path.dirname(os.path.abspath(path)), memory=memory)


def _check_memory(grid, material, bodies, options, memory):
    """Refuse tables whose grid, material and inhomogeneities alone need more than ``memory`` [bytes]."""
    from .resources import check_memory, estimate
    check_memory(estimate(grid, material, inclusions=bodies, margin=options.inclusion_margin), memory)


def check_path(value, *, name):
    """``value``, a file or folder name from a file, unless it holds a control character (a newline, a tab, ESC).

    Such a name is legal on most file systems, but it breaks every line that
    prints it and hides in listings; it is always a mistake or a trap.
    """
    for position, character in enumerate(value):
        if unicodedata.category(character) == "Cc":
            raise ParameterError(f"{name}: {value!r} holds the control character {character!r} at position "
                                 f"{position}; expected a file name of printable characters")
    return value


def demo_path():
    """Path of the built-in default scenario."""
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenarios", "demo.toml")


