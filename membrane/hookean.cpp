// Hookean force density, Eqs. (47)-(50), from periodic cubic splines in the rest arclength s.
//
// Two ways to take f = d(T tau)/ds (Eq. 50). ProductSpline, the default: the spline's first
// derivative at the knots is O(h^4) but its second derivative M_k only O(h^2), so two d/ds beat one
// X_ss; knot derivatives of a periodic spline telescope, so sum_k f_k ds = 0 to round-off on any
// shape (momentum conserved); f matches -dE/dX at order 4; it costs 4 spline fits instead of 2.
// Analytic: the chain rule on X_ss, order 2. Their measured errors and orders are in
// tests/test_membrane.cpp (HookeanTest.*).
// Caveat: d/ds of a uniform spline barely sees the sawtooth (-1)^k (its symbol
// 3 sin(th)/(h (2 + cos th)) vanishes at th = pi), so a marker-scale zigzag meets ~90x less
// restoring force than with Analytic, whose X_ss symbol there is -12/h^2.
#include "membrane/hookean.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace sphib {

Membrane make_membrane(Mat2 X, double r0, double T0) {
  if (X.rows() < 4)
    throw std::invalid_argument("membrane: nb = " + std::to_string(X.rows()) + " markers, need nb >= 4");
  if (!(r0 > 0.0) || !std::isfinite(r0))
    throw std::invalid_argument("membrane: rest radius r0 = " + std::to_string(r0) + " must be positive and finite");
  constexpr double kPi = 3.14159265358979323846;
  return {std::move(X), 2.0 * kPi * r0, T0};
}

HookeanForce::HookeanForce(int nb, double L0, HookeanScheme scheme)
    : nb_(nb), L0_(L0), scheme_(scheme), sx_(nb, L0), sy_(nb, L0), wx_(nb, L0), wy_(nb, L0), X_s_(nb, 2), W_(nb, 2) {}

void HookeanForce::compute(const Mat2& X, double T0, Mat2& f, Vec& T) {
  if (X.rows() != nb_)
    throw std::invalid_argument("HookeanForce: X has " + std::to_string(X.rows()) +
                                " markers, expected nb = " + std::to_string(nb_));
  f.resize(nb_, 2);  // no-op (no allocation) when already nb x 2
  T.resize(nb_);
  const int n = nb_;

  PeriodicSpline::fit_pair(sx_, X.data(), sy_, X.data() + n);  // one spline per coordinate
  for (int d = 0; d < 2; ++d) {  // X_s (and X_ss) at the knots
    spline(d).d1_at_knots(X_s_.data() + d * n);
    if (scheme_ == HookeanScheme::Analytic) spline(d).d2_at_knots(W_.data() + d * n);
  }

  if (scheme_ == HookeanScheme::ProductSpline) {
    for (int k = 0; k < n; ++k) {
      const double xs = X_s_(k, 0), ys = X_s_(k, 1);
      const double norm = std::sqrt(xs * xs + ys * ys);  // |X_s|
      T[k] = T0 * (norm - 1.0);                          // Eq. (47)
      const double T_over_norm = T[k] / norm;            // T tau = T X_s/|X_s|, Eq. (48)
      W_(k, 0) = T_over_norm * xs;
      W_(k, 1) = T_over_norm * ys;
    }
    PeriodicSpline::fit_pair(wx_, W_.data(), wy_, W_.data() + n);  // f = d(T tau)/ds, Eq. (50)
    wx_.d1_at_knots(f.data());
    wy_.d1_at_knots(f.data() + n);
    return;
  }

  // Analytic: d(T tau)/ds = T0 (X_ss - X_ss/|X_s| + X_s (X_s . X_ss)/|X_s|^3), Eqs. (47,48,50).
  for (int k = 0; k < n; ++k) {
    const double xs = X_s_(k, 0), ys = X_s_(k, 1);
    const double xss = W_(k, 0), yss = W_(k, 1);
    const double norm = std::sqrt(xs * xs + ys * ys);      // |X_s|
    T[k] = T0 * (norm - 1.0);                              // Eq. (47)
    const double inv = 1.0 / norm;
    const double a = T0 * (1.0 - inv);                     // T0 (1 - 1/|X_s|) X_ss
    const double b = T0 * (xs * xss + ys * yss) * inv * inv * inv;  // T0 (X_s.X_ss)/|X_s|^3 X_s
    f(k, 0) = a * xss + b * xs;                            // Eq. (50)
    f(k, 1) = a * yss + b * ys;
  }
}

}  // namespace sphib
