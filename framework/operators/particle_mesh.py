"""Eigenstrains on scattered cuboids at a cost that follows them: a coarse box and near-field corrections.

:class:`~framework.operators.eigenstrain.HalfSpaceEigenstrain` transforms the whole box around its
cuboids: a dispersion at 10 % pays for the nine tenths of matrix between its bodies. Here the
bodies' cuboids alone are the unknowns (the particle-mesh or precorrected-FFT idea: Hockney &
Eastwood 1988; Phillips & White 1997, IEEE TCAD 16(10) 1059):

1. **Far field on a coarse box.** Each fine cuboid's eigenstrain is spread onto the ``(p+1)^3``
   nearest cuboids of a lattice twice as coarse along each axis (:data:`COARSE`), with weights that
   match its moments up to order ``p`` (:data:`ORDER`); the half-space operator of that coarse box
   (the same :class:`HalfSpaceEigenstrain`: infinite-space, mirror and Boussinesq terms) gives the
   coarse strain, which the same weights interpolate back to the fine cuboids. The coarse cuboids are
   themselves cuboids (a source and, averaged, a target of size ``H`` where the fine ones are ``h``), so
   the weights match the moments of a fine cuboid *less* a coarse one: second cumulant
   ``(h^2 - H^2)/12`` per axis. Its error falls like ``(H/r)^(p+1)`` times the kernel (``r^-3``).
2. **Near field exact.** For every pair closer than :data:`NEAR` fine cuboids (a ball in index
   space) the coarse path's value is replaced by the fine operator's own: a table of ``exact - coarse``
   6 x 6 blocks per offset and per class of source cuboid (its parity along each axis within the
   coarse cells and, within :attr:`ParticleMeshEigenstrain.shallow` layers of the surface, its layer,
   since the mirror and Boussinesq terms and the one-sided stencils there depend on depth). The
   tables are made once, by the two operators applied to unit eigenstrains in small boxes.

The surface displacement of the eigenstrains (Betti's theorem, the contact's part of a coupling) takes the same
two paths: the coarse box's, interpolated to the grid's cells, and near tables for the cells within ``shallow``
layers of the surface (deeper ones' is smooth there).

Memory: the coarse box (an eighth of the cuboids of the hull box), the stencils and the tables;
time: the coarse product plus the near sums, ``O(bodies' cuboids x neighbours within NEAR)``.
The product approximates the fine operator's; :mod:`tests.test_particle_mesh` states by how much.
"""
import numpy as np

from .. import _fused
from ..errors import ParameterError, ShapeError
from ..grid import Grid
from .eigenstrain import CONTRACTION, PATCH_DEPTHS, HalfSpaceEigenstrain

#: Coarse cuboids per fine cuboid along each axis.
COARSE = 2
#: Order of the moments the stencils match (``ORDER + 1`` coarse cuboids per axis).
ORDER = 3
#: Radius of the near field [fine cuboids, in index space]: pairs within it are the fine operator's exactly.
NEAR = 8


def stencil_weights(x, nodes, cumulant):
    """Weights on coarse ``nodes`` (coarse units, centres) whose moments ``0 .. len(nodes) - 1`` are those of a
    point at ``x`` spread with second cumulant ``cumulant`` (a Gaussian's moments: the fine cuboid less the
    coarse one, ``(h^2 - H^2) / (12 H^2)``)."""
    k = len(nodes)
    # moments of x + N(0, cumulant): m_n = sum_j C(n, 2j) x^(n-2j) (2j-1)!! cumulant^j
    moments = np.zeros(k)
    for n in range(k):
        total, j, double_factorial = 0.0, 0, 1.0
        while 2 * j <= n:
            binomial = np.prod(np.arange(n - 2 * j + 1, n + 1)) / np.prod(np.arange(1, 2 * j + 1))
            total += binomial * x ** (n - 2 * j) * double_factorial * cumulant ** j
            j += 1
            double_factorial *= 2 * j - 1
        moments[n] = total
    vandermonde = np.vander(np.asarray(nodes, dtype=float), k, increasing=True).T
    return np.linalg.solve(vandermonde, moments)


