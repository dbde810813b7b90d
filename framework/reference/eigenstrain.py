"""Strain caused by a uniform eigenstrain in a cuboid, by brute-force quadrature.

An independent reference for the closed-form (corner-sum) and FFT eigenstrain
operators: it shares no algebra with them.  The displacement caused by an
eigenstrain ``eps*`` in a homogeneous isotropic body is (T. Mura,
*Micromechanics of Defects in Solids*, 2nd ed., Martinus Nijhoff, 1987,
chapter 1, there for the infinite body)::

    u_i(x) = -int_V C_jlmn eps*_mn(x') dG_ij(x, x')/dx_l dV'

with ``G_ij(x, x')`` the displacement along ``i`` at ``x`` caused by a unit
force along ``j`` at ``x'``.  The eigenstrain acts as the body force
``f_j = -d(sigma*_jl chi_V)/dx'_l`` with ``sigma* = C : eps*`` and ``chi_V``
the indicator of the cuboid; for a uniform ``eps*`` this is the surface
force ``sigma*_jl n_l`` on the cuboid's faces (``n`` the outward normal), so

    u_i(x) = sigma*_jl  sum over the 6 faces of int_face G_ij(x, x') n_l dS'.

This form holds for any Green's function, translation invariant or not.  The
displacement gradient is the same face integral of ``dG_ij/dx_k``, a smooth
integrand when ``x`` is off the faces, inside the cuboid or outside alike.

Green's functions (shear modulus 1; the strain does not depend on it):

- infinite body, Kelvin (W. Thomson, *Cambridge and Dublin Math. J.* 3, 1848;
  Mura 1987, chapter 1)::

      G_ij = [(3-4nu) delta_ij / r + r_i r_j / r^3] / (16 pi mu (1-nu)),  r = x - x'

- half-space ``x3 >= 0`` with a traction-free surface ``x3 = 0``: Mindlin
  (R. D. Mindlin, *Force at a point in the interior of a semi-infinite
  solid*, Physics 7, 195-202, 1936), see :func:`mindlin_point_force_displacement`.

Quadrature: each face is cut into rectangular panels, recursively halved
along each side longer than ``_RATIO`` times the panel's distance to the
nearest singular point (the field point, and for Mindlin its mirror image
``(x1, x2, -x3)``), and each panel gets an ``order x order`` Gauss-Legendre
rule.  The derivatives ``dG/dx_k`` are taken by the complex step
(``Im G(x + i h e_k) / h``, h = 1e-30 in units of the cuboid's size), exact to
rounding, as every formula is analytic in ``x``.  Lengths are scaled by the
cuboid's largest half-size first.

Conventions: ``x3`` is the depth for the half-space, ``u3`` positive into the
solid (along ``+x3``), tensor (not engineering) shear strains.
"""
import numpy as np

from .._validation import check_finite_array, check_poisson, check_positive, check_positive_int, check_real
from ..errors import ParameterError, ShapeError

#: A panel is halved along each side longer than this times its distance to the nearest singular point.
_RATIO = 1.0
#: Smallest panel side, relative to the cuboid's largest half-size: a field point on a face (the surface
#: displacement above a cuboid that touches the surface) is reached by panels this small, whose 1/r
#: singularity is integrated to about this absolute error.
_SMALLEST = 1e-9
#: Complex step, in units of the cuboid's largest half-size.
_STEP = 1e-30


def _eigenstrain_poisson(poisson):
    """Poisson's ratio admitted here: -1 < nu < 0.5 (sigma* = C : eps* is unbounded at 0.5)."""
    nu = check_real(poisson, name="poisson")
    if not -1.0 < nu < 0.5:
        raise ParameterError(f"poisson must lie in (-1, 0.5) for the eigenstrain references "
                             f"(C : eps* is unbounded at 0.5), got {poisson!r}")
    return nu


