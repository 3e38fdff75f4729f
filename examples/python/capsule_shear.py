"""A capsule in simple shear from Python: a circular membrane at its rest length between
walls y = +-H/2 sliding at -+U (shear rate G = 2U/H), periodic in x; capillary number
Ca = mu G r0 / Es (Es: the law's modulus, the Hookean T0), bending modulus Eb = eb_hat Es r0^2. It becomes an inclined ellipse round which its membrane tank-treads. Prints the
Taylor deformation D, the inclination theta and the tank-treading frequency omega/G, means over the
last quarter of the run: the same scene as cases/capsule_shear.cpp (build/capsule_shear), built from keys.

    /usr/bin/python3 examples/python/capsule_shear.py [--ca 0.05,0.1,0.2] [--law skalak] [--eb-hat 0.1]
                                                      [--steps N] [--out DIR]
"""
import argparse
import math
import os

import numpy as np
import sphib

ap = argparse.ArgumentParser(description="capsule in simple shear: D, theta, omega against Ca")
ap.add_argument("--ca", default="0.1", help="capillary numbers mu G r0 / T0, comma-separated (default 0.1)")
ap.add_argument("--law", default="hookean", help="tension law: hookean, neo_hookean, skalak (default hookean)")
ap.add_argument("--eb-hat", type=float, default=0.0, help="bending modulus Eb / (Es r0^2) (default 0: no bending)")
ap.add_argument("--steps", type=int, default=0, help="stop each run after N steps (0: to t = 16/G)")
ap.add_argument("--out", default="out/capsule_shear_py", help="output directory (one run per Ca inside)")
args = ap.parse_args()

H, L, U, r0, rho, mu, nx = 2.0, 4.0, 1.0, 0.4, 1.0, 1.0, 64
G = 2 * U / H
dx = L / nx
print(f"{'Ca':>6} {'Es':>6} {'D':>8} {'theta':>8} {'omega/G':>8} {'area err':>10}")
for Ca in (float(c) for c in args.ca.split(",")):
    Es = mu * G * r0 / Ca
    material = {"T0": Es} if args.law == "hookean" else {"law": args.law, "Es": Es}
    scene = sphib.Scene({"domain": {"x": [-L / 2, L / 2], "y": [-H / 2, H / 2], "periodic_x": True, "periodic_y": False},
                         "walls": {"top": [U, 0.0], "bottom": [-U, 0.0]},
                         "grid": {"nx": nx, "ny": nx // 2}, "fluid": {"rho": rho, "mu": mu},
                         "time": {"dt": 0.0125 * dx / U, "end": 16 / G, "max_steps": args.steps}},
                        name=f"capsule, Ca = {Ca:g}")
    nb = round(2 * math.pi * r0 / (0.5 * dx))  # two markers per lattice spacing
    scene.add_membrane(sphib.circle(nb=nb, r0=r0, Eb=args.eb_hat * Es * r0**2, **material), h_star=1.4 * 1.2 * dx)
    history = []  # (t, D, theta, omega) at every diagnostics row

    def deformation(sim):
        shape = sim.shape(0)  # the ellipse with the markers' area moments
        history.append((sim.time, shape.deformation, shape.theta, sim.angular_velocity(0)))
        return shape.deformation

    scene.observe("D", deformation)
    scene.observe("theta_deg", lambda sim: math.degrees(history[-1][2]))
    scene.observe("omega_over_G", lambda sim: history[-1][3] / G)
    summary = sphib.run(scene, out=os.path.join(args.out, f"ca_{Ca:g}"))
    h = np.array(history)
    last = h[h[:, 0] >= 0.75 * h[-1, 0]]  # the last quarter
    print(f"{Ca:6g} {Es:6g} {last[:, 1].mean():8.4f} {math.degrees(last[:, 2].mean()):8.2f} "
          f"{last[:, 3].mean() / G:8.4f} {summary['area_relative_error']:10.2e}")
