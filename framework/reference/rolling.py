"""Steady rolling (frictionless sliding) of a rigid body over a viscoelastic half-space: dense references.

Independent references for the steady-state solver of THEORY.md sec. 7: a
rigid cylinder in plane strain (Hunter's problem; S. C. Hunter, "The rolling
contact of a rigid cylinder with a viscoelastic half space", J. Appl. Mech. 28
(1961) 611-617) and a rigid sphere, both discretised directly with dense
matrices. Nothing here uses :mod:`framework.operators`, :mod:`framework.fft`,
the solver or the time stepper: the influence coefficients are written below
from their closed forms, the exponential filter of the hereditary integral is
folded into them by quadrature, and the discrete complementarity problem with
the load constraint is solved exactly by an active-set method.

Conventions
-----------
SI units. Coordinates ``(x1, x2)`` in the body's frame, centred on its axis;
``x3`` (and the displacement ``u3``) positive into the solid; pressure ``p``
positive compressive. The body moves with the constant velocity ``V`` along
``x1`` over the material (``V > 0``: towards ``+x1``; frictionless sliding and
rolling of a rigid body are the same normal problem, seed 000). Heights
``h = (x1**2 + x2**2) / (2 R)`` (sphere, a paraboloid) or ``h = x1**2 / (2 R)``
(cylinder with its axis along ``x2``). Gap ``g = h - delta + u3 >= 0``,
``p >= 0``, ``p g = 0`` and ``sum p dA = W`` (load control).

The steady displacement and the direction of the filter
---------------------------------------------------------
The material obeys ``u3(X, t) = int G(X - Y) int_{-inf}^{t} C*(t - t') d_t' p(Y, t') dY``
in material coordinates ``X`` (correspondence with a constant Poisson ratio:
the spatial Boussinesq kernel ``G`` per unit compliance acts on the compliance
history of the pressure at the *material* point ``Y``; THEORY.md sec. 5), with
``C*(t) = c0 + flow t + sum_k c_k (1 - exp(-t/lambda_k))`` the contact
compliance of the material (:class:`framework.materials.ComplianceSeries`).

The body's axis is at ``X1 = V t``, so a material point ``Y`` sits at
``y = Y - V t e1`` in the body's frame now and sat at ``Y - V t' e1 = y + V s e1``
a time ``s = t - t'`` ago: with ``V > 0`` the material it carries came from
the leading side, ``+x1``. In the steady state ``p(Y, t') = P(y + V s e1)`` and
``d_t' p = -V d_1 P(y + V s e1) = -d_s [P(y + V s e1)]``, so that

    int_{-inf}^{t} C*(t - t') d_t' p = - int_0^inf C*(s) d_s P(y + V s e1) ds
                                    = C*(0) P(y) + int_0^inf C*'(s) P(y + V s e1) ds

(integration by parts; ``C*(s) P(y + V s e1)`` vanishes as ``s -> inf`` for a
pressure of bounded support, even with the linear flow term). With
``C*'(s) = flow + sum_k (c_k/lambda_k) exp(-s/lambda_k)`` and ``X - Y = x - y``:

    u3(x) = G * [c0 P + sum_k c_k F_k P + flow Q](x),
    F_k P(y) = int_0^inf (1/lambda_k) exp(-s/lambda_k) P(y + V s e1) ds,
    Q(y) = int_0^inf P(y + V s e1) ds = (1/V) int_{y1}^{inf} P(xi, y2) dxi      (V > 0),

which is THEORY.md's formula with the sign made explicit: the filter looks
*ahead* of the point along the motion (``+x1`` for ``V > 0``), i.e. the
material under and behind the body remembers the pressure it met earlier
ahead. Folding the filter into the kernel (``G`` is translation invariant):
``G * F_k P = G_k * P`` with

    G_k(d) = int_0^inf (1/lambda_k) exp(-s/lambda_k) G(d + V s e1) ds
           = int_0^inf exp(-sigma) G(d + L_k sigma e1) dsigma,   L_k = V lambda_k,

``d = x - y`` the offset of the field point from the source. For a piecewise-
constant pressure the same holds cell by cell with the cell influence
coefficient in place of ``G`` (the filter commutes with the cell average), so
``u3_i = sum_j A_ij p_j`` with ``A_ij = c0 K(d_ij) + sum_k c_k K_k(d_ij)``, a
dense, non-symmetric matrix that needs no grid behind the contact: the wake is
inside ``K_k``. ``V < 0`` mirrors ``d1``. ``V = 0`` gives the relaxed elastic
problem (compliance ``C*(inf)``).

Quadrature of the filter: ``K_k(d) = int_0^inf exp(-sigma) K(d1 + L sigma, d2) dsigma``
over ``sigma`` in ``[0, 40]`` (``e^-40 ~ 4e-18``), split where
``d1 + L sigma`` crosses a cell edge ``+-dx1/2`` (the cell kernel's gradient is
log-singular there), each piece graded geometrically towards both ends (down
to a fraction ``2**-levels`` of the piece, ``levels`` growing with
``log2(L / dx1)`` so that the ``1/xi`` decay of the kernel near an edge is
resolved at high speed) and covered elsewhere by panels of width <= 1.25, with
10 Gauss-Legendre points per panel: ~1e-12 relative, checked in
``tests/test_reference_rolling.py`` against the exact plane-strain result and
against adaptive quadrature.

Influence coefficients
----------------------
* Plane strain, uniform pressure on ``|y - x_j| <= h``:
  ``u3(x) = -(2/pi) C* int ln(|x - y| / l) p dy`` (Johnson, *Contact
  Mechanics*, 1985, eq. 2.41b with the arbitrary constant written as the
  length ``l``), so ``K(d) = -(2/pi) [F(d + h) - F(d - h)]`` with
  ``F(t) = t ln(|t|/l) - t``. Plane-strain displacements are defined up to a
  constant: with ``l = half_length`` the reported approach is measured from
  the surface points at the distance ``half_length`` from the load; it enters
  only ``delta``, never the pressure. The filtered kernel has a closed form
  (used by the tests): ``int_0^inf e^-sigma F(t + L sigma) dsigma = F(t) + L
  [ln(|t|/l) - e^(t/L) Ei(-t/L)]``.
* Half-space, uniform pressure on the rectangle ``|y1| <= a``, ``|y2| <= b``
  (Love 1929; Johnson 1985 sec. 3.2):
  ``K(x) = (1/pi) Sum+- [X ln(Y + R) + Y ln(X + R)]`` (corner sum over
  ``X = x1 -+ a``, ``Y = x2 -+ b``, ``R = sqrt(X**2 + Y**2)``), evaluated without
  cancellation for negative ``X`` or ``Y`` and, beyond 200 cell sizes, by its
  multipole expansion ``(4ab/pi) [1/r + (a**2 (3 x1**2 - r**2) + b**2 (3 x2**2 - r**2)) / (6 r**5)]``
  (the corner sum loses ``(r/dx)**2`` of its digits to cancellation).

Fluids and solids without instantaneous compliance
-----------------------------------------------------
A fluid (``flow > 0``, :class:`framework.materials.Maxwell`) leaves behind the
body a groove whose effective pressure ``Q`` does not decay: ``Q = W'/V`` on
the whole wake in plane strain, the line density ``(1/V) int P(xi, y2) dxi`` on
a strip as wide as the contact in 3-D. After the body has travelled a distance
``D``, the wake tilts the surface under the body, in plane strain, by
``(2/pi) (flow W'/V) ln(D/a)``: without bound, so there is no steady state. In
3-D the tilt converges (``int dxi / xi**2``) but the approach grows like
``ln D``: the pressure has a steady limit, the approach has none. Both
references refuse a fluid (:class:`ParameterError`). A solid without
instantaneous compliance (``c0 = 0``, Kelvin-Voigt) is refused too: its
pressure jumps at the leading edge (the layer below shrinks to nothing).

Resolution and limits
---------------------
* With ``c0 > 0`` the pressure rises steeply at the leading edge over a layer
  of width about ``|V| lambda_k c0 / c_k`` (where ``c0 + c_k / (1 - i k L_k)``
  turns from the retarded to the glassy response): the peak pressure needs
  cells finer than that; the friction coefficient does not (it converges at
  about second order in the cell size once ``|V| lambda_k`` spans a cell).
* Low speed (perturbation of the relaxed contact, ``F_k P = P + V lambda_k
  d_1 P + ...``; ``-<P, K d_1 P> = 0`` as ``K`` is even; inside the contact
  ``C*(inf) d_1 (K * P) = -x1/R``): for the sphere and the cylinder alike

      mu = V sum_k c_k lambda_k / (R C*(inf)) + O(V**2).

* High speed, sphere (``F_k P = Q/lambda_k + ...``, ``d_1 Q = -P``, glassy
  Hertz radius ``a_g``): ``mu = (4/5) a_g**2 / (R c0) sum_k c_k / (lambda_k |V|)``
  to first order in ``1/V``; in plane strain the wake adds a logarithm and
  ``mu ~ (a/(V lambda)) ln(V lambda / a)``.
* Energy: with ``w_k = F_k P`` the power ``mu W |V|`` equals the dissipation
  of the Kelvin chain, ``mu W = |V| sum_k c_k lambda_k <d_1 w_k, K d_1 w_k>``
  (positive for every pressure, so ``mu > 0`` for ``V != 0``).

Outputs
-------
Apparent (rolling) friction coefficient ``mu = sign(V) F_t / W`` with
``F_t = sum p (dh/dx1) dA = sum p x1 dA / R``: positive when it resists the
motion (the pressure centre ahead of the axis). The pressure on the body is
normal to its surface; its component along the motion is ``-F_t``. The
resisting torque about the body's axis in the half-space approximation
(vertical tractions) is ``M = sign(V) sum p x1 dA = mu W R`` and the power
dissipated in the material ``F_t V = mu W |V|``.
"""
from dataclasses import dataclass

