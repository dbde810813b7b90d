"""Polonsky & Keer conjugate-gradient solver of the normal contact problem.

Polonsky & Keer, Wear 231 (1999) 206-219. The unknown is the pressure ``p >= 0``
on the grid; the gap is ``g = b + A p - delta`` with ``b`` the initial
separation (indenter height plus any known displacement), ``A`` the
displacement operator (symmetric, positive) and ``delta`` the rigid approach.
Complementarity: ``p > 0 => g = 0`` and ``p = 0 => g >= 0``.

Under load control ``sum p dA = W`` and ``delta`` is the mean of ``b + A p``
over the contact set (the projection that keeps the load); under approach
control ``delta`` is given.
"""
from dataclasses import dataclass

import numpy as np

from . import _fused, fft
from ._fused import _dot
from ._validation import check_bool, check_positive_int, check_real
from .errors import ConvergenceError, LoadNotCarriedError, ParameterError

#: The smallest tolerance a solve can meet: relative changes below it are round-off in double precision.
SMALLEST_TOLERANCE = 1e-15


@dataclass(frozen=True)
class SolverOptions:
    """Tolerances of the contact solver.

    Parameters
    ----------
    tolerance : float
        Relative L1 change of the pressure between two iterations, in
        ``[SMALLEST_TOLERANCE, 1)`` (a smaller one cannot be met in double precision).
    residual_tolerance : float
        Complementarity residual: the largest gap in the contact set and the
        largest interpenetration outside it, relative to the largest displacement;
        in ``[SMALLEST_TOLERANCE, 1)``.
    max_iterations : int
        Iterations before the solve is declared stalled, >= 1.
    raise_on_failure : bool
        Raise :class:`ConvergenceError` when the solve does not converge (else
        return the result with ``success = False``).
    preconditioned : bool
        Precondition the conjugate gradients with the half-space's surface
        stiffness (:class:`framework.operators.stiffness.SurfaceStiffness`)
        where the caller provides it (:class:`framework.Simulation` does):
        2-4 times fewer iterations; ``False`` gives the plain iteration of
        Polonsky & Keer (the same solution to the tolerance).
    """

    tolerance: float = 1e-8
    residual_tolerance: float = 1e-6
    max_iterations: int = 2000
    raise_on_failure: bool = True
    preconditioned: bool = True

    def __post_init__(self):
        for name in ("tolerance", "residual_tolerance"):
            value = check_real(getattr(self, name), name=name)
            if not SMALLEST_TOLERANCE <= value < 1.0:
                raise ParameterError(f"{name} must lie in [{SMALLEST_TOLERANCE:g}, 1) (a relative error; smaller "
                                     f"ones are round-off in double precision), got {value!r}")
            object.__setattr__(self, name, value)
        object.__setattr__(self, "max_iterations", check_positive_int(self.max_iterations, name="max_iterations"))
        object.__setattr__(self, "raise_on_failure", check_bool(self.raise_on_failure, name="raise_on_failure"))
        object.__setattr__(self, "preconditioned", check_bool(self.preconditioned, name="preconditioned"))


@dataclass
class ContactSolution:
    """Outcome of one normal contact solve (SI units)."""

    pressure: np.ndarray      # [Pa]
    displacement: np.ndarray  # A p [m], positive into the solid
    gap: np.ndarray           # b + A p - delta [m]
    approach: float           # delta [m]
    load: float               # sum p dA [N]
    iterations: int
    residual: float
    pressure_change: float
    success: bool
    slopes: tuple = (0.0, 0.0)  # rigid tilt (alpha1, alpha2) of an eccentrically loaded indenter


