"""Fixtures shared by the test modules."""
import os
import tempfile

import pytest


@pytest.fixture
def unwritable_folder(tmp_path):
    """A folder that exists and in which this process cannot create files.

    ``chmod 555`` for a user; root ignores permissions, so for root a sysfs
    folder, where not even root can create a file (the kernel refuses it).
    """
    if os.geteuid() != 0:
        folder = tmp_path / "read-only"
        folder.mkdir()
        folder.chmod(0o555)
        yield str(folder)
        folder.chmod(0o755)
        return
    folder = "/sys/kernel"
    try:
        with tempfile.TemporaryFile(dir=folder):
            writable = True
    except OSError:
        writable = False
    if not os.path.isdir(folder) or writable:
        pytest.skip(f"running as root and {folder} is not an existing folder closed to new files")
    yield folder


@pytest.fixture
def flip_byte():
    """``flip_byte(path, dataset, step=0)``: damage one byte of a dataset's stored data in an HDF5 file."""
    h5py = pytest.importorskip("h5py")

    def flip_byte(path, dataset, step=0):
        """Invert the middle byte of a dataset's raw (filtered) data: of the chunk holding ``step``, or of the whole."""
        with h5py.File(path, "r") as f:
            stored, chunks = f[dataset].id, f[dataset].chunks
            if chunks:
                corner = (step // chunks[0] * chunks[0],) + (0,) * (len(chunks) - 1)
                info = stored.get_chunk_info_by_coord(corner)
                offset, size = info.byte_offset, info.size
            else:
                offset, size = stored.get_offset(), stored.get_storage_size()
        with open(path, "r+b") as f:
            f.seek(offset + size // 2)
            byte = f.read(1)
            f.seek(offset + size // 2)
            f.write(bytes([byte[0] ^ 0xFF]))

    return flip_byte


@pytest.fixture
def stop_after():
    """``stop_after(simulation, index, checkpoint)``: run with a checkpoint every step, killed after step ``index``."""
    class Stop(Exception):
        pass

    def run(simulation, index, checkpoint):
        def stop(result, record):
            if record.index == index:
                raise Stop

        with pytest.raises(Stop):
            simulation.run(checkpoint=checkpoint, every=1, callback=stop)
    return run

