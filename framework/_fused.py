"""The elementwise passes of a contact iteration, fused: compiled by numba when it is installed.

An iteration of :func:`framework.solver.solve_normal` is two FFT products and
a dozen elementwise operations on grid fields; as numpy expressions each is
a pass through memory (and often a temporary), which on a doubly periodic grid
cost more than the FFTs. Here they are grouped into six passes (and three
more for a preconditioned solve, one for the spectral products), each one
loop over the grid, or a box of it, that does all its work per cell and
returns its sums:

=============  ===============================================================
``gap``        on the rows ``top .. bottom - 1`` (outside them the pressure
               vanishes): ``gap = base + u``, ``contact = p > 0``; the gap
               summed over the contact, its cell count, ``sum u^4`` (with
               :meth:`norm`'s, ``sqrt`` of it bounds ``max u^2``), the first
               row holding contact and the last plus one (-1, -1: none)
``norm``       ``sum (gap - shift)^2`` over the contact, whether a free cell
               interpenetrates (``gap < shift``; on the other rows, where
               ``gap`` is not written, ``base + u < shift``), ``sum u^4`` on
               those rows; it reads, writes nothing
``direction``  ``d = beta d + gap - shift`` on the contact, 0 elsewhere;
               ``sum d (gap - shift)``
``mask``       the gap less the shift on the contact, 0 elsewhere, on a box
               of the grid (the preconditioner's input)
``preconditioned`` ``sum z`` over the contact, ``sum z b`` and ``sum b`` for the
               preconditioned gap ``z`` of the masked gap ``b``, on the box
``direction_box`` ``d = beta d + z - mean`` on the contact, 0 elsewhere;
               ``sum d (gap - shift)``
``curvature``  ``sum r d``, ``sum r`` over the contact and ``sum d``, with the
               response ``r`` on a box of the grid
``advance``    ``p' = max(p - step d, 0)`` on the contact, ``-entry (gap -
               shift)`` on free cells that interpenetrate (``gap < shift``), 0
               elsewhere; ``sum p'``
``rescale``    ``p' *= factor``; ``sum |p' - p|`` and ``sum p'``
``multiply``   ``spectrum *= multiplier`` (complex by real, in place): the
               spectral product of a convolution
=============  ===============================================================

The gap is kept as ``base + u``: the rigid shift (the approach) is subtracted
where the gap is read, which spares a pass over the grid an iteration; the
passes on the contact set walk only its rows.

``gap`` and ``norm`` walk the 2-D grid fields by rows (the displacement may
be a block of a padded FFT buffer, which has no flat view); ``mask``, ``preconditioned``,
``direction_box`` and ``curvature`` walk boxes of them; the others take flat
views (``a.reshape(-1)``) of C-ordered grid fields.

With numba (``pip install viscocontact[jit]``, :data:`NUMBA_MINIMUM`) each is a
compiled loop (cached on disk, so compiled once per installation) on grids of
:data:`COMPILED_FROM` cells or more; without it, on smaller grids, or with
``FRAMEWORK_JIT=0`` or :func:`set_compiled`, the same passes are numpy
expressions. The two give the same numbers to rounding (sums in another
order), as the reference loop of the solver does.
"""
import contextlib
import os

import numpy as np

from .errors import ParameterError

#: The oldest numba the compiled passes are written for (pyproject.toml's ``jit`` extra; the first with NumPy 2).
NUMBA_MINIMUM = "0.60"

#: Grids of fewer cells take the numpy passes: there the passes of a whole run cost less than importing
#: numba (half a second, once per process), which small runs and the test suite's processes are spared.
COMPILED_FROM = 128 * 128

_compiled = os.environ.get("FRAMEWORK_JIT", "1") != "0"
_cache = {}


def numba_available():
    """Whether numba can be imported here."""
    if "numba" not in _cache:
        try:
            import numba
        except ImportError:
            numba = None
        if numba is not None and _release(numba.__version__) < _release(NUMBA_MINIMUM):
            numba = None  # an older numba cannot compile these loops against this numpy: use the numpy passes
        _cache["numba"] = numba
    return _cache["numba"] is not None


def _release(version):
    """``(major, minor)`` of a version string."""
    return tuple(int(part) for part in version.split(".")[:2])


def set_compiled(flag):
    """Use the compiled passes (``True``, when numba is installed) or the numpy ones (``False``)."""
    global _compiled
    if not isinstance(flag, bool):
        raise ParameterError(f"compiled must be True or False, got {flag!r}")
    _compiled = flag


@contextlib.contextmanager
def use_compiled(flag):
    """Context manager selecting the compiled or the numpy passes for the duration of a block."""
    previous = _compiled
    set_compiled(flag)
    try:
        yield
    finally:
        set_compiled(previous)