def kelvin_point_force_displacement(points, source, *, shear_modulus, poisson):
    """Displacement caused by unit point forces in an infinite isotropic body (Kelvin).

    Parameters
    ----------
    points : array_like, shape (n, 3)
        Field points [m]; none may coincide with ``source``.
    source : array_like, shape (3,)
        Point of application of the force [m].
    shear_modulus : float
        Shear modulus mu [Pa].
    poisson : float
        Poisson's ratio nu [-].

    Returns
    -------
    ndarray, shape (n, 3, 3)
        ``G[:, i, j]``, the displacement along ``i`` per newton of force along
        ``j`` [m/N].

    Notes
    -----
    Kelvin's solution (Mura 1987, chapter 1), ``r = x - x'``::

        G_ij = [(3-4nu) delta_ij / r + r_i r_j / r^3] / (16 pi mu (1-nu))
    """
    points, source, mu, nu = _check_point_force(points, source, shear_modulus, poisson)
    return _kelvin(points, source, nu) / mu


def mindlin_point_force_displacement(points, source, *, shear_modulus, poisson):
    """Displacement caused by unit point forces inside a half-space (Mindlin 1936).

    Parameters
    ----------
    points, source, shear_modulus, poisson
        As in :func:`kelvin_point_force_displacement`, with ``x3 >= 0`` the
        depth of the points and of the force ``c = source[2]`` [m].

    Returns
    -------
    ndarray, shape (n, 3, 3)
        ``G[:, i, j]`` [m/N] as in :func:`kelvin_point_force_displacement`;
        ``u3`` and the force along ``x3`` point into the solid.

    Notes
    -----
    Mindlin (1936), in the form usually quoted (e.g. H. G. Poulos & E. H.
    Davis, *Elastic Solutions for Soil and Rock Mechanics*, Wiley, 1974,
    chapter 2), with
    ``x, y`` the horizontal offsets from the force, ``z`` the depth of the
    field point, ``R1^2 = x^2 + y^2 + (z-c)^2``, ``R2^2 = x^2 + y^2 + (z+c)^2``,
    ``k = 1 / (16 pi mu (1-nu))``, ``a = 3-4nu``, ``b = 4(1-nu)(1-2nu)``.
    Vertical unit force::

        u_x = k x [(z-c)/R1^3 + a (z-c)/R2^3 - b/(R2 (R2+z+c)) + 6 c z (z+c)/R2^5]
        u_z = k [a/R1 + (8(1-nu)^2 - a)/R2 + (z-c)^2/R1^3
                 + (a (z+c)^2 - 2 c z)/R2^3 + 6 c z (z+c)^2/R2^5]

    Horizontal unit force along ``x``::

        u_x = k [a/R1 + 1/R2 + x^2/R1^3 + a x^2/R2^3 + (2 c z/R2^3)(1 - 3 x^2/R2^2)
                 + (b/(R2+z+c)) (1 - x^2/(R2 (R2+z+c)))]
        u_y = k x y [1/R1^3 + a/R2^3 - 6 c z/R2^5 - b/(R2 (R2+z+c)^2)]
        u_z = k x [(z-c)/R1^3 + a (z-c)/R2^3 - 6 c z (z+c)/R2^5 + b/(R2 (R2+z+c))]

    The ``R1`` terms are Kelvin's solution.  The tests check that the surface
    is free of traction, that Navier's equations hold and that the solution
    tends to Kelvin's far from the surface.
    """
    points, source, mu, nu = _check_point_force(points, source, shear_modulus, poisson)
    if source[2] < 0.0 or np.any(points[:, 2] < 0.0):
        raise ParameterError("points and source must lie in the half-space x3 >= 0, got depths "
                             f"{float(min(source[2], points[:, 2].min()))!r}")
    return _mindlin(points, source, nu) / mu