def axis_stencils(indices, origin, order, cumulant, lowest=None, highest=None):
    """Coarse nodes ``(n, order + 1)`` and weights of fine cuboids ``indices`` along one axis whose coarse cell
    ``c`` holds the fine ones ``origin + 2c`` and ``origin + 2c + 1``; nodes at least ``lowest`` and at most
    ``highest`` where given (one-sided stencils at the surface, or at a grid's edge)."""
    indices = np.asarray(indices)
    k = order + 1
    cells = (indices - origin) // COARSE
    x = (indices - origin + 0.5) / COARSE - (cells + 0.5)            # within the coarse cell, coarse units
    first = cells - k // 2 + (x > 0)
    if highest is not None:
        first = np.minimum(first, highest - k + 1)
    if lowest is not None:
        first = np.maximum(first, lowest)
    nodes = first[:, None] + np.arange(k)
    weights = np.empty(nodes.shape)
    # a few distinct (x, first - cell) pairs (x = -1/4 or 1/4 with COARSE = 2): solve each once
    keys = np.stack([np.round(x * 4).astype(int), first - cells], axis=-1)
    unique, inverse = np.unique(keys, axis=0, return_inverse=True)
    for u, (quarter, shift) in enumerate(unique):
        weights[inverse.ravel() == u] = stencil_weights(quarter / 4, shift + np.arange(k), cumulant)
    return nodes, weights


