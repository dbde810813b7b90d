"""Inhomogeneities in an elastic half-space under a uniform applied strain (``fw.solve_inclusions``)."""
import numpy as np

from .._validation import check_bool, check_finite_array
from ..errors import InclusionError, ParameterError, ShapeError
from ..materials import Elastic, Viscoelastic, isotropic_tensor
from ..operators.eigenstrain import COMPONENTS, BoxLattices, HalfSpaceEigenstrain
from .equivalent import MANDEL, EquivalentInclusionProblem, isotropic_mandel, mandel_matrix, preconditioner_cell

#: Inhomogeneities must be at least this stiff relative to the matrix (smallest eigenvalue of
#: ``C_M^-1/2 C_I C_M^-1/2``). The cell-averaged operator's spectrum lies in [0, 0.983] (see
#: :data:`~framework.operators.eigenstrain.AVERAGE_POINTS`), so the system is regular for any
#: positive stiffness, but its conditioning grows like ``1 / ratio``: GMRES took 23 iterations at 0.2, 32 at
#: 0.1, 44 at 0.05 (sphere, tolerance 1e-10) before the filled cell's preconditioner, 8-10 with it. Softer bodies
#: and voids are refused until they are validated against Eshelby's solution (a sphere at 1/19: 2.2 %,
#: ``tests/test_inclusions.py``).
MIN_STIFFNESS_RATIO = 0.05
#: Inhomogeneities may be at most this stiff relative to the matrix (largest eigenvalue of the same matrix). Measured
#: on a sphere (``tests/test_silent_results.py``): the stress converges to the rigid limit (5e-4 between 1e4 and
#: 1e6) in 60-120 GMRES iterations; at 1e8 rounding, amplified by the conditioning, moves it by 1e-3 from one FFT
#: plan to another. 1e6 is diamond in a 1 MPa rubber; a stiffer body is rigid for every purpose.
MAX_STIFFNESS_RATIO = 1e6
#: [Pa] No inhomogeneity is stiffer in shear than diamond, the stiffest solid: the largest eigenvalue of its Mandel
#: stiffness on the deviatoric (volume-preserving) strains, twice a shear modulus, is 2 C44 = 1.16e12 Pa; the bound
#: leaves 70 % margin. (Not in bulk: a nearly incompressible body's bulk modulus is legitimately unbounded.)
STIFFEST = 2e12


def _largest_shear(stiffness):
    """Largest eigenvalue [Pa] of a Mandel stiffness restricted to the deviatoric strains (trace-free)."""
    hydrostatic = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0]) / np.sqrt(3.0)
    projector = np.eye(6) - np.outer(hydrostatic, hydrostatic)
    return float(np.linalg.eigvalsh(projector @ stiffness @ projector)[-1])
#: The applied strain must be small (largest component), as linear elasticity, the theory of every operator here,
#: assumes: at 10 % strain a body's geometry has changed by 10 %.
LARGEST_STRAIN = 0.1


def instantaneous(matrix):
    """Young's modulus of the matrix at the instant of loading [Pa] (the glassy one of a viscoelastic solid)."""
    return matrix.young if isinstance(matrix, Elastic) else matrix.instantaneous_modulus


def inclusion_box(grid, inclusions, margin=0.0):
    """Block of the grid's cuboids that holds every inhomogeneity, grown by ``margin`` [m] per side.

    Returns
    -------
    start, shape : tuple of int
        First cuboid and number of cuboids along x1, x2 and the layers (clipped to the grid).
    """
    lower, upper = inclusions.bounds()
    spacing = np.array([*grid.spacing, grid.layer_thickness])
    origin = np.array([-grid.size[0] / 2, -grid.size[1] / 2, 0.0])
    limits = np.array([*grid.shape, grid.layers])
    first = np.floor((lower - margin - origin) / spacing).astype(int)
    last = np.ceil((upper + margin - origin) / spacing).astype(int)
    first, last = np.clip(first, 0, limits), np.clip(last, 0, limits)
    return tuple(int(v) for v in first), tuple(int(v) for v in last - first)


