#!/usr/bin/python3
"""Figures of the membrane validation gallery (docs/membrane_validation.md), from bench_out/.

  plot_membrane_validation.py rbc RUN_AXIS RUN_OFFSET [--out docs]   red-cell shapes and velocities
  plot_membrane_validation.py capsule DIR [--out docs]                D against Ca_b (bench_out/capsule_bending)
  plot_membrane_validation.py relaxation DIR [--out docs]             a_n(t) and rates (bench_out/relaxation)
  plot_membrane_validation.py period DIR [--out docs]                 period against h* (bench_out/oscillation_period)

Each writes PNG files into --out and prints the numbers it plotted.
"""
import argparse
import csv
import json
import math
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import membrane_theory  # noqa: E402


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def series(run_dir):
    rows = read_csv(os.path.join(run_dir, "diagnostics.csv"))
    return {k: np.array([float(r[k]) if r[k] != "" else np.nan for r in rows]) for k in rows[0]}


def rbc(a):
    fig, axes = plt.subplots(1, 2, figsize=(9, 4.2))
    for ax, run, label in zip(axes, a.runs, ["on the axis", "off the axis"]):
        with h5py.File(os.path.join(run, "output.h5"), "r") as h5:
            snaps = sorted(h5["snapshots"])
            times = [h5["snapshots"][s].attrs["time"] for s in snaps]
            X0 = h5["snapshots"][snaps[0]]["membrane_0"]["X"][()]
            XN = h5["snapshots"][snaps[-1]]["membrane_0"]["X"][()]
        d = series(run)
        t, cx = d["t"], d["m0_cx"]
        half = t >= 0.5 * t[-1]
        U = np.polyfit(t[half], cx[half], 1)[0]  # the cell's mean velocity over the second half
        for X, style, what in ((X0, "--", "t = 0"), (XN, "-", "t = %g" % times[-1])):
            c = X.mean(axis=0)
            Xc = np.vstack([X, X[:1]])
            ax.plot(Xc[:, 0] - c[0], Xc[:, 1], style, color="k" if style == "-" else "0.5", label=what)
        ax.axhline(1, color="0.3", lw=2)
        ax.axhline(-1, color="0.3", lw=2)
        ax.annotate("", xy=(0.55, -0.85), xytext=(0.25, -0.85), arrowprops=dict(arrowstyle="->"))
        ax.text(0.25, -0.8, "flow", fontsize=8)
        ax.set_aspect("equal")
        ax.set_xlim(-0.8, 0.8)
        ax.set_ylim(-1.05, 1.05)
        ax.set_xlabel("x - x_c")
        ax.set_title("%s: cell velocity %.3f (centreline 3)" % (label, U), fontsize=9)
        ax.legend(fontsize=7, loc="upper left")
        print(f"{run}: mean cell velocity over t >= {0.5 * t[-1]:g}: {U:.4f} (U/U_centreline {U / 3:.4f}), "
              f"final centroid y {d['m0_cy'][-1]:.4f}, D {d['m0_D'][-1]:.4f}, area error {d['m0_area_rel_error'][-1]:.2e}")
    axes[0].set_ylabel("y")
    fig.tight_layout()
    out = os.path.join(a.out, "membrane_rbc_channel.png")
    fig.savefig(out, dpi=110)
    print("wrote", out)