class RigidModes:
    """The indenter's rigid motions that the load fixes: ``w = delta`` or ``w = delta + a1 x1 + a2 x2``.

    Without ``coordinates`` only the approach is free (the projection of
    Polonsky & Keer removes the mean gap over the contact set). With them the
    two tilts are free too (THEORY.md sec. 6): the projection removes the
    least-squares plane over the contact set, and after each update the
    pressure is corrected by a plane on the contact set so that the force and
    both moments hold exactly.

    Parameters
    ----------
    coordinates : tuple of ndarray, optional
        Cell-centre coordinates ``(X1, X2)`` [m].
    """

    def __init__(self, coordinates=None):
        self.tilt = coordinates is not None
        if self.tilt:
            scale = max(np.ptp(coordinates[0]), np.ptp(coordinates[1]), np.finfo(float).tiny)
            self.scale = scale  # fit in coordinates of order one: a well-conditioned 3 x 3 system
            self.basis = np.stack([np.ones_like(coordinates[0]), coordinates[0] / scale, coordinates[1] / scale])

    def fit(self, field, contact, box=(slice(None), slice(None))):
        """Least-squares rigid displacement of ``field`` over ``contact``: (field of it, coefficients)."""
        if not self.tilt:
            mean = np.mean(field, where=contact)
            return mean, (mean, 0.0, 0.0)
        basis = self.basis[(slice(None),) + box]
        selected = basis[:, contact]
        coefficients = np.linalg.lstsq(selected @ selected.T, selected @ field[contact], rcond=None)[0]
        return np.tensordot(coefficients, basis, axes=1), coefficients

    def slopes(self, coefficients):
        """Tilt slopes ``(alpha1, alpha2)`` of fitted coefficients."""
        return (coefficients[1] / self.scale, coefficients[2] / self.scale) if self.tilt else (0.0, 0.0)

    def restore(self, pressure, targets, cell_area):
        """Scale and correct ``pressure`` in place so that its resultants equal ``targets``."""
        total = pressure.sum() * cell_area
        if total <= 0:
            return False
        pressure *= targets[0] / total
        if not self.tilt:
            return True
        for _ in range(20):
            contact = pressure > 0
            selected = self.basis[:, contact]
            missing = targets - selected @ pressure[contact] * cell_area
            if np.abs(missing).max() <= 1e-13 * targets[0]:
                return True
            # least squares: cells on a line (two cells carrying a load between them) are a
            # rank-deficient but valid support when the load centre lies on that line
            gram = selected @ selected.T * cell_area
            pressure[contact] += np.linalg.lstsq(gram, missing, rcond=1e-12)[0] @ selected
            np.maximum(pressure, 0.0, out=pressure)
        return False


def _residual(gap, contact, displacement, shift=0.0):
    """Complementarity residual of the gap ``gap - shift``, relative to the largest displacement."""
    scale = max(np.abs(displacement).max(), np.finfo(float).tiny)
    inside = np.abs(gap[contact] - shift).max(initial=0.0)
    outside = max(0.0, shift - gap[~contact].min(initial=shift))
    return max(inside, outside) / scale


