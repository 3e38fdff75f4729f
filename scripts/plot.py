#!/usr/bin/python3
"""PNG plots of an sphib run from its HDF5 output, CSV diagnostics and JSON summary.

    plot.py RUN_DIR             reads RUN_DIR/output.h5, RUN_DIR/diagnostics.csv and, if present,
                                RUN_DIR/summary.json; writes PNGs into RUN_DIR
    plot.py --sweep SWEEP_CSV   log-log plot of every *_error column against nx -> SWEEP.png

HDF5 layout read here (written by io/hdf5_writer): /snapshots/NNNNNN with attributes time, step,
datasets x, y and particle scalars, subgroups membrane_k with X (nb x 2); root attributes hold
the run parameters (e.g. derived.membrane_radius, and every scene key as TOML text).

Free-surface runs (a partly filled tank or open sides) draw their particles as dots coloured by
pressure (snapshot_*.png, every time of output.times among them), and, when their series have
them: the wall loads (loads.png, Afanasiev et al. Eq. 31), the droplet's semi-axis against the RK4
solution (droplet_axis.png), the dam-break front against the experiments of cases/reference
(dam_break_front.png), the inclined plane's velocity profile against Eq. (39) (velocity_profile.png).
"""
import ast
import argparse
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

try:
    import h5py  # noqa: E402
except ImportError:  # pragma: no cover
    sys.exit("plot.py: h5py is missing (Debian: apt-get install python3-h5py)")

N_SNAPSHOT_PLOTS = 4   # the last snapshot and up to three evenly spaced earlier ones
MAX_ARROWS = 600       # quiver arrows per snapshot plot


def fail(msg):
    sys.exit("plot.py: " + msg)


def require(path):
    if not os.path.isfile(path):
        hint = ""
        if os.path.isfile(path + ".part"):
            hint = " (only %s.part exists: the run is still going or was killed)" % path
        fail("missing file %s%s" % (path, hint))
    return path


# ---------------------------------------------------------------------------------------------
# Reading

def read_csv(path):
    """Columns of a CSV with a header row, as {name: float array}."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        fail("%s is empty (no header row)" % path)
    header = [h.strip() for h in rows[0]]
    body = [r for r in rows[1:] if r]
    data = np.full((len(body), len(header)), np.nan)
    for i, r in enumerate(body):
        for j, cell in enumerate(r[:len(header)]):
            try:
                data[i, j] = float(cell)
            except ValueError:
                pass
    return {name: data[:, j] for j, name in enumerate(header)}


def read_summary(run_dir):
    path = os.path.join(run_dir, "summary.json")
    if not os.path.isfile(path):
        return {}
    with open(path) as f:
        return json.load(f)


class Snapshot:
    def __init__(self, group):
        self.name = group.name.rsplit("/", 1)[-1]
        self.t = float(group.attrs.get("time", np.nan))
        self.step = int(group.attrs.get("step", -1))
        self.x = group["x"][()]
        self.y = group["y"][()]
        self.scalars = {k: v[()] for k, v in group.items()
                        if isinstance(v, h5py.Dataset) and v.ndim == 1 and k not in ("x", "y")}
        self.membranes = []
        for k in sorted((k for k in group if k.startswith("membrane_")),
                        key=lambda s: int(s.split("_")[1])):
            self.membranes.append(group[k]["X"][()])


def attr(h5, key, default=None):
    """A scene key from the root attributes (TOML text) as a Python value."""
    if key not in h5.attrs:
        return default
    v = h5.attrs[key]
    v = v.decode() if isinstance(v, bytes) else str(v)
    try:
        return ast.literal_eval(v.replace("true", "True").replace("false", "False"))
    except (ValueError, SyntaxError):
        return v


def si_units(h5):
    """Axis units for a run in SI units (water's density of 1000 or gravity of 9.81: the cases of
    Afanasiev et al. and Vukcevic et al.), else none: the other cases are dimensionless."""
    try:
        si = abs(float(np.hypot(*attr(h5, "fluid.gravity", [0.0, 0.0]))) - 9.81) < 0.01 or \
            abs(float(attr(h5, "fluid.rho", 1.0)) - 1000.0) < 1e-9
    except (TypeError, ValueError):
        si = False
    if not si:
        return {k: "" for k in ("t", "x", "p", "u", "load", "energy")}
    return {"t": " (s)", "x": " (m)", "p": " (Pa)", "u": " (m/s)", "load": " (N/m)", "energy": " (J/m)"}


def readable(column):
    """A diagnostics column's name as a legend says it: m0_rx -> 'rx, membrane 0'."""
    names = {"rx": "half-chord rx", "ry": "half-chord ry", "area_rel_error": "relative area error",
             "elastic_energy": "elastic energy", "kinetic_energy": "kinetic energy", "cx": "centroid x",
             "cy": "centroid y", "rms_error": "rms error (Eq. 69)", "max_speed": "max |u|"}
    if column.startswith("m") and "_" in column and column[1:column.index("_")].isdigit():
        k, rest = column[1:column.index("_")], column[column.index("_") + 1:]
        return "%s, membrane %s" % (names.get(rest, rest.replace("_", " ")), k)
    if column.startswith("load_"):
        return column[5:] + " wall"
    return names.get(column, column.replace("_", " "))


