"""The measurements behind framework/resolution.py's thresholds, repeated (a few minutes on 2 cores).

1. ``wake``: a cylinder (R = 10 mm, W' = 100 N/m) rolling steadily over a standard linear solid (E(inf) = 10 MPa,
   E(0) = 2 or 10 E(inf), nu = 0.5) with cells of a/16, a/32, a/64 of the relaxed half-width a, at speeds whose
   wake ``V lambda`` spans 1/16 to 2 cells: the friction coefficient's error against 8 times finer cells, and that
   error per ``h / a`` (the model's ``F``) beside :func:`framework.resolution.layer_error`. ``--transient`` rolls
   from rest instead (one cell per step, 5 half-widths) against the same steady reference.
2. ``bodies``: deep spheres and a tilted ellipsoid (stiffness ratios 1/18 to 10) at 3, 4, 5, 6, 8 cuboids per
   smallest semi-axis: the error of the mean interior stress, of the stress at the centre and of the worst cuboid
   against Eshelby's uniform interior solution, and the staircase's volume over the ellipsoid's.

    .venv/bin/python bench/resolution.py wake [--transient]
    .venv/bin/python bench/resolution.py bodies [--geometry laminate]
"""
import argparse
import math
import warnings

import numpy as np

import framework as fw
from framework import inclusions, indenters, materials, resolution, schedules
from framework.errors import ResolutionWarning
from framework.operators.eigenstrain import COMPONENTS
from framework.reference import eshelby

RADIUS, LOAD = 10e-3, 100.0
OPTIONS = {"residual_tolerance": 1e-9, "tolerance": 1e-10}


def half_width(material):
    """Relaxed Hertz half-width [m] of the cylinder."""
    return math.sqrt(4 * LOAD * RADIUS * material.contact_compliance().relaxed / math.pi)


def steady(material, speed, h, a):
    n = int(round(3 * a / h))
    grid = fw.Grid(shape=(n, 4), size=(n * h, 4 * h), periodic=(False, True))
    schedule = schedules.Rolling(load=LOAD * grid.size[1], velocity=(speed, 0.0), steady=True)
    return fw.Simulation(grid=grid, material=material, indenter=indenters.Cylinder(radius=RADIUS, axis=1),
                         schedule=schedule, options=OPTIONS).run().friction_coefficient[0]


def transient(material, speed, h, a):
    wake = speed * material.contact_compliance().times[0]
    n = 2 * math.ceil((1.3 * a + 3.2 * wake) / h)
    grid = fw.Grid(shape=(n, 4), size=(n * h, 4 * h), periodic=(False, True))
    count = int(round(5 * max(wake, a) / h))
    schedule = schedules.Rolling(load=LOAD * grid.size[1], velocity=(speed, 0.0), distance=count * h,
                                 times=[count * h / speed])
    return fw.Simulation(grid=grid, material=material, indenter=indenters.Cylinder(radius=RADIUS, axis=1),
                         schedule=schedule, options=OPTIONS).run().friction_coefficient[-1]


def wake(moving):
    for ratio in (2.0, 10.0):
        material = materials.StandardLinearSolid(e_inf=1e7, e_1=(ratio - 1) * 1e7, tau=1.0, poisson=0.5)
        lam, a = material.contact_compliance().times[0], half_width(material)
        for per in (16, 32, 64):
            h = a / per
            for cells in (1 / 16, 1 / 8, 1 / 4, 1 / 2, 1, 2):
                speed = cells * h / lam
                mu = (transient if moving else steady)(material, speed, h, a)
                error = mu / steady(material, speed, h / 8, a) - 1
                print(f"E(0)/E(inf) = {ratio:4g}  h = a/{per:<3d} V lambda/h = {cells:6.4g}  V tau/h = "
                      f"{cells / lam:6.3g}  error {error:+.2e}  F = {abs(error) * per:.3f}  "
                      f"model {resolution.layer_error(cells):.3f}", flush=True)


E, NU = 200e9, 0.3
TILT = inclusions.axis_angle_orientation((0, 1, 0), np.radians(30))
BODIES = {
    "sphere, ratio 3": ((1, 1, 1), materials.Elastic(3 * E, NU), None),
    "sphere, ratio 10": ((1, 1, 1), materials.Elastic(10 * E, NU), None),
    "sphere, ratio 1/3": ((1, 1, 1), materials.Elastic(E / 3, 0.25), None),
    "ellipsoid, ratio 1/18": ((1, 0.8, 0.6), materials.Elastic(E / 18, NU), TILT),
    "ellipsoid, ratio 2": ((1, 0.7, 0.45), materials.Elastic(2 * E, 0.2), TILT),
}


def body_errors(semi_axes, material, orientation, cells, geometry):
    """A body of largest semi-axis 1 mm, 6 mm deep, ``cells`` cuboids along its smallest semi-axis."""
    a, depth = 1e-3, 6e-3
    h = a * min(semi_axes) / cells
    n = int(np.ceil(4 * a / h / 2)) * 2
    layers = int(round((depth + 1.5 * a) / h))
    grid = fw.Grid(shape=(n, n), size=(n * h, n * h), depth=layers * h, layers=layers)
    body = inclusions.Ellipsoid(center=(0.0, 0.0, depth), semi_axes=tuple(s * a for s in semi_axes),
                                material=material, orientation=orientation)
    applied = np.array([[1e-3, 0.4e-3, -0.2e-3], [0.4e-3, -0.5e-3, 0.3e-3], [-0.2e-3, 0.3e-3, 0.8e-3]])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResolutionWarning)
        solution = fw.solve_inclusions(grid, materials.Elastic(E, NU), [body], applied, geometry=geometry)
    expected = eshelby.interior_solution(body.semi_axes, body.orientation, E, NU, body.stiffness_tensor,
                                         applied).stress
    expected = np.array([expected[i, j] for i, j in COMPONENTS])
    inside = solution.inhomogeneity[solution.box] > 0
    stresses, scale = solution.stress[inside], np.abs(expected).max()
    centre = solution.stress_at(np.array([[0.0, 0.0, depth + 1e-9]]))[0]
    return (np.abs(stresses.mean(axis=0) - expected).max() / scale, np.abs(centre - expected).max() / scale,
            np.abs(stresses - expected).max() / scale,
            inside.sum() * h**3 / (4 / 3 * np.pi * np.prod(semi_axes) * a**3))


def bodies(geometry):
    for name, (semi_axes, material, orientation) in BODIES.items():
        for cells in (3, 4, 5, 6, 8):
            mean, centre, worst, volume = body_errors(semi_axes, material, orientation, cells, geometry)
            print(f"{name:22s} {cells} cuboids per semi-axis: mean {mean:.4f}  centre {centre:.4f}  worst cuboid "
                  f"{worst:.3f}  volume {volume:.3f}", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("study", choices=("wake", "bodies"))
    parser.add_argument("--transient", action="store_true", help="wake: roll from rest instead of steadily")
    parser.add_argument("--geometry", default="staircase", help="bodies: staircase (default) or laminate")
    args = parser.parse_args()
    warnings.simplefilter("ignore", ResolutionWarning)   # the coarse runs are coarse on purpose
    if args.study == "wake":
        wake(args.transient)
    else:
        bodies(args.geometry)


if __name__ == "__main__":
    main()
