"""Optional packages: the extra that installs each, and which of them a scenario run needs.

The core needs numpy and scipy. Writing files and pictures needs optional
packages, installed by the extras of ``pyproject.toml``; ``check`` finds the
missing ones before ``run`` would fail on them, and names the command that
installs them. Packages are looked up (:func:`importlib.util.find_spec`),
not imported: the check is quick and starts nothing (VTK's rendering).
"""
import importlib.util

from .errors import FrameworkError

#: The extra of ``pyproject.toml`` that installs each optional package (by its import name).
EXTRAS = {"h5py": "io", "vtkmodules": "viz", "pyvista": "viz", "matplotlib": "viz", "PIL": "viz",
          "dask": "cluster", "distributed": "cluster"}
#: The names the package indexes know them by, where they differ from the import name.
DISTRIBUTIONS = {"vtkmodules": "vtk", "PIL": "pillow"}


class MissingExtraError(FrameworkError, ImportError):
    """An optional dependency of this feature is not installed: the message names the extra."""


def installed(package):
    """Whether the top-level package ``package`` can be imported (without importing it)."""
    try:
        return importlib.util.find_spec(package) is not None
    except (ImportError, ValueError):  # a parent that fails to import, a module whose __spec__ is None
        return False


def install_command(extras):
    """``pip install 'viscocontact[io,viz]'`` for the extras ``extras``."""
    return f"pip install 'viscocontact[{','.join(sorted(set(extras)))}]'"


def scenario_needs(output, *, layers=0, animate=None):
    """``{what: packages}``: the optional packages each file of a scenario run needs.

    Parameters
    ----------
    output : framework.scenario.Output
        The scenario's ``[output]``.
    layers : int
        The grid's layers (volumes are written only with layers).
    animate : str, optional
        The field of ``--animate``.
    """
    needs = {"result.h5": ("h5py",)}
    if output.vtu:
        needs["VTU files"] = ("vtkmodules", "pyvista")
    if output.pictures:
        needs["pictures"] = ("vtkmodules", "pyvista")
    if output.history:
        needs["history.png"] = ("matplotlib",)
    if animate:
        needs["--animate"] = ("vtkmodules", "pyvista", "PIL")
    return needs


def require(needs, *, what):
    """Raise one :class:`MissingExtraError` line naming every missing package, what needs it, and the command.

    Parameters
    ----------
    needs : dict
        ``{what needs them: packages}`` (:func:`scenario_needs`).
    what : str
        Who needs them, the start of the message (``"examples/hertz.toml: run"``).
    """
    users = {}
    for purpose, packages in needs.items():
        for package in packages:
            if not installed(package):
                users.setdefault(package, []).append(purpose)
    if users:
        listed = "; ".join(f"{DISTRIBUTIONS.get(package, package)} (for {', '.join(purposes)})"
                           for package, purposes in users.items())
        raise MissingExtraError(f"{what} needs packages that are not installed: {listed}; install them with: "
                                f"{install_command(EXTRAS[package] for package in users)}")
