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
``(C_I - R_eff C_bar) D[e*] + R_eff C_bar e* = S p + s_hist - C_I e0``. The system reads both
histories on the inhomogeneities' cuboids only, so they live there: memory per step, one ``(N, 6)``
field per creep term and per relaxation term, plus the last two fields (``N`` the inhomogeneities'
cuboids). The matrix's stress elsewhere in the box is the eigenstrains' field, which
:meth:`framework.result.Result.stress` computes from ``e~`` below, as it does beyond the box.

One more relaxation recursion carries ``e~ = R * de*``, the eigenstrains weighted by the relaxation
modulus over their history: the eigenstrains' stress beyond the box is ``C_bar : D[e~]``
(:meth:`framework.result.Result.stress`), known exactly at every step the run took, recorded or not.
"""
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError
from ..history import HereditarySum, PronyRecursion, translate
from ..materials import ComplianceSeries, Elastic
from ..operators.eigenstrain import MANDEL, stress_from_strain, strain_from_stress


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

    ``eigenstrain`` and ``stress`` are ``(N, 6)`` values on the inhomogeneities' cuboids (the
    problem's ``cells``, tensor shears; the total stress [Pa], ``C_I : strain``); ``displacement``
    the eigenstrains' surface displacement the contact saw; ``contact_stress`` and ``field`` (on the
    same cuboids) what the matrix's histories remember of the step; ``relaxed`` ``e~ = R * de*`` [Pa]
    (the eigenstrains under the matrix's relaxation modulus), None for an elastic matrix (there
    ``E e*``) or a run resumed from a checkpoint that lacked its history.
    """

    contact: object
    eigenstrain: np.ndarray
    stress: np.ndarray
    displacement: np.ndarray
    couplings: int
    change: float
    contact_stress: np.ndarray
    field: np.ndarray
    relaxed: np.ndarray = None


