#pragma once
// Cubic B-spline smoothing kernel in two dimensions, Eq. (19), support 2h.
// Contract: a Kernel gives W(r), dW/dr and (1/r) dW/dr for one smoothing length h.
#include <cmath>

namespace sphib {

struct CubicSplineKernel {
  double h;
  double w0;  // 15 / (7 pi h^2): 2-D normalisation of Eq. (19)

  explicit CubicSplineKernel(double h_) : h(h_), w0(15.0 / (7.0 * M_PI * h_ * h_)) {}

  double support() const { return 2.0 * h; }

  // W(r, h), Eq. (19)
  double W(double r) const {
    const double q = r / h;
    if (q < 1.0) return w0 * (2.0 / 3.0 - q * q + 0.5 * q * q * q);
    if (q < 2.0) { const double t = 2.0 - q; return w0 * t * t * t / 6.0; }
    return 0.0;
  }

  // dW/dr
  double dWdr(double r) const {
    const double q = r / h;
    if (q < 1.0) return w0 / h * (-2.0 * q + 1.5 * q * q);
    if (q < 2.0) { const double t = 2.0 - q; return -w0 / h * 0.5 * t * t; }
    return 0.0;
  }

  // (1/r) dW/dr, finite as r -> 0 (limit -2 w0 / h^2); the factor every SPH operator of Eqs. (27)-(35) uses.
  double F(double r) const {
    const double q = r / h;
    if (q < 1.0) return w0 / (h * h) * (-2.0 + 1.5 * q);
    if (q < 2.0) { const double t = 2.0 - q; return -w0 / (h * h) * 0.5 * t * t / q; }
    return 0.0;
  }
};

}  // namespace sphib
