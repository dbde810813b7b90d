"""Surface stiffness of the half-space: the Fourier inverse of the compliance, to precondition the contact solver.

The normal surface displacement of a half-space under a pressure is, mode by
mode, ``u(q) = C* (2/|q|) p(q)`` (:class:`SurfaceCompliance`'s continuous
kernel); its inverse, the pressure that makes a displacement, multiplies by
``|q|/2`` per unit compliance. Restricted to the contact set, this inverse is
an approximate inverse of the contact set's influence matrix, whose condition
number grows with the cells across the contact (the displacement operator
smooths like ``1/|q|``): conjugate gradients preconditioned by it need far
fewer iterations, and a number that grows more slowly under refinement (the
idea of Vollebregt, J. Comput. Phys. 257 (2014) 333-351, in its simplest
form: no deflation, no treatment of the contact's edge).

Applied on a box holding the contact set (:meth:`SurfaceStiffness.window`)
as if the box were periodic: any positive definite operator preconditions
conjugate gradients correctly; this one costs an FFT pair of the box,
unpadded (a DC-FFT product costs a pair of twice the grid along each open
axis), also on a periodic grid, where the products need the whole grid.
"""
import numpy as np

from .. import _fused, fft
from .convolution import wavenumbers
from .surface import box_around, most_recent


class SurfaceStiffness:
    """``|q|/2`` applied to fields on boxes of a grid (per unit contact compliance; any factor is immaterial).

    The mean mode, where ``|q|`` vanishes, gets the stiffness of the longest
    wave the box holds, so that the operator is positive definite.

    Parameters
    ----------
    grid : framework.Grid
        The surface grid; its spacing sets the wavenumbers.
    """

    #: Box shapes whose FFT plans and buffers are kept, the most recently used: a contact that shrinks from
    #: the whole grid (a load-controlled start) leaves no plan of the whole grid behind (a 4096^2 one is
    #: 0.4 GB).
    KEPT = 3

    def __init__(self, grid):
        self.spacing = grid.spacing
        self._boxes = {}    # box shape -> (FFT pair, multiplier times the pair's normalisation), oldest first

    def _plan(self, shape):
        shape = tuple(shape)

        def build():
            pair = fft.RealFFTPair(shape)
            q = np.hypot(*wavenumbers(shape, self.spacing))
            longest = [2 * np.pi / (n * d) for n, d in zip(shape, self.spacing) if n > 1]
            q[0, 0] = min(longest) if longest else 1.0 / max(self.spacing)
            return pair, 0.5 * q * pair.normalisation

        def current(plan):   # made for the FFT backend and threads in use
            return (plan[0].backend, plan[0].threads) == (fft.get_backend(), fft.THREADS)

        return most_recent(self._boxes, shape, build, self.KEPT, current)

    def window(self, support):
        """Slices of a box holding ``support`` (boolean, the grid's shape) to apply the operator on
        (:func:`framework.operators.surface.box_around`: sides multiples of 32, planned boxes reused)."""
        return box_around(support, self._boxes)

    def input(self, shape):
        """The operator's input buffer for fields of ``shape``: a field written there is not copied by
        :meth:`apply`, nor changed by it."""
        return self._plan(tuple(shape))[0].real_in

    def apply(self, field, copy=True):
        """``|q|/2`` times ``field`` (any 2-D shape, taken as periodic) [per m]; ``copy=False`` returns the
        operator's own buffer, overwritten by the next call on a box of that shape."""
        pair, multiplier = self._plan(np.shape(field))
        pair.forward_from(field)
        _fused.multiply(pair.spectrum, multiplier)
        pair.inverse()
        return pair.real_out.copy() if copy else pair.real_out