def box_coordinates(grid, start, shape):
    """Cuboid-centre coordinates ``(x1, x2, x3)`` of a box, three 1-D arrays [m]."""
    return (grid.x1[start[0]:start[0] + shape[0]], grid.x2[start[1]:start[1] + shape[1]],
            grid.x3[start[2]:start[2] + shape[2]])


def layout(grid, inclusions, margin=None):
    """The box around the inhomogeneities and its indicator: ``(start, shape, indicator)``.

    ``margin`` [m] grows the box on every side (None: half the largest semi-axis, where the
    eigenstrains' stresses are still a sizeable part of the field); the indicator is 0 in the
    matrix and ``k + 1`` in the cuboids of the ``k``-th inhomogeneity.
    """
    start, shape = inclusion_box(grid, inclusions, box_margin(inclusions, margin))
    return start, shape, inclusions.indicator(*box_coordinates(grid, start, shape))


def box_margin(inclusions, margin=None):
    """The box's margin [m]: ``margin``, or (None) half the largest semi-axis."""
    return 0.5 * max(max(inclusion.semi_axes) for inclusion in inclusions) if margin is None else margin


def body_cuboids(grid, inclusions, placed, geometry="staircase"):
    """The box's cuboids the equivalent-inclusion system solves on (``np.nonzero`` of its indicator, C order):
    those whose centre a body contains, and with ``geometry="laminate"`` also those a body's boundary cuts.

    ``placed`` is the box's :func:`layout` ``(start, shape, indicator)``. A run's records keep their
    eigenstrains and stresses on these cuboids only (``(N, 6)``), the cuboids of
    :class:`InclusionProblem`'s ``problem.cells``, found without building its operators.
    """
    start, shape, indicator = placed
    if geometry != "laminate":
        return np.nonzero(indicator)
    fraction, owner, _ = inclusions.fractions(*box_coordinates(grid, start, shape),
                                              (*grid.spacing, grid.layer_thickness))
    return np.nonzero((owner > 0) & (fraction > 0.0))


def place(grid, field, start):
    """A box field ``(m1, m2, m3, ...)`` whose first cuboid is ``start``, in a zero grid field ``(n1, n2, layers, ...)``."""
    out = np.zeros((*grid.shape, grid.layers, *field.shape[3:]), dtype=field.dtype)
    out[tuple(slice(s, s + m) for s, m in zip(start, field.shape[:3]))] = field
    return out


def stiffness_ratio(inclusion_stiffness, matrix_stiffness):
    """Smallest eigenvalue of ``C_M^-1/2 C_I C_M^-1/2`` (Mandel matrices)."""
    return softest_mode(inclusion_stiffness, matrix_stiffness)[0]


def softest_mode(inclusion_stiffness, matrix_stiffness):
    """``(ratio, volumetric)``: :func:`stiffness_ratio` and whether its mode is a change of volume.

    ``volumetric`` when the mode's strain ``C_M^-1/2 v`` lies within 25 degrees of the hydrostatic
    strain ``(1, 1, 1, 0, 0, 0)``: the inhomogeneity is too soft in bulk, as any compressible
    one is in a nearly incompressible matrix.
    """
    values, vectors = np.linalg.eigh(matrix_stiffness)
    root = vectors @ np.diag(values ** -0.5) @ vectors.T
    ratios, modes = np.linalg.eigh(root @ inclusion_stiffness @ root)
    strain = root @ modes[:, 0]
    hydrostatic = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0]) / np.sqrt(3.0)
    return float(ratios[0]), bool(abs(strain @ hydrostatic) >= np.cos(np.radians(25.0)) * np.linalg.norm(strain))


def strain_vector(strain, *, name):
    """A symmetric 3x3 strain as the ``(6,)`` tensor-shear vector (Voigt order xx yy zz yz xz xy)."""
    strain = check_finite_array(strain, name=name)
    if strain.shape != (3, 3):
        raise ShapeError(f"{name} must be a 3x3 strain tensor, got shape {strain.shape}")
    if np.abs(strain - strain.T).max() > 1e-12 * max(np.abs(strain).max(), 1e-300):
        raise ParameterError(f"{name} must be symmetric (a strain tensor), got {strain.tolist()}")
    return np.array([strain[i, j] for i, j in COMPONENTS])


