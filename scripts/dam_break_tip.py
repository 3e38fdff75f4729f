#!/usr/bin/python3
"""The dam break's leading edge in snapshots (docs/free_surfaces.md, "Dam break: the surge front").

    /usr/bin/python3 scripts/dam_break_tip.py [--T 0.5,1,1.5] [--lead 8] RUN...

For each run and each T = t sqrt(2g/a) asked for, the snapshot nearest it (its own T is printed):
the leading particles of the floor band (within 2 dy of the floor), each with its x, its height,
its number of neighbours within the kernel's support 2h, u, v and p; the mean u of the particles
0-10 dx and 10-30 dx behind the leading one, row by row from the floor (rows dy apart); then the front Z = x/a by
several measures:
  support1   the solvers' front_x: the farthest particle of the floor band with another particle
             within 2h, plus dx/2;
  supportK   the same with at least K other particles within 2h (K = 4, 8);
  depth D    the farthest x at which the water layer is at least D deep, the layer's depth at x being
             the particles' area (n dx dy) in the strip of width dx around x over dx; D = 2 dx, and
             the fixed depths 2 mm and 5 mm (a leading edge seen in a photograph is a layer of some
             thickness, not a particle).
Snapshots come from output.times (e.g. --set 'output.times=[0.0431,0.0863,0.1294]').
With --first: the pressure and the face's horizontal acceleration of the first step against the
incompressible column released from rest (initial_field: p at t = 0+ solves Laplace's equation in
the column [0, a] x [0, H] with p = 0 on the face x = a and the top y = H, dp/dx = 0 on the wall behind
and dp/dy = -rho g on the floor; the series below), from a run with a snapshot at every step (e.g.
--set time.end=1.5e-3 --set output.interval=1.5e-4 --set 'output.times=[]').
With --curve: Z(T) of the solvers' front_x (diagnostics.csv) at T = 0.25, 0.5, ..., 3 beside the
experiments' (interpolated; "-" outside their points), and dZ/dT over T = 0.5-1.5 and 1.5-2.5.
With --rms: the rms of Z - Z_exp against each experiment (as scripts/dam_break_front.py, up to
Z = 3.5) of the front by each measure over every snapshot of the run (e.g. output.interval = 0.005).
"""
import argparse
import os
import sys

import numpy as np
import h5py

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot import attr, read_csv, read_front_reference, reference_dir, require  # noqa: E402
from dam_break_front import NAMES, rms_against  # noqa: E402


def neighbour_counts(x, y, idx, reach):
    """The number of other particles within reach of each particle idx."""
    out = []
    for i in idx:
        d2 = (x - x[i]) ** 2 + (y - y[i]) ** 2
        out.append(int(np.count_nonzero(d2 < reach * reach)) - 1)
    return np.array(out, int)


def depth_front(x, dx, dy, depth, x0):
    """The farthest x (strip centre + dx/2) whose strip of width dx holds an area of at least depth * dx."""
    k = np.floor((x - x0) / dx).astype(int)
    n = np.bincount(k[k >= 0])
    ok = np.nonzero(n * dy >= depth * (1 - 1e-9))[0]
    return x0 + (ok[-1] + 1) * dx if len(ok) else float("nan")


def initial_field(x, y, a, H, g, rho, terms=4000):
    """p and the horizontal acceleration at t = 0+ of a column [0, a] x [0, H] released from rest.

    p = rho g (H - y) + q, q = -rho g sum_n c_n cosh(k_n x) / cosh(k_n a) cos(k_n y), k_n = (2n - 1) pi / (2H):
    cos(k_n y) gives q = 0 at y = H and dq/dy = 0 on the floor, cosh(k_n x) dq/dx = 0 at x = 0, and
    c_n = 2 / (H k_n^2), the cosine coefficients of H - y on [0, H], gives p = 0 on the face x = a.
    a_x = -(1/rho) dp/dx = g sum_n 2 / (H k_n) sinh(k_n x) / cosh(k_n a) cos(k_n y); for a -> infinity on the
    face it sums to (2g/pi) ln cot(pi y / 4H), infinite at the toe y = 0.
    """
    k = (2 * np.arange(1, terms + 1) - 1) * np.pi / (2 * H)
    p, ax = np.empty(len(x)), np.empty(len(x))
    for i, (xi, yi) in enumerate(zip(x, y)):
        e = np.exp(k * (xi - a)) / (1 + np.exp(-2 * k * a))  # cosh(k x) / cosh(k a) without overflow, times 2 / (1 + e^(-2kx))
        c = np.cos(k * yi)
        p[i] = rho * g * ((H - yi) - np.sum(2 / (H * k * k) * e * (1 + np.exp(-2 * k * xi)) * c))
        ax[i] = g * np.sum(2 / (H * k) * e * (1 - np.exp(-2 * k * xi)) * c)
    return p, ax


