"""Adapter that drives Tamaas (PyPI ``tamaas`` 2.9.0) for our benchmarks.

Two entry points:

* :func:`hertz` -- normal frictionless contact of a rigid paraboloid on an
  elastic half-space, ``tamaas.PolonskyKeerRey`` solver, non-periodic
  (DC-FFT) integral operator by default.
* :func:`maxwell_creep` -- step-load creep of a rigid sphere (paraboloid) on a
  generalized-Maxwell viscoelastic half-space, ``tamaas.MaxwellViscoelastic``
  solver, non-periodic (DC-FFT) operator by default.

``tamaas`` is imported inside the functions only, so this module imports
without Tamaas installed.  See ``bench/TAMAAS_NOTES.md`` for the conventions
and the accuracy figures.

Our conventions (both functions)
--------------------------------
* Grid: ``n x n`` cells covering ``[-size/2, size/2]^2``, cell centres
  ``x1 = -size/2 + (i1 + 0.5) * size / n`` (numpy index ``[i1, i2]``).
* Rigid indenter ``h = r^2 / (2 radius)`` pressed onto the half-space with a
  total force ``load`` (N).  Pressures in Pa, positive in compression.
* Displacement: normal surface displacement of the half-space, positive in
  the direction of the indenter motion (into the half-space), so that in the
  contact zone ``u = approach - r^2 / (2 radius)``.
* ``approach``: rigid-body penetration of the paraboloid apex.

Internally the problem is made dimensionless (length unit ``size``; pressure
unit ``E*`` for :func:`hertz` and ``G_inf = e_inf / (2 (1 + nu))`` for
:func:`maxwell_creep` -- the latter is REQUIRED, see the notes: Tamaas 2.9's
``MaxwellViscoelastic`` only integrates the generalized Maxwell law correctly
when the model's shear modulus equals 1).
"""

from __future__ import annotations

import contextlib
import os
import re
import sys
import tempfile
import time as _time

import numpy as np

__all__ = [
    "hertz",
    "maxwell_creep",
    "hertz_reference",
    "creep_compliance",
    "lee_radok_radius",
]

_METHODS = ("dcfft", "periodic_padded", "periodic")


# --------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------
def _centres(n, length):
    """Cell-centre coordinates of ``n`` cells covering [-length/2, length/2]."""
    return -0.5 * length + (np.arange(n) + 0.5) * (length / n)


def _paraboloid(n, length, radius):
    """Tamaas surface (indenter heights, apex at 0, negative elsewhere)."""
    x = _centres(n, length)
    x1, x2 = np.meshgrid(x, x, indexing="ij")
    return -(x1 ** 2 + x2 ** 2) / (2.0 * radius)


@contextlib.contextmanager
def _capture_stderr_fd():
    """Capture what C++ writes on file descriptor 2 (Tamaas' Logger).

    Yields a list that receives the captured text on exit.
    """
    out = []
    sys.stderr.flush()
    saved = os.dup(2)
    with tempfile.TemporaryFile(mode="w+b") as tmp:
        os.dup2(tmp.fileno(), 2)
        try:
            yield out
        finally:
            sys.stderr.flush()
            os.dup2(saved, 2)
            os.close(saved)
            tmp.seek(0)
            out.append(tmp.read().decode(errors="replace"))


_ITER_LINE = re.compile(r"^\s*(\d+)\s+\S+\s+\S+\s*$")


def _parse_iterations(text):
    """Last iteration index printed by Tamaas' solver log (None if absent)."""
    last = None
    for line in text.splitlines():
        m = _ITER_LINE.match(line)
        if m:
            last = int(m.group(1))
    return last


def _timed_solve(tm, solver, target, count_iterations):
    """Run ``solver.solve(target)``; return (seconds, error, iterations).

    Only the ``solve`` call is inside the timing window.  When
    ``count_iterations`` is true, Tamaas' log level is raised to ``info`` so
    that the solver prints its iteration table on stderr (a handful of lines:
    iteration 0, every ``dump_freq`` iterations and the last one), which is
    captured at the file-descriptor level and parsed.
    """
    if not count_iterations:
        t0 = _time.perf_counter()
        err = solver.solve(target)
        return _time.perf_counter() - t0, err, None
    with _capture_stderr_fd() as captured:
        t0 = _time.perf_counter()
        err = solver.solve(target)
        dt = _time.perf_counter() - t0
    text = captured[0] if captured else ""
    return dt, err, _parse_iterations(text)


