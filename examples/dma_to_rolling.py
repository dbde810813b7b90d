"""From DMA sweeps to rolling friction at three temperatures: master curve, Prony series, steady rolling.

What a polymer lab hands over is dynamic mechanical analysis (DMA): the
storage and loss moduli E'(f), E''(f) over a few decades of frequency at
several temperatures. This example takes such sweeps
(``examples/data/dma_sweeps.csv``) through the whole chain:

1. Master curve: the sweeps shifted along log(frequency) onto the reference
   temperature T_ref = 296.15 K (``materials.master_curve``: the shifts that
   best lay neighbouring sweeps' log E' and log E'' on each other), and the
   WLF law ``log10 a_T = -c1 (T - T_ref) / (c2 + T - T_ref)`` fitted to the
   shift factors (``MasterCurve.fit_wlf``).
2. Prony series: ``fit_prony(kind="dynamic")`` on the master curve, relaxation
   times and moduli both fitted; the fewest terms whose fit lies within 0.1 %
   of every point.
3. Rolling friction: a rigid sphere (R = 10 mm, W = 8 N) in steady rolling
   (``schedules.Rolling(steady=True)``) on the fitted solid at T_ref, T_ref + 10 K
   and T_ref + 20 K (``Viscoelastic.at(T, wlf)``: every relaxation time times
   a_T), friction coefficient against speed. Time-temperature superposition
   makes the three curves copies of one another shifted by 1/a_T along the
   speed axis: each temperature is solved at the same reduced speeds V a_T,
   and the largest difference between the curves there is printed as a check.

THE DATA ARE COMPUTED, NOT MEASURED. No published table of measured DMA sweeps
could be found with this project's literature search, so the file holds the
sweeps (0.1 to 100 Hz, seven temperatures from T_ref - 5 K to T_ref + 25 K) of
an illustrative solid computed from two published sets of constants: the PMMA
relaxation modulus of Spinu & Cerlinca (seed 001, a Prony fit of the data of
Ramesh Kumar & Narasimhan, Current Science 87, 2004; ``materials.PMMA``) as
the master curve at T_ref, and the "universal" WLF constants c1 = 17.44,
c2 = 51.6 K of Williams, Landel & Ferry (J. Am. Chem. Soc. 77, 3701, 1955)
at T_ref. Real PMMA is glassy up to about 378 K and follows neither near room
temperature; the file's header says the same. What the example shows is that
the chain gives those constants back: the shift factors within 1e-4 decades,
c1 and c2 within 1e-4, the Prony times and moduli within 1e-4.

Writes to ``--out``: ``dma_shift_factors.csv`` (fitted and WLF shift factors
per temperature), ``dma_prony.csv`` (the fitted terms), ``dma_rolling.csv``
(friction, contact area and peak pressure per temperature and speed) and, with
matplotlib, ``dma_master_curve.png`` and ``dma_rolling_friction.png``.

    python examples/dma_to_rolling.py [--cells 32] [--per-decade 2] [--out out/examples]
"""
import argparse
import os

import numpy as np

import framework as fw
from framework import indenters, materials, schedules
from framework.sweep import write_table

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "dma_sweeps.csv")
REFERENCE = 296.15                         # K, the master curve's temperature
TEMPERATURES = (296.15, 306.15, 316.15)    # K, where the sphere rolls
POISSON = 0.35
RADIUS, LOAD = 10e-3, 8.0                  # m, N: relaxed Hertz radius a0 = 0.30 mm on this solid
#: Reduced speeds V a_T [m/s] of each friction curve: relaxed to glassy (the peak near 3e-6 m/s at T_ref).
REDUCED_SPEEDS = (1e-8, 1e-3)
#: Default cells per side of the steady grid (3 relaxed contact radii): the peak friction within 1 %.
CELLS = 32
#: Most Prony terms tried; the fit stops at the first within TOLERANCE of every point.
MOST_TERMS, TOLERANCE = 6, 1e-3