def _check_point_force(points, source, shear_modulus, poisson):
    """Validated (points (n, 3), source (3,), mu, nu) of a point-force solution."""
    points = check_finite_array(points, name="points", ndim=2)
    if points.shape[1] != 3:
        raise ShapeError(f"points must have shape (n, 3), got {points.shape}")
    source = check_finite_array(source, name="source", shape=(3,))
    return points, source, check_positive(shear_modulus, name="shear_modulus", unit="Pa"), check_poisson(poisson)


def _kelvin(x, source, nu):
    """Kelvin's G_ij(x, source) with mu = 1; x (..., 3) real or complex, source broadcast with it."""
    r = x - source
    rr = np.sqrt(np.sum(r * r, axis=-1))[..., None, None]
    outer = r[..., :, None] * r[..., None, :]
    return ((3.0 - 4.0 * nu) * np.eye(3) / rr + outer / rr**3) / (16.0 * np.pi * (1.0 - nu))


def _mindlin(x, source, nu):
    """Mindlin's G_ij(x, source) with mu = 1, as :func:`_kelvin` plus the image terms."""
    dx = x[..., 0] - source[..., 0]
    dy = x[..., 1] - source[..., 1]
    z = x[..., 2]
    c = source[..., 2]
    r2 = np.sqrt(dx * dx + dy * dy + (z + c) ** 2)
    s = r2 + z + c
    k = 1.0 / (16.0 * np.pi * (1.0 - nu))
    a = 3.0 - 4.0 * nu
    b = 4.0 * (1.0 - nu) * (1.0 - 2.0 * nu)
    cz = c * z
    # the image part of u_3 under a horizontal force, per unit offset (x or y)
    horizontal_3 = a * (z - c) / r2**3 - 6.0 * cz * (z + c) / r2**5 + b / (r2 * s)
    # the image part of u_x under a vertical force, per unit offset
    vertical_h = a * (z - c) / r2**3 - b / (r2 * s) + 6.0 * cz * (z + c) / r2**5
    cross = a / r2**3 - 6.0 * cz / r2**5 - b / (r2 * s * s)  # u_y under a force along x, per x y
    image = np.empty(np.broadcast(dx, c).shape + (3, 3), dtype=np.result_type(x, source))
    for i, d in enumerate((dx, dy)):
        image[..., i, i] = (1.0 / r2 + a * d * d / r2**3 + (2.0 * cz / r2**3) * (1.0 - 3.0 * d * d / r2**2)
                            + (b / s) * (1.0 - d * d / (r2 * s)))
        image[..., 2, i] = d * horizontal_3
        image[..., i, 2] = d * vertical_h
    image[..., 0, 1] = image[..., 1, 0] = dx * dy * cross
    image[..., 2, 2] = ((8.0 * (1.0 - nu) ** 2 - a) / r2 + (a * (z + c) ** 2 - 2.0 * cz) / r2**3
                        + 6.0 * cz * (z + c) ** 2 / r2**5)
    return _kelvin(x, source, nu) + k * image


def _faces():
    """The 6 faces of a cuboid: (normal axis, outward sign, in-plane axes)."""
    for axis in range(3):
        others = [a for a in range(3) if a != axis]
        for sign in (-1.0, 1.0):
            yield axis, sign, others


