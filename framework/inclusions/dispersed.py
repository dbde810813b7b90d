"""The equivalent-inclusion system of a dispersion on its bodies' cuboids alone (issue 26).

:func:`~framework.inclusions.field.solve_inclusions` solves on the box around the bodies with the box's
eigenstrain operator: time and memory follow the box, ten times the bodies' cuboids in a 10 % dispersion and
twenty times in a ball-shaped cloud. Here the unknowns, the Krylov basis and the operator
(:class:`~framework.operators.particle_mesh.ParticleMeshEigenstrain`: a coarse box at half the resolution and
exact near tables) follow the bodies' cuboids. The system is the same (``equivalent.py``)::

    (C_I - C_M) D[e*] + C_M e* = (C_M - C_I) e0

in Mandel's basis, by flexible GMRES preconditioned body by body (:class:`BodyPreconditioner`: each body's
system in its own box taken as a periodic cell filled with it, the box path's Fourier preconditioner with its
inner solve, :class:`~framework.inclusions.equivalent.EquivalentInclusionProblem`; bodies whose cuboids span the
same box and share a material share its matrices). ``D`` is the particle mesh's, whose error against the box operator's is stated in
``tests/test_particle_mesh.py`` (a few 1e-3 at its default near radius).
"""
import numpy as np

from ..errors import ParameterError
from ..grid import Grid
from ..materials import Elastic
from ..operators.eigenstrain import MANDEL, HalfSpaceEigenstrain
from ..operators.particle_mesh import NEAR, ParticleMeshEigenstrain
from .equivalent import RESTART, EquivalentInclusionProblem, isotropic_mandel, mandel_matrix


def body_cells(grid, inclusions):
    """The grid's cuboids ``(n, 3)`` whose centre a body holds and the body of each ``(n,)`` (0-based), found in each
    body's own window of the lattice (by :meth:`InclusionSet.indicator`, the box path's rule), C order per body."""
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
    return np.concatenate(cells).astype(np.int64), np.concatenate(owners)


class BodyPreconditioner:
    """An approximate inverse of the bodies' system, body by body: each body's own system in its box, solved as the
    box path solves one body's (the box a periodic cell filled with the body's material, the cell's system on its
    cuboids to :data:`~framework.inclusions.equivalent.INNER_TOLERANCE`); a nonlinear map (an inner GMRES), for a
    flexible outer solve. Bodies whose cuboids span boxes of one shape and share a material share the box operator
    and the cell's matrices."""

    def __init__(self, grid, poisson, cells, body, stiffnesses, young):
        self.rows = [np.flatnonzero(body == k) for k in range(len(stiffnesses))]
        self.problems = []
        operators, cells_matrices = {}, {}
        for k, rows in enumerate(self.rows):
            low = cells[rows].min(axis=0)
            shape = tuple(int(m) for m in cells[rows].max(axis=0) - low + 1)
            if shape not in operators:
                # only the infinite-space kernels on the box's periodic cells serve: a grid of the box alone (on the
                # whole grid each shape's Boussinesq maps reached 4 box depths around it: 100 bodies, 0.5 GiB)
                spacing = (*grid.spacing, grid.layer_thickness)
                own = Grid(shape=shape[:2], size=(shape[0] * spacing[0], shape[1] * spacing[1]),
                           depth=shape[2] * spacing[2], layers=shape[2])
                operators[shape] = HalfSpaceEigenstrain(own, poisson, (0, 0, 0), shape)
            indicator = np.zeros(shape, dtype=np.int8)
            indicator[tuple((cells[rows] - low).T)] = 1
            problem = EquivalentInclusionProblem(operators[shape], indicator, [stiffnesses[k]], young,
                                                 preconditioner="fourier", recycle=False)
            key = (shape, stiffnesses[k].tobytes())
            if key in cells_matrices:                  # the filled cell does not depend on where the cuboids lie
                problem._fourier = cells_matrices[key]
            self.problems.append((problem, key))
        self._shared = cells_matrices

    def __call__(self, values):
        """The preconditioned values ``(N, 6)`` (Mandel) of values ``(N, 6)`` on the bodies' cuboids."""
        out = np.empty_like(values)
        for rows, (problem, key) in zip(self.rows, self.problems):
            out[rows] = problem._local_solve(values[rows].ravel()).reshape(-1, 6)
            if key not in self._shared:
                self._shared[key] = problem._fourier
            elif problem._fourier is None:
                problem._fourier = self._shared[key]
        return out


