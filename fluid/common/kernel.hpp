#pragma once
// Cubic B-spline smoothing kernel in two dimensions, Eq. (19), support 2h.
// Contract: a Kernel gives W(r), dW/dr and (1/r) dW/dr for one smoothing length h.
#include "kernels/cubic_spline.hpp"  // the scalar and lane forms of Eq. (19)

namespace sphib {

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

  // The markers' loops (coupling/neighbourhood.hpp) take two points at a time, lane by lane, from
  // squared distances r2 (kernels/cubic_spline.hpp: branch-free, one square root; within a few units
  // in the last place of W(0) and F(0) of the scalar forms; 0 from 2h on).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
  template <class L>
  L W2(L r2) const { return CubicSplineLanes<L>(scale(), r2).W(); }
  template <class L>
  void W_F2(L r2, L& w, L& f) const {
    const CubicSpline s = scale();
    const CubicSplineLanes<L> p(s, r2);
    w = p.W();
    f = p.F();
  }
  // ... and G = (1/r) dF/dr: the Hessian of W(|x|) is F I + G x x^T (0 at r = 0, where G x x^T -> 0).
  template <class L>
  void W_F_G2(L r2, L& w, L& f, L& g) const {
    const CubicSpline s = scale();
    const CubicSplineLanes<L> p(s, r2);
    w = p.W();
    f = p.F();
    g = p.G();
  }
#pragma GCC diagnostic pop
};

}  // namespace sphib