def _panels(low, high, singular, plane, axis, others):
    """Panels ``(a0, a1, b0, b1)`` of the face rectangle [low, high] (in-plane axes ``others``).

    A panel is halved along each side longer than ``_RATIO`` times its
    distance to the nearest of the ``singular`` points (and longer than
    ``_SMALLEST``), so that the Gauss rule on it sees a smooth integrand.
    """
    normal = (singular[:, axis] - plane) ** 2
    done = []
    stack = [(low[0], high[0], low[1], high[1])]
    while stack:
        a0, a1, b0, b1 = stack.pop()
        da = np.maximum(np.maximum(a0 - singular[:, others[0]], singular[:, others[0]] - a1), 0.0)
        db = np.maximum(np.maximum(b0 - singular[:, others[1]], singular[:, others[1]] - b1), 0.0)
        reach = _RATIO * np.sqrt(np.min(normal + da * da + db * db))
        split_a = a1 - a0 > max(reach, _SMALLEST)
        split_b = b1 - b0 > max(reach, _SMALLEST)
        if not (split_a or split_b):
            done.append((a0, a1, b0, b1))
            continue
        cuts_a = [(a0, 0.5 * (a0 + a1)), (0.5 * (a0 + a1), a1)] if split_a else [(a0, a1)]
        cuts_b = [(b0, 0.5 * (b0 + b1)), (0.5 * (b0 + b1), b1)] if split_b else [(b0, b1)]
        stack.extend((p0, p1, q0, q1) for p0, p1 in cuts_a for q0, q1 in cuts_b)
    return np.array(done)


def _face_rule(target, center, half_sizes, traction, order, mirror):
    """Nodes (N, 3), weights (N,) and face forces (N, 3) of the surface integral for one field point.

    ``traction[axis]`` is ``sigma*[:, axis]``: the force per area on the face
    of outward normal ``+e_axis`` (its negative on the opposite face).
    """
    singular = np.array([target, target * [1.0, 1.0, -1.0]]) if mirror else target[None, :]
    base, base_weights = np.polynomial.legendre.leggauss(order)
    nodes, weights, forces = [], [], []
    for axis, sign, others in _faces():
        plane = center[axis] + sign * half_sizes[axis]
        low = center[others] - half_sizes[others]
        high = center[others] + half_sizes[others]
        panels = _panels(low, high, singular, plane, axis, others)
        mid_a, half_a = 0.5 * (panels[:, 0] + panels[:, 1]), 0.5 * (panels[:, 1] - panels[:, 0])
        mid_b, half_b = 0.5 * (panels[:, 2] + panels[:, 3]), 0.5 * (panels[:, 3] - panels[:, 2])
        w = (half_a * half_b)[:, None, None] * base_weights[None, :, None] * base_weights[None, None, :]
        points = np.empty(w.shape + (3,))  # (panel, node along a, node along b, xyz)
        points[..., axis] = plane
        points[..., others[0]] = (mid_a[:, None] + half_a[:, None] * base)[:, :, None]
        points[..., others[1]] = (mid_b[:, None] + half_b[:, None] * base)[:, None, :]
        nodes.append(points.reshape(-1, 3))
        weights.append(w.ravel())
        forces.append(np.broadcast_to(sign * traction[axis], (w.size, 3)))
    return np.concatenate(nodes), np.concatenate(weights), np.concatenate(forces)


def _eigenstress(eigenstrain, nu):
    """sigma* = C : eps* with shear modulus 1."""
    lam = 2.0 * nu / (1.0 - 2.0 * nu)
    return 2.0 * eigenstrain + lam * np.trace(eigenstrain) * np.eye(3)


def _gradient(green, target, nodes, weights, forces):
    """Displacement gradient du_i/dx_k (3, 3) at ``target``: complex step on the face integral."""
    shifted = target + 1j * _STEP * np.eye(3)  # one row per derivative direction k
    g = green(shifted[:, None, :], nodes[None, :, :])  # (k, node, i, j)
    return np.einsum("knij,nj,n->ik", g.imag, forces, weights) / _STEP