def first_step(h5, a, H, g, rho, dx):
    """The first step's p and the face column's u / t against initial_field, printed."""
    names = sorted(h5["snapshots"].keys())
    s0, s1 = h5["snapshots"][names[0]], h5["snapshots"][names[1]]
    x, y, t = s0["x"][()], s0["y"][()], float(s1.attrs["time"])
    pe, ae = initial_field(x, y, a, H, g, rho)
    err = s1["p"][()] - pe
    print("  t = %.3g s (step %d): p - p_exact: rms %.4f, max %.4f rho g H" % (
        t, int(s1.attrs.get("step", -1)), np.sqrt(np.mean(err ** 2)) / (rho * g * H), np.abs(err).max() / (rho * g * H)))
    face = np.nonzero(x > x.max() - 0.5 * dx)[0]
    face = face[np.argsort(y[face])]
    u = s1["u"][()]
    for i in face[[k for k in (0, 1, 2, 4, 9, 19, 49, 79) if k < len(face)]]:
        print("    face particle at y/H = %.3f: u/t = %7.2f m/s^2, exact a_x %6.2f" % (y[i] / H, u[i] / t, ae[i]))


def measures(x, y, dx, dy, reach, x0, y0):
    band = np.nonzero(y - y0 < 2 * dy)[0]
    order = band[np.argsort(-x[band])]
    nb = neighbour_counts(x, y, order, reach)
    out = {}
    for K in (1, 4, 8):
        hit = order[nb >= K]
        out["support%d" % K] = (x[hit[0]] if len(hit) else x[order[0]]) + 0.5 * dx
    for name, D in (("depth 2dx", 2 * dx), ("depth 2mm", 2e-3), ("depth 5mm", 5e-3)):
        out[name] = depth_front(x, dx, dy, D, x0)
    return out, order, nb


CURVE_T = (0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0)


