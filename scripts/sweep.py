#!/usr/bin/python3
"""Runs a scene over a grid of parameter values and tabulates summary figures with observed orders.

  sweep.py --scene cases/membrane_equilibrium.toml --out out/fig10 \
      --vary grid.nx=40,60,80 --vary fluid.mu=0.25,1 \
      --derive grid.ny={grid.nx} --derive time.dt=0.1*3/{grid.nx} \
      --set membrane.nb=360 --report pressure_mad_error,velocity_mad_error

Every combination of the --vary values is run (`sphib run SCENE --out OUT/run_k --set ...`);
--derive sets a key from an arithmetic expression of the varied keys; --set fixes a key for
all runs. The first --vary key is the resolution: observed orders are computed between
successive values of it, with the other keys fixed, as log(e_a/e_b)/log(n_b/n_a).
Writes OUT/sweep.csv (one row per run: the varied and derived values, then the reported
summary fields) and OUT/sweep.md (the same with orders), and prints the table.
A run is reused only when its directory holds a summary.json of the same run: the same scene file
(its SHA-256), the same --set values (OUT/run_k/sweep_run.json keeps them) and not stopped by a
signal; any other is run again (its files replaced). A key both varied and set is refused.
"""
import argparse
import csv
import hashlib
import itertools
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def same_run(summary_path, record_path, record):
    """The directory holds a complete run of this scene file and these settings."""
    try:
        with open(record_path) as f:
            if json.load(f) != record:
                return False
        with open(summary_path) as f:
            s = json.load(f)
        return "stop_signal" not in s and s.get("stop_reason") not in ("interrupted", "terminated")
    except (OSError, ValueError):
        return False


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--vary", action="append", default=[], help="key=v1,v2,...")
    ap.add_argument("--derive", action="append", default=[], help="key=expression of {varied.key}")
    ap.add_argument("--set", action="append", default=[], help="key=value for every run")
    ap.add_argument("--report", default="rms_error", help="comma-separated summary fields")
    ap.add_argument("--sphib", default=os.path.join(ROOT, "build", "sphib"))
    a = ap.parse_args()

    keys, values = [], []
    for v in a.vary:
        k, vals = v.split("=", 1)
        keys.append(k)
        values.append(vals.split(","))
    if not keys:
        sys.exit("sweep: give at least one --vary key=v1,v2,...")
    for s in a.set + a.derive:
        if s.split("=", 1)[0] in keys:
            sys.exit(f"sweep: {s.split('=', 1)[0]} is varied (--vary) and set or derived as well: give it once")
    report = [r for r in a.report.split(",") if r]
    with open(a.scene, "rb") as f:
        scene_sha256 = hashlib.sha256(f.read()).hexdigest()
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for k, combo in enumerate(itertools.product(*values)):
        env = dict(zip(keys, combo))
        sets = [f"{kk}={vv}" for kk, vv in env.items()]
        derived = {}
        for d in a.derive:
            dk, expr = d.split("=", 1)
            text = expr
            for kk, vv in env.items():
                text = text.replace("{" + kk + "}", vv)
            val = eval(text, {"__builtins__": {}}, {"sqrt": math.sqrt, "pi": math.pi})
            derived[dk] = repr(val) if isinstance(val, float) else str(val)
            sets.append(f"{dk}={derived[dk]}")
        sets += a.set
        run_dir = os.path.join(a.out, "run_%03d" % k)
        summary_path = os.path.join(run_dir, "summary.json")
        record_path = os.path.join(run_dir, "sweep_run.json")
        record = {"scene": os.path.abspath(a.scene), "scene_sha256": scene_sha256, "sets": sets}
        if not same_run(summary_path, record_path, record):
            cmd = [a.sphib, "run", a.scene, "--out", run_dir, "--quiet"]
            for s in sets:
                cmd += ["--set", s]
            print("sweep:", " ".join(cmd), flush=True)
            r = subprocess.run(cmd)
            if r.returncode != 0 and not os.path.exists(summary_path):
                print(f"sweep: run {k} failed (exit {r.returncode})", file=sys.stderr)
                continue
            with open(record_path + ".part", "w") as f:
                json.dump(record, f)
            os.replace(record_path + ".part", record_path)
        with open(summary_path) as f:
            s = json.load(f)
        row = dict(env)
        row.update(derived)
        for r in report:  # a dotted name reaches into nested objects: area_relative_error_at.2
            v = s
            for part in r.split("."):
                v = v.get(part) if isinstance(v, dict) else None
            row[r] = v
        row["steps"] = s.get("steps")
        row["wall_seconds"] = s.get("wall_seconds")
        row["run"] = run_dir
        rows.append(row)

    cols = keys + list(dict.fromkeys(d.split("=", 1)[0] for d in a.derive)) + report + ["steps", "wall_seconds", "run"]
    with open(os.path.join(a.out, "sweep.csv.part"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for r in rows:
            w.writerow(r)
    os.replace(os.path.join(a.out, "sweep.csv.part"), os.path.join(a.out, "sweep.csv"))

    # Observed orders along the first varied key, the others fixed.
    res = keys[0]
    lines = ["| " + " | ".join(cols[:-1]) + " | " + " | ".join("order " + r for r in report) + " |",
             "|" + "---|" * (len(cols) - 1 + len(report))]
    for i, r in enumerate(rows):
        prev = None
        for j in range(i - 1, -1, -1):
            if all(rows[j][k] == r[k] for k in keys[1:]):
                prev = rows[j]
                break
        orders = []
        for rep in report:
            try:
                e0, e1 = float(prev[rep]), float(r[rep])
                n0, n1 = float(prev[res]), float(r[res])
                orders.append("%.2f" % (math.log(abs(e0) / abs(e1)) / math.log(n1 / n0)))
            except (TypeError, ValueError, ZeroDivisionError, KeyError):
                orders.append("")
        fmt = lambda v: ("%.4g" % v) if isinstance(v, float) else str(v)
        lines.append("| " + " | ".join(fmt(r[c]) for c in cols[:-1]) + " | " + " | ".join(orders) + " |")
    md = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "sweep.md.part"), "w") as f:
        f.write(md)
    os.replace(os.path.join(a.out, "sweep.md.part"), os.path.join(a.out, "sweep.md"))
    print(md)


if __name__ == "__main__":
    main()
