#!/usr/bin/python3
"""Self-convergence of the oscillating membrane against a fine reference (the paper's Table 3).

  self_convergence.py [--out bench_out/table3] [--nx 32,64,128] [--ref-nx 256] [--steps 256]

Noutcheuwa & Owens (2012), Section 5.2.2, Table 3: the membrane released from the ellipse
rx = 0.75, ry = 0.5 (cases/membrane_oscillation.toml) with T0 = 1, mu = 0.05, Nb = 512,
h = 1.2 dx (2h = 1.2 (dx + dy)) and a fixed spreading radius 2h* = 0.085 (h* = 0.0425), run to
t = 0.0625 on Nx = Ny = 32, 64, 128 and on the reference Nx = 256. For psi = p^{n+1/2}, u^{n+1},
v^{n+1} the table gives max_i |psi_Nx(x_i) - psi_256(x_i)| over the Nx x Nx particles x_i and
the order q solving the paper's relation between successive rows,
  e(Nx) / e(2Nx) = ((256/Nx)^q - 1) / ((256/(2Nx))^q - 1),
i.e. (8^q - 1)/(4^q - 1) for Nx = 32 and (4^q - 1)/(2^q - 1) = 2^q + 1 for Nx = 64.

Comparing resolutions. The paper takes the maximum over the coarse particles without saying how
the fine solution is evaluated there. Our lattice (Eq. 68) puts particles at x_i = x0 + i dx
along the periodic x axis, so every coarse column is a fine column, and at y_j = y0 + (j + 1/2) dy
along the walled y axis, so every coarse particle sits half-way between two fine rows. The fine
field is therefore taken at the coarse columns and interpolated in y only, by the Lagrange
polynomial through --stencil fine rows (default 6, centred; one-sided at the walls). Its error is
measured by the same interpolation from every other fine row (spacing 2 dy, and 4 dy) onto the
rows half-way between them, which bounds the error at spacing dy; it is printed beside the
differences it must be well below.

Time step. The paper's dt = dx cannot reach t = 0.0625 at Nx = 32 (dx = 3/32). The main table
uses one dt = t_end / --steps at every resolution, so p^{n+1/2} is at the same time t - dt/2
everywhere. The same table is repeated with dt/2 and along dt ~ dx (steps * Nx / ref_nx steps at
Nx, the reference shared). --halvings NX:K runs NX also with dt/2, ..., dt/2^K and prints the
change of each field per halving (the pressure of the finer run averaged over its last two half
levels, t - dt/4 and t - 3 dt/4, to sit at t - dt/2 as well) with the observed order in dt.
The differences are also split by distance to the reference membrane (--near).

The pressure of every run has zero mean over its own particles (the solver's gauge); it is
compared as it is.

Writes OUT/table3.csv (the tables), OUT/table3_dt.csv (the changes per halving) and
OUT/table3.md (all of it, with the interpolation check and the wall time) and prints the
Markdown. Runs go to OUT/runs/nxN_stepsS; a run that already has a summary.json, made with the
same scene and settings, is not run again (--force reruns it). Other scene values: --set key=value (e.g. membrane.fixed=true).
"""
import argparse
import csv
import io
import json
import math
import os
import resource
import subprocess
import sys
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Table 3's settings (T0, mu, Nb, h/dx, h*) on top of cases/membrane_oscillation.toml.
TABLE3_SETTINGS = ["membrane.T0=1", "fluid.mu=0.05", "membrane.nb=512", "membrane.h_star=0.0425",
                   "kernel.h_over_dx=1.2"]
FIELDS = ("p", "u", "v")
PAPER = {  # Table 3 of the paper, quoted for comparison only (never used in a computation)
    32: ("2.8390e-1", "3.56", "5.7788e-1", "3.35", "5.8963e-1", "4.23"),
    64: ("2.3799e-2", "0.77", "5.6064e-2", "1.12", "3.1248e-2", "1.25"),
    128: ("8.8049e-3", "", "1.7687e-2", "", "9.2301e-3", ""),
}


