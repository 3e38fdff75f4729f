#!/usr/bin/python3
"""The oscillating membrane's mode-2 frequency and decay rate from a fit of the whole signal.

rx(t) (column m0_rx of diagnostics.csv) over a window [t0, t1] is fitted by

    rx(t) = c + d t + A exp(sigma t) cos(omega t + phi),

the linear mode's form (scripts/membrane_theory.py oscillation gives its s = sigma + i omega) on a
slowly drifting mean: for each (sigma, omega) the best c, d, A cos(phi), A sin(phi) are a linear
least-squares problem, and (sigma, omega) minimise what is left (a grid refined around its best
point). Every sample counts, so the estimate does not rest on a few extremum times. The window starts
after the release's transient (the response of a fluid started from rest is the mode plus a slowly
decaying viscous part, most of it gone by t = 0.5); the spread of the estimates over three window
starts (t0, t0 + 0.3, t0 + 0.7) is printed as the estimate's uncertainty.

    /usr/bin/python3 scripts/oscillation_fit.py RUN_DIR [RUN_DIR ...] [--t0 0.5] [--t1 3.3]

prints, per run, the period 2 pi / omega and sigma (window from t0), their spread over the three
windows, and the rms of the fit's residual relative to the swing.
"""
import argparse
import csv
import math
import os
import sys

import numpy as np


def read(run):
    with open(os.path.join(run, "diagnostics.csv")) as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["t"]) for r in rows])
    rx = np.array([float(r["m0_rx"]) for r in rows])
    return t, rx


def residual(t, y, sigma, omega):
    """Least-squares residual norm of the fit at (sigma, omega) and its linear coefficients."""
    e = np.exp(sigma * t)
    M = np.column_stack([np.ones_like(t), t, e * np.cos(omega * t), e * np.sin(omega * t)])
    coef, *_ = np.linalg.lstsq(M, y, rcond=None)
    r = y - M @ coef
    return float(r @ r), coef


def fit(t, y, sigma0=-1.15, omega0=4.3):
    """(sigma, omega) minimising the residual: a 41 x 41 grid, refined ten times around its best point."""
    best = (sigma0, omega0)
    span = (1.0, 1.0)
    for _ in range(10):
        ss = np.linspace(best[0] - span[0], best[0] + span[0], 41)
        ws = np.linspace(best[1] - span[1], best[1] + span[1], 41)
        val = min((residual(t, y, s, w)[0], s, w) for s in ss for w in ws)
        best = (val[1], val[2])
        span = (span[0] / 8, span[1] / 8)
    r2, coef = residual(t, y, *best)
    return best[0], best[1], math.sqrt(r2 / len(t)), coef


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="run directories holding diagnostics.csv")
    ap.add_argument("--t0", type=float, default=0.5, help="window start (after the release's transient)")
    ap.add_argument("--t1", type=float, default=3.3, help="window end")
    a = ap.parse_args()
    print(f"{'run':<40} {'period':>9} {'+-':>7} {'sigma':>8} {'+-':>7} {'rms/swing':>10}")
    for run in a.runs:
        t, rx = read(run)
        est = []
        for t0 in (a.t0, a.t0 + 0.3, a.t0 + 0.7):
            keep = (t >= t0) & (t <= a.t1)
            if keep.sum() < 20:
                print(f"{run}: fewer than 20 samples in [{t0}, {a.t1}]", file=sys.stderr)
                return 1
            sigma, omega, rms, coef = fit(t[keep], rx[keep])
            swing = math.hypot(coef[2], coef[3]) * math.exp(sigma * t0)
            est.append((2 * math.pi / omega, sigma, rms / swing))
        periods, sigmas = [e[0] for e in est], [e[1] for e in est]
        print(f"{run:<40} {est[0][0]:9.5f} {max(periods) - min(periods):7.4f} {est[0][1]:8.4f} "
              f"{max(sigmas) - min(sigmas):7.4f} {est[0][2]:10.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
