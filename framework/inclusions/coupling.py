"""Contact and inhomogeneities in one step: pressure -> stress at the inhomogeneities -> eigenstrains
-> surface displacement -> contact, to a fixed point (THEORY.md sec. 8).

A viscoelastic matrix (constant Poisson ratio) keeps the eigenstrain operators instantaneous: the
strain an eigenstrain causes in the homogeneous body does not depend on the modulus. What has
memory is, on the box around the inhomogeneities (tensor shears, ``C_bar`` the unit-modulus
stiffness, ``S p`` the contact stress, modulus-free):

- the strain of the homogeneous half-space under the contact, ``e0 = C_bar^-1 (J * d[S p])``
  (creep compliance ``J``);
- the matrix stress of the equivalent body, ``s_M = S p + R * d[C_bar (D[e*] - e*)]`` (relaxation
  modulus ``R``).

Both hereditary integrals are carried by Prony recursions (:class:`framework.history.PronyRecursion`,
or the full sum with ``options={"history": "hereditary"}``) with the fields ``S p`` and
``C_bar (D[e*] - e*)`` linear within a step: each step is an elastic equivalent-inclusion problem
with the matrix modulus ``R_eff`` (the mean of ``R`` over the step) and a known history stress,
``(C_I - R_eff C_bar) D[e*] + R_eff C_bar e* = S p + s_hist - C_I e0``. Memory per step: one
``(m1, m2, m3, 6)`` field per creep term and per relaxation term, plus the last two fields.
"""
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError
from ..history import HereditarySum, PronyRecursion, translate
from ..materials import ComplianceSeries, Elastic
from ..operators.eigenstrain import MANDEL, stress_from_strain, strain_from_stress
from ..operators.stress import SubsurfaceStress


def matrix_series(matrix):
    """Creep compliance ``J`` and relaxation modulus ``R`` of the matrix as Prony sums ``c0 + sum c_k (1 - e^-t/l_k)``.

    ``R(t) = E(0) - sum E_i (1 - exp(-t/tau_i))``: the same form with negative coefficients, so
    one recursion serves both.
    """
    if isinstance(matrix, Elastic):
        return ComplianceSeries(c0=1.0 / matrix.young), ComplianceSeries(c0=matrix.young)
    j0, creep = matrix.creep_terms
    _, relaxation = matrix.relaxation_terms
    return (ComplianceSeries(c0=j0, terms=tuple(creep)),
            ComplianceSeries(c0=matrix.instantaneous_modulus, terms=tuple((-e, tau) for e, tau in relaxation)))


