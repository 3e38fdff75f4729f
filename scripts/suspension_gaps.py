#!/usr/bin/env python3
"""The least distance between the marker polygons of two membranes (segment to segment, minimum
image along a periodic x of period --period), at each snapshot of a run's output.h5: 0 where two
polygons cross. For suspensions (docs/suspensions.md); the run's gap_min column is the same
between markers only.

    /usr/bin/python3 scripts/suspension_gaps.py out/suspension/output.h5 [--period 1] [--dx 0.00390625]
"""
import argparse

import h5py
import numpy as np


def point_segment(p, a, b):
    ab = b - a
    t = np.clip(((p - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 0.0, 1.0)
    return np.linalg.norm(a + t[..., None] * ab - p, axis=-1)


def segment_distance(p1, p2, q1, q2):
    """Distance between the segments p1p2 and q1q2 (broadcast), 0 where they cross."""
    d = np.minimum.reduce([point_segment(p1, q1, q2), point_segment(p2, q1, q2),
                           point_segment(q1, p1, p2), point_segment(q2, p1, p2)])

    def cross(u, v):
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    crossing = ((cross(p2 - p1, q1 - p1) * cross(p2 - p1, q2 - p1) < 0)
                & (cross(q2 - q1, p1 - q1) * cross(q2 - q1, p2 - q1) < 0))
    return np.where(crossing, 0.0, d)


def least_gap(X, period):
    best = np.inf
    for i in range(len(X)):
        A = X[i]
        A2 = np.roll(A, -1, 0)
        size = np.ptp(A, axis=0).max()
        for j in range(i + 1, len(X)):
            B = X[j]
            if period > 0:  # the nearest periodic copy of B
                B = B - np.array([period * np.round((B[:, 0].mean() - A[:, 0].mean()) / period), 0.0])
            if np.linalg.norm(A.mean(0) - B.mean(0)) > size + np.ptp(B, axis=0).max():
                continue  # bounding circles apart
            B2 = np.roll(B, -1, 0)
            best = min(best, segment_distance(A[:, None], A2[:, None], B[None], B2[None]).min())
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("output", help="a run's output.h5")
    ap.add_argument("--period", type=float, default=1.0, help="period along x (0: not periodic)")
    ap.add_argument("--dx", type=float, default=0.0, help="lattice spacing, to print the gap in spacings too")
    a = ap.parse_args()
    with h5py.File(a.output, "r") as f:
        for s in sorted(f["snapshots"].keys()):
            g = f["snapshots"][s]
            names = sorted((k for k in g.keys() if k.startswith("membrane_")), key=lambda n: int(n.split("_")[1]))
            gap = least_gap([g[n]["X"][()] for n in names], a.period)
            extra = f" = {gap / a.dx:.3f} dx" if a.dx > 0 else ""
            print(f"snapshot {s}: {len(names)} membranes, least polygon distance {gap:.6g}{extra}")


if __name__ == "__main__":
    main()
