"""Configuration objects as plain data, and back.

:func:`describe` turns a grid, material, indenter, load history, schedule or
options object into nested dicts/lists of numbers and strings, each object as
``{"type": "ClassName", field: value, ...}``; :func:`build` does the inverse.
Results carry this description (VTU field data, saved files), and scenario
files are written in the same form.
"""
import dataclasses
import inspect

import numpy as np

from .errors import ParameterError


def _registry():
    from . import grid, inclusions, indenters, loads, materials, options, schedules, solver
    classes = [grid.Grid, materials.Elastic, materials.Viscoelastic, materials.Maxwell, materials.KelvinVoigt,
               materials.AnisotropicElastic, materials.WLF, materials.Arrhenius,
               materials.WLFArrhenius, inclusions.Ellipsoid, inclusions.InclusionSet,
               indenters.Sphere, indenters.FlatPunch, indenters.RoundedFlatPunch, indenters.Cylinder,
               indenters.HeightMap, loads.Step, loads.Ramp, loads.Hold, loads.Table, loads.Cyclic, loads.Sequence,
               schedules.Static, schedules.Eccentric, schedules.Rolling, options.Options, solver.SolverOptions]
    table = {cls.__name__: cls for cls in classes}
    table["StandardLinearSolid"] = materials.StandardLinearSolid
    return table


def describe(obj):
    """Plain-data description of ``obj`` (JSON and TOML friendly, callables excepted)."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        out = {"type": type(obj).__name__}
        for f in dataclasses.fields(obj):
            value = getattr(obj, f.name)
            if f.init and value is not None:  # None means "the default": leave it out
                out[f.name] = describe(value)
        return out
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (list, tuple)):
        return [describe(item) for item in obj]
    if isinstance(obj, dict):
        return {key: describe(value) for key, value in obj.items()}
    if isinstance(obj, (np.floating, np.integer, np.bool_)):
        return obj.item()
    if callable(obj):
        return f"<function {getattr(obj, '__qualname__', repr(obj))}>"
    return obj


def build(data, *, name="configuration"):
    """Objects from a description made by :func:`describe` (or written by hand).

    ``name`` is the key path used in error messages, e.g. ``"material"``.
    """
    if isinstance(data, list):
        return [build(item, name=f"{name}[{i}]") for i, item in enumerate(data)]
    if not isinstance(data, dict) or "type" not in data:
        if isinstance(data, dict):
            return {key: build(value, name=f"{name}.{key}") for key, value in data.items()}
        return data
    registry = _registry()
    kind = data["type"]
    if kind not in registry:
        raise ParameterError(f"{name}.type: unknown type {kind!r}; expected one of {sorted(registry)}")
    factory = registry[kind]
    parameters = inspect.signature(factory).parameters
    accepted = {p for p, v in parameters.items() if v.kind in (v.POSITIONAL_OR_KEYWORD, v.KEYWORD_ONLY)}
    kwargs = {key: build(value, name=f"{name}.{key}") for key, value in data.items() if key != "type"}
    unknown = set(kwargs) - accepted
    if unknown:
        raise ParameterError(f"{name}: unknown key(s) {sorted(unknown)} for {kind}; "
                             f"expected some of {sorted(accepted)}")
    missing = [p for p in accepted if parameters[p].default is inspect.Parameter.empty and p not in kwargs]
    if missing:
        raise ParameterError(f"{name}: missing required key(s) {missing} for {kind}")
    if kind in ("Table", "Sequence"):
        kwargs = {key: tuple(value) if isinstance(value, list) else value for key, value in kwargs.items()}
    try:
        return factory(**kwargs)
    except ParameterError as exc:
        raise ParameterError(f"{name}: {exc}") from exc
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name}: {exc}") from exc