class InclusionProblem:
    """The equivalent-inclusion problem of a set of inhomogeneities in an elastic half-space.

    Builds the eigenstrain operator on the block of cuboids around the inhomogeneities
    (grown by ``margin``) and the preconditioned linear system; :meth:`solve` returns the
    eigenstrains for a given strain of the matrix without inhomogeneities.

    Parameters
    ----------
    grid : framework.Grid
        Open grid with layers: the inhomogeneities must lie inside its subsurface box.
    matrix : framework.materials.Elastic or framework.materials.Viscoelastic
        The half-space (a viscoelastic one with a constant Poisson ratio: the system is
        built with its instantaneous modulus, and :class:`~framework.inclusions.coupling.ContactCoupling`
        gives it each step's effective modulus).
    inclusions : framework.inclusions.InclusionSet
        The inhomogeneities.
    margin : float, optional
        Distance [m] the box extends beyond the inhomogeneities, where the total
        stress (with the eigenstrains' fields) is computed for the outputs (see :func:`layout`).
    travel : sequence of (int, int), optional
        The whole-cell shifts of the material at each step of a rolling run: the box
        moves with them, and must stay on the grid all the way.
    geometry : {"staircase", "laminate"}
        How the cuboids hold a body. ``"staircase"``: the cuboids whose centre it contains, whole.
        ``"laminate"``: also each cuboid its boundary cuts, with the body's share of its volume and
        the stiffness of a laminate of body and matrix parallel to the boundary there
        (:mod:`framework.inclusions.subcell`; an elastic matrix only, as the laminate mixes its
        stiffness): the interior stress is 6 times closer to Eshelby's and the boundary cuboids
        free of the staircase's stripes, for about twice the GMRES iterations. :attr:`indicator`
        stays the staircase's either way; :attr:`fraction` is each cuboid's share of a body.
    recycle : bool
        Keep the Krylov directions of each solve for the next ones (a run's sequence of solves); False for
        one solve (:func:`solve_inclusions`), which keeps them across its restarts only.
    """

    def __init__(self, grid, matrix, inclusions, margin=None, travel=None, geometry="staircase", recycle=True):
        from .subcell import GEOMETRIES, cut_cell_materials
        if geometry not in GEOMETRIES:
            raise ParameterError(f"geometry must be one of {', '.join(map(repr, GEOMETRIES))}, got {geometry!r}")
        if geometry == "laminate" and not isinstance(matrix, Elastic):
            raise ParameterError(f"geometry='laminate' needs an elastic matrix (its cut cuboids mix the matrix's "
                                 f"stiffness with the body's, and a viscoelastic one's relaxes), got "
                                 f"{type(matrix).__name__}; use geometry='staircase'")
        if not isinstance(matrix, (Elastic, Viscoelastic)):
            raise ParameterError(f"matrix must be a framework.materials.Elastic or Viscoelastic (a solid with an "
                                 f"instantaneous modulus), got {type(matrix).__name__}")
        if matrix.poisson == 0.5:
            raise ParameterError(
                f"material.poisson (the matrix around the inclusions) = {matrix.poisson!r}, an incompressible "
                f"solid: not supported with inclusions, whose equivalent-inclusion method works with the matrix's "
                f"stiffness, and its bulk modulus E / (3 (1 - 2 poisson)) is infinite at 0.5; expected poisson < 0.5, "
                f"e.g. 0.4999, within about 1e-4 of the incompressible limit (the inclusions must then be nearly "
                f"incompressible too: see MIN_STIFFNESS_RATIO)")
        inclusions.check_inside(grid)
        if len(inclusions) == 0:
            raise ParameterError("inclusions is empty: give at least one inhomogeneity")
        self.grid, self.matrix, self.inclusions = grid, matrix, inclusions
        stiffnesses = [inclusion.stiffness_tensor for inclusion in inclusions]
        # checked before the operator is built (seconds on a large box), with the matrices the system uses
        matrix_stiffness = isotropic_mandel(instantaneous(matrix), matrix.poisson)
        for k, stiffness in enumerate(stiffnesses):
            largest = _largest_shear(mandel_matrix(stiffness))
            if largest > STIFFEST:
                raise ParameterError(f"inclusions[{k}].material is stiffer than any solid: its stiffness in shear reaches "
                                     f"{largest:.3g} Pa (twice a shear modulus), expected at most {STIFFEST:g} Pa "
                                     f"(diamond, the stiffest solid, has 1.16e12)")
            stiffest = float(np.max(np.linalg.eigvalsh(np.linalg.solve(matrix_stiffness, mandel_matrix(stiffness)))))
            if stiffest > MAX_STIFFNESS_RATIO * (1 + 1e-9):   # round-off of an exact 1e8
                raise ParameterError(f"inclusions[{k}].material is {stiffest:.3g} times stiffer than the matrix along its "
                                     f"stiffest mode, expected at most {MAX_STIFFNESS_RATIO:g}: beyond it the inclusion "
                                     f"is rigid to round-off and only the conditioning changes; give it a stiffness "
                                     f"{MAX_STIFFNESS_RATIO:g} times the matrix's for a rigid body")
            ratio, volumetric = softest_mode(mandel_matrix(stiffness), matrix_stiffness)
            if ratio < MIN_STIFFNESS_RATIO:
                bulk = (f"; the softest mode is a change of volume: the matrix's poisson {matrix.poisson!r} makes "
                        f"it nearly incompressible, and an inclusion in it must be nearly incompressible too"
                        if volumetric else "")
                raise ParameterError(f"inclusions[{k}].material is too soft for the equivalent-inclusion method: its "
                                     f"stiffness is {ratio:.3g} times the matrix's along its softest mode, expected "
                                     f">= {MIN_STIFFNESS_RATIO} (the system's conditioning grows like 1/ratio; voids "
                                     f"are not supported){bulk}")
        self._stiffer = [float(np.mean(np.linalg.eigvalsh(np.linalg.solve(matrix_stiffness, mandel_matrix(c))))) > 1.0
                         for c in stiffnesses]
        start, self.shape, self.indicator = layout(grid, inclusions, margin)
        self.geometry = geometry
        materials, solved = self.indicator, stiffnesses
        self.fraction = (self.indicator > 0).astype(float)
        if geometry == "laminate":
            spacing = (*grid.spacing, grid.layer_thickness)
            self.fraction, owner, normal = inclusions.fractions(*box_coordinates(grid, start, self.shape), spacing)
            materials, solved = cut_cell_materials(owner, self.fraction, normal, stiffnesses,
                                                   isotropic_tensor(matrix.young, matrix.poisson))
        starts = None
        if travel is not None:
            starts = self._check_travel(start, travel)
        # the kernels on the folded lattice only where the bodies' preconditioner will take it
        lattices = BoxLattices(self.shape, (*grid.spacing, grid.layer_thickness))
        lattice, kind, _ = preconditioner_cell(lattices, np.nonzero(materials), [mandel_matrix(c) for c in solved],
                                               instantaneous(matrix), matrix.poisson)
        self.operator = HalfSpaceEigenstrain(grid, matrix.poisson, start, self.shape, whole_patch=travel is not None,
                                             starts=starts, folded=kind == "fourier" and lattice == "folded")
        self.problem = EquivalentInclusionProblem(self.operator, materials, solved, instantaneous(matrix),
                                                  recycle=check_bool(recycle, name="recycle"))
        for k in range(len(inclusions)):
            if not np.any(self.indicator == k + 1):
                raise ParameterError(f"inclusions[{k}] contains no cuboid centre of the grid: refine the grid")

    def _check_travel(self, start, travel):
        """The box must stay on the grid while the material carries it (a rolling run), checked before any step.

        Returns every ``(x1, x2)`` start the box takes (the operator's surface maps are sized for them).
        """
        position = np.array(start[:2])
        starts = [tuple(int(c) for c in position)]
        for cells in travel:
            position = position + cells
            for axis in range(2):
                if position[axis] < 0 or position[axis] + self.shape[axis] > self.grid.shape[axis]:
                    spacing = self.grid.spacing[axis]
                    raise InclusionError(
                        f"inclusions: the material carries the inhomogeneities (and the box of "
                        f"{self.shape[axis]} cells around them) off the grid along x{axis + 1} after "
                        f"{abs(position[axis] - start[axis]) * spacing:.4g} m of motion; expected them to "
                        f"stay on the grid for the whole run: lengthen grid.size[{axis}], shorten the distance or "
                        f"start them further ahead")
            starts.append(tuple(int(c) for c in position))
        return starts

    @property
    def start(self):
        """First cuboid of the box on the grid (where the material has carried it)."""
        return self.operator.start

    @property
    def box(self):
        """Slices of the box in the grid's ``(n1, n2, layers)`` arrays (where it lies now)."""
        return self.operator.box

    def move(self, cells):
        """Move the inhomogeneities and their box with the material by ``cells = (c1, c2)`` whole cells."""
        self.operator.move(cells)

    def on_grid(self, field, start=None):
        """A box field ``(m1, m2, m3, ...)`` placed in a zero grid field ``(n1, n2, layers, ...)``.

        ``start`` is where the box lay (a record of a rolling run), by default where it lies now.
        """
        return place(self.grid, field, self.start if start is None else start)

    def stress_at(self, points, applied_strain, eigenstrain):
        """Total stress ``(n, 6)`` [Pa] at points ``(n, 3)`` [m]: applied strain plus the eigenstrains' field.

        ``C_M : (strain - e*)`` with ``e*`` the eigenstrain of the cuboid holding the point (zero in the matrix),
        except in the cuboids of an inhomogeneity softer than the matrix (mean stiffness ratio below 1), where
        it is ``C_I : strain``: the two are equal at the solution, and each form multiplies the difference
        between the point strain and the cell-averaged strain the solver balanced by the smaller stiffness. A
        point is in a body where its cuboid is (the bodies are their cuboids).

        Any point of the grid's subsurface box, the surface and the bottom included: a point on a face, edge
        or corner of the cuboids (within :data:`~framework.operators.one_sided.FACE_TOLERANCE` of a cuboid's
        size) belongs to the cuboid on its positive side (larger x1, x2, x3: the one ``floor`` picks), and
        its stress is the limit from inside that cuboid (:mod:`framework.operators.one_sided`). Where the
        stress is continuous (between cuboids of equal eigenstrain) that is its value; on a body's boundary,
        where it jumps, it is the value on the side of larger coordinates; on an edge between cuboids of
        different eigenstrain, where the staircase's strain is logarithmically infinite, its finite part.
        ``applied_strain`` is a function of the points returning ``(n, 6)`` strains.
        """
        from ..operators.one_sided import lattice_index
        points = check_finite_array(points, name="points", ndim=2)
        if points.shape[1] != 3:
            raise ShapeError(f"points must have shape (n, 3), got {points.shape}")
        grid = self.grid
        outside = ((np.abs(points[:, 0]) > grid.size[0] / 2) | (np.abs(points[:, 1]) > grid.size[1] / 2)
                   | (points[:, 2] < 0) | (points[:, 2] > grid.depth))
        if outside.any():
            raise ParameterError(f"points must lie inside the subsurface box |x1| <= {grid.size[0] / 2:g}, "
                                 f"|x2| <= {grid.size[1] / 2:g}, 0 <= x3 <= {grid.depth:g} m; got "
                                 f"{points[np.argmax(outside)].tolist()}")
        strain = applied_strain(points) + self.operator.strain_at(points, eigenstrain)
        spacing = np.array(self.operator.spacing)
        origin = np.array([-grid.size[0] / 2, -grid.size[1] / 2, 0.0]) + np.array(self.start) * spacing
        index = lattice_index(points, origin, spacing)
        inside_box = np.all((index >= 0) & (index < self.shape), axis=1)
        cell = np.zeros((len(points), 6))
        cell[inside_box] = eigenstrain[tuple(index[inside_box].T)]
        stress = ((strain - cell) * MANDEL) @ self.problem.matrix.T
        body = np.zeros(len(points), dtype=int)
        body[inside_box] = self.indicator[tuple(index[inside_box].T)]
        for k in range(len(self.inclusions)):
            # a softer body: C_I : strain; a stiffer one keeps C_M : (strain - e*) (equal at the solution), as
            # C_I would multiply the small difference between the point strain and the cell-averaged one the
            # solver balanced by the stiffness ratio (a 1000x stiffer sphere's centre read -0.2 for 2.3 MPa)
            if self._stiffer[k]:
                continue
            inside = body == k + 1
            stress[inside] = (strain[inside] * MANDEL) @ self.problem.stiffness[k].T
        return stress / MANDEL