def solve_normal(apply, base_gap, *, cell_area, load=None, approach=None, initial=None,
                 options=SolverOptions(), window=None, apply_window=None, offset=None, coordinates=None,
                 diagonal=None, precondition=None):
    """Solve the frictionless normal contact by conjugate gradients.

    Parameters
    ----------
    apply : callable
        ``apply(p)`` returns the displacement [m] of the pressure field ``p`` [Pa];
        it may return a buffer of its own that its next call overwrites (the
        solver reads it before then, and copies the displacement it returns).
    base_gap : ndarray
        Separation ``b`` [m] before the approach and the displacement of ``p``.
    cell_area : float
        Area of one cell [m^2].
    load : float, optional
        Total load ``W`` [N] (load control).
    approach : float, optional
        Rigid approach ``delta`` [m] (approach control).
    initial : ndarray, optional
        Starting pressure (warm start), e.g. the previous step's.
    options : SolverOptions
        Tolerances.
    window, apply_window : callable, optional
        ``window(support)`` returns slices of a box holding the contact set and
        ``apply_window(field, box)`` the displacement of a field that vanishes
        outside the box, on the box. The conjugate direction lives on the
        contact set and its response is only needed there, so this saves most
        of one of the two convolutions per iteration.
    offset, coordinates : tuple, optional
        Load control only: the load acts at ``offset = (e1, e2)`` [m] from the
        origin, and the indenter tilts; ``coordinates`` are the cell centres
        ``(X1, X2)`` [m]. The solution's ``slopes`` are the tilts.
    diagonal : float, optional
        Displacement [m/Pa] of a cell under its own unit pressure (the
        operator's diagonal), which scales the re-entry of cells; computed
        with one product when not given.
    precondition : SurfaceStiffness, optional
        An approximate inverse of the operator,
        :class:`framework.operators.SurfaceStiffness` (or an object with its
        ``window``, ``input`` and ``apply``): the conjugate gradients are then
        preconditioned by it on a box around the contact set, restricted to
        the set and projected as the gap is: 2-4 times fewer iterations, each
        with one more FFT pair (of the box). Only its direction counts, not
        its scale. Without it, or with ``options.preconditioned`` False: the
        plain iteration of Polonsky & Keer.

    Returns
    -------
    ContactSolution
    """
    base_gap = np.asarray(base_gap, dtype=float)
    missing = np.count_nonzero(np.isnan(base_gap))
    if missing:
        raise ParameterError(f"base_gap must hold numbers (the separation [m], +inf where nothing can touch), "
                             f"got NaN at {missing} of its {base_gap.size} cells")
    load_control = load is not None
    modes = RigidModes(coordinates if offset is not None else None)
    targets = None
    if load_control:
        targets = np.array([load, 0.0, 0.0])
        if modes.tilt:
            targets = load * np.array([1.0, offset[0] / modes.scale, offset[1] / modes.scale])
    touch = base_gap.min()
    if (load_control and load == 0.0) or (not load_control and approach <= touch):
        zero = np.zeros_like(base_gap)
        delta = touch if load_control else approach
        return ContactSolution(zero, zero.copy(), base_gap - delta, delta, 0.0, 0, 0.0, 0.0, True)

    if initial is not None and np.any(initial > 0):
        pressure = np.array(initial, dtype=float)
    elif load_control:
        # Uniform over the cells that can plausibly touch: those within a few times the displacement
        # of the load spread over the grid (a punch's walls would otherwise dominate the first steps).
        pressure = np.full(base_gap.shape, load / (base_gap.size * cell_area))
        scale = apply(pressure).max()
        if not scale > 0:
            # a doubly periodic grid, where the mean carries no displacement: that of the same load on an
            # open square of the grid's area (n cells of a side: n times a cell's own displacement)
            if diagonal is None:
                diagonal = _self_compliance(apply, base_gap.shape)
            scale = pressure.flat[0] * diagonal * np.sqrt(base_gap.size)
        if scale > 0:
            pressure = np.where(base_gap <= touch + 4.0 * scale, pressure, 0.0)
    else:  # the interpenetration, scaled so that its displacement matches it at the peak
        pressure = np.maximum(approach - base_gap, 0.0)
        pressure *= (approach - touch) / apply(pressure).max()
    if load_control:
        carried = modes.restore(pressure, targets, cell_area)
        if not carried and modes.tilt:
            # A body that tilts carries the load about its point of application (a sphere rolls its
            # contact there), which the cells nearest the lowest point may not surround: start from the
            # smallest disc of cells around the offset that carries the load and both moments.
            distance = np.hypot(coordinates[0] - offset[0], coordinates[1] - offset[1])
            for radius in 1.5 * np.sqrt(cell_area) * 2.0 ** np.arange(16):
                pressure = np.where(distance <= radius, 1.0, 0.0)
                carried = modes.restore(pressure, targets, cell_area)
                if carried or radius > distance.max():
                    break
        if not carried:
            raise LoadNotCarriedError(_not_carried(load, offset, pressure > 0))

    problem = _Problem(apply, base_gap, cell_area, load if load_control else None, approach, offset, targets, modes,
                       options, window, apply_window, diagonal, precondition if options.preconditioned else None)
    # the start in an array the FFTs of an unpadded grid read in place, which the loop then works in
    pressure = fft.aligned(pressure)
    pressure, displacement, gap, delta, coefficients, iteration, residual, change = _iterate(problem, pressure)
    displacement = np.array(displacement)   # apply's own buffer, perhaps

    success = change < options.tolerance and residual < options.residual_tolerance
    solution = ContactSolution(pressure, displacement, gap, float(delta), float(pressure.sum() * cell_area),
                               iteration, float(residual), float(change), bool(success),
                               tuple(float(a) for a in modes.slopes(coefficients)))
    if not success and options.raise_on_failure:
        raise ConvergenceError(
            f"contact solver stopped after {iteration} iterations with pressure change {change:.3g} "
            f"(tolerance {options.tolerance:g}) and complementarity residual {residual:.3g} "
            f"(tolerance {options.residual_tolerance:g}); raise max_iterations or loosen the tolerances",
            result=solution)
    return solution


