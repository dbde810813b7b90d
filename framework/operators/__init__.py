"""Half-space operators: each builds its kernel spectrum once and exposes ``apply``."""
from .convolution import Convolution
from .stress import SubsurfaceStress
from .stiffness import SurfaceStiffness
from .surface import SurfaceCompliance

__all__ = ["Convolution", "SubsurfaceStress", "SurfaceCompliance", "SurfaceStiffness"]
