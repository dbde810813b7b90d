"""What a run will take, told before it starts: memory, time and the size of its files; and the machine's memory.

``python -m framework check`` prints the estimate and refuses a run that
cannot fit in this machine's memory (``run`` refuses it too, before it writes
anything); :func:`framework.scenario.parse` takes a memory limit and refuses a
scenario whose grid alone exceeds it, before the first large array is made.

The figures are models, not measurements of the run: each constant below is a
peak resident memory, a time or a file size measured on this project's
examples and benchmarks (2-core AMD EPYC, Python 3.11, pyFFTW, one FFT
thread), scaled by the number of cells, cuboids and steps. Expect the memory
within tens of percent and the time within a factor of a few (iterations
vary with the problem, and a shared machine runs slower); enough to know
whether a run fits, and whether it takes seconds, minutes or days.
"""
import dataclasses
import math
import os

from .errors import ParameterError

# --------------------------------------------------------------------------- memory [bytes]

#: The interpreter with numpy, scipy and the framework imported (measured: 107 MB), and with the packages
#: VTU files and pictures import (vtk, pyvista, matplotlib: 277 MB measured, 170 MB more).
BASE = 110e6
VIZ = 170e6
#: Per cell, the contact solve of one step: the kernel spectrum, the solver's fields and the FFT arrays, on a
#: grid padded to twice its size along each open axis (DC-FFT). Measured peaks of an elastic Hertz solve: 378
#: bytes per cell on an open 1024^2 grid (padded 4 times), 217 on a periodic one: 163 + 54 per padded cell.
CONTACT = 163
CONTACT_PADDED = 54
#: Per cell, a material with memory: its history and the stepper's other fields. Measured: 178 bytes per cell
#: with PMMA's 2 terms on an open 1024^2 grid (100 + 40 per term, rounded up).
HISTORY = 100
HISTORY_TERM = 40
#: Per cell and recorded step: pressure, displacement and gap, kept in the result (float64).
RECORD = 24
#: Per cuboid (cell x layer), the subsurface stresses of one step: the stresses, the kernel spectra and, for a VTU
#: volume, the VTK mesh. Measured 575-595 bytes per cuboid writing a volume on 128^2 x 64 and 256^2 x 32; a
#: slice picture needs the stresses and spectra only (about half).
VOLUME = 600
STRESS = 300
#: Per cuboid of the inhomogeneities' box: the eigenstrain operator's 42 spectra, the Krylov solver's basis and
#: the fields of a coupled step. Measured 4.5 kB per cuboid between boxes of 17576 and 64000 cuboids.
INCLUSION = 4500
#: A large box: the solver's basis, kept directions and block spectra stop growing at their caps (384, 768, 128 MiB),
#: and what grows is the kernels (528 bytes a box cuboid; 264 where its cuboids are square in x1, x2, half of them
#: stored) and the box's fields: INCLUSION_FIXED + INCLUSION_LARGE a cuboid where that is less than INCLUSION a
#: cuboid. Measured peaks less the contact's, with every kernel stored: 2.93 GB at 2.1 million cuboids (a 128^3
#: solve), 4.4 GB at 2.6 million and 11.5 GB at 7.75 million (100 and 300 glass spheres rolled over,
#: `bench/dispersion.py`), which INCLUSION alone put at 9.4, 11.9 and 35 GB: `check` refused the last on a 24 GB
#: machine where it runs in 10.8 GiB. A box whose cuboids are square in x1, x2 stores half its kernels
#: (`eigenstrain.box_lattice`) and grows by INCLUSION_LARGE_SQUARE a cuboid: measured with blocks of at least 8 q3
#: and the preconditioner's transforms in the product's buffers, 3.41 and 8.87 GB for the 100 and 300 spheres
#: (950 and 1028 bytes a cuboid past INCLUSION_FIXED; 3.7 and 9.6 GB when the preconditioner had buffers of its own).
INCLUSION_FIXED = 0.9e9
INCLUSION_LARGE = 1500
INCLUSION_LARGE_SQUARE = 1100
#: Per cuboid inside the bodies and recorded step: its eigenstrains and total stresses (12 float64), the records
#: keep them on the bodies' cuboids only (in a dispersion at 10 %, a tenth of the box's).
INCLUSION_RECORD = 96
#: Above this fraction of the machine's memory, ``check`` warns: the estimate is a model, the machine runs other
#: processes, and a run that swaps takes days.
WARN_FRACTION = 0.5

