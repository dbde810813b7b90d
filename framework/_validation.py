"""Small checks that name the parameter and the value they received.

Physical inputs must also lie within :data:`LIMITS`, per SI unit: ranges wide
enough for any physical use, narrow enough that products of a few of them
(pressure x area, compliance x length, time / relaxation time) stay far inside
double precision. Outside them (1e-300 m, 1e300 Pa) a run would overflow or
divide by zero deep inside a solve, or report a misleading cause.
"""
import numbers
import os
import pathlib

import numpy as np

from .errors import ParameterError, ShapeError


#: Admissible magnitudes of physical inputs (non-zero ones), per SI unit: ``unit: (low, high)``.
LIMITS = {
    "m": (1e-12, 1e6),     # lengths: below an atom's size to a thousand kilometres
    "Pa": (1e-3, 1e15),    # moduli: a thousand times softer than the softest gels, harder than diamond
    "1/Pa": (1e-15, 1e3),  # compliances: the inverse range
    "s": (1e-15, 1e15),    # times: a femtosecond to thirty million years
    "N": (0.0, 1e12),      # loads (a history passes through small values: no lower limit)
    "m/s": (1e-15, 1e9),   # speeds: far slower than any creep test to far faster than any sound wave
    "rad/s": (1e-40, 1e40),  # angular frequencies: the inverse range of the relaxation times
    "K": (1e-3, 1e5),      # temperatures: a millikelvin to far hotter than any polymer survives
    "J/mol": (1e-3, 1e9),  # activation energies: far below and above any molecular process
}
#: Relaxation and retardation times [s] of a material, wider than the times of a run: a polymer's master curve spans
#: 30-35 decades of relaxation times at one temperature, and shifted 20 decades to another (its DMA range) some
#: reach 1e-30 s or 1e35 s: physically instantaneous or permanent, numerically harmless (t/tau < 1e80 for any time
#: of a run). The reduced frequencies of a master curve span the inverse range (LIMITS["rad/s"]).
RELAXATION_TIMES = (1e-40, 1e40)


def _is_real(value):
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def check_real(value, *, name):
    """Return ``value`` as a finite float or raise naming ``name``."""
    if not _is_real(value) or not np.isfinite(value):
        raise ParameterError(f"{name} must be a finite real number, got {value!r}")
    return float(value)


def check_positive(value, *, name, unit=""):
    """Return ``value`` as a float if it is finite and > 0."""
    value = check_real(value, name=name)
    if value <= 0.0:
        raise ParameterError(f"{name} must be positive{unit and ' [' + unit + ']'}, got {value!r}")
    return value


def check_non_negative(value, *, name, unit=""):
    """Return ``value`` as a float if it is finite and >= 0."""
    value = check_real(value, name=name)
    if value < 0.0:
        raise ParameterError(f"{name} must be >= 0{unit and ' [' + unit + ']'}, got {value!r}")
    return value


def check_quantity(value, *, name, unit, zero=False, lower=True, limits=None):
    """Return ``value`` as a float if it is finite, > 0 (>= 0 with ``zero``) and, unless 0, within ``LIMITS[unit]``.

    ``lower=False`` waives the lower limit (a Prony term may be arbitrarily weak next to the others); ``limits``
    replaces ``LIMITS[unit]`` (relaxation times: :data:`RELAXATION_TIMES`).
    """
    value = check_non_negative(value, name=name, unit=unit) if zero else check_positive(value, name=name, unit=unit)
    low, high = LIMITS[unit] if limits is None else limits
    low = low if lower else 0.0
    if value and not low <= value <= high:
        raise ParameterError(f"{name} must lie between {low:g} and {high:g} {unit}{' (or be 0)' if zero else ''}, "
                             f"the range this framework accepts, got {value!r}")
    return value


def check_bool(value, *, name):
    """Return ``value`` as a bool if it is one (``"no"`` or ``1`` are not booleans)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} must be a boolean, true or false, got {value!r}")
    return bool(value)


def check_positive_int(value, *, name, minimum=1):
    """Return ``value`` as an int if it is an integer >= ``minimum``."""
    if not isinstance(value, numbers.Integral) or isinstance(value, bool) or value < minimum:
        raise ParameterError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def check_poisson(value, *, name="poisson"):
    """Poisson ratio of an isotropic solid: -1 < nu <= 0.5."""
    value = check_real(value, name=name)
    if not -1.0 < value <= 0.5:
        raise ParameterError(f"{name} must lie in (-1, 0.5], got {value!r}")
    return value


def check_finite_array(array, *, name, shape=None, ndim=None):
    """Return ``array`` as a float array, finite, with the shape asked for."""
    try:
        array = np.asarray(array, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name} must be an array of real numbers, got {type(array).__name__}") from exc
    if ndim is not None and array.ndim != ndim:
        raise ShapeError(f"{name} must have {ndim} dimensions, got shape {array.shape}")
    if shape is not None and array.shape != tuple(shape):
        raise ShapeError(f"{name} has shape {array.shape}, expected {tuple(shape)}")
    if not np.all(np.isfinite(array)):
        bad = np.argwhere(~np.isfinite(array))[0]
        raise ParameterError(
            f"{name} must be finite everywhere, got {float(array[tuple(bad)])!r} at index {tuple(int(i) for i in bad)}")
    return array


def check_inside(value, folder, *, name, kind, owner, hint=""):
    """``value``, a path relative to ``folder``, resolved (links followed) once it leads inside ``folder``.

    The path is resolved before it is compared, so that neither ``..`` nor a
    link can lead out of the folder; links that stay inside are followed.

    Parameters
    ----------
    value : str
        The path as a file gave it (a scenario's ``material.dma``, a sweep's ``folder``).
    folder : str or os.PathLike
        The folder it is relative to and must stay in (the file's folder).
    name : str
        The key named in messages.
    kind : str
        What the path names, in messages ("DMA file", "folder").
    owner : str
        Whose folder ``folder`` is, in messages ("scenario file").
    hint : str
        Appended to the message of an absolute path or one that leads out (what to do instead).

    Returns
    -------
    pathlib.Path
        The absolute path, links resolved; it need not exist.

    Raises
    ------
    ParameterError
        Naming ``name``, the value and what was expected: for a value that is
        not a non-empty ``str``, an absolute path, a loop of links, or a path
        that leads out of ``folder``.
    """
    if not isinstance(value, str) or not value.strip():
        raise ParameterError(f"{name}: expected a {kind} relative to the {owner}'s folder, got {value!r}")
    base = pathlib.Path(folder).resolve()
    if os.path.isabs(value) or pathlib.PureWindowsPath(value).anchor:
        raise ParameterError(f"{name}: expected a {kind} relative to the {owner}'s folder {str(base)!r}, got the "
                             f"absolute path {value!r}{hint}")
    try:
        path = (base / value).resolve()
    except (OSError, RuntimeError) as exc:   # a loop of links
        raise ParameterError(f"{name}: cannot follow {value!r} from {str(base)!r}: {exc}") from exc
    if not path.is_relative_to(base):
        raise ParameterError(f"{name}: expected a {kind} inside the {owner}'s folder {str(base)!r}, got {value!r}, "
                             f"which leads to {str(path)!r}{hint}")
    return path