def flexible_gmres(apply, precondition, right, tolerance, max_iterations, restart=RESTART):
    """Solve ``apply(x) = right`` by flexible GMRES (Saad 1993), right-preconditioned by ``precondition`` (which may
    change between iterations); the residual is the system's own, ``|right - A x| / |right|``. Returns ``(x,
    iterations, residual)``."""
    scale = np.linalg.norm(right)
    x = np.zeros_like(right)
    if scale == 0.0:
        return x, 0, 0.0
    residual_vector, iterations = right.copy(), 0
    residual = 1.0
    while iterations < max_iterations:
        beta = np.linalg.norm(residual_vector)
        basis, directions = [residual_vector / beta], []
        hessenberg = np.zeros((restart + 1, restart))
        for j in range(restart):
            directions.append(precondition(basis[j]))
            w = apply(directions[j])
            for i, v in enumerate(basis):
                hessenberg[i, j] = v @ w
                w = w - hessenberg[i, j] * v
            hessenberg[j + 1, j] = np.linalg.norm(w)
            iterations += 1
            target = np.zeros(j + 2)
            target[0] = beta
            weights, *_ = np.linalg.lstsq(hessenberg[:j + 2, :j + 1], target, rcond=None)
            residual = np.linalg.norm(hessenberg[:j + 2, :j + 1] @ weights - target) / scale
            if residual <= tolerance or hessenberg[j + 1, j] == 0.0 or iterations >= max_iterations:
                break
            basis.append(w / hessenberg[j + 1, j])
        for weight, direction in zip(weights, directions):
            x += weight * direction
        if residual <= tolerance or iterations >= max_iterations:
            break
        residual_vector = right - apply(x)
    return x, iterations, residual


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
        GMRES iterations, final relative residual, convergence, operator products.
    operator : ParticleMeshEigenstrain
    """

    def __init__(self, **fields):
        self.__dict__.update(fields)


def solve_on_bodies(grid, matrix, inclusions, applied_strain, tolerance=1e-8, near=NEAR, max_iterations=300):
    """Inhomogeneities in an elastic half-space under a uniform applied strain, on their cuboids alone.

    As :func:`~framework.inclusions.field.solve_inclusions` (the same system and cuboids), with the particle-mesh
    operator: memory and time follow the bodies' cuboids, not the box around them.

    Parameters
    ----------
    grid : framework.Grid
        Open grid with layers.
    matrix : framework.materials.Elastic
    inclusions : framework.inclusions.InclusionSet
    applied_strain : array_like
        3x3 strain the matrix would have without the inhomogeneities (uniform).
    tolerance : float
        Relative residual of the system (flexible GMRES).
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
    cells, body = body_cells(grid, inclusions)
    for k in range(len(inclusions)):
        if not np.any(body == k):
            raise ParameterError(f"inclusions[{k}] contains no cuboid centre of the grid: refine the grid")
    operator = ParticleMeshEigenstrain(grid, matrix.poisson, cells, near=near)
    c_matrix = isotropic_mandel(matrix.young, matrix.poisson)
    c_bodies = np.array([mandel_matrix(b.stiffness_tensor) for b in inclusions])
    contrast = c_bodies - c_matrix                                    # (bodies, 6, 6)
    preconditioner = BodyPreconditioner(grid, matrix.poisson, cells, body, [b.stiffness_tensor for b in inclusions],
                                        matrix.young)
    n = len(cells)
    products = [0]

    def strain_of(e_mandel):                                          # D[e*] in Mandel's basis
        products[0] += 1
        return operator.strain(e_mandel / MANDEL) * MANDEL

    def apply(vector):
        e = vector.reshape(n, 6)
        return (np.einsum("nab,nb->na", contrast[body], strain_of(e)) + e @ c_matrix.T).ravel()

    e0 = np.broadcast_to(applied * MANDEL, (n, 6))
    right = -np.einsum("nab,nb->na", contrast[body], e0).ravel()
    solution, iterations, residual = flexible_gmres(apply, lambda v: preconditioner(v.reshape(n, 6)).ravel(), right,
                                                    tolerance, max_iterations)
    eigenstrain = solution.reshape(n, 6)
    strain = e0 + strain_of(eigenstrain)
    stress = np.einsum("nab,nb->na", c_bodies[body], strain) / MANDEL
    return BodiesSolution(cells=cells, body=body, eigenstrain=eigenstrain / MANDEL, strain=strain / MANDEL,
                          stress=stress, iterations=iterations, residual=float(residual),
                          success=bool(residual <= tolerance), products=products[0], operator=operator)
