"""The equivalent-inclusion system of a dispersion on its bodies' cuboids alone (issue 26).

:func:`~framework.inclusions.field.solve_inclusions` solves on the box around the bodies with the box's
eigenstrain operator: time and memory follow the box, ten times the bodies' cuboids in a 10 % dispersion and
twenty times in a ball-shaped cloud. Here the unknowns, the Krylov basis and the operator
(:class:`~framework.operators.particle_mesh.ParticleMeshEigenstrain`: a coarse box at half the resolution and
exact near tables) follow the bodies' cuboids. The system is the same (``equivalent.py``)::

    (C_I - C_M) D[e*] + C_M e* = (C_M - C_I) e0

in Mandel's basis, by the box path's own problem and flexible GMRES
(:class:`~framework.inclusions.equivalent.EquivalentInclusionProblem`) on a "box" whose cuboids are the bodies'
(:class:`CellsOperator`), preconditioned body by body (:class:`BodyPreconditioner`: each body's system in its own
box taken as a periodic cell filled with it, the box path's Fourier preconditioner with its inner solve; bodies
whose cuboids span the same box and share a material share its matrices). ``D`` is the particle mesh's, whose error against the box operator's is stated in
``tests/test_particle_mesh.py`` (a few 1e-3 at its default near radius).
"""
import numpy as np

from ..errors import InclusionError, ParameterError
from ..grid import Grid
from ..materials import Elastic
from ..operators.eigenstrain import HalfSpaceEigenstrain
from ..operators.particle_mesh import NEAR, ParticleMeshEigenstrain
from .equivalent import EquivalentInclusionProblem

#: The relative residual to which each body's system in its filled cell is solved, and its inner iterations at most.
#: The coupling's Anderson mixing takes the preconditioner for a linear map (its residuals' differences for the
#: operator's): an inner GMRES stopped early is not one. At the box path's
#: :data:`~framework.inclusions.equivalent.INNER_TOLERANCE` (0.1) the first roll step over 30 and 100 glass spheres at
#: 8 cuboids per radius (bench/dispersion.py) stalled at an equivalent-inclusion residual of 2e-4 in 100 couplings,
#: though the same system alone (its pressure frozen) took 22 flexible-GMRES products to 1e-7; at 3e-2 / 1e-2 / 1e-3
#: the 30 spheres' steps took 11 / 11 / 11 products (the rest step 13) and 9.5 / 10.9 / 12.4 s, the 100 spheres' 11-15
#: at 1e-2. 1e-2 keeps a margin of ten below the stall.
BODY_TOLERANCE = 1e-2
BODY_ITERATIONS = 40
#: Each body's box is its cuboids' extent rounded up to a multiple of this along each axis, the body in its middle: a
#: margin of 0-3 cuboids where a body filled its box tightly (22 randomly oriented glass fibres of aspect 4, 4.2
#: cuboids across, rolled over: the first roll step 19 -> 11 products, the later steps 10-15 % faster; a margin of 2
#: cuboids on every side instead: the same products, 1.7 times slower on its larger, odd-sized cells), sizes the
#: transforms like, and bodies of nearly the same extent share the box operator and the cell's matrices.
SHAPE_STEP = 4


def body_cells(grid, inclusions):
    """The grid's cuboids ``(n, 3)`` whose centre a body holds and the body of each ``(n,)`` (0-based), found in each
    body's own window of the lattice (by :meth:`InclusionSet.indicator`, the box path's rule), in the grid's C order
    (the order of ``np.nonzero`` of the box path's indicator, in which a run records its bodies' fields)."""
    axes = (grid.x1, grid.x2, grid.x3)
    cells, owners = [], []
    for k, body in enumerate(inclusions):
        lower, upper = body.bounds()
        window = [slice(int(np.searchsorted(a, lo, "left")), int(np.searchsorted(a, hi, "right")))
                  for a, lo, hi in zip(axes, lower, upper)]
        if any(w.start >= w.stop for w in window):
            continue
        inside = np.argwhere(inclusions.indicator(*(a[w] for a, w in zip(axes, window))) == k + 1)
        cells.append(inside + [w.start for w in window])
        owners.append(np.full(len(inside), k))
    if not cells:
        return np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    cells, owners = np.concatenate(cells).astype(np.int64), np.concatenate(owners)
    order = np.lexsort(cells.T[::-1])           # the grid's C order: a box's np.nonzero order, a run's records'
    return cells[order], owners[order]


