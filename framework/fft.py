"""Real-to-complex FFTs over the last two axes, with pyFFTW when present.

pyFFTW plans are built once per (shape, direction) with ``FFTW_MEASURE`` and all
cores, then reused; without pyFFTW (or after ``set_backend("scipy")``) the same
calls go to :mod:`scipy.fft` with ``workers`` = all cores. The two paths give
the same numbers to rounding.
"""
import contextlib
import os

import numpy as np
import scipy.fft

from .errors import ParameterError

try:  # pragma: no cover - depends on the environment
    import pyfftw
    import pyfftw.builders
except ImportError:  # pragma: no cover
    pyfftw = None

THREADS = os.cpu_count() or 1
_backend = "pyfftw" if pyfftw is not None else "scipy"
_plans = {}


def available_backends():
    """Names of the backends that can be selected here."""
    return ("pyfftw", "scipy") if pyfftw is not None else ("scipy",)


def get_backend():
    """Name of the backend in use: ``"pyfftw"`` or ``"scipy"``."""
    return _backend


def set_backend(name):
    """Select the FFT backend (``"pyfftw"`` or ``"scipy"``) for every later transform."""
    global _backend
    if name not in available_backends():
        raise ParameterError(f"FFT backend must be one of {available_backends()}, got {name!r}")
    _backend = name


@contextlib.contextmanager
def use_backend(name):
    """Context manager selecting a backend for the duration of a block."""
    previous = get_backend()
    set_backend(name)
    try:
        yield
    finally:
        set_backend(previous)


def _plan(kind, shape):
    key = (kind, shape)
    plan = _plans.get(key)
    if plan is None:
        if kind == "forward":
            buffer = pyfftw.empty_aligned(shape, dtype="float64")
            plan = pyfftw.builders.rfftn(buffer, axes=(-2, -1), threads=THREADS,
                                         planner_effort="FFTW_MEASURE", auto_align_input=True)
        else:
            real_shape = shape[:-1]
            spectral = real_shape[:-1] + (real_shape[-1] // 2 + 1,)
            buffer = pyfftw.empty_aligned(spectral, dtype="complex128")
            plan = pyfftw.builders.irfftn(buffer, s=real_shape[-2:], axes=(-2, -1), threads=THREADS,
                                          planner_effort="FFTW_MEASURE", auto_align_input=True)
        _plans[key] = plan
    return plan


def rfft2(array):
    """Forward real FFT over the last two axes of ``array``."""
    if _backend == "pyfftw":
        return _plan("forward", array.shape)(array).copy()
    return scipy.fft.rfftn(array, axes=(-2, -1), workers=THREADS)


def irfft2(spectrum, shape):
    """Inverse of :func:`rfft2`; ``shape`` is the real shape of the last two axes."""
    shape = tuple(shape)
    if _backend == "pyfftw":
        key_shape = spectrum.shape[:-2] + shape + (0,)
        return _plan("inverse", key_shape)(spectrum).copy()
    return scipy.fft.irfftn(spectrum, s=shape, axes=(-2, -1), workers=THREADS)