import numpy as np

from .._validation import check_positive, check_positive_int, check_real
from ..errors import ConvergenceError, GridTooSmallError, ParameterError

__all__ = ["SteadyLineContact", "SteadySphereContact", "steady_line_contact", "steady_sphere",
           "low_speed_friction_slope", "high_speed_sphere_friction"]

#: The filter integral stops at ``sigma = 40``: ``exp(-40) = 4e-18``.
_SIGMA_END = 40.0
#: Gauss-Legendre points per panel of the filter quadrature.
_ORDER = 10
#: Beyond this many cell sizes the Love coefficient uses its multipole expansion.
_FAR = 200.0


# --------------------------------------------------------------------------- material

def _compliance(material, *, three_dimensional):
    """``(c0, c_k, lambda_k)`` of the material's contact compliance; refuses fluids."""
    series = getattr(material, "contact_compliance", None)
    if not callable(series):
        raise ParameterError(f"material must be a framework material with contact_compliance(), "
                             f"got {type(material).__name__}")
    series = series()
    if series.flow > 0.0:
        why = ("in plane strain the wake's effective pressure W'/V never decays and tilts the surface under "
               "the body by (2/pi) flow W'/V ln(distance travelled): there is no steady state"
               if not three_dimensional else
               "the approach grows like the logarithm of the distance travelled: there is no steady approach")
        raise ParameterError(f"material must be a solid (bounded creep) for a steady rolling reference, got "
                             f"{type(material).__name__} with flow {series.flow!r} 1/(Pa s); {why}")
    if not series.c0 > 0.0:
        raise ParameterError(f"material must have an instantaneous compliance for a steady rolling reference, got "
                             f"{type(material).__name__} with c0 = {series.c0!r} 1/Pa; without one (Kelvin-Voigt) the "
                             f"pressure jumps at the leading edge, which piecewise-constant collocation does not "
                             f"resolve")
    return series.c0, series.coefficients, series.times