@contextlib.contextmanager
def _log_level(tm, level):
    old = tm.get_log_level()
    tm.set_log_level(level)
    try:
        yield
    finally:
        tm.set_log_level(old)


def _pad_for(method, n):
    if method not in _METHODS:
        raise ValueError(f"method must be one of {_METHODS}, got {method!r}")
    return n // 2 if method == "periodic_padded" else 0


# --------------------------------------------------------------------------
# 1. elastic Hertz contact
# --------------------------------------------------------------------------
def hertz(n, size, radius, load, young, poisson, tolerance, *,
          method="dcfft", max_iter=10000, count_iterations=True):
    """Frictionless normal contact of a rigid paraboloid on an elastic half-space.

    Tamaas calls (dimensionless: length unit ``size``, pressure unit E*)::

        model = tm.ModelFactory.createModel(tm.model_type.basic_2d,
                                            [Lx, Ly], [Nx, Ny])
        model.E, model.nu = 1 - nu**2, nu          # -> model.E_star == 1
        tm.ModelFactory.registerNonPeriodic(model, 'dcfft')   # method dcfft
        solver = tm.PolonskyKeerRey(model, surface, tolerance)
        solver.setIntegralOperator('dcfft')                   # method dcfft
        solver.max_iter = max_iter
        error = solver.solve(load / (Lx * Ly))     # MEAN pressure over domain
        model.operators['dcfft'](model.traction, model.displacement)

    ``method``:
      * ``"dcfft"`` (default): Tamaas' non-periodic DC-FFT Boussinesq operator
        on the ``n x n`` grid (true isolated contact on a half-space).
      * ``"periodic_padded"``: emulation of a non-periodic domain with the
        default periodic operator on a ``(n + 2*(n//2))``-cell grid (about
        2n x 2n, twice the size), the ``n x n`` block in the centre returned.
      * ``"periodic"``: plain periodic ``n x n`` (contact with periodic images).

    Returns a dict: ``time`` (s, the ``solve`` call only), ``iterations``
    (Tamaas' own iteration counter parsed from its log; None if
    ``count_iterations`` is false), ``pressure`` (n x n, Pa),
    ``displacement`` (n x n, m, positive into the half-space; absolute for
    ``dcfft``, for the periodic methods Tamaas' shifted field with u = h in
    the contact, i.e. only relative), ``converged`` (Tamaas' final error <=
    tolerance), ``error``, ``approach`` (m, ``dcfft`` only, else None),
    ``contact_area`` (m^2, n_contact * cell area), ``contact_radius``
    (sqrt(area / pi)), ``total_force`` (N, check), ``method``.
    """
    import tamaas as tm

    n = int(n)
    pad = _pad_for(method, n)
    big = n + 2 * pad
    big_len = big / n  # dimensionless (size == 1)
    nu = float(poisson)
    e_star = float(young) / (1.0 - nu ** 2)
    rad = float(radius) / float(size)
    mean_p = float(load) / (float(size) ** 2 * big_len ** 2 * e_star)

    with _log_level(tm, tm.LogLevel.info if count_iterations
                    else tm.LogLevel.warning):
        model = tm.ModelFactory.createModel(tm.model_type.basic_2d,
                                            [big_len, big_len], [big, big])
        model.E = 1.0 - nu ** 2
        model.nu = nu
        surface = _paraboloid(big, big_len, rad)
        solver = tm.PolonskyKeerRey(model, surface, float(tolerance))
        if method == "dcfft":
            tm.ModelFactory.registerNonPeriodic(model, "dcfft")
            solver.setIntegralOperator("dcfft")
        if max_iter is not None:
            solver.max_iter = int(max_iter)

        elapsed, err, iters = _timed_solve(tm, solver, mean_p,
                                           count_iterations)

        approach = None
        if method == "dcfft":
            # the solver shifts the displacement (gap = 0 in contact); the
            # absolute displacement is recovered with the DC-FFT operator
            model.operators["dcfft"](model.traction, model.displacement)
        p = np.array(model.traction, dtype=float, copy=True)
        u = np.array(model.displacement, dtype=float, copy=True)

    sl = slice(pad, pad + n)
    p = p[sl, sl]
    u = u[sl, sl]
    h = surface[sl, sl]
    contact = p > 0
    if method == "dcfft" and contact.any():
        approach = float(np.mean((u - h)[contact])) * float(size)

    cell = (float(size) / n) ** 2
    area = int(contact.sum()) * cell
    pressure = p * e_star
    return {
        "time": elapsed,
        "iterations": iters,
        "pressure": pressure,
        "displacement": u * float(size),
        "converged": bool(err <= tolerance),
        "error": float(err),
        "approach": approach,
        "contact_area": area,
        "contact_radius": float(np.sqrt(area / np.pi)),
        "total_force": float(pressure.sum() * cell),
        "method": method,
        "grid": big,
    }