def reference_speed(speed):
    """A round speed near `speed` (1, 2 or 5 times a power of ten) for the reference arrow."""
    if not (speed > 0 and math.isfinite(speed)):
        return 0.0
    e = math.floor(math.log10(speed))
    for m in (5, 2, 1):
        if m * 10 ** e <= speed:
            return m * 10 ** e
    return 10 ** e


def free_surface_run(h5):
    return attr(h5, "fill.shape", "domain") != "domain" or bool(attr(h5, "domain.open", []))


def snapshot_names(h5):
    if "snapshots" not in h5:
        return []
    return sorted(h5["snapshots"].keys())


def pick_evenly(n, k):
    """Up to k indices out of range(n), evenly spaced, always including the last."""
    if n == 0:
        return []
    return sorted(set(int(round(i)) for i in np.linspace(n - 1, 0, min(n, k))))


# ---------------------------------------------------------------------------------------------
# Geometry helpers

def lattice(x, y):
    """(ix, iy, xs, ys) if the particles sit on a full tensor-product lattice, else None."""
    scale = max(np.ptp(x), np.ptp(y), 1e-300)
    xs = np.unique(np.round(x / scale, 9))
    ys = np.unique(np.round(y / scale, 9))
    if len(xs) * len(ys) != len(x) or len(xs) < 2 or len(ys) < 2:
        return None
    ix = np.searchsorted(xs, np.round(x / scale, 9))
    iy = np.searchsorted(ys, np.round(y / scale, 9))
    if len(set(zip(ix.tolist(), iy.tolist()))) != len(x):
        return None
    return ix, iy, xs * scale, ys * scale


def spacing(x, y):
    """Typical particle spacing: lattice step, else median nearest-neighbour distance of a sample."""
    n = len(x)
    if n < 2:
        return 1.0
    grid = lattice(x, y)
    if grid is not None:
        return float(min(np.median(np.diff(grid[2])), np.median(np.diff(grid[3]))))
    nearest = []
    for i in np.linspace(0, n - 1, min(n, 100)).astype(int):  # O(100 N) time, O(N) memory
        d2 = (x - x[i]) ** 2 + (y - y[i]) ** 2
        d2[i] = np.inf
        nearest.append(d2.min())
    return float(np.sqrt(np.median(nearest)))


def closed(X):
    return np.vstack([X, X[:1]])


# ---------------------------------------------------------------------------------------------
# Plots

