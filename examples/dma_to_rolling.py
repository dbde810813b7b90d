"""From measured DMA sweeps to a map of rolling friction over speed and temperature.

What a polymer lab hands over is dynamic mechanical analysis (DMA): storage
and loss moduli E'(f), E''(f) over a few decades of frequency at several
temperatures. This example takes MEASURED sweeps, pyvisco's example data set
(``examples/data/dma/pyvisco_freq_raw.csv``: 21 isotherms, -50 to 100 degC,
0.1-100 Hz, a photovoltaic encapsulant through its glass transition; Springer,
NREL/pyvisco 2022, BSD licence, notice in ``examples/data/dma/README.md``)
through the whole chain:

1. ``materials.read_dma``: the file (byte-order mark, units row, MPa, Hz,
   degC) to sweeps in Pa, rad/s and K.
2. ``materials.master_curve``: the sweeps shifted onto T_ref (the sweep
   nearest 55 degC, just above the glass transition, where the sphere rolls),
   the glass transition from the loss peak at 1 Hz, WLF constants quoted at
   it (``fit_wlf``), and the law for the whole range (``fit_shift``: WLF above
   T_g, Arrhenius below).
3. ``fit_prony``: the Prony series of the master curve, relaxation times
   fitted, the term count chosen automatically.
4. Steady rolling (``schedules.Rolling(steady=True)``) of a rigid sphere
   (R = 10 mm, W = 1 N: relaxed contact radius ~0.3 mm, strains of a few
   percent) on the fitted solid at five temperatures from 40 to 100 degC
   (``Viscoelastic.at``): the friction map over speed and temperature, and
   the speed of the friction peak at each temperature. Each temperature is
   solved at the same reduced speeds V a_T, so each curve is the one at T_ref
   moved by 1/a_T along the speed axis.

Writes to ``--out``: ``dma_shift_factors.csv``, ``dma_prony.csv``,
``dma_rolling.csv`` (friction, contact area and peak pressure per temperature
and speed) and, with matplotlib, ``dma_master_curve.png`` (sweeps, master
curve with the fit, shift factors with the laws) and ``dma_friction_map.png``.

    python examples/dma_to_rolling.py [--cells 32] [--per-decade 2] [--out out/examples]
"""
import argparse
import os

import numpy as np

import framework as fw
from framework import indenters, materials, schedules
from framework.sweep import write_table

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "dma", "pyvisco_freq_raw.csv")
REFERENCE = 328.15                         # K (55 degC): the master curve's temperature is the sweep nearest it
TEMPERATURES = (313.15, 328.15, 343.15, 358.15, 373.15)    # K, where the sphere rolls (40-100 degC)
POISSON = 0.35
RADIUS, LOAD = 10e-3, 1.0                  # m, N
#: Reduced speeds V a_T [m/s] of the map (a_T relative to the master curve's temperature): at every temperature the
#: speeds that span the friction peak (near 1e-6 m/s at 55 degC) and the relaxed and glassy plateaus beside it.
REDUCED_SPEEDS = (1e-11, 1e-2)
#: Default cells per side of the steady grid (3 relaxed contact radii).
CELLS = 32


def steady_friction(material, speed, cells):
    """One steady rolling solve on a grid 3 relaxed Hertz radii square: the one-record :class:`Result`."""
    relaxed = material.contact_compliance().relaxed
    a0 = (3 * LOAD * RADIUS * relaxed / 4) ** (1 / 3)
    step = 3 * a0 / cells
    grid = fw.Grid(shape=(cells, cells), size=(cells * step, cells * step))
    return fw.Simulation(grid=grid, material=material, indenter=indenters.Sphere(radius=RADIUS),
                         schedule=schedules.Rolling(load=LOAD, velocity=(speed, 0.0), steady=True)).run()


def peak_speed(speeds, mu):
    """Speed of the friction peak: the vertex of the parabola in log V through the largest value and its neighbours."""
    i = int(np.clip(np.argmax(mu), 1, len(mu) - 2))
    x, y = np.log10(speeds[i - 1:i + 2]), mu[i - 1:i + 2]
    a, b, _ = np.polyfit(x - x[1], y, 2)
    return 10 ** (x[1] - b / (2 * a)) if a < 0 else speeds[int(np.argmax(mu))]