def passes(cells=None):
    """The passes for a grid of ``cells`` cells: compiled when selected, numba is installed and the grid
    has :data:`COMPILED_FROM` cells or more (or ``cells`` is None), else numpy."""
    if not (_compiled and (cells is None or cells >= COMPILED_FROM) and numba_available()):
        return NumpyPasses
    if "compiled" not in _cache:
        # Reassociation lets the sums use vector registers; "no NaN" lets the selections on the contact
        # set use them too (the solver refuses a NaN separation, and no pass makes one from numbers).
        # Infinities keep their meaning.
        jit = _cache["numba"].njit(cache=True, nogil=True, fastmath={"reassoc", "nsz", "nnan"})
        _cache["compiled"] = type("CompiledPasses", (), {name: staticmethod(jit(getattr(_Loops, name)))
                                                         for name in _NAMES})
    return _cache["compiled"]


def multiply(spectrum, multiplier):
    """``spectrum *= multiplier`` in place: by the compiled pass (twice numpy's speed, which casts the real
    factor to complex) for a real C-ordered factor of the spectrum's shape, else by numpy."""
    if (multiplier.dtype == np.float64 and multiplier.shape == spectrum.shape and multiplier.flags.c_contiguous
            and spectrum.flags.c_contiguous and spectrum.ndim == 2):
        passes(spectrum.size).multiply(spectrum, multiplier)
    else:
        np.multiply(spectrum, multiplier, out=spectrum)


_NAMES = ("gap", "norm", "direction", "mask", "preconditioned", "direction_box", "curvature", "advance",
          "rescale", "multiply")


class _Loops:
    """The passes as loops over the cells, for numba (in plain Python they would be far too slow).

    Fields are walked as flat arrays (``ravel`` views of the C-ordered grids):
    plain indices let the compiler use vector registers, which an offset
    index (``i + first``, possibly negative to numba) prevents; the box of
    :meth:`curvature` is walked by rows of its own.
    """

    def gap(base, displacement, pressure, gap, contact, top, bottom):
        total, count, quartic = 0.0, 0.0, 0.0
        first, last = -1, -1
        columns = base.shape[1]
        for i in range(top, bottom):
            b, u, p, g, c = base[i], displacement[i], pressure[i], gap[i], contact[i]
            cells = 0.0
            for j in range(columns):
                value = b[j] + u[j]
                g[j] = value
                inside = p[j] > 0.0
                c[j] = inside
                # selections, not branches: they keep the loop on vector registers
                total += value if inside else 0.0
                cells += 1.0 if inside else 0.0
                square = u[j] * u[j]
                quartic += square * square
            if cells > 0.0:
                last = i + 1
                if first < 0:
                    first = i
            count += cells
        return total, count, quartic, first, last

    def norm(gap, contact, base, displacement, shift, top, bottom):
        norm, overlaps, quartic = 0.0, 0.0, 0.0
        rows, columns = gap.shape
        for i in range(rows):
            if top <= i < bottom:
                g, c = gap[i], contact[i]
                for j in range(columns):
                    value = g[j] - shift
                    inside = c[j]
                    norm += value * value if inside else 0.0
                    overlaps += 1.0 if value < 0.0 and not inside else 0.0
            else:   # no contact on these rows, and no gap written: the free cells' gap from its terms
                b, u = base[i], displacement[i]
                for j in range(columns):
                    value = (b[j] + u[j]) - shift
                    overlaps += 1.0 if value < 0.0 else 0.0
                    square = u[j] * u[j]
                    quartic += square * square
        return norm, overlaps, quartic

    def direction(direction, gap, contact, beta, shift):
        numerator = 0.0
        for k in range(gap.size):
            g = gap[k] - shift
            value = beta * direction[k] + g if contact[k] else 0.0
            direction[k] = value
            numerator += value * g
        return numerator

    def mask(buffer, gap, contact, top, left, shift):
        rows, columns = buffer.shape
        for i in range(rows):
            b, g, c = buffer[i], gap[top + i, left:left + columns], contact[top + i, left:left + columns]
            for j in range(columns):
                b[j] = g[j] - shift if c[j] else 0.0

    def preconditioned(field, buffer, contact, top, left):
        inside, product, total = 0.0, 0.0, 0.0
        rows, columns = field.shape
        for i in range(rows):
            f, b, c = field[i], buffer[i], contact[top + i, left:left + columns]
            for j in range(columns):
                inside += f[j] if c[j] else 0.0
                product += f[j] * b[j]
                total += b[j]
        return inside, product, total

    def direction_box(direction, field, gap, contact, beta, mean, first, last, top, left, shift):
        numerator = 0.0
        rows, columns = field.shape
        width = direction.shape[1]
        for i in range(first, last):
            d = direction[i]
            if i < top or i >= top + rows:
                for j in range(width):
                    d[j] = 0.0
                continue
            f, g, c = field[i - top], gap[i, left:left + columns], contact[i, left:left + columns]
            for j in range(left):
                d[j] = 0.0
            for j in range(left + columns, width):
                d[j] = 0.0
            b = d[left:left + columns]
            for j in range(columns):
                value = beta * b[j] + f[j] - mean if c[j] else 0.0
                b[j] = value
                numerator += value * (g[j] - shift)
        return numerator

    def curvature(response, direction, contact, first, second):
        product, inside, total = 0.0, 0.0, 0.0
        rows, columns = response.shape
        for i in range(rows):
            r = response[i]
            d = direction[first + i, second:second + columns]
            c = contact[first + i, second:second + columns]
            for j in range(columns):
                product += r[j] * d[j]
                inside += r[j] if c[j] else 0.0
                total += d[j]
        return product, inside, total

    def advance(fresh, pressure, direction, gap, contact, step, entry, shift):
        total = 0.0
        for k in range(gap.size):
            g = gap[k] - shift
            value = max(pressure[k] - step * direction[k], 0.0) if contact[k] else (-entry * g if g < 0.0 else 0.0)
            fresh[k] = value
            total += value
        return total

    def rescale(fresh, pressure, factor):
        moved, total = 0.0, 0.0
        for k in range(fresh.size):
            value = fresh[k] * factor
            fresh[k] = value
            moved += abs(value - pressure[k])
            total += value
        return moved, total

    def multiply(spectrum, multiplier):
        rows, columns = multiplier.shape
        for i in range(rows):
            s, m = spectrum[i], multiplier[i]
            for j in range(columns):
                s[j] = s[j] * m[j]


