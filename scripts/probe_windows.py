#!/usr/bin/python3
"""A probe's readings over other time windows, from one run (docs/free_surfaces.md, Lobovsky et al.).

  probe_windows.py RUN [--windows 0,1e-3,5e-3] [--probes P1,P2,P3,P4]

RUN is a run directory whose diagnostics.csv has every step (output.diagnostics_every = 1) and its
summary.json the probes' window (observe.probe_window). Each column probe_<name> is the mean of the
sensor's readings over the steps of the last window (observe/probes.cpp: the steps j <= k with
t_j >= t_k - window); the readings of the single steps follow from those means one after the other,

    p_k = n_k m_k - sum of p_j over the other steps of step k's window (n_k steps),

exact for a sensor that starts dry (p = 0 before the flow reaches it). The script averages them again
over each window asked for (0: the single step) and prints each probe's largest reading, its time and
its time in t sqrt(g/H) (H from --height, 0.3 m for Lobovsky et al.'s column).
"""
import argparse
import csv
import json
import math
import os

import numpy as np


def window_starts(t, window):
    """For each step k, the first step of its window (t_j >= t_k - window, as observe/probes.cpp)."""
    start = np.zeros(len(t), dtype=int)
    a = 0
    for k in range(len(t)):
        while a < k and t[a] < t[k] - window * (1 + 1e-9):
            a += 1
        start[k] = a
    return start


def single_steps(t, means, window):
    """The single steps' readings whose means over `window` are `means` (exact from a dry start)."""
    start = window_starts(t, window)
    p = np.zeros(len(t))
    for k in range(len(t)):
        n = k - start[k] + 1
        p[k] = n * means[k] - p[start[k]:k].sum()
    return p


def window_means(t, p, window):
    """The means of the readings p over `window` (the probes' rule; 0: p itself)."""
    if window == 0:
        return p.copy()
    start = window_starts(t, window)
    c = np.concatenate(([0.0], np.cumsum(p)))
    idx = np.arange(len(t))
    return (c[idx + 1] - c[start]) / (idx - start + 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--windows", default="0,1e-3,5e-3", help="windows in seconds (0: the single step)")
    ap.add_argument("--probes", default="P1,P2,P3,P4")
    ap.add_argument("--height", type=float, default=0.3, help="the column's height H for t sqrt(g/H), m")
    a = ap.parse_args()
    with open(os.path.join(a.run, "summary.json")) as f:
        window = float(json.load(f)["probe_window"])
    with open(os.path.join(a.run, "diagnostics.csv")) as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["t"]) for r in rows])
    if len(t) > 2 and np.max(np.diff(t)) > 1.5 * np.median(np.diff(t)):
        raise SystemExit(f"{a.run}: diagnostics.csv misses steps (output.diagnostics_every must be 1)")
    scale = math.sqrt(9.81 / a.height)
    print(f"{a.run}: {len(t)} steps, the run's window {window:g} s")
    for name in a.probes.split(","):
        col = "probe_" + name
        if col not in rows[0]:
            raise SystemExit(f"{a.run}: no column {col} in diagnostics.csv")
        p = single_steps(t, np.array([float(r[col]) for r in rows]), window)
        for w in (float(x) for x in a.windows.split(",")):
            m = window_means(t, p, w)
            k = int(np.argmax(m))
            print(f"  {name} window {w:g} s: peak {m[k]:.0f} Pa at t = {t[k]:.5f} s (t sqrt(g/H) = {t[k] * scale:.3f})")


if __name__ == "__main__":
    main()
