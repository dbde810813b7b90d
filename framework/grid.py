"""The surface grid and the cuboid layers below it."""
from dataclasses import dataclass

import numpy as np

from ._validation import check_bool, check_positive_int, check_quantity
from .errors import ParameterError


@dataclass(frozen=True)
class Grid:
    """Cell-centred surface grid centred on the origin, with optional subsurface layers.

    Parameters
    ----------
    shape : tuple of int
        Number of surface cells ``(n1, n2)`` along x1 and x2.
    size : tuple of float
        Side lengths ``(L1, L2)`` of the surface grid [m].
    depth : float, optional
        Depth of the subsurface box [m]; needed when ``layers > 0``.
    layers : int
        Number of cuboid layers of uniform thickness ``depth / layers``; subsurface
        fields are evaluated at the layer centres.
    periodic : tuple of bool
        Per surface axis: periodic (circular convolution) or not (DC-FFT, the
        exact linear convolution).

    Lengths lie between 1e-12 and 1e6 m (``framework._validation.LIMITS``). A
    simulation needs at least 3 cells along a non-periodic axis.
    """

    shape: tuple
    size: tuple
    depth: float = None
    layers: int = 0
    periodic: tuple = (False, False)

    def __post_init__(self):
        shape, size, periodic = self.shape, self.size, self.periodic
        if not isinstance(shape, (tuple, list)) or len(shape) != 2:
            raise ParameterError(f"shape must be a pair (n1, n2) of cell counts, got {shape!r}")
        shape = tuple(check_positive_int(n, name=f"shape[{i}]") for i, n in enumerate(shape))
        if not isinstance(size, (tuple, list)) or len(size) != 2:
            raise ParameterError(f"size must be a pair (L1, L2) of lengths [m], got {size!r}")
        size = tuple(check_quantity(s, name=f"size[{i}]", unit="m") for i, s in enumerate(size))
        if not isinstance(periodic, (tuple, list)) or len(periodic) != 2:
            raise ParameterError(f"periodic must be a pair of booleans, got {periodic!r}")
        periodic = tuple(check_bool(p, name=f"periodic[{i}]") for i, p in enumerate(periodic))
        layers = check_positive_int(self.layers, name="layers", minimum=0)
        depth = self.depth
        if layers > 0 and depth is None:
            raise ParameterError(f"depth is missing: layers = {layers} needs the depth [m] of the subsurface box")
        if depth is not None:
            depth = check_quantity(depth, name="depth", unit="m")
        object.__setattr__(self, "shape", shape)
        object.__setattr__(self, "size", size)
        object.__setattr__(self, "periodic", periodic)
        object.__setattr__(self, "layers", layers)
        object.__setattr__(self, "depth", depth)

    @property
    def spacing(self):
        """Cell sizes ``(dx1, dx2)`` [m]."""
        return (self.size[0] / self.shape[0], self.size[1] / self.shape[1])

    @property
    def cell_area(self):
        """Area of one surface cell [m^2]."""
        dx1, dx2 = self.spacing
        return dx1 * dx2

    @property
    def layer_thickness(self):
        """Thickness ``dx3`` of one subsurface layer [m] (None without layers)."""
        return self.depth / self.layers if self.layers else None

    @property
    def x1(self):
        """Cell-centre coordinates along x1 [m]."""
        return (np.arange(self.shape[0]) + 0.5) * self.spacing[0] - 0.5 * self.size[0]

    @property
    def x2(self):
        """Cell-centre coordinates along x2 [m]."""
        return (np.arange(self.shape[1]) + 0.5) * self.spacing[1] - 0.5 * self.size[1]

    @property
    def x3(self):
        """Depths of the layer centres [m] (empty without layers)."""
        if not self.layers:
            return np.zeros(0)
        return (np.arange(self.layers) + 0.5) * self.layer_thickness

    def coordinates(self):
        """Cell-centre coordinates ``(X1, X2)`` as two ``(n1, n2)`` arrays [m]."""
        return np.meshgrid(self.x1, self.x2, indexing="ij")
