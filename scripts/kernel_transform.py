#!/usr/bin/python3
"""The 2-D Fourier transform of the cubic spline kernel (h = 1, support 2) against sinc^4(q/2) and the
stiff-force filter's upper bound min(1, 1.5 sinc^4(q/2) + 1e-3) (coupling/stiff_force.cpp), by a
numerical Hankel transform W^(q) = 2 pi int_0^2 W(r) J0(q r) r dr. Usage: scripts/kernel_transform.py"""
import numpy as np


def W(r):
    w = np.zeros_like(r)
    a, b = r < 1, (r >= 1) & (r < 2)
    w[a] = 1 - 1.5 * r[a] ** 2 + 0.75 * r[a] ** 3
    w[b] = 0.25 * (2 - r[b]) ** 3
    return w * 10 / (7 * np.pi)


def J0(x):
    th = np.linspace(0, np.pi, 4001)
    return np.trapz(np.cos(np.outer(x, np.sin(th))), th, axis=1) / np.pi


r = np.linspace(0, 2, 20001)
print(f"{'q':>5} {'W^(q)':>10} {'sinc^4':>10} {'bound':>10}")
worst = 0.0
for q in [0, 0.5, 1, 2, 3, 4, 5, 5.5, 6, 7, 8, 10, 12, 15, 20]:
    Wq = 2 * np.pi * np.trapz(W(r) * J0(q * r) * r, r)
    s = np.sinc(q / 2 / np.pi) ** 4
    bound = min(1.0, 1.5 * s + 1e-3)
    worst = max(worst, abs(Wq) / bound)
    print(f"{q:5g} {Wq:10.5f} {s:10.5f} {bound:10.5f}")
print(f"largest |W^|/bound: {worst:.3f} (the bound holds where this is <= 1)")
