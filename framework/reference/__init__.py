"""Analytic and independent reference solutions, shared by tests and examples.

- :mod:`.hertz`: sphere and cylinder on a half-space (Hertz 1882).
- :mod:`.punch`: flat punch (Boussinesq) and rounded flat punch (Ciavarella 1999).
- :mod:`.westergaard`: periodic wavy surface (Westergaard 1939).
- :mod:`.boussinesq`: point-load fields and rectangle loads by quadrature.
- :mod:`.plane_strain`: line load (Flamant), uniform strip and Hertz line
  contact (McEwen 1949) stresses, and line loads by quadrature.
- :mod:`.viscoelastic`: Lee & Radok (1960) step load, step and ramp approach;
  Ting (1966) / Graham (1967) receding contact (sphere, single maximum).
- :mod:`.rolling`: steady rolling / frictionless sliding of a rigid cylinder
  (plane strain, Hunter 1961) and sphere over a viscoelastic half-space,
  solved densely (filtered influence coefficients, exact active set).
- :mod:`.eshelby`: Eshelby tensor and interior field of an ellipsoidal inhomogeneity, Mindlin &
  Cheng (1950) centre of dilatation, dilute change of an indenter's approach.
- :mod:`.eigenstrain`: strain of a uniform eigenstrain in a cuboid in an infinite body (Kelvin) and
  a half-space (Mindlin 1936), and the half-space's surface displacement, by face quadrature.
- :mod:`.mori_tanaka`: Mori-Tanaka (Benveniste 1987) effective stiffness of a matrix with aligned,
  planar or randomly oriented spheroids; a viscoelastic matrix by the correspondence principle.
- :mod:`.layered`: an elastic layer (or a stack) bonded to a half-space (Chen & Engel 1972; O'Sullivan &
  King 1988): surface compliance and a rigid sphere's contact; :mod:`.layered_rolling`: steady rolling on
  viscoelastic layers.
"""
from .boussinesq import (point_load_displacement, point_load_stress, rectangle_displacement_by_quadrature,
                         rectangle_stress_by_quadrature)
from .hertz import HertzCylinder, HertzSphere
from .plane_strain import hertz_line_stress, line_load_stress, plane_strain_stress_by_quadrature, strip_stress
from .punch import FlatPunch, RoundedFlatPunch
from .rolling import (SteadyLineContact, SteadySphereContact, high_speed_sphere_friction, low_speed_friction_slope,
                      steady_line_contact, steady_sphere)
from .viscoelastic import (TingSolution, lee_radok_load_for_approach, lee_radok_ramp_load,
                           lee_radok_step_approach_load, lee_radok_step_load, lee_radok_step_load_pressure,
                           ting_contact_radius)
from .westergaard import Westergaard
from .eshelby import (InteriorSolution, dilatation_strength, dilatation_surface_displacement, dilute_approach_change,
                      eshelby_integrals, eshelby_tensor, hertz_axis_stress, hertz_axis_stress_rate, interior_solution,
                      isotropic_stiffness)
from .eigenstrain import (kelvin_cuboid_strain, kelvin_point_force_displacement, mindlin_cuboid_strain,
                          mindlin_cuboid_surface_displacement, mindlin_point_force_displacement)
from .mori_tanaka import (HomogenisedViscoelastic, mori_tanaka, mori_tanaka_fit, mori_tanaka_moduli,
                          mori_tanaka_stiffness)
from .layered import LayeredSphereContact, layered_compliance, layered_sphere_contact, stack_compliance
from .layered_rolling import LayeredSteadySphere, layered_steady_sphere

__all__ = ["FlatPunch", "HertzCylinder", "HertzSphere", "RoundedFlatPunch", "SteadyLineContact", "SteadySphereContact",
           "TingSolution", "Westergaard",
           "lee_radok_load_for_approach", "lee_radok_ramp_load", "lee_radok_step_approach_load", "lee_radok_step_load",
           "lee_radok_step_load_pressure", "ting_contact_radius",
           "point_load_displacement", "point_load_stress", "rectangle_displacement_by_quadrature",
           "rectangle_stress_by_quadrature", "hertz_line_stress", "line_load_stress",
           "plane_strain_stress_by_quadrature", "strip_stress", "steady_line_contact", "steady_sphere",
           "low_speed_friction_slope", "high_speed_sphere_friction",
           "InteriorSolution", "dilatation_strength", "dilatation_surface_displacement", "dilute_approach_change",
           "eshelby_integrals", "eshelby_tensor", "hertz_axis_stress", "hertz_axis_stress_rate", "interior_solution",
           "isotropic_stiffness",
           "kelvin_cuboid_strain", "kelvin_point_force_displacement", "mindlin_cuboid_strain",
           "mindlin_cuboid_surface_displacement", "mindlin_point_force_displacement",
           "HomogenisedViscoelastic", "mori_tanaka", "mori_tanaka_fit", "mori_tanaka_moduli", "mori_tanaka_stiffness",
           "LayeredSphereContact", "LayeredSteadySphere", "layered_compliance", "layered_sphere_contact",
           "layered_steady_sphere", "stack_compliance"]