def run(a, nx, steps):
    """Runs the scene at nx x nx with `steps` steps to t_end, with snapshots at the last two steps;
    returns (run_dir, summary)."""
    dt = a.t_end / steps
    run_dir = os.path.join(a.out, "runs", f"nx{nx}_steps{steps}")
    summary_path = os.path.join(run_dir, "summary.json")
    sets_path = os.path.join(run_dir, "sets.json")  # a run is reused only with the same settings
    sets = TABLE3_SETTINGS + [f"grid.nx={nx}", f"grid.ny={nx}", f"time.dt={dt!r}", f"time.end={a.t_end!r}",
                              f"output.interval={(steps - 1) * dt!r}"] + a.set  # snapshots at steps - 1, steps
    old = None
    if os.path.exists(sets_path):
        with open(sets_path) as f:
            old = json.load(f)
    if a.force or old != [a.scene] + sets or not os.path.exists(summary_path):
        cmd = [a.sphib, "run", a.scene, "--out", run_dir, "--quiet"]
        for s in sets:
            cmd += ["--set", s]
        print("self_convergence:", " ".join(cmd), flush=True)
        r = subprocess.run(cmd)
        if r.returncode != 0:
            sys.exit(f"self_convergence: run {run_dir} failed (exit {r.returncode})")
        write_atomic(sets_path, json.dumps([a.scene] + sets))
    with open(summary_path) as f:
        s = json.load(f)
    if s.get("stop_reason") != "end time" or s.get("steps") != steps:
        sys.exit(f"self_convergence: {run_dir} stopped with {s.get('stop_reason')} after {s.get('steps')} steps")
    return run_dir, s


def fields(run_dir, nx, steps, t_end):
    """Final fields of a run as (ny, nx) arrays (row j, column i: particle i + nx j), checked to be at
    t_end, and p_prev, the pressure one step earlier (p^{n-1/2})."""
    with h5py.File(os.path.join(run_dir, "output.h5"), "r") as f:
        snaps = sorted(f["snapshots"].values(), key=lambda g: g.attrs["step"])
        last, prev = snaps[-1], snaps[-2]
        if last.attrs["step"] != steps or abs(last.attrs["time"] - t_end) > 1e-12 * t_end:
            sys.exit(f"self_convergence: {run_dir}: last snapshot at step {last.attrs['step']}, "
                     f"t = {last.attrs['time']!r}, not t = {t_end!r}")
        if prev.attrs["step"] != steps - 1:
            sys.exit(f"self_convergence: {run_dir}: no snapshot at step {steps - 1}")
        out = {k: last[k][()].reshape(nx, nx) for k in ("x", "y") + FIELDS}
        out["p_prev"] = prev["p"][()].reshape(nx, nx)
        out["X"] = last["membrane_0/X"][()]
    return out


def at_half_level_of(f):
    """The fields of a run with dt/2 with p at the half level t - dt/2 of the run with dt: the mean of
    its last two pressures, at t - dt/4 and t - 3 dt/4."""
    g = dict(f)
    g["p"] = 0.5 * (f["p"] + f["p_prev"])
    return g


def lagrange_weights(nodes, x):
    """Weights w_k with sum_k w_k f(nodes_k) the Lagrange interpolant through the nodes at x."""
    w = np.ones(len(nodes))
    for k, xk in enumerate(nodes):
        for m, xm in enumerate(nodes):
            if m != k:
                w[k] *= (x - xm) / (xk - xm)
    return w


