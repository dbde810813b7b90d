"""Resolutions too coarse to trust a result to a percent, said in one :class:`ResolutionWarning` line each.

Three ways a grid can be too coarse for the numbers it returns, each with a threshold measured against an
independent reference (the measurements are repeated in ``tests/test_resolution.py`` and ``bench/resolution.py``):

* **a contact a few cells wide**: Hertz's peak pressure (elastic sphere, open grid) comes out 12 % high at 1
  cell per contact radius, 2.6 % at 2, 1.1 % at 3, 0.6 % at 4, 0.2 % at 6: warned below
  :data:`MIN_CELLS_PER_RADIUS` (half-width of a line contact alike). Needs the result (the contact's size).
* **a rolling wake shorter than a cell**: each retardation term ``(c_k, lambda_k)`` of the contact compliance
  leaves a wake, and a layer at the contact's leading edge, ``V lambda_k`` long. Shorter than a cell ``h``, the
  layer is smeared over the leading cell and the friction coefficient comes out low. Measured (a cylinder on a
  standard linear solid, E(0)/E(inf) = 2 and 10, steady, against grids 8 and 16 times finer; ``h`` = a/16,
  a/32, a/64 of the half-width ``a``): the error collapses onto ``(h / a) F(V lambda / h)`` with ``F`` = 1.0,
  0.92, 0.57, 0.22, 0.055, 0.01 at 1/16, 1/8, 1/4, 1/2, 1, 2 cells per wake (:func:`layer_error`), for a
  sphere alike; transient rolling (one cell per step) errs by half to all of it. The length is the
  retardation time's wake (the compliance's, which :mod:`framework.operators.rolling` filters), not the
  relaxation time's: materials with lambda/tau = 2 and 10 give the same curve in ``V lambda / h``. With
  several terms, each term's error is weighted by its share of the friction (:func:`friction_shares`,
  checked on two-term solids to a factor 1.5). Warned when the estimate reaches :data:`FRICTION_ERROR`; it
  needs the contact's size, so a run checks it on its result, and ``check`` on a Hertz estimate.
* **a body of barely three cuboids per semi-axis**: a staircase of whole cuboids (the default geometry).
  Measured against Eshelby's uniform interior stress (deep bodies, contrasts 1/18 to 10): at 3 cuboids per
  semi-axis a sphere's staircase holds up to 20 % too much volume (4 % at 4, 0.8 % at 6), the stress at its
  centre is 0.7-23 % off, growing with the contrast (0.4-14 % at 4, 0.3-8 % at 6; 3.9, 2.1, 1.4 % for a
  ratio of 3) and its mean interior stress 0.8-4.6 % (0.7-3.3 % at 4);
  the step from 3 to 4 gains most, further refinement gains at first order. With ``geometry='laminate'`` (cut
  cuboids carry their share of the body) the volume is right, but the centre's stress is still 5-8 % off at 3
  cuboids (stiffness ratios 10 and 1/18), 3.5-6 % at 4, 2.2-3.3 % at 6: the same threshold. Warned below
  :data:`MIN_CUBOIDS_PER_SEMI_AXIS`, before the first step (the bodies are known); the equivalent
  inclusion method refuses fewer than 3 (:data:`framework.inclusions.bodies.MIN_CELLS_PER_SEMI_AXIS`).
"""
import warnings

import numpy as np

from .errors import ResolutionWarning

#: A contact narrower than this many cells (radius, or half-width of a line contact) is warned of. Measured,
#: Hertz (elastic sphere, open grid): the peak pressure is 12 % high at 1 cell per radius, 2.6 % at 2, 1.1 % at 3,
#: 0.6 % at 4, 0.2 % at 6.
MIN_CELLS_PER_RADIUS = 4
#: A rolling run whose friction coefficient is estimated this far off (relative) by wakes shorter than a cell
#: is warned of: the same 1 % as a contact of :data:`MIN_CELLS_PER_RADIUS` cells.
FRICTION_ERROR = 0.01
#: ``F(x) = 1 / (1 + (x / LAYER_SCALE)^LAYER_POWER)``, the friction error per ``h / a`` of a wake of ``x`` cells:
#: a least-squares-by-eye fit of the measured 1.0, 0.92, 0.57, 0.22, 0.055, 0.01 at x = 1/16 ... 2 (within 15 %).
LAYER_SCALE = 0.28
LAYER_POWER = 2.24
#: A body spanning fewer cuboids than this along a semi-axis is warned of (see the module docstring).
MIN_CUBOIDS_PER_SEMI_AXIS = 4


