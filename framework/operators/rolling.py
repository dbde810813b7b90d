"""The half-space under a body moving at constant velocity: the steady-state compliance.

In the body's frame a material point now at ``x`` was at ``x + V s`` a time
``s`` ago (the body moves with velocity ``V`` over the material, the material
flows by at ``-V``). With the displacement ``P = K * p`` of the pressure
history and ``C*(t) = c0 + sum_k c_k (1 - exp(-t/lambda_k))``, the hereditary
integral along the material path gives, after an integration by parts
(THEORY.md sec. 7; Hunter 1961),

    u3(x) = c0 P(x) + sum_k c_k int_0^inf (1/lambda_k) exp(-s/lambda_k) P(x + V s) ds.

For a pressure piecewise constant on the cells, ``P = K * p`` with Love's
kernel, so the filter folds into the kernel:

    u3 = (c0 K + sum_k c_k K_k) * p,  K_k(r) = int_0^inf (1/L_k) exp(-xi/L_k) K(r + xi m) dxi,

``m`` the unit vector of the motion and ``L_k = |V| lambda_k`` the length of
the k-th wake. ``K_k`` is evaluated from the closed-form kernel at any offset,
on and beyond the grid, so the grid need only hold the contact: the wake
behind it is in the kernel. The operator is a convolution (one DC-FFT per
application), not symmetric. Limits: ``|V| -> 0`` gives the relaxed kernel
``C*(inf) K``, ``|V| -> inf`` the glassy one ``c0 K``.

The filter is computed by a backward scan along the motion, one interval of
offsets at a time, ``K_f(r) = int_0^h w K(r + xi) dxi + exp(-h/L) K_f(r + h)``,
from far beyond the grid (geometrically growing intervals, until ``40 L`` and
a kernel 1e-17 of its value on the grid) down to the most negative offset.
Each interval is integrated in two halves (the cell edges, where the kernel's
derivative is logarithmically singular, are at their ends), each half in
pieces of 1, 1, 2, 4 ... wake lengths from its start (so the weight is
resolved whatever ``L`` is), by Gauss-Legendre graded towards both ends of each
piece. Checked against adaptive quadrature in the tests to 1e-10.
"""
import numpy as np

from .._validation import check_positive
from ..errors import ParameterError
from .convolution import wrapped_offsets
from .kernels import surface_displacement
from .surface import SurfaceCompliance, mixed_mode_kernel

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(16)
_T = 0.5 * (_NODES + 1.0)
_GRADE = _T**3 * (10.0 - 15.0 * _T + 6.0 * _T**2)       # its Jacobian vanishes to second order at both ends
_GRADE_WEIGHTS = 0.5 * _WEIGHTS * 30.0 * _T**2 * (1.0 - _T) ** 2


def exponential_filter(kernel, spacing, count, length):
    """``K_f(j h) = int_0^inf (1/L) exp(-xi/L) K(j h + xi) dxi`` for ``j = -(count-1) .. count-1``.

    Parameters
    ----------
    kernel : callable
        ``kernel(x)`` -> array ``(len(x), ...)``: the kernel at offsets ``x`` [m]
        along the motion (any other axes after the first), smooth except for a
        logarithmically singular derivative at odd multiples of ``spacing/2``
        (the cell edges), decaying or growing at most logarithmically far away.
    spacing : float
        Cell size ``h`` along the motion [m].
    count : int
        Number of cells along the motion.
    length : float
        Wake length ``L`` [m] (> 0).

    Returns
    -------
    ndarray
        ``(2 count - 1, ...)``, the filtered kernel at ascending offsets.
    """
    length = check_positive(length, name="wake length", unit="m")
    near = np.arange(-(count - 1), count + 1) * spacing      # uniform offsets, one cell beyond the grid
    far, step = [near[-1]], spacing
    while far[-1] - near[-1] < 40.0 * length or len(far) < 8:   # exp(-40) = 4e-18: the rest is negligible
        step *= 1.5
        far.append(far[-1] + step)
    starts = np.concatenate([near[:-1], far[:-1]])
    widths = np.diff(np.concatenate([near, far[1:]]))
    # Each interval in two halves (the cell edges, where the kernel's derivative is singular, are at
    # their ends), each half in pieces from its start of 1, 1, 2, 4, ... 32 wake lengths (the weight
    # exp(-xi/L) is smooth on each; beyond 64 L it is below 1e-27), integrated by Gauss-Legendre
    # graded towards both ends of every piece.
    halves = np.stack([np.zeros_like(widths), 0.5 * widths, widths], axis=1)          # (intervals, 3)
    marks = length * np.array([0.0, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0])
    edges = np.minimum(halves[:, :2, None] + marks, halves[:, 1:, None])               # (intervals, 2, 8)
    edges = np.concatenate([edges, halves[:, 1:, None]], axis=2)                       # the half's end last
    low, high = edges[..., :-1], edges[..., 1:]
    used = high > low
    interval = np.broadcast_to(np.arange(starts.size)[:, None, None], used.shape)[used]
    low, span = low[used], (high - low)[used]
    xi = low[:, None] + span[:, None] * _GRADE                                          # (pieces, nodes)
    weights = span[:, None] * _GRADE_WEIGHTS * np.exp(-xi / length) / length
    values = kernel((starts[interval][:, None] + xi).ravel())
    values = values.reshape(xi.shape + values.shape[1:])
    pieces = np.zeros((starts.size,) + values.shape[2:])
    np.add.at(pieces, interval, np.einsum("pn,pn...->p...", weights, values))
    decay = np.exp(-widths / length)
    out = np.zeros(pieces.shape)
    carry = np.zeros(pieces.shape[1:])
    for i in range(starts.size - 1, -1, -1):
        carry = pieces[i] + decay[i] * carry
        out[i] = carry
    return out[: 2 * count - 1]