def save_plane(fig, ax, out, title, unit=""):
    """An x-y picture at equal scales, written to out."""
    ax.set_aspect("equal")
    ax.set_xlabel("x" + unit)
    ax.set_ylabel("y" + unit)
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def plot_particles(s, out, box, walls, units=None):
    """Free surface: every particle a dot coloured by pressure (colours clipped to the 1st-99th
    percentiles: a weakly compressible pressure is noisy). The view: the tank's side where it has a
    wall (walls: left, right, bottom, top booleans), else the particles with a margin."""
    x, y = s.x, s.y
    d = spacing(x, y)
    lim = [box[0] if walls[0] else x.min() - 3 * d, box[1] if walls[1] else x.max() + 3 * d,
           box[2] if walls[2] else y.min() - 3 * d, box[3] if walls[3] else y.max() + 3 * d]
    if not walls[3]:
        lim[3] = min(box[3], y.max() + max(3 * d, 0.15 * (y.max() - lim[2])))
    w, hgt = lim[1] - lim[0], lim[3] - lim[2]
    units = units or {}
    fig, ax = plt.subplots(figsize=(7.0, min(9.0, max(2.5, 6.0 * hgt / w + 1.0))))
    p = s.scalars.get("p")
    size = (72.0 * 6.0 * d / w) ** 2 * 0.7  # dots about one particle spacing across
    if p is not None:
        lo, hi = np.percentile(p, [1, 99])
        im = ax.scatter(x, y, c=p, s=size, cmap="viridis", vmin=lo, vmax=hi, linewidths=0)
        fig.colorbar(im, ax=ax, label="pressure p" + units.get("p", ""))
    else:
        ax.scatter(x, y, s=size, linewidths=0)
    ax.set_xlim(lim[0], lim[1])
    ax.set_ylim(lim[2], lim[3])
    save_plane(fig, ax, out, "t = %.4g%s (step %d): particles coloured by pressure" % (s.t, units.get("t", "").strip(" ()").join("  ").rstrip(), s.step),
               units.get("x", ""))


def plot_snapshot(s, out, u_max=None, units=None):
    """Pressure as a coloured field, velocity as arrows on one scale for the whole run: an arrow of
    the run's largest speed u_max is 1.5 arrow spacings long, and a reference arrow in the corner gives
    the scale (a slow flow draws short arrows, not arrows as long as the fast one's)."""
    units = units or {}
    fig, ax = plt.subplots(figsize=(6.4, 5.8))
    x, y = s.x, s.y
    grid = lattice(x, y)
    p = s.scalars.get("p")
    if p is not None and len(x) > 0:
        if grid is not None:
            ix, iy, xs, ys = grid
            P = np.full((len(ys), len(xs)), np.nan)
            P[iy, ix] = p
            im = ax.pcolormesh(xs, ys, P, shading="nearest", cmap="viridis")
        elif len(x) >= 3:
            im = ax.tricontourf(x, y, p, levels=40, cmap="viridis")
        else:
            im = ax.scatter(x, y, c=p, cmap="viridis")
        fig.colorbar(im, ax=ax, label="pressure p" + units.get("p", ""))
    else:
        ax.plot(x, y, ".", ms=2, color="0.6")
    u, v = s.scalars.get("u"), s.scalars.get("v")
    speed_now = float(np.hypot(u, v).max()) if u is not None and v is not None and len(x) else 0.0
    if u is not None and v is not None and len(x) > 0:
        if grid is not None:
            ix, iy, xs, ys = grid
            stride = max(1, int(math.ceil(math.sqrt(len(x) / MAX_ARROWS))))
            sel = (ix % stride == 0) & (iy % stride == 0)
            arrow_gap = stride * spacing(x, y)
        else:
            sel = np.zeros(len(x), bool)
            sel[::max(1, int(math.ceil(len(x) / MAX_ARROWS)))] = True
            arrow_gap = math.sqrt(np.ptp(x) * np.ptp(y) / max(sel.sum(), 1))
        top = u_max if u_max and u_max > 0 else speed_now
        if top > 0 and np.any(np.hypot(u[sel], v[sel]) > 0):
            q = ax.quiver(x[sel], y[sel], u[sel], v[sel], color="white", edgecolor="black", linewidth=0.3,
                          width=0.004, angles="xy", scale_units="xy", scale=top / (1.5 * arrow_gap))
            ref = reference_speed(top)
            ax.quiverkey(q, 0.74, -0.105, ref, "|u| = %g%s" % (ref, units.get("u", "")), labelpos="E",
                         coordinates="axes", color="black", fontproperties={"size": "small"})
    for k, X in enumerate(s.membranes):
        C = closed(X)
        ax.plot(C[:, 0], C[:, 1], "-", color="red", lw=1.5,
                label="membrane %d" % k if len(s.membranes) > 1 else None)
    if len(s.membranes) > 1:
        ax.legend(loc="upper right", fontsize="small")
    save_plane(fig, ax, out, "t = %.6g%s: pressure, velocity (max |u| = %.3g%s)" % (s.t, units.get("t", "").strip(" ()").join("  ").rstrip(), speed_now, units.get("u", "").strip(" ()").join("  ").rstrip()),
               units.get("x", ""))