def warn(messages, stacklevel=1):
    """Issue each message as a :class:`ResolutionWarning` (``stacklevel`` as for :func:`warnings.warn`, from here)."""
    for message in messages:
        warnings.warn(ResolutionWarning(message), stacklevel=stacklevel)


# --------------------------------------------------------------------------- contact size

def contact_message(size, cell, *, line, where):
    """The warning text for a contact of ``size`` [m] (radius, or half-width if ``line``) on cells of ``cell`` [m].

    Returns None when the contact spans at least :data:`MIN_CELLS_PER_RADIUS` cells (or does not touch).
    ``where`` says which step (or which estimate) it is.
    """
    if not size > 0 or size >= MIN_CELLS_PER_RADIUS * cell:
        return None
    what = "half-width" if line else "contact radius"
    return (f"the {what} {where} is {size:.4g} m, {size / cell:.2g} cells of {cell:.4g} m: a contact resolved by "
            f"fewer than {MIN_CELLS_PER_RADIUS} cells per {what} has its peak pressure off by 1 % or more (12 % at "
            f"one cell); refine the grid (cells of {size / MIN_CELLS_PER_RADIUS:.3g} m or smaller) or shrink it "
            f"around the contact")


def contact_cell(grid, line):
    """The cell [m] that resolves a contact: across the line of a line contact, else the larger side."""
    return grid.spacing[1 if grid.periodic[0] else 0] if line else max(grid.spacing)


# --------------------------------------------------------------------------- rolling wakes

def layer_error(cells_per_wake):
    """``F(x)``: the relative friction error per ``h / a`` of a term whose wake spans ``x = V lambda / h`` cells [-]."""
    x = np.asarray(cells_per_wake, dtype=float)
    return 1.0 / (1.0 + (x / LAYER_SCALE) ** LAYER_POWER)


def friction_shares(series, speed, size):
    """Each retardation term's share of the friction of a contact of ``size`` [m] rolling at ``speed`` [m/s].

    A term's friction rises like ``c_k y_k`` at low speed and falls like ``c_k / y_k`` at high speed
    (``y_k = V lambda_k / a``; THEORY.md sec. 7, the two limits of
    :func:`framework.reference.low_speed_friction_slope` and ``high_speed_sphere_friction``): the share is
    ``c_k g(y_k) / sum_j c_j g(y_j)`` with ``g(y) = y / (1 + y^2)``.
    """
    coefficients = np.array([c for c, _ in series.terms], dtype=float)
    y = speed * np.array([lam for _, lam in series.terms], dtype=float) / size
    weights = coefficients * y / (1.0 + y * y)
    total = weights.sum()
    return weights / total if total > 0 else np.zeros_like(weights)


def friction_errors(series, speed, cell, size):
    """Estimated relative error [-] of the friction coefficient from each term's wake (see the module)."""
    cells = speed * np.array([lam for _, lam in series.terms], dtype=float) / cell
    return friction_shares(series, speed, size) * (cell / size) * layer_error(cells)


def _largest(test, low, high):
    """The largest value in ``[low, high]`` for which ``test`` holds (it holds at ``low``, 60 bisections in log)."""
    if test(high):
        return high
    for _ in range(60):
        middle = np.sqrt(low * high)
        low, high = (middle, high) if test(middle) else (low, middle)
    return low


def _worst_wake(series, speed, cell, sizes, steps, how):
    """``[message]`` for the step of ``steps`` whose wakes put the friction furthest off (contact sizes ``sizes``
    per step), or ``[]`` when it is within :data:`FRICTION_ERROR`."""
    totals = [friction_errors(series, speed, cell, sizes[k]).sum() for k in steps]
    k = int(steps[int(np.argmax(totals))])
    message = wake_message(series, speed, cell, sizes[k], where=f"at step {k}{how}")
    return [message] if message else []


