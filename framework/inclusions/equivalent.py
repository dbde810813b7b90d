"""Eshelby's equivalent inclusion method on the cuboid lattice (THEORY.md sec. 8).

Each inhomogeneity (stiffness ``C_I``) is replaced by matrix material (``C_M``) with an
eigenstrain ``e*`` such that the stress is the same in every cuboid of the inhomogeneity
(Eshelby 1957; Mura 1987 sec. 22; Jacq et al. 2002; Koumi et al. 2014)::

    C_I : (e0 + D[e*]) = C_M : (e0 + D[e*] - e*)

``e0`` the strain without the inhomogeneities, ``D`` the half-space eigenstrain operator
(:class:`~framework.operators.eigenstrain.HalfSpaceEigenstrain`). Written as
``(C_I - C_M) D[e*] + C_M e* = (C_M - C_I) e0`` it is solved by GMRES (the operator is not
symmetric), left-preconditioned per inhomogeneity by ``[(C_I - C_M) S + C_M]^-1`` with
``S`` the strain a cuboid's own eigenstrain causes in it (as the operator takes it: averaged over
the cuboid or at its centre): for an isolated cuboid
this is the exact local solve, and it makes the iteration count nearly independent of the
resolution and of the stiffness contrast.

Strains are ``(..., 6)`` arrays in Voigt order xx yy zz yz xz xy with tensor shears;
internally the unknowns are in Mandel's basis (shears times sqrt 2), where the 6x6
matrices of the stiffness tensors are symmetric.
"""
from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_triangular

from ..errors import ConvergenceError, ShapeError
from ..operators.eigenstrain import COMPONENTS, MANDEL, cuboid_potentials, strain_from_potentials

#: GMRES restart length: the Krylov basis holds this many vectors of 6 values per cuboid of the
#: inhomogeneities (the preconditioned system converges in 5 to 30 iterations).
RESTART = 30


def mandel_matrix(tensor):
    """6x6 Mandel matrix of a stiffness tensor ``(3, 3, 3, 3)``."""
    out = np.empty((6, 6))
    for a, (i, j) in enumerate(COMPONENTS):
        for b, (k, l) in enumerate(COMPONENTS):
            out[a, b] = tensor[i, j, k, l] * MANDEL[a] * MANDEL[b]
    return out


def isotropic_mandel(young, poisson):
    """6x6 Mandel matrix of an isotropic stiffness."""
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    mu = young / (2 * (1 + poisson))
    out = 2 * mu * np.eye(6)
    out[:3, :3] += lam
    return out


def cuboid_self_strain(spacing, poisson, average=False):
    """Mandel matrix of the strain at a cuboid's centre (or its average over the cuboid, ``average``)
    per unit eigenstrain of the cuboid (infinite body)."""
    spacing = np.asarray(spacing, dtype=float)
    potentials = cuboid_potentials(np.zeros(3), 0.5 * spacing, spacing if average else None)
    columns = [strain_from_potentials(potentials, np.eye(6)[c] / MANDEL[c], poisson) * MANDEL for c in range(6)]
    return np.array(columns).T


@dataclass
class EquivalentInclusionSolution:
    """Solution of one equivalent-inclusion solve on an operator's box.

    Attributes
    ----------
    eigenstrain : ndarray
        ``(m1, m2, m3, 6)`` equivalent eigenstrain (zero in the matrix).
    strain : ndarray
        ``(m1, m2, m3, 6)`` total strain ``e0 + D[e*]``.
    stress : ndarray
        ``(m1, m2, m3, 6)`` total stress [Pa]: ``C_I : strain`` in the inhomogeneities,
        ``C_M : strain`` in the matrix.
    iterations : int
        GMRES iterations.
    residual : float
        Final ``|A e* - b| / |b|`` of the unpreconditioned system.
    success : bool
        Whether the residual met the tolerance.
    """

    eigenstrain: np.ndarray
    strain: np.ndarray
    stress: np.ndarray
    iterations: int
    residual: float
    success: bool


