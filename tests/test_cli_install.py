"""The wheel holds what an installed package needs; `make test` installs it and runs it (.ci/wheel).

Building and installing the wheel takes 15-20 s and the package registry
(setuptools, cached by pip): CI does it once per `make test`, in `.ci/wheel`.
These tests guard, in a second, what that step relies on.
"""
import fnmatch
import os
import re
import subprocess
import tomllib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PACKAGES = ("framework", "viz")


def pyproject():
    with open(os.path.join(ROOT, "pyproject.toml"), "rb") as f:
        return tomllib.load(f)


def files_of(package):
    """Files of a package folder, relative to the repository, without caches."""
    out = []
    for folder, folders, names in os.walk(os.path.join(ROOT, package)):
        folders[:] = [name for name in folders if name != "__pycache__"]
        out += [os.path.relpath(os.path.join(folder, name), ROOT) for name in names if not name.endswith(".pyc")]
    return out


def test_every_data_file_of_the_packages_is_package_data():
    """A data file not declared is left out of the wheel: the demo failed with "no such scenario file"."""
    data = pyproject()["tool"]["setuptools"]["package-data"]
    for package in PACKAGES:
        for path in files_of(package):
            if path.endswith(".py"):
                continue
            inside = os.path.relpath(path, package)
            assert any(fnmatch.fnmatch(inside, pattern) for pattern in data.get(package, [])), \
                f"{path} is not package data of {package} in pyproject.toml: the wheel would leave it out"
    assert "scenarios/*.toml" in data["framework"]


def test_every_folder_of_python_files_is_a_package():
    """setuptools finds packages by their __init__.py: a folder without one is left out of the wheel."""
    include = pyproject()["tool"]["setuptools"]["packages"]["find"]["include"]
    assert set(include) == {f"{package}*" for package in PACKAGES}
    for package in PACKAGES:
        for folder, folders, names in os.walk(os.path.join(ROOT, package)):
            folders[:] = [name for name in folders if name != "__pycache__"]
            if any(name.endswith(".py") for name in names):
                assert "__init__.py" in names, f"{os.path.relpath(folder, ROOT)} has no __init__.py"


def test_make_test_installs_the_wheel_and_runs_it_elsewhere():
    with open(os.path.join(ROOT, "Makefile")) as f:
        makefile = f.read()
    test = re.search(r"^test: .*\n((?:\t.*\n)+)", makefile, re.M).group(1)
    assert "test-wheel" in test
    assert re.search(r"^test-wheel: .*\n\t.*\.ci/wheel", makefile, re.M)
    script = os.path.join(ROOT, ".ci", "wheel")
    assert os.access(script, os.X_OK)
    with open(script) as f:
        text = f.read()
    for step in ("pip wheel", "venv", "install --quiet --no-deps --no-index", "-m framework demo",
                 "viscocontact\" run hertz.toml", "sweep sweep_sphere.toml --check", 'cd "$RUN"'):
        assert step in text, step
    assert subprocess.run(["bash", "-n", script]).returncode == 0  # it parses