# --------------------------------------------------------------------------- influence coefficients

def _plane_strain_cell(offset, half, scale):
    """Plane-strain displacement per unit compliance and unit pressure on ``|y| <= half`` [m].

    ``-(2/pi) int_{-half}^{half} ln(|offset - y| / scale) dy``, ``offset`` [m] any shape.
    """
    def antiderivative(t):
        magnitude = np.abs(t)
        with np.errstate(divide="ignore", invalid="ignore"):
            value = t * np.log(magnitude / scale) - t
        return np.where(magnitude > 0.0, value, 0.0)

    return -2.0 / np.pi * (antiderivative(offset + half) - antiderivative(offset - half))


def _love_cell(x1, x2, half1, half2):
    """Surface displacement per unit compliance and unit pressure on ``|y1| <= half1, |y2| <= half2`` [m].

    Love (1929): ``(1/pi) Sum+- [X ln(Y + R) + Y ln(X + R)]``; ``x1``, ``x2`` [m] broadcast.
    """
    x1, x2 = np.broadcast_arrays(np.asarray(x1, dtype=float), np.asarray(x2, dtype=float))
    distance = np.hypot(x1, x2)
    far = distance > _FAR * max(half1, half2)

    def log_sum(a, b, r):
        # ln(a + r) with r = hypot(a, b), without cancellation when a < 0: a + r = b**2 / (r - a)
        with np.errstate(divide="ignore"):
            return np.where(a >= 0.0, np.log(a + r), 2.0 * np.log(np.abs(b)) - np.log(r - a))

    def corner(x, y):
        r = np.hypot(x, y)
        with np.errstate(invalid="ignore"):
            first = np.where(x == 0.0, 0.0, x * log_sum(y, x, r))
            second = np.where(y == 0.0, 0.0, y * log_sum(x, y, r))
        return first + second

    near1, near2 = x1[~far], x2[~far]
    value = np.empty(x1.shape)
    value[~far] = (corner(near1 + half1, near2 + half2) - corner(near1 + half1, near2 - half2)
                   - corner(near1 - half1, near2 + half2) + corner(near1 - half1, near2 - half2)) / np.pi
    r = distance[far]
    value[far] = 4.0 * half1 * half2 / np.pi * (
        1.0 / r + (half1**2 * (3.0 * x1[far]**2 - r**2) + half2**2 * (3.0 * x2[far]**2 - r**2)) / (6.0 * r**5))
    return value


