"""Ellipsoidal elastic inhomogeneities in the half-space (THEORY.md sec. 8: equivalent inclusion method).

:class:`Ellipsoid` (centre, semi-axes, elastic or anisotropic material, orientation),
:class:`InclusionSet` (any number of them, refused when they overlap), the orientation helpers
:func:`euler_orientation` and :func:`axis_angle_orientation`, and the Perram-Wertheim
:func:`contact_function` behind the overlap test; :func:`solve_inclusions` on the box around the bodies and
:func:`solve_on_bodies` on their cuboids alone (the particle mesh).
"""
from .bodies import (MIN_CELLS_PER_SEMI_AXIS, Ellipsoid, InclusionSet, axis_angle_orientation, contact_function,
                     euler_orientation)
from .dispersed import solve_on_bodies
from .dispersion import random_dispersion
from .field import InclusionSolution, solve_inclusions

__all__ = ["MIN_CELLS_PER_SEMI_AXIS", "Ellipsoid", "InclusionSet", "axis_angle_orientation", "contact_function",
           "euler_orientation", "InclusionSolution", "solve_inclusions", "random_dispersion",
           "solve_on_bodies"]