def _love_along(grid, axis):
    """Love's kernel (per unit compliance) at offsets ``x`` along ``axis``, against the other axis's offsets.

    Returns ``(kernel, expand)``: the kernel is even across the motion, so it is
    evaluated on the distinct ``|offsets|`` of the other axis only, and
    ``expand(values)`` takes such columns to the wrapped layout of that axis.
    """
    other = 1 - axis
    (dx1, dx2), shape = grid.spacing, grid.shape
    wrapped = np.nan_to_num(wrapped_offsets(shape[other], grid.spacing[other], False))
    across, index = np.unique(np.abs(wrapped), return_inverse=True)

    def kernel(x):
        x = np.asarray(x, dtype=float)[:, None]
        x1, x2 = (x, across[None, :]) if axis == 0 else (across[None, :], x)
        return surface_displacement(x1, x2, half1=dx1 / 2, half2=dx2 / 2)

    def expand(values):
        out = values[:, index]
        out[:, shape[other]] = 0.0  # the unused offset -n of the wrapped layout
        return out

    return kernel, expand


def _wrap(values, count):
    """Ascending offsets ``-(count-1)..count-1`` (first axis) to the DC-FFT wrap-around order, offset -n zero."""
    wrapped = np.zeros((2 * count,) + values.shape[1:])
    wrapped[:count] = values[count - 1:]
    wrapped[count + 1:] = values[: count - 1]
    return wrapped


def check_steady(grid, series, velocity):
    """Raise unless a steady state exists for this grid, material and motion; return the motion's axis.

    The motion must run along an open grid axis; a fluid (``flow > 0``) has no
    steady state (its groove deepens without bound), and a solid without
    instantaneous compliance (Kelvin-Voigt) no bounded pressure (it jumps at
    the leading edge).
    """
    axis = 0 if velocity[1] == 0 else 1
    if grid.periodic[axis]:
        raise ParameterError(f"velocity: a steady state is solved along an open grid axis; axis {axis} of the grid "
                             f"is periodic (periodic={grid.periodic}): make it open, or roll transiently (the "
                             f"material then comes round again)")
    if series.flow:
        raise ParameterError("material: a fluid (a Maxwell material, flow > 0) has no steady rolling state: the "
                             "groove its flow leaves behind the body deepens without bound, so the approach is "
                             "infinite; roll it transiently (steady=False) over a finite distance instead")
    if series.c0 <= 0:
        raise ParameterError(f"material: a solid without instantaneous compliance (C*(0) = {series.c0:g} 1/Pa, "
                             f"Kelvin-Voigt) has no bounded steady rolling pressure (it jumps at the leading edge); "
                             f"roll it transiently")
    return axis


def steady_rolling_kernel(grid, series, velocity):
    """The wrapped kernel ``c0 K + sum_k c_k K_k`` [m/Pa] of a body moving at ``velocity`` (see the module).

    Parameters
    ----------
    grid : framework.Grid
        Open along the motion; the other axis open or periodic (a line contact).
    series : framework.materials.ComplianceSeries
        The contact compliance (no flow term: a fluid has no steady state).
    velocity : tuple of float
        ``(v1, v2)`` [m/s] of the body over the material, along one grid axis.

    Returns
    -------
    ndarray
        The kernel in the layout :class:`SurfaceCompliance` takes (``kernel=``).
    """
    axis = check_steady(grid, series, velocity)
    speed = float(velocity[axis])
    n, h = grid.shape[axis], grid.spacing[axis]
    if grid.periodic[1 - axis]:
        along, expand = mixed_mode_kernel(grid), None         # (x, modes): open axis = the motion axis
    else:
        along, expand = _love_along(grid, axis)
    sign = np.sign(speed)

    def oriented(x):                                        # the filter looks ahead, along the motion
        return along(sign * np.asarray(x))

    base = oriented(np.arange(-(n - 1), n) * h)
    total = series.c0 * base
    for c, lam in series.terms:
        total = total + c * exponential_filter(oriented, h, n, abs(speed) * lam)
    if sign < 0:
        total = total[::-1]
    if expand is not None:
        total = expand(total)
    wrapped = _wrap(total, n)
    return wrapped if axis == 0 else np.moveaxis(wrapped, 0, 1)


class SteadyRollingCompliance(SurfaceCompliance):
    """Surface displacement [m] of a pressure [Pa] under a body in steady motion: ``u3 = (c0 K + sum c_k K_k) * p``.

    A :class:`SurfaceCompliance` whose kernel carries the compliance and the
    wake (see the module docstring); ``apply`` returns the displacement itself.

    Parameters
    ----------
    grid : framework.Grid
        The surface grid in the body's frame.
    series : framework.materials.ComplianceSeries
        The material's contact compliance.
    velocity : tuple of float
        ``(v1, v2)`` [m/s] of the body over the material, along one axis.
    """

    def __init__(self, grid, series, velocity):
        self.kernel = steady_rolling_kernel(grid, series, velocity)
        super().__init__(grid, kernel=self.kernel)

    def symmetric(self):
        """The symmetric part ``(A + A^T)/2``: the kernel averaged with its reflection, a :class:`SurfaceCompliance`.

        Positive definite; the start of the steady solver (conjugate gradients apply to it).
        """
        open_axes = tuple(axis for axis in (0, 1) if not self.grid.periodic[axis])
        reflected = np.roll(np.flip(self.kernel, open_axes), 1, axis=open_axes)  # offset r -> -r, wrapped
        return SurfaceCompliance(self.grid, kernel=0.5 * (self.kernel + reflected))
