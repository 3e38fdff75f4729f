#!/usr/bin/python3
"""Where a membrane's length error sits along it: the stretch lambda = |X_s| / a of its markers (a periodic
cubic spline in the label, a = L0 / (nb ds) = 1 on a circular reference of radius r0), split into its
Fourier modes up to the cutoff mc = L / cutoff (those a tension cutoff keeps) and above, at the last
snapshot of a run (or every one with --all).
Usage: scripts/strain_modes.py RUN_DIR --r0 R0 --cutoff LENGTH [--membrane K] [--all]"""
import argparse

import h5py
import numpy as np
from scipy.interpolate import CubicSpline

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("run")
ap.add_argument("--r0", type=float, required=True, help="the reference circle's radius (membrane.r0)")
ap.add_argument("--cutoff", type=float, required=True, help="the wavelength split, e.g. 2 dx")
ap.add_argument("--membrane", type=int, default=0)
ap.add_argument("--all", action="store_true", help="every snapshot, not only the last")
a = ap.parse_args()
L0 = 2 * np.pi * a.r0
print(f"{'t':>8} {'max|lambda-1|':>14} {'mc':>4} {'modes <= mc':>12} {'modes > mc':>12}")
with h5py.File(f"{a.run}/output.h5", "r") as f:
    snaps = sorted(f["snapshots"].keys())
    for name in snaps if a.all else snaps[-1:]:
        g = f["snapshots"][name]
        X = g[f"membrane_{a.membrane}/X"][:]
        n = len(X)
        s = np.arange(n + 1) * L0 / n
        Xs = CubicSpline(s, np.vstack([X, X[:1]]), bc_type="periodic")(s[:-1], 1)
        e = np.hypot(Xs[:, 0], Xs[:, 1]) - 1.0
        mc = int((1.0 + e.mean()) * L0 / a.cutoff)
        E = np.fft.rfft(e)
        low = np.fft.irfft(np.where(np.arange(n // 2 + 1) > mc, 0.0, E), n)
        t = g.attrs.get("time", np.nan)
        print(f"{float(t):8.3f} {abs(e).max():14.3e} {mc:4d} {abs(low).max():12.3e} {abs(e - low).max():12.3e}")
