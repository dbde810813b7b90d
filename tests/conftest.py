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
