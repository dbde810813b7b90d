"""Rounded flat punch on an elastic half-space against Ciavarella (1999).

For flat radius b = 0.2, 0.5 and 0.8 of the contact radius a (edge radius
a - b, as in seed 001), loads the punch with Ciavarella's load for that a and
compares contact radius and approach; writes ``rounded_punch_elastic.csv``.

    python examples/rounded_punch_elastic.py [--cells 121] [--out out/examples]
"""
import argparse
import csv
import os

import framework as fw
from framework import indenters, materials, reference, schedules


def main(cells=121, out="out/examples"):
    os.makedirs(out, exist_ok=True)
    pmma_glassy = materials.Elastic(young=2.49e9, poisson=0.35)
    a = 1e-3
    rows = []
    for ratio in (0.2, 0.5, 0.8):
        b, rc = ratio * a, (1 - ratio) * a
        exact = reference.RoundedFlatPunch(flat_radius=b, edge_radius=rc,
                                           contact_modulus=pmma_glassy.contact_modulus)
        load = exact.load(a)
        grid = fw.Grid(shape=(cells, cells), size=(3 * a, 3 * a))
        result = fw.Simulation(grid=grid, material=pmma_glassy,
                               indenter=indenters.RoundedFlatPunch(flat_radius=b, edge_radius=rc),
                               schedule=schedules.Static(load=load)).run()
        rows.append({"flat_ratio": ratio, "load_N": load, "contact_radius_m": result.contact_radius[0],
                     "approach_m": result.approach[0], "ciavarella_approach_m": exact.approach(a),
                     "max_pressure_Pa": result.max_pressure[0]})
        print(f"b/a = {ratio}: W = {load:.1f} N, a error {result.contact_radius[0] / a - 1:+.2e}, "
              f"approach error {result.approach[0] / exact.approach(a) - 1:+.2e}")
    path = os.path.join(out, "rounded_punch_elastic.csv")
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("wrote", path)
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=121)
    parser.add_argument("--out", default="out/examples")
    main(**vars(parser.parse_args()))