def wake_message(series, speed, cell, size, *, where):
    """The warning text when wakes shorter than a cell put the friction :data:`FRICTION_ERROR` or more off, else None.

    Parameters
    ----------
    series : ComplianceSeries
        The contact compliance (its retardation terms).
    speed : float
        Rolling speed ``|V|`` [m/s].
    cell : float
        Cell size along the motion [m].
    size : float
        Contact radius, or half-width of a line contact [m].
    where : str
        Which step or estimate.
    """
    if not len(series.terms) or not size > 0 or not speed > 0:
        return None
    errors = friction_errors(series, speed, cell, size)
    if errors.sum() < FRICTION_ERROR:
        return None
    k = int(np.argmax(errors))
    c, lam = series.terms[k]

    def fine(h):
        return friction_errors(series, speed, h, size).sum() < FRICTION_ERROR
    use = _largest(fine, 1e-6 * cell, cell)

    def fast(v):
        return friction_errors(series, v, cell, size).sum() < FRICTION_ERROR
    # the error falls as the wakes lengthen; 1e6 times faster every wake spans thousands of cells
    faster = next((v for v in speed * np.geomspace(1.0, 1e6, 121)[1:] if fast(v)), None)
    if faster is not None:
        slow, faster = speed, faster
        for _ in range(60):
            middle = np.sqrt(slow * faster)
            slow, faster = (slow, middle) if fast(middle) else (middle, faster)
    speeds = f"; or roll faster than {faster:.3g} m/s on this grid" if faster is not None else ""
    return (f"the friction coefficient {where} is an estimated {100 * errors.sum():.2g} % low: the wake of "
            f"retardation term {k} (lambda = {lam:.4g} s, {100 * friction_shares(series, speed, size)[k]:.3g} % of "
            f"the friction) is V lambda = {speed * lam:.3g} m, {speed * lam / cell:.2g} cells of {cell:.4g} m, "
            f"thinner than a cell at the contact's leading edge (contact size {size:.4g} m); refine the grid along "
            f"the motion (cells of {use:.3g} m or smaller){speeds}")


# --------------------------------------------------------------------------- bodies

def body_messages(grid, inclusions):
    """The warning texts for bodies spanning fewer than :data:`MIN_CUBOIDS_PER_SEMI_AXIS` cuboids along a semi-axis.

    Cuboids along a semi-axis direction ``d`` are counted as in
    :meth:`framework.inclusions.InclusionSet.check_inside`: ``a_k / sqrt(sum_i (d_i h_i)^2)``.
    """
    if not inclusions or grid.layers == 0:
        return []
    spacing = np.array([*grid.spacing, grid.layer_thickness])
    messages = []
    for k, body in enumerate(inclusions):
        steps = np.sqrt(np.square(spacing[:, None] * body.orientation).sum(axis=0))
        cells = np.asarray(body.semi_axes) / steps
        axis = int(np.argmin(cells))
        if cells[axis] < MIN_CUBOIDS_PER_SEMI_AXIS:
            scale = cells[axis] / MIN_CUBOIDS_PER_SEMI_AXIS
            messages.append(
                f"inclusions[{k}]: semi_axes[{axis}] = {body.semi_axes[axis]:.4g} m spans {cells[axis]:.3g} cuboids "
                f"(cuboids {spacing[0]:.3g} x {spacing[1]:.3g} x {spacing[2]:.3g} m): with fewer than "
                f"{MIN_CUBOIDS_PER_SEMI_AXIS} cuboids per semi-axis the stress at the body's centre is up to 23 % off "
                f"(5-8 % with geometry='laminate') and a staircase's volume up to 20 % (contrasts 1/18 to 10, "
                f"against Eshelby); use cuboids of {spacing[0] * scale:.3g} x {spacing[1] * scale:.3g} x "
                f"{spacing[2] * scale:.3g} m or smaller")
    return messages


def check_bodies(grid, inclusions, stacklevel=1):
    """Warn (before the first step) of bodies spanning fewer than :data:`MIN_CUBOIDS_PER_SEMI_AXIS` cuboids.

    ``stacklevel`` 1 points the warning at the caller, 2 at its caller, ...
    """
    warn(body_messages(grid, inclusions), stacklevel=stacklevel + 2)


# --------------------------------------------------------------------------- a result

def result_messages(result):
    """The warning texts of a finished run: its narrowest contact, and its wakes at the worst moving step."""
    if not len(result):
        return []
    line = result.line_contact
    sizes = np.asarray(result.half_width if line else result.contact_radius, dtype=float)
    grid = result.grid
    messages = []
    touching = sizes > 0
    if touching.any():
        k = int(np.flatnonzero(touching)[np.argmin(sizes[touching])])
        message = contact_message(sizes[k], contact_cell(grid, line), line=line, where=f"at step {k}")
        if message:
            messages.append(message)
    schedule = result.schedule
    speed = getattr(schedule, "speed", None)
    if speed is None or not hasattr(result.material, "contact_compliance"):
        return messages
    series = result.material.contact_compliance()
    cell = grid.spacing[schedule.axis]
    moving = np.flatnonzero(result._moving() & touching)
    if len(series.terms) and moving.size:
        messages += _worst_wake(series, speed, cell, sizes, moving, "")
    return messages