def plot_sections(s, radius, jump, out):
    """p along y = 0 and x = 0 (particles within half a spacing), with the exact step."""
    p = s.scalars.get("p")
    if p is None:
        return False
    h = spacing(s.x, s.y)
    centre = s.membranes[0].mean(axis=0) if s.membranes else np.zeros(2)
    r = np.hypot(s.x - centre[0], s.y - centre[1])
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, (along, across, label) in zip(axes, ((s.x, s.y, "y = 0"), (s.y, s.x, "x = 0"))):
        on = np.abs(across) <= 0.5 * h * (1 + 1e-6)
        # a lattice offset by h/2 puts two rows at +-h/2: average them per position
        key = np.round(along[on] / h, 3)
        pos, inv = np.unique(key, return_inverse=True)
        p_mean = np.bincount(inv, weights=p[on]) / np.bincount(inv)
        s_mean = np.bincount(inv, weights=along[on]) / np.bincount(inv)
        rows = int(round(on.sum() / max(len(pos), 1)))
        ax.plot(s_mean, p_mean, ".-", ms=4, lw=0.8,
                label="computed" + (" (mean of %d rows)" % rows if rows > 1 else ""))
        if radius is not None and jump is not None and on.any():
            far = r > radius + 3 * h
            if not far.any():
                far = r > radius
            p_out = float(np.median(p[far])) if far.any() else 0.0
            c, off = (centre[0], centre[1]) if label == "y = 0" else (centre[1], centre[0])
            half = math.sqrt(max(radius ** 2 - off ** 2, 0.0))  # half chord of the circle
            lo, hi = float(along[on].min()), float(along[on].max())
            xs = np.array([lo, c - half, c - half, c + half, c + half, hi])
            ps = np.array([0, 0, 1, 1, 0, 0]) * jump + p_out
            ax.plot(xs, ps, "k--", lw=1, label="exact, jump %.4g" % jump)
        ax.set_xlabel("x" if label == "y = 0" else "y")
        ax.set_title("p along %s, t = %.6g" % (label, s.t))
        ax.grid(alpha=0.3)
        ax.legend(fontsize="small")
    axes[0].set_ylabel("p")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return True


def finish(fig, ax, out, xlabel, ylabel, title):
    """Labels, grid and legend, then the PNG; returns its path."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


def plot_series(cols, names, ylabel, title, out, logy=False):
    """Columns `names` (those present) against t, with readable legend names; False if nothing to draw."""
    t = cols.get("t")
    present = [n for n in names if n in cols]
    if t is None or not present or len(t) == 0:
        return False
    fig, ax = plt.subplots(figsize=(6.4, 4))
    for n in present:
        y = cols[n]
        if logy and np.any(y > 0):
            ax.semilogy(t[y > 0], y[y > 0], label=readable(n))
        else:
            ax.plot(t, y, label=readable(n))
    finish(fig, ax, out, "t", ylabel, title)
    return True


def plot_energies(cols, out, units):
    """Kinetic energy on a log axis in its own panel (it falls by decades while the elastic energy
    sits at a finite rest value), the membranes' elastic energy below it."""
    t = cols.get("t")
    elastic = [c for c in cols if c.startswith("m") and c.endswith("_elastic_energy")]
    if t is None or "kinetic_energy" not in cols or len(t) == 0:
        return False
    fig, axes = plt.subplots(2 if elastic else 1, 1, figsize=(6.4, 6 if elastic else 3.6), sharex=True, squeeze=False)
    ax = axes[0, 0]
    ke = cols["kinetic_energy"]
    pos = ke > 0
    ax.semilogy(t[pos], ke[pos], label="kinetic energy of the fluid")
    ax.set_ylabel("kinetic energy" + units.get("energy", ""))
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small")
    ax.set_title("energies")
    if elastic:
        ax2 = axes[1, 0]
        for c in elastic:
            ax2.plot(t, cols[c], label=readable(c))
        ax2.set_ylabel("elastic energy" + units.get("energy", ""))
        ax2.grid(alpha=0.3)
        ax2.legend(fontsize="small")
    axes[-1, 0].set_xlabel("t" + units.get("t", ""))
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return True


