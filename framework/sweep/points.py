"""The points of a sweep: expanded from value lists, named by a stable hash, and the table's reserved columns."""
import hashlib
import itertools
import json

from ..errors import ParameterError

#: Columns of every row besides the parameters and the outputs (reserved: no parameter may take these names).
BOOKKEEPING = ("index", "status", "error", "file", "wall_time", "steps")
#: The last step's value of a series is the column ``final.<series>`` (``final.load``): a dotted name, which
#: no keyword argument of a ``build`` function and no scenario key (``material.young``: a table first) can be.
OUTPUT_PREFIX = "final."


def expand(parameters):
    """The list of points (dicts) of ``parameters``, in the order the sweep numbers them.

    A dict of value lists gives the Cartesian product in the dict's order, the
    last key varying fastest (``itertools.product``); a list of dicts is taken
    as the points themselves.
    """
    if isinstance(parameters, dict):
        if not parameters:
            raise ParameterError("parameters: expected at least one parameter with a list of values, got {}")
        keys, values = list(parameters), []
        for key in keys:
            _check_name(key)
            value = parameters[key]
            if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__iter__"):
                raise ParameterError(f"parameters[{key!r}]: expected a list of values, got {value!r}")
            value = list(value)
            if not value:
                raise ParameterError(f"parameters[{key!r}]: expected a non-empty list of values, got []")
            values.append(value)
        return [dict(zip(keys, combination)) for combination in itertools.product(*values)]
    if isinstance(parameters, (list, tuple)):
        if not parameters:
            raise ParameterError("parameters: expected at least one point, got an empty list")
        points = []
        for i, point in enumerate(parameters):
            if not isinstance(point, dict):
                raise ParameterError(f"parameters[{i}]: expected a dict of parameter values, got {point!r}")
            for key in point:
                _check_name(key)
            points.append(dict(point))
        return points
    raise ParameterError(f"parameters: expected a dict of value lists or a list of dicts, got "
                         f"{type(parameters).__name__}")


def _check_name(key):
    if not isinstance(key, str) or not key:
        raise ParameterError(f"parameter names must be non-empty strings, got {key!r}")
    if key in BOOKKEEPING or key.startswith(OUTPUT_PREFIX):
        raise ParameterError(f"parameter name {key!r} is taken by the table: {list(BOOKKEEPING)} and "
                             f"'{OUTPUT_PREFIX}<series>' are its own columns; rename the parameter")


def plain(value):
    """``value`` as plain data (numbers, strings, lists, dicts): what the table and the hash see."""
    from ..config import describe
    return describe(value)


def point_hash(point):
    """Short stable hash (8 hex digits) of a point: the same values give the same hash in every process."""
    text = json.dumps(plain(point), sort_keys=True, separators=(",", ":"), default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:8]


def point_file(index, point):
    """File name of a point's result: ``point_<index:04d>_<hash>.h5``."""
    return f"point_{index:04d}_{point_hash(point)}.h5"


def describe_point(point):
    """``key = value, ...`` of a point, for messages."""
    return ", ".join(f"{key} = {value!r}" for key, value in point.items())


def series_names():
    """Names of the scalar series of :meth:`Result.summary`, in its order."""
    from ..grid import Grid
    from ..result import Result
    return list(Result(Grid(shape=(1, 1), size=(1.0, 1.0)), None, None, None, None).summary())
