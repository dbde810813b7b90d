"""Analytic and independent reference solutions, shared by tests and examples.

- :mod:`.hertz`: sphere and cylinder on a half-space (Hertz 1882).
- :mod:`.punch`: flat punch (Boussinesq) and rounded flat punch (Ciavarella 1999).
- :mod:`.westergaard`: periodic wavy surface (Westergaard 1939).
- :mod:`.boussinesq`: point-load fields and rectangle loads by quadrature.
"""
from .boussinesq import (point_load_displacement, point_load_stress, rectangle_displacement_by_quadrature,
                         rectangle_stress_by_quadrature)
from .hertz import HertzCylinder, HertzSphere
from .punch import FlatPunch, RoundedFlatPunch
from .westergaard import Westergaard

__all__ = ["FlatPunch", "HertzCylinder", "HertzSphere", "RoundedFlatPunch", "Westergaard",
           "point_load_displacement", "point_load_stress", "rectangle_displacement_by_quadrature",
           "rectangle_stress_by_quadrature"]