def hertz_reference(radius, load, young, poisson):
    """Hertz: contact radius a, peak pressure p0, approach delta."""
    e_star = young / (1.0 - poisson ** 2)
    a = (3.0 * load * radius / (4.0 * e_star)) ** (1.0 / 3.0)
    return {"a": a, "p0": 3.0 * load / (2.0 * np.pi * a ** 2),
            "delta": a ** 2 / radius}


# --------------------------------------------------------------------------
# 2. viscoelastic creep (generalized Maxwell)
# --------------------------------------------------------------------------
def creep_compliance(t, e_inf, terms):
    """Creep compliance J(t) of E(t) = e_inf + sum E_i exp(-t/tau_i).

    Exact inverse of the Prony relaxation modulus (e_inf > 0):
    J(t) = 1/e_inf + sum_j exp(s_j t) / (s_j f'(s_j)), with s_j the (negative,
    real) roots of f(s) = e_inf + sum E_i s / (s + 1/tau_i).
    For one term it reduces to 1/E_inf - E_1/(E_inf (E_inf+E_1))
    exp(-t E_inf / (tau (E_inf + E_1))).
    """
    from scipy.optimize import brentq

    t = np.asarray(t, dtype=float)
    terms = [(float(e), float(tau)) for e, tau in terms if float(e) != 0.0]
    lam = sorted(1.0 / tau for _, tau in terms)
    ei = np.array([e for e, _ in terms])
    li = np.array([1.0 / tau for _, tau in terms])

    def f(s):
        return e_inf + np.sum(ei * s / (s + li))

    def fp(s):
        return np.sum(ei * li / (s + li) ** 2)

    roots = []
    bounds = [0.0] + [-x for x in lam]
    for hi, lo in zip(bounds[:-1], bounds[1:]):
        eps = 1e-12 * max(abs(lo), 1.0)
        roots.append(brentq(f, lo + eps, hi - (eps if hi != 0.0 else 0.0),
                            xtol=1e-300, rtol=1e-15, maxiter=500))
    j = np.full_like(t, 1.0 / e_inf)
    for s in roots:
        j = j + np.exp(s * t) / (s * fp(s))
    return j


def lee_radok_radius(t, radius, load, e_inf, terms, poisson):
    """Lee & Radok: a(t)^3 = 3 R W C*(t) / 4, C* = (1 - nu^2) J(t)."""
    c = (1.0 - poisson ** 2) * creep_compliance(t, e_inf, terms)
    return (0.75 * radius * load * c) ** (1.0 / 3.0)


