"""Why a stiff body's equivalent-inclusion solve needed many products with the filled cell's inverse alone as its
preconditioner, and what solving that cell's system on the body does: the spectra of the preconditioned
operators, the shape of their largest modes, and a continuum estimate of them.

The body of ``bench/rolling_inclusion.py`` (a glass sphere 20 cuboids across, E = 70 GPa, nu = 0.22) in a
matrix of that bench's effective modulus (E = 2.25 GPa, nu = 0.35), its default box (margin half a semi-axis),
deep in the half-space. Prints, on this machine:

1. GMRES iterations to 1e-4, 1e-7 and 1e-10 under a uniform strain (no recycled directions), with the filled
   periodic cell's inverse ``F^-1`` alone and with the cell's system on the body ``P F P x = v`` solved
   (:meth:`~framework.inclusions.equivalent.EquivalentInclusionProblem._inner_solve`, the default);
2. the largest eigenvalues of ``A M`` (``A`` the equivalent-inclusion operator, ``M = F^-1``; ARPACK,
   ``--modes`` of them) and, for each of their eigenvectors, the share of it that polynomials of the position
   over the body of degree 0 to 3 hold (a smooth mode: most of it); then those of ``A (P F P)^-1`` (the cell's
   system solved to 1e-10): what is left is the half-space's mirror and surface terms and the cell's images;
3. the continuum estimate for the body's uniform modes: on a field confined to a sphere the box filled with
   the body's material applies ``<F(n)^-1>``, the average over directions ``n`` of the inverse plane-wave
   operator ``F(n) = (C_I - C_M) D(n) + C_M``, where the sphere needs ``[(C_I - C_M) S + C_M]^-1``
   (Eshelby: ``S = <D(n)>``). ``D(n) = sym(n (x) N(n) C_M e* n)`` with ``N = (n . C_M . n)^-1`` is the strain
   of a plane-wave eigenstrain along ``n`` (Mura 1987, sec. 3). The eigenvalues of
   ``[(C_I - C_M) S + C_M] <F(n)^-1>`` (dilatation, shear) at several contrasts: GMRES needs about the
   square root of the largest times the digits it gains.

    OMP_NUM_THREADS=1 .venv/bin/python bench/preconditioner_spectrum.py [--modes 8] [--cells 20]
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import framework as fw  # noqa: E402
from framework import inclusions, materials  # noqa: E402
from framework.inclusions import equivalent  # noqa: E402
from framework.inclusions.equivalent import MANDEL, isotropic_mandel  # noqa: E402
from framework.inclusions.field import InclusionProblem, strain_vector  # noqa: E402
from elastic_hertz import machine  # noqa: E402

MATRIX = materials.Elastic(2.25e9, 0.35)
GLASS = materials.Elastic(70e9, 0.22)


def uniform_mode_estimate(contrasts, directions=4000, poisson=GLASS.poisson):
    """Eshelby's tensor ``S`` (Mandel) from the directions, and ``{contrast: sorted eigenvalues}`` of
    ``[(C_I - C_M) S + C_M] <F(n)^-1>`` (:func:`framework.inclusions.equivalent.filled_cell_estimate`) for a
    body of Poisson ratio ``poisson`` (the glass's) and Young's modulus ``contrast`` times the matrix's."""
    out = {}
    for contrast in contrasts:
        out[contrast], eshelby = equivalent.filled_cell_estimate(
            isotropic_mandel(contrast * MATRIX.young, poisson), MATRIX.young, MATRIX.poisson, directions)
    return eshelby, out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--modes", type=int, default=8, help="largest eigenvalues computed")
    parser.add_argument("--cells", type=int, default=20, help="cuboids across the sphere")
    args = parser.parse_args()
    print(machine())
    cell, radius = 25e-6, args.cells / 2
    layers = int(3 * args.cells)
    grid = fw.Grid(shape=(64, 64), size=(64 * cell, 64 * cell), depth=layers * cell, layers=layers)
    body = inclusions.Ellipsoid(center=(0.0, 0.0, 2 * args.cells * cell), semi_axes=(radius * cell,) * 3,
                                material=GLASS)
    inner = InclusionProblem(grid, MATRIX, inclusions.InclusionSet([body]), recycle=False).problem
    print(f"glass sphere {args.cells} cuboids across in E = {MATRIX.young / 1e9:g} GPa (contrast "
          f"{GLASS.young / MATRIX.young:.1f}), box {inner.operator.shape}, {inner.material.size} cuboids inside, "
          f"preconditioner {inner.preconditioner} on the {inner._lattice} lattice")
    for solved in (False, True):
        inner.inner = solved
        counts = [inner.solve(strain_vector(np.diag([1e-3, 0.0, 0.0]), name="a"), tolerance=t).iterations
                  for t in (1e-4, 1e-7, 1e-10)]
        how = "the filled cell's system solved on the body (the default)" if solved else \
            "the filled cell's inverse alone"
        print(f"1. GMRES iterations to 1e-4 / 1e-7 / 1e-10, {how}: {counts[0]} / {counts[1]} / {counts[2]}")

    from scipy.sparse.linalg import LinearOperator, eigs

    def preconditioned(vector, solved=False):
        values = np.real(vector).reshape(-1, 6)
        z = inner._inner_solve(values) if solved else inner._filled(values)
        return inner._image(z, inner.operator.strain(inner.box_field(z.reshape(-1, 6)))[inner.cells] * MANDEL)

    begin = time.perf_counter()
    values, vectors = eigs(LinearOperator((inner.size, inner.size), matvec=preconditioned, dtype=float),
                           k=args.modes, which="LM", tol=1e-4)
    order = np.argsort(-np.abs(values))
    cells = np.array(inner.cells, dtype=float).T
    x = (cells - cells.mean(0)) / radius
    bases = []
    for degree in range(4):
        powers = [(a, b, c) for a in range(degree + 1) for b in range(degree + 1 - a)
                  for c in range(degree + 1 - a - b)]
        bases.append(np.linalg.qr(np.array([x[:, 0] ** a * x[:, 1] ** b * x[:, 2] ** c for a, b, c in powers]).T)[0])
    print(f"2. largest eigenvalues of A M, M the filled cell's inverse ({time.perf_counter() - begin:.0f} s), and their "
          f"eigenvectors' share in polynomials of degree 0 / 1 / 2 / 3 over the body:")
    for k in order:
        mode = np.real(vectors[:, k]).reshape(-1, 6)
        shares = [float(((basis.T @ mode) ** 2).sum() / (mode ** 2).sum()) for basis in bases]
        print(f"   {values[k].real:6.2f}   " + " / ".join(f"{s:.3f}" for s in shares))
    tolerance, equivalent.INNER_TOLERANCE = equivalent.INNER_TOLERANCE, 1e-10     # the cell's system solved exactly
    solved = eigs(LinearOperator((inner.size, inner.size), matvec=lambda v: preconditioned(v, True), dtype=float),
                  k=args.modes, which="LM", tol=1e-4, return_eigenvectors=False)
    equivalent.INNER_TOLERANCE = tolerance
    print("   with the filled cell's system solved on the body: " + " ".join(f"{v.real:.3f}" for v in
                                                                        sorted(solved, key=lambda v: -abs(v))))
    eshelby, estimates = uniform_mode_estimate([3.0, 10.0, GLASS.young / MATRIX.young, 100.0, 266.0])
    print(f"3. continuum estimate for the uniform modes (Eshelby's S1111 from the directions: {eshelby[0, 0]:.4f}, "
          f"exact {(7 - 5 * MATRIX.poisson) / (15 * (1 - MATRIX.poisson)):.4f}):")
    for contrast, eigenvalues in estimates.items():
        print(f"   contrast {contrast:6.1f}: dilatation {eigenvalues[0]:.2f}, shear {eigenvalues[-1]:.2f}")


if __name__ == "__main__":
    main()
