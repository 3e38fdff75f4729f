#pragma once
// The cubic B-spline kernel of Eq. (19) (2-D, support 2h): its scale (h and the normalisation w0)
// in a small struct, its plain scalar form (the equation as written, the reference every lane form
// of kernels/cubic_spline_lanes.hpp is tested against), and the kernel of one smoothing length as
// the fluid and the coupling hold it.
// Contract: a CubicSplineKernel gives W(r), dW/dr and (1/r) dW/dr for one smoothing length h.
#include <cmath>

namespace sphib {

// h and w0 = 15 / (7 pi h^2), the 2-D normalisation of Eq. (19)
struct CubicSpline {
  double h, w0;
  static CubicSpline of(double h) { return {h, 15.0 / (7.0 * M_PI * h * h)}; }
};

// W(r, h), Eq. (19)
inline double cubic_W(const CubicSpline& k, double r) {
  const double q = r / k.h;
  if (q < 1.0) return k.w0 * (2.0 / 3.0 - q * q + 0.5 * q * q * q);
  if (q < 2.0) { const double t = 2.0 - q; return k.w0 * t * t * t / 6.0; }
  return 0.0;
}
// dW/dr
inline double cubic_dWdr(const CubicSpline& k, double r) {
  const double q = r / k.h;
  if (q < 1.0) return k.w0 / k.h * (-2.0 * q + 1.5 * q * q);
  if (q < 2.0) { const double t = 2.0 - q; return -k.w0 / k.h * 0.5 * t * t; }
  return 0.0;
}
// F = (1/r) dW/dr, finite as r -> 0 (limit -2 w0 / h^2); the factor of every SPH operator of Eqs. (27)-(35).
inline double cubic_F(const CubicSpline& k, double r) {
  const double q = r / k.h;
  if (q < 1.0) return k.w0 / (k.h * k.h) * (-2.0 + 1.5 * q);
  if (q < 2.0) { const double t = 2.0 - q; return -k.w0 / (k.h * k.h) * 0.5 * t * t / q; }
  return 0.0;
}
// G = (1/r) dF/dr: the Hessian of W(|x|) is F I + G x x^T (G x x^T -> 0 as r -> 0, so 0 there)
inline double cubic_G(const CubicSpline& k, double r) {
  const double q = r / k.h, c = k.w0 / (k.h * k.h * k.h * k.h);
  if (r == 0.0) return 0.0;
  if (q < 1.0) return 1.5 * c / q;
  if (q < 2.0) return 0.5 * c * (2.0 - q) * (q + 2.0) / (q * q * q);
  return 0.0;
}

struct CubicSplineKernel {
  double h;
  double w0;  // 15 / (7 pi h^2): 2-D normalisation of Eq. (19)

  explicit CubicSplineKernel(double h_) : h(h_), w0(15.0 / (7.0 * M_PI * h_ * h_)) {}

  double support() const { return 2.0 * h; }

  // W(r, h), Eq. (19)
  double W(double r) const { return cubic_W(scale(), r); }
  // dW/dr
  double dWdr(double r) const { return cubic_dWdr(scale(), r); }
  // (1/r) dW/dr, finite as r -> 0 (limit -2 w0 / h^2); the factor every SPH operator of Eqs. (27)-(35) uses.
  double F(double r) const { return cubic_F(scale(), r); }
  CubicSpline scale() const { return {h, w0}; }
};

}  // namespace sphib