def _check_cuboid(points, center, half_sizes, eigenstrain, poisson, order, half_space):
    """Validated (points (n, 3), center, half_sizes, eigenstrain (3, 3), nu, order)."""
    points = check_finite_array(points, name="points", ndim=2)
    if points.shape[1] != (2 if half_space == "surface" else 3):
        width = 2 if half_space == "surface" else 3
        raise ParameterError(f"points must have shape (n, {width}), got {points.shape}")
    center = check_finite_array(center, name="center", shape=(3,))
    half_sizes = check_finite_array(half_sizes, name="half_sizes", shape=(3,))
    if np.any(half_sizes <= 0.0):
        raise ParameterError(f"half_sizes must be positive [m], got {half_sizes.tolist()}")
    eigenstrain = check_finite_array(eigenstrain, name="eigenstrain", shape=(3, 3))
    if np.any(np.abs(eigenstrain - eigenstrain.T) > 1e-12 * np.abs(eigenstrain).max()):
        raise ParameterError(f"eigenstrain must be a symmetric 3x3 tensor, got {eigenstrain.tolist()}")
    nu = _eigenstrain_poisson(poisson)
    order = check_positive_int(order, name="order", minimum=2)
    if half_space:
        if center[2] - half_sizes[2] < 0.0:
            raise ParameterError("the cuboid must lie in the half-space x3 >= 0: center[2] - half_sizes[2] "
                                 f"must be >= 0 [m], got {center[2] - half_sizes[2]:g}")
        if half_space is True and np.any(points[:, 2] < 0.0):
            raise ParameterError(f"points must lie in the half-space x3 >= 0, got x3 = {points[:, 2].min():g}")
    if half_space != "surface":
        on_face = np.all(np.abs(points - center) <= half_sizes, axis=1) & np.any(
            np.abs(np.abs(points - center) - half_sizes) == 0.0, axis=1)
        if np.any(on_face):
            raise ParameterError("the strain is singular on the cuboid's faces: points must not lie on them, got "
                                 f"{points[np.argmax(on_face)].tolist()}")
    return points, center, half_sizes, 0.5 * (eigenstrain + eigenstrain.T), nu, order


def _local_frame(center, half_sizes, mirror):
    """(origin, scale, centre, half-sizes): lengths scaled by the largest half-size about ``origin``.

    The origin is the cuboid's centre, or its projection on the surface for the
    half-space (``mirror``), whose surface stays at x3 = 0.
    """
    scale = half_sizes.max()
    origin = np.array([center[0], center[1], 0.0 if mirror else center[2]])
    return origin, scale, (center - origin) / scale, half_sizes / scale


def _cuboid_strain(points, center, half_sizes, eigenstrain, nu, order, mirror):
    """Strain (n, 3, 3) at ``points`` from the face integral with Kelvin's or Mindlin's G (``mirror``)."""
    origin, scale, local_center, local_half = _local_frame(center, half_sizes, mirror)
    traction = _eigenstress(eigenstrain, nu).T  # row m: sigma*[:, m]
    green = (lambda x, y: _mindlin(x, y, nu)) if mirror else (lambda x, y: _kelvin(x, y, nu))
    strain = np.empty((len(points), 3, 3))
    for n, x in enumerate((points - origin) / scale):
        nodes, weights, forces = _face_rule(x, local_center, local_half, traction, order, mirror)
        gradient = _gradient(green, x, nodes, weights, forces)
        strain[n] = 0.5 * (gradient + gradient.T)
    return strain


def kelvin_cuboid_strain(points, *, center, half_sizes, eigenstrain, poisson, order=10):
    """Strain caused by a uniform eigenstrain in a cuboid inside an infinite isotropic body.

    Face integral of the gradient of Kelvin's Green's function, see the
    module's docstring (Mura 1987 eq. 3.7 turned into a surface integral).

    Parameters
    ----------
    points : array_like, shape (n, 3)
        Field points [m], inside or outside the cuboid but not on its faces.
        With ``order=10`` the error is below 1e-11 of ``max |eps*|``
        (measured against ``order=24`` and independent routes) down to
        1e-3 half-sizes from a face; closer points cost more panels.
    center : array_like, shape (3,)
        Centre of the axis-aligned cuboid ``|x_i - c_i| <= h_i`` [m].
    half_sizes : array_like, shape (3,)
        Its half-sizes ``h_i`` [m].
    eigenstrain : array_like, shape (3, 3)
        Uniform eigenstrain (symmetric, tensor shears) [-].
    poisson : float
        Poisson's ratio, ``-1 < nu < 0.5`` [-].  The strain does not depend
        on the modulus.  Near 0.5 the dilatational part of ``C : eps*``
        grows like ``1/(1-2 nu)`` and the error with it.
    order : int, optional
        Gauss-Legendre points per panel side.

    Returns
    -------
    ndarray, shape (n, 3, 3)
        Total strain (compatible, including ``eps*`` inside the cuboid),
        tensor shears [-].
    """
    points, center, half_sizes, eigenstrain, nu, order = _check_cuboid(
        points, center, half_sizes, eigenstrain, poisson, order, half_space=False)
    return _cuboid_strain(points, center, half_sizes, eigenstrain, nu, order, mirror=False)