# --------------------------------------------------------------------------- time [s]

#: Per cell and contact iteration: two FFT pairs on the padded grid. Measured 61.5 ms per iteration on an open
#: 1024^2 grid (59 ns per cell), 25.5 ms on a periodic one (24 ns): 12 ns + 12 ns per padded cell.
ITERATION = 12e-9
ITERATION_PADDED = 12e-9
#: Iterations of the first solve of a run, and of each later one: measured 17-28 for Hertz solves at 1e-8 to
#: 1e-10, 8-11 per viscoelastic step warm-started from the last.
FIRST_ITERATIONS = 25
ITERATIONS = 12
#: Per cuboid, the stresses of one step and their VTU file (5-8 us measured, the first step building the kernels).
VOLUME_TIME = 7e-6
#: A step with inhomogeneities iterates between the contact and the eigenstrains: 13-21 couplings measured in a
#: first step, 6-10 in the later steps of a rolling run (warm-started). Each coupling costs a fixed part and a part
#: per cuboid of the box: measured 0.26 s on a box of 64000 cuboids, 0.030-0.033 s on one of 2304.
FIRST_COUPLINGS = 20
COUPLINGS = 10
COUPLING_TIME = 0.03
COUPLING_CUBOID = 4e-6

# --------------------------------------------------------------------------- files [bytes]

#: Per cell and step, zlib-compressed: the surface VTU (26 bytes measured), the indenter's VTU (18), result.h5 (8-11).
SURFACE_FILE = 26
INDENTER_FILE = 18
RESULT_FILE = 10
#: Per cuboid and volume step: the volume VTU in float64 (107-110 bytes measured) or float32 (44-56), and the
#: inhomogeneities' fields added to it (about 40 more).
VOLUME_FILE = 110
VOLUME_FILE_SINGLE = 56
VOLUME_FILE_INCLUSIONS = 40
#: A picture (75-135 kB measured), history.png (80 kB), a frame of an animation.
PICTURE_FILE = 150e3
HISTORY_FILE = 80e3
FRAME_FILE = 100e3


@dataclasses.dataclass(frozen=True)
class Estimate:
    """What a run will take.

    Attributes
    ----------
    memory : float
        Peak memory [bytes].
    seconds : float
        Time on one core [s].
    disk : float
        Size of the files written [bytes].
    parts : dict
        ``{what: bytes}``: the memory of each part, largest first (the message names the first).
    files : dict
        ``{kind: (count, bytes)}`` of the files written.
    """

    memory: float
    seconds: float
    disk: float
    parts: dict
    files: dict

    def describe(self, available=None):
        """One line: ``about 1.2 GiB of memory (this machine: 23.5 GiB), 40 s on one core, 35 MB of files``."""
        machine = "" if available is None else f" (this machine: {size(available)})"
        kinds = ", ".join(_count(count, kind) for kind, (count, _) in self.files.items() if count)
        return (f"about {size(self.memory)} of memory{machine}, {duration(self.seconds)} on one core, "
                f"{size(self.disk)} of files" + (f" ({kinds})" if kinds else ""))


def _count(count, kind):
    """``result.h5``, ``3 surface steps``, ``1 volume``: a kind of file and how many (a file name alone)."""
    if "." in kind:
        return kind
    return f"{count} {kind[:-1] if count == 1 and kind.endswith('s') else kind}"


def size(bytes_):
    """``1.2 GiB``, ``35 MB``, ``120 kB``: binary units from 1 GiB up (as memory is sold), decimal below."""
    for unit, scale in (("PiB", 2**50), ("TiB", 2**40), ("GiB", 2**30)):
        if bytes_ >= scale:
            return f"{bytes_ / scale:.3g} {unit}"
    if bytes_ >= 1e6:
        return f"{bytes_ / 1e6:.3g} MB"
    return f"{max(bytes_, 0.0) / 1e3:.3g} kB"