def capsule(a):
    fig, ax = plt.subplots(figsize=(5.5, 4))
    cab = np.logspace(-2.5, 0.5, 100)
    ax.plot(cab, [membrane_theory.capsule(c)[0] / c for c in cab], "k-", label="theory (unbounded)")
    for name, style, label in (("ca_H2", "o", "H = 2 (2 r0/H = 0.4)"), ("ca_H4", "s", "H = 4 (0.2)"),
                               ("ca_H8", "^", "H = 8 (0.1)")):
        f = os.path.join(a.dir, name, "table.csv")
        if not os.path.exists(f):
            continue
        rows = read_csv(f)
        x = np.array([float(r["Ca_b"]) for r in rows])
        y = np.array([float(r["D"]) for r in rows]) / x
        ax.plot(x, y, style, label=label)
        for r in rows:
            print(f"{name}: Ca_b {float(r['Ca_b']):g} D {float(r['D']):.5f} D/Ca_b {float(r['D']) / float(r['Ca_b']):.4f} "
                  f"D/D_lin {float(r['D']) / float(r['D_lin']):.4f} theta {float(r['theta_deg']):.2f} "
                  f"(theory {float(r['theta_lin_deg']):.2f})")
    ax.set_xscale("log")
    ax.set_xlabel("Ca_b = mu G r0^3 / Eb")
    ax.set_ylabel("D / Ca_b")
    ax.set_title("capsule with bending in shear (Skalak, 64 x 32 per H = 2)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    out = os.path.join(a.out, "membrane_capsule_D.png")
    fig.savefig(out, dpi=110)
    print("wrote", out)


def relaxation(a):
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
    for ax, n in zip(axes, (2, 3)):
        for nx in (32, 64, 128, 256):
            run = os.path.join(a.dir, "L4", f"n{n}_nx{nx}")
            if not os.path.exists(os.path.join(run, "diagnostics.csv")):
                continue
            d = series(run)
            ax.semilogy(d["t"], d["a_n"] / d["a_n"][0], label=f"{nx}^2")
        sigma = membrane_theory.stokes_rates(n, 0.5, 1.0, 40.0, 0.0, 0.1)[0]
        t = np.linspace(0, 3.5 / sigma, 50)
        ax.semilogy(t, np.exp(-sigma * t), "k--", label=f"Stokes theory, rate {sigma:g}")
        ax.set_xlabel("t")
        ax.set_ylabel("a_%d / a_%d(0)" % (n, n))
        ax.set_title(f"mode {n} (L = 4)", fontsize=9)
        ax.legend(fontsize=7)
    fig.tight_layout()
    out = os.path.join(a.out, "membrane_relaxation.png")
    fig.savefig(out, dpi=110)
    print("wrote", out)


def period(a):
    def rows(name):
        f = os.path.join(a.dir, name, "sweep.csv")
        return read_csv(f) if os.path.exists(f) else []

    fig, ax = plt.subplots(figsize=(5.5, 4))
    for name, label, style, L in (("hs_dx", "h* = 1.68 dx (the scene's)", "o-", 3.0),
                                  ("hs_fixed", "h* = 0.0788 fixed, dx smaller", "s", 3.0),
                                  ("hs_half", "h* = 0.0394 at 256^2", "D", 3.0),
                                  ("small", "amplitude 0.63: h* = 1.68 dx", "v-", 3.0),
                                  ("domain6_small_conv", "amplitude 0.63, domain 6 x 6", "^-", 6.0)):
        r = rows(name)
        if not r:
            continue
        hs = []
        for x in r:
            nx = float(x["grid.nx"])
            h = float(x["membrane.h_star"]) if "membrane.h_star" in x and x["membrane.h_star"] else 1.68 * L / nx
            hs.append(h)
        P = [float(x["period"]) for x in r]
        ax.plot(hs, P, style, label=label)
        print(name, " ".join(f"h*={h:.4g}: {p:.4f}" for h, p in zip(hs, P)))
    R = math.sqrt(0.75 * 0.5)  # the circle of the ellipse's area (both amplitudes: area 0.375 pi)
    lam = R / 0.5
    s = membrane_theory.root(2, R, 0.1, 1.0, 10 * lam, 10 * (lam - 1), 0.0, complex(-1, 4))
    ax.axhline(2 * math.pi / abs(s.imag), color="k", ls="--", lw=1)
    ax.text(0.002, 2 * math.pi / abs(s.imag) - 0.012, "linear theory, unbounded: %.4f" % (2 * math.pi / abs(s.imag)),
            fontsize=8)
    ax.set_xscale("log")
    ax.set_xlabel("h*")
    ax.set_ylabel("period")
    ax.legend(fontsize=7)
    fig.tight_layout()
    out = os.path.join(a.out, "membrane_oscillation_period.png")
    fig.savefig(out, dpi=110)
    print("wrote", out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["rbc", "capsule", "relaxation", "period"])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "docs"))
    a = ap.parse_args()
    a.dir = a.runs[0]
    {"rbc": rbc, "capsule": capsule, "relaxation": relaxation, "period": period}[a.what](a)


if __name__ == "__main__":
    main()
