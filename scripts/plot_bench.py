#!/usr/bin/python3
"""Plots of the issue-6 benchmarks from their CSV files (run with /usr/bin/python3, matplotlib).

    plot_bench.py [BENCH_OUT]        default bench_out; draws whatever of these exists:

    BENCH_OUT/speed_accuracy/speed_accuracy.csv (bench/speed_accuracy)
        speed_accuracy_poiseuille.png  rms error vs CPU time, start-up Poiseuille (EPSPH grid, LPSPH) and
                                       the Vukcevic channel (WCSPH and EPSPH); Pareto fronts as steps
        speed_accuracy_membrane.png    area error at t = 2 and max rx error on [0, 2] vs CPU time,
                                       oscillating membrane A (Section 5.2.2) and B (Fig. 19 settings)
        membrane_rx.png                rx(t) of the reference runs and of the runs on the rx Pareto front
    BENCH_OUT/stability_map/stability_runs.csv, stability_dtmax.csv (bench/stability_map)
        stability_dtmax.png            largest stable dt vs T0 per mu (parts T, E, S) with the fitted
                                       max(C_i sqrt(rho dx^3/T0), C_v mu dx/T0), `sphib check`'s estimate
                                       and the classical explicit estimate
        stability_collapse.png         the same limits in the one variable they depend on:
                                       dt_max sqrt(T0/(rho dx^3)) against mu/sqrt(rho T0 dx), with the
                                       fit, `sphib check` and the classical estimate as lines
        stability_grid.png             the classification grid (part G): dt vs each parameter
        stability_axes.png             largest stable dt vs dx, markers per dx, h/dx, h*/h (part X)
    BENCH_OUT/scaling/scaling.csv, solvers.csv (bench/scaling)
        scaling.png                    time per step, set-up phases and peak memory vs N, with fitted slopes
        scaling_solvers.png            per-solve and factorisation times of the solver variants vs N
                                       (CHOLMOD supernodal, simplicial, Jacobi-PCG, Eigen SimplicialLDLT)

Each PNG is written as NAME.png.part and renamed.
"""
import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def fl(row, key):
    try:
        v = float(row.get(key, "") or "nan")
    except ValueError:
        return math.nan
    return v


def save(fig, path):
    part = path + ".part"
    fig.savefig(part, dpi=110, bbox_inches="tight", format="png")
    plt.close(fig)
    os.replace(part, path)
    print("wrote", path)


def pareto_line(ax, pts, **kw):
    """Step line through the Pareto-optimal (cost, error) points."""
    pts = sorted(p for p in pts if p[0] > 0 and p[1] > 0 and math.isfinite(p[0]) and math.isfinite(p[1]))
    front, best = [], math.inf
    for c, e in pts:
        if e < best:
            front.append((c, e))
            best = e
    if front:
        xs, ys = zip(*front)
        ax.step(xs, ys, where="post", **kw)


def slope(xs, ys):
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0]
    if len(pts) < 2:
        return math.nan, math.nan
    n = len(pts)
    sx = sum(p[0] for p in pts)
    sy = sum(p[1] for p in pts)
    sxx = sum(p[0] ** 2 for p in pts)
    sxy = sum(p[0] * p[1] for p in pts)
    a = (n * sxy - sx * sy) / (n * sxx - sx * sx)
    return a, (sy - a * sx) / n


# ---- speed-accuracy ----------------------------------------------------------------------------