# --------------------------------------------------------------------------- exponential filter

def _panel_template(levels):
    """Gauss-Legendre nodes and weights on [0, 1]: graded towards both ends, panels <= 1/32 inside.

    Returns ``(nodes, complements, weights)`` with ``complements = 1 - nodes``
    computed without rounding near 1.
    """
    graded = 2.0 ** -np.arange(levels, 5, -1)                  # 2^-levels ... 2^-6
    left = np.concatenate([[0.0], graded, np.linspace(1.0 / 32.0, 0.5, 16)])
    points, weights = np.polynomial.legendre.leggauss(_ORDER)
    points, weights = 0.5 * (points + 1.0), 0.5 * weights
    starts, widths = left[:-1], np.diff(left)
    half_nodes = (starts[:, None] + widths[:, None] * points).ravel()
    half_weights = (widths[:, None] * weights).ravel()
    # the right half mirrors the left one: its complements are the left nodes, exactly
    nodes = np.concatenate([half_nodes, 1.0 - half_nodes[::-1]])
    complements = np.concatenate([1.0 - half_nodes, half_nodes[::-1]])
    return nodes, complements, np.concatenate([half_weights, half_weights[::-1]])


def _filtered(kernel, offsets, length, edge):
    """``int_0^inf exp(-sigma) kernel(offsets + length sigma) dsigma`` for every offset.

    Parameters
    ----------
    kernel : callable
        ``kernel(xi)`` for an array ``xi`` of shape ``offsets.shape + (q,)`` [m].
    offsets : numpy.ndarray
        Offsets ``d1`` along the motion [m], 1-D.
    length : float
        ``L = |V| lambda`` > 0 [m].
    edge : float
        Half cell size along the motion [m]: the kernel's gradient is singular
        at ``xi = +-edge``.

    Returns
    -------
    numpy.ndarray
        Shape of ``offsets``.
    """
    levels = 14 + int(np.ceil(np.log2(max(1.0, _SIGMA_END * length / edge))))
    nodes, complements, weights = _panel_template(levels)
    kinks = np.clip((np.array([-edge, edge])[None, :] - offsets[:, None]) / length, 0.0, _SIGMA_END)
    ends = np.concatenate([np.zeros((offsets.size, 1)), kinks, np.full((offsets.size, 1), _SIGMA_END)], axis=1)
    total = np.zeros(offsets.shape)
    for start, stop in zip(ends[:, :-1].T, ends[:, 1:].T):
        width = (stop - start)[:, None]
        # nodes near the right end measured from it keep their distance to the kink exact
        sigma = np.where(nodes < 0.5, start[:, None] + width * nodes, stop[:, None] - width * complements)
        values = kernel(offsets[:, None] + length * sigma)
        total += np.sum(values * np.exp(-sigma) * width * weights, axis=-1)
    return total


def _kernel_row(cell_kernel, offsets1, compliance, velocity, edge):
    """``c0 K(d1) + sum_k c_k K_k(d1)`` on the offsets ``d1`` [m] (one row of offsets per call).

    ``cell_kernel(xi)`` is the unfiltered cell coefficient along the motion;
    ``V < 0`` mirrors the offsets (the filter then looks towards ``-x1``).
    """
    c0, coefficients, times = compliance
    mirrored = offsets1 if velocity >= 0.0 else -offsets1
    value = c0 * cell_kernel(offsets1)
    for c, lam in zip(coefficients, times):
        length = abs(velocity) * lam
        if length == 0.0:            # at rest the filter is the identity: relaxed compliance
            value = value + c * cell_kernel(offsets1)
        else:
            value = value + c * _filtered(cell_kernel, mirrored, length, edge)
    return value


