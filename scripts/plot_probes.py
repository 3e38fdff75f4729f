#!/usr/bin/python3
"""Pressure probes of Lobovsky et al. (2014)'s dam break against the experiments (docs/free_surfaces.md).

  plot_probes.py OUT.png RUN [RUN ...]

Each RUN is a run directory of cases/dam_break_lobovsky*.toml (diagnostics.csv with probe_P1 ...
probe_P4, output.h5 with the scene's attributes). Draws p / (rho g H) against t sqrt(g/H) for sensors
1-4, one panel each, every run as a line, and the experiments' peak pressures over 100 repetitions
(cases/reference/lobovsky_2014_peak_pressure.csv: median and the 2.5-97.5 % band) as a band at the
right of each panel. Prints each run's windowed peak per sensor and its time, in the same units.
"""
import csv
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot import read_csv, require  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REFERENCE = os.path.join(ROOT, "cases", "reference", "lobovsky_2014_peak_pressure.csv")
H, G, RHO = 0.3, 9.81, 1000.0


def reference():
    with open(REFERENCE) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    head, body = rows[0], rows[1:]
    return [dict(zip(head, map(float, r))) for r in body]


def main(out, runs):
    ref = reference()
    scale_p, scale_t = 1.0 / (RHO * G * H), np.sqrt(G / H)
    fig, axes = plt.subplots(2, 2, figsize=(11, 7), sharex=True)
    for k, (ax, e) in enumerate(zip(axes.flat, ref)):
        lo, med, hi = (e[c] * 100.0 * scale_p for c in ("p2.5_mbar", "median_mbar", "p97.5_mbar"))
        ax.axhspan(lo, hi, color="0.85", label="experiments' peaks, 2.5-97.5 %")
        ax.axhline(med, color="0.4", ls="--", lw=1, label="their median")
        for run in runs:
            d = read_csv(require(os.path.join(run, "diagnostics.csv")))
            col = "probe_P%d" % (k + 1)
            if col not in d:
                sys.exit("%s: no column %s (not a cases/dam_break_lobovsky*.toml run?)" % (run, col))
            t, p = d["t"] * scale_t, d[col] * scale_p
            ax.plot(t, p, lw=1, label=os.path.basename(os.path.normpath(run)))
            i = int(np.argmax(p))
            print("%s sensor %d: peak %.3f rho g H at t sqrt(g/H) = %.3f (sampled rows; the summary's probe_P%d_max is over every step)"
                  % (run, k + 1, p[i], t[i], k + 1))
        ax.set_title("sensor %d, %g mm above the bed" % (k + 1, 1e3 * e["z_m"]))
        ax.set_ylabel("p / (rho g H)")
        ax.grid(alpha=0.3)
        if k == 0:
            ax.legend(fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel("t sqrt(g/H)")
    fig.suptitle("Dam break, H = 0.3 m: far-wall pressure probes against Lobovsky et al. (2014)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote", out)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