class _CoarsePath:
    """The far-field path of fine cuboids ``cells`` ``(n, 3)`` (grid indices): spread to a coarse box, its
    half-space operator, interpolated back. ``origin`` ``(o1, o2)``: the fine index where coarse cells start
    along x1 and x2 (along x3 they start at the surface); ``extent``: the fine grid's surface cells ``(n1, n2)``;
    ``shifts``: every ``(c1, c2)`` the cells will be moved by (:meth:`shift`), for which the coarse grid covers the
    fine grid's surface too."""

    def __init__(self, spacing, poisson, cells, origin, extent, order, average, shifts=((0, 0),)):
        h = np.asarray(spacing, dtype=float)
        self.cells = np.asarray(cells)
        ratio = float(COARSE) ** 2
        source_cumulant = (1.0 / ratio - 1.0) / 12.0
        target_cumulant = source_cumulant if average else 0.0
        origins = (origin[0], origin[1], 0)
        stencils = {}
        for name, cumulant in (("source", source_cumulant), ("target", target_cumulant)):
            stencils[name] = [axis_stencils(self.cells[:, a], origins[a], order, cumulant, lowest=0 if a == 2 else None)
                              for a in range(3)]
        low = [min(stencils[n][a][0].min() for n in stencils) for a in range(3)]
        high = [max(stencils[n][a][0].max() for n in stencils) + 1 for a in range(3)]
        low[2] = 0
        shape = tuple(hi - lo for lo, hi in zip(low, high))
        spacing_c = COARSE * h
        # the coarse grid covers the fine grid's surface (``extent`` cells from index 0), and the box, so that its
        # Boussinesq patch is cut where the fine operator's is
        shifts = np.asarray(shifts, dtype=int).reshape(-1, 2)
        first = [min(low[a], int(np.min(-(origins[a] + shifts[:, a]) // COARSE))) for a in range(2)]
        last = [max(high[a], int(np.max((extent[a] - 1 - origins[a] - shifts[:, a]) // COARSE)) + 1) for a in range(2)]
        surface = [last[a] - first[a] for a in range(2)]
        grid = Grid(shape=tuple(surface), size=tuple(surface[a] * spacing_c[a] for a in range(2)),
                    depth=shape[2] * spacing_c[2], layers=shape[2])
        self.operator = HalfSpaceEigenstrain(grid, poisson, (low[0] - first[0], low[1] - first[1], 0), shape,
                                             average=average, folded=False)
        self.shape = shape
        # the fine grid's surface cells from the coarse grid's (surface_displacement): averages over a cell, as the
        # fine operator's are (a fine cell less a coarse one), clamped to the coarse grid at its edges
        self._mapping = (extent, order, source_cumulant, first, last)
        self.origin = (int(origins[0]), int(origins[1]))
        self._surface_stencils()
        # per axis: the first node of each cell's stencil and the weights (the stencils are tensor products: 200
        # bytes a cell for both sets, where a sparse matrix of their 64 products took 1.5 KB)
        self.first = np.stack([stencils["source"][a][0][:, 0] - low[a] for a in range(3)], axis=1).astype(np.int64)
        self.weights = {name: np.stack([stencils[name][a][1] for a in range(3)], axis=1) for name in stencils}
        self.volume = 1.0 / COARSE ** 3

    def _surface_stencils(self):
        extent, order, cumulant, first, last = self._mapping
        self._surface = []
        for a in range(2):
            nodes, weights = axis_stencils(np.arange(extent[a]), self.origin[a], order, cumulant, lowest=first[a],
                                           highest=last[a] - 1)
            self._surface.append((nodes - first[a], weights))

    def shift(self, cells):
        """The cells moved by ``cells`` ``(c1, c2)`` across the fine grid: the coarse box moves with them (nothing
        changes relative to them), its surface cells map onto the fine grid's anew."""
        self.origin = (self.origin[0] + int(cells[0]), self.origin[1] + int(cells[1]))
        self._surface_stencils()

    def spread(self, eigenstrain):
        """The coarse box's eigenstrain ``(M1, M2, M3, 6)`` of the cells' ``(n, 6)`` (the volume ratio included)."""
        coarse = np.zeros((*self.shape, 6))
        compiled = _fused._compiled and _fused.numba_available()
        (_stencil_loops()["spread"] if compiled else _spread_numpy)(
            self.first, self.weights["source"], np.ascontiguousarray(eigenstrain, dtype=float) * self.volume, coarse)
        return coarse

    def strain(self, eigenstrain, displacement=False):
        """The coarse path's strain ``(n, 6)`` at the cells from their eigenstrain ``(n, 6)``; with ``displacement``
        also its surface displacement over the fine grid, from the same spread (and, where the coarse box's surface
        map is its grid, the same surface transforms: a coupling iteration needs both)."""
        coarse = self.spread(eigenstrain)
        if displacement:
            strain, field = self.operator.strain(coarse, displacement=True)
        else:
            strain = self.operator.strain(coarse)
        out = np.zeros((len(self.first), 6))
        compiled = _fused._compiled and _fused.numba_available()
        (_stencil_loops()["gather"] if compiled else _gather_numpy)(self.first, self.weights["target"], strain, out)
        return (out, self._on_grid(field)) if displacement else out

    def surface_displacement(self, eigenstrain):
        """The coarse path's surface displacement ``(n1, n2)`` over the fine grid: the coarse operator's,
        interpolated."""
        return self._on_grid(self.operator.surface_displacement(self.spread(eigenstrain)))

    def _on_grid(self, field):
        """A field ``(N1, N2)`` on the coarse grid's surface cells interpolated to the fine grid's."""
        (nodes1, weights1), (nodes2, weights2) = self._surface
        rows = np.einsum("ik,ikj->ij", weights1, field[nodes1])                 # along x1, then x2
        return np.einsum("jk,ijk->ij", weights2, rows[:, nodes2])


def _stencil_flat(first, shape, a, b, c):
    return ((first[:, 0] + a) * shape[1] + first[:, 1] + b) * shape[2] + first[:, 2] + c


def _spread_numpy(first, weights, values, coarse):
    """``coarse[nodes of cell] += w1 w2 w3 values[cell]`` (numpy form)."""
    k = weights.shape[2]
    flat = coarse.reshape(-1, 6)
    for a, b, c in np.ndindex(k, k, k):
        w = weights[:, 0, a] * weights[:, 1, b] * weights[:, 2, c]
        index = _stencil_flat(first, coarse.shape, a, b, c)
        for component in range(6):
            flat[:, component] += np.bincount(index, weights=w * values[:, component], minlength=len(flat))


def _gather_numpy(first, weights, coarse, out):
    """``out[cell] += sum w1 w2 w3 coarse[nodes of cell]`` (numpy form)."""
    k = weights.shape[2]
    flat = coarse.reshape(-1, 6)
    for a, b, c in np.ndindex(k, k, k):
        w = weights[:, 0, a] * weights[:, 1, b] * weights[:, 2, c]
        out += w[:, None] * flat[_stencil_flat(first, coarse.shape, a, b, c)]


def _spread_loops(first, weights, values, coarse):
    k = weights.shape[2]
    for n in range(first.shape[0]):
        f1, f2, f3 = first[n, 0], first[n, 1], first[n, 2]
        for a in range(k):
            for b in range(k):
                wab = weights[n, 0, a] * weights[n, 1, b]
                for c in range(k):
                    w = wab * weights[n, 2, c]
                    node = coarse[f1 + a, f2 + b, f3 + c]
                    for component in range(6):
                        node[component] += w * values[n, component]


def _gather_loops(first, weights, coarse, out):
    k = weights.shape[2]
    for n in range(first.shape[0]):
        f1, f2, f3 = first[n, 0], first[n, 1], first[n, 2]
        for a in range(k):
            for b in range(k):
                wab = weights[n, 0, a] * weights[n, 1, b]
                for c in range(k):
                    w = wab * weights[n, 2, c]
                    node = coarse[f1 + a, f2 + b, f3 + c]
                    for component in range(6):
                        out[n, component] += w * node[component]


def _stencil_loops():
    """The stencils' spread and gather compiled (numba must be installed)."""
    if "spread" not in _compiled:
        jit = _fused._cache["numba"].njit(cache=True, nogil=True, fastmath={"reassoc", "nsz", "nnan", "contract"})
        _compiled["spread"], _compiled["gather"] = jit(_spread_loops), jit(_gather_loops)
    return _compiled


def ball_offsets(radius):
    """Index offsets ``(m, 3)`` within ``radius`` (Euclidean, index units), the zero offset first."""
    r = int(radius)
    grid = np.stack(np.meshgrid(*[np.arange(-r, r + 1)] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    keep = grid[(grid ** 2).sum(axis=1) <= radius * radius]
    order = np.argsort((keep ** 2).sum(axis=1), kind="stable")
    return keep[order]


#: Targets summed together, an offset at a time (their strains and sources stay in the caches while the offsets'
#: blocks stream).
CHUNK = 512


def _near_numpy(index, flat, group, deltas, group_class, table, source, out):
    """``out[:, t] += table[o, group_class[group[t], o]] @ source[s]`` over the offsets ``o``, ``s =
    index[flat[t] - deltas[o]]`` (the sentinel ``len(source) - 1``, a zero row, where no cuboid lies): numpy form."""
    count = source.shape[0] - 1
    for o, delta in enumerate(deltas):
        found = index[flat - delta]
        classes = group_class[group, o]
        hit = np.flatnonzero((found < count) & (classes >= 0))
        if hit.size:
            out[:, hit] += np.einsum("nab,nb->an", table[o, classes[hit]], source[found[hit], :6])


def _near_loops(index, starts, flat, deltas, group_class, table, source, out):
    """The near sums as loops, for numba. The targets are sorted by group (parities across, layer or parity down),
    so that a group's sources at one offset share one class and one block: :data:`CHUNK` targets of a group
    gather their sources' eigenstrains (rows of ``source``, padded to 8), then one 6 x 6 block multiplies them all
    (a loop over contiguous targets, which the compiler vectorises: 100 spheres at 8 cuboids per radius, near 8,
    3.2 -> 1.8 s; a 6 x 6 product per pair stayed scalar)."""
    gathered = np.empty((6, CHUNK))
    for g in range(starts.shape[0] - 1):
        for t0 in range(starts[g], starts[g + 1], CHUNK):
            t1 = min(t0 + CHUNK, starts[g + 1])
            m = t1 - t0
            for o in range(deltas.shape[0]):
                c = group_class[g, o]
                if c < 0:
                    continue
                delta = deltas[o]
                for k in range(m):
                    s = index[flat[t0 + k] - delta]
                    for b in range(6):
                        gathered[b, k] = source[s, b]
                block = table[o, c]
                u0, u1, u2 = gathered[0, :m], gathered[1, :m], gathered[2, :m]
                u3, u4, u5 = gathered[3, :m], gathered[4, :m], gathered[5, :m]
                for a in range(6):
                    y = out[a, t0:t1]
                    c0, c1, c2, c3, c4, c5 = block[a, 0], block[a, 1], block[a, 2], block[a, 3], block[a, 4], block[a, 5]
                    for k in range(m):
                        y[k] += c0 * u0[k] + c1 * u1[k] + c2 * u2[k] + c3 * u3[k] + c4 * u4[k] + c5 * u5[k]


_compiled = {}


def _near():
    """The near sums compiled (numba must be installed)."""
    if "near" not in _compiled:
        jit = _fused._cache["numba"].njit(cache=True, nogil=True, fastmath={"reassoc", "nsz", "nnan", "contract"})
        _compiled["near"] = jit(_near_loops)
    return _compiled["near"]


class ParticleMeshEigenstrain:
    """Strain at scattered cuboids of the half-space caused by eigenstrains on the same cuboids.

    Parameters
    ----------
    grid : framework.Grid
        Open grid with layers; the cuboids are ``dx1 x dx2 x dx3``.
    poisson : float
        Poisson ratio of the (homogeneous, isotropic) half-space.
    cells : array_like of int, shape (n, 3)
        The cuboids ``(i1, i2, layer)`` of the grid that hold eigenstrains (distinct).
    near : float
        Radius of the exact near field [fine cuboids]; see :data:`NEAR`.
    order : int
        Order of the moments the coarse stencils match (odd); see :data:`ORDER`.
    average : bool
        The Galerkin operator (strain averaged over each target cuboid), as
        :class:`~framework.operators.eigenstrain.HalfSpaceEigenstrain`'s ``average``.
    shifts : sequence of (int, int), optional
        Every ``(c1, c2)`` the cells will be moved by from here (:meth:`move`; a rolling run), so that the coarse
        grid is sized for them once; by default none.
    """

    def __init__(self, grid, poisson, cells, near=NEAR, order=ORDER, average=True, shifts=None):
        if any(grid.periodic):
            raise ParameterError(f"the particle-mesh eigenstrain operator needs an open grid, got "
                                 f"periodic={grid.periodic}")
        if not isinstance(average, bool):
            raise ParameterError(f"average must be a bool, got {average!r}")
        if not (isinstance(order, (int, np.integer)) and order >= 1 and order % 2 == 1):
            raise ParameterError(f"order must be an odd integer of at least 1, got {order!r}")
        if not (np.isfinite(near) and near >= 2):
            raise ParameterError(f"near must be a radius of at least 2 cuboids, got {near!r}")
        cells = np.asarray(cells)
        if cells.ndim != 2 or cells.shape[1] != 3 or not np.issubdtype(cells.dtype, np.integer):
            raise ParameterError(f"cells must be integer indices of shape (n, 3), got {cells.dtype} {cells.shape}")
        limits = np.array([*grid.shape, grid.layers])
        if len(cells) == 0 or np.any(cells < 0) or np.any(cells >= limits):
            raise ParameterError(f"cells must be a non-empty set of the grid's cuboids 0 .. {tuple(limits - 1)}")
        self.grid, self.poisson, self.average = grid, float(poisson), average
        self.spacing = (*grid.spacing, grid.layer_thickness)
        self.near, self.order = float(near), int(order)
        self.cells = cells.astype(np.int64)
        low = self.cells.min(axis=0)
        local = self.cells - low
        if len(np.unique(np.ravel_multi_index(tuple(local.T), tuple(local.max(axis=0) + 1)))) != len(cells):
            raise ParameterError("cells must be distinct cuboids")
        self.origin = (int(low[0]), int(low[1]))
        # sources deeper than this keep a class per parity: their mirror image and the surface are beyond the near
        # field, and their targets' stencils are two-sided (one-sided ones reach 2 coarse cells, 4 fine layers, down)
        self.shallow = int(np.ceil(self.near)) + 2 * COARSE
        self.offsets = ball_offsets(self.near)
        self.shifts = [(0, 0)] if shifts is None else [(int(a), int(b)) for a, b in shifts]
        self.coarse = _CoarsePath(self.spacing, self.poisson, self.cells, self.origin, grid.shape, self.order,
                                  average, shifts=self.shifts)
        self.moved = (0, 0)
        self.classes = self._classes(self.cells)
        self.table = self._table()
        self._pairs(local)

    def _pairs(self, local):
        """The near sums' layout: the cells' index in their box grown by the near radius (the sentinel ``n`` where no
        cell lies), the targets sorted by group (lateral parities, then the layer where sources within the near radius
        may be shallow, else the parity), each group's source class at each offset (-1: above the surface)."""
        n, r = len(self.cells), int(np.ceil(self.near))
        shape = tuple(local.max(axis=0) + 1 + 2 * r)
        self.index = np.full(shape, n, dtype=np.int32)
        self.index[tuple((local + r).T)] = np.arange(n, dtype=np.int32)
        self.index = self.index.ravel()
        strides = np.array([shape[1] * shape[2], shape[2], 1])
        reach = self.shallow + r            # targets below it see deep sources only
        layers = self.cells[:, 2]
        vertical = np.where(layers < reach, layers, reach + (layers - reach) % 2)
        lateral = ((self.cells[:, 0] - self.origin[0]) % COARSE) * COARSE + (self.cells[:, 1] - self.origin[1]) % COARSE
        group = lateral * (reach + 2) + vertical
        self.order = np.lexsort((local[:, 2], local[:, 1], local[:, 0], group))
        self.group = group[self.order]
        self.starts = np.searchsorted(self.group, np.arange(COARSE * COARSE * (reach + 2) + 1))
        self.flat = (local[self.order] + r) @ strides
        self.deltas = self.offsets @ strides
        # a group's first member stands for all: its sources' classes at every offset
        self.group_class = np.full((len(self.starts) - 1, len(self.offsets)), -1, dtype=np.int64)
        for g in np.flatnonzero(np.diff(self.starts)):
            sources = self.cells[self.order[self.starts[g]]] - self.offsets
            above = sources[:, 2] < 0
            self.group_class[g, ~above] = self._classes(sources[~above])

    def _classes(self, cells):
        """A cuboid's class: its parities along x1, x2 within the coarse cells and its layer (near the surface) or
        parity (deeper)."""
        depth = self.shallow + 2
        vertical = np.where(cells[:, 2] < self.shallow, cells[:, 2], self.shallow + (cells[:, 2] - self.shallow) % 2)
        lateral = ((cells[:, 0] - self.origin[0]) % COARSE) * COARSE + (cells[:, 1] - self.origin[1]) % COARSE
        return (lateral * depth + vertical).astype(np.int64)

    @property
    def class_count(self):
        """Classes of source cuboids: four lateral parities times the shallow layers and the two deeper parities."""
        return COARSE * COARSE * (self.shallow + 2)

    def _table(self):
        """``exact - coarse`` blocks ``(offsets, classes, 6, 6)`` of a unit eigenstrain of each class at each near
        offset (target minus source), by both paths in two small boxes: the deep classes' and the shallow ones'."""
        r = int(np.ceil(self.near))
        table = np.zeros((len(self.offsets), self.class_count, 6, 6))
        # the surface displacement's near tables (the shallow classes'; deeper sources' are smooth at the surface)
        self.disk = self.offsets[self.offsets[:, 2] == 0, :2]
        self.surface_table = np.zeros((len(self.disk), self.class_count, 6))
        side = 2 * r + 2
        boxes = [("deep", self.shallow - r, (side, side, side)), ("shallow", 0, (side, side, self.shallow + r + 1))]
        for kind, top, shape in boxes:
            # the classes the cells hold only (a dispersion below the surface has no cells in its top layers)
            present = set(np.unique(self.cells[:, 2]).tolist())
            layers = ([k for k in (self.shallow, self.shallow + 1) if any(l >= self.shallow and (l - k) % 2 == 0
                                                                           for l in present)]
                      if kind == "deep" else [k for k in range(self.shallow) if k in present])
            if not layers:
                continue
            # a grid wide enough for the fine operator's whole Boussinesq patch
            reach = [int(np.ceil(PATCH_DEPTHS * (top + shape[2]) * self.spacing[2] / self.spacing[a])) for a in range(2)]
            lateral = [shape[a] + 2 * reach[a] for a in range(2)]
            grid = Grid(shape=tuple(lateral), size=tuple(lateral[a] * self.spacing[a] for a in range(2)),
                        depth=(top + shape[2]) * self.spacing[2], layers=top + shape[2])
            start = (reach[0], reach[1], top)
            exact = HalfSpaceEigenstrain(grid, self.poisson, start, shape, average=self.average, folded=False)
            box = np.stack(np.meshgrid(*[np.arange(s, s + m) for s, m in zip(start, shape)], indexing="ij"),
                           axis=-1).reshape(-1, 3)
            # coarse cells start where this operator's do: the same parities
            origin = (start[0] - ((start[0] - self.origin[0]) % COARSE), start[1] - ((start[1] - self.origin[1]) % COARSE))
            coarse = _CoarsePath(self.spacing, self.poisson, box, origin, grid.shape, self.order, self.average)
            for layer in layers:
                # the fine operator's response does not depend on where the source lies across (x1, x2): once per
                # layer and component; the coarse path's does, on the source's parities in the coarse cells
                centre = np.array([start[0] + r, start[1] + r, layer])
                targets = centre + self.offsets
                valid = np.flatnonzero(targets[:, 2] >= 0)
                flat = np.ravel_multi_index(tuple((targets[valid] - start).T), shape)
                exact_blocks = np.empty((len(valid), 6, 6))
                exact_surface = np.empty((len(self.disk), 6))
                for component in range(6):
                    unit = np.zeros((*shape, 6))
                    unit[tuple(centre - start) + (component,)] = 1.0
                    exact_blocks[:, :, component] = exact.strain(unit).reshape(-1, 6)[flat]
                    if kind == "shallow":
                        lateral = exact.surface_displacement(unit)
                        exact_surface[:, component] = lateral[tuple((centre[:2] + self.disk).T)]
                for p1 in range(COARSE):
                    for p2 in range(COARSE):
                        # the source: parities p1, p2, next to the box's middle
                        source = centre + [(p1 - (centre[0] - self.origin[0])) % COARSE,
                                           (p2 - (centre[1] - self.origin[1])) % COARSE, 0]
                        cls = self._classes(source[None])[0]
                        moved = np.ravel_multi_index(tuple((source + self.offsets[valid] - start).T), shape)
                        for component in range(6):
                            unit = np.zeros((len(box), 6))
                            unit[np.ravel_multi_index(tuple(source - start), shape), component] = 1.0
                            table[valid, cls, :, component] = exact_blocks[:, :, component] - coarse.strain(unit)[moved]
                            if kind == "shallow":
                                lateral = coarse.surface_displacement(unit)[tuple((source[:2] + self.disk).T)]
                                self.surface_table[:, cls, component] = exact_surface[:, component] - lateral
        return table

    def strain(self, eigenstrain, displacement=False):
        """Total strain ``(n, 6)`` (tensor shears) at the cells from their eigenstrain ``(n, 6)``; with
        ``displacement``, also its :meth:`surface_displacement`, as ``(strain, displacement)``, from one spread onto
        the coarse box (a coupling iteration's product)."""
        eigenstrain = self._check(eigenstrain)
        if not displacement:
            return self.coarse.strain(eigenstrain) + self.near_strain(eigenstrain)
        strain, surface = self.coarse.strain(eigenstrain, displacement=True)
        return strain + self.near_strain(eigenstrain), surface + self._near_surface(eigenstrain)

    def _check(self, eigenstrain):
        eigenstrain = np.asarray(eigenstrain, dtype=float)
        if eigenstrain.shape != (len(self.cells), 6):
            raise ShapeError(f"eigenstrain has shape {eigenstrain.shape}, the operator has {len(self.cells)} cells")
        return eigenstrain

    def move(self, cells):
        """Move every cell by ``cells = (c1, c2)`` whole surface cells (the material under a rolling body). Nothing
        changes relative to the cells (their coarse box and tables move with them); their surface displacement and
        the pressure stress they feel map onto the grid where they now lie. The total move must be one of
        ``shifts``."""
        moved = (self.moved[0] + int(cells[0]), self.moved[1] + int(cells[1]))
        if moved not in self.shifts:
            raise ParameterError(f"move: the cells would lie {moved} cells from where they were built, not one of the "
                                 f"shifts given to the operator ({len(self.shifts)}): give every shift at construction")
        limits = np.array(self.grid.shape)
        lateral = self.cells[:, :2] + np.array(cells)
        if np.any(lateral < 0) or np.any(lateral >= limits):
            raise ParameterError(f"move: the cells would leave the grid's surface cells 0 .. {tuple(limits - 1)}")
        self.cells[:, :2] = lateral
        self.origin = (self.origin[0] + int(cells[0]), self.origin[1] + int(cells[1]))
        self.coarse.shift(cells)
        self.moved = moved

    def surface_displacement(self, eigenstrain):
        """Normal surface displacement ``(n1, n2)`` [m] over the grid, positive into the solid, of the eigenstrain
        ``(n, 6)`` (tensor shears) on the cells: the coarse box's (Betti's theorem, as
        :meth:`HalfSpaceEigenstrain.surface_displacement`) interpolated to the grid's cells, and for the cells within
        :attr:`shallow` layers of the surface the fine operator's own within the near radius (tables)."""
        eigenstrain = self._check(eigenstrain)
        return self.coarse.surface_displacement(eigenstrain) + self._near_surface(eigenstrain)

    def _near_surface(self, eigenstrain):
        """The surface tables' part ``(n1, n2)`` of :meth:`surface_displacement` (the shallow cells')."""
        n1, n2 = self.grid.shape
        near = np.zeros(n1 * n2)
        shallow = np.flatnonzero(self.cells[:, 2] < self.shallow)
        for o, (d1, d2) in enumerate(self.disk if shallow.size else ()):
            i1, i2 = self.cells[shallow, 0] + d1, self.cells[shallow, 1] + d2
            inside = (i1 >= 0) & (i1 < n1) & (i2 >= 0) & (i2 < n2)
            values = np.einsum("nc,nc->n", self.surface_table[o, self.classes[shallow[inside]]],
                               eigenstrain[shallow[inside]])
            near += np.bincount(i1[inside] * n2 + i2[inside], weights=values, minlength=near.size)
        return near.reshape(n1, n2)

    def pressure_stress(self, pressure):
        """Stress ``(n, 6)`` [Pa] at the cells of a surface pressure ``(n1, n2)`` [Pa] on the grid (the homogeneous
        half-space): the transpose of :meth:`surface_displacement` by Betti's theorem, ``sum p u3 dA = sum s : e* dV``
        (as :meth:`HalfSpaceEigenstrain.pressure_stress` is of its own), so the coarse box's pressure stress (the
        pressure gathered onto its surface cells by the interpolation's weights) spread back by the cells' stencils,
        and the near tables' transposes for the shallow cells."""
        pressure = np.asarray(pressure, dtype=float)
        if pressure.shape != tuple(self.grid.shape):
            raise ShapeError(f"pressure has shape {pressure.shape}, the grid is {tuple(self.grid.shape)}")
        path = self.coarse
        (nodes1, weights1), (nodes2, weights2) = path._surface
        surface = path.operator.grid.shape
        rows = np.zeros((surface[0], pressure.shape[1]))
        np.add.at(rows, nodes1.ravel(), (weights1[:, :, None] * pressure[:, None, :]).reshape(-1, pressure.shape[1]))
        coarse_pressure = np.zeros(surface)
        np.add.at(coarse_pressure.T, nodes2.ravel(), (weights2[:, :, None] * rows.T[:, None, :]).reshape(-1, surface[0]))
        stress = path.operator.pressure_stress(coarse_pressure)
        out = np.zeros((len(self.cells), 6))
        compiled = _fused._compiled and _fused.numba_available()
        (_stencil_loops()["gather"] if compiled else _gather_numpy)(path.first, path.weights["source"], stress, out)
        # sigma = (A / V) W^-1 S^T p, S^T the surface displacement's transpose; through the coarse box (its own Betti
        # pair, S_c^T q = (V_c / A_c) W sigma_c(q)) the factor is (A / V) (V_c / A_c) times the spread's volume ratio
        out *= COARSE * path.volume
        shallow = np.flatnonzero(self.cells[:, 2] < self.shallow)
        if shallow.size:
            n1, n2 = pressure.shape
            near = np.zeros((shallow.size, 6))
            for o, (d1, d2) in enumerate(self.disk):
                i1, i2 = self.cells[shallow, 0] + d1, self.cells[shallow, 1] + d2
                inside = np.flatnonzero((i1 >= 0) & (i1 < n1) & (i2 >= 0) & (i2 < n2))
                near[inside] += (self.surface_table[o, self.classes[shallow[inside]]]
                                 * pressure[i1[inside], i2[inside]][:, None])
            out[shallow] += near / self.spacing[2] / CONTRACTION
        return out

    def near_strain(self, eigenstrain):
        """The near tables' part ``(n, 6)`` of :meth:`strain` (``exact - coarse`` within the near radius)."""
        eigenstrain = self._check(eigenstrain)
        source = np.zeros((len(self.cells) + 1, 8))          # rows padded to a cache line; the last the sentinel
        source[:-1, :6] = eigenstrain
        near = np.zeros((6, len(self.cells)))
        if _fused._compiled and _fused.numba_available():
            _near()(self.index, self.starts, self.flat, self.deltas, self.group_class, self.table, source, near)
        else:
            _near_numpy(self.index, self.flat, self.group, self.deltas, self.group_class, self.table, source, near)
        strain = np.empty((len(self.cells), 6))
        strain[self.order] = near.T
        return strain

    @property
    def nbytes(self):
        """Memory held [bytes]: tables, stencils, the near sums' layout (the coarse operator's own not counted)."""
        stencils = self.coarse.first.nbytes + sum(w.nbytes for w in self.coarse.weights.values())
        layout = sum(a.nbytes for a in (self.index, self.order, self.group, self.flat, self.classes, self.cells))
        return self.table.nbytes + stencils + layout