# --------------------------------------------------------------------------- complementarity

def solve_dense_contact(matrix, heights, cell_area, load, start, *, max_iterations=200, tolerance=1e-9):
    """Exact solution of ``g = h - delta + A p >= 0, p >= 0, p g = 0, sum p dA = W``.

    Primal-dual active set (every cell with a negative pressure leaves the
    contact set and every cell with a negative gap enters it, at once; a
    repeated set falls back to one change at a time). Each set gives the
    pressure by a dense LU solve of the bordered system
    ``[A_II, -1; dA, 0] [p_I; delta] = [-h_I; W]``; the matrix is not
    symmetric. Its symmetric part is positive definite on load-free pressures
    (the filter's symbol has a positive real part), so the problem has one
    solution.

    Returns
    -------
    pressure, approach, gap, iterations, residual
        ``residual`` is the largest complementarity violation, relative to
        the mean contact pressure and to the heights' range over the contact.

    Raises
    ------
    ConvergenceError
        When no set satisfies complementarity to ``tolerance``.
    """
    size = heights.size
    active = start.copy() if start.any() else heights <= heights.min()
    seen = {active.tobytes()}
    for iteration in range(1, max_iterations + 1):
        index = np.flatnonzero(active)
        system = np.empty((index.size + 1, index.size + 1))
        system[:-1, :-1] = matrix[np.ix_(index, index)]
        system[:-1, -1] = -1.0
        system[-1, :-1] = cell_area
        system[-1, -1] = 0.0
        solution = np.linalg.solve(system, np.concatenate([-heights[index], [load]]))
        pressure = np.zeros(size)
        pressure[index] = solution[:-1]
        approach = solution[-1]
        gap = heights - approach + matrix @ pressure
        pressure_scale = load / (cell_area * index.size)
        gap_scale = max(np.ptp(heights[index]), abs(approach), np.finfo(float).tiny)
        negative = active & (pressure < 0.0)
        violating = ~active & (gap < -tolerance * 1e-3 * gap_scale)
        if not negative.any() and not violating.any():
            break
        update = (active & ~negative) | violating
        if update.tobytes() in seen:
            update = active.copy()
            if negative.any():
                update[np.argmin(np.where(negative, pressure, np.inf))] = False
            else:
                update[np.argmin(np.where(violating, gap, np.inf))] = True
        seen.add(update.tobytes())
        active = update
    residual = max(np.max(np.maximum(-pressure, 0.0)) / pressure_scale,
                   np.max(np.maximum(-gap, 0.0)) / gap_scale,
                   np.max(np.abs(gap[active])) / gap_scale,
                   abs(np.sum(pressure) * cell_area - load) / load)
    if residual > tolerance or negative.any() or violating.any():
        raise ConvergenceError(f"the dense active-set solve did not satisfy complementarity: residual {residual:.3g} "
                               f"after {iteration} iterations, expected <= {tolerance:g}")
    return pressure, approach, gap, iteration, residual


# --------------------------------------------------------------------------- grid and results

def _grid_and_material(radius, load, velocity, material, half, cells, cell_range, *, three_dimensional):
    """Checked parameters, the material's compliance and the uniform cells of both references.

    ``load = (value, name, unit)``, ``half = (value, name)``,
    ``cell_range = (minimum, maximum, why)``.

    Returns
    -------
    radius, load, velocity, compliance, spacing, centres, offsets
        ``offsets`` are the ``2 cells - 1`` centre-to-centre offsets [m].
    """
    radius = check_positive(radius, name="radius", unit="m")
    load = check_positive(load[0], name=load[1], unit=load[2])
    velocity = check_real(velocity, name="velocity")
    half = check_positive(half[0], name=half[1], unit="m")
    cells = check_positive_int(cells, name="cells", minimum=cell_range[0])
    if cells > cell_range[1]:
        raise ParameterError(f"cells must be <= {cell_range[1]} {cell_range[2]}, got {cells!r}")
    compliance = _compliance(material, three_dimensional=three_dimensional)
    spacing = 2.0 * half / cells
    centres = -half + (np.arange(cells) + 0.5) * spacing
    return radius, load, velocity, compliance, spacing, centres, np.arange(-(cells - 1), cells) * spacing


