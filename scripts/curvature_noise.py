#!/usr/bin/python3
"""Marker-scale roughness of a membrane: the curvature of its markers (spectral derivatives along the
label) and the rms of its Fourier modes above nb/4, at each snapshot of a run.
Usage: scripts/curvature_noise.py RUN_DIR [--membrane K]"""
import argparse

import h5py
import numpy as np

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("run")
ap.add_argument("--membrane", type=int, default=0)
a = ap.parse_args()
with h5py.File(f"{a.run}/output.h5", "r") as f:
    print(f"{'t':>8} {'mean kappa':>11} {'rms kappa, modes > nb/4':>24}")
    for s in sorted(f["snapshots"]):
        X = f["snapshots"][s][f"membrane_{a.membrane}"]["X"][:]
        n = len(X)
        m = np.fft.fftfreq(n, 1.0 / n)
        d = lambda y, p: np.real(np.fft.ifft((1j * m) ** p * np.fft.fft(y)))
        xs, ys, xss, yss = d(X[:, 0], 1), d(X[:, 1], 1), d(X[:, 0], 2), d(X[:, 1], 2)
        kappa = (xs * yss - ys * xss) / (xs * xs + ys * ys) ** 1.5
        k_hat = np.fft.fft(kappa) / n
        high = np.abs(m) > n / 4
        print(f"{f['snapshots'][s].attrs['time']:8.3f} {np.mean(kappa):11.4g} {np.sqrt(np.sum(np.abs(k_hat[high]) ** 2)):24.3e}")
