#!/usr/bin/env python3
"""Tank-treading or tumbling of the vesicle of cases/vesicle_shear.toml, read from runs' diagnostics.csv.

For each run directory: the inclination theta(t) of membrane 0 (m0_inclination, the ellipse of the
same second moments of area, unwrapped modulo 180 degrees), its motion and, against the 2-D
fixed-shape models (scripts/vesicle_theory.py), the angle or the verdict.

  tumbling      theta fell by more than 90 degrees during the run; the period is the time between
                the last two crossings of theta = -90 k degrees (n/a if fewer than two);
  tank-treading otherwise; theta_TT is the mean over the last quarter, with its standard deviation
                and its drift (last - first value of that quarter) as the test of steadiness;
  not settled   no fall of 90 degrees, but a drift over the last quarter above 1 degree.

omega is the diagnostics' m0_omega (the markers' mean angular velocity from their velocities) over the
last quarter; omega_X, when output.h5 holds at least three snapshots in the last half of the run
(output.interval), is the same rate measured from the markers' positions only: each marker's polar
angle about the centroid of the enclosed polygon, unwrapped, fitted by a line in time, averaged
over the markers.

  vesicle_shear.py RUN_DIR ... [--csv FILE] [--plot PNG] [--nu NU] [--reference CSV]

--plot draws theta(t) of the runs and the tank-treading angle against lambda beside the 2-D
fixed-ellipse models; it reads the lattice and lambda from run names nNX_lLAMBDA (H4_ or H8_ in front: the
wider channels; a suffix _tT for a longer run, which then stands for its lambda), as
bench/validate.sh vesicle_shear names them. --nu sets the reduced area of the plot's models (0.8,
the scene's). --reference reads a published curve (a CSV of viscosity_contrast and beta_rad, e.g.
cases/reference/quaife_biros_vesicle_inclination_ra066.csv): each tank-treading run named .._lLAMBDA
gets the curve's angle at its lambda (linear interpolation; none beyond the curve's last point) and
the difference, and the plot draws the curve.
"""
import argparse
import csv
import json
import math
import os
import re
import sys

import numpy as np


def analyse(run):
    path = os.path.join(run, "diagnostics.csv")
    partial = not os.path.exists(path) and os.path.exists(path + ".part")  # a run still going
    with open(path + ".part" if partial else path) as f:
        rows = list(csv.DictReader(f))[: -1 if partial else None]
    if len(rows) < 2:
        return {"run": run, "motion": "(no rows yet)"}
    t = np.array([float(r["t"]) for r in rows])
    th = np.array([float(r["m0_inclination"]) for r in rows])
    th = np.unwrap(2 * th) / 2  # the axis is defined modulo pi
    th_deg = np.degrees(th)
    om = np.array([float(r["m0_omega"]) for r in rows])
    D = np.array([float(r["m0_D"]) for r in rows])
    area = np.array([float(r["m0_area_rel_error"]) for r in rows])
    strain = np.array([float(r["m0_strain_max"]) for r in rows])
    A = np.array([float(r["m0_area"]) for r in rows])
    L = np.array([float(r["m0_length"]) for r in rows])
    nu = 4 * np.pi * A / L ** 2  # the reduced area the run actually has (the penalty lets the length drift)
    q = t >= 0.75 * t[-1]
    out = {"run": run + (" (running)" if partial else ""), "t_end": float(t[-1]), "area_rel_error_end": float(area[-1]),
           "strain_max_end": float(strain[-1]), "D_end": float(D[-1]),
           "nu_start": float(nu[0]), "nu_end": float(nu[-1])}
    fall = th_deg[0] - th_deg.min()
    if fall > 90.0:
        # crossings of -90 k (k = 1, 2, ...)
        k = np.floor(-(th_deg - th_deg[0]) / 180.0 + 0.5)  # half-turn count past -90, -270, ...
        cross = [t[i] for i in range(1, len(t)) if k[i] > k[i - 1]]
        out["motion"] = "tumbling"
        out["first_minus90_time"] = float(cross[0]) if cross else float("nan")
        out["period"] = float(cross[-1] - cross[-2]) if len(cross) >= 2 else float("nan")
        out["turns_half"] = len(cross)
    else:
        out["motion"] = "tank-treading"
        out["theta_deg"] = float(th_deg[q].mean())
        out["theta_sd_deg"] = float(th_deg[q].std())
        out["theta_drift_deg"] = float(th_deg[q][-1] - th_deg[q][0])
        out["omega"] = float(om[q].mean())
        out["D"] = float(D[q].mean())
        out["theta_min_deg"] = float(th_deg.min())
        if abs(out["theta_drift_deg"]) > 1.0:  # still turning: neither verdict yet
            out["motion"] = "not settled"
    wx = omega_from_positions(run)
    if wx is not None:
        out["omega_X"] = wx
    try:
        with open(os.path.join(run, "summary.json")) as f:
            s = json.load(f)
        out["wall_seconds"] = s.get("wall_seconds", float("nan"))
    except OSError:
        pass
    return out