def _check_edges(active_line, *, name, size):
    """Raise when the contact reaches the first or last cell along one axis."""
    if active_line[0] or active_line[-1]:
        raise GridTooSmallError(f"the contact reaches the edge of the grid: enlarge {name} (got {size!r} m) "
                                f"or lower the load")


def _contact_edges(x, pressure, spacing):
    """Trailing (min) and leading (max) edges of the contact along ``x`` [m].

    From the outermost contact cell, the zero of ``p**2`` extrapolated
    linearly from it and its inner neighbour (``p**2`` is linear in the
    distance to a square-root edge), at most 1.5 cells away; the cell's
    boundary when the pressure does not fall towards the edge (an unresolved
    leading-edge layer).
    """
    index = np.flatnonzero(pressure > 0.0)
    edges = []
    for last, direction in ((index[0], -1.0), (index[-1], 1.0)):
        outer, inner = pressure[last] ** 2, pressure[last - int(direction)] ** 2
        step = min(outer / (inner - outer), 1.5) if inner > outer else 0.5
        edges.append(x[last] + direction * spacing * step)
    return edges[0], edges[1]


def _motion_summary(x, pressure_row, spacing, moment, radius, load, velocity):
    """Edges along the motion and the friction outputs, as keyword arguments of the result classes.

    ``pressure_row`` is the pressure along ``x`` [Pa] that locates the edges;
    ``moment = sum p x1 dA`` [N m or N]; ``load`` [N or N/m].
    """
    trailing, leading = _contact_edges(x, pressure_row, spacing)
    if velocity < 0.0:
        trailing, leading = leading, trailing
    friction = (-1.0 if velocity < 0.0 else 1.0) * moment / (radius * load)
    return dict(leading_edge=float(leading), trailing_edge=float(trailing), half_width=0.5 * abs(leading - trailing),
                pressure_centre=float(moment / load), friction_coefficient=float(friction),
                torque=float(friction * load * radius), dissipated_power=float(friction * load * abs(velocity)))


@dataclass(frozen=True)
class _SteadyContact:
    """What both dense rolling references return.

    Attributes
    ----------
    pressure : numpy.ndarray
        Contact pressure per cell [Pa].
    gap : numpy.ndarray
        Gap ``h - delta + u3`` at the cell centres [m].
    approach : float
        ``delta`` [m].
    leading_edge, trailing_edge : float
        Contact edges along ``x1`` ahead of and behind the axis [m]
        (``leading_edge`` on the side the body moves towards): the outermost
        contact cells moved by the extrapolation of ``p**2`` to zero.
    half_width : float
        ``|leading_edge - trailing_edge| / 2`` [m].
    max_pressure : float
        Peak cell pressure [Pa].
    pressure_centre : float
        ``sum p x1 dA / W`` [m].
    friction_coefficient : float
        ``mu = sign(V) sum p x1 dA / (R W)`` [-], positive when resisting.
    torque : float
        Resisting torque about the axis ``mu W R`` [N m, or N per unit length].
    dissipated_power : float
        ``mu W |V|`` [W, or W/m].
    iterations : int
        Active-set iterations.
    residual : float
        Complementarity residual (relative).
    """

    pressure: np.ndarray
    gap: np.ndarray
    approach: float
    leading_edge: float
    trailing_edge: float
    half_width: float
    max_pressure: float
    pressure_centre: float
    friction_coefficient: float
    torque: float
    dissipated_power: float
    iterations: int
    residual: float


# --------------------------------------------------------------------------- plane strain

@dataclass(frozen=True)
class SteadyLineContact(_SteadyContact):
    """Steady rolling of a rigid cylinder over a viscoelastic half-space in plane strain (dense reference).

    The attributes of every steady reference (pressure, gap, approach, edges,
    peak pressure, pressure centre, friction coefficient, torque and power per
    unit length, iterations, residual) and the cell centres.

    Attributes
    ----------
    x : numpy.ndarray
        Cell centres along the motion [m], in the body's frame.

    Notes
    -----
    ``approach`` is measured from the surface points at the distance
    ``half_length`` from the load (plane strain has no absolute approach).
    """

    x: np.ndarray