def check_result(result, stacklevel=1):
    """Warn of a finished run's contacts and wakes resolved too coarsely (see :func:`result_messages`).

    ``stacklevel`` 1 points the warning at the caller, 2 at its caller, ...
    """
    warn(result_messages(result), stacklevel=stacklevel + 2)


# --------------------------------------------------------------------------- before the run: estimates

def _hertz_size(indenter, load, compliance, line, grid):
    """Hertz's contact radius (half-width of a line contact) [m] under ``load`` [N] with ``compliance`` [1/Pa]."""
    if line:
        length = grid.size[indenter.axis]
        return np.sqrt(4.0 * (load / length) * indenter.radius * compliance / np.pi)
    return (0.75 * load * indenter.radius * compliance) ** (1.0 / 3.0)


def estimated_sizes(simulation):
    """Hertz estimates of the contact size [m] at the output times, or None where Hertz says nothing.

    A sphere, or a cylinder along the periodic axis of a grid periodic along that one axis (a line contact),
    under load (a sphere also under approach: ``a = sqrt(R delta)``), without an offset. At rest the compliance
    is ``C*(t)`` of the time since the start (Lee & Radok's step load); rolling, ``C*`` of the time the
    material takes to cross the contact, ``2 a / V`` (a few fixed-point passes).

    Returns
    -------
    (sizes, line) or None
        ``sizes`` one per output time (0 without load), ``line`` True for a line contact.
    """
    from . import indenters, schedules
    indenter, grid, schedule = simulation.indenter, simulation.grid, simulation.schedule
    line = sum(grid.periodic) == 1
    if isinstance(indenter, indenters.Cylinder):
        if not (line and grid.periodic[indenter.axis]):
            return None
    elif not isinstance(indenter, indenters.Sphere) or line:
        return None
    if getattr(schedule, "offset", None) is not None and any(schedule.offset):
        return None
    series = simulation.material.contact_compliance()
    times = np.asarray(simulation.output_times, dtype=float)
    if isinstance(schedule, schedules.Rolling):
        values = np.asarray(schedule.loads if schedule.steady else schedule.history(
            np.maximum(times - schedule.motion_start, 0.0)), dtype=float)
        if not schedule.steady and schedule.start is not None:
            resting = times <= schedule.motion_start
            values = np.where(resting, schedule.start.history(times), values)
        sizes = []
        for value in values:
            size = _hertz_size(indenter, value, series.c0 if series.c0 > 0 else float(series(1.0)), line, grid)
            for _ in range(20):
                size = _hertz_size(indenter, value, float(series(2.0 * size / schedule.speed)), line, grid)
            sizes.append(size)
        return np.array(sizes), line
    values = np.asarray(schedule.history(times), dtype=float)
    if schedule.control == "approach":
        if line:
            return None
        return np.sqrt(indenter.radius * values), line
    return np.array([_hertz_size(indenter, w, float(series(t)), line, grid) for w, t in zip(values, times)]), line


def preview_messages(simulation):
    """What a run would warn of, told before it starts (``python -m framework check``).

    The bodies exactly; the contact and the wakes from Hertz estimates (:func:`estimated_sizes`), each marked
    as an estimate, and nothing where Hertz does not apply.
    """
    messages = body_messages(simulation.grid, simulation.inclusions or [])
    try:
        estimate = estimated_sizes(simulation)
    except (AttributeError, TypeError, ValueError, ZeroDivisionError):
        estimate = None
    if estimate is None:
        return messages
    sizes, line = estimate
    grid, schedule = simulation.grid, simulation.schedule
    touching = sizes > 0
    if not touching.any():
        return messages
    k = int(np.flatnonzero(touching)[np.argmin(sizes[touching])])
    message = contact_message(sizes[k], contact_cell(grid, line), line=line,
                              where=f"at step {k} (Hertz's estimate)")
    if message:
        messages.append(message)
    speed = getattr(schedule, "speed", None)
    series = simulation.material.contact_compliance()
    if speed is not None and len(series.terms):
        cell = grid.spacing[schedule.axis]
        moving = np.flatnonzero(touching & (np.ones(len(sizes), bool) if schedule.steady
                                            else np.asarray(simulation.output_times) > schedule.motion_start))
        if moving.size:
            messages += _worst_wake(series, speed, cell, sizes, moving, " (with Hertz's contact size)")
    return messages