class InclusionSolution:
    """Result of :func:`solve_inclusions`.

    Attributes
    ----------
    eigenstrain : ndarray
        ``(n1, n2, layers, 6)`` equivalent eigenstrain (tensor shears, Voigt order xx yy zz yz xz xy).
    inhomogeneity : ndarray
        ``(n1, n2, layers)`` indicator: 0 in the matrix, ``k + 1`` in the ``k``-th inhomogeneity.
    fraction : ndarray
        ``(n1, n2, layers)`` share of each cuboid inside a body: 0 or 1 for the staircase, the cut
        cuboids' volume fractions with ``geometry="laminate"`` (where ``stress`` is the cuboid's mean).
    stress : ndarray
        ``(m1, m2, m3, 6)`` total stress [Pa] on the box ``box`` around the inhomogeneities.
    box : tuple of slice
        Where the box lies in the grid's arrays.
    iterations, residual, success
        GMRES iterations, final relative residual, convergence.
    """

    def __init__(self, problem, applied, solution):
        self._problem, self._applied, self._box_eigenstrain = problem, applied, solution.eigenstrain
        self.box = problem.box
        self.eigenstrain = problem.on_grid(solution.eigenstrain)
        self.inhomogeneity = problem.on_grid(problem.indicator)
        self.fraction = problem.on_grid(problem.fraction)
        self.stress = solution.stress
        self.iterations, self.residual, self.success = solution.iterations, solution.residual, solution.success

    def stress_at(self, points):
        """Total stress ``(n, 6)`` [Pa] at arbitrary points ``(n, 3)`` [m] of the subsurface box (direct sums)."""
        applied = self._applied
        return self._problem.stress_at(points, lambda p: np.broadcast_to(applied, (len(p), 6)),
                                       self._box_eigenstrain)