def steady_line_contact(radius, load_per_length, velocity, material, half_length, cells):
    """Steady rolling of a rigid cylinder over a viscoelastic half-space, plane strain (Hunter 1961).

    Dense reference: ``cells`` uniform cells on ``[-half_length, half_length]``,
    piecewise-constant pressure, displacements at the cell centres from the
    exact cell integrals of the plane-strain log kernel with the exponential
    filter of every retardation term folded in by quadrature (module
    docstring), complementarity with the load constraint solved exactly.

    Parameters
    ----------
    radius : float
        Cylinder radius R [m]; heights ``x**2 / (2 R)``.
    load_per_length : float
        Load per unit length W' [N/m].
    velocity : float
        Velocity V of the body along x1 over the material [m/s]; 0 gives the
        relaxed elastic contact, a negative value the motion towards -x1.
    material : material
        Any framework material with an instantaneous compliance whose
        ``contact_compliance()`` is bounded (elastic, viscoelastic); a fluid
        (Maxwell) has no steady state in plane strain and a Kelvin-Voigt solid
        no bounded pressure: both are refused.
    half_length : float
        Half-length of the discretised interval [m]; it must hold the contact
        (no wake is needed: it is inside the filtered kernel).
    cells : int
        Number of cells, 8 to 4000.

    Returns
    -------
    SteadyLineContact

    Raises
    ------
    ParameterError
        For a bad parameter, a fluid or a solid without instantaneous compliance.
    GridTooSmallError
        When the contact reaches either end of the interval.
    ConvergenceError
        When the active-set solve fails its complementarity check.
    """
    radius, load, velocity, compliance, spacing, x, offsets = _grid_and_material(
        radius, (load_per_length, "load_per_length", "N/m"), velocity, material, (half_length, "half_length"),
        cells, (8, 4000, "for a dense reference"), three_dimensional=False)
    row = _kernel_row(lambda xi: _plane_strain_cell(xi, 0.5 * spacing, half_length), offsets, compliance,
                         velocity, 0.5 * spacing)
    index = np.arange(cells)
    matrix = row[index[:, None] - index[None, :] + cells - 1]
    # start from the relaxed Hertz contact: the steady one lies inside it but for a shift of its leading edge
    relaxed = np.sqrt(4.0 * load * radius * (compliance[0] + compliance[1].sum()) / np.pi)
    pressure, approach, gap, iterations, residual = solve_dense_contact(matrix, x**2 / (2.0 * radius), spacing,
                                                                        load, np.abs(x) < relaxed)
    _check_edges(pressure > 0.0, name="half_length", size=half_length)

    return SteadyLineContact(x=x, pressure=pressure, gap=gap, approach=float(approach),
                             max_pressure=float(pressure.max()),
                             **_motion_summary(x, pressure, spacing, np.sum(pressure * x) * spacing, radius, load,
                                               velocity),
                             iterations=iterations, residual=float(residual))


# --------------------------------------------------------------------------- sphere

@dataclass(frozen=True)
class SteadySphereContact(_SteadyContact):
    """Steady rolling of a rigid sphere over a viscoelastic half-space (dense reference).

    The attributes of every steady reference (pressure ``(n, n)`` with axis 0
    along ``x1``, gap, approach, edges on the row of cells nearest ``x2 = 0``,
    peak pressure, pressure centre, friction coefficient, torque, power,
    iterations, residual), the cell centres and the contact area.

    Attributes
    ----------
    x1, x2 : numpy.ndarray
        Cell centres along and across the motion [m], in the body's frame.
    contact_area : float
        Area of the cells in contact [m^2].
    """

    x1: np.ndarray
    x2: np.ndarray
    contact_area: float