def read_sweeps(path=DATA):
    """``{temperature [K]: (angular frequencies [rad/s], E' + i E'' [Pa])}`` from the CSV file (Hz in the file)."""
    table = np.loadtxt(path, delimiter=",", comments="#")
    sweeps = {}
    for temperature in np.unique(table[:, 0]):
        rows = table[table[:, 0] == temperature]
        sweeps[float(temperature)] = (2 * np.pi * rows[:, 1], rows[:, 2] + 1j * rows[:, 3])
    return sweeps


def fit_series(curve):
    """The Prony fit with the fewest terms whose largest relative error is below ``TOLERANCE``."""
    for n_terms in range(1, MOST_TERMS + 1):
        fit = curve.fit_prony(n_terms, poisson=POISSON)
        print(f"  {n_terms} term(s): rms relative error {fit.rms_relative_error:.2e}, "
              f"largest {fit.max_relative_error:.2e}")
        if fit.max_relative_error < TOLERANCE:
            return fit
    return fit


def steady_friction(material, speed, cells):
    """One steady rolling solve on a grid 3 relaxed Hertz radii square: the one-record :class:`Result`."""
    relaxed = material.contact_compliance().relaxed
    a0 = (3 * LOAD * RADIUS * relaxed / 4) ** (1 / 3)
    step = 3 * a0 / cells
    grid = fw.Grid(shape=(cells, cells), size=(cells * step, cells * step))
    return fw.Simulation(grid=grid, material=material, indenter=indenters.Sphere(radius=RADIUS),
                         schedule=schedules.Rolling(load=LOAD, velocity=(speed, 0.0), steady=True)).run()


def main(cells=CELLS, out="out/examples", per_decade=2):
    """Master curve, Prony fit and friction curves; write the CSV files and pictures to ``out``; return the rows.

    Parameters
    ----------
    cells : int
        Cells per side of the steady rolling grid.
    out : str
        Output folder.
    per_decade : int
        Speeds per decade of each friction curve.
    """
    os.makedirs(out, exist_ok=True)
    sweeps = read_sweeps()
    curve = materials.master_curve(sweeps, reference=REFERENCE)
    wlf = curve.fit_wlf()
    print(f"master curve: {len(sweeps)} sweeps, {curve.frequencies.size} points over "
          f"{np.log10(curve.frequencies[-1] / curve.frequencies[0]):.1f} decades of reduced frequency; "
          f"WLF fit c1 = {wlf.c1:.5g}, c2 = {wlf.c2:.5g} K at T_ref = {wlf.reference} K")
    write_table([{"temperature_K": t, "shift_factor": a, "wlf_shift_factor": wlf.factor(t)}
                 for t, a in zip(curve.temperatures, curve.shift_factors)], os.path.join(out, "dma_shift_factors.csv"))
    print("Prony fit of the master curve (relaxation times fitted too):")
    fit = fit_series(curve)
    print(f"  e_inf = {fit.constant / 1e6:.6g} MPa, terms (MPa, s): "
          + ", ".join(f"({modulus / 1e6:.6g}, {tau:.6g})" for modulus, tau in fit.terms))
    write_table([{"modulus_Pa": fit.constant, "relaxation_time_s": float("inf")}]
                + [{"modulus_Pa": m, "relaxation_time_s": tau} for m, tau in fit.terms],
                os.path.join(out, "dma_prony.csv"))

    reduced = np.geomspace(*REDUCED_SPEEDS, round(per_decade * np.log10(REDUCED_SPEEDS[1] / REDUCED_SPEEDS[0])) + 1)
    rows, curves = [], {}
    for temperature in TEMPERATURES:
        material = fit.material.at(temperature, wlf)
        speeds = reduced / material.shift_factor
        results = [steady_friction(material, speed, cells) for speed in speeds]
        mu = np.array([result.friction_coefficient[0] for result in results])
        curves[temperature] = speeds, mu
        rows += [{"temperature_K": temperature, "shift_factor": material.shift_factor, "speed_m_s": v,
                  "friction_coefficient": r.friction_coefficient[0], "contact_area_m2": r.contact_area[0],
                  "max_pressure_Pa": r.max_pressure[0]} for v, r in zip(speeds, results)]
        peak = int(np.argmax(mu))
        print(f"T = {temperature} K (a_T = {material.shift_factor:.4g}): peak friction {mu[peak]:.4g} at "
              f"V = {speeds[peak]:.3g} m/s (V a_T = {reduced[peak]:.3g} m/s)")
    spread = np.ptp([mu for _, mu in curves.values()], axis=0).max()
    print(f"the three curves at equal V a_T differ by {spread:.2g} at most (time-temperature superposition)")
    write_table(rows, os.path.join(out, "dma_rolling.csv"))
    plot(sweeps, curve, fit, wlf, curves, out)
    return rows