def _self_compliance(apply, shape):
    """Displacement of a cell under its own unit pressure, by one product (a convolution: any cell)."""
    unit = np.zeros(shape)
    unit.flat[0] = 1.0
    return float(apply(unit).flat[0])


def _corner(box):
    """Row and column of the first cell of ``box`` (slices of the grid)."""
    return tuple(0 if s.start is None else s.start for s in box)


def _not_carried(load, offset, contact):
    return (f"the load {load:g} N at offset {tuple(offset) if offset is not None else (0, 0)} m cannot be carried: "
            f"the contact shrank to {int(contact.sum())} cells; the load centre must lie well inside the area "
            f"the body can touch (for a flat punch, inside its face)")


@dataclass
class _Problem:
    """What an iteration loop needs: the operator, the separation, the control and the tolerances."""

    apply: object
    base_gap: np.ndarray
    cell_area: float
    load: float               # None under approach control
    approach: float
    offset: tuple
    targets: np.ndarray
    modes: RigidModes
    options: SolverOptions
    window: object
    apply_window: object
    diagonal: float = None
    precondition: object = None

    def self_compliance(self):
        """Displacement of a cell under its own unit pressure (the operator is a convolution: any cell)."""
        if self.diagonal is None:
            self.diagonal = _self_compliance(self.apply, self.base_gap.shape)
        return self.diagonal

    def entry(self, step):
        """The re-entry factor of Polonsky & Keer: the conjugate step, at most a cell's own stiffness.

        Preconditioned, the step multiplies the preconditioned gap, not the gap: the caller passes the step
        times the preconditioner's gain on the gap (``sum z g / sum g^2`` over the contact), the stiffness
        the step applies to the gap, as the plain iteration's step is.
        """
        return 1.0 / self.self_compliance() if step <= 0 else min(step, 1.0 / self.self_compliance())


def _stalls(count, step, conjugate):
    """Iterations in a row with no step and nothing re-entered: more than 2, and the solve has stalled."""
    return count + 1 if step == 0.0 and conjugate else 0


