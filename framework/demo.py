"""The default scenario (``framework/scenarios/demo.toml``) as a simulation object."""
from .scenario import demo_path, read


def build(cells=None):
    """The demo :class:`Simulation`, optionally on a ``cells x cells`` grid of the same size."""
    return read(demo_path(), cells=cells).simulation
