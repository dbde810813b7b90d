"""The filled cell's inverse on a stiff body, measured against its continuum estimate, and what solving the cell's
system on the body leaves (``bench/preconditioner_spectrum.py``; README, "Where the products go").

On a field confined to a sphere, the box filled with the body's material applies the direction average of
the inverse plane-wave operator, where Eshelby's solution needs the inverse of the average: the
preconditioned operator's uniform modes have eigenvalues ``[(C_I - C_M) S + C_M] <F(n)^-1>``, 6.0
(dilatation) and 8.5 (shear) for glass in a polymer of 2.25 GPa. These tests check the estimate's pieces
against Eshelby's closed forms and the operator's largest eigenvalue against the estimate.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "bench"))

import preconditioner_spectrum as spectrum  # noqa: E402
import framework as fw  # noqa: E402
from framework import inclusions  # noqa: E402
from framework.inclusions import equivalent  # noqa: E402
from framework.inclusions.equivalent import MANDEL  # noqa: E402
from framework.inclusions.field import InclusionProblem  # noqa: E402


def test_the_direction_average_of_plane_waves_is_eshelbys_sphere_and_one_material_is_exact():
    """``equivalent.filled_cell_estimate``: the average of the plane-wave strains over 2,000 directions is
    Eshelby's sphere tensor (S1111 = (7 - 5 nu) / (15 (1 - nu)), S2323 = (4 - 5 nu) / (15 (1 - nu)),
    S1122 = (5 nu - 1) / (15 (1 - nu))) to 1e-3; a body of the matrix's material gives the identity; glass in
    the polymer 6.0 and 8.5."""
    young, nu = spectrum.MATRIX.young, spectrum.MATRIX.poisson
    glass = equivalent.isotropic_mandel(spectrum.GLASS.young, spectrum.GLASS.poisson)
    estimate, eshelby = equivalent.filled_cell_estimate(glass, young, nu, directions=2000)
    d = 15 * (1 - nu)
    assert abs(eshelby[0, 0] - (7 - 5 * nu) / d) <= 1e-3
    assert abs(eshelby[0, 1] - (5 * nu - 1) / d) <= 1e-3
    assert abs(eshelby[3, 3] - 2 * (4 - 5 * nu) / d) <= 1e-3      # Mandel: 2 S2323
    same = equivalent.filled_cell_estimate(equivalent.isotropic_mandel(young, nu), young, nu, directions=200)[0]
    assert np.abs(same - 1.0).max() <= 1e-12
    assert 5.5 <= estimate[0] <= 6.5 and 8.0 <= estimate[-1] <= 9.0


def test_a_stiff_spheres_largest_preconditioned_eigenvalue_is_the_uniform_modes_estimate(monkeypatch):
    """Glass (contrast 31) sphere 12 cuboids across, deep: with the filled cell's inverse alone as M, on the cell's
    symbol as the box's kernels give it (``equivalent.CLIP_SYMBOL`` off), the largest eigenvalue of A M is within
    10 % of the continuum shear estimate (measured 8.06 against 8.52) and its eigenvector is smooth (99 % in quadratic
    polynomials of position over the body); on the clipped symbol (the default) it is lower (7.28). With the cell's
    system solved on the body (the default preconditioner, here to 1e-10: a linear map), what is left, the
    half-space's mirror and surface terms and the cell's images, puts the largest at 1.20."""
    from scipy.sparse.linalg import LinearOperator, eigs
    cell = 25e-6
    grid = fw.Grid(shape=(32, 32), size=(32 * cell, 32 * cell), depth=36 * cell, layers=36)
    body = inclusions.Ellipsoid(center=(0.0, 0.0, 24 * cell), semi_axes=(6 * cell,) * 3, material=spectrum.GLASS)
    shear = equivalent.filled_cell_estimate(equivalent.isotropic_mandel(spectrum.GLASS.young, spectrum.GLASS.poisson),
                                            spectrum.MATRIX.young, spectrum.MATRIX.poisson)[0][-1]
    tops = {}
    for clip in (False, True):
        monkeypatch.setattr(equivalent, "CLIP_SYMBOL", clip)
        inner = InclusionProblem(grid, spectrum.MATRIX, inclusions.InclusionSet([body]), recycle=False).problem
        assert inner.preconditioner == "fourier"

        def preconditioned(vector, solved=False):
            values = np.real(vector).reshape(-1, 6)
            z = inner._inner_solve(values) if solved else inner._filled(values)
            return inner._image(z, inner.operator.strain(inner.box_field(z.reshape(-1, 6)))[inner.cells] * MANDEL)

        inner._local_solve(np.zeros(inner.size))        # the preconditioner built
        operator = LinearOperator((inner.size, inner.size), matvec=preconditioned, dtype=float)
        values, vectors = eigs(operator, k=2, which="LM", tol=1e-4, v0=np.ones(inner.size))
        top = int(np.argmax(np.abs(values)))
        assert abs(values[top].imag) <= 1e-6 * abs(values[top].real)
        tops[clip] = values[top].real
        if not clip:
            assert abs(values[top].real - shear) <= 0.1 * shear
    assert 0.8 * shear <= tops[True] <= tops[False]
    cells = np.array(inner.cells, dtype=float).T
    x = (cells - cells.mean(0)) / 6.0
    powers = [(a, b, c) for a in range(3) for b in range(3 - a) for c in range(3 - a - b)]
    basis = np.linalg.qr(np.array([x[:, 0] ** a * x[:, 1] ** b * x[:, 2] ** c for a, b, c in powers]).T)[0]
    mode = np.real(vectors[:, top]).reshape(-1, 6)
    assert ((basis.T @ mode) ** 2).sum() >= 0.95 * (mode ** 2).sum()
    monkeypatch.setattr(equivalent, "INNER_TOLERANCE", 1e-10)
    solved = LinearOperator((inner.size, inner.size), matvec=lambda v: preconditioned(v, True), dtype=float)
    largest = np.abs(eigs(solved, k=2, which="LM", tol=1e-4, v0=np.ones(inner.size), return_eigenvectors=False))
    assert 1.0 <= largest.max() <= 1.3
