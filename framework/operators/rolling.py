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
On the loaded cell's own column each interval is integrated in two halves (the
cell edges, where the kernel's derivative is logarithmically singular, are at
their ends), each half in pieces of 1, 1, 2, 4 ... wake lengths from its start
(so the weight is resolved whatever ``L`` is), by Gauss-Legendre graded towards
both ends of each piece; on the other columns, where the kernel is analytic
along the motion, each interval whole, in the same pieces, by plain
Gauss-Legendre (16 nodes one column off, 10 farther: a third of the kernel
evaluations, which are most of the build). Checked against adaptive quadrature
in the tests to 1e-10.
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


def exponential_filter(kernel, spacing, count, length, nodes=None):
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
    nodes : int, optional
        For a kernel analytic along the whole line (Love's kernel off the
        loaded cell's own column): each interval whole, in pieces of 1, 1, 2,
        4 ... wake lengths, by plain Gauss-Legendre with ``nodes`` nodes per
        piece. By default each interval in two halves, graded towards the cell
        edges (16 nodes a piece).

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
    # their ends), or whole for an analytic kernel, each part in pieces from its start of 1, 1, 2, 4, ...
    # 32 wake lengths (the weight exp(-xi/L) is smooth on each; beyond 64 L it is below 1e-27),
    # integrated by Gauss-Legendre graded towards both ends of every piece, or plain for an analytic kernel.
    if nodes is None:
        parts = np.stack([np.zeros_like(widths), 0.5 * widths, widths], axis=1)       # (intervals, 3)
        rule, rule_weights = _GRADE, _GRADE_WEIGHTS
    else:
        parts = np.stack([np.zeros_like(widths), widths], axis=1)
        abscissae, rule_weights = np.polynomial.legendre.leggauss(nodes)
        rule, rule_weights = 0.5 * (abscissae + 1.0), 0.5 * rule_weights
    marks = length * np.array([0.0, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0])
    edges = np.minimum(parts[:, :-1, None] + marks, parts[:, 1:, None])              # (intervals, parts, 8)
    edges = np.concatenate([edges, parts[:, 1:, None]], axis=2)                      # the part's end last
    low, high = edges[..., :-1], edges[..., 1:]
    used = high > low
    interval = np.broadcast_to(np.arange(starts.size)[:, None, None], used.shape)[used]
    low, span = low[used], (high - low)[used]
    xi = low[:, None] + span[:, None] * rule                                           # (pieces, nodes)
    weights = span[:, None] * rule_weights * np.exp(-xi / length) / length
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


#: Plain Gauss-Legendre nodes a piece for the columns of Love's kernel one cell off the loaded one, and farther:
#: there the kernel is analytic along the motion, the nearest singularity (a cell edge's, across) half a cell and
#: 1.5 cells away; against adaptive quadrature, 16 and 10 nodes give 1e-13 (tests/test_rolling_operator.py).
_OFF_COLUMN_NODES = {1: 16, 2: 10}


def _love_along(grid, axis):
    """Love's kernel (per unit compliance) at offsets ``x`` along ``axis``, against the other axis's offsets.

    Returns ``(kernel, expand, groups)``: the kernel is even across the motion,
    so it is evaluated on the distinct ``|offsets|`` of the other axis only,
    ``kernel(x, columns)`` on those of ``columns`` (an index array), and
    ``expand(values)`` takes such columns to the wrapped layout of that axis;
    ``groups`` pairs the columns with the quadrature of
    :func:`exponential_filter` (``nodes``) they take: the loaded cell's own
    column (the derivative singular at its edges) the graded rule, the next
    and the farther ones plain rules (:data:`_OFF_COLUMN_NODES`).
    """
    other = 1 - axis
    (dx1, dx2), shape = grid.spacing, grid.shape
    wrapped = np.nan_to_num(wrapped_offsets(shape[other], grid.spacing[other], False))
    across, index = np.unique(np.abs(wrapped), return_inverse=True)
    cells = np.rint(across / grid.spacing[other])
    groups = [(np.flatnonzero(cells == 0), None), (np.flatnonzero(cells == 1), _OFF_COLUMN_NODES[1]),
              (np.flatnonzero(cells >= 2), _OFF_COLUMN_NODES[2])]

    def kernel(x, columns=slice(None)):
        x = np.asarray(x, dtype=float)[:, None]
        x1, x2 = (x, across[None, columns]) if axis == 0 else (across[None, columns], x)
        return surface_displacement(x1, x2, half1=dx1 / 2, half2=dx2 / 2)

    def expand(values):
        out = values[:, index]
        out[:, shape[other]] = 0.0  # the unused offset -n of the wrapped layout
        return out

    return kernel, expand, [(columns, nodes) for columns, nodes in groups if columns.size]


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
        mixed = mixed_mode_kernel(grid)                      # (x, modes): open axis = the motion axis

        def along(x, columns=slice(None)):
            return mixed(x)[:, columns]
        expand, groups = None, [(slice(None), None)]         # every mode: its derivative singular at the edges
    else:
        along, expand, groups = _love_along(grid, axis)
    sign = np.sign(speed)

    def oriented(x, columns=slice(None)):                   # the filter looks ahead, along the motion
        return along(sign * np.asarray(x), columns)

    base = oriented(np.arange(-(n - 1), n) * h)
    total = series.c0 * base
    for c, lam in series.terms:
        for columns, nodes in groups:
            total[:, columns] += c * exponential_filter(lambda x: oriented(x, columns), h, n, abs(speed) * lam,
                                                        nodes)
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