def interpolate_rows(F, y_src, y_dst, n):
    """F (rows along y_src, uniform) at the rows y_dst by n-point Lagrange interpolation in y:
    the n rows nearest to each target (centred, shifted inside at the ends)."""
    dy = y_src[1] - y_src[0]
    out = np.empty((len(y_dst), F.shape[1]))
    for j, y in enumerate(y_dst):
        s = (y - y_src[0]) / dy                  # position in rows
        k0 = int(math.floor(s)) - (n // 2 - 1)   # n rows, centred on the bracketing pair
        k0 = min(max(k0, 0), len(y_src) - n)
        out[j] = lagrange_weights(np.arange(k0, k0 + n, dtype=float), s) @ F[k0:k0 + n]
    return out


def fine_at_coarse(fine, coarse, n):
    """The fine fields at the coarse particles: coarse columns are fine columns (checked), the rows
    are interpolated in y."""
    nf, nc = fine["x"].shape[1], coarse["x"].shape[1]
    r = nf // nc
    if nf != r * nc or np.max(np.abs(fine["x"][0, ::r] - coarse["x"][0])) > 1e-12:
        sys.exit("self_convergence: coarse columns are not fine columns")
    y_f, y_c = fine["y"][:, 0], coarse["y"][:, 0]
    return {k: interpolate_rows(fine[k][:, ::r], y_f, y_c, n) for k in FIELDS}


def max_diff(a, b):
    return {k: float(np.max(np.abs(a[k] - b[k]))) for k in FIELDS}


def interpolation_error(fine, n, stride=1):
    """Max error of the y interpolation from the fine rows 0, 2s, 4s, ... (spacing 2s dy, s = stride)
    onto the rows s, 3s, ..., each half-way between two of them (rows beyond the last source row are
    skipped): the error of the interpolation used at spacing dy, measured at spacing 2s dy."""
    y = fine["y"][:, 0]
    src, dst = slice(0, None, 2 * stride), slice(stride, len(y) - stride, 2 * stride)
    return {k: float(np.max(np.abs(interpolate_rows(fine[k][src], y[src], y[dst], n) - fine[k][dst])))
            for k in FIELDS}


def order(e_coarse, e_fine, n, n_ref):
    """q with e(n)/e(2n) = ((n_ref/n)^q - 1)/((n_ref/2n)^q - 1) (the paper's relation), by bisection."""
    if not (e_coarse > 0 and e_fine > 0):
        return float("nan")
    R = e_coarse / e_fine
    a, b = n_ref / n, n_ref / (2 * n)

    def g(q):  # increasing in q, -> 1 as q -> -inf, log(a)/log(b) at 0
        if abs(q) < 1e-12:
            return math.log(a) / math.log(b)
        return math.expm1(q * math.log(a)) / math.expm1(q * math.log(b))

    lo, hi = -20.0, 20.0
    if not g(lo) < R < g(hi):
        return float("nan")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) < R else (lo, mid)
    return 0.5 * (lo + hi)


def fmt(v, spec="%.4e"):
    return "" if v is None or (isinstance(v, float) and math.isnan(v)) else spec % v


def table(F, nxs, ref_nx, stencil):
    """Errors max |psi_n - psi_ref| at the n x n particles and the orders between successive n, for
    the runs F (n -> fields)."""
    err = {n: max_diff(F[n], fine_at_coarse(F[ref_nx], F[n], stencil)) for n in nxs}
    q = {n: {k: order(err[n][k], err[m][k], n, ref_nx) for k in FIELDS} for n, m in zip(nxs, nxs[1:])}
    return err, q


