"""Bit flips in result files, run in a child process so that a flip that hangs HDF5 fails a test instead of hanging it.

HDF5 can loop forever on damaged metadata that no checksum guards (format 4's variable-length strings in the
global heap: a flipped bit in the heap collection's size hung HDF5 2.0 while it read the configuration). A load
cannot be interrupted inside HDF5's C code, so :func:`flip_in_child` runs the loads in a fresh interpreter
(``python bit_flips.py ...``) under a timeout, and names the flip it was loading when the timeout struck.

Each flip counts as detected (a one-line :class:`~framework.errors.FileError` naming the file) or harmless (the
file loads equal to the original, array by array); anything else is a failure.
"""
import json
import os
import subprocess
import sys
import uuid
import warnings

import numpy as np

#: Flips of the sampled campaign, per file: bytes of names, and bytes of the other metadata.
NAME_FLIPS, METADATA_FLIPS = 250, 250


def simulation():
    """A 16 x 16 x 8 grid, a stiff sphere under a spherical indenter, two loads (about 1 s)."""
    import framework as fw
    from framework import inclusions, materials
    grid = fw.Grid(shape=(16, 16), size=(1e-3, 1e-3), depth=0.5e-3, layers=8)
    body = inclusions.Ellipsoid(center=(0.0, 0.0, 0.25e-3), semi_axes=(0.2e-3, 0.2e-3, 0.2e-3),
                                material=materials.Elastic(600e9, 0.25))
    return fw.Simulation(grid=grid, material=materials.Elastic(200e9, 0.3), indenter=fw.indenters.Sphere(radius=10e-3),
                         schedule=fw.schedules.Static(load=[20.0, 40.0], times=[1.0, 2.0]), inclusions=[body])


def stored_numbers(path):
    """Byte ranges of the datasets' stored data (their chunks): what Fletcher-32 guards."""
    import h5py
    ranges = []
    with h5py.File(path, "r") as f:
        def visit(name, item):
            if isinstance(item, h5py.Dataset):
                for k in range(item.id.get_num_chunks()):
                    info = item.id.get_chunk_info(k)
                    ranges.append((info.byte_offset, info.byte_offset + info.size))
        f.visititems(visit)
    return ranges


def regions(path):
    """``(names, metadata)``: offsets of the bytes of every group, dataset and attribute name, and of every other
    byte outside the stored numbers (superblock, object headers, B-trees, heaps, the attributes' text)."""
    import h5py
    whole = open(path, "rb").read()
    numbers = np.zeros(len(whole), bool)
    for start, stop in stored_numbers(path):
        numbers[start:stop] = True
    labels = set()
    with h5py.File(path, "r") as f:
        labels.update(f.attrs)
        f.visititems(lambda name, item: labels.update(name.split("/")) or labels.update(item.attrs))
    names = set()
    for label in labels:
        start = whole.find(label.encode())
        while start >= 0:
            names.update(range(start, start + len(label)))
            start = whole.find(label.encode(), start + 1)
    names = np.array(sorted(at for at in names if not numbers[at]), dtype=int)
    metadata = np.setdiff1d(np.flatnonzero(~numbers), names)
    return names, metadata


def sample(offsets, count, full=False):
    """``(offset, bit)`` pairs: every bit of every offset (``full``), else ``count`` offsets evenly spread, one bit
    each, the bit turning with the offset's rank."""
    if full:
        return [(int(at), bit) for at in offsets for bit in range(8)]
    chosen = offsets[np.unique(np.linspace(0, len(offsets) - 1, min(count, len(offsets))).astype(int))]
    return [(int(at), rank % 8) for rank, at in enumerate(chosen)]


def campaign_flips(path, full=False):
    """The flips of the campaign over ``path``: :data:`NAME_FLIPS` in names, :data:`METADATA_FLIPS` elsewhere."""
    names, metadata = regions(path)
    return sample(names, NAME_FLIPS, full) + sample(metadata, METADATA_FLIPS, full)


