# The dam-break surge front against the experiments (docs/validation/isph.md, "Dam break by ISPH"):
#   /usr/bin/python3 scripts/dam_break_front.py RUN...
# First the experiments against each other (rms of Z_B - Z_A at A's points up to Z = 3.5, B
# interpolated in T, where B has points: their own scatter). Then per run: the rms of Z - Z_exp for each experiment as
# the summary's front_deviation_* (points up to Z = 3.5), the front's mean speed dZ/dT over
# T = 1.5-2.5, the time the front first loads the right wall, and the delay dT of the run's time
# origin (run sampled at T - dT, on a 0.01 grid in [0, 1]) that minimises the mean of the three rms,
# with the rms after it.
import os, sys
import numpy as np
import h5py
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot import attr, read_csv, read_front_reference, reference_dir, require  # noqa: E402

NAMES = ["koshizuka_oka_1996", "martin_moyce_1952_a1.125in", "martin_moyce_1952_a2.25in"]


def rms_against(T, Z, e):
    m = (e[:, 1] <= 3.5) & (e[:, 0] >= T[0]) & (e[:, 0] <= T[-1])  # Z up to 3.5 (observe/dam_break.cpp), within T
    return float(np.sqrt(np.mean((np.interp(e[m, 0], T, Z) - e[m, 1]) ** 2)))


def main(runs):
    exps = None
    for run in runs:
        with h5py.File(require(os.path.join(run, "output.h5")), "r") as h5:
            fx = attr(h5, "fill.x", [0, 1])
            a = float(fx[1]) - float(fx[0])
            g = float(np.hypot(*attr(h5, "fluid.gravity", [0.0, -9.81])))
            ref = reference_dir(h5)
        if exps is None:
            exps = {n: read_front_reference(os.path.join(ref, "dam_break_front_%s.csv" % n)) for n in NAMES}
            for A in NAMES:
                print("experiment %s: rms against %s" % (A, ", ".join(
                    "%s %.3f" % (B, rms_against(exps[B][:, 0], exps[B][:, 1], exps[A])) for B in NAMES if B != A)))
        d = read_csv(require(os.path.join(run, "diagnostics.csv")))
        T, Z = d["t"] * np.sqrt(2 * g / a), d["front_x"] / a
        dev = lambda dT: [rms_against(np.r_[0.0, T + dT], np.r_[Z[0], Z], e) for e in exps.values()]  # noqa: E731
        best = min(np.arange(0.0, 1.0, 0.01), key=lambda s: np.mean(dev(s)))
        loaded = d["load_right"] != 0 if "load_right" in d else np.zeros(1, bool)
        hit = d["t"][np.argmax(loaded)] if loaded.any() else float("nan")  # nan: not by the run's end
        print("%s: rms %s; dZ/dT(1.5-2.5) %.3f; right wall loaded at t = %.4f; delay dT = %.2f (%.1f ms): rms %s"
              % (run, " ".join("%.3f" % v for v in dev(0.0)), np.interp(2.5, T, Z) - np.interp(1.5, T, Z), hit,
                 best, 1e3 * best / np.sqrt(2 * g / a), " ".join("%.3f" % v for v in dev(best))))
    for n, e in (exps or {}).items():
        print("%s: dZ/dT(1.5-2.5) %.3f" % (n, np.interp(2.5, e[:, 0], e[:, 1]) - np.interp(1.5, e[:, 0], e[:, 1])))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__ or "usage: dam_break_front.py RUN...")
    main(sys.argv[1:])