def _iterate(problem, start):
    """Polonsky-Keer conjugate gradients from the pressure ``start``, with fused passes (:mod:`framework._fused`).

    The same iteration as :func:`_iterate_reference`, which it must match to
    rounding: each block of elementwise work is one pass of
    :func:`framework._fused.passes` instead of a dozen numpy expressions, the
    new pressure is written into a second buffer instead of a new array, and the
    mean response over the contact is folded into the curvature
    (``sum (r - m) d = sum r d - m sum d``) instead of being subtracted, and
    the passes on the direction and the new pressure walk only the rows that
    hold the contact, this one's and the last one's (outside them both vanish).
    The gap is kept as ``b + A p``, the rigid shift subtracted where the passes
    read it (no pass writes the centred gap), and it is written only on the
    rows where the pressure may be positive: on the others the norm pass finds
    the free cells that interpenetrate from ``b`` and ``A p`` directly, and the
    gap is completed there only when it is read (a re-entry, the last check).

    Returns
    -------
    tuple
        ``(pressure, displacement, gap, approach, coefficients, iterations, residual, change)``.
    """
    passes = _fused.passes(np.size(start))
    apply, options, modes = problem.apply, problem.options, problem.modes
    load_control = problem.load is not None
    base = np.ascontiguousarray(problem.base_gap)
    # the pressure and the direction in arrays the FFTs of an unpadded grid read in place: the start is the
    # caller's own array and the first of the two pressure buffers (solve_normal aligns it before the call, so
    # that no second grid is held; fft.aligned here only guarantees the C order the passes' flat views need)
    pressure, fresh, direction = fft.aligned(start), fft.empty_aligned(base.shape), fft.empty_aligned(base.shape)
    direction[...] = 0.0
    gap = np.empty_like(base)
    contact = np.empty(pressure.shape, dtype=bool)
    # the passes walk flat views of the grid fields (see framework._fused)
    flat_gap, flat_contact, flat_direction = (a.reshape(-1) for a in (gap, contact, direction))
    whole = (slice(None), slice(None))
    rows, columns = pressure.shape
    held = (0, rows)    # rows outside which the direction and the second buffer vanish (at first: unknown)
    support = (0, rows)     # rows outside which the pressure vanishes (at first: unknown)
    coefficients = (0.0, 0.0, 0.0)
    norm_old, conjugate = 1.0, False
    change, residual, stalled = np.inf, np.inf, 0
    for iteration in range(options.max_iterations + 1):
        displacement = apply(pressure)
        # the gap and the contact on the pressure's rows only; the contact is false elsewhere (it was set on rows
        # the pressure covered, which the next one covers too), the gap there is written when it is read
        total, count, quartic, first, last = passes.gap(base, displacement, pressure, gap, contact, *support)
        current = (first, last) if count else held
        first_row, last_row = min(held[0], current[0]), max(held[1], current[1])
        span = slice(first_row * columns, last_row * columns)    # those rows in the flat views
        held = current
        # the gap stays b + A p: the passes subtract the rigid shift where they read it (the approach; under a
        # tilt the plane is removed here, a pass of its own, and the shift is 0)
        shift = problem.approach
        if load_control and modes.tilt:
            rigid, coefficients = modes.fit(gap, contact)
            gap -= rigid
            shift = 0.0
        elif load_control:
            shift = total / count
            coefficients = (shift, 0.0, 0.0)
        delta = coefficients[0] if load_control else problem.approach
        norm, overlaps, quartic_rest = passes.norm(gap, contact, base, displacement, shift, *support)
        quartic += quartic_rest     # over the whole grid: sum u^4 (numpy passes: maxima of u^4), >= max u^4
        last_check = change < options.tolerance or iteration == options.max_iterations or stalled > 2
        if overlaps or last_check:   # the re-entry and the residual read the gap on every row
            _complete(gap, base, displacement, *support)
        # (a stalled solve stops here too, with the displacement and gap of the pressure it returns)
        if last_check:
            residual = _residual(gap, contact, displacement, shift)
            if residual < options.residual_tolerance or iteration == options.max_iterations or stalled > 2:
                if shift:
                    gap -= shift
                break
        step, gain = 0.0, 1.0
        # as in the reference: no direction when the gap is flat to rounding over the contact set; the
        # bound sqrt(sum u^4) >= max u^2 spares the exact maximum unless the norm comes near that limit
        if (norm > 1e-24 * np.sqrt(quartic) * count
                or norm > (1e-12 * max(displacement.max(), -displacement.min())) ** 2 * count):
            box = whole if problem.window is None else problem.window(contact)
            preconditioned = None
            if problem.precondition is not None:
                # the products' box where they have one (an open grid), else a box of the preconditioner's
                around = box if box != whole else problem.precondition.window(contact)
                preconditioned, mean, product = _precondition(problem, passes, gap, contact, around, count,
                                                              load_control, shift)
            if preconditioned is not None:
                gain = product / norm
                top, left = _corner(around)
                numerator = passes.direction_box(direction, preconditioned, gap, contact,
                                                 product / norm_old if conjugate else 0.0, mean,
                                                 first_row, last_row, top, left, shift)
                norm_old = product
            else:
                numerator = passes.direction(flat_direction[span], flat_gap[span], flat_contact[span],
                                             norm / norm_old if conjugate else 0.0, shift)
                norm_old = norm
            if problem.window is None:
                response = apply(direction)
            else:
                response = problem.apply_window(direction[box], box)
            if load_control and modes.tilt:
                response -= modes.fit(response, contact[box], box)[0]
                curvature = _dot(response, direction[box])
            else:
                first, second = _corner(box)
                if box == whole:
                    first, response = first_row, response[first_row:last_row]
                product, inside, outside = passes.curvature(response, direction, contact, first, second)
                curvature = product - inside * outside / count if load_control else product
            # a direction that rounding has swamped takes no step
            step = numerator / curvature if curvature > 0 else 0.0
        else:
            direction[...] = 0.0
        conjugate = not overlaps
        entry = 0.0 if conjugate else problem.entry(step * gain)
        if overlaps:   # cells anywhere may re-enter
            span = slice(None)
        for halving in range(40):
            total = passes.advance(fresh.reshape(-1)[span], pressure.reshape(-1)[span], flat_direction[span],
                                   flat_gap[span], flat_contact[span], 0.5**halving * step, 0.5**halving * entry,
                                   shift)
            factor = 1.0
            if not load_control:
                break
            if modes.tilt:
                if modes.restore(fresh, problem.targets, problem.cell_area):
                    break
            elif total > 0:
                factor = problem.targets[0] / (total * problem.cell_area)
                break
        else:  # even a vanishing step leaves no pressure that carries the load (the current one did: not reached)
            raise LoadNotCarriedError(_not_carried(problem.load, problem.offset, pressure > 0))
        if halving:  # the step was cut: the conjugate directions are lost, restart them
            conjugate = False
        moved, total = passes.rescale(fresh.reshape(-1)[span], pressure.reshape(-1)[span], factor)
        change = moved / max(total, np.finfo(float).tiny)
        pressure, fresh = fresh, pressure
        # the new pressure vanishes outside the rows walked (a tilt's restoring plane covers the contact only,
        # but keep the whole grid there: it is a small case)
        support = (0, rows) if span == slice(None) or modes.tilt else (first_row, last_row)
        stalled = _stalls(stalled, step, conjugate)
    return pressure, displacement, gap, delta, coefficients, iteration, residual, change