def steady_sphere(radius, load, velocity, material, half_size, cells):
    """Steady rolling of a rigid sphere over a viscoelastic half-space (dense reference).

    ``cells x cells`` uniform square cells on ``[-half_size, half_size]**2``,
    piecewise-constant pressure, displacements at the cell centres from Love's
    rectangle coefficients with the exponential filter of every retardation
    term folded in by quadrature along ``x1`` (one quadrature per offset; by
    translation invariance and the symmetry in ``x2`` only ``(2n - 1) n``
    offsets), complementarity with the load constraint solved exactly (module
    docstring).

    Parameters
    ----------
    radius : float
        Sphere radius R [m]; heights ``(x1**2 + x2**2) / (2 R)``.
    load : float
        Normal load W [N].
    velocity : float
        Velocity V of the body along x1 over the material [m/s]; 0 gives the
        relaxed elastic contact, a negative value the motion towards -x1.
    material : material
        Any framework material with an instantaneous compliance whose
        ``contact_compliance()`` is bounded (elastic, viscoelastic); a fluid
        (Maxwell) and a Kelvin-Voigt solid are refused.
    half_size : float
        Half-side of the square grid [m]; it must hold the contact.
    cells : int
        Cells per side, 4 to 64 (the dense matrix has ``cells**4`` entries).

    Returns
    -------
    SteadySphereContact

    Raises
    ------
    ParameterError
        For a bad parameter, a fluid or a solid without instantaneous compliance.
    GridTooSmallError
        When the contact reaches the edge of the grid.
    ConvergenceError
        When the active-set solve fails its complementarity check.
    """
    radius, load, velocity, compliance, spacing, x, offsets = _grid_and_material(
        radius, (load, "load", "N"), velocity, material, (half_size, "half_size"), cells,
        (4, 64, "for a dense reference (cells**4 matrix entries)"), three_dimensional=True)
    table = np.empty((offsets.size, cells))
    for column in range(cells):
        table[:, column] = _kernel_row(lambda xi: _love_cell(xi, column * spacing, 0.5 * spacing, 0.5 * spacing),
                                          offsets, compliance, velocity, 0.5 * spacing)
    index = np.arange(cells)
    along = (index[:, None] - index[None, :] + cells - 1)          # x1 offset of field i from source j
    across = np.abs(index[:, None] - index[None, :])
    matrix = table[along[:, None, :, None], across[None, :, None, :]].reshape(cells**2, cells**2)

    x1, x2 = np.meshgrid(x, x, indexing="ij")
    heights = (x1**2 + x2**2) / (2.0 * radius)
    # start from the relaxed Hertz contact: the steady one lies inside it but for a shift of its leading edge
    relaxed = (0.75 * load * radius * (compliance[0] + compliance[1].sum())) ** (1.0 / 3.0)
    cell_area = spacing**2
    pressure, approach, gap, iterations, residual = solve_dense_contact(matrix, heights.ravel(), cell_area, load,
                                                                        np.hypot(x1, x2).ravel() < relaxed)
    pressure, gap = pressure.reshape(cells, cells), gap.reshape(cells, cells)
    contact = pressure > 0.0
    _check_edges(contact.any(axis=1), name="half_size", size=half_size)
    _check_edges(contact.any(axis=0), name="half_size", size=half_size)
    return SteadySphereContact(x1=x, x2=x.copy(), pressure=pressure, gap=gap, approach=float(approach),
                               contact_area=float(np.count_nonzero(contact) * cell_area),
                               max_pressure=float(pressure.max()),
                               **_motion_summary(x, pressure[:, cells // 2], spacing,
                                                 np.sum(pressure * x1) * cell_area, radius, load, velocity),
                               iterations=iterations, residual=float(residual))


# --------------------------------------------------------------------------- asymptotes


def low_speed_friction_slope(material, radius):
    """``d mu / dV`` [s/m] at ``V = 0``: ``sum_k c_k lambda_k / (R C*(inf))``, sphere and cylinder alike.

    The first order of the perturbation of the relaxed Hertz contact (module
    docstring, "Low speed"): ``mu = V sum_k c_k lambda_k / (R C*(inf)) + O(V^2)``.

    Parameters
    ----------
    material : material
        A solid (no flow term) with its ``contact_compliance()``.
    radius : float
        Radius R of the sphere or cylinder [m].
    """
    series = material.contact_compliance()
    if series.flow:
        raise ParameterError("material: a fluid has no relaxed compliance, so no low-speed friction slope")
    radius = check_positive(radius, name="radius", unit="m")
    return float(np.sum(series.coefficients * series.times) / (radius * series.relaxed))


def high_speed_sphere_friction(material, radius, load, velocity):
    """The sphere's friction coefficient as ``V -> inf``: ``(4/5) a_g^2 / (R c0) sum_k c_k / (lambda_k |V|)``.

    The first order in ``1/V`` about the glassy Hertz contact of radius
    ``a_g = (3 W R c0 / 4)^(1/3)`` (module docstring, "High speed").

    Parameters
    ----------
    material : material
        A solid with an instantaneous compliance ``c0 > 0``.
    radius : float
        Sphere radius R [m].
    load : float
        Normal load W [N].
    velocity : float
        Speed [m/s] (either sign).
    """
    series = material.contact_compliance()
    if series.c0 <= 0:
        raise ParameterError("material: without an instantaneous compliance there is no glassy contact")
    radius = check_positive(radius, name="radius", unit="m")
    load = check_positive(load, name="load", unit="N")
    speed = abs(check_real(velocity, name="velocity"))
    glassy = (0.75 * load * radius * series.c0) ** (1 / 3)
    return float(0.8 * glassy**2 / (radius * series.c0) * np.sum(series.coefficients / series.times) / speed)