def solve_inclusions(grid, matrix, inclusions, applied_strain, tolerance=1e-10, margin=0.0, geometry="staircase"):
    """Inhomogeneities in an elastic half-space under a uniform applied strain, by the equivalent inclusion method.

    Parameters
    ----------
    grid : framework.Grid
        Open grid with layers; the operators live on the block of its cuboids around the
        inhomogeneities (grown by ``margin``), so memory and time follow the inhomogeneities.
    matrix : framework.materials.Elastic
        The half-space.
    inclusions : framework.inclusions.InclusionSet
        The inhomogeneities (or a list of :class:`~framework.inclusions.Ellipsoid`).
    applied_strain : array_like
        3x3 strain the matrix would have without the inhomogeneities (uniform).
    tolerance : float
        Relative residual of the GMRES solve.
    margin : float
        Extra distance [m] around the inhomogeneities where ``stress`` is tabulated.
    geometry : {"staircase", "laminate"}
        Whole cuboids, or also the cut cuboids as laminates (see :class:`InclusionProblem`).

    Returns
    -------
    InclusionSolution
    """
    from .bodies import InclusionSet
    if not isinstance(matrix, Elastic):
        raise ParameterError(f"matrix must be a framework.materials.Elastic (a uniform applied strain has no time "
                             f"history), got {type(matrix).__name__}")
    if not isinstance(inclusions, InclusionSet):
        inclusions = InclusionSet(inclusions)
    applied = strain_vector(applied_strain, name="applied_strain")
    if np.max(np.abs(applied)) > LARGEST_STRAIN:
        raise ParameterError(f"applied_strain must be small, every component at most {LARGEST_STRAIN:g} in magnitude "
                             f"(linear elasticity), got a largest component of {float(np.max(np.abs(applied))):g}")
    from ..resolution import check_bodies
    problem = InclusionProblem(grid, matrix, inclusions, margin=margin, geometry=geometry, recycle=False)
    check_bodies(grid, inclusions, stacklevel=2)   # after the problem's own checks: only for bodies it accepts
    solution = problem.problem.solve(applied, tolerance=tolerance)
    return InclusionSolution(problem, applied, solution)