def mindlin_cuboid_strain(points, *, center, half_sizes, eigenstrain, poisson, order=10):
    """Strain caused by a uniform eigenstrain in a cuboid inside a half-space with a free surface.

    Face integral of the gradient (with respect to the field point) of
    Mindlin's (1936) point-force solution, see the module's docstring.

    Parameters
    ----------
    points : array_like, shape (n, 3)
        Field points, depth ``x3 >= 0`` [m], not on the cuboid's faces.
    center : array_like, shape (3,)
        Centre of the cuboid, ``center[2] - half_sizes[2] >= 0`` (it may
        touch the surface) [m].
    half_sizes : array_like, shape (3,)
        Its half-sizes [m].
    eigenstrain : array_like, shape (3, 3)
        Uniform eigenstrain (symmetric, tensor shears) [-].
    poisson : float
        Poisson's ratio, ``-1 < nu < 0.5`` [-].
    order : int, optional
        Gauss-Legendre points per panel side.

    Returns
    -------
    ndarray, shape (n, 3, 3)
        Total strain, tensor shears [-].
    """
    points, center, half_sizes, eigenstrain, nu, order = _check_cuboid(
        points, center, half_sizes, eigenstrain, poisson, order, half_space=True)
    return _cuboid_strain(points, center, half_sizes, eigenstrain, nu, order, mirror=True)


def mindlin_cuboid_surface_displacement(points_xy, *, center, half_sizes, eigenstrain, poisson, order=10):
    """Surface displacement of a half-space caused by a uniform eigenstrain in a cuboid inside it.

    ``u_i(x) = sigma*_jl sum_faces int G_ij(x, x') n_l dS'`` with Mindlin's
    (1936) ``G``, at ``x3 = 0``; see the module's docstring.

    Parameters
    ----------
    points_xy : array_like, shape (n, 2)
        Surface points ``(x1, x2)`` [m]; they may lie on the face of a cuboid
        that touches the surface (the ``1/r`` singularity is integrable).
    center, half_sizes, eigenstrain, poisson, order
        As in :func:`mindlin_cuboid_strain`.

    Returns
    -------
    ndarray, shape (n, 3)
        Displacement [m]; ``u3`` positive into the solid (``+x3``), so a
        rising surface has ``u3 < 0``.
    """
    points, center, half_sizes, eigenstrain, nu, order = _check_cuboid(
        points_xy, center, half_sizes, eigenstrain, poisson, order, half_space="surface")
    origin, scale, local_center, local_half = _local_frame(center, half_sizes, mirror=True)
    traction = _eigenstress(eigenstrain, nu).T
    displacement = np.empty((len(points), 3))
    for n, xy in enumerate((points - origin[:2]) / scale):
        x = np.array([xy[0], xy[1], 0.0])
        # on the surface the field point is its own image: one singular point
        nodes, weights, forces = _face_rule(x, local_center, local_half, traction, order, mirror=False)
        displacement[n] = np.einsum("nij,nj,n->i", _mindlin(x, nodes, nu), forces, weights)
    return displacement * scale