def curve(runs):
    """Z(T) of each run's front_x and of the experiments, at CURVE_T."""
    def row(name, T, Z):
        z = [np.interp(t, T, Z) if T[0] <= t <= T[-1] else np.nan for t in CURVE_T]
        s1, s2 = (np.interp(1.5, T, Z) - np.interp(0.5, T, Z), np.interp(2.5, T, Z) - np.interp(1.5, T, Z))
        print("%-34s %s | %s %s" % (name[-34:], " ".join("  -   " if np.isnan(v) else "%6.3f" % v for v in z),
                                    "  -  " if T[0] > 0.5 else "%5.3f" % s1, "  -  " if T[-1] < 2.5 else "%5.3f" % s2))
    print("%-34s %s | dZ/dT 0.5-1.5, 1.5-2.5" % ("Z at T =", " ".join("%6.2f" % t for t in CURVE_T)))
    ref = None
    for run in runs:
        with h5py.File(require(os.path.join(run, "output.h5")), "r") as h5:
            fx = attr(h5, "fill.x")
            a = float(fx[1]) - float(fx[0])
            g = float(np.hypot(*attr(h5, "fluid.gravity", [0.0, -9.81])))
            ref = ref or reference_dir(h5)
        d = read_csv(require(os.path.join(run, "diagnostics.csv")))
        row(run, d["t"] * np.sqrt(2 * g / a), d["front_x"] / a)
    for n in NAMES:
        e = read_front_reference(os.path.join(ref, "dam_break_front_%s.csv" % n))
        row(n, e[:, 0], e[:, 1])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--T", default="0.5,1,1.5", help="the times T = t sqrt(2g/a), comma-separated")
    ap.add_argument("--lead", type=int, default=8, help="how many leading floor particles to list")
    ap.add_argument("--first", action="store_true", help="the first step against the column released from rest")
    ap.add_argument("--rms", action="store_true", help="the rms against the experiments by each measure")
    ap.add_argument("--curve", action="store_true", help="Z(T) of the runs' front_x beside the experiments'")
    args = ap.parse_args()
    if args.curve:
        return curve(args.runs)
    for run in args.runs:
        with h5py.File(require(os.path.join(run, "output.h5")), "r") as h5:
            fx = attr(h5, "fill.x")
            a = float(fx[1]) - float(fx[0])
            g = float(np.hypot(*attr(h5, "fluid.gravity", [0.0, -9.81])))
            dom_x, dom_y = attr(h5, "domain.x"), attr(h5, "domain.y")
            nx, ny = int(attr(h5, "grid.nx")), int(attr(h5, "grid.ny"))
            dx, dy = (dom_x[1] - dom_x[0]) / nx, (dom_y[1] - dom_y[0]) / ny
            hdx = float(attr(h5, "kernel.h_over_dx", 1.3))
            reach = 2 * hdx * dx
            scale = np.sqrt(2 * g / a)
            names = sorted(h5["snapshots"].keys())
            times = np.array([float(h5["snapshots"][n].attrs["time"]) for n in names])
            print("%s: a = %.4g m, dx = %.4g m, 2h = %.4g m" % (run, a, dx, reach))
            if args.first:
                fy = attr(h5, "fill.y")
                first_step(h5, a, float(fy[1]) - float(fy[0]), g, float(attr(h5, "fluid.rho", 1000.0)), dx)
                continue
            if args.rms:
                exps = [read_front_reference(os.path.join(reference_dir(h5), "dam_break_front_%s.csv" % n)) for n in NAMES]
                rows = [measures(h5["snapshots"][n]["x"][()], h5["snapshots"][n]["y"][()], dx, dy, reach, dom_x[0],
                                 dom_y[0])[0] for n in names]
                for m in rows[0]:
                    Z = np.array([(r[m] - dom_x[0]) / a for r in rows])
                    print("  %-10s rms %s (%d snapshots)" % (m, " ".join("%.3f" % rms_against(times * scale, Z, e)
                                                                     for e in exps), len(names)))
            for T in (float(s) for s in args.T.split(",")):
                k = int(np.argmin(np.abs(times * scale - T)))
                s = h5["snapshots"][names[k]]
                x, y = s["x"][()], s["y"][()]
                m, order, nb = measures(x, y, dx, dy, reach, dom_x[0], dom_y[0])
                print("  T = %.3f (t = %.4f s): Z by %s" % (times[k] * scale, times[k], ", ".join(
                    "%s %.3f" % (n, (v - dom_x[0]) / a) for n, v in m.items())))
                cols = {c: s[c][()] for c in ("u", "v", "p") if c in s}
                if "u" in cols:
                    tipx = x[order[0]]
                    for lo, hi in ((0, 10), (10, 30)):
                        rows = []
                        for r in range(4):
                            m = ((x <= tipx - lo * dx) & (x > tipx - hi * dx) & (y - dom_y[0] >= r * dy)
                                 & (y - dom_y[0] < (r + 1) * dy))
                            rows.append("%.3f (%d)" % (cols["u"][m].mean(), m.sum()) if m.any() else "-")
                        print("    mean u %d-%d dx behind the tip, rows 1-4 from the floor (particles): %s"
                              % (lo, hi, ", ".join(rows)))
                print("    leading floor-band particles: (x - x_lead)/dx, y/dy, neighbours within 2h, u, v, p")
                for i, nbi in zip(order[:args.lead], nb[:args.lead]):
                    print("      %6.2f %5.2f %3d %s" % ((x[i] - x[order[0]]) / dx, (y[i] - dom_y[0]) / dy, nbi,
                                                    " ".join("%9.3f" % cols[c][i] for c in cols)))


if __name__ == "__main__":
    main()