def omega_from_positions(run):
    """The markers' mean angular velocity from the positions of membrane 0 in output.h5's snapshots of
    the last half of the run (None without h5py or with fewer than three)."""
    path = os.path.join(run, "output.h5")
    try:
        import h5py
    except ImportError:
        return None
    if not os.path.exists(path):
        return None
    with h5py.File(path, "r") as f:
        snaps = [f["snapshots"][k] for k in sorted(f["snapshots"].keys())]
        t = np.array([float(g.attrs["time"]) for g in snaps])
        keep = t >= 0.5 * t[-1]
        if keep.sum() < 3:
            return None
        ang = []
        for g, k in zip(snaps, keep):
            if not k:
                continue
            X = g["membrane_0"]["X"][()]
            x, y = X[:, 0], X[:, 1]
            x1, y1 = np.roll(x, -1), np.roll(y, -1)
            cr = x * y1 - x1 * y
            A = 0.5 * cr.sum()
            cx, cy = ((x + x1) * cr).sum() / (6 * A), ((y + y1) * cr).sum() / (6 * A)
            ang.append(np.arctan2(y - cy, x - cx))
    ang = np.unwrap(np.array(ang), axis=0)  # snapshots closer than half a turn of a marker
    return float(np.polyfit(t[keep], ang, 1)[0].mean())


def read_reference(path):
    """A published curve: (lambda, angle in degrees) from a CSV with columns viscosity_contrast, beta_rad
    (lines starting with # are its source)."""
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    lam = np.array([float(r["viscosity_contrast"]) for r in rows])
    return lam, np.degrees([float(r["beta_rad"]) for r in rows])


def run_lambda(run):
    m = re.search(r"_l([\d.]+)(?:_t\d+)?$", os.path.basename(os.path.normpath(run)))
    return float(m.group(1)) if m else None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--csv", help="write the table here too")
    ap.add_argument("--plot", help="write the figure here (PNG)")
    ap.add_argument("--nu", type=float, default=0.8, help="the reduced area of the plot's models")
    ap.add_argument("--reference", help="a published curve: CSV of viscosity_contrast, beta_rad")
    a = ap.parse_args()
    ref = read_reference(a.reference) if a.reference else None
    runs = [r for r in a.runs if os.path.exists(os.path.join(r, "diagnostics.csv")) or
            os.path.exists(os.path.join(r, "diagnostics.csv.part"))]
    for r in sorted(set(a.runs) - set(runs)):
        print(f"run={r}  (no diagnostics yet)")
    res = [analyse(r) for r in runs]
    if ref is not None:
        for run, r in zip(runs, res):
            lam = run_lambda(run)
            if lam is not None and ref[0][0] <= lam <= ref[0][-1]:
                r["theta_ref_deg"] = float(np.interp(lam, *ref))
                if "theta_deg" in r:
                    r["theta_minus_ref_deg"] = r["theta_deg"] - r["theta_ref_deg"]
    keys = ["run", "motion", "nu_start", "nu_end", "theta_deg", "theta_ref_deg", "theta_minus_ref_deg", "theta_sd_deg", "theta_drift_deg", "theta_min_deg", "omega", "omega_X", "D",
            "first_minus90_time", "period", "area_rel_error_end", "strain_max_end", "t_end", "wall_seconds"]
    for r in res:
        line = []
        for k in keys:
            if k not in r:
                continue
            v = r[k]
            line.append(f"{k}={v:.5g}" if isinstance(v, float) else f"{k}={v}")
        print("  ".join(line))
    if a.plot:
        plot(runs, res, a.plot, a.nu, ref)
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
            w.writeheader()
            for r in res:
                w.writerow(r)


