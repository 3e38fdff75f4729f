# When the flow reaches each pressure probe and its largest reading (docs/free_surfaces.md, "Dam break:
# impact pressures against Lobovsky et al. (2014)"):
#   /usr/bin/python3 scripts/probe_arrival.py [--H 0.3] RUN...
# per run and probe: the first time its reading is above zero (the sensor wet: the window's mean of
# a dry sensor is 0), the largest reading and its time (the window's end), times also as t sqrt(g/H).
# The diagnostics must be written every step (output.diagnostics_every = 1).
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot import read_csv, require  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--H", type=float, default=0.3, help="the column's height, m (Lobovsky et al.: 0.3)")
    ap.add_argument("--g", type=float, default=9.81)
    ap.add_argument("runs", nargs="+")
    a = ap.parse_args()
    s = np.sqrt(a.g / a.H)
    for run in a.runs:
        d = read_csv(require(os.path.join(run, "diagnostics.csv")))
        t = d["t"]
        for name in sorted(k for k in d if k.startswith("probe_")):
            p = d[name]
            wet = np.flatnonzero(p > 0)
            tw = t[wet[0]] if wet.size else float("nan")
            k = int(np.argmax(p))
            print("%s %s: wet at t = %.4f (%.3f); max %.0f Pa at t = %.4f (%.3f)%s"
                  % (run, name, tw, tw * s, p[k], t[k], t[k] * s, " (the run's end)" if k == len(p) - 1 else ""))


if __name__ == "__main__":
    main()
