"""A scenario as the ``build`` of a sweep: dotted keys (``"material.young"``) replace values of its tables."""
import copy
import os

from ..scenario import ARRAYS, TABLES, ScenarioError, load_tables, parse
from .points import describe_point


class ScenarioBuilder:
    """A scenario as a picklable ``build`` for :func:`sweep`: dotted keys replace its values.

    ``ScenarioBuilder("base.toml")(**{"material.young": 2e9, "indenter.radius": 5e-3})``
    is the :class:`Simulation` of ``base.toml`` with those values. A key names
    a table and a key in it, through nested tables and list indices
    (``"schedule.load.value"``, ``"schedule.load.segments.0.end"``); a key with
    the table alone (``"material"``) replaces the whole table. The tables on
    the way must exist in the base scenario; the last key may be new (a value
    left at its default there) and is checked when the scenario is parsed. Any
    mistake raises :class:`ScenarioError` naming the key.

    The file is read once, here: the builder carries its tables, so workers
    need no access to it, except to a file the scenario names (a ``dma``
    material, read relative to the scenario's folder by each point). The base
    scenario is checked at once.
    """

    def __init__(self, path_or_data, *, source=None):
        if isinstance(path_or_data, (str, os.PathLike)):
            path = os.fspath(path_or_data)
            self.data = load_tables(path, "scenario")
            self.source = source or path
            self.folder = os.path.dirname(os.path.abspath(path))
        elif isinstance(path_or_data, dict):
            self.data = copy.deepcopy(path_or_data)
            self.source = source or "<scenario>"
            self.folder = None
        else:
            raise ScenarioError(f"ScenarioBuilder: expected a scenario file path or a dict of tables, got "
                                f"{type(path_or_data).__name__}")
        parse(copy.deepcopy(self.data), source=self.source, folder=self.folder)

    def __repr__(self):
        return f"ScenarioBuilder({self.source!r})"

    def __eq__(self, other):
        return isinstance(other, ScenarioBuilder) and (self.data, self.source, self.folder) == (
            other.data, other.source, other.folder)

    __hash__ = None

    def check(self, key):
        """Raise :class:`ScenarioError` unless ``key`` can be set (its table and the tables on the way exist)."""
        self._place(copy.deepcopy(self.data), key, None)

    def tables(self, **overrides):
        """The scenario's tables with ``overrides`` applied (a new dict)."""
        data = copy.deepcopy(self.data)
        for key, value in overrides.items():
            self._place(data, key, copy.deepcopy(value))
        return data

    def scenario(self, **overrides):
        """The :class:`framework.scenario.Scenario` with ``overrides`` applied."""
        source = self.source
        if overrides:
            source += " with " + describe_point(overrides)
        return parse(self.tables(**overrides), source=source, folder=self.folder)

    def __call__(self, **overrides):
        return self.scenario(**overrides).simulation

    def _place(self, data, key, value):
        if not isinstance(key, str) or not key or not all(key.split(".")):
            raise ScenarioError(f"{self.source}: {key!r}: expected a dotted key like 'material.young'")
        parts = key.split(".")
        table = parts[0]
        if table not in TABLES | ARRAYS:
            raise ScenarioError(f"{self.source}: {key}: unknown table {table!r}; expected one of "
                                f"{sorted(TABLES | ARRAYS)}")
        if len(parts) == 1:
            data[table] = value
            return
        node = data.setdefault(table, {})
        for depth, part in enumerate(parts[1:], start=1):
            where = ".".join(parts[:depth])
            if isinstance(node, list):
                if not part.lstrip("-").isdigit() or not -len(node) <= int(part) < len(node):
                    raise ScenarioError(f"{self.source}: {key}: {where} is a list of {len(node)}; "
                                        f"{part!r} is not an index in it")
                part = int(part)
            elif not isinstance(node, dict):
                raise ScenarioError(f"{self.source}: {key}: {where} is {node!r}, not a table: "
                                    f"it has no key {part!r}")
            if depth == len(parts) - 1:
                node[part] = value
                return
            if isinstance(node, dict) and part not in node:
                raise ScenarioError(f"{self.source}: {key}: unknown key {'.'.join(parts[:depth + 1])!r} "
                                    f"(the base scenario's {where} has {sorted(node)})")
            node = node[part]
