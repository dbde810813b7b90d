"""Small checks that name the parameter and the value they received."""
import numbers

import numpy as np

from .errors import ParameterError, ShapeError


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