def membrane_distance(f, X):
    """Distance from every particle of the fields f to the nearest of the markers X (N x 2)."""
    P = np.stack([f["x"].ravel(), f["y"].ravel()], axis=1)
    d = np.empty(len(P))
    for i in range(0, len(P), 4096):  # in blocks: 4096 x Nb distances at a time
        q = P[i:i + 4096]
        d[i:i + 4096] = np.sqrt(((q[:, None, :] - X[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
    return d.reshape(f["x"].shape)


def split_errors(F, nxs, ref_nx, stencil, near):
    """Max errors at the particles within `near` of the reference membrane and beyond it."""
    out = {}
    for n in nxs:
        d = membrane_distance(F[n], F[ref_nx]["X"])
        I = fine_at_coarse(F[ref_nx], F[n], stencil)
        out[n] = {(k, w): float(np.max(np.abs(F[n][k] - I[k])[m])) for k in FIELDS
                  for w, m in (("near", d <= near), ("far", d > near))}
    return out


def markdown_table(header, rows):
    return ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)] + ["| " + " | ".join(r) + " |" for r in rows]


def write_atomic(path, text):
    with open(path + ".part", "w", newline="") as f:
        f.write(text)
    os.replace(path + ".part", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench_out", "table3"))
    ap.add_argument("--scene", default=os.path.join(ROOT, "cases", "membrane_oscillation.toml"))
    ap.add_argument("--sphib", default=os.path.join(ROOT, "build", "sphib"))
    ap.add_argument("--nx", default="32,64,128", help="resolutions compared with the reference")
    ap.add_argument("--ref-nx", type=int, default=256, help="reference resolution")
    ap.add_argument("--t-end", type=float, default=0.0625)
    ap.add_argument("--steps", type=int, default=256,
                    help="time steps to t_end at every resolution (dt = t_end/steps); the dt ~ dx table takes "
                         "steps * Nx / ref_nx steps at Nx")
    ap.add_argument("--halvings", default="32:3,64:3,128:3,256:1",
                    help="NX:K: also run NX with dt/2, ..., dt/2^K (a second table at dt/2 when every "
                         "resolution has K >= 1; '' for none)")
    ap.add_argument("--near", type=float, default=0.2,
                    help="errors are also split at this distance from the reference membrane")
    ap.add_argument("--stencil", type=int, default=6, help="fine rows in the y interpolation (even)")
    ap.add_argument("--set", action="append", default=[], help="key=value for every run (after Table 3's)")
    ap.add_argument("--force", action="store_true", help="rerun the runs even when they are complete")
    a = ap.parse_args()
    if a.stencil < 2 or a.stencil % 2:
        sys.exit("self_convergence: --stencil must be even and at least 2")
    nxs = sorted(int(v) for v in a.nx.split(",") if v)
    halvings = {int(k): int(v) for k, v in (h.split(":") for h in a.halvings.split(",") if h)}
    for n in nxs + list(halvings):
        if a.ref_nx % n:
            sys.exit(f"self_convergence: Nx = {n} does not divide the reference {a.ref_nx}")
    tied = {n: a.steps * n // a.ref_nx for n in nxs}
    if any(a.steps * n % a.ref_nx or tied[n] < 2 for n in nxs):
        sys.exit("self_convergence: steps * Nx / ref_nx must be an integer of at least 2 for the dt ~ dx table")
    os.makedirs(a.out, exist_ok=True)
    t0 = time.monotonic()
    S, all_n = a.steps, nxs + [a.ref_nx]

    # Runs: (Nx, steps) -> fields.
    wanted = {(n, S) for n in all_n} | {(n, tied[n]) for n in nxs}
    wanted |= {(n, S * 2 ** k) for n, K in halvings.items() for k in range(1, K + 1)}
    F, wall = {}, {}
    for n, st in sorted(wanted):
        d, s = run(a, n, st)
        F[(n, st)] = fields(d, n, st, a.t_end)
        wall[(n, st)] = s["wall_seconds"]

    # The tables: one dt for all, the same with dt/2, dt ~ dx.
    tables = [("one dt", S, table({n: F[(n, S)] for n in all_n}, nxs, a.ref_nx, a.stencil),
               {n: S for n in nxs})]
    if all(halvings.get(n, 0) >= 1 for n in all_n):
        tables.append(("one dt, halved", 2 * S,
                       table({n: F[(n, 2 * S)] for n in all_n}, nxs, a.ref_nx, a.stencil), {n: 2 * S for n in nxs}))
    tied_F = {n: F[(n, tied[n])] for n in nxs}
    tied_F[a.ref_nx] = F[(a.ref_nx, S)]
    tables.append(("dt ~ dx", None, table(tied_F, nxs, a.ref_nx, a.stencil), tied))
    err = tables[0][2][0]
    dx = {n: float(F[(n, S)]["x"][0, 1] - F[(n, S)]["x"][0, 0]) for n in all_n}
    smallest = {k: min(err[n][k] for n in nxs) for k in FIELDS}

    split = split_errors({n: F[(n, S)] for n in all_n}, nxs, a.ref_nx, a.stencil, a.near)

    # Time step: the change of each field when dt is halved, p compared at the same half level.
    dt_rows = []
    for n, K in sorted(halvings.items()):
        prev = None
        for k in range(K):
            st = S * 2 ** k
            d = max_diff(F[(n, st)], at_half_level_of(F[(n, 2 * st)]))
            dt_rows.append((n, st, d, {f: math.log2(prev[f] / d[f]) for f in FIELDS} if prev else None))
            prev = d

    # Interpolation error of the reference's y interpolation.
    ref = F[(a.ref_nx, S)]
    interp = interpolation_error(ref, a.stencil)          # at spacing 2 dy: a bound
    interp4 = interpolation_error(ref, a.stencil, 2)      # at 4 dy: with it, the order and an estimate at dy
    interp_low = interpolation_error(ref, a.stencil - 2) if a.stencil > 2 else None
    interp_order = {k: math.log2(interp4[k] / interp[k]) for k in FIELDS}
    interp_est = {k: interp[k] * interp[k] / interp4[k] for k in FIELDS}

    # CSV files.
    cols = ["table", "nx", "ref_nx", "steps", "dt", "t"] + [c for k in FIELDS for c in (f"err_{k}", f"q_{k}")]
    cols += ["wall_seconds"]
    rows = []
    for name, _, (e_, q_), steps in tables:
        for n in nxs:
            r = {"table": name, "nx": n, "ref_nx": a.ref_nx, "steps": steps[n], "dt": repr(a.t_end / steps[n]),
                 "t": repr(a.t_end), "wall_seconds": "%.2f" % wall[(n, steps[n])]}
            for k in FIELDS:
                r[f"err_{k}"] = "%.6e" % e_[n][k]
                r[f"q_{k}"] = fmt(q_.get(n, {}).get(k), "%.4f")
            rows.append(r)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=cols)
    w.writeheader()
    w.writerows(rows)
    write_atomic(os.path.join(a.out, "table3.csv"), buf.getvalue())
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["nx", "steps", "dt"] + [f"change_{k}" for k in FIELDS] + [f"order_{k}" for k in FIELDS])
    for n, st, d, o in dt_rows:
        w.writerow([n, st, repr(a.t_end / st)] + ["%.6e" % d[k] for k in FIELDS]
                   + [fmt(o[k] if o else None, "%.4f") for k in FIELDS])
    write_atomic(os.path.join(a.out, "table3_dt.csv"), buf.getvalue())

    # Markdown.
    e = lambda v: "%.4e" % v
    cmdline = " ".join(["scripts/self_convergence.py"] + sys.argv[1:])
    L = [f"# Table 3: self-convergence of the oscillating membrane at t = {a.t_end:g}", "",
         f"T0 = 1, mu = 0.05, Nb = 512, h = 1.2 dx, h* = 0.0425 (2h* = 0.085), rx(0) = 0.75, ry(0) = 0.5, "
         f"r0 = 0.5; reference Nx = Ny = {a.ref_nx}. Made by `/usr/bin/python3 {cmdline}`.",
         f"Errors: max over the Nx x Nx particles of |psi_Nx - psi_{a.ref_nx}| (psi = p^{{n+1/2}}, u^{{n+1}}, "
         f"v^{{n+1}}); q solves e(Nx)/e(2Nx) = ((Nref/Nx)^q - 1)/((Nref/2Nx)^q - 1) as in the paper.", ""]
    for name, st, (e_, q_), steps in tables:
        if st is not None:
            L.append(f"**{name}**: dt = t_end/{st} = {a.t_end / st:.6g} at every resolution:")
        else:
            L.append(f"**{name}**: dt = t_end/(steps) with steps = " + ", ".join(f"{steps[n]} (Nx = {n})" for n in nxs)
                     + f", {S} (Nx = {a.ref_nx}), i.e. dt = {a.t_end / S / dx[a.ref_nx]:.4g} dx; p^{{n+1/2}} is "
                     "compared as it is, at t - dt/2 of each run:")
        L += [""] + markdown_table(
            ["Nx = Ny", "steps", "p^{n+1/2}", "q", "u^{n+1}", "q", "v^{n+1}", "q"],
            [[str(n), str(steps[n])] + [x for k in FIELDS for x in (e(e_[n][k]), fmt(q_.get(n, {}).get(k), "%.2f"))]
             for n in nxs]) + [""]
    L += ["The paper's Table 3 (its caption: dt = dx; otherwise the same settings):", ""]
    L += markdown_table(["Nx = Ny", "p", "q", "u", "q", "v", "q"], [[str(n)] + list(PAPER[n]) for n in sorted(PAPER)])
    L += ["", "## Time step", "",
          f"The main table uses one dt = t_end/{S} = {a.t_end / S:.6g} at every resolution (the paper's dt = dx "
          f"cannot reach t = {a.t_end:g} at Nx = {nxs[0]}, where dx = {dx[nxs[0]]:.4g}): p^{{n+1/2}} is then at the same time "
          "t - dt/2 on every lattice and a time error common to all lattices cancels from the differences. "
          "Change of each field when dt is halved at a fixed lattice, max |psi(dt) - psi(dt/2)| (the pressure "
          "of the dt/2 run averaged over its last two half levels, to t - dt/2 of the dt run), and the observed "
          "order in dt, log2 of the ratio of successive changes:", ""]
    L += markdown_table(["Nx", "dt -> dt/2", "p", "u", "v", "order p", "order u", "order v"],
                        [[str(n), f"{a.t_end / st:.4g} -> {a.t_end / st / 2:.4g}"] + [e(d[k]) for k in FIELDS]
                         + [fmt(o[k] if o else None, "%.2f") for k in FIELDS] for n, st, d, o in dt_rows])
    L += ["", "The spatial differences of the main table, for comparison: "
          + "; ".join(f"Nx = {n}: " + ", ".join(f"{k} {e(err[n][k])}" for k in FIELDS) for n in nxs) + ".", ""]
    L += ["## Where the differences are", "",
          f"The main table's differences at the particles within {a.near:g} of the reference membrane (its markers "
          f"at t = {a.t_end:g}) and beyond, with the paper's q:", ""]
    srows = []
    for i, n in enumerate(nxs):
        r = [str(n)]
        for k in FIELDS:
            for w in ("near", "far"):
                r.append(e(split[n][(k, w)]))
                r.append(fmt(order(split[n][(k, w)], split[nxs[i + 1]][(k, w)], n, a.ref_nx), "%.2f")
                         if i + 1 < len(nxs) else "")
        srows.append(r)
    L += markdown_table(["Nx"] + [f"{k} {w}{x}" for k in FIELDS for w in ("near", "far") for x in ("", " q")], srows)
    L += ["", "## Interpolation", "",
          "Coarse particles lie on fine columns (periodic x: x_i = x0 + i dx) and half-way between two fine rows "
          "(walled y: y_j = y0 + (j + 1/2) dy). The reference is interpolated in y by the "
          f"{a.stencil}-point Lagrange polynomial (one-sided at the walls). Its error, measured by interpolating "
          f"rows of the Nx = {a.ref_nx} fields at spacing 2 dy (and 4 dy) onto the rows half-way between them, "
          "bounds the error at spacing dy:", ""]
    irows = [[f"{a.stencil} points, 4 dy"] + [e(interp4[k]) for k in FIELDS],
             [f"{a.stencil} points, 2 dy (bound)"] + [e(interp[k]) for k in FIELDS]]
    if interp_low:
        irows.append([f"{a.stencil - 2} points, 2 dy"] + [e(interp_low[k]) for k in FIELDS])
    irows += [["observed order 4 dy -> 2 dy"] + ["%.2f" % interp_order[k] for k in FIELDS],
              [f"{a.stencil} points, dy (estimate: that order once more)"] + [e(interp_est[k]) for k in FIELDS],
              ["smallest difference of the main table"] + [e(smallest[k]) for k in FIELDS]]
    L += markdown_table(["stencil, spacing", "p", "u", "v"], irows)
    ratio = max(interp[k] / smallest[k] for k in FIELDS)
    ratio_est = max(interp_est[k] / smallest[k] for k in FIELDS)
    L += ["", f"Largest ratio to the smallest difference: {ratio:.2g} for the bound, {ratio_est:.2g} for the "
          "estimate.", ""]
    cpu = resource.getrusage(resource.RUSAGE_CHILDREN)
    L += ["## Wall time", ""]
    L += markdown_table(["Nx", "steps", "wall seconds"], [[str(n), str(st), "%.1f" % wsec]
                                                          for (n, st), wsec in sorted(wall.items())])
    L += ["", f"Total of the runs: {sum(wall.values()):.1f} s (from their summary.json); this invocation: "
          f"{time.monotonic() - t0:.1f} s wall, {cpu.ru_utime + cpu.ru_stime:.1f} s CPU in the runs it started "
          "(complete runs with the same settings are reused).", ""]
    md = "\n".join(L)
    write_atomic(os.path.join(a.out, "table3.md"), md)
    print(md)


if __name__ == "__main__":
    main()