def main(cells=CELLS, out="out/examples", per_decade=2):
    """Master curve, laws, Prony fit and friction map; write the CSV files and pictures to ``out``; return the rows.

    Parameters
    ----------
    cells : int
        Cells per side of the steady rolling grid.
    out : str
        Output folder.
    per_decade : int
        Speeds per decade of the map.
    """
    os.makedirs(out, exist_ok=True)
    sweeps = materials.read_dma(DATA)
    reference = min(sweeps, key=lambda t: abs(t - REFERENCE))
    curve = materials.master_curve(sweeps, reference=reference)
    tg, wlf, law = curve.glass_transition, curve.fit_wlf(), curve.fit_shift()
    print(f"{len(sweeps)} sweeps ({sweeps.format} file, {sweeps.modulus}), master curve at {reference:.2f} K over "
          f"{np.log10(curve.frequencies[-1] / curve.frequencies[0]):.1f} decades of reduced frequency")
    print(f"glass transition (loss peak at 1 Hz) {tg:.1f} K; WLF at {wlf.reference:.2f} K: c1 = {wlf.c1:.3g}, "
          f"c2 = {wlf.c2:.3g} K; below T_g Arrhenius E_a = {law.activation_energy / 1e3:.0f} kJ/mol")
    write_table([{"temperature_K": t, "log10_shift_factor": np.log10(a), "log10_law": law.log10_factor(t)}
                 for t, a in zip(curve.temperatures, curve.shift_factors)], os.path.join(out, "dma_shift_factors.csv"))
    fit = curve.fit_prony(poisson=POISSON)
    errors = [np.sqrt(np.mean(np.log10(part(fit.fitted) / part(curve.complex_modulus))**2)) for part in (np.real, np.imag)]
    print(f"Prony fit: {len(fit.terms)} terms, e_inf = {fit.constant / 1e6:.4g} MPa; rms log10 error "
          f"{errors[0]:.4f} (E'), {errors[1]:.4f} (E'')")
    write_table([{"modulus_Pa": fit.constant, "relaxation_time_s": float("inf")}]
                + [{"modulus_Pa": m, "relaxation_time_s": tau} for m, tau in fit.terms],
                os.path.join(out, "dma_prony.csv"))

    reduced = np.geomspace(*REDUCED_SPEEDS, round(per_decade * np.log10(REDUCED_SPEEDS[1] / REDUCED_SPEEDS[0])) + 1)
    relaxed = fit.material.contact_compliance().relaxed
    print(f"sphere R = {RADIUS * 1e3:g} mm, W = {LOAD:g} N: relaxed Hertz radius "
          f"{(3 * LOAD * RADIUS * relaxed / 4) ** (1 / 3) * 1e3:.3f} mm")
    rows, peaks, friction, maps = [], [], [], []
    for temperature in TEMPERATURES:
        material = fit.material.at(temperature, law)
        speeds = reduced / material.shift_factor
        maps.append(speeds)
        results = [steady_friction(material, speed, cells) for speed in speeds]
        mu = np.array([result.friction_coefficient[0] for result in results])
        friction.append(mu)
        rows += [{"temperature_K": temperature, "log10_shift_factor": np.log10(material.shift_factor),
                  "speed_m_s": v, "friction_coefficient": r.friction_coefficient[0],
                  "contact_area_m2": r.contact_area[0], "max_pressure_Pa": r.max_pressure[0]}
                 for v, r in zip(speeds, results)]
        peaks.append(peak_speed(speeds, mu))
        print(f"T = {temperature:.2f} K (log10 a_T = {np.log10(material.shift_factor):+.2f}): peak friction "
              f"{mu.max():.4g} at V = {peaks[-1]:.3g} m/s")
    per_kelvin = np.diff(np.log10(peaks)) / np.diff(TEMPERATURES)
    print("the friction peak moves to higher speeds as the polymer warms: " + ", ".join(
        f"{rate:.3f}" for rate in per_kelvin) + " decades per K between the temperatures (the shift law's slope: "
        "time-temperature superposition makes each curve a copy of the one at T_ref)")
    write_table(rows, os.path.join(out, "dma_rolling.csv"))
    plot(sweeps, curve, fit, law, np.array(maps), np.array(friction), out)
    return rows


