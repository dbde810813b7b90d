"""Real-to-complex FFTs over the last two axes, with pyFFTW when present.

pyFFTW plans are built once per (shape, direction) with ``FFTW_MEASURE``, then
reused. Transforms use one thread unless ``FRAMEWORK_FFT_THREADS`` (a number,
or ``auto``: every core this process may use) or :func:`set_threads` says
otherwise: at the sizes of contact grids threads gain little, and a threaded
FFTW transform stalls when another process holds a core (measured here on 2
cores: 30 ms instead of 0.4 ms for a 512^2 transform), which is the normal
state of a parameter sweep — ``auto`` is for a dedicated machine; without pyFFTW (or after ``set_backend("scipy")``) the same
calls go to :mod:`scipy.fft` with ``workers`` = all cores. The two paths give
the same numbers to rounding.

FFTW's wisdom (the plans it measured) is kept between processes in one file,
``FRAMEWORK_FFT_WISDOM`` (default ``$XDG_CACHE_HOME/viscocontact/fftw-wisdom``,
else ``~/.cache/...``; ``off`` keeps none): read before the process's first
plan, written back at exit when the process planned a transform the file did not
hold. A process then starts as fast as a warm one (the first transient roll of a
process planned its box shapes for 0.7 s of 2 s). The wisdom says which algorithm
FFTW runs, not what it computes: the transforms agree to rounding whichever plan
runs; a file measured on another machine gives plans that may be slower, never
other numbers. An unreadable or damaged file is ignored (and replaced at exit).
"""
import atexit
import contextlib
import functools
import os

import numpy as np
import scipy.fft

from .errors import ParameterError

try:  # pragma: no cover - depends on the environment
    import pyfftw
    import pyfftw.builders
except ImportError:  # pragma: no cover
    pyfftw = None

def available_cores():
    """Cores this process may run on (its CPU affinity where the system tells it)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        return os.cpu_count() or 1


def threads_from_environment(value):
    """FFT threads from ``FRAMEWORK_FFT_THREADS``: unset -> 1, ``auto`` -> :func:`available_cores`, else an int >= 1."""
    if value is None or value == "":
        return 1
    if value.strip().lower() == "auto":
        return available_cores()
    try:
        count = int(value)
    except ValueError:
        count = 0
    if count < 1:
        raise ParameterError(f"FRAMEWORK_FFT_THREADS must be a whole number >= 1 or 'auto', got {value!r}")
    return count


THREADS = threads_from_environment(os.environ.get("FRAMEWORK_FFT_THREADS"))
_backend = "pyfftw" if pyfftw is not None else "scipy"
if os.environ.get("FRAMEWORK_FFT_BACKEND") in ("scipy", "pyfftw") and (pyfftw is not None
                                                                     or os.environ["FRAMEWORK_FFT_BACKEND"] == "scipy"):
    _backend = os.environ["FRAMEWORK_FFT_BACKEND"]
_plans = {}


def wisdom_path(value):
    """The wisdom file for a ``FRAMEWORK_FFT_WISDOM`` value: unset or empty -> the user's cache folder,
    ``off`` (or ``0``, ``none``, ``false``) -> None (no file), else the path given."""
    if value is None or value.strip() == "":
        cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        return os.path.join(cache, "viscocontact", "fftw-wisdom")
    if value.strip().lower() in ("off", "0", "none", "false"):
        return None
    return os.path.abspath(os.path.expanduser(value.strip()))


class _Wisdom:
    """FFTW's wisdom read from its file before the first plan and written back at exit when it grew."""

    def __init__(self, path):
        self.path, self.loaded, self.known = path, False, None

    def load(self):
        """Read the file once (before the process's first plan); a missing or damaged one is left for exit."""
        if self.loaded or pyfftw is None or self.path is None:
            return
        self.loaded = True
        try:
            with open(self.path, "rb") as handle:
                pyfftw.import_wisdom((handle.read(), b"", b""))
        except (OSError, ValueError, TypeError):
            pass
        self.known = pyfftw.export_wisdom()[0]
        atexit.register(self.save)

    def save(self):
        """Write the wisdom back (atomically, umask permissions) if this process added to it; never raises."""
        from .io import temporary     # the result files' temporary name (leftovers of dead processes removed)
        wisdom = pyfftw.export_wisdom()[0]
        if wisdom == self.known:
            return
        writing = None
        try:
            os.makedirs(os.path.dirname(self.path), exist_ok=True)
            writing = temporary(self.path)
            with open(writing, "wb") as out:        # open's mode: 0o666 less the umask
                out.write(wisdom)
            os.replace(writing, self.path)
            self.known = wisdom
        except OSError:     # a read-only or full disk costs the next process its planning, nothing else
            if writing is not None:
                with contextlib.suppress(OSError):
                    os.remove(writing)