def plot(runs, res, png, nu=0.8, ref=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import vesicle_theory as vt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    groups = {}
    for run, r in zip(runs, res):
        if "t_end" not in r:
            continue
        m = re.fullmatch(r"(?:H(\d+)_)?n(\d+)_l([\d.]+)(_t\d+)?", os.path.basename(os.path.normpath(run)))
        if not m:
            continue
        key = f"{m.group(2)} x {int(m.group(2)) // 2}" + (f" spacing, H = {m.group(1)}" if m.group(1) else "")
        groups.setdefault(key, []).append((float(m.group(3)), r, run))
    for key in groups:  # one run per lambda: the longest
        best = {}
        for lam, r, run in groups[key]:
            if lam not in best or r["t_end"] > best[lam][1]["t_end"]:
                best[lam] = (lam, r, run)
        groups[key] = list(best.values())
    finest = max(groups, key=lambda k: len(groups[k]))  # the lambda sweep
    for lam, r, run in sorted(groups[finest]):
        with open(os.path.join(run, "diagnostics.csv")) as f:
            rows = list(csv.DictReader(f))
        t = [float(x["t"]) for x in rows]
        th = np.degrees(np.unwrap(2 * np.array([float(x["m0_inclination"]) for x in rows])) / 2)
        ax1.plot(t, th, label=f"lambda = {lam:g}")
    ax1.set_xlabel("G t")
    ax1.set_ylabel("inclination (degrees)")
    ax1.set_title(f"inclination, {finest}, H = 2")
    ax1.legend(fontsize=8)
    a, b = vt.axes_for_reduced_area(nu)
    for field, style, name in (("inextensible", "k-", "fixed ellipse, inextensible membrane"),
                               ("ks", "k--", "fixed ellipse, Keller-Skalak field")):
        lc = vt.lambda_c(a, b, field)
        lams = np.linspace(0.5, lc, 60)
        th = [0.5 * np.degrees(np.arccos(min(1.0, 1.0 / vt.coefficients(a, b, l, field)[0]))) for l in lams]
        ax2.plot(lams, th, style, label=name + ", unbounded")
        ax2.axvline(lc, color="k", ls=":", lw=0.8)
    if ref is not None:
        ax2.plot(ref[0], ref[1], "r-", lw=2, alpha=0.6, label="published (boundary integral), unbounded")
    def order(k):  # the scene's channel first, then the wider ones; coarse lattices first
        return (int(k.split("H = ")[1]) if "H = " in k else 0, int(k.split()[0]))

    for key, marker in zip(sorted(groups, key=order), "osd^v"):
        pts = sorted(groups[key])
        tt = [(l, r["theta_deg"]) for l, r, _ in pts if r["motion"] == "tank-treading"]
        tu = [l for l, r, _ in pts if r["motion"] == "tumbling"]
        line, = ax2.plot([p[0] for p in tt], [p[1] for p in tt], marker + "-", label=key)
        if tu:
            ax2.plot(tu, [0.0] * len(tu), marker, mfc="none", color=line.get_color())
    ax2.axhline(0.0, color="k", lw=0.5)
    ax2.set_xlabel("lambda = mu_in / mu_out")
    ax2.set_ylabel("tank-treading angle (degrees); open at 0: tumbling")
    ax2.set_title(f"nu = {nu:g}; confinement 2 R0/H: 0.4 (H = 2), 0.2, 0.1")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main()