def plot(sweeps, curve, fit, law, speeds, friction, out):
    try:
        from matplotlib.figure import Figure
    except ImportError:
        print("matplotlib not installed (pip install 'viscocontact[viz]'): no pictures")
        return
    figure = Figure(figsize=(13, 4.2), layout="constrained")
    raw, master, shifts = figure.subplots(1, 3)
    for temperature, (w, modulus) in sweeps.items():
        colour = (0.1 + 0.8 * (temperature - min(sweeps)) / np.ptp(list(sweeps)), 0.2, 0.6)
        raw.loglog(w, modulus.real, "-", lw=1, color=colour)
        raw.loglog(w, modulus.imag, "--", lw=1, color=colour)
    raw.set(title=f"{len(sweeps)} measured sweeps: $E'$ (solid), $E''$ (dashed)", xlabel="$\\omega$ [rad/s]",
            ylabel="modulus [Pa]")
    w = np.geomspace(curve.frequencies[0], curve.frequencies[-1], 400)
    master.loglog(curve.frequencies, curve.complex_modulus.real, ".", ms=3, label="$E'$ shifted")
    master.loglog(curve.frequencies, curve.complex_modulus.imag, ".", ms=3, label="$E''$ shifted")
    master.loglog(w, fit.material.storage_modulus(w), "k-", lw=0.8, label=f"{len(fit.terms)}-term Prony fit")
    master.loglog(w, fit.material.loss_modulus(w), "k-", lw=0.8)
    master.set(title=f"master curve at {curve.reference:.1f} K", xlabel="$\\omega a_T$ [rad/s]")
    master.legend(fontsize=8)
    temperatures = np.linspace(curve.temperatures[0], curve.temperatures[-1], 200)
    shifts.plot(curve.temperatures, np.log10(curve.shift_factors), "o", ms=4, label="fitted shifts")
    shifts.plot(temperatures, law.log10_factor(temperatures), "-", label="WLF above $T_g$, Arrhenius below")
    shifts.axvline(curve.glass_transition, color="0.6", lw=0.8, ls=":", label=f"$T_g$ = {curve.glass_transition:.1f} K")
    shifts.set(title="shift factors", xlabel="$T$ [K]", ylabel="$\\log_{10} a_T$")
    shifts.legend(fontsize=8)
    figure.savefig(os.path.join(out, "dma_master_curve.png"), dpi=110)
    figure = Figure(figsize=(11, 4.2), layout="constrained")
    curves, chart = figure.subplots(1, 2)
    for temperature, v, mu in zip(TEMPERATURES, speeds, friction):
        curves.semilogx(v, mu, "o-", ms=3, label=f"$T$ = {temperature - 273.15:.0f} \u00b0C")
    curves.set(xlabel="rolling speed $V$ [m/s]", ylabel="friction coefficient $\\mu = F_t / W$",
               title=f"sphere R = {RADIUS * 1e3:g} mm, W = {LOAD:g} N on the measured polymer")
    curves.grid(True, alpha=0.3)
    curves.legend(fontsize=8)
    image = chart.pcolormesh(np.log10(speeds), np.repeat(np.array(TEMPERATURES)[:, None] - 273.15, speeds.shape[1], 1),
                             friction, shading="nearest", cmap="viridis")
    chart.set(xlabel="$\\log_{10} V$ [m/s]", ylabel="$T$ [\u00b0C]", title="rolling friction coefficient $\\mu$")
    figure.colorbar(image, ax=chart)
    figure.savefig(os.path.join(out, "dma_friction_map.png"), dpi=110)
    print("wrote", os.path.join(out, "dma_master_curve.png"), "and", os.path.join(out, "dma_friction_map.png"))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cells", type=int, default=CELLS, help="cells per side of the steady grid (3 a0)")
    parser.add_argument("--per-decade", type=int, default=2, help="speeds per decade of the map")
    parser.add_argument("--out", default="out/examples")
    main(**vars(parser.parse_args()))