class BodyPreconditioner:
    """An approximate inverse of the bodies' system, body by body: each body's own system in its box, solved as the
    box path solves one body's (the box a periodic cell filled with the body's material, the cell's system on its
    cuboids to :data:`BODY_TOLERANCE`): a nonlinear map (an inner GMRES), for a flexible outer solve, close enough to
    a linear one for the coupling's Anderson mixing. Bodies whose cuboids span boxes of one shape and share a
    material share the box operator and the cell's matrices (at one matrix modulus)."""

    def __init__(self, grid, poisson, cells, body, stiffnesses, young):
        self.rows = [np.flatnonzero(body == k) for k in range(len(stiffnesses))]
        self.problems = []
        operators, shared = {}, {}
        for k, rows in enumerate(self.rows):
            low = cells[rows].min(axis=0)
            extent = cells[rows].max(axis=0) - low + 1
            shape = tuple(int(m) for m in -(-extent // SHAPE_STEP) * SHAPE_STEP)
            low = low - (np.array(shape) - extent) // 2         # the body in the middle of its box
            if shape not in operators:
                # only the infinite-space kernels on the box's periodic cells serve: a grid of the box alone (on the
                # whole grid each shape's Boussinesq maps reached 4 box depths around it: 100 bodies, 0.5 GiB)
                spacing = (*grid.spacing, grid.layer_thickness)
                own = Grid(shape=shape[:2], size=(shape[0] * spacing[0], shape[1] * spacing[1]),
                           depth=shape[2] * spacing[2], layers=shape[2])
                operators[shape] = HalfSpaceEigenstrain(own, poisson, (0, 0, 0), shape)
            indicator = np.zeros(shape, dtype=np.int8)
            indicator[tuple((cells[rows] - low).T)] = 1
            key = (shape, stiffnesses[k].tobytes())
            # the cell the box path takes for a body filling its box: the folded lattice (on the cell's clipped
            # symbol, equivalent.CLIP_SYMBOL: unclipped, a sphere of radius 8 cuboids in its 16^3 box had Ritz values
            # near -5.2 there)
            problem = EquivalentInclusionProblem(operators[shape], indicator, [stiffnesses[k]], young,
                                                 preconditioner="fourier", recycle=False,
                                                 shared=shared.setdefault(key, {}))
            problem.inner_tolerance, problem.inner_iterations = BODY_TOLERANCE, BODY_ITERATIONS
            self.problems.append((problem, key))

    def set_modulus(self, young):
        """The matrix's Young's modulus [Pa] (a viscoelastic matrix's of a step)."""
        for problem, _ in self.problems:
            problem.set_modulus(young)

    def __call__(self, values):
        """The preconditioned values ``(N, 6)`` (Mandel) of values ``(N, 6)`` on the bodies' cuboids."""
        out = np.empty_like(values)
        for rows, (problem, _) in zip(self.rows, self.problems):
            out[rows] = problem.precondition(values[rows])
        return out


class CellsOperator:
    """The particle mesh seen as a box whose cuboids are the bodies' (``shape = (N,)``; box fields are ``(N, 6)``), for
    :class:`~framework.inclusions.equivalent.EquivalentInclusionProblem` and its solver. A cell list has no lattice:
    the Fourier preconditioner's is never asked for (``BodiesProblem`` solves body by body)."""

    def __init__(self, mesh):
        self.mesh = mesh
        self.shape = (len(mesh.cells),)
        self.own_shape = self.folded_shape = self.fft_shape = self.shape
        self.spacing, self.poisson, self.average = mesh.spacing, mesh.poisson, mesh.average

    def strain(self, eigenstrain, displacement=False):
        """Strain ``(N, 6)`` at the cells (and their surface displacement over the grid with ``displacement``)."""
        return self.mesh.strain(eigenstrain, displacement=displacement)

    def surface_displacement(self, eigenstrain):
        return self.mesh.surface_displacement(eigenstrain)

    def pressure_stress(self, pressure):
        return self.mesh.pressure_stress(pressure)

    def move(self, cells):
        self.mesh.move(cells)


class BodiesProblem(EquivalentInclusionProblem):
    """The equivalent-inclusion system on the bodies' cuboids: the box path's problem and flexible GMRES (with its
    recycled directions) on :class:`CellsOperator`, preconditioned by :class:`BodyPreconditioner`."""

    def __init__(self, mesh, body, stiffnesses, young, recycle=True):
        self._bodies = BodyPreconditioner(mesh.grid, mesh.poisson, mesh.cells, body, stiffnesses, young)
        super().__init__(CellsOperator(mesh), np.asarray(body) + 1, stiffnesses, young, preconditioner="local",
                         recycle=recycle)
        self.inner = True       # the preconditioner is a nonlinear map: the solver keeps its directions

    def set_modulus(self, young):
        super().set_modulus(young)
        self._bodies.set_modulus(young)

    def _local_solve(self, vector):
        return self._bodies(np.reshape(vector, (-1, 6))).ravel()


class BodiesInclusionProblem:
    """The inhomogeneities of a run on their cuboids alone (``Options(inclusion_operator="particle_mesh")``): what
    :class:`~framework.inclusions.coupling.ContactCoupling` reads of
    :class:`~framework.inclusions.field.InclusionProblem` (``operator``, ``problem``, ``shape``, ``start``, ``move``),
    with the particle mesh and :class:`BodiesProblem`. The box of the layout (``margin``) only names where the run's
    records lie: its ``start`` moves with the material, nothing is built on it.

    ``travel``: the ``(c1, c2)`` moves of a rolling run, one per station (the particle mesh's ``shifts``)."""

    def __init__(self, grid, matrix, inclusions, margin=None, travel=None, near=NEAR, recycle=True):
        from .field import box_margin, inclusion_box, instantaneous
        self.grid, self.matrix, self.inclusions = grid, matrix, inclusions
        cells, self.body = body_cells(grid, inclusions)
        for k in range(len(inclusions)):
            if not np.any(self.body == k):
                raise ParameterError(f"inclusions[{k}] contains no cuboid centre of the grid: refine the grid")
        # where the records' box starts (no indicator on it: nothing here follows the box)
        self._start = np.array(inclusion_box(grid, inclusions, box_margin(inclusions, margin))[0])
        shifts = np.cumsum(np.array([(0, 0)] + [tuple(c) for c in (travel or [])], dtype=int), axis=0)
        limits = np.array(grid.shape)
        for shift in shifts:
            moved = cells[:, :2] + shift
            if np.any(moved < 0) or np.any(moved >= limits):
                raise InclusionError(f"inclusions: the material carries the inhomogeneities off the grid after a "
                                     f"move of {tuple(int(c) for c in shift)} cells; expected them to stay on the grid "
                                     f"for the whole run: lengthen grid.size, shorten the distance or start them "
                                     f"further ahead")
        self.mesh = ParticleMeshEigenstrain(grid, matrix.poisson, cells, near=near,
                                            shifts=[tuple(int(c) for c in shift) for shift in shifts])
        self.operator = CellsOperator(self.mesh)
        self.shape = self.operator.shape
        self.problem = BodiesProblem(self.mesh, self.body, [b.stiffness_tensor for b in inclusions],
                                     instantaneous(matrix), recycle=recycle)

    @property
    def start(self):
        """First cuboid of the layout's box on the grid (where the material has carried it)."""
        return tuple(int(c) for c in self._start)

    def move(self, cells):
        """Move the inhomogeneities with the material by ``cells = (c1, c2)`` whole cells."""
        self.operator.move(cells)
        self._start[:2] += np.asarray(cells, dtype=int)


class BodiesSolution:
    """Result of :func:`solve_on_bodies`: fields on the bodies' cuboids only.

    Attributes
    ----------
    cells : ndarray ``(n, 3)``
        The cuboids ``(i1, i2, layer)`` of the grid inside a body.
    body : ndarray ``(n,)``
        Which body (0-based) holds each.
    eigenstrain, strain, stress : ndarray ``(n, 6)``
        Equivalent eigenstrain, total strain (tensor shears, Voigt order xx yy zz yz xz xy) and total stress [Pa].
    iterations, residual, success, products
        GMRES iterations, final relative residual ``|b - A x| / |b|``, convergence, operator products.
    operator : ParticleMeshEigenstrain
    """

    def __init__(self, **fields):
        self.__dict__.update(fields)


def solve_on_bodies(grid, matrix, inclusions, applied_strain, tolerance=1e-8, near=NEAR, max_iterations=300):
    """Inhomogeneities in an elastic half-space under a uniform applied strain, on their cuboids alone.

    As :func:`~framework.inclusions.field.solve_inclusions` (the same system, cuboids and solver), with the
    particle-mesh operator: memory and time follow the bodies' cuboids, not the box around them.

    Parameters
    ----------
    grid : framework.Grid
        Open grid with layers.
    matrix : framework.materials.Elastic
    inclusions : framework.inclusions.InclusionSet
    applied_strain : array_like
        3x3 strain the matrix would have without the inhomogeneities (uniform).
    tolerance : float
        Relative residual ``|b - A x| / |b|`` of the system.
    near : float
        The particle mesh's near radius [cuboids] (its accuracy: ``tests/test_particle_mesh.py``).
    max_iterations : int
        GMRES iterations at most.

    Returns
    -------
    BodiesSolution
    """
    from .bodies import InclusionSet
    from .field import LARGEST_STRAIN, strain_vector
    if not isinstance(matrix, Elastic):
        raise ParameterError(f"matrix must be a framework.materials.Elastic, got {type(matrix).__name__}")
    if not isinstance(inclusions, InclusionSet):
        inclusions = InclusionSet(inclusions)
    inclusions.check_inside(grid)
    applied = strain_vector(applied_strain, name="applied_strain")
    if np.max(np.abs(applied)) > LARGEST_STRAIN:
        raise ParameterError(f"applied_strain must be small, every component at most {LARGEST_STRAIN:g} in magnitude, "
                             f"got {float(np.max(np.abs(applied))):g}")
    if not (np.isfinite(tolerance) and 0 < tolerance < 1):
        raise ParameterError(f"tolerance must lie in (0, 1), got {tolerance!r}")
    bodies = BodiesInclusionProblem(grid, matrix, inclusions, near=near, recycle=False)
    problem = bodies.problem
    solution = problem.solve(applied, tolerance=tolerance, max_iterations=max_iterations, raise_on_failure=False)
    return BodiesSolution(cells=bodies.mesh.cells, body=bodies.body, eigenstrain=solution.eigenstrain,
                          strain=solution.strain, stress=solution.stress, iterations=solution.iterations,
                          residual=solution.residual, success=solution.success, products=problem.products,
                          operator=bodies.mesh)