def _dot(a, b):
    """Sum of ``a * b`` (flat or 2-D) in numpy's own loop: BLAS threads stall when the cores are busy."""
    axes = "ij"[:a.ndim]
    return float(np.einsum(f"{axes},{axes}->", a, b))


class NumpyPasses:
    """The passes as numpy expressions, with the same arguments and results as :class:`_Loops`."""

    @staticmethod
    def gap(base, displacement, pressure, gap, contact, top, bottom):
        rows = slice(top, bottom)
        np.add(base[rows], displacement[rows], out=gap[rows])
        np.greater(pressure[rows], 0.0, out=contact[rows])
        touched = np.flatnonzero(contact[rows].any(axis=1))
        first, last = (int(touched[0]) + top, int(touched[-1]) + top + 1) if touched.size else (-1, -1)
        return (float(gap[rows].sum(where=contact[rows])), float(np.count_nonzero(contact[rows])),
                float(np.abs(displacement[rows]).max(initial=0.0)) ** 4, first, last)

    @staticmethod
    def norm(gap, contact, base, displacement, shift, top, bottom):
        rows = slice(top, bottom)
        centred = np.subtract(gap[rows], shift)
        inside = np.where(contact[rows], centred, 0.0)
        # gap < shift on a free cell: the overlap is where the centred gap outside the contact set is negative
        overlaps = np.count_nonzero(centred - inside < 0.0)
        quartic = 0.0
        for other in (slice(0, top), slice(bottom, None)):
            overlaps += np.count_nonzero(base[other] + displacement[other] - shift < 0.0)
            quartic = max(quartic, float(np.abs(displacement[other]).max(initial=0.0)) ** 4)
        return _dot(inside, inside), float(overlaps), quartic

    @staticmethod
    def direction(direction, gap, contact, beta, shift):
        centred = np.subtract(gap, shift)
        np.multiply(direction, beta, out=direction)
        np.add(direction, centred, out=direction)
        np.multiply(direction, contact, out=direction)
        return _dot(direction, centred)

    @staticmethod
    def mask(buffer, gap, contact, top, left, shift):
        box = (slice(top, top + buffer.shape[0]), slice(left, left + buffer.shape[1]))
        np.subtract(gap[box], shift, out=buffer)
        np.multiply(buffer, contact[box], out=buffer)

    @staticmethod
    def preconditioned(field, buffer, contact, top, left):
        box = (slice(top, top + field.shape[0]), slice(left, left + field.shape[1]))
        return float(field.sum(where=contact[box])), _dot(field, buffer), float(buffer.sum())

    @staticmethod
    def direction_box(direction, field, gap, contact, beta, mean, first, last, top, left, shift):
        box = (slice(top, top + field.shape[0]), slice(left, left + field.shape[1]))
        rows = slice(min(first, box[0].start), max(last, box[0].stop))   # the box's rows and the old direction's
        np.multiply(direction[rows], beta, out=direction[rows])
        direction[box] += field
        if mean:
            direction[box] -= mean
        np.multiply(direction[rows], contact[rows], out=direction[rows])
        return _dot(direction[rows], gap[rows] - shift)

    @staticmethod
    def curvature(response, direction, contact, first, second):
        box = (slice(first, first + response.shape[0]), slice(second, second + response.shape[1]))
        return _dot(response, direction[box]), float(response.sum(where=contact[box])), float(direction[box].sum())

    @staticmethod
    def advance(fresh, pressure, direction, gap, contact, step, entry, shift):
        np.multiply(direction, step, out=fresh)
        np.subtract(pressure, fresh, out=fresh)
        np.maximum(fresh, 0.0, out=fresh)
        if entry:
            overlap = ~contact & (gap < shift)
            fresh[overlap] = -entry * (gap[overlap] - shift)
        return float(fresh.sum())

    @staticmethod
    def rescale(fresh, pressure, factor):
        np.multiply(fresh, factor, out=fresh)
        return float(np.abs(fresh - pressure).sum()), float(fresh.sum())

    @staticmethod
    def multiply(spectrum, multiplier):
        np.multiply(spectrum, multiplier, out=spectrum)
