"""Normal contact with a non-symmetric operator: the steady state of a moving body.

The steady rolling compliance (:mod:`framework.operators.rolling`) is not
symmetric, so the conjugate gradients of :mod:`framework.solver` do not apply:
their step length and conjugacy rest on a symmetric operator, and they stall
(THEORY.md sec. 7). Its symmetric part is positive definite (per Fourier mode
``2/|q| [c0 + sum_k c_k / (1 + (q_m L_k)^2)] > 0``), so the discrete
complementarity problem has a P-matrix and one solution.

Method: a primal-dual active set iteration (Hintermueller, Ito & Kunisch, SIAM
J. Optim. 13, 2003; a semismooth Newton method for ``min(p, g) = 0``). Given
the contact set ``S``, the equality problem ``g = 0`` on ``S``, ``p = 0`` off
it, ``sum p dA = W`` is solved exactly (to a tolerance far below the
solver's) by GMRES, a Krylov method for non-symmetric operators, on
``A_SS`` (one convolution per product, in a box around ``S``): ``p = z + delta y``
with ``A_SS z = -b_S``, ``A_SS y = 1`` and ``delta`` fixed by the load. Then
the cells of ``S`` with ``p < 0`` leave it and the cells outside with
``g < 0`` join it. When ``S`` no longer changes, ``p >= 0``, ``g = 0`` on ``S`` and
``g >= 0`` off it: the solution, checked with the same complementarity
residual as the static solver. A set met before (a cycle, possible for
P-matrices) switches to single moves, the most negative pressure out or else
the deepest interpenetration in (Murty's principal pivoting, finite for
P-matrices). The warm start (the previous solution, else the contact of the
symmetric part) usually leaves a few outer iterations.
"""
import numpy as np
from scipy.sparse.linalg import LinearOperator, gmres

from .errors import ConvergenceError, LoadNotCarriedError
from .solver import ContactSolution, SolverOptions, _residual, solve_normal


def solve_steady(apply, base_gap, *, cell_area, load, initial=None, options=SolverOptions(), window=None,
                 apply_window=None):
    """Solve the frictionless normal contact under load control with a non-symmetric operator.

    Parameters
    ----------
    apply : callable
        ``apply(p)`` -> displacement [m] of the pressure ``p`` [Pa] on the grid.
    base_gap : ndarray
        Separation ``b`` [m] before the approach and the displacement.
    cell_area : float
        Area of one cell [m^2].
    load : float
        Total load ``W`` [N].
    initial : ndarray, optional
        Starting pressure (its contact set is the first active set).
    options : SolverOptions
        ``residual_tolerance`` (complementarity, relative to the largest
        displacement) and ``max_iterations`` (active-set iterations); the
        inner GMRES solves go 100 times below the residual tolerance.
    window, apply_window : callable, optional
        As for :func:`framework.solver.solve_normal`: the products on the
        contact set are computed on a box around it.

    Returns
    -------
    ContactSolution
        ``iterations`` counts the operator products (GMRES iterations and
        the full products of the active-set updates).
    """
    base_gap = np.asarray(base_gap, dtype=float)
    if load == 0.0:
        zero = np.zeros_like(base_gap)
        delta = base_gap.min()
        return ContactSolution(zero, zero.copy(), base_gap - delta, delta, 0.0, 0, 0.0, 0.0, True)
    if initial is None or not np.any(initial > 0):
        # the symmetric part's contact (conjugate gradients apply to it) starts the active set close:
        # A^T is the convolution with the kernel reflected, i.e. A applied to the reflected field
        def symmetric(p):
            return 0.5 * (apply(p) + apply(p[::-1, ::-1])[::-1, ::-1])
        initial = solve_normal(symmetric, base_gap, cell_area=cell_area, load=load,
                               options=SolverOptions(tolerance=1e-6, residual_tolerance=1e-4, max_iterations=500,
                                                     raise_on_failure=False)).pressure
    contact = initial > 0
    whole = (slice(None), slice(None))
    products = [0]
    seen = set()
    pivoting = False
    pressure = np.zeros_like(base_gap)
    inner = 1e-2 * options.residual_tolerance
    delta, converged = 0.0, False
    for iteration in range(options.max_iterations):
        box = window(contact) if window is not None else whole
        cells = contact[box]

        def product(values, box=box, cells=cells):
            field = np.zeros(cells.shape)
            field[cells] = values
            products[0] += 1
            out = apply_window(field, box) if apply_window is not None and box != whole else apply(field)[box]
            return out[cells]

        size = int(cells.sum())
        operator = LinearOperator((size, size), matvec=product, dtype=float)
        z = _krylov(operator, -base_gap[box][cells], inner, (z_field if iteration else initial)[box][cells])
        y = _krylov(operator, np.ones(size), inner, y_field[box][cells] if iteration else None)
        if y.sum() <= 0:
            raise LoadNotCarriedError(f"the load {load:g} N cannot be carried by the steady contact set of {size} "
                                      f"cells (the operator restricted to it is not positive)")
        delta = (load / cell_area - z.sum()) / y.sum()
        z_field, y_field, candidate = np.zeros_like(base_gap), np.zeros_like(base_gap), np.zeros_like(base_gap)
        z_field[box][cells], y_field[box][cells] = z, y
        candidate[box][cells] = z + delta * y
        displacement = apply(candidate)
        products[0] += 1
        gap = base_gap + displacement - delta
        negative = contact & (candidate < 0)
        entering = ~contact & (gap < 0)
        pressure = np.where(contact, candidate, 0.0)
        if not negative.any() and not entering.any():
            converged = True
            break
        key = contact.tobytes()
        if key in seen:
            pivoting = True
        seen.add(key)
        contact = contact.copy()
        if not pivoting:
            contact[negative] = False
            contact[entering] = True
        elif negative.any():  # one move at a time: the most negative pressure leaves
            contact.flat[np.argmin(np.where(negative, candidate, np.inf))] = False
        else:                 # or the deepest interpenetration enters
            contact.flat[np.argmin(np.where(entering, gap, np.inf))] = True
        if not contact.any():
            contact = base_gap + displacement <= (base_gap + displacement).min()
    if not converged:  # the last iterate, made admissible, to report how far it is
        pressure = np.maximum(pressure, 0.0)
        displacement = apply(pressure)
        gap = base_gap + displacement - delta
    residual = _residual(gap, pressure > 0, displacement)
    success = converged and residual < options.residual_tolerance
    solution = ContactSolution(pressure, displacement, gap, float(delta), float(pressure.sum() * cell_area),
                               products[0], float(residual), 0.0, success)
    if not success and options.raise_on_failure:
        raise ConvergenceError(
            f"steady contact solver stopped after {iteration + 1} active-set iterations ({products[0]} operator "
            f"products) with complementarity residual {residual:.3g} (tolerance {options.residual_tolerance:g}); "
            f"raise max_iterations or loosen residual_tolerance", result=solution)
    return solution


def _krylov(operator, right, tolerance, start):
    """GMRES to ``tolerance`` relative residual (restarted every 200); raises if it does not get there."""
    solution, info = gmres(operator, right, x0=start, rtol=tolerance, atol=0.0, restart=200, maxiter=50)
    if info != 0:
        achieved = np.linalg.norm(operator.matvec(solution) - right) / max(np.linalg.norm(right), 1e-300)
        if achieved > 10 * tolerance:
            raise ConvergenceError(f"GMRES on the steady contact set stopped at relative residual {achieved:.3g} "
                                   f"(tolerance {tolerance:g})")
    return solution