@dataclass
class CoupledStep:
    """One converged step: the contact solution, the eigenstrain fields and the fixed-point count.

    ``eigenstrain`` and ``stress`` are box fields ``(m1, m2, m3, 6)`` (tensor shears; the total
    stress [Pa]); ``displacement`` the eigenstrains' surface displacement the contact saw;
    ``contact_stress`` and ``field`` what the matrix's histories remember of the step.
    """

    contact: object
    eigenstrain: np.ndarray
    stress: np.ndarray
    displacement: np.ndarray
    couplings: int
    change: float
    contact_stress: np.ndarray
    field: np.ndarray


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
    inclusion_tolerance : float, optional
        The tightest GMRES tolerance of the equivalent-inclusion solves (default a tenth of
        ``tolerance``); a solve that stalls short of it is accepted when its residual is below
        ten times ``tolerance``.
    max_couplings : int
        Fixed-point iterations before giving up.
    """

    def __init__(self, problem, tolerance=1e-8, inclusion_tolerance=None, max_couplings=100, history="recursive"):
        self.problem = problem
        if inclusion_tolerance is None:
            inclusion_tolerance = 0.1 * tolerance
        self.tolerance, self.inclusion_tolerance, self.max_couplings = tolerance, inclusion_tolerance, max_couplings
        self._stress = SubsurfaceStress(problem.grid, problem.matrix.poisson)
        integrator = PronyRecursion if history == "recursive" else HereditarySum
        creep, relaxation = matrix_series(problem.matrix)
        shape = (*problem.shape, 6)
        self._creep, self._relaxation = integrator(creep, shape), integrator(relaxation, shape)
        self.eigenstrain = None     # the last step's, to start the next one from
        self.disturbance = None     # D[eigenstrain], known from its solve: saves a product per solve
        self.displacement = 0.0

    def move(self, cells, periodic=(False, False)):
        """The material moved by ``cells`` whole cells (rolling): the inhomogeneities, their box and the
        surface displacement they caused move with it (the next step starts from it, displaced)."""
        if any(cells):
            self.problem.move(cells)
            self.disturbance = None     # the surface correction's patch edge sees the box elsewhere
            if np.ndim(self.displacement):
                self.displacement = translate(self.displacement, cells, periodic)

    def prepare(self, time):
        """Set up the step to ``time`` [s]: the matrix's effective modulus and its history stresses."""
        self._compliance, self._creep_history = self._creep.prepare(time)
        self._modulus, self._relaxation_history = self._relaxation.prepare(time)
        self.problem.problem.set_modulus(self._modulus)
        self._time = time

    def commit(self, step):
        """Remember the converged step (its contact stress and equivalent-body field)."""
        self._creep.commit(self._time, step.contact_stress)
        self._relaxation.commit(self._time, step.field)

    def _fields(self, pressure, initial, initial_disturbance, tolerance):
        """Eigenstrains, total stress, the fields to commit, and the inner solve's residual and success."""
        problem, nu = self.problem, self.problem.matrix.poisson
        inner = problem.problem
        contact_stress = self._stress.apply(pressure, problem.operator.depths)[problem.box[:2]]
        creep = self._compliance * contact_stress
        if self._creep_history is not None:
            creep = creep + self._creep_history
        strain0 = strain_from_stress(creep, nu)                   # e0 (unit-modulus compliance times J)
        matrix_stress = contact_stress if self._relaxation_history is None \
            else contact_stress + self._relaxation_history
        cells = inner.cells
        right = (matrix_stress[cells] * MANDEL
                 - inner.per_material(inner.stiffness, strain0[cells] * MANDEL))
        # a Krylov solve that stalls short of a tight inner tolerance is judged by the coupling's own test
        eigenstrain, disturbance, _, residual, success = inner.solve_for(
            right, initial=initial, initial_disturbance=initial_disturbance, tolerance=tolerance, max_iterations=200,
            raise_on_failure=False)
        field = stress_from_strain(disturbance - eigenstrain, nu)   # C_bar (D[e*] - e*)
        stress = matrix_stress + self._modulus * field
        strain = strain0 + disturbance
        stress[cells] = inner.per_material(inner.stiffness, strain[cells] * MANDEL) / MANDEL
        return eigenstrain, disturbance, stress, contact_stress, field, residual, success

    def solve(self, solve_contact):
        """Converge one step; ``solve_contact(extra_displacement)`` solves the contact with that displacement added.

        Call :meth:`prepare` before and :meth:`commit` (with the returned step) after. The
        fixed point ``u -> F(u)`` (``u`` the eigenstrains' surface displacement) is
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
            eigenstrain, self.disturbance, stress, contact_stress, field, inner_residual, inner_success = self._fields(
                contact.pressure, self.eigenstrain, self.disturbance, tolerance)
            self.eigenstrain = eigenstrain
            image = problem.operator.surface_displacement(eigenstrain)
            residual = image - displacement
            scale = max(np.abs(contact.displacement).max(), np.abs(image).max(), 1e-300)
            change = float(np.abs(residual).max() / scale)
            if change <= self.tolerance and (inner_success or inner_residual <= 10 * self.tolerance):
                self.displacement = image
                # the contact saw ``displacement``; the eigenstrains answer its pressure: consistent to the tolerance
                return CoupledStep(contact, eigenstrain, stress, displacement, count, change, contact_stress, field)
            residuals.append(residual.ravel())
            images.append(image.ravel())
            del residuals[:-ANDERSON_DEPTH - 1], images[:-ANDERSON_DEPTH - 1]
            displacement = _anderson(residuals, images).reshape(image.shape)
        raise ConvergenceError(f"contact and inhomogeneities did not converge in {self.max_couplings} coupling "
                               f"iterations: the eigenstrains' surface displacement still changes by {change:.3g} of "
                               f"the surface displacement, tolerance {self.tolerance:g}")

    def snapshot(self):
        """The coupling's memory as arrays (for a checkpoint), keys prefixed ``inclusion_``."""
        out = {"inclusion_eigenstrain": self.eigenstrain, "inclusion_start": np.array(self.problem.start)}
        if self.disturbance is not None:
            out["inclusion_disturbance"] = self.disturbance
        for name, integrator in (("creep", self._creep), ("relaxation", self._relaxation)):
            out.update({f"inclusion_{name}_{key}": value for key, value in integrator.snapshot().items()})
        return out

    def restore(self, snapshot):
        """Continue from :meth:`snapshot`'s arrays."""
        self.eigenstrain = snapshot["inclusion_eigenstrain"]
        self.disturbance = snapshot.get("inclusion_disturbance")
        if "inclusion_start" in snapshot:    # where the material had carried the box (rolling)
            start = np.asarray(snapshot["inclusion_start"], dtype=int)
            self.problem.move(tuple(int(c) for c in start[:2] - np.array(self.problem.start[:2])))
        self.displacement = self.problem.operator.surface_displacement(self.eigenstrain)
        for name, integrator in (("creep", self._creep), ("relaxation", self._relaxation)):
            prefix = f"inclusion_{name}_"   # (inclusion_start and inclusion_eigenstrain have no such prefix)
            integrator.restore({key[len(prefix):]: value for key, value in snapshot.items() if key.startswith(prefix)})


#: Iterates the Anderson mixing of the coupling remembers.
ANDERSON_DEPTH = 4


def _anderson(residuals, images):
    """Next iterate of Anderson mixing (type II) from the residuals ``F(u) - u`` and the images ``F(u)``."""
    if len(residuals) == 1:
        return images[-1]
    differences = np.diff(np.array(residuals), axis=0).T
    weights, *_ = np.linalg.lstsq(differences, residuals[-1], rcond=None)
    return images[-1] - np.diff(np.array(images), axis=0).T @ weights
