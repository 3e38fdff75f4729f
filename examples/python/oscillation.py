"""The oscillating membrane (Section 5.2.2, cases/membrane_oscillation.toml) from Python: the
library's own run and output, with one observer of our own; prints the final enclosed-area error.

    /usr/bin/python3 examples/python/oscillation.py --steps 1000     (after scripts/run_main.sh; or PYTHONPATH=build/python)
"""
import argparse
import os

import sphib

here = os.path.dirname(os.path.abspath(__file__))
ap = argparse.ArgumentParser(description="the oscillating membrane from Python")
ap.add_argument("--steps", type=int, default=0, help="stop after N steps (0: to the scene's end, t = 10)")
ap.add_argument("--out", default="out/python_oscillation", help="output directory")
args = ap.parse_args()

scene = sphib.load_scene(os.path.join(here, "..", "..", "cases", "membrane_oscillation.toml"),
                         set={"time.max_steps": args.steps})
scene.observe("mean_tension", lambda sim: float(sim.tension(0).mean()))  # a column of diagnostics.csv
summary = sphib.run(scene, out=args.out)
print(f"{summary['steps']} steps to t = {summary['time']:.6g}: rx = {summary['rx']:.6f}, "
      f"mean tension {summary['mean_tension']:.6f}, area error {summary['area_relative_error']:.6e}")