def same_arrays(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def same_records(first, second):
    return len(first) == len(second) and all(
        same_arrays(getattr(a, key), getattr(b, key)) for a, b in zip(first, second)
        for key in a.__dataclass_fields__)


def loader(kind, folder):
    """``(load, equal)`` for a flipped copy of ``folder/r.h5`` (``kind = "result"``) or ``folder/c.h5``
    (``"checkpoint"``), compared with the originals read back (a round trip is exact to the bit, test_io)."""
    import framework as fw
    from framework import io
    result = fw.load_result(os.path.join(folder, "r.h5"))
    if kind == "result":
        return fw.load_result, lambda loaded: loaded.configuration() == result.configuration() and same_records(
            loaded.records, result.records)
    configuration, records, state = io.read(os.path.join(folder, "c.h5"), name="resume")
    sim = simulation()

    def resume(path):
        resumed = sim.run(resume=path)   # the run is finished: nothing is solved
        return resumed, io.read(path, name="resume")

    def equal(loaded):
        resumed, (again, stored, kept) = loaded
        return same_records(resumed.records, result.records) and again == configuration \
            and same_records(stored, records) and list(kept) == list(state) \
            and all(same_arrays(kept[key], state[key]) for key in state)
    return resume, equal


def flip(original, target, offset, bit):
    data = bytearray(open(original, "rb").read())
    data[offset] ^= 1 << bit
    with open(target, "wb") as f:
        f.write(bytes(data))


def outcome(load, equal, target):
    """``"detected"``, ``"harmless"`` or the failure's description, for the file ``target``."""
    from framework import errors
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")    # a warning (format 1, ...) would be a failure
            loaded = load(target)
    except errors.FrameworkError as exc:
        message = str(exc)
        if isinstance(exc, errors.FileError) and "\n" not in message and repr(str(target)) in message:
            return "detected"
        return f"{type(exc).__name__}: {message}"
    except Exception as exc:  # noqa: BLE001 - a raw error is what the campaign looks for
        return f"{type(exc).__name__}: {exc}"
    return "harmless" if equal(loaded) else "loaded, and differs from the original"


def flip_in_child(original, kind, flips, timeout):
    """Flip each ``(offset, bit)`` of ``flips`` in turn in a copy of ``original`` (``r.h5`` or ``c.h5`` of its
    folder, loaded as ``kind``) and load it, in a child process.

    Returns ``(tried, detected, harmless, failures)``, ``failures`` a list of ``(offset, bit, what)``. A child
    still loading after ``timeout`` seconds is killed and reported as a failure ``(offset, bit, "hangs ...")`` of
    the flip it was loading; a child that dies is a failure too.
    """
    folder, name = os.path.split(os.path.abspath(original))
    target = os.path.join(folder, f"flipped-{uuid.uuid4().hex[:8]}-{name}")
    command = [sys.executable, os.path.abspath(__file__), os.fspath(original), kind, target]
    try:   # the flips on stdin: a full campaign's list is longer than a command line may be
        done = subprocess.run(command, input=json.dumps([list(pair) for pair in flips]), capture_output=True,
                              text=True, timeout=timeout)
        lines, error = done.stdout.splitlines(), (done.stderr.strip().splitlines() or [""])[-1]
    except subprocess.TimeoutExpired as exc:   # the child is killed
        output = exc.stdout.decode() if isinstance(exc.stdout, bytes) else exc.stdout or ""
        lines, error = output.splitlines(), None
    finally:
        if os.path.exists(target):
            os.remove(target)
    tried = detected = harmless = 0
    failures, loading = [], None
    for line in lines:
        if line.startswith("flip "):
            loading = tuple(int(v) for v in line.split()[1:])
            tried += 1
        elif line.startswith("outcome "):
            what = line[len("outcome "):]
            detected += what == "detected"
            harmless += what == "harmless"
            if what not in ("detected", "harmless"):
                failures.append((*loading, what))
            loading = None
    if loading is not None:
        why = f"hangs (still loading after the {timeout} s allowed)" if error is None else f"killed the child: {error}"
        failures.append((*loading, why))
    elif error is None or tried < len(flips):
        failures.append((None, None, f"the child stopped after {tried} of {len(flips)} flips: {error}"))
    return tried, detected, harmless, failures


def main(original, kind, target, flips):
    """The child of :func:`flip_in_child` (the flips as JSON on stdin): one ``flip OFFSET BIT`` line before each
    load, ``outcome ...`` after."""
    load, equal = loader(kind, os.path.dirname(original))
    for offset, bit in flips:
        flip(original, target, offset, bit)
        print(f"flip {offset} {bit}", flush=True)
        print(f"outcome {' '.join(outcome(load, equal, target).split())}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], [tuple(pair) for pair in json.load(sys.stdin)])
