"""What a run returns: per-step series and fields, subsurface stresses on demand."""
from dataclasses import dataclass

import numpy as np

from ._validation import check_finite_array, check_positive_int
from ._version import __version__
from .errors import ParameterError, ShapeError
from .operators.one_sided import love_stress_at
from .operators.stress import SubsurfaceStress


@dataclass
class StepRecord:
    """One recorded step (SI units)."""

    index: int
    time: float
    load: float
    approach: float
    pressure: np.ndarray
    displacement: np.ndarray
    gap: np.ndarray
    iterations: int
    residual: float
    success: bool
    tilt: tuple = (0.0, 0.0)
    eigenstrain: np.ndarray = None        # (N, 6) on the inhomogeneities' N cuboids of their box, tensor shears
    inclusion_stress: np.ndarray = None   # (N, 6) total stress [Pa] on those cuboids
    couplings: int = 0                    # fixed-point iterations between contact and inhomogeneities
    inclusion_start: tuple = None         # first cuboid of that box on the grid (it moves when rolling)
    time_error: float = float("nan")      # estimated time-stepping error, relative (framework.time_error; NaN: unknown)
    relaxed_eigenstrain: np.ndarray = None    # (N, 6) e~ = R * de* [Pa] (viscoelastic matrix; else None)


#: SI unit of each series of :meth:`Result.summary` (``summary.csv`` writes them in its header).
SERIES_UNITS = {"time": "s", "load": "N", "approach": "m", "contact_area": "m2", "contact_radius": "m",
                "half_width": "m", "max_pressure": "Pa", "center_x1": "m", "center_x2": "m", "tilt_x1": "rad",
                "tilt_x2": "rad", "friction_coefficient": "1", "torque": "N m", "dissipated_power": "W",
                "position_x1": "m", "position_x2": "m", "iterations": "1", "residual": "1", "time_error": "1"}