def plot_run(run_dir, n_snapshots=N_SNAPSHOT_PLOTS, compare=None):
    h5_path = require(os.path.join(run_dir, "output.h5"))
    csv_path = require(os.path.join(run_dir, "diagnostics.csv"))
    summary = read_summary(run_dir)
    written = []

    with h5py.File(h5_path, "r") as h5:
        radius = h5.attrs.get("derived.membrane_radius")
        radius = float(radius) if radius is not None else None
        names = snapshot_names(h5)
        if not names:
            print("plot.py: %s has no snapshots" % h5_path, file=sys.stderr)
        free = free_surface_run(h5)
        units = si_units(h5)
        u_max = None  # the run's largest speed: one arrow scale for every snapshot
        diag = read_csv(csv_path)
        if "max_speed" in diag and np.isfinite(diag["max_speed"]).any():
            u_max = float(np.nanmax(diag["max_speed"]))
        box = [float(v) for v in attr(h5, "domain.x", [0, 1]) + attr(h5, "domain.y", [0, 1])]
        opened = attr(h5, "domain.open", [])
        px, py = attr(h5, "domain.periodic_x", True), attr(h5, "domain.periodic_y", False)
        walls = [not px and "left" not in opened, not px and "right" not in opened,
                 not py and "bottom" not in opened, not py and "top" not in opened]
        walls = [w or (k < 2 and px) for k, w in enumerate(walls)]  # periodic in x: the whole period
        chosen = set(pick_evenly(len(names), n_snapshots))
        if names and attr(h5, "output.times"):  # the snapshots nearest output.times
            times = np.array([float(h5["snapshots"][n].attrs.get("time", np.nan)) for n in names])
            chosen |= {int(np.nanargmin(np.abs(times - t))) for t in attr(h5, "output.times")}
        for i in sorted(chosen):
            s = Snapshot(h5["snapshots"][names[i]])
            out = os.path.join(run_dir, "snapshot_%s.png" % s.name)
            if free:
                plot_particles(s, out, box, walls, units)
            else:
                plot_snapshot(s, out, u_max, units)
            written.append(out)
        written += plot_free_surface_series(h5, names, run_dir, diag, compare, units)
        if names and not free:
            last = Snapshot(h5["snapshots"][names[-1]])
            jump = summary.get("pressure_jump_exact")
            jump = float(jump) if isinstance(jump, (int, float)) and math.isfinite(jump) else None
            out = os.path.join(run_dir, "pressure_sections.png")
            if plot_sections(last, radius, jump, out):
                written.append(out)

    cols = read_csv(csv_path)
    membranes = sorted({c.split("_")[0] for c in cols if c.startswith("m") and c.endswith("_rx")})
    for names, ylabel, title, fname, logy in (
            ([m + s for m in membranes for s in ("_rx", "_ry")], "half-chord", "membrane half-chords (extent along x, y)",
             "rx_ry.png", False),
            ([m + "_area_rel_error" for m in membranes], "(A - A0) / A0", "enclosed area: relative error",
             "area_error.png", False),
            (["rms_error"], "rms error", "rms error against the exact solution",
             "rms_error.png", True)):
        out = os.path.join(run_dir, fname)
        if plot_series(cols, names, ylabel, title, out, logy):
            written.append(out)
    out = os.path.join(run_dir, "energy.png")
    if plot_energies(cols, out, units):
        written.append(out)
    return written