def speed_accuracy(d):
    path = os.path.join(d, "speed_accuracy.csv")
    if not os.path.exists(path):
        return
    rows = [r for r in read(path) if r["status"] == "ok"]
    # Poiseuille
    P_all = [r for r in rows if r["study"] == "poiseuille"]
    P = [r for r in P_all if r["group"] != "lagrangian"]
    L = [r for r in P_all if r["group"] == "lagrangian"]
    W = [r for r in rows if r["study"] == "vukcevic"]
    if P_all or W:
        fig, axs = plt.subplots(1, 2, figsize=(13, 5))
        ax = axs[0]
        hs = sorted({fl(r, "h_over_dx") for r in P})
        dts = sorted({fl(r, "dt") for r in P})
        markers = "os^vDP*X"
        cmap = plt.get_cmap("viridis")
        for r in P:
            h, dt = fl(r, "h_over_dx"), fl(r, "dt")
            ax.scatter(fl(r, "cpu_s"), fl(r, "rms_error"), color=cmap(hs.index(h) / max(1, len(hs) - 1)),
                       marker=markers[dts.index(dt) % len(markers)], s=14 + 4 * int(r["nx"]) ** 0.8, alpha=0.8,
                       edgecolors="k" if r["pareto_rms"] == "1" else "none")
        for r in L:
            h, dt = fl(r, "h_over_dx"), fl(r, "dt")
            ax.scatter(fl(r, "cpu_s"), fl(r, "rms_error"), facecolors="none",
                       edgecolors=cmap(hs.index(h) / max(1, len(hs) - 1)) if h in hs else "m",
                       marker=markers[dts.index(dt) % len(markers)] if dt in dts else "o",
                       s=14 + 4 * int(r["nx"]) ** 0.8, linewidths=1.2)
        if L:
            ax.scatter([], [], facecolors="none", edgecolors="grey", marker="o", label="LPSPH (hollow)")
        pareto_line(ax, [(fl(r, "cpu_s"), fl(r, "rms_error")) for r in P_all], color="r", lw=1.2,
                    label="Pareto front" + (" (both methods)" if L else ""))
        for h in hs:
            ax.scatter([], [], color=cmap(hs.index(h) / max(1, len(hs) - 1)), marker="o", label=f"h/dx = {h:g}")
        for dt in dts:
            ax.scatter([], [], color="grey", marker=markers[dts.index(dt) % len(markers)], label=f"dt = {dt:g}")
        ax.set(xscale="log", yscale="log", xlabel="CPU seconds (set-up + loop)", ylabel="rms error, Eq. (69)",
               title="Start-up Poiseuille (EPSPH" + (", LPSPH hollow" if L else "") +
               "), t = 0.0125\nsize ~ Nx (16..64); black edge: Pareto")
        ax.legend(fontsize=7, ncol=2)
        ax.grid(True, which="both", alpha=0.3)
        ax = axs[1]
        for method, c in (("wcsph", "tab:orange"), ("eulerian", "tab:blue")):
            rs = [r for r in W if r["method"] == method]
            for r in rs:
                ax.scatter(fl(r, "cpu_s"), fl(r, "rms_error"), color=c, s=10 + int(r["ny"]))
                ax.annotate(f'{r["nx"]}x{r["ny"]}', (fl(r, "cpu_s"), fl(r, "rms_error")), fontsize=6)
            ax.scatter([], [], color=c, label="WCSPH" if method == "wcsph" else "EPSPH")
        pareto_line(ax, [(fl(r, "cpu_s"), fl(r, "rms_error")) for r in W], color="r", lw=1.2, label="Pareto front")
        ax.set(xscale="log", yscale="log", xlabel="CPU seconds", ylabel="rms error / u_max",
               title="Poiseuille of Vukcevic et al. (t = 1 s)")
        ax.legend(fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
        save(fig, os.path.join(d, "speed_accuracy_poiseuille.png"))
    # membranes
    studies = [s for s in ("membrane_A", "membrane_B") if any(r["study"] == s for r in rows)]
    if studies:
        fig, axs = plt.subplots(len(studies), 2, figsize=(13, 5 * len(studies)), squeeze=False)
        groups = ["base", "Nx", "Nx, dt = 0.1 dx", "Nb", "h/dx", "h*/h", "dt", "combined", "reference"]
        colors = dict(zip(groups, ["k", "tab:blue", "tab:cyan", "tab:orange", "tab:green", "tab:purple", "tab:red",
                                   "tab:brown", "grey"]))
        for i, s in enumerate(studies):
            rs = [r for r in rows if r["study"] == s and r["group"] != "reference"]
            for j, (key, lab, pk) in enumerate((("area_err_t2", "|area error| at t = 2", "pareto_area"),
                                                ("rx_max_err", "max |rx - rx_ref| on [0, 2]", "pareto_rx"))):
                ax = axs[i][j]
                seen = set()
                for r in rs:
                    e = abs(fl(r, key))
                    if not (e > 0):
                        continue
                    g = r["group"].replace(";", ",")  # csv_text wrote "," as ";"
                    ax.scatter(fl(r, "cpu_s"), e, color=colors.get(g, "m"), s=30,
                               edgecolors="r" if r[pk] == "1" else "none", linewidths=1.5)
                    if g not in seen:
                        ax.scatter([], [], color=colors.get(g, "m"), s=30, label=g)
                    seen.add(g)
                    if r[pk] == "1" or g == "base":
                        ax.annotate(r["label"], (fl(r, "cpu_s"), e), fontsize=6, xytext=(3, 3), textcoords="offset points")
                pareto_line(ax, [(fl(r, "cpu_s"), abs(fl(r, key))) for r in rs], color="r", lw=1, alpha=0.6,
                            label="Pareto front (red edge)")
                title = ("A: Section 5.2.2 (64², Nb 128, dt 1e-4, T0 10, μ 0.1)" if s == "membrane_A"
                         else "B: Fig. 19 settings (64², Nb 360, dt 0.1 dx, h* 0.0425, T0 1, μ 0.05)")
                ax.set(xscale="log", yscale="log", xlabel="CPU seconds", ylabel=lab)
                ax.set_title(title, fontsize=9)
                ax.grid(True, which="both", alpha=0.3)
                ax.legend(fontsize=7)
        save(fig, os.path.join(d, "speed_accuracy_membrane.png"))
        # rx(t)
        fig, axs = plt.subplots(1, len(studies), figsize=(7 * len(studies), 4.5), squeeze=False)
        for i, s in enumerate(studies):
            ax = axs[0][i]
            sel = [r for r in rows if r["study"] == s and (r["group"] in ("reference", "base") or r["pareto_rx"] == "1")]
            for r in sel:
                f = os.path.join(d, "runs", r["tag"], "diagnostics.csv")
                if not os.path.exists(f):
                    continue
                dg = read(f)
                t = [fl(x, "t") for x in dg]
                rx = [fl(x, "m0_rx") for x in dg]
                ax.plot(t, rx, lw=2.2 if r["group"] == "reference" else 1,
                        color="k" if r["group"] == "reference" else None, label=f'{r["group"]}: {r["label"]}')
            ax.set(xlabel="t", ylabel="rx(t)", title=s.replace("_", " ") + ": reference and rx-Pareto runs")
            ax.legend(fontsize=6)
            ax.grid(True, alpha=0.3)
        save(fig, os.path.join(d, "membrane_rx.png"))


# ---- stability ---------------------------------------------------------------------------------


def stability(d):
    p_runs = os.path.join(d, "stability_runs.csv")
    p_dt = os.path.join(d, "stability_dtmax.csv")
    if os.path.exists(p_dt):
        D = read(p_dt)
        parts = [p for p in ("T", "E", "S") if any(r["part"] == p for r in D)]
        if parts:
            fig, axs = plt.subplots(1, len(parts), figsize=(6.5 * len(parts), 5), squeeze=False, sharey=True)
            titles = {"T": "T: run_scene's verdict (convection on)",
                      "E": "E: no dx-per-step guards, convection on",
                      "S": "S: no guards, convection off (Stokes)"}
            for k, p in enumerate(parts):
                ax = axs[0][k]
                rs = [r for r in D if r["part"] == p]
                mus = sorted({fl(r, "mu") for r in rs})
                cmap = plt.get_cmap("plasma")
                for i, mu in enumerate(mus):
                    c = cmap(i / max(1, len(mus) - 0.5))
                    sub = sorted((r for r in rs if fl(r, "mu") == mu), key=lambda r: fl(r, "T0"))
                    T0 = [fl(r, "T0") for r in sub]
                    ax.plot(T0, [fl(r, "dt_max") for r in sub], "o-", color=c, label=f"μ = {mu:g}")
                    # bracket as error bars
                    for r in sub:
                        lo, hi = fl(r, "dt_stable"), fl(r, "dt_unstable")
                        if math.isfinite(lo) and math.isfinite(hi):
                            ax.plot([fl(r, "T0")] * 2, [lo, hi], color=c, lw=3, alpha=0.5)
                        elif math.isfinite(lo):
                            ax.annotate("", (fl(r, "T0"), lo * 3), (fl(r, "T0"), lo),
                                        arrowprops=dict(arrowstyle="->", color=c))
                    fit = [max(fl(r, "fit_inertial"), fl(r, "fit_viscous")) for r in sub]
                    ax.plot(T0, fit, "--", color=c, lw=1)
                    ax.plot(T0, [fl(r, "check_estimate") for r in sub], ":", color=c, lw=1)
                    if "classical_estimate" in sub[0]:
                        ax.plot(T0, [fl(r, "classical_estimate") for r in sub], "-.", color=c, lw=0.8, alpha=0.7)
                if rs:
                    ci, cv = fl(rs[0], "fit_Ci"), fl(rs[0], "fit_Cv")
                    ax.plot([], [], "k--", lw=1, label=f"fit max(C_i √(ρdx³/T0), C_v μ dx/T0)\nC_i = {ci:.3g}, C_v = {cv:.3g}")
                    ax.plot([], [], "k:", lw=1, label="sphib check: max(√(ρh*³/T0), 10 μ h*/T0)")
                    if "classical_estimate" in rs[0]:
                        ax.plot([], [], "k-.", lw=0.8,
                                label="classical explicit: max(√(ρdx³/(2πT0)), (8/π) μ dx/T0)")
                ax.set(xscale="log", yscale="log", xlabel="T0", ylabel="largest stable dt", title=titles[p])
                ax.grid(True, which="both", alpha=0.3)
                ax.legend(fontsize=7)
            save(fig, os.path.join(d, "stability_dtmax.png"))
            collapse(d, D, parts)
        X = [r for r in D if r["part"] == "X"]
        if X:
            axes = [("Nx", "dx", lambda r: fl(r, "dx")), ("markers/dx", "markers per grid spacing", lambda r: fl(r, "markers_per_dx")),
                    ("h/dx", "h/dx (h* fixed)", lambda r: fl(r, "h_over_dx")), ("h*/h", "h*/h", lambda r: fl(r, "h_star_over_h"))]
            fig, axs = plt.subplots(1, 4, figsize=(20, 4.5))
            styles = {"runner/inertial": ("tab:blue", "-"), "runner/viscous": ("tab:red", "-"),
                      "elastic/inertial": ("tab:blue", "--"), "elastic/viscous": ("tab:red", "--")}
            for k, (ax_name, lab, xv) in enumerate(axes):
                ax = axs[k]
                for where, (c, ls) in styles.items():
                    sub = sorted((r for r in X if r["axis"] == f"{where}:{ax_name}"), key=xv)
                    if not sub:
                        continue
                    xs = [xv(r) for r in sub]
                    ys = [fl(r, "dt_max") for r in sub]
                    a, _ = slope(xs, ys)
                    ax.plot(xs, ys, "o" + ls, color=c, label=f"{where} (slope {a:.2f})")
                    ax.plot(xs, [fl(r, "check_estimate") for r in sub], ":", color=c, lw=1)
                ax.set(xscale="log", yscale="log", xlabel=lab, ylabel="largest stable dt",
                       title=f"T0 = 1e3; blue μ = 1e-3, red μ = 10; dotted: check")
                ax.grid(True, which="both", alpha=0.3)
                ax.legend(fontsize=7)
            save(fig, os.path.join(d, "stability_axes.png"))
    if os.path.exists(p_runs):
        R = [r for r in read(p_runs) if r["part"] == "G"]
        if R:
            axes = []
            for r in R:
                if r["axis"] not in axes:
                    axes.append(r["axis"])
            val = {"T0": lambda r: fl(r, "T0"), "mu": lambda r: fl(r, "mu"),
                   "markers/dx": lambda r: fl(r, "markers_per_dx"), "h/dx": lambda r: fl(r, "h_over_dx"),
                   "h*/h": lambda r: fl(r, "h_star_over_h")}
            style = {"stable": ("tab:green", "o"), "refused": ("grey", "s")}
            reason_marker = {"non-finite": "X", "particle CFL": "x", "marker CFL": "+", "marker left fluid": "D",
                             "fixed point": "v", "energy growth": "^", "other": "*"}
            fig, axs = plt.subplots(1, len(axes), figsize=(4.2 * len(axes), 4), squeeze=False)
            for k, a in enumerate(axes):
                ax = axs[0][k]
                seen = set()
                for r in (x for x in R if x["axis"] == a):
                    if r["verdict"] == "unstable":
                        c, mk, lab = "tab:red", reason_marker.get(r["reason"], "*"), "unstable: " + r["reason"]
                    else:
                        c, mk = style[r["verdict"]]
                        lab = r["verdict"]
                    ax.scatter(val[a](r), fl(r, "dt"), color=c, marker=mk, s=45, label=lab if lab not in seen else None)
                    seen.add(lab)
                ax.set(xscale="log", yscale="log", xlabel=a, ylabel="dt", title=f"G: dt vs {a}")
                ax.grid(True, which="both", alpha=0.3)
                ax.legend(fontsize=6)
            save(fig, os.path.join(d, "stability_grid.png"))


def collapse(d, D, parts):
    """dt_max in units of sqrt(rho dx^3/T0) against mu/sqrt(rho T0 dx): with rho and the geometry fixed,
    (T0, mu) -> (l^2 T0, l mu) rescales time by 1/l, so this is the one variable the limit depends on."""
    rs = [r for r in D if r["part"] in parts]
    if not rs or "classical_estimate" not in rs[0]:
        return
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    style = {"T": ("tab:blue", "o", "T: run_scene (guards, convection)"),
             "E": ("tab:orange", "s", "E: no guards, convection"),
             "S": ("tab:green", "^", "S: no guards, Stokes")}
    rho = 1.0
    for p in parts:
        c, mk, lab = style[p]
        sub = [r for r in rs if r["part"] == p]
        xs, ys, xa, ya = [], [], [], []
        for r in sub:
            dx, T0, mu = fl(r, "dx"), fl(r, "T0"), fl(r, "mu")
            unit = math.sqrt(rho * dx ** 3 / T0)
            x = mu / math.sqrt(rho * T0 * dx)
            if math.isfinite(fl(r, "dt_max")):
                xs.append(x)
                ys.append(fl(r, "dt_max") / unit)
            elif math.isfinite(fl(r, "dt_stable")):  # stable up to the cap: a lower bound
                xa.append(x)
                ya.append(fl(r, "dt_stable") / unit)
        ax.scatter(xs, ys, color=c, marker=mk, s=28, label=lab, alpha=0.8)
        for x, y in zip(xa, ya):  # lower bounds: hollow, with an arrow up
            ax.scatter([x], [y], facecolors="none", edgecolors=c, marker=mk, s=40)
            ax.annotate("", (x, y * 2.2), (x, y), arrowprops=dict(arrowstyle="->", color=c, lw=1))
        ci, cv = fl(sub[0], "fit_Ci"), fl(sub[0], "fit_Cv")
        xx = [10 ** (k / 20) for k in range(-110, 31)]
        if math.isfinite(ci) and math.isfinite(cv):
            ax.plot(xx, [max(ci, cv * x) for x in xx], "--", color=c, lw=1,
                    label=f"fit {p}: max({ci:.2f}, {cv:.1f} x)")
    xx = [10 ** (k / 20) for k in range(-110, 31)]
    # sphib check uses h*: in these units max(s^1.5, 10 s x), s = h*/dx (the bench's default h* = 1.68 dx)
    sr = [fl(r, "h_star") / fl(r, "dx") for r in rs if r["axis"].startswith("T0")]
    if sr:
        sv = sr[0]
        ax.plot(xx, [max(sv ** 1.5, 10 * sv * x) for x in xx], "k:", lw=1,
                label=f"sphib check (h* = {sv:.2f} dx): max((h*/dx)^1.5, 10 (h*/dx) x)")
    ax.plot(xx, [max(1 / math.sqrt(2 * math.pi), 8 / math.pi * x) for x in xx], "k-.", lw=1.2,
            label="classical explicit: max(1/√(2π), (8/π) x)\n(Brackbill et al. 1992; Stokes rate T0 k/4μ)")
    ax.set(xscale="log", yscale="log", xlabel="μ / √(ρ T0 dx)", ylabel="dt_max / √(ρ dx³ / T0)",
           title="Largest stable dt, 32², all (T0, μ) pairs\n(hollow with arrow: stable up to dt = 1, a lower bound)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    save(fig, os.path.join(d, "stability_collapse.png"))


# ---- scaling -----------------------------------------------------------------------------------


def ok_rows_by_case(path):
    """The rows of a scaling CSV without an error, and their cases in order of appearance."""
    R = [r for r in read(path) if not r["error"]]
    return R, list(dict.fromkeys(r["case"] for r in R))


def scaling(d):
    p = os.path.join(d, "scaling.csv")
    if os.path.exists(p):
        R, cases = ok_rows_by_case(p)
        fig, axs = plt.subplots(1, 3, figsize=(19, 5))
        colors = {"poiseuille": "tab:blue", "membrane": "tab:red"}
        for c in cases:
            rs = sorted((r for r in R if r["case"] == c), key=lambda r: fl(r, "n"))
            N = [fl(r, "n") for r in rs]
            big = [(n, r) for n, r in zip(N, rs) if int(r["nx"]) >= 64]

            def plot(ax, key, ls, lab, f=lambda r, k: fl(r, k)):
                ys = [f(r, key) for r in rs]
                a, b = slope([n for n, _ in big], [f(r, key) for _, r in big])
                ax.plot(N, ys, "o" + ls, color=colors.get(c), label=f"{c}: {lab} (N^{a:.2f})")

            plot(axs[0], "per_step_s", "-", "time per step")
            plot(axs[0], "solves_per_step_s", "--", "solves")
            plot(axs[1], "setup_neighbours_s", ":", "neighbours")
            plot(axs[1], "setup_assembly_s", "--", "assembly")
            plot(axs[1], "setup_factorisation_s", "-", "analysis + factorisation")
            plot(axs[2], "vmhwm_kb", "-", "peak − start", f=lambda r, k: (fl(r, "vmhwm_kb") - fl(r, "rss_start_kb")) / 1024)
        axs[0].set(ylabel="seconds per step")
        axs[1].set(ylabel="seconds (once)")
        axs[2].set(ylabel="MB")
        for ax, t in zip(axs, ("time per step (one core)", "one-off set-up", "peak memory (VmHWM) above the start")):
            ax.set(xscale="log", yscale="log", xlabel="particles N", title=t)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
        save(fig, os.path.join(d, "scaling.png"))
    p = os.path.join(d, "solvers.csv")
    if os.path.exists(p):
        R, cases = ok_rows_by_case(p)
        fig, axs = plt.subplots(len(cases), 2, figsize=(13, 4.5 * len(cases)), squeeze=False)
        colors = {"cholmod_supernodal": "tab:blue", "cholmod_simplicial": "tab:green", "pcg": "tab:red",
                  "eigen_ldlt": "tab:purple"}
        for i, c in enumerate(cases):
            for v, col in colors.items():
                rs = sorted((r for r in R if r["case"] == c and r["cn"] == v), key=lambda r: fl(r, "n"))
                if not rs:
                    continue
                N = [fl(r, "n") for r in rs]
                axs[i][0].plot(N, [fl(r, "cn_solve_per_step_s") for r in rs], "o-", color=col, label=f"{v}: Crank-Nicolson")
                axs[i][0].plot(N, [fl(r, "poisson_solve_per_step_s") for r in rs], "s--", color=col, label=f"{v}: Poisson")
                axs[i][1].plot(N, [fl(r, "cn_analyse_s") + fl(r, "cn_factor_s") for r in rs], "o-", color=col,
                               label=f"{v}: Crank-Nicolson")
                axs[i][1].plot(N, [fl(r, "poisson_analyse_s") + fl(r, "poisson_factor_s") for r in rs], "s--",
                               color=col, label=f"{v}: Poisson")
            axs[i][0].set(title=f"{c}: time per solve", ylabel="seconds")
            axs[i][1].set(title=f"{c}: analysis + factorisation", ylabel="seconds")
            for ax in axs[i]:
                ax.set(xscale="log", yscale="log", xlabel="particles N")
                ax.grid(True, which="both", alpha=0.3)
                ax.legend(fontsize=7)
        save(fig, os.path.join(d, "scaling_solvers.png"))


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "bench_out"
    if len(sys.argv) > 1 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return
    speed_accuracy(os.path.join(root, "speed_accuracy"))
    stability(os.path.join(root, "stability_map"))
    scaling(os.path.join(root, "scaling"))


if __name__ == "__main__":
    main()
