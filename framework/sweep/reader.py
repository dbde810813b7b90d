"""Sweep files: a scenario, the values of its dotted keys, a folder; every point checked before anything runs.

::

    scenario = "hertz_elastic.toml"      # relative to this file; or an inline [scenario] table
    folder = "out/hertz_sweep"           # optional, relative to this file and inside its folder
    [parameters]                         # Cartesian product, the last key varying fastest
    "indenter.radius" = [5e-3, 10e-3]
    "material.young" = [70e9, 210e9]
    # or explicit points instead of [parameters]:
    # [[points]]
    # "indenter.radius" = 5e-3
"""
import os

from .._validation import check_inside
from ..errors import FrameworkError
from ..scenario import ScenarioError, check_path, load_tables, parse
from .builder import ScenarioBuilder
from .points import describe_point, expand

SWEEP_KEYS = ("scenario", "parameters", "points", "folder")


def is_sweep(tables):
    """Whether parsed TOML tables are a sweep file's (its own keys, none of a scenario's tables)."""
    from ..scenario import ARRAYS, TABLES
    return bool(set(tables) & set(SWEEP_KEYS)) and not set(tables) & (TABLES | ARRAYS)


def _flatten(table, prefix=""):
    """Nested tables to dotted keys; a table with a ``type`` (an object) stays a value."""
    out = {}
    for key, value in table.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict) and "type" not in value:
            out.update(_flatten(value, name + "."))
        else:
            out[name] = value
    return out


def _folder(path, value, base):
    """The sweep file's ``folder``: relative to the file's folder ``base`` and inside it, links followed."""
    try:
        check_inside(value, base, name="folder", kind="folder", owner="sweep file",
                     hint=" (give --folder on the command line to write elsewhere)")
        check_path(value, name="folder")
    except FrameworkError as exc:
        raise ScenarioError(f"{path}: {exc}") from exc
    return os.path.join(base, value)


def read_sweep(path):
    """``(builder, parameters, folder)`` from a sweep file (see the module's docstring).

    ``scenario`` is a path relative to the sweep file (or absolute) or an
    inline table of scenario tables; ``[parameters]`` maps dotted keys to value
    lists (their Cartesian product), or ``[[points]]`` lists the points (nested
    tables become dotted keys, except tables with a ``type``, which are
    values); ``folder`` is relative to the sweep file and must lead to a
    folder inside the sweep file's (absolute paths, ``..`` or links out of it
    are refused: give ``--folder`` to write elsewhere), None when absent. File
    names with control characters are refused. Mistakes raise
    :class:`ScenarioError` naming the file and the key. The points themselves
    are checked by :func:`check_points`.
    """
    path = os.fspath(path)
    data = load_tables(path, "sweep")
    unknown = sorted(set(data) - set(SWEEP_KEYS))
    if unknown:
        raise ScenarioError(f"{path}: unknown key(s) {unknown}; expected some of {list(SWEEP_KEYS)}")
    base = os.path.dirname(os.path.abspath(path))
    if "scenario" not in data:
        raise ScenarioError(f"{path}: missing 'scenario' (a scenario file's path, or a [scenario] table)")
    scenario = data["scenario"]
    if isinstance(scenario, str):
        try:
            check_path(scenario, name="scenario")
        except FrameworkError as exc:
            raise ScenarioError(f"{path}: {exc}") from exc
        builder = ScenarioBuilder(os.path.join(base, scenario))
    elif isinstance(scenario, dict):
        builder = ScenarioBuilder(scenario, source=f"{path} [scenario]")
    else:
        raise ScenarioError(f"{path}: scenario: expected a path or a table, got {scenario!r}")
    if ("parameters" in data) == ("points" in data):
        raise ScenarioError(f"{path}: expected either a [parameters] table (value lists) or [[points]], "
                            f"{'not both' if 'points' in data else 'found neither'}")
    if "parameters" in data:
        if not isinstance(data["parameters"], dict):
            raise ScenarioError(f"{path}: parameters: expected a table of value lists")
        parameters = _flatten(data["parameters"])
        if not parameters:
            raise ScenarioError(f"{path}: [parameters] is empty")
        for key, values in parameters.items():
            if not isinstance(values, list) or not values:
                raise ScenarioError(f"{path}: parameters.{key}: expected a non-empty list of values, got {values!r}")
        keys = list(parameters)
    else:
        points = data["points"]
        if not isinstance(points, list) or not points or not all(isinstance(p, dict) for p in points):
            raise ScenarioError(f"{path}: points: expected an array of tables [[points]], got {points!r}")
        parameters = [_flatten(point) for point in points]
        keys = list(dict.fromkeys(key for point in parameters for key in point))
    for key in keys:
        try:
            builder.check(key)
        except ScenarioError as exc:
            raise ScenarioError(f"{path}: {exc}") from exc
    folder = data.get("folder")
    if folder is not None:
        folder = _folder(path, folder, base)
    return builder, parameters, folder


def check_points(path, builder, parameters, *, memory=None):
    """Parse every point of a sweep (its scenario with the point's values); the scenarios, or one error.

    Run before any cluster starts: a misspelt key (``material.yung``) or a bad
    value fails here, naming the point, instead of on the workers. ``memory``
    [bytes]: a point whose grid alone needs more is refused before it is set
    up (:func:`framework.scenario.parse`); None on a remote cluster, whose
    workers may have more than this machine.

    Returns
    -------
    list of framework.scenario.Scenario
        One per point, in point order.

    Raises
    ------
    ScenarioError
        On one line: how many points are refused, the first of them (its index
        and values) and why.
    """
    points = expand(parameters)
    scenarios, refused = [], []
    for index, point in enumerate(points):
        try:
            scenarios.append(parse(builder.tables(**point), source=f"{builder.source} with {describe_point(point)}",
                                   folder=builder.folder, memory=memory))
        except MemoryError as exc:
            refused.append((index, point, f"does not fit in this machine's memory ({exc})"))
        except FrameworkError as exc:
            refused.append((index, point, str(exc)))
    if refused:
        index, point, reason = refused[0]
        source = f"{builder.source} with {describe_point(point)}: "
        reason = reason[len(source):] if reason.startswith(source) else reason
        if len(points) == 1:
            which = f"the point ({describe_point(point)})"
        elif len(refused) > 1:
            which = f"{len(refused)} of {len(points)} points are refused; the first, point {index} " \
                    f"({describe_point(point)})"
        else:
            which = f"point {index} ({describe_point(point)})"
        raise ScenarioError(f"{path}: {which}: {' '.join(reason.split())}")
    return scenarios