class Result:
    """Series (one value per step) and fields of a run.

    Series: ``times`` [s], ``load`` [N], ``approach`` [m], ``contact_area`` [m^2],
    ``contact_radius`` [m] (of the disc of the same area: point contacts),
    ``half_width`` [m] (line contacts on a grid periodic along one axis, else
    NaN), ``max_pressure`` [Pa],
    ``center`` (n, 2) load centre [m], ``tilt`` (n, 2) [rad],
    ``friction_coefficient`` [-], ``torque`` [N m], ``dissipated_power`` [W]
    and ``position`` (n, 2) [m] of a rolling body (zero without motion),
    ``iterations`` and ``residual`` of each solve, ``couplings`` the
    fixed-point iterations between the contact and the inhomogeneities (0
    without them), ``time_error`` the estimated time-stepping error [-]
    (``Options.time_tolerance``).
    Fields: :meth:`pressure`, :meth:`displacement`, :meth:`gap` on the surface;
    :meth:`stress`, :meth:`von_mises`, :meth:`stress_at` below it. With a
    constant Poisson ratio the stresses depend on the current pressure only,
    so they are computed when asked for.

    ``stress_memory`` [bytes] (default 2 GiB, settable) bounds the memory the
    stress kernels' spectra keep between calls (one ``6 x 2 n1 x (n2 + 1)``
    array per depth, 6.3 MB at 256^2); beyond it the remaining depths' kernels
    are rebuilt at every call: less memory, more time.
    """

    def __init__(self, grid, material, indenter, schedule, options, inclusions=None, inclusion_problem=None):
        self.grid, self.material, self.indenter = grid, material, indenter
        self.schedule, self.options = schedule, options
        self.inclusions = inclusions
        self._inclusion_problem = inclusion_problem
        self._inclusion_layout = None
        self._inclusion_cells = None
        self.version = __version__
        self.records = []
        self._stress_operator = None
        self.stress_memory = 2 * 1024**3
        self._stress_cache = (None, None)
        self._field_operator = None
        self._relaxation_replay = (-1, None, None)
        self._reductions = []

    def append(self, record):
        """Add a finished step (records are appended, never changed)."""
        self.records.append(record)

    def _reduced(self):
        """Per record, the sums over its pressure that the series need, computed once for each new record.

        Columns: cells in contact, peak pressure, ``sum p``, ``sum p x1``,
        ``sum p x2``, and for a moving body ``sum p grad h . m`` and
        ``sum p x . m`` (``m`` the unit vector of the motion; else 0).
        """
        cache = self._reductions
        if len(cache) < len(self.records):
            x1, x2 = self.grid.coordinates()
            direction = getattr(self.schedule, "direction", None)
            if direction is not None:
                slopes = self.indenter.slopes_on_grid(self.grid)
                slope = direction[0] * slopes[0] + direction[1] * slopes[1]
                arm = direction[0] * x1 + direction[1] * x2
            for record in self.records[len(cache):]:
                p = record.pressure
                cache.append((np.count_nonzero(p > 0), p.max(), p.sum(), (p * x1).sum(), (p * x2).sum(),
                              0.0 if direction is None else (p * slope).sum(),
                              0.0 if direction is None else (p * arm).sum()))
        return np.array(cache[: len(self.records)], dtype=float).reshape(-1, 7)

    def __len__(self):
        return len(self.records)

    def _series(self, name):
        return np.array([getattr(r, name) for r in self.records], dtype=float)

    times = property(lambda self: self._series("time"))
    load = property(lambda self: self._series("load"))
    approach = property(lambda self: self._series("approach"))
    iterations = property(lambda self: self._series("iterations").astype(int))
    couplings = property(lambda self: self._series("couplings").astype(int))
    residual = property(lambda self: self._series("residual"))
    time_error = property(lambda self: self._series("time_error"), doc=(
        "Estimated time-stepping error of each recorded step [-], relative to the run's pressure and approach "
        "scale (:mod:`framework.time_error`); 0 without memory, NaN when unknown (a file written before it was "
        "kept)."))
    tilt = property(lambda self: np.array([r.tilt for r in self.records], dtype=float).reshape(-1, 2))

    @property
    def contact_area(self):
        """Area of the cells in contact [m^2]."""
        return self._reduced()[:, 0] * self.grid.cell_area

    @property
    def line_contact(self):
        """True on a grid periodic along exactly one axis: a line contact (plane strain)."""
        return sum(self.grid.periodic) == 1

    @property
    def contact_radius(self):
        """Radius of the disc with the contact area [m]: the size of a point contact.

        A line contact (a cylinder along the periodic axis of a grid periodic
        along one axis) has no radius: read :attr:`half_width` there.
        """
        return np.sqrt(self.contact_area / np.pi)

    @property
    def half_width(self):
        """Half-width of a line contact [m]: the contact area over twice the grid's length along its line.

        A line contact lies along the periodic axis of a grid periodic along
        exactly one axis; this is its half-width across the line, averaged
        along it. NaN on other grids, whose contacts have a
        :attr:`contact_radius` instead.
        """
        if not self.line_contact:
            return np.full(len(self.records), np.nan)
        length = self.grid.size[0] if self.grid.periodic[0] else self.grid.size[1]
        return self.contact_area / (2 * length)

    @property
    def max_pressure(self):
        """Peak pressure [Pa]."""
        return self._reduced()[:, 1]

    @property
    def center(self):
        """Load centre ``sum p x dA / W`` [m], shape (n, 2).

        Without load (no pressure) the centre is undefined: it is then the
        point where the schedule applies the load, its ``offset`` (``(0, 0)``,
        the indenter's axis, for a centred schedule), so that the series holds
        no NaN.
        """
        reduced = self._reduced()
        total = reduced[:, 2:3]
        applied = np.asarray(getattr(self.schedule, "offset", (0.0, 0.0)), dtype=float)
        return np.where(total > 0, reduced[:, 3:5] / np.where(total > 0, total, 1.0), applied)

    def _moving(self):
        """Which records have moved: all of a steady run, those after the start of a transient one, else none."""
        schedule = self.schedule
        if getattr(schedule, "velocity", None) is None:
            return np.zeros(len(self.records), bool)
        return np.ones(len(self.records), bool) if schedule.steady else self.times > schedule.motion_start

    def _resistance(self, column):
        """A sum of :meth:`_reduced` times the cell area, zero for the records without motion."""
        return np.where(self._moving(), self._reduced()[:, column] * self.grid.cell_area, 0.0)

    @property
    def friction_coefficient(self):
        """Apparent (rolling) friction coefficient ``F_t / W`` [-], positive when it resists the motion.

        ``F_t = sum p (grad h . m) dA`` over the contact, ``m`` the unit vector of
        the motion and ``h`` the body's height (for a sphere ``sum p x.m dA / R``):
        the part of the normal pressure on the body that pushes against its
        motion (THEORY.md sec. 7). Zero without motion (indentation, and the
        rest before a rolling body starts).
        """
        load = self.load
        return np.divide(self._resistance(5), load, out=np.zeros(len(self.records)), where=load > 0)

    @property
    def torque(self):
        """Resisting torque ``sum p (x . m) dA`` [N m] of the pressure about the body's axis (zero without motion).

        The half-space approximation takes the pressure vertical, so for a
        sphere or a cylinder of radius R it is ``friction_coefficient * W * R``.
        On a line contact it is per grid length along the line (the grid's load).
        """
        return self._resistance(6)

    @property
    def dissipated_power(self):
        """Power dissipated in the material ``F_t |V|`` [W] (zero without motion)."""
        return self._resistance(5) * getattr(self.schedule, "speed", 0.0)

    @property
    def position(self):
        """Position ``(n, 2)`` [m] of the body's axis in the material frame: 0 at rest, ``V (t - t_start)`` rolling.

        Zero for a steady run (its frame moves with the body).
        """
        velocity = getattr(self.schedule, "velocity", None)
        if velocity is None or self.schedule.steady:
            return np.zeros((len(self.records), 2))
        moved = np.maximum(self.times - self.schedule.motion_start, 0.0)
        return moved[:, None] * np.asarray(velocity, dtype=float)[None, :]

    def _record(self, step):
        if not isinstance(step, (int, np.integer)) or isinstance(step, bool) \
                or not -len(self.records) <= step < len(self.records):
            raise ParameterError(f"step must be an integer index in [-{len(self.records)}, {len(self.records)}), "
                                 f"got {step!r}")
        return self.records[step]

    def pressure(self, step):
        """Contact pressure [Pa], shape (n1, n2)."""
        return self._record(step).pressure

    def displacement(self, step):
        """Normal surface displacement [m], positive into the solid, shape (n1, n2)."""
        return self._record(step).displacement

    def gap(self, step):
        """Gap between the indenter and the deformed surface [m], shape (n1, n2)."""
        return self._record(step).gap

    def _operator(self):
        memory = check_positive_int(self.stress_memory, name="stress_memory [bytes]")
        if self._stress_operator is None or self._stress_operator.cache_bytes != memory:
            self._stress_operator = SubsurfaceStress(self.grid, self.material.poisson, cache_bytes=memory)
        return self._stress_operator

    def stress(self, step):
        """Stress [Pa] at the layer centres, shape (n1, n2, layers, 6), Voigt xx yy zz yz xz xy.

        The contact's stress (Love's coefficients) plus, with inhomogeneities, their eigenstrains'
        field on the whole grid: on the bodies' cuboids the stress the run computed (recorded there),
        elsewhere, in their box as beyond it,
        :class:`~framework.operators.eigenstrain_field.EigenstrainField` of the step's eigenstrains
        (the same kernels as the run's box operator; on the bodies the equivalent homogeneous body's
        stress from it meets the run's to the solver's tolerance). Its operator is built at the first
        call and kept; each step costs one product (1.0-1.3 s and about 0.3 GiB on a 128 x 128 x 40
        grid around a 30 x 31 x 30 box).

        With a viscoelastic matrix (constant Poisson ratio) the strain an eigenstrain causes does
        not depend on the modulus, but the matrix's stress does, through its history: beyond the
        bodies it is ``C_bar : D[e~]`` with ``e~(t) = int_0^t R(t - s) de*(s)`` the eigenstrains
        weighted by the relaxation modulus ``R`` (THEORY.md sec. 8), neither the instantaneous
        ``E(0) D[e*]`` nor the relaxed ``E_inf D[e*]``. The run carries ``e~`` by one more Prony
        recursion over every step it takes, recorded or not (``StepRecord.relaxed_eigenstrain``), so
        the field is the run's own at any output time. (A record without it, from a run resumed from a
        checkpoint written before it was carried, falls back on the recursion replayed over the
        recorded steps, ``e*`` linear between them: exact only where every step was recorded.)
        """
        record = self._record(step)
        if not self.grid.layers:
            raise ParameterError("stress needs subsurface layers: the grid has layers=0; "
                                 "give Grid(..., depth=..., layers=...)")
        key, value = self._stress_cache
        if key != record.index:
            if record.inclusion_stress is None:
                value = self._operator().apply(record.pressure)
            else:
                position = step % len(self.records)
                value = self._eigenstrain_field().apply(self._box_field(self._relaxed_eigenstrain(position)),
                                                        start=self._inclusion_start(record), pressure=record.pressure)
                value[self._inclusion_box(record)][self._cells()] = record.inclusion_stress
            self._stress_cache = (record.index, value)
        return value

    def _eigenstrain_field(self):
        """The operator from the box's eigenstrains to the stress on the whole grid (built once), refused before it
        is built where its memory (:func:`~framework.operators.eigenstrain_field.field_bytes`) exceeds what this
        machine has left."""
        if self._field_operator is None:
            from . import resources
            from .operators.eigenstrain_field import EigenstrainField, field_bytes
            start, shape, _ = self._layout()
            starts = self._box_starts(start)
            needs, total = field_bytes(self.grid, start, shape, starts), resources.machine_memory()
            left = None if total is None else max(total - resources.resident_memory(), 0)
            if left is not None and needs > left:
                n1, n2 = self.grid.shape
                raise ParameterError(
                    f"stress: the inhomogeneities' field on the whole grid ({n1} x {n2} x {self.grid.layers} "
                    f"cuboids, box {shape[0]} x {shape[1]} x {shape[2]}) needs about {resources.size(needs)} of "
                    f"memory, more than the {resources.size(left)} this "
                    f"machine has left of its {resources.size(total)}; expected a field that fits: a machine with "
                    f"more memory, or a run on fewer cells or layers (the kernels span the grid, twice its size along "
                    f"each axis)")
            self._field_operator = EigenstrainField(self.grid, self.material.poisson, start, shape,
                                                    starts=starts, surface_stress=self._operator())
        return self._field_operator

    def _box_starts(self, start):
        """Every (x1, x2) place of the box in the run: the start alone, or each one a rolling run carries it to."""
        schedule = self.schedule
        if getattr(schedule, "velocity", None) is None or schedule.steady:
            return [tuple(start[:2])]
        from .stations import rolling_stations
        position, starts = np.array(start[:2]), [tuple(start[:2])]
        for station in rolling_stations(schedule, self.grid, refine=False):
            position = position + station.shift
            starts.append(tuple(int(c) for c in position))
        return starts

    def _relaxed_eigenstrain(self, position):
        """``e~ = int R(t - s) de*(s)`` [Pa] on the inhomogeneities' cuboids (``(N, 6)``) at record ``position``:
        ``E e*`` for an elastic matrix; for a
        viscoelastic one the run's own (recorded), else the relaxation recursion replayed over the records up to
        it (kept, so steps asked in order cost one update each)."""
        from .materials import Elastic
        records = self.records
        if isinstance(self.material, Elastic):
            return self.material.young * records[position].eigenstrain
        if records[position].relaxed_eigenstrain is not None:
            return records[position].relaxed_eigenstrain
        from .history import PronyRecursion
        from .inclusions.coupling import matrix_series
        done, recursion, relaxed = self._relaxation_replay
        if done == position:
            return relaxed
        if recursion is None or done > position:
            done, recursion = -1, PronyRecursion(matrix_series(self.material)[1], records[position].eigenstrain.shape)
        for k in range(done + 1, position + 1):
            modulus, history = recursion.prepare(records[k].time)
            relaxed = modulus * records[k].eigenstrain + (0.0 if history is None else history)
            recursion.commit(records[k].time, records[k].eigenstrain)
        self._relaxation_replay = (position, recursion, relaxed)
        return relaxed

    def _inclusions_problem(self):
        """The inhomogeneities' operators (built on demand for ``stress_at`` of a loaded result)."""
        if self._inclusion_problem is None:
            self._require_inclusions()
            from .inclusions.field import InclusionProblem
            self._inclusion_problem = InclusionProblem(self.grid, self.material, self.inclusions,
                                                       margin=self.options.inclusion_margin,
                                                       geometry=self.options.inclusion_geometry)
        return self._inclusion_problem

    def _require_inclusions(self):
        if not self.inclusions:
            raise ParameterError("this run has no inhomogeneities (Simulation(..., inclusions=None))")

    def _layout(self):
        """``(start, shape, indicator)`` of the box at the start of the run: no operator needed to place fields."""
        if self._inclusion_layout is None:
            self._require_inclusions()
            from .inclusions.field import layout
            self._inclusion_layout = layout(self.grid, self.inclusions, self.options.inclusion_margin)
        return self._inclusion_layout

    def _cells(self):
        """The box's cuboids the records' inhomogeneity fields lie on (:func:`~framework.inclusions.field.body_cuboids`)."""
        if self._inclusion_cells is None:
            if self._inclusion_problem is not None:
                self._inclusion_cells = self._inclusion_problem.problem.cells
            else:
                self._require_inclusions()
                from .inclusions.field import body_cuboids
                self._inclusion_cells = body_cuboids(self.grid, self.inclusions, self._layout(),
                                                     self.options.inclusion_geometry)
        return self._inclusion_cells

    def _box_field(self, values):
        """A box field ``(m1, m2, m3, 6)``, zero in the matrix, of a record's values ``(N, 6)`` on :meth:`_cells`."""
        out = np.zeros((*self._layout()[1], 6))
        out[self._cells()] = values
        return out

    def _inclusion_start(self, record):
        return self._layout()[0] if record.inclusion_start is None else record.inclusion_start

    def _inclusion_box(self, record):
        return tuple(slice(s, s + m) for s, m in zip(self._inclusion_start(record), self._layout()[1]))

    def eigenstrain(self, step):
        """Equivalent eigenstrain of the inhomogeneities, shape (n1, n2, layers, 6), tensor shears, Voigt order.

        Zero outside the inhomogeneities (THEORY.md sec. 8).
        """
        from .inclusions.field import place
        record = self._record(step)
        if record.eigenstrain is None:
            raise ParameterError("this run has no inhomogeneities (Simulation(..., inclusions=None))")
        return place(self.grid, self._box_field(record.eigenstrain), self._inclusion_start(record))

    def inhomogeneity(self, step):
        """Indicator of the inhomogeneities on the cuboids, shape (n1, n2, layers): 0 matrix, k + 1 the k-th."""
        from .inclusions.field import place
        record = self._record(step)
        return place(self.grid, self._layout()[2], self._inclusion_start(record))

    def von_mises(self, step):
        """Von Mises equivalent stress [Pa], shape (n1, n2, layers)."""
        return von_mises(self.stress(step))

    def stress_at(self, step, points):
        """Stress [Pa] at arbitrary points, shape (n, 6), by direct summation over the cells.

        Below the surface the contact's stress is continuous; at the surface it jumps at the
        edges of the cells, where the pressure does, and a point on an edge or corner (within
        :data:`~framework.operators.one_sided.FACE_TOLERANCE` of a cell) takes the value of the
        cell on its positive side (larger x1, x2). With inhomogeneities the same convention
        holds on the faces, edges and corners of the cuboids
        (:meth:`framework.inclusions.field.InclusionProblem.stress_at`).

        Parameters
        ----------
        step : int
            Step index.
        points : array_like
            ``(n, 3)`` coordinates ``(x1, x2, x3)`` [m] with ``x3 >= 0`` inside the
            subsurface box (``|x1| <= L1/2``, ``|x2| <= L2/2``, ``x3 <= depth``).
        """
        pressure = self._record(step).pressure
        points = check_finite_array(points, name="points", ndim=2)
        if points.shape[1] != 3:
            raise ShapeError(f"points must have shape (n, 3), got {points.shape}")
        grid = self.grid
        depth = grid.depth if grid.depth is not None else 0.0
        outside = (np.abs(points[:, 0]) > grid.size[0] / 2) | (np.abs(points[:, 1]) > grid.size[1] / 2) \
            | (points[:, 2] < 0) | (points[:, 2] > depth)
        if outside.any():
            raise ParameterError(f"points must lie inside the subsurface box |x1| <= {grid.size[0] / 2:g}, "
                                 f"|x2| <= {grid.size[1] / 2:g}, 0 <= x3 <= {depth:g} m; got "
                                 f"{points[np.argmax(outside)].tolist()}")
        if any(grid.periodic):
            raise ParameterError(f"stress_at sums over the cells of a non-periodic grid, got periodic={grid.periodic}")
        loaded = pressure > 0
        x1, x2 = (c[loaded] for c in grid.coordinates())
        out = love_stress_at(points, x1, x2, pressure[loaded], spacing=grid.spacing, poisson=self.material.poisson)
        record = self._record(step)
        if record.eigenstrain is not None:
            from .materials import Elastic
            from .operators.eigenstrain import strain_from_stress
            if getattr(self.schedule, "direction", None) is not None:
                raise ParameterError("stress_at: with inhomogeneities under a rolling body the stress around them "
                                     "is kept on the cuboids only; read Result.stress(step) instead")
            if not isinstance(self.material, Elastic):
                raise ParameterError("stress_at: with inhomogeneities in a viscoelastic matrix the stress around "
                                     "them depends on the history of their fields, kept on the cuboids only; read "
                                     "Result.stress(step) (cuboid centres) instead")
            strain = strain_from_stress(out, self.material.poisson, self.material.young)
            out = self._inclusions_problem().stress_at(points, lambda _: strain, self._box_field(record.eigenstrain))
        return out

    def configuration(self):
        """The run's full configuration as plain data (see :func:`framework.config.describe`)."""
        from .config import describe
        from .indenters import HeightMap
        indenter = self.indenter
        if isinstance(indenter, HeightMap) and callable(indenter.heights):
            indenter = HeightMap(indenter.on_grid(self.grid))  # a function cannot be stored: its values can
        configuration = {"framework_version": self.version, "grid": describe(self.grid),
                         "material": describe(self.material), "indenter": describe(indenter),
                         "schedule": describe(self.schedule), "options": describe(self.options)}
        if self.inclusions:  # left out without inhomogeneities: such files read as before
            configuration["inclusions"] = describe(self.inclusions)
            # the eigenstrain operator's discretisation: a checkpoint written with the earlier collocated
            # operator lacks this key, so it is not resumed with the cell-averaged one
            configuration["eigenstrain_operator"] = "cell-averaged"
        return configuration

    def save(self, path):
        """Write everything to the HDF5 file ``path`` (read back with :func:`framework.load_result`).

        Every dataset and the file's structure carry checksums that reading
        verifies (layout in :mod:`framework.io`). ``path`` must not be a folder,
        and its folder must exist and be writable: else :class:`ParameterError`
        naming ``path``.
        """
        from .io import save
        save(self, path)

    def summary(self):
        """Per-step scalar table as a dict of arrays (units: :data:`SERIES_UNITS`)."""
        center, position = self.center, self.position
        return {"time": self.times, "load": self.load, "approach": self.approach,
                "contact_area": self.contact_area, "contact_radius": self.contact_radius,
                "half_width": self.half_width,
                "max_pressure": self.max_pressure, "center_x1": center[:, 0], "center_x2": center[:, 1],
                "tilt_x1": self.tilt[:, 0], "tilt_x2": self.tilt[:, 1],
                "friction_coefficient": self.friction_coefficient, "torque": self.torque,
                "dissipated_power": self.dissipated_power,
                "position_x1": position[:, 0], "position_x2": position[:, 1],
                "iterations": self.iterations, "residual": self.residual, "time_error": self.time_error}


def von_mises(stress):
    """Von Mises stress of Voigt-ordered stresses ``(..., 6)`` [Pa]."""
    s11, s22, s33, s23, s13, s12 = np.moveaxis(stress, -1, 0)
    return np.sqrt(0.5 * ((s11 - s22) ** 2 + (s22 - s33) ** 2 + (s33 - s11) ** 2)
                   + 3.0 * (s12**2 + s13**2 + s23**2))