class ContactCoupling:
    """Couples the contact solve of a step with the equivalent-inclusion solve.

    The contact pressure's strain at the box (Love's coefficients, the matrix's
    compliance) is the applied strain of the inhomogeneities; their eigenstrains
    displace the surface (Betti), which enters the contact solve's gap. One sequence
    of iterates solves both (:meth:`solve`), each iterate one eigenstrain-operator
    product, until the eigenstrains' surface displacement lies within ``tolerance`` times
    the largest surface displacement of the step's fixed point (its last change, or, once
    the residual is that small too, the last change times the contraction the residuals
    show: :func:`estimated_distance`) and the equivalent-inclusion residual is below
    ``inclusion_tolerance`` of its right-hand side. A slow case raises
    :class:`~framework.errors.ConvergenceError` after ``max_couplings``.

    Parameters
    ----------
    problem : framework.inclusions.field.InclusionProblem
        The inhomogeneities, their box and operators.
    tolerance : float
        Relative distance of the eigenstrains' surface displacement from the step's fixed point at
        convergence (its last change, or that change times the residuals' contraction).
    inclusion_tolerance : float, optional
        The equivalent-inclusion residual at convergence, relative to its right-hand side
        (default ten times ``tolerance``, what the former nested solves accepted: the
        eigenstrains' error then moves the surface by about ``tolerance`` of its displacement).
    max_couplings : int
        Iterations before giving up (one product each).
    """

    def __init__(self, problem, tolerance=1e-8, inclusion_tolerance=None, max_couplings=100, history="recursive"):
        self.problem = problem
        if inclusion_tolerance is None:
            inclusion_tolerance = 10.0 * tolerance
        self.tolerance, self.inclusion_tolerance, self.max_couplings = tolerance, inclusion_tolerance, max_couplings
        integrator = PronyRecursion if history == "recursive" else HereditarySum
        creep, relaxation = matrix_series(problem.matrix)
        cells = (problem.problem.material.size, 6)
        # the system reads the contact's strain and the matrix's stress on the inhomogeneities' cuboids only, and
        # e~ = R * de* (the eigenstrains' stress in the matrix, only where R has memory) is zero outside them: their
        # histories live there (a dispersion at 10 % fills a tenth of its box)
        self._creep, self._relaxation = integrator(creep, cells), integrator(relaxation, cells)
        self._weighted = integrator(relaxation, cells) if relaxation.terms else None
        self.eigenstrain = None     # the last step's (N, 6) on the cuboids, to start the next one from
        self.disturbance = None     # D[eigenstrain], known from its solve: saves a product per solve
        self.displacement = 0.0
        self.past = []              # (time, Mandel values) of the last accepted steps: the moved step's predictor
        self._moved = False         # the box moved since the last step (its start is then predicted)

    def move(self, cells, periodic=(False, False)):
        """The material moved by ``cells`` whole cells (rolling): the inhomogeneities, their box and the
        surface displacement they caused move with it (the next step starts from it, displaced)."""
        if any(cells):
            self.problem.move(cells)
            self.disturbance = None     # the surface correction's patch edge sees the box elsewhere
            self._moved = True
            if np.ndim(self.displacement):
                self.displacement = translate(self.displacement, cells, periodic)

    def prepare(self, time):
        """Set up the step to ``time`` [s]: the matrix's effective modulus and its history stresses."""
        self._compliance, self._creep_history = self._creep.prepare(time)
        self._modulus, self._relaxation_history = self._relaxation.prepare(time)
        if self._weighted is not None:
            self._weighted_history = self._weighted.prepare(time)[1]
        self.problem.problem.set_modulus(self._modulus)
        self._time = time

    def commit(self, step):
        """Remember the converged step (its contact stress and equivalent-body field)."""
        self._creep.commit(self._time, step.contact_stress)
        self._relaxation.commit(self._time, step.field)
        if self._weighted is not None:
            self._weighted.commit(self._time, step.eigenstrain)
        self.past = (self.past + [(self._time, step.eigenstrain * MANDEL)])[-PREDICTOR_STEPS:]

    def _right(self, pressure):
        """The equivalent-inclusion system's right-hand side (Mandel, ``(N, 6)``) for the contact pressure, with
        the contact's stress and the strain without inhomogeneities, both on the inhomogeneities' cuboids
        (``(N, 6)``, tensor shears)."""
        problem, nu = self.problem, self.problem.matrix.poisson
        inner = problem.problem
        contact_stress = inner.on_cells(problem.operator.pressure_stress(pressure))
        creep = self._compliance * contact_stress
        if self._creep_history is not None:
            creep = creep + self._creep_history
        strain0 = strain_from_stress(creep, nu)                   # e0 (unit-modulus compliance times J)
        matrix_stress = contact_stress if self._relaxation_history is None \
            else contact_stress + self._relaxation_history
        right = matrix_stress * MANDEL - inner.per_material(inner.stiffness, strain0 * MANDEL)
        return right, contact_stress, strain0

    def _outputs(self, eigenstrain, strain, strain0):
        """The total stress ``C_I : (e0 + D[e*])`` and the field ``C_bar (D[e*] - e*)`` the relaxation remembers,
        from the eigenstrain and its strain ``D[e*]`` on the inhomogeneities' cuboids (``(N, 6)``, tensor shears)."""
        inner, nu = self.problem.problem, self.problem.matrix.poisson
        field = stress_from_strain(strain - eigenstrain, nu)      # C_bar (D[e*] - e*)
        stress = inner.per_material(inner.stiffness, (strain0 + strain) * MANDEL) / MANDEL
        return stress, field

    def solve(self, solve_contact):
        """Converge one step; ``solve_contact(extra_displacement)`` solves the contact with that displacement added.

        Call :meth:`prepare` before and :meth:`commit` (with the returned step) after. One
        sequence of iterates ``e_k`` (the eigenstrains, Mandel values on the inhomogeneities'
        cuboids) solves the contact and the inhomogeneities together: each iterate's surface
        displacement ``B e_k`` is given to the contact, whose pressure makes the right-hand side
        ``b_k``; the preconditioned residual ``z_k = M (b_k - A e_k)`` is one product ``D[z_k]``,
        and Anderson mixing (Walker & Ni 2011) over the last :data:`ANDERSON_DEPTH` iterates gives
        the next. On a linear problem this is GMRES with ``M`` (Fourier and recycled directions,
        :class:`~framework.inclusions.equivalent.EquivalentInclusionProblem`); the contact's
        nonlinearity (cells entering or leaving) is a small change of ``b`` that the mixing absorbs.
        The strains ``D[e_k]`` and displacements ``B e_k`` are combined as the iterates are, so a
        product per iteration is all the operator costs (one more at the start when the box has moved,
        or when the last step's box was too large to keep its strain there, :data:`ANDERSON_BYTES`). The
        step has converged when the eigenstrains' surface displacement lies within ``tolerance``
        times the surface displacement of the fixed point (its last change; or, once the residual is
        below ``tolerance`` too, that change times ``r / (1 - r)``, ``r`` the last residuals' ratio:
        :func:`estimated_distance`, which saves the coupling that only confirmed the change) and
        the equivalent-inclusion residual is below ``inclusion_tolerance`` of its right-hand side.
        """
        problem = self.problem
        inner, operator = problem.problem, problem.operator
        shape = (*problem.shape, 6)
        if self.eigenstrain is None:
            values, disturbance = np.zeros((inner.material.size, 6)), np.zeros(shape)
            displacement = np.zeros(problem.grid.shape)
        else:
            values = self.eigenstrain * MANDEL
            disturbance, displacement = self.disturbance, self.displacement
            if disturbance is None:     # the box moved, or is too large to keep it: both anew (the displacement
                if self._moved:         # was only translated), for a moved step's predicted eigenstrain
                    values = predicted(self.past, self._time, values)
                disturbance, displacement = operator.strain(inner.box_field(values), displacement=True)
                inner.products += 1
        self._moved = False
        deflation = inner.recycled.preconditioner(inner._image, inner.young)
        # A large box's iterates keep their strain on the inhomogeneities' cuboids only (Mandel values), and the next
        # step computes its start's strain on the box by one product: the history's box fields were most of the
        # memory of a rolling run over a dispersion (2.6 M box cuboids: 21 x 127 MB)
        whole = (ANDERSON_DEPTH + 1) * 8 * int(np.prod(shape)) <= ANDERSON_BYTES
        if not whole:
            disturbance = inner.on_cells(disturbance) * MANDEL
        history = []            # (G, D[G], B G, f) of the last iterates
        directions, strains = [], []
        previous = last_relative = None
        for count in range(1, self.max_couplings + 1):
            contact = solve_contact(displacement)
            right, contact_stress, strain0 = self._right(contact.pressure)
            residual = right - (inner._apply(values, disturbance) if whole
                                else inner._image(values, disturbance).reshape(-1, 6))
            scale = max(np.abs(contact.displacement).max(), np.abs(displacement).max(), 1e-300)
            change = 1.0 if previous is None else float(np.abs(displacement - previous).max() / scale)
            size = np.linalg.norm(right)
            relative = float(np.linalg.norm(residual) / size) if size > 0 else 0.0
            # the distance to the fixed point, estimated from the contraction, once the residual is as small as the
            # change must be (what the extra coupling of the change alone brought it to)
            distance = estimated_distance(change, relative, last_relative) if relative <= self.tolerance else change
            if relative <= self.inclusion_tolerance and (distance <= self.tolerance or relative == 0.0):
                inner.recycled.add(directions, strains, inner._image, inner.young)
                eigenstrain = values / MANDEL
                strain = inner.on_cells(disturbance) if whole else disturbance / MANDEL
                stress, field = self._outputs(eigenstrain, strain, strain0)
                self.eigenstrain, self.displacement = eigenstrain, displacement
                self.disturbance = disturbance if whole else None
                relaxed = None
                if self._weighted is not None and self._weighted_history is not None:
                    relaxed = self._modulus * eigenstrain + self._weighted_history
                return CoupledStep(contact, eigenstrain, stress, displacement, count, change, contact_stress, field,
                                   relaxed)
            correction = inner._precondition(residual.ravel(), deflation)
            image, moved = operator.strain(inner.box_field(correction.reshape(-1, 6)), displacement=True)
            inner.products += 1
            directions.append(correction)
            strains.append(inner.on_cells(image) * MANDEL)
            # the recycled space keeps at most its own count of them: a large dispersion's (4 of its 22 a step at
            # 0.2 M cuboids) would otherwise hold every iteration's pair until the step ends (440 MB there)
            surplus = len(directions) - inner.recycled.kept
            if surplus > 0:
                del directions[:surplus], strains[:surplus]
            history.append((values.ravel() + correction, disturbance + (image if whole else strains[-1]),
                            displacement + moved, correction))
            del image
            del history[:-ANDERSON_DEPTH - 1]
            previous, last_relative = displacement, relative
            values, disturbance, displacement = _anderson(history)
            values = values.reshape(-1, 6)
        raise ConvergenceError(f"contact and inhomogeneities did not converge in {self.max_couplings} coupling "
                               f"iterations: the eigenstrains' surface displacement still changes by {change:.3g} of "
                               f"the surface displacement, tolerance {self.tolerance:g}, and the equivalent-inclusion "
                               f"residual is {relative:.3g} of its right-hand side, tolerance {self.inclusion_tolerance:g} "
                               f"(Options.max_couplings allows more iterations, Options.coupling_tolerance a looser "
                               f"tolerance)")

    def snapshot(self):
        """The coupling's memory as arrays (for a checkpoint), keys prefixed ``inclusion_``."""
        out = {"inclusion_eigenstrain": self.eigenstrain, "inclusion_start": np.array(self.problem.start)}
        if self.past:               # the predictor's steps (a resumed run predicts as the whole one did)
            out["inclusion_past_times"] = np.array([t for t, _ in self.past])
            out["inclusion_past_values"] = np.array([values for _, values in self.past])
        if self.disturbance is not None:    # with the surface displacement the iterates combined (a step starts there)
            out["inclusion_disturbance"] = self.disturbance
            out["inclusion_displacement"] = np.asarray(self.displacement, dtype=float)
        # the Krylov solver's memory: a resumed run repeats the same iterations
        out.update({f"inclusion_recycled_{key}": value
                    for key, value in self.problem.problem.recycled.snapshot().items()})
        for name, integrator in self._integrators():
            out.update({f"inclusion_{name}_{key}": value for key, value in integrator.snapshot().items()})
        return out

    def restore(self, snapshot):
        """Continue from :meth:`snapshot`'s arrays."""
        inner = self.problem.problem
        self.eigenstrain = np.asarray(snapshot["inclusion_eigenstrain"])
        if self.eigenstrain.ndim == 4:      # written when it was kept on the whole box: its cuboids
            self.eigenstrain = self.eigenstrain[inner.cells]
        self.disturbance = snapshot.get("inclusion_disturbance")
        self.past = [(float(t), np.asarray(values)) for t, values in
                     zip(snapshot.get("inclusion_past_times", ()), snapshot.get("inclusion_past_values", ()))]
        if "inclusion_start" in snapshot:    # where the material had carried the box (rolling)
            start = np.asarray(snapshot["inclusion_start"], dtype=int)
            self.problem.move(tuple(int(c) for c in start[:2] - np.array(self.problem.start[:2])))
        self.displacement = snapshot.get("inclusion_displacement")
        if self.displacement is None or self.disturbance is None:
            self.displacement = self.problem.operator.surface_displacement(inner.box_field(self.eigenstrain * MANDEL))
        recycled = self.problem.problem.recycled
        recycled.clear()
        if "inclusion_recycled_directions" in snapshot:
            recycled.restore({key[len("inclusion_recycled_"):]: value for key, value in snapshot.items()
                              if key.startswith("inclusion_recycled_")})
        for name, integrator in self._integrators():
            prefix = f"inclusion_{name}_"   # (inclusion_start and inclusion_eigenstrain have no such prefix)
            kept = {key[len(prefix):]: value for key, value in snapshot.items() if key.startswith(prefix)}
            if name == "weighted" and not kept:     # a checkpoint written before e~ was carried: not known
                self._weighted = None
                continue
            box = (*self.problem.shape, 6)  # written when these histories lived on the whole box: their cuboids
            kept = {key: value[(slice(None),) * (np.ndim(value) - 4) + inner.cells]
                    if np.ndim(value) >= 4 and np.shape(value)[-4:] == box else value
                    for key, value in kept.items()}
            integrator.restore(kept)

    def _integrators(self):
        """``(name, integrator)`` of the matrix's histories: the contact's strain, the matrix's stress and e~."""
        out = [("creep", self._creep), ("relaxation", self._relaxation)]
        return out if self._weighted is None else out + [("weighted", self._weighted)]