def duration(seconds):
    """``40 s``, ``12 min``, ``3.5 h``, ``20 days``: two significant digits."""
    for unit, scale in (("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if seconds >= 2 * scale:
            return f"{seconds / scale:.2g} {unit}"
    return f"{max(seconds, 1.0):.2g} s"


def machine_memory():
    """This machine's memory [bytes], or the container's limit where it is lower; None where unknown."""
    try:
        total = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):  # not a POSIX system
        return None
    for limit in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            with open(limit) as f:
                text = f.read().strip()
        except OSError:
            continue
        if text.isdigit() and 0 < int(text) < total:
            total = int(text)
    return total if total > 0 else None


def resident_memory():
    """This process's resident memory [bytes] (Linux's ``/proc/self/statm``), or 0 where unknown."""
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError, AttributeError):
        return 0


def _padding(grid):
    """How many times the FFT grid is larger than the grid: twice along each open axis (DC-FFT)."""
    return math.prod(1 if periodic else 2 for periodic in grid.periodic)


def _history_terms(material):
    """The number of history arrays a material with memory needs (None: it has none)."""
    try:
        series = material.contact_compliance()
    except Exception:  # noqa: BLE001 - a material the run refuses itself, with its own message
        return None
    terms = len(series.terms) + (1 if series.flow > 0 else 0)
    return terms or None


def _box(grid, inclusions, margin):
    """The inhomogeneities' box and the cuboids inside them: ``(start, shape, inside)`` (None without them); ``inside``
    from the bodies' volumes (at most the box's cuboids), not their staircase (a large box's takes seconds)."""
    if not inclusions:
        return None
    from .inclusions import InclusionSet
    from .inclusions.field import inclusion_box
    bodies = inclusions if isinstance(inclusions, InclusionSet) else InclusionSet(list(inclusions))
    if margin is None:  # as framework.inclusions.field.layout
        margin = 0.5 * max(max(body.semi_axes) for body in bodies)
    start, shape = inclusion_box(grid, bodies, margin)
    volume = sum(4.0 / 3.0 * math.pi * math.prod(body.semi_axes) for body in bodies)
    inside = min(math.prod(shape), math.ceil(volume / (grid.spacing[0] * grid.spacing[1] * grid.layer_thickness)))
    return start, shape, inside


def _field_bytes(grid, start, shape):
    """Memory of the inhomogeneities' stress field on the whole grid, the box anywhere on it (a rolling run's
    moves it): :func:`framework.operators.eigenstrain_field.field_bytes`."""
    from .operators.eigenstrain_field import field_bytes
    extremes = [(0, 0), (grid.shape[0] - shape[0], grid.shape[1] - shape[1])]
    return field_bytes(grid, start, shape, starts=extremes)


def _steps(steps, total):
    """The number of steps ``"all"`` or a list of indices name (of ``total``)."""
    if steps == "all":
        return total
    return len({step % total for step in steps}) if total else 0