def plot(sweeps, curve, fit, wlf, curves, out):
    try:
        from matplotlib.figure import Figure
    except ImportError:
        print("matplotlib not installed (pip install 'viscocontact[viz]'): no pictures")
        return
    figure = Figure(figsize=(11, 4.2), layout="constrained")
    raw, master, shifts = figure.subplots(1, 3)
    for temperature, (w, modulus) in sweeps.items():
        line, = raw.loglog(w, modulus.real, "-", lw=1, label=f"{temperature:g} K")
        raw.loglog(w, modulus.imag, "--", lw=1, color=line.get_color())
    raw.set(title="sweeps: E' (solid), E'' (dashed)", xlabel="w [rad/s]", ylabel="modulus [Pa]")
    raw.legend(fontsize=7, ncol=2)
    w = np.geomspace(curve.frequencies[0], curve.frequencies[-1], 300)
    master.loglog(curve.frequencies, curve.complex_modulus.real, ".", ms=3, label="E' shifted")
    master.loglog(curve.frequencies, curve.complex_modulus.imag, ".", ms=3, label="E'' shifted")
    master.loglog(w, fit.material.storage_modulus(w), "k-", lw=0.8, label=f"{len(fit.terms)}-term Prony fit")
    master.loglog(w, fit.material.loss_modulus(w), "k-", lw=0.8)
    master.set(title=f"master curve at {curve.reference} K", xlabel="w a_T [rad/s]")
    master.legend(fontsize=8)
    temperatures = np.linspace(curve.temperatures[0], curve.temperatures[-1], 100)
    shifts.plot(curve.temperatures, np.log10(curve.shift_factors), "o", label="fitted shifts")
    shifts.plot(temperatures, wlf.log10_factor(temperatures), "-",
                label=f"WLF c1 = {wlf.c1:.4g}, c2 = {wlf.c2:.4g} K")
    shifts.set(title="shift factors", xlabel="T [K]", ylabel="log10 a_T")
    shifts.legend(fontsize=8)
    figure.savefig(os.path.join(out, "dma_master_curve.png"), dpi=110)
    figure = Figure(figsize=(6.5, 4.2), layout="constrained")
    ax = figure.subplots()
    for temperature, (speeds, mu) in curves.items():
        ax.semilogx(speeds, mu, "o-", ms=3, label=f"T = {temperature} K")
    ax.set(xlabel="rolling speed V [m/s]", ylabel="friction coefficient F_t / W",
           title=f"sphere R = {RADIUS * 1e3:g} mm, W = {LOAD:g} N on the fitted solid")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    figure.savefig(os.path.join(out, "dma_rolling_friction.png"), dpi=110)
    print("wrote", os.path.join(out, "dma_master_curve.png"), "and", os.path.join(out, "dma_rolling_friction.png"))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=CELLS, help="cells per side of the steady grid (3 a0)")
    parser.add_argument("--per-decade", type=int, default=2, help="speeds per decade of each friction curve")
    parser.add_argument("--out", default="out/examples")
    main(**vars(parser.parse_args()))
