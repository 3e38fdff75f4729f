#!/usr/bin/python3
"""The SPH operators' constant factor on a uniform lattice (docs/membrane_validation.md).

On an infinite lattice of spacing dx, the SPH gradient sum_j V_j (f_j - f_i) grad W(x_i - x_j) of a
linear field, and the Brookshaw laplacian 2 sum_j V_j (f_i - f_j) W'(r)/r of a quadratic one, both
equal the exact value times

    F(h/dx) = -sum_{(i,j) != 0} (i^2 / r) W'(r) dx^2,    r = |(i, j)| dx,

the lattice sum of a moment the continuous integral makes exactly 1. F depends on h/dx only (the sum
scales with dx), so it does not tend to 1 as dx -> 0 at a fixed h/dx. W is the 2-D cubic spline of
Eq. (19) of the main paper (kernels/cubic_spline.hpp; support 2h, normalisation 10/(7 pi h^2)).

  lattice_kernel_factor.py [h/dx ...]      (default: 1.2 1.5 2.0)
"""
import math
import sys


def dW(r, h):
    """dW/dr of the 2-D cubic spline kernel with support 2h."""
    q, s = r / h, 10.0 / (7.0 * math.pi * h * h)
    if q < 1.0:
        return s * (-3.0 * q + 2.25 * q * q) / h
    if q < 2.0:
        return -0.75 * s * (2.0 - q) ** 2 / h
    return 0.0


def factor(h_over_dx):
    """F for dx = 1, h = h_over_dx."""
    n = int(2 * h_over_dx) + 1
    return -sum(i * i / math.hypot(i, j) * dW(math.hypot(i, j), h_over_dx)
                for i in range(-n, n + 1) for j in range(-n, n + 1) if (i, j) != (0, 0))


if __name__ == "__main__":
    for a in sys.argv[1:] or ["1.2", "1.5", "2.0"]:
        F = factor(float(a))
        print(f"h/dx = {float(a):g}: factor {F:.5f} ({100 * (F - 1):+.2f}%)")
