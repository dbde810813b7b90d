"""The equivalent-inclusion system of a dispersion on its bodies' cuboids alone (issue 26).

:func:`~framework.inclusions.field.solve_inclusions` solves on the box around the bodies with the box's
eigenstrain operator: time and memory follow the box, ten times the bodies' cuboids in a 10 % dispersion and
twenty times in a ball-shaped cloud. Here the unknowns, the Krylov basis and the operator
(:class:`~framework.operators.particle_mesh.ParticleMeshEigenstrain`: a coarse box at half the resolution and
exact near tables) follow the bodies' cuboids. The system is the same (``equivalent.py``)::

    (C_I - C_M) D[e*] + C_M e* = (C_M - C_I) e0

in Mandel's basis, by GMRES left-preconditioned cuboid by cuboid with ``[(C_I - C_M) S + C_M]^-1`` (``S`` a
cuboid's own averaged strain). ``D`` is the particle mesh's, whose error against the box operator's is stated in
``tests/test_particle_mesh.py`` (a few 1e-3 at its default near radius).
"""
import numpy as np
import scipy.sparse.linalg

from ..errors import ParameterError
from ..materials import Elastic
from ..operators.eigenstrain import MANDEL
from ..operators.particle_mesh import NEAR, ParticleMeshEigenstrain
from .equivalent import RESTART, cuboid_self_strain, isotropic_mandel, mandel_matrix


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
        GMRES iterations, final relative residual (preconditioned), convergence, operator products.
    operator : ParticleMeshEigenstrain
    """

    def __init__(self, **fields):
        self.__dict__.update(fields)


def solve_on_bodies(grid, matrix, inclusions, applied_strain, tolerance=1e-8, near=NEAR, max_iterations=300):
    """Inhomogeneities in an elastic half-space under a uniform applied strain, on their cuboids alone.

    As :func:`~framework.inclusions.field.solve_inclusions` (the same system, cuboids and preconditioner), with the
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
        Relative residual of the preconditioned GMRES solve.
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
    own = cuboid_self_strain(operator.spacing, matrix.poisson, average=True)
    local = np.linalg.inv(contrast @ own + c_matrix)                  # the cuboid-by-cuboid preconditioner
    n = len(cells)
    products = [0]

    def strain_of(e_mandel):                                          # D[e*] in Mandel's basis
        products[0] += 1
        return operator.strain(e_mandel / MANDEL) * MANDEL

    def apply(vector):
        e = vector.reshape(n, 6)
        out = np.einsum("nab,nb->na", contrast[body], strain_of(e)) + e @ c_matrix.T
        return np.einsum("nab,nb->na", local[body], out).ravel()

    e0 = np.broadcast_to(applied * MANDEL, (n, 6))
    rhs = np.einsum("nab,nb->na", local[body], -np.einsum("nab,nb->na", contrast[body], e0)).ravel()
    system = scipy.sparse.linalg.LinearOperator((6 * n, 6 * n), matvec=apply, dtype=float)
    residuals = []
    solution, info = scipy.sparse.linalg.gmres(system, rhs, rtol=tolerance, atol=0.0, restart=RESTART,
                                               maxiter=max(1, -(-max_iterations // RESTART)),
                                               callback=residuals.append, callback_type="pr_norm")
    eigenstrain = solution.reshape(n, 6)
    strain = e0 + strain_of(eigenstrain)
    stress = np.einsum("nab,nb->na", c_bodies[body], strain) / MANDEL
    residual = float(np.linalg.norm(apply(solution) - rhs) / np.linalg.norm(rhs))
    return BodiesSolution(cells=cells, body=body, eigenstrain=eigenstrain / MANDEL, strain=strain / MANDEL,
                          stress=stress, iterations=len(residuals), residual=residual, success=info == 0,
                          products=products[0], operator=operator)


