"""A warm-started contact solve on an open grid that iterates on a box around the contact (the stepper's solve)."""
from dataclasses import replace

import numpy as np

from .solver import solve_normal

__all__ = ["BOX_CELLS", "BOX_MARGIN", "solve_boxed"]


#: The box a warm-started solve iterates on holds the start's contact grown by this fraction of its extent
#: (and :data:`BOX_CELLS` cells at least) on every side.
BOX_MARGIN = 0.25
BOX_CELLS = 4


def solve_boxed(operator, compliance, base, *, stiffness, options, initial, cell_area, load=None, approach=None):
    """A contact solve on an open grid that iterates on a box around the cells the contact can reach.

    The box holds the start's contact (the last step's, for a warm start) grown by :data:`BOX_MARGIN`
    of its extent on every side; the conjugate gradients run on it alone, each product an FFT of twice
    the box instead of twice the grid (a transient roll over a 512 x 256 grid: 128^2 instead of
    1024 x 512). The pressure outside the box is zero, which is the solution wherever the gap there
    stays open: the whole grid's displacement is computed once at the end, and a cell outside the box
    that interpenetrates (beyond the solver's residual tolerance) sends the solve to the whole grid,
    started from the box's pressure. Without a start, or when the box would cover most of the grid,
    the whole grid from the beginning.
    """
    def apply(pressure):
        return operator.apply(pressure, compliance, copy=False)

    def within(field, window):       # a window of the box (the box itself when the window is all of it)
        return operator.apply_window(field, box if window == (slice(None), slice(None)) else window, compliance,
                                     copy=False)

    common = dict(window=operator.window, diagonal=compliance * operator.diagonal, precondition=stiffness,
                  cell_area=cell_area, load=load, approach=approach, options=options)
    whole = dict(common, apply_window=lambda field, window: operator.apply_window(field, window, compliance,
                                                                                   copy=False))
    support = None if initial is None else np.asarray(initial) > 0
    if support is None or not support.any():
        return solve_normal(apply, base, initial=initial, **whole)
    box = []
    for axis, n in enumerate(base.shape):
        cells = np.flatnonzero(support.any(axis=1 - axis))
        grow = max(BOX_CELLS, int(np.ceil(BOX_MARGIN * (cells[-1] - cells[0] + 1))))
        first, last = cells[0] - grow, cells[-1] + 1 + grow
        # sides of whole multiples of 32 cells: a run meets few box shapes, each planned once
        size = min(n, -(-(last - first) // 32) * 32)
        first = min(max(0, first - (size - (last - first)) // 2), n - size)
        box.append(slice(first, first + size))
    box = tuple(box)
    if (box[0].stop - box[0].start) * (box[1].stop - box[1].start) > 0.5 * base.size:
        return solve_normal(apply, base, initial=initial, **whole)
    boxed = solve_normal(lambda p: within(p, box), base[box], initial=np.asarray(initial)[box],
                         apply_window=within, **common)
    pressure = np.zeros(base.shape)
    pressure[box] = boxed.pressure
    displacement = operator.apply(pressure, compliance)
    gap = base + displacement - boxed.approach
    outside = np.ones(base.shape, dtype=bool)
    outside[box] = False
    scale = max(np.abs(displacement).max(), np.finfo(float).tiny)
    if -gap[outside].min(initial=0.0) > options.residual_tolerance * scale:    # the contact left the box
        return solve_normal(apply, base, initial=pressure, **whole)
    return replace(boxed, pressure=pressure, displacement=displacement, gap=gap)
