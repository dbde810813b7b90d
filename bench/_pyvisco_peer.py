"""Peer runner: pyvisco's own DMA -> Prony workflow on a raw frequency-sweep file.

Runs under the pyvisco virtual environment made by ``bench/pyvisco_env.py``
(it must not import ``framework``) and prints ONE JSON object on stdout.

pyvisco: M. Springer, "PYVISCO: A Python library for identifying Prony series
parameters of linear viscoelastic materials" (NREL, 2022, BSD-3-Clause),
https://github.com/NREL/pyvisco (now NatLabRockies/pyvisco), PyPI ``pyvisco``.

The steps and their defaults are those of pyvisco's headless tutorial
``tutorials/freq_raw.py`` (same as ``verification/verify_freq_raw.ipynb`` and
``tutorials/tutorial.ipynb``):

1. ``load.file`` + ``load.user_raw(data, 'freq', 'E')``  (Hz, MPa, degC)
2. ``master.get_aT(df_raw, RefT)``  pairwise power-law shift factors, RefT = -5 degC
3. ``master.get_curve``  shifted master curve
4. ``shift.fit_WLF`` and ``shift.fit_poly``  shift functions
5. ``master.smooth(df_master, win=5)``  moving-median filter used by discretize
6. ``prony.discretize(df_master)``  window 'round', one term per decade
7. ``prony.fit(df_dis)``  frequency-domain NNLS collocation fit (opt=False)
8. ``opt.nprony(df_master, prony, window='min')``  term-count minimisation:
   refits N-1, N-2, ... terms (L-BFGS-B on alpha_i and tau_i) and picks the N
   whose residual is closest to 1.5 x the smallest residual.

Units: pyvisco keeps the file's modulus unit (here MPa) and Hz; its ``omega``
is 2*pi*f in rad/s and its ``tau_i`` are in s (tau = 1/omega).  The JSON gives
moduli in Pa and reduced angular frequency in rad/s.  The Prony series is
E(t) = E_inf + sum E_i exp(-t/tau_i) with E_i = E_0 alpha_i,
E_inf = E_0 (1 - sum alpha_i) (tensile).

Usage: python bench/_pyvisco_peer.py RAW_CSV [--reference DEGC] [--smooth WIN] [--shift CSV]
(``--shift``: pyvisco's other documented path, ``load.user_shift``, as in
``verification/verify_freq_raw.ipynb``; the default computes them with ``get_aT``.)
"""

import argparse
import contextlib
import json
import sys
import time
import warnings

PA = {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9}


def storage_loss(omega, e_inf, e_i, tau_i):
    """Generalised-Maxwell E'(omega), E''(omega) for omega in rad/s."""
    import numpy as np

    a = np.outer(omega, tau_i)
    return e_inf + (a**2 / (1 + a**2)) @ e_i, (a / (1 + a**2)) @ e_i


def summarise(series, scale, omega, stor, loss):
    """Prony dict of pyvisco -> E_inf, terms and its fit at the master points (Pa)."""
    import numpy as np

    terms = series["df_terms"]
    e_0 = float(series["E_0"]) * scale
    alpha = terms["alpha_i"].to_numpy(float)
    tau = terms["tau_i"].to_numpy(float)
    e_i, e_inf = e_0 * alpha, e_0 * (1.0 - alpha.sum())
    fs, fl = storage_loss(omega, e_inf, e_i, tau)

    def rms(fit, data):
        return float(np.sqrt(np.mean((np.log10(fit) - np.log10(data)) ** 2)))

    return {
        "n_terms": int(len(tau)),
        "e_0_Pa": e_0,
        "e_inf_Pa": float(e_inf),
        "terms": [[float(e), float(t)] for e, t in zip(e_i, tau)],
        "fit_storage_Pa": fs.tolist(),
        "fit_loss_Pa": fl.tolist(),
        "rms_log10_storage": rms(fs, stor),
        "rms_log10_loss": rms(fl, loss),
        "residual": float(series["err"]),
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("raw_csv")
    ap.add_argument("--reference", type=float, default=-5.0,
                    help="reference temperature, degC (pyvisco tutorial: -5); "
                         "snapped to the nearest set temperature like pyvisco's GUI")
    ap.add_argument("--smooth", type=int, default=5, help="master.smooth window (tutorial: 5)")
    ap.add_argument("--shift", metavar="CSV",
                    help="use recorded shift factors (load.user_shift) instead of master.get_aT")
    args = ap.parse_args(argv)

    t0 = time.perf_counter()
    import matplotlib

    matplotlib.use("Agg")  # pyvisco imports pyplot; no figure is drawn here
    import numpy as np
    import pyvisco
    from pyvisco import load, master, opt, prony, shift

    import_s = time.perf_counter() - t0
    warnings.filterwarnings("ignore")  # pandas warns on pyvisco's DataFrame attributes

    stages = {}
    with contextlib.redirect_stdout(sys.stderr):  # opt.nprony prints per-N progress
        t = t_start = time.perf_counter()
        df_raw, arr_reft, units = load.user_raw(load.file(args.raw_csv), "freq", "E")
        ref = float(arr_reft.iloc[(arr_reft - args.reference).abs().argsort().iloc[0]])
        stages["load"], t = time.perf_counter() - t, time.perf_counter()
        if args.shift:
            df_aT = load.user_shift(load.file(args.shift)).sort_values("T", ignore_index=True)
        else:
            df_aT, _ = master.get_aT(df_raw, ref)
        df_master = master.get_curve(df_raw, df_aT, ref)
        df_wlf = shift.fit_WLF(df_master.RefT, df_aT)
        shift.fit_poly(df_aT)
        df_master = master.smooth(df_master, args.smooth)
        stages["shift_master"], t = time.perf_counter() - t, time.perf_counter()
        df_dis = prony.discretize(df_master)
        full, _ = prony.fit(df_dis)
        stages["prony_fit"], t = time.perf_counter() - t, time.perf_counter()
        dict_prony, n_opt, _ = opt.nprony(df_master, full, window="min")
        stages["nprony"] = time.perf_counter() - t
        time_s = time.perf_counter() - t_start

    scale = PA[units["E_stor"]]
    order = np.argsort(df_master["omega"].to_numpy(float), kind="stable")
    omega = df_master["omega"].to_numpy(float)[order]
    stor = df_master["E_stor"].to_numpy(float)[order] * scale
    loss = df_master["E_loss"].to_numpy(float)[order] * scale
    final = summarise(dict_prony[n_opt], scale, omega, stor, loss)
    out = {
        "tool": "pyvisco",
        "pyvisco_version": pyvisco.__version__,
        "time_s": time_s,
        "import_s": import_s,
        "stage_s": stages,
        "reference_degC": ref,
        "smooth_window": args.smooth,
        "shift_source": args.shift or "master.get_aT",
        "shift_factors": [[float(T), float(a)] for T, a in zip(df_aT["T"], df_aT["log_aT"])],
        "wlf": {"c1": float(df_wlf["C1"].iloc[0]), "c2": float(df_wlf["C2"].iloc[0]),
                "reference_degC": float(df_wlf["RefT"].iloc[0])},
        "n_terms": final["n_terms"],
        "n_terms_full": int(full["df_terms"].shape[0]),
        "master_omega": omega.tolist(),
        "master_storage_Pa": stor.tolist(),
        "master_loss_Pa": loss.tolist(),
        "downward_variation": float(np.clip(-np.diff(np.log10(stor)), 0, None).sum()),
        **final,
        "full": summarise(full, scale, omega, stor, loss),
    }
    json.dump(out, sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
