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

from .errors import ConvergenceError, LoadNotCarriedError
from .solver import ContactSolution, SolverOptions, _residual, solve_normal


def solve_steady(apply, base_gap, *, cell_area, load, initial=None, options=SolverOptions(), window=None,
                 apply_window=None, symmetric=None, precondition=None):
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
        inner GMRES solves go 100 times below the residual tolerance (not
        below 1e-13).
    window, apply_window : callable, optional
        As for :func:`framework.solver.solve_normal`: the products on the
        contact set are computed on a box around it.
    symmetric : operator, optional
        The symmetric part ``(A + A^T)/2`` as an operator with ``apply``,
        ``window`` and ``apply_window``, for the start; else it is applied as
        two products with ``A``.
    precondition : SurfaceStiffness, optional
        As for :func:`framework.solver.solve_normal`: for the start's
        conjugate gradients on the symmetric part, and on the right of the
        GMRES solves on each contact set (on the products' box), unless
        ``options.preconditioned`` is False.

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
        # the symmetric part's contact (conjugate gradients apply to it) starts the active set close
        if symmetric is None:  # A^T is the convolution with the kernel reflected: A of the reflected field
            def apply_symmetric(p):
                return 0.5 * (apply(p) + apply(p[::-1, ::-1])[::-1, ::-1])
            windows = {}
        else:
            apply_symmetric = symmetric.apply
            windows = dict(window=symmetric.window, apply_window=symmetric.apply_window, diagonal=symmetric.diagonal)
        initial = solve_normal(apply_symmetric, base_gap, cell_area=cell_area, load=load,
                               options=SolverOptions(tolerance=1e-6, residual_tolerance=1e-4, max_iterations=500,
                                                     raise_on_failure=False,
                                                     preconditioned=options.preconditioned),
                               precondition=precondition, **windows).pressure
    contact = initial > 0
    whole = (slice(None), slice(None))
    products = [0]
    seen = set()
    pivoting = False
    pressure = np.array(initial, dtype=float)
    inner = max(1e-2 * options.residual_tolerance, 1e-13)   # GMRES gets no closer than rounding
    delta, converged = 0.0, False
    z_field = y_field = None       # the last iteration's solutions on the grid (its warm start from the second on)
    for iteration in range(options.max_iterations):
        box = window(contact) if window is not None else whole
        cells = contact[box]

        def product(values, box=box, cells=cells):
            field = np.zeros(cells.shape)
            field[cells] = values
            products[0] += 1
            out = apply_window(field, box) if apply_window is not None and box != whole else apply(field)[box]
            return out[cells]

        def preconditioned(values, cells=cells):
            field = precondition.input(cells.shape)    # written in place: the operator copies nothing
            field[...] = 0.0
            field[cells] = values
            return precondition.apply(field, copy=False)[cells]
        right_precondition = preconditioned if precondition is not None and options.preconditioned else None

        size = int(cells.sum())
        try:
            z = _gmres(product, -base_gap[box][cells], inner, (z_field if iteration else initial)[box][cells],
                       precondition=right_precondition)
            y = _gmres(product, np.ones(size), inner, y_field[box][cells] if iteration else None,
                       precondition=right_precondition)
        except ConvergenceError:
            if options.raise_on_failure:
                raise
            break   # reported below, with the last admissible iterate
        # sum(y) may take either sign: a plane-strain kernel is defined up to a constant (its value far
        # away), which shifts the approach, not the pressure; only sum(y) = 0 leaves the approach undefined
        if y.sum() == 0 or not np.isfinite(y.sum()):
            raise LoadNotCarriedError(f"the load {load:g} N cannot be carried by the steady contact set of {size} "
                                      f"cells: the approach is undefined there (sum of A^-1 1 = {y.sum():g})")
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


def _gmres(product, right, tolerance, start, restart=200, cycles=50, precondition=None):
    """Restarted GMRES (Saad & Schultz 1986) to ``tolerance`` relative residual; raises if it does not get there.

    With ``precondition`` (a linear map), preconditioned on the right: the
    Krylov space is that of ``product(precondition(.))`` and the residual the
    true one, so the tolerance means the same.

    Written out rather than scipy's: the orthogonalisation is two passes of
    classical Gram-Schmidt as sums in numpy's own loops (threaded BLAS stalls
    when another process holds a core, 20 times slower here with the contact
    sets of a 1024 x 512 grid) and the Givens rotations run on Python floats.
    """
    x = np.zeros_like(right) if start is None else np.array(start, dtype=float)
    target = tolerance * np.sqrt(np.einsum("i,i->", right, right))
    basis = np.empty((restart + 1, right.size))
    for _ in range(cycles):
        residual = right - product(x)
        beta = float(np.sqrt(np.einsum("i,i->", residual, residual)))
        if beta <= target:
            return x
        basis[0] = residual / beta
        hessenberg = np.zeros((restart + 1, restart))
        rotations, g = [], [beta] + [0.0] * restart
        for j in range(restart):
            w = product(basis[j] if precondition is None else precondition(basis[j]))
            column = np.zeros(j + 2)
            for _pass in range(2):
                h = np.einsum("kn,n->k", basis[: j + 1], w)
                w -= np.einsum("k,kn->n", h, basis[: j + 1])
                column[: j + 1] += h
            column[j + 1] = float(np.sqrt(np.einsum("i,i->", w, w)))
            if column[j + 1] > 0:
                basis[j + 1] = w / column[j + 1]
            for i, (c, sn) in enumerate(rotations):
                column[i], column[i + 1] = c * column[i] + sn * column[i + 1], -sn * column[i] + c * column[i + 1]
            a, b = float(column[j]), float(column[j + 1])
            radius = np.hypot(a, b)
            c, sn = (a / radius, b / radius) if radius > 0 else (1.0, 0.0)
            rotations.append((c, sn))
            column[j], column[j + 1] = radius, 0.0
            g[j], g[j + 1] = c * g[j], -sn * g[j]
            hessenberg[: j + 2, j] = column
            if abs(g[j + 1]) <= target or b == 0:
                break
        k = j + 1
        y = np.linalg.solve(np.triu(hessenberg[:k, :k]), np.array(g[:k]))
        step = np.einsum("k,kn->n", y, basis[:k])
        x = x + (step if precondition is None else precondition(step))
    residual = right - product(x)
    achieved = float(np.sqrt(np.einsum("i,i->", residual, residual))) / max(target / tolerance, 1e-300)
    if achieved > 10 * tolerance:
        raise ConvergenceError(f"GMRES on the steady contact set stopped at relative residual {achieved:.3g} "
                               f"(tolerance {tolerance:g}) after {cycles} cycles of {restart}")
    return x
