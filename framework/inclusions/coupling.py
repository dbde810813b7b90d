"""Contact and inhomogeneities in one step: pressure -> stress at the inhomogeneities -> eigenstrains
-> surface displacement -> contact, to a fixed point (THEORY.md sec. 8)."""
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError
from ..operators.eigenstrain import strain_from_stress
from ..operators.stress import SubsurfaceStress


@dataclass
class CoupledStep:
    """One converged step: the contact solution, the eigenstrain solution and the fixed-point count."""

    contact: object
    inclusions: object
    displacement: np.ndarray
    couplings: int
    change: float


class ContactCoupling:
    """Couples the contact solve of a step with the equivalent-inclusion solve.

    The contact pressure's strain at the box (Love's coefficients, the matrix's
    compliance) is the applied strain of the inhomogeneities; their eigenstrains
    displace the surface (Betti), which enters the next contact solve's gap.
    Fixed-point iteration with Anderson mixing, each solve warm-started from the
    last, until the eigenstrains' surface displacement changes by less than
    ``tolerance`` times the largest surface displacement. The map is a contraction when the
    inhomogeneities' effect on the surface is smaller than the contact's own
    compliance, i.e. always for inhomogeneities below the surface in practice;
    a slow case raises :class:`~framework.errors.ConvergenceError` after
    ``max_couplings``.

    Parameters
    ----------
    problem : framework.inclusions.field.InclusionProblem
        The inhomogeneities, their box and operators.
    tolerance : float
        Relative change of the eigenstrains' surface displacement at convergence.
    inclusion_tolerance : float
        GMRES tolerance of each equivalent-inclusion solve.
    max_couplings : int
        Fixed-point iterations before giving up.
    """

    def __init__(self, problem, tolerance=1e-8, inclusion_tolerance=1e-10, max_couplings=100):
        self.problem = problem
        self.tolerance, self.inclusion_tolerance, self.max_couplings = tolerance, inclusion_tolerance, max_couplings
        self._stress = SubsurfaceStress(problem.grid, problem.matrix.poisson)
        self.eigenstrain = None     # the last step's, to start the next one from
        self.displacement = 0.0

    def applied_strain(self, pressure):
        """Strain ``(m1, m2, m3, 6)`` of the homogeneous half-space under ``pressure`` on the box."""
        problem = self.problem
        stress = self._stress.apply(pressure, problem.operator.depths)[problem.box[:2]]
        return strain_from_stress(stress, problem.matrix.poisson, problem.matrix.young)

    def solve(self, solve_contact):
        """Converge one step; ``solve_contact(extra_displacement)`` solves the contact with that displacement added.

        The fixed point ``u -> F(u)`` (``u`` the eigenstrains' surface displacement) is
        accelerated by Anderson mixing over the last :data:`ANDERSON_DEPTH` iterates (Walker &
        Ni 2011), and each equivalent-inclusion solve is inexact: to 1 % of the current
        change, between ``inclusion_tolerance`` and 1e-3 (Krylov iterations are not spent on
        eigenstrains the next coupling replaces).
        """
        problem = self.problem
        displacement = self.displacement
        residuals, images = [], []
        change = 1.0
        for count in range(1, self.max_couplings + 1):
            contact = solve_contact(displacement)
            tolerance = min(1e-3, max(self.inclusion_tolerance, 1e-2 * change))
            solution = problem.problem.solve(self.applied_strain(contact.pressure), initial=self.eigenstrain,
                                             tolerance=tolerance)
            self.eigenstrain = solution.eigenstrain
            image = problem.operator.surface_displacement(solution.eigenstrain)
            residual = image - displacement
            scale = max(np.abs(contact.displacement).max(), np.abs(image).max(), 1e-300)
            change = float(np.abs(residual).max() / scale)
            if change <= self.tolerance:
                self.displacement = image
                # the contact saw ``displacement``; the eigenstrains answer its pressure: consistent to the tolerance
                return CoupledStep(contact, solution, displacement, count, change)
            residuals.append(residual.ravel())
            images.append(image.ravel())
            del residuals[:-ANDERSON_DEPTH - 1], images[:-ANDERSON_DEPTH - 1]
            displacement = _anderson(residuals, images).reshape(image.shape)
        raise ConvergenceError(f"contact and inhomogeneities did not converge in {self.max_couplings} coupling "
                               f"iterations: the eigenstrains' surface displacement still changes by {change:.3g} of "
                               f"the surface displacement, tolerance {self.tolerance:g}")


#: Iterates the Anderson mixing of the coupling remembers.
ANDERSON_DEPTH = 4


def _anderson(residuals, images):
    """Next iterate of Anderson mixing (type II) from the residuals ``F(u) - u`` and the images ``F(u)``."""
    if len(residuals) == 1:
        return images[-1]
    differences = np.diff(np.array(residuals), axis=0).T
    weights, *_ = np.linalg.lstsq(differences, residuals[-1], rcond=None)
    return images[-1] - np.diff(np.array(images), axis=0).T @ weights