def reference_dir(h5):
    """cases/reference of the run's scene (observe.reference_dir beside the scene file), else the
    one beside this script."""
    scene = attr(h5, "scene", "")
    ref = attr(h5, "observe.reference_dir", "reference")
    for d in (os.path.join(os.path.dirname(str(scene)), ref),
              os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cases", "reference")):
        if os.path.isdir(d):
            return d
    return None


def read_front_reference(path):
    """The (T, Z) rows of a surge-front experiment in cases/reference (comment lines and header skipped)."""
    with open(path) as f:
        rows = [r for r in f.read().splitlines() if r and not r.startswith("#")][1:]
    return np.array([[float(c) for c in r.split(",")] for r in rows], ndmin=2)


def plot_free_surface_series(h5, names, run_dir, cols, compare=None, units=None):
    """Loads, droplet axis, dam-break front, inclined-plane profile: those the run has. `compare`: a
    second run directory whose loads are drawn dashed beside this run's (Fig. 10: ISPH and SPH)."""
    units = units or si_units(h5)
    written = []
    t = cols.get("t")
    loads = [c for c in cols if c.startswith("load_")]
    if t is not None and loads:
        out = os.path.join(run_dir, "loads.png")
        fig, ax = plt.subplots(figsize=(6.4, 4))
        other = read_csv(require(os.path.join(compare, "diagnostics.csv"))) if compare else {}
        me, them = read_summary(run_dir).get("method", ""), compare and read_summary(compare).get("method", "")
        for c in loads:
            line, = ax.plot(t, cols[c], label=c.replace("load_", "") + " wall" + (" (%s)" % me if compare else ""))
            if c in other:
                ax.plot(other["t"], other[c], "--", color=line.get_color(), lw=1,
                        label=c.replace("load_", "") + " wall (%s)" % them)
        written.append(finish(fig, ax, out, "t" + units["t"], "load per unit depth" + units["load"] + ", Eq. (31)",
                              "hydrodynamic loads: int (p(t) - p(0)) over each wall"))
    if t is not None and "droplet_a" in cols:
        out = os.path.join(run_dir, "droplet_axis.png")
        fig, ax = plt.subplots(figsize=(6.4, 4))
        ax.plot(t, cols["droplet_a_exact"], "k-", lw=1, label="RK4 of Eq. (42)")
        ax.plot(t[::max(1, len(t) // 40)], cols["droplet_a"][::max(1, len(t) // 40)], "o", ms=4,
                label="SPH: (I_xx / I_yy)^(1/4)")
        written.append(finish(fig, ax, out, "t" + units["t"], "semi-axis a" + units["x"],
                              "elliptic droplet (Afanasiev et al. Section 6.3)"))
    if t is not None and "front_x" in cols:
        fx = attr(h5, "fill.x", attr(h5, "domain.x", [0, 1]))
        a = float(fx[1]) - float(fx[0])
        g = float(np.hypot(*attr(h5, "fluid.gravity", [0.0, -9.81])))
        out = os.path.join(run_dir, "dam_break_front.png")
        fig, ax = plt.subplots(figsize=(6.4, 4))
        ax.plot(t * np.sqrt(2 * g / a), cols["front_x"] / a, "-", label="SPH")
        ref = reference_dir(h5)
        for name, marker, label in (("martin_moyce_1952_a1.125in", "o", "Martin & Moyce (1952), a = 1.125 in"),
                                    ("martin_moyce_1952_a2.25in", "s", "Martin & Moyce (1952), a = 2.25 in"),
                                    ("koshizuka_oka_1996", "^", "Koshizuka & Oka (1996)")):
            path = ref and os.path.join(ref, "dam_break_front_%s.csv" % name)
            if path and os.path.isfile(path):
                d = read_front_reference(path)
                ax.plot(d[:, 0], d[:, 1], marker, mfc="none", label=label)
        T, Z = t * np.sqrt(2 * g / a), cols["front_x"] / a
        T_wall = float(T[np.argmax(Z >= 0.99 * np.nanmax(Z))])  # the front meets the far wall
        ax.set_xlim(0, min(float(T.max()), T_wall + 1.0))
        ax.set_ylim(0.9, max(4.2, float(np.nanmax(cols["front_x"] / a)) + 0.2))
        written.append(finish(fig, ax, out, "T = t sqrt(2g/a)", "Z = front / a", "dam break: surge front"))
    if names and attr(h5, "observe.exact") == "inclined_plane":
        s = Snapshot(h5["snapshots"][names[-1]])
        F = float(attr(h5, "fluid.body_force", [0, 0])[0]) / float(attr(h5, "fluid.rho", 1.0))
        nu = float(attr(h5, "fluid.mu", 1.0)) / float(attr(h5, "fluid.rho", 1.0))
        H = float(np.diff(attr(h5, "fill.y", attr(h5, "domain.y", [0, 1])))[0])
        y0 = float(attr(h5, "domain.y", [0, 1])[0])
        yy = np.linspace(0, H, 200)
        out = os.path.join(run_dir, "velocity_profile.png")
        fig, ax = plt.subplots(figsize=(5, 4.5))
        ax.plot(F * (H - yy / 2) * yy / nu, yy, "k-", lw=1, label="Eq. (39), steady")
        ax.plot(s.scalars["u"], s.y - y0, ".", ms=2, label="SPH, t = %.3g" % s.t)
        written.append(finish(fig, ax, out, "u" + units["u"], "y" + units["x"], "flow down an inclined plane"))
    return written


def plot_sweep(sweep_csv):
    cols = read_csv(require(sweep_csv))
    if "nx" not in cols:
        fail("%s has no nx column (columns: %s)" % (sweep_csv, ", ".join(cols)))
    errors = [c for c in cols if c.endswith("_error")]
    if not errors:
        fail("%s has no *_error column (columns: %s)" % (sweep_csv, ", ".join(cols)))
    nx = cols["nx"]
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    for c in errors:
        ok = (nx > 0) & (cols[c] > 0) & np.isfinite(cols[c])
        if not ok.any():
            continue
        n, e = nx[ok], cols[c][ok]
        order = np.argsort(n)
        n, e = n[order], e[order]
        label = c
        if len(n) >= 2:  # observed order: least-squares slope of log e against log nx
            label += " (order %.2f)" % -np.polyfit(np.log(n), np.log(e), 1)[0]
        ax.loglog(n, e, "o-", label=label)
    ticks = np.unique(nx[nx > 0])
    ax.set_xticks(ticks)
    ax.set_xticklabels(["%g" % v for v in ticks])
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.set_xlabel("nx")
    ax.set_ylabel("error")
    ax.set_title(os.path.basename(sweep_csv))
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small")
    out = os.path.splitext(sweep_csv)[0] + ".png"
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return [out]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run_dir", nargs="?", help="run directory with output.h5, diagnostics.csv")
    ap.add_argument("--sweep", metavar="SWEEP_CSV", help="resolution sweep CSV (nx, *_error)")
    ap.add_argument("--snapshots", type=int, default=N_SNAPSHOT_PLOTS,
                    help="how many snapshots to draw, evenly spaced, always the last (default %(default)s)")
    ap.add_argument("--compare", metavar="RUN_DIR", help="a second run whose loads are drawn dashed in loads.png "
                    "(Fig. 10: ISPH against SPH)")
    a = ap.parse_args()
    if a.sweep:
        written = plot_sweep(a.sweep)
    elif a.run_dir:
        if not os.path.isdir(a.run_dir):
            fail("missing run directory %s" % a.run_dir)
        written = plot_run(a.run_dir, a.snapshots, a.compare)
    else:
        ap.error("give RUN_DIR or --sweep SWEEP_CSV")
    for w in written:
        print(w)


if __name__ == "__main__":
    main()