WISDOM = _Wisdom(wisdom_path(os.environ.get("FRAMEWORK_FFT_WISDOM")))


def available_backends():
    """Names of the backends that can be selected here."""
    return ("pyfftw", "scipy") if pyfftw is not None else ("scipy",)


def set_threads(count):
    """Threads per transform (default 1, or ``FRAMEWORK_FFT_THREADS``); plans made later use it."""
    global THREADS
    if not isinstance(count, int) or count < 1:
        raise ParameterError(f"threads must be an integer >= 1, got {count!r}")
    THREADS = count
    _plans.clear()


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


def _plan(kind, shape, dims=2):
    key = (kind, shape, THREADS, dims)
    plan = _plans.get(key)
    if plan is None:
        WISDOM.load()
        axes = tuple(range(-dims, 0))
        # Measuring plans pays off for the many small 2-D transforms of a contact solve; a 3-D
        # transform of an eigenstrain box runs a few hundred times and would wait seconds for it.
        effort = "FFTW_MEASURE" if dims == 2 else "FFTW_ESTIMATE"
        if kind == "forward":
            buffer = pyfftw.empty_aligned(shape, dtype="float64")
            plan = pyfftw.builders.rfftn(buffer, axes=axes, threads=THREADS,
                                         planner_effort=effort, auto_align_input=True)
        else:
            real_shape = shape[:-1]
            spectral = real_shape[:-1] + (real_shape[-1] // 2 + 1,)
            buffer = pyfftw.empty_aligned(spectral, dtype="complex128")
            plan = pyfftw.builders.irfftn(buffer, s=real_shape[-dims:], axes=axes, threads=THREADS,
                                          planner_effort=effort, auto_align_input=True)
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


def rfft3(array):
    """Forward real FFT over the last three axes of ``array``."""
    if _backend == "pyfftw":
        return _plan("forward", array.shape, dims=3)(array).copy()
    return scipy.fft.rfftn(array, axes=(-3, -2, -1), workers=THREADS)


def irfft3(spectrum, shape):
    """Inverse of :func:`rfft3`; ``shape`` is the real shape of the last three axes."""
    shape = tuple(shape)
    if _backend == "pyfftw":
        key_shape = spectrum.shape[:-3] + shape + (0,)
        return _plan("inverse", key_shape, dims=3)(spectrum).copy()
    return scipy.fft.irfftn(spectrum, s=shape, axes=(-3, -2, -1), workers=THREADS)


def empty_aligned(shape):
    """An uninitialised float64 array that :meth:`RealFFTPair.forward_from` can transform in place (aligned for
    pyFFTW's vector instructions; a plain array without pyFFTW)."""
    if pyfftw is not None:
        return pyfftw.empty_aligned(shape, dtype="float64")
    return np.empty(shape)


def aligned(array):
    """``array`` itself where :meth:`RealFFTPair.forward_from` can read it in place, else a copy that it can."""
    if _in_place(array):
        return array
    out = empty_aligned(array.shape)
    out[...] = array
    return out


def _in_place(array):
    """Whether pyFFTW's plans can read ``array`` where it lies: C-ordered float64, aligned for its vector
    instructions (any C-ordered float64 array without pyFFTW)."""
    return (array.dtype == np.float64 and array.flags.c_contiguous
            and (pyfftw is None or array.ctypes.data % pyfftw.simd_alignment == 0))


class RealFFTPair:
    """Forward and inverse real FFT of one fixed 2-D shape, with buffers of its own.

    Write the input into ``real_in`` (what lies outside the written block stays
    as it is, so zero padding is written once), call :meth:`forward`, work on
    ``spectrum`` in place, call :meth:`inverse` and read ``real_out`` times
    ``normalisation``: the inverse is left unnormalised (pyFFTW's raw
    transform), so that the reader folds the factor into the pass that copies
    the block it needs instead of a pass over the whole (padded) buffer.
    Nothing is allocated per call: in the solver loop that is most of the cost.
    """

    def __init__(self, shape):
        self.shape = tuple(shape)
        self.backend = _backend
        self.threads = THREADS
        spectral = self.shape[:-1] + (self.shape[-1] // 2 + 1,)
        self.normalisation = 1.0 / (self.shape[-1] * self.shape[-2]) if _backend == "pyfftw" else 1.0
        if _backend == "pyfftw":
            WISDOM.load()
            self.real_in = pyfftw.zeros_aligned(self.shape, dtype="float64")
            self.spectrum = pyfftw.zeros_aligned(spectral, dtype="complex128")
            self.real_out = pyfftw.zeros_aligned(self.shape, dtype="float64")
            # No FFTW_DESTROY_INPUT on the forward plan: the zero padding of real_in is written once.
            self._forward = pyfftw.FFTW(self.real_in, self.spectrum, axes=(-2, -1),
                                        flags=("FFTW_MEASURE",), threads=THREADS)
            self._inverse = pyfftw.FFTW(self.spectrum, self.real_out, axes=(-2, -1), direction="FFTW_BACKWARD",
                                        flags=("FFTW_MEASURE", "FFTW_DESTROY_INPUT"), threads=THREADS)
            self.real_in[...] = 0.0  # planning with FFTW_MEASURE scribbles on the buffers
        else:
            self.real_in = np.zeros(self.shape)
            self.spectrum = np.zeros(spectral, dtype=complex)
            self.real_out = np.zeros(self.shape)

    def forward(self):
        """``spectrum <- rfft2(real_in)``."""
        if self.backend == "pyfftw":
            self._forward.execute()
        else:
            self.spectrum[...] = scipy.fft.rfftn(self.real_in, axes=(-2, -1), workers=THREADS)

    def forward_from(self, array):
        """``spectrum <- rfft2(array)`` for a float array of the pair's shape, read where it lies when it can be.

        pyFFTW reads an array from :func:`empty_aligned` (C-ordered, aligned as
        the plan's buffers) in place, for the cost of pointing the plan at it
        and back; any other array is first copied into ``real_in``. ``array``
        is not changed.
        """
        if array is self.real_in:
            self.forward()
        elif self.backend == "pyfftw" and array.shape == self.shape and _in_place(array):
            self._forward.update_arrays(array, self.spectrum)
            try:
                self._forward.execute()
            finally:
                self._forward.update_arrays(self.real_in, self.spectrum)
        elif self.backend == "pyfftw":
            self.real_in[...] = array
            self._forward.execute()
        else:
            self.spectrum[...] = scipy.fft.rfftn(array, axes=(-2, -1), workers=THREADS)

    def inverse(self):
        """``real_out <- irfft2(spectrum) / normalisation`` (``spectrum`` is destroyed)."""
        if self.backend == "pyfftw":
            self._inverse.execute()
        else:
            self.real_out[...] = scipy.fft.irfftn(self.spectrum, s=self.shape[-2:], axes=(-2, -1), workers=THREADS)


class Transform:
    """One planned transform between two fixed arrays: ``target <- DFT(source)`` over ``axes``, unnormalised.

    ``source`` real and ``target`` complex: the real-to-complex transform (the last of ``axes`` halved);
    complex to real: its inverse (``source`` is destroyed); complex to complex: forward, or backward with
    ``inverse=True``. The backward transforms are not divided by the number of points (pyFFTW's raw
    transforms; the reader folds the factor into a pass it makes anyway). With pyFFTW the plan is made
    once (``effort``, an FFTW planner flag) and the input of a forward transform is left as it is, so a
    zero padding written once stays; with scipy each call transforms anew with ``workers=THREADS``.
    Both arrays should come from :func:`zeros` so that pyFFTW can use its vector instructions.
    ``effort="wisdom"``: FFTW's measured plan where its wisdom (kept between processes) holds one for this
    transform, else its estimate (no measuring); :attr:`effort` says which was made.
    """

    def __init__(self, source, target, axes, inverse=False, effort="FFTW_MEASURE"):
        self.source, self.target, self.axes = source, target, tuple(axes)
        real_in, real_out = not np.iscomplexobj(source), not np.iscomplexobj(target)
        self.kind = "r2c" if real_in else ("c2r" if real_out else ("c2c-inverse" if inverse else "c2c"))
        self.backend, self.effort = _backend, effort
        if _backend == "pyfftw":
            WISDOM.load()
            extra = ["FFTW_DESTROY_INPUT"] if self.kind == "c2r" else []
            direction = "FFTW_BACKWARD" if self.kind in ("c2r", "c2c-inverse") else "FFTW_FORWARD"
            plan = functools.partial(pyfftw.FFTW, source, target, axes=self.axes, direction=direction,
                                     threads=THREADS)
            if effort == "wisdom":      # neither asks FFTW to run transforms: the buffers are left alone
                try:
                    self._plan, self.effort = plan(flags=["FFTW_MEASURE", "FFTW_WISDOM_ONLY"] + extra), "FFTW_MEASURE"
                except RuntimeError:    # "No FFTW wisdom is known for this plan."
                    self._plan, self.effort = plan(flags=["FFTW_ESTIMATE"] + extra), "FFTW_ESTIMATE"
            elif effort == "FFTW_ESTIMATE":
                self._plan = plan(flags=[effort] + extra)
            else:
                saved = np.array(source, copy=True)     # planning by measurement scribbles on the buffers
                self._plan = plan(flags=[effort] + extra)
                source[...] = saved

    def __call__(self):
        if self.backend == "pyfftw":
            self._plan.execute()
            return
        axes, target = self.axes, self.target
        if self.kind == "r2c":
            target[...] = scipy.fft.rfftn(self.source, axes=axes, workers=THREADS)
        elif self.kind == "c2c":
            target[...] = scipy.fft.fftn(self.source, axes=axes, workers=THREADS)
        elif self.kind == "c2c-inverse":
            target[...] = scipy.fft.ifftn(self.source, axes=axes, workers=THREADS, norm="forward")
        else:
            shape = [target.shape[a] for a in axes]
            target[...] = scipy.fft.irfftn(self.source, s=shape, axes=axes, workers=THREADS, norm="forward")


def zeros(shape, dtype=float):
    """A zeroed array of ``shape`` aligned for pyFFTW's vector instructions (a plain one without pyFFTW)."""
    if pyfftw is not None:
        return pyfftw.zeros_aligned(shape, dtype=dtype)
    return np.zeros(shape, dtype=dtype)


def even_size(n):
    """The smallest even length ``>= n`` whose half is a fast transform length (5-smooth)."""
    return 2 * scipy.fft.next_fast_len((int(n) + 1) // 2, real=True)