def estimate(grid, material, *, inclusions=None, margin=None, steps=1, solves=None, output=None, animate=None):
    """The :class:`Estimate` of a run.

    Parameters
    ----------
    grid : framework.Grid
        The grid.
    material : framework.materials material
        The half-space's material (its number of Prony terms).
    inclusions : sequence of Ellipsoid, optional
        The inhomogeneities.
    margin : float, optional
        ``Options.inclusion_margin`` [m] (None: half the largest semi-axis).
    steps : int
        Recorded steps (``len(simulation.output_times)``).
    solves : int, optional
        Contact solves (the stepper's stations, recorded or not); default ``steps``.
    output : framework.scenario.Output, optional
        What a scenario run writes besides result.h5; None: result.h5 only (the Python API).
    animate : str, optional
        The field of ``--animate``: a stress field computes the stresses at every step.
    """
    cells = grid.shape[0] * grid.shape[1]
    cuboids = cells * grid.layers
    padding = _padding(grid)
    solves = steps if solves is None else solves
    terms = _history_terms(material)
    place = _box(grid, inclusions, margin)
    box, inside = (math.prod(place[1]), place[2]) if place else (0, 0)
    if box:
        from .operators.eigenstrain import box_lattice
        square = box_lattice(place[1], (*grid.spacing, grid.layer_thickness))[1]
        large = INCLUSION_LARGE_SQUARE if square else INCLUSION_LARGE
    parts = {"the contact solver": cells * (CONTACT + CONTACT_PADDED * padding),
             "the recorded steps": cells * RECORD * steps + inside * INCLUSION_RECORD * steps}
    if terms:
        parts["the material's history"] = cells * (HISTORY + HISTORY_TERM * terms)
    if box:
        parts["the inhomogeneities' box"] = min(box * INCLUSION, INCLUSION_FIXED + box * large)
    seconds = cells * (ITERATION + ITERATION_PADDED * padding) * (FIRST_ITERATIONS + ITERATIONS * max(solves - 1, 0))
    if box:
        seconds += (FIRST_COUPLINGS + COUPLINGS * max(solves - 1, 0)) * (COUPLING_TIME + COUPLING_CUBOID * box)
    files = {"result.h5": (1, cells * RESULT_FILE * steps + inside * INCLUSION_RECORD * steps)}
    viz = False
    if output is not None:
        surfaces = _steps(output.steps, steps) if output.vtu else 0
        volumes = _steps(output.volume_steps, steps) if output.vtu and grid.layers else 0
        slices = sum(picture.get("kind", "map") == "slice" for picture in output.pictures) if grid.layers else 0
        stressed = volumes + slices + (steps if animate and animate.startswith(("stress", "von_mises")) else 0)
        if volumes:
            parts["a volume's stresses"] = cuboids * VOLUME
        elif stressed:
            parts["the subsurface stresses"] = cuboids * STRESS
        if stressed and box:
            parts["the inhomogeneities' stress field"] = _field_bytes(grid, *place[:2])
        seconds += cuboids * VOLUME_TIME * stressed
        per_volume = cuboids * ((VOLUME_FILE_SINGLE if output.single else VOLUME_FILE)
                                + (VOLUME_FILE_INCLUSIONS if box else 0))
        files.update({"surface steps": (surfaces, cells * (SURFACE_FILE + INDENTER_FILE) * surfaces),
                      "volumes": (volumes, per_volume * volumes),
                      "pictures": (len(output.pictures), PICTURE_FILE * len(output.pictures)),
                      "history.png": (1 if output.history else 0, HISTORY_FILE if output.history else 0)})
        viz = bool(output.vtu or output.pictures or output.history or animate)
    if animate:
        files[f"{animate}.gif"] = (1, FRAME_FILE * steps)
    memory = BASE + (VIZ if viz else 0.0) + sum(parts.values())
    parts = dict(sorted(parts.items(), key=lambda item: -item[1]))
    return Estimate(memory=memory, seconds=seconds, disk=sum(b for _, b in files.values()), parts=parts,
                    files=files)


def for_simulation(simulation, output=None, animate=None):
    """The :class:`Estimate` of a constructed :class:`framework.Simulation` (its steps and stations known)."""
    steps = len(simulation.output_times)
    solves = len(getattr(simulation, "_timeline", ())) or steps
    return estimate(simulation.grid, simulation.material, inclusions=simulation.inclusions or None,
                    margin=simulation.options.inclusion_margin, steps=steps, solves=solves, output=output,
                    animate=animate)


def check_memory(estimate_, available):
    """Refuse an estimate above ``available`` [bytes]; the text of a warning above :data:`WARN_FRACTION` of it.

    Returns
    -------
    str or None
        The warning (None: below the threshold, or ``available`` unknown).

    Raises
    ------
    ParameterError
        Naming the estimate, its largest part and the machine's memory.
    """
    if available is None:
        return None
    part, bytes_ = next(iter(estimate_.parts.items()))
    needs = f"the run needs about {size(estimate_.memory)} of memory ({part}: {size(bytes_)})"
    if estimate_.memory > available:
        raise ParameterError(f"{needs}, more than this machine's {size(available)}; expected a run that fits: "
                             f"fewer cells or layers (--cells N for a quick look), fewer recorded steps, or a "
                             f"machine with more memory")
    if estimate_.memory > WARN_FRACTION * available:
        return (f"{needs}, more than {WARN_FRACTION:.0%} of this machine's {size(available)}; the estimate is a "
                f"model, and a run that swaps takes far longer")
    return None
