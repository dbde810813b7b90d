"""Optional dependencies of :mod:`viz`, imported when first needed.

The core package never imports :mod:`viz`; this package imports vtk, pyvista,
meshio, matplotlib, Pillow and imageio only inside the functions that use them, so that
``import viz`` works without the ``viz`` extra and a missing package is
reported with the command that installs it.
"""
import importlib
import os
import sys

INSTALL = "pip install 'viscocontact[viz]'"


def require(module):
    """Import ``module`` or raise an ImportError that names the ``viz`` extra.

    Parameters
    ----------
    module : str
        Dotted module name, e.g. ``"pyvista"`` or ``"matplotlib.figure"``.

    Returns
    -------
    module
        The imported module.
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".")[0]
        raise ImportError(f"viz needs the optional package {top!r} ({exc}); install the visualisation extra with: "
                          f"{INSTALL}") from exc


def headless():
    """True on Linux without an X11 or Wayland display (a batch node, a container, CI)."""
    return sys.platform.startswith("linux") and not os.environ.get("DISPLAY") \
        and not os.environ.get("WAYLAND_DISPLAY")


def prepare_vtk():
    """Choose the off-screen EGL render window when there is no display; call before importing vtk.

    Only sets ``VTK_DEFAULT_OPENGL_WINDOW`` when it is unset, so a user's choice
    (e.g. ``vtkOSOpenGLRenderWindow`` for OSMesa) wins.
    """
    if headless():
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def pyvista(rendering=False):
    """The ``pyvista`` module.

    Parameters
    ----------
    rendering : bool
        True when the caller renders: without a display, ``pyvista.OFF_SCREEN``
        is then set too (plotters made by :mod:`viz` are off screen anyway).
    """
    prepare_vtk()
    pv = require("pyvista")
    if rendering and headless():
        pv.OFF_SCREEN = True
    return pv