#: Iterates the Anderson mixing of the coupling remembers.
ANDERSON_DEPTH = 20

#: Memory the Anderson history's strains on the whole box may take [bytes]: a larger box keeps them on the
#: inhomogeneities' cuboids only (all a step's outputs need), and its next step, unless the box moved (which costs
#: the product anyway), computes its start's strain on the box by one product.
ANDERSON_BYTES = 256 * 2**20

#: Relative cut of the Anderson Gram matrix's eigenvalues (singular values of the scaled differences below 1e-6
#: of the largest are dropped: nearly dependent iterates add nothing but rounding).
GRAM_RCOND = 1e-12

#: Accepted steps the predictor of a moved step extrapolates from (3: quadratic in time). Rolling over glass
#: (bench/rolling_inclusion.py), the step's first relative residual falls from 0.08 (the last step's eigenstrain)
#: to 0.010 (linear) and 0.0024 (quadratic), and the iterations from 17 to 15.
PREDICTOR_STEPS = 3


#: The largest ratio of consecutive equivalent-inclusion residuals that :func:`estimated_distance` reads as the
#: iteration's contraction; a slower iteration (or a growing residual: the contact set changed) is judged by its
#: last change alone.
CONTRACTION_LIMIT = 0.5


def estimated_distance(change, relative, last_relative):
    """The distance of the iterate's surface displacement from the step's fixed point, relative as ``change`` is.

    ``change`` the last change of the displacement, ``relative`` and ``last_relative`` the equivalent-inclusion
    residuals after and before it. An iteration that contracts by ``r`` per step is within ``change r / (1 - r)``
    of its limit (the sum of its further changes); ``r`` is read from the residuals where they fall by at least
    :data:`CONTRACTION_LIMIT`, else the change itself is the estimate. Rolling over glass
    (``bench/rolling_inclusion.py``) the residual falls 20-50 times per iteration: a change of 2.5e-7 there is
    within 5e-9 of the limit, which the last change's criterion took one more coupling to see (2.9e-9).
    """
    if last_relative is None or last_relative <= 0.0 or change >= 1.0:
        return change
    ratio = relative / last_relative
    return change * ratio / (1.0 - ratio) if ratio <= CONTRACTION_LIMIT else change