class EquivalentInclusionProblem:
    """The linear system of the equivalent inclusion method on one box.

    Parameters
    ----------
    operator : framework.operators.eigenstrain.HalfSpaceEigenstrain
        The matrix's eigenstrain operator on the box.
    indicator : ndarray of int
        ``(m1, m2, m3)``: 0 in the matrix, ``k + 1`` in the cuboids of the ``k``-th inhomogeneity.
    stiffnesses : sequence of ndarray
        Stiffness tensors ``(3, 3, 3, 3)`` [Pa] of the inhomogeneities, in the global frame.
    young : float
        Young's modulus of the matrix [Pa] (its Poisson ratio is the operator's).
    """

    def __init__(self, operator, indicator, stiffnesses, young):
        indicator = np.asarray(indicator)
        if indicator.shape != operator.shape:
            raise ShapeError(f"indicator has shape {indicator.shape}, the operator's box is {operator.shape}")
        self.operator = operator
        self.indicator = indicator
        self.cells = np.nonzero(indicator)
        self.material = indicator[self.cells] - 1
        self.stiffness = [mandel_matrix(c) for c in stiffnesses]
        self._local = cuboid_self_strain(operator.spacing, operator.poisson, operator.average)
        self.young = None
        self.set_modulus(young)

    def set_modulus(self, young):
        """Give the matrix the Young's modulus ``young`` [Pa] (a viscoelastic matrix's effective one of a step)."""
        if young == self.young:
            return
        self.young = young
        self.matrix = isotropic_mandel(young, self.operator.poisson)
        self.contrast = [c - self.matrix for c in self.stiffness]
        self._preconditioner = [np.linalg.inv(d @ self._local + self.matrix) for d in self.contrast]

    @property
    def size(self):
        """Number of unknowns (6 per cuboid of the inhomogeneities)."""
        return 6 * self.material.size

    def per_material(self, matrices, values):
        out = np.empty_like(values)
        for k, matrix in enumerate(matrices):
            rows = self.material == k
            out[rows] = values[rows] @ matrix.T
        return out

    def box_field(self, values):
        """Tensor-shear box field ``(m1, m2, m3, 6)`` of Mandel values ``(N, 6)`` on the inhomogeneities' cuboids."""
        field = np.zeros((*self.operator.shape, 6))
        field[self.cells] = values / MANDEL
        return field

    def _apply(self, values, disturbance=None):
        if disturbance is None:
            disturbance = self.operator.strain(self.box_field(values))
        return self.per_material(self.contrast, disturbance[self.cells] * MANDEL) + values @ self.matrix.T

    def solve(self, applied_strain, initial=None, tolerance=1e-10, max_iterations=500, raise_on_failure=True):
        """Equivalent eigenstrain for the strain ``applied_strain`` the matrix would have without inhomogeneities.

        Parameters
        ----------
        applied_strain : ndarray
            ``(m1, m2, m3, 6)`` tensor-shear strain on the box, or ``(6,)`` uniform.
        initial : ndarray, optional
            ``(m1, m2, m3, 6)`` eigenstrain to start from (warm start across steps).
        tolerance : float
            Relative residual of the preconditioned system.
        max_iterations : int
            GMRES iterations (restarted every :data:`RESTART`) before the solve is declared failed.
        raise_on_failure : bool
            Raise :class:`~framework.errors.ConvergenceError` when the tolerance is not met.
        """
        shape = (*self.operator.shape, 6)
        applied = np.broadcast_to(np.asarray(applied_strain, dtype=float), shape)
        right = -self.per_material(self.contrast, applied[self.cells] * MANDEL)
        eigenstrain, disturbance, iterations, residual, success = self.solve_for(
            right, initial=initial, tolerance=tolerance, max_iterations=max_iterations,
            raise_on_failure=raise_on_failure)
        return self._solution(eigenstrain, applied, iterations, residual, success, disturbance)

    def solve_for(self, right, initial=None, tolerance=1e-10, max_iterations=500, raise_on_failure=True,
                  initial_disturbance=None):
        """Solve ``(C_I - C_M) D[e*] + C_M e* = right`` for any right-hand side (Mandel, ``(N, 6)``).

        ``initial_disturbance``, the box field ``D[initial]`` when the caller knows it (the
        last solve's), saves the first product. Returns ``(eigenstrain, disturbance,
        iterations, residual, success)``: the box fields ``e*`` and ``D[e*]`` (tensor
        shears), the GMRES count, the relative residual, convergence.
        """
        shape = (*self.operator.shape, 6)
        n = self.size
        scale = np.linalg.norm(right)
        if n == 0 or scale == 0.0:
            return np.zeros(shape), np.zeros(shape), 0, 0.0, True
        values = np.zeros((self.material.size, 6))
        disturbance = np.zeros(shape)
        if initial is not None:
            values = np.asarray(initial, dtype=float)[self.cells] * MANDEL
            disturbance = (self.operator.strain(self.box_field(values)) if initial_disturbance is None
                           else np.asarray(initial_disturbance, dtype=float))
        local_right = self.per_material(self._preconditioner, right)
        values, disturbance, iterations, precond_residual = self._gmres(local_right, values, disturbance, tolerance,
                                                                        max_iterations)
        residual = float(np.linalg.norm(self._apply(values, disturbance) - right) / scale)
        success = precond_residual <= 10 * tolerance
        if not success and raise_on_failure:
            raise ConvergenceError(f"the equivalent-inclusion solve stopped after {iterations} GMRES iterations at "
                                   f"relative residual {precond_residual:.3g}, tolerance {tolerance:g}")
        return self.box_field(values), disturbance, iterations, residual, success

    def _gmres(self, right, values, disturbance, tolerance, max_iterations):
        """Restarted GMRES (Saad & Schultz 1986) on ``P A x = P b`` that carries ``D[x]`` along.

        Each product computes ``D[v]`` of a Krylov vector; keeping them (one box field per
        vector of the basis) gives ``D[x]`` of the solution, and the residual at a restart,
        as the same combination, without the extra product a library GMRES would need.
        Classical Gram-Schmidt, repeated once (Giraud et al. 2005): matrix products, as
        accurate as the modified one. Stops when the preconditioned residual is below
        ``tolerance`` times ``|P b|``; returns ``(values, D[x], iterations, that relative residual)``.
        """
        def preconditioned(vector_values, vector_disturbance):
            return self.per_material(self._preconditioner, self._apply(vector_values, vector_disturbance)).ravel()

        target = tolerance * np.linalg.norm(right)
        residual = right.ravel() - preconditioned(values, disturbance)
        beta = np.linalg.norm(residual)
        iterations = 0
        while beta > target and iterations < max_iterations:
            size = min(RESTART, self.size, max_iterations - iterations)
            basis = np.empty((size + 1, self.size))
            images = []
            hessenberg = np.zeros((size + 1, size))
            rotations = np.zeros((size, 2))
            projected = np.zeros(size + 1)
            basis[0], projected[0] = residual / beta, beta
            used = 0
            for j in range(size):
                vector = basis[j].reshape(-1, 6)
                images.append(self.operator.strain(self.box_field(vector)))
                w = preconditioned(vector, images[-1])
                h = basis[:j + 1] @ w
                w -= h @ basis[:j + 1]
                again = basis[:j + 1] @ w
                w -= again @ basis[:j + 1]
                length = np.linalg.norm(w)
                column = np.zeros(size + 1)
                column[:j + 1], column[j + 1] = h + again, length
                for i in range(j):          # the earlier Givens rotations
                    c, s = rotations[i]
                    column[i], column[i + 1] = c * column[i] + s * column[i + 1], -s * column[i] + c * column[i + 1]
                radius = np.hypot(column[j], column[j + 1])
                c, s = (1.0, 0.0) if radius == 0.0 else (column[j] / radius, column[j + 1] / radius)
                rotations[j] = c, s
                column[j], column[j + 1] = radius, 0.0
                projected[j], projected[j + 1] = c * projected[j], -s * projected[j]
                hessenberg[:, j] = column
                used, iterations = j + 1, iterations + 1
                if abs(projected[j + 1]) <= target or length == 0.0:
                    break
                basis[j + 1] = w / length
            weights = solve_triangular(hessenberg[:used, :used], projected[:used])
            values = values + (weights @ basis[:used]).reshape(-1, 6)
            for weight, image in zip(weights, images):
                disturbance = disturbance + weight * image
            residual = right.ravel() - preconditioned(values, disturbance)
            beta = np.linalg.norm(residual)
        return values, disturbance, iterations, float(beta / np.linalg.norm(right))

    def _solution(self, eigenstrain, applied, iterations, residual, success, disturbance=0.0):
        strain = applied + disturbance
        stress = (strain * MANDEL) @ self.matrix.T
        stress[self.cells] = self.per_material(self.stiffness, strain[self.cells] * MANDEL)
        return EquivalentInclusionSolution(eigenstrain=eigenstrain, strain=np.array(strain), stress=stress / MANDEL,
                                           iterations=iterations, residual=residual, success=success)