def maxwell_creep(n, size, radius, load, e_inf, terms, poisson, times,
                  tolerance, *, method="dcfft", max_iter=10000,
                  count_iterations=True):
    """Step-load creep of a rigid paraboloid on a generalized Maxwell solid.

    Material (our convention): relaxation modulus
    ``E(t) = e_inf + sum_i E_i exp(-t / tau_i)``, ``terms = [(E_i, tau_i)]``
    (Pa, s), constant Poisson ratio ``poisson`` for every branch.

    Load: ``load`` (N) applied as a step at t = 0 and held.  ``times`` are
    increasing output times >= 0; Tamaas integrates with backward Euler from
    the previous output time (t_0 = 0), i.e. ``dt_k = times[k] - times[k-1]``.
    ``times[0] == 0`` gives the instantaneous (glassy) response.

    Tamaas calls (dimensionless; length unit ``size``; pressure unit
    ``G_inf = e_inf / (2 (1 + nu))`` so that ``model.mu == 1``)::

        model = tm.ModelFactory.createModel(tm.model_type.basic_2d,
                                            [1, 1], [n, n])
        model.E, model.nu = 2 * (1 + nu), nu        # elastic branch, mu = 1
        solver = tm.MaxwellViscoelastic(model, surface, tolerance,
                                        time_step=dt_1,
                                        shear_moduli=[E_i / e_inf, ...],
                                        characteristic_times=[tau_i, ...])
        tm.ModelFactory.registerNonPeriodic(model, 'dcfft')   # dcfft
        solver.setIntegralOperator('dcfft')                   # dcfft
        for t_k: solver.time_step = dt_k; solver.solve(load / (L^2 G_inf))

    (``shear_moduli`` are shear moduli G_i of the Maxwell branches;
    G_i / G_inf = E_i / e_inf at constant nu.)

    Returns a dict: ``time`` (s, sum of the ``solve`` calls), ``step_times``,
    ``times``, ``approach`` (m per step, ``dcfft`` only, else None; absolute
    apex penetration reconstructed from Tamaas' pressures, see notes),
    ``approach_spread`` (max-min of u - h over the contact cells, m; ~0 is a
    consistency check of the reconstruction), ``contact_area`` (m^2 per
    step), ``contact_radius`` (m per step), ``iterations`` (per step, or
    None), ``converged`` (per step), ``error`` (per step), ``pressure``
    (final n x n field, Pa), ``total_force`` (per step, N).
    """
    import tamaas as tm

    n = int(n)
    pad = _pad_for(method, n)
    big = n + 2 * pad
    big_len = big / n
    nu = float(poisson)
    size = float(size)
    g_inf = float(e_inf) / (2.0 * (1.0 + nu))   # pressure unit
    rad = float(radius) / size
    mean_p = float(load) / (size ** 2 * big_len ** 2 * g_inf)
    terms = [(float(e), float(tau)) for e, tau in terms]
    g_rel = [e / float(e_inf) for e, _ in terms]         # G_i / G_inf
    taus = [tau for _, tau in terms]
    times = np.asarray(times, dtype=float)
    if times.ndim != 1 or times.size == 0 or times[0] < 0 \
            or np.any(np.diff(times) < 0):
        raise ValueError("times must be a non-empty increasing sequence >= 0")

    cell = (size / n) ** 2
    sl = slice(pad, pad + n)
    out = {k: [] for k in ("step_times", "approach", "approach_spread",
                           "contact_area", "contact_radius", "iterations",
                           "converged", "error", "total_force")}

    with _log_level(tm, tm.LogLevel.info if count_iterations
                    else tm.LogLevel.warning):
        model = tm.ModelFactory.createModel(tm.model_type.basic_2d,
                                            [big_len, big_len], [big, big])
        model.E = 2.0 * (1.0 + nu)
        model.nu = nu
        surface = _paraboloid(big, big_len, rad)
        solver = tm.MaxwellViscoelastic(model, surface, float(tolerance),
                                        float(times[0]), g_rel, taus)
        op = None
        if method == "dcfft":
            tm.ModelFactory.registerNonPeriodic(model, "dcfft")
            solver.setIntegralOperator("dcfft")
            op = model.operators["dcfft"]
        if max_iter is not None:
            solver.max_iter = int(max_iter)

        # state of our own reconstruction of the absolute displacement
        # (same backward-Euler generalized Maxwell law, see notes)
        u_prev = np.zeros((big, big))
        q = [np.zeros((big, big)) for _ in terms]
        w = np.zeros((big, big))
        t_prev = 0.0
        for t_k in times:
            dt = float(t_k - t_prev)
            t_prev = float(t_k)
            solver.time_step = dt
            elapsed, err, iters = _timed_solve(tm, solver, mean_p,
                                               count_iterations)
            p = np.array(model.traction, dtype=float, copy=True)

            out["step_times"].append(elapsed)
            out["iterations"].append(iters)
            out["error"].append(float(err))
            out["converged"].append(bool(err <= tolerance))
            pc = p[sl, sl]
            contact = pc > 0
            area = int(contact.sum()) * cell
            out["contact_area"].append(area)
            out["contact_radius"].append(float(np.sqrt(area / np.pi)))
            out["total_force"].append(float(pc.sum() * cell * g_inf))

            if op is not None:
                # w = K p / E*_model ; in these units E*_inf = 1 and
                # E*_i = g_rel_i, q_i = branch "stress" / E*_model
                op(p, w)
                gam = [tau / (tau + dt) if (tau + dt) > 0 else 0.0
                       for tau in taus]
                rhs = w.copy()
                stiff = 1.0
                for gk, gi, qk in zip(gam, g_rel, q):
                    rhs -= gk * (qk - gi * u_prev)
                    stiff += gk * gi
                u_new = rhs / stiff
                for k, (gk, gi) in enumerate(zip(gam, g_rel)):
                    q[k] = gk * (q[k] + gi * (u_new - u_prev))
                u_prev = u_new
                du = (u_new[sl, sl] - surface[sl, sl])[contact]
                if du.size:
                    out["approach"].append(float(du.mean()) * size)
                    out["approach_spread"].append(float(np.ptp(du)) * size)
                else:
                    out["approach"].append(float("nan"))
                    out["approach_spread"].append(float("nan"))

    res = {k: np.asarray(v) for k, v in out.items()}
    if op is None:
        res["approach"] = None
        res["approach_spread"] = None
    if not count_iterations:
        res["iterations"] = None
    res["time"] = float(np.sum(res["step_times"]))
    res["times"] = times
    res["pressure"] = p[sl, sl] * g_inf
    res["method"] = method
    return res


