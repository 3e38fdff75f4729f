#!/usr/bin/python3
"""Plots of bench/poiseuille_sweep output (start-up planar Poiseuille, Noutcheuwa & Owens 2012, Sec. 5.1).

    plot_sweep.py [CSV]     default bench_out/poiseuille_sweep.csv; writes next to it
        poiseuille_fig4.png   rms velocity error vs Nx, one curve per h/dx   (cf. Fig. 4)
        poiseuille_fig7.png   rms velocity error vs h, one curve per dx       (cf. Fig. 7)
        poiseuille_time.png   our total time and the paper's Table 1 time vs Nx, per h/dx
Rows whose status is not "ok" are skipped.
"""
import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402



def finish(fig, ax, xlabel, ylabel, title, path, legend=8):
    """Labels, title and legend of a one-panel figure, saved to path."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=legend)
    fig.tight_layout()
    fig.savefig(path, dpi=120)

def load(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r.get("status") == "ok"]
    if not rows:
        sys.exit("plot_sweep.py: no successful runs in " + path)
    return rows


def slope_guide(ax, xs, y0, order, label):
    x0, x1 = min(xs), max(xs)
    ax.plot([x0, x1], [y0, y0 * (x1 / x0) ** order], "k:", lw=1)
    ax.text(x1, y0 * (x1 / x0) ** order, " " + label, va="center", fontsize=8)


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join("bench_out", "poiseuille_sweep.csv")
    if not os.path.isfile(path):
        sys.exit("plot_sweep.py: no such file " + path)
    rows = load(path)
    out = os.path.dirname(os.path.abspath(path))
    steps = sorted({int(r["steps"]) for r in rows})
    t_end = ", ".join("t = %g" % (s * 1.25e-6) for s in steps)

    by_h = defaultdict(list)
    by_nx = defaultdict(list)
    for r in rows:
        nx, hdx = int(r["nx"]), float(r["h_over_dx"])
        by_h[hdx].append((nx, float(r["rms_error"]), float(r["total_s"]),
                          float(r["paper_s_scaled_to_steps"]) if r["paper_s_scaled_to_steps"] else math.nan))
        by_nx[nx].append((float(r["h"]), float(r["rms_error"])))

    fig, ax = plt.subplots(figsize=(6, 4.5))
    for hdx in sorted(by_h):
        d = sorted(by_h[hdx])
        ax.loglog([p[0] for p in d], [p[1] for p in d], "o-", label="h = %g dx" % hdx)
    nxs = sorted({int(r["nx"]) for r in rows})
    if len(nxs) > 1:
        slope_guide(ax, nxs, min(float(r["rms_error"]) for r in rows), -2, "slope -2")
    finish(fig, ax, "Nx (= 1/dx)", "rms velocity error, Eq. (69)", "EPSPH start-up Poiseuille (cf. Fig. 4), " + t_end,
           os.path.join(out, "poiseuille_fig4.png"))

    fig, ax = plt.subplots(figsize=(6, 4.5))
    for nx in sorted(by_nx):
        d = sorted(by_nx[nx])
        ax.loglog([p[0] for p in d], [p[1] for p in d], "o-", label="dx = 1/%d" % nx)
    finish(fig, ax, "h", "rms velocity error, Eq. (69)", "EPSPH start-up Poiseuille (cf. Fig. 7), " + t_end,
           os.path.join(out, "poiseuille_fig7.png"))

    fig, ax = plt.subplots(figsize=(6, 4.5))
    for k, hdx in enumerate(sorted(by_h)):
        d = sorted(by_h[hdx])
        c = "C%d" % (k % 10)
        ax.loglog([p[0] for p in d], [p[2] for p in d], "o-", color=c, label="ours, h = %g dx" % hdx)
        pd = [p for p in d if not math.isnan(p[3])]
        if pd:
            ax.loglog([p[0] for p in pd], [p[3] for p in pd], "s--", color=c, alpha=0.5)
    finish(fig, ax, "Nx (= 1/dx)", "total time incl. set-up [s]",
           "solid: ours; dashed: paper Table 1 (x 1e5 s, scaled to our steps)", os.path.join(out, "poiseuille_time.png"),
           legend=7)
    print("wrote poiseuille_fig4.png, poiseuille_fig7.png, poiseuille_time.png in " + out)


if __name__ == "__main__":
    main()