def predicted(past, time, values):
    """The eigenstrain at ``time`` extrapolated from the last accepted steps ``past`` [(time, values)].

    Lagrange's polynomial through the last steps (at most :data:`PREDICTOR_STEPS`, equally spaced or
    not) evaluated at ``time``; ``values`` (the last step's) when there are fewer than two steps, when
    the last one is not ``values``' step, or when the steps do not increase in time. Used where the
    box has moved (rolling: the body passes the contact one cell a step, and the eigenstrain varies
    smoothly with the step), whose first product is needed anyway.
    """
    if len(past) < 2 or past[-1][1].shape != values.shape or not np.array_equal(past[-1][1], values):
        return values
    times = np.array([t for t, _ in past])
    if np.any(np.diff(times) <= 0.0) or time <= times[-1]:
        return values
    out = np.zeros_like(values)
    for k, (t_k, v_k) in enumerate(past):
        weight = np.prod([(time - t_j) / (t_k - t_j) for j, t_j in enumerate(times) if j != k])
        out += weight * v_k
    return out


def _anderson(history):
    """Next iterate of Anderson mixing (type II) from the images ``G_k = e_k + f_k`` and residuals ``f_k``.

    ``history`` holds ``(G, D[G], B G, f)`` per iterate; the same combination of the images gives
    the next iterate, its strain and its surface displacement.
    """
    if len(history) == 1:
        return history[-1][:3]
    residuals = np.array([item[3] for item in history])
    differences = np.diff(residuals, axis=0)
    # the least squares min |f_last - sum w_k df_k| by its normal equations, columns scaled to unit length (as
    # scipy.optimize's Anderson does): a (k, k) Gram matrix instead of numpy's SVD of the (n, k) differences,
    # 16 vs 10 ms on one core and 290 vs 42 ms under threaded BLAS on a busy machine; the iterates' residuals are
    # computed afresh, so the weights' rounding only changes the path, not the converged answer
    lengths = np.sqrt(np.einsum("ij,ij->i", differences, differences))
    lengths[lengths == 0.0] = 1.0
    scaled = differences / lengths[:, None]
    weights = np.linalg.lstsq(scaled @ scaled.T, scaled @ residuals[-1], rcond=GRAM_RCOND)[0] / lengths
    out = []
    for part in range(3):
        stack = [item[part] for item in history]
        value = stack[-1].copy()
        for k, weight in enumerate(weights):
            value -= weight * (stack[k + 1] - stack[k])
        out.append(value)
    return tuple(out)