def _complete(gap, base, displacement, top, bottom):
    """Write ``gap = base + displacement`` on the rows outside ``top .. bottom - 1`` (the gap pass's)."""
    for rows in (slice(0, top), slice(bottom, None)):
        np.add(base[rows], displacement[rows], out=gap[rows])


def _precondition(problem, passes, gap, contact, box, count, load_control, shift):
    """The preconditioned gap (``gap - shift`` on the contact) on ``box`` (the preconditioner's), the mean it
    loses on the contact set and its product with the gap.

    Returns ``(field, mean, product)``: the direction's new part is ``field - mean``
    on the contact set (0 elsewhere); ``field`` is the preconditioner's buffer.
    ``(None, 0, 0)`` when rounding leaves no positive product: the step then
    follows the gap, unpreconditioned, as the reference does.
    """
    top, left = _corner(box)
    buffer = problem.precondition.input(contact[box].shape)   # the masked gap goes straight into the operator's input
    passes.mask(buffer, gap, contact, top, left, shift)
    field = problem.precondition.apply(buffer, copy=False)
    if load_control and problem.modes.tilt:
        field = field - problem.modes.fit(field, contact[box], box)[0]
    inside, product, total = passes.preconditioned(field, buffer, contact, top, left)
    mean = inside / count if load_control and not problem.modes.tilt else 0.0
    product -= mean * total
    if not product > 0.0:
        return None, 0.0, 0.0
    return field, mean, product