# --------------------------------------------------------------------------
# 3. self-check
# --------------------------------------------------------------------------
def _main():
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--n-creep", type=int, default=128)
    ap.add_argument("--tol", type=float, default=1e-12)
    args = ap.parse_args()

    print("== Hertz (PolonskyKeerRey) ==")
    size, radius, young = 1.0, 1.0, 1.0
    for nu in (0.0, 0.3):
        e_star = young / (1 - nu ** 2)
        a0 = 0.15 * size
        load = 4.0 * e_star * a0 ** 3 / (3.0 * radius)
        ref = hertz_reference(radius, load, young, nu)
        for method in _METHODS:
            r = hertz(args.n, size, radius, load, young, nu, args.tol,
                      method=method)
            ap_err = ("%+.2e" % (r["approach"] / ref["delta"] - 1)
                      if r["approach"] is not None else "   n/a  ")
            print(f"nu={nu:.1f} n={args.n} {method:16s} grid={r['grid']:4d} "
                  f"time={r['time']:.3f}s it={r['iterations']} "
                  f"conv={r['converged']} "
                  f"p0 err={r['pressure'].max() / ref['p0'] - 1:+.2e} "
                  f"a err={r['contact_radius'] / ref['a'] - 1:+.2e} "
                  f"delta err={ap_err} "
                  f"F/W-1={r['total_force'] / load - 1:+.1e}")

    print("== Maxwell creep (MaxwellViscoelastic), one-term SLS ==")
    nc = args.n_creep
    e_inf, e1, tau, nu = 1.0, 3.0, 1.0, 0.3
    t_ret = tau * (e_inf + e1) / e_inf
    # load such that the relaxed (t -> inf) Hertz radius is 0.15 size
    load = 4.0 * e_inf / (1 - nu ** 2) * (0.15 * size) ** 3 / (3 * radius)
    for dt in (0.1 * tau, 0.02 * tau):
        times = np.concatenate([[0.0], np.arange(1, int(round(3 * t_ret / dt))
                                                 + 1) * dt])
        r = maxwell_creep(nc, size, radius, load, e_inf, [(e1, tau)], nu,
                          times, args.tol)
        a_lr = lee_radok_radius(times, radius, load, e_inf, [(e1, tau)], nu)
        ea = r["contact_radius"] / a_lr - 1
        ed = r["approach"] / (a_lr ** 2 / radius) - 1
        print(f"n={nc} dt={dt:g} steps={times.size} time={r['time']:.2f}s "
              f"it/step={np.mean(r['iterations']):.1f} "
              f"all conv={bool(np.all(r['converged']))}")
        print(f"  a(t) vs Lee-Radok: max|err|={np.max(np.abs(ea)):.2e} "
              f"(t=0: {ea[0]:+.2e}, t=tau: "
              f"{ea[np.argmin(abs(times - tau))]:+.2e}, end: {ea[-1]:+.2e})")
        print(f"  delta(t) vs a_LR^2/R: max|err|={np.max(np.abs(ed)):.2e} "
              f"(t=0: {ed[0]:+.2e}, t=tau: "
              f"{ed[np.argmin(abs(times - tau))]:+.2e}, end: {ed[-1]:+.2e}); "
              f"max spread/delta="
              f"{np.max(r['approach_spread'] / r['approach']):.1e}")


if __name__ == "__main__":
    _main()