def _iterate_reference(problem, pressure):
    """The iteration of :func:`_iterate` as plain numpy expressions: the reference the tests hold it to."""
    apply, base_gap, options, modes = problem.apply, problem.base_gap, problem.options, problem.modes
    load_control = problem.load is not None
    cell_area, targets, approach = problem.cell_area, problem.targets, problem.approach
    coefficients = (0.0, 0.0, 0.0)
    direction = np.zeros_like(pressure)
    norm_old, conjugate = 1.0, False
    change, residual, stalled = np.inf, np.inf, 0
    for iteration in range(options.max_iterations + 1):
        displacement = apply(pressure)
        gap = base_gap + displacement
        contact = pressure > 0
        if load_control:
            rigid, coefficients = modes.fit(gap, contact)
            delta = coefficients[0]
            gap -= rigid
        else:
            delta = approach
            gap -= delta
        # (a stalled solve stops here too, with the displacement and gap of the pressure it returns)
        if change < options.tolerance or iteration == options.max_iterations or stalled > 2:
            residual = _residual(gap, contact, displacement)
            if residual < options.residual_tolerance or iteration == options.max_iterations or stalled > 2:
                break
        # The direction vanishes outside the contact set, so plain dot products are sums over it.
        np.copyto(direction, 0.0, where=~contact)
        gap_c = np.where(contact, gap, 0.0)
        norm = _dot(gap_c, gap_c)
        step, curvature, gain = 0.0, 0.0, 1.0
        # A gap flat to rounding over the contact set has no direction to follow (a set with no free
        # direction: one cell, the symmetric apex cells of an even grid, three cells under a tilt):
        # the rounding noise would give an arbitrary step. Only the re-entry below can move it.
        if norm > (1e-12 * np.abs(displacement).max()) ** 2 * np.count_nonzero(contact):
            box = (slice(None), slice(None)) if problem.window is None else problem.window(contact)
            # Preconditioned: the approximate inverse of the gap on the box, on the contact set, projected
            # as the gap is (no mean, or no plane, over the contact set: the load and moments stay)
            preconditioned = gap_c
            if problem.precondition is not None:
                preconditioned = np.zeros_like(gap_c)
                around = box if box != (slice(None), slice(None)) else problem.precondition.window(contact)
                preconditioned[around] = problem.precondition.apply(gap_c[around])
                preconditioned[~contact] = 0.0
                if load_control:
                    preconditioned -= modes.fit(preconditioned, contact)[0]
                    preconditioned[~contact] = 0.0
                product = _dot(gap_c, preconditioned)
                if product > 0.0:  # else rounding only (the preconditioner is positive definite): plain
                    norm, gain = product, product / norm
                else:
                    preconditioned = gap_c
            direction *= norm / norm_old if conjugate else 0.0
            direction += preconditioned
            norm_old = norm
            if problem.window is None:
                response = apply(direction)
            else:
                response = problem.apply_window(direction[box], box)
            if load_control:
                response -= modes.fit(response, contact[box], box)[0]
            curvature = _dot(response, direction[box])
            # a direction that rounding has swamped takes no step
            step = _dot(gap_c, direction) / curvature if curvature > 0 else 0.0
        else:
            direction[:] = 0.0
        # Re-entry (Polonsky & Keer): free cells that interpenetrate join the contact set, with the
        # pressure that closes their overlap: the conjugate step times the overlap, at most what
        # would close it in a cell alone (its own compliance), which is the step when there is none.
        overlap = ~contact & (gap < 0)
        conjugate = not overlap.any()
        entry = 0.0 if conjugate else problem.entry(step * gain)
        previous = pressure
        # Under load control the step must leave a pressure that can carry the load (and, with a
        # tilt, both moments: not every clipped step can): halve it until it does.
        for halving in range(40):
            pressure = np.maximum(previous - 0.5**halving * step * direction, 0.0)
            pressure[overlap] = -0.5**halving * entry * gap[overlap]
            if not load_control or modes.restore(pressure, targets, cell_area):
                break
        else:  # even a vanishing step leaves no pressure that carries the load (previous did: not reached)
            raise LoadNotCarriedError(_not_carried(problem.load, problem.offset, previous > 0))
        if halving:  # the step was cut: the conjugate directions are lost, restart them
            conjugate = False
        change = np.abs(pressure - previous).sum() / max(pressure.sum(), np.finfo(float).tiny)
        stalled = _stalls(stalled, step, conjugate)
    return pressure, displacement, gap, delta, coefficients, iteration, residual, change
