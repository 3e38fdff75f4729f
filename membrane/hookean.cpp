// Hookean force density, Eqs. (47)-(50), from periodic cubic splines in the rest arclength s.
//
// Two ways to take f = d(T tau)/ds (Eq. 50), measured against the exact f (chain rule on the
// analytic X(s)); max |f - f_exact| / max |f_exact|, r0 = 0.5, T0 = 3:
//
//          ellipse rx = 0.75, ry = 0.5 (non-uniform stretch)   circle re = 0.6
//   nb     ProductSpline  order   Analytic  order              ProductSpline  Analytic
//   32     3.07e-3        -       3.21e-3   -                  5.81e-5        3.18e-3
//   64     1.61e-4        4.26    8.03e-4   2.00               3.62e-6        8.01e-4
//   128    9.57e-6        4.07    2.01e-4   2.00               2.26e-7        2.01e-4
//   256    5.91e-7        4.02    5.02e-5   2.00               1.41e-8        5.02e-5
//
// Paper case (Section 5.2.1, nb = 140): f.n = -1.2 to 1.9e-7 (ProductSpline), 2.0e-4
// (Analytic). T of Eq. (47) is common to both: order 4, 1.5e-7 at nb = 128 on the ellipse.
//
// Default ProductSpline, because (i) the spline's first derivative at the knots is O(h^4)
// but its second derivative M_k only O(h^2), so two d/ds beat one X_ss; (ii) knot
// derivatives of a periodic spline telescope, so sum_k f_k ds = 0 to round-off on any shape
// (momentum conserved; Analytic leaves |sum f ds| = 3.8e-3 on a blob at nb = 128); (iii) f
// matches -dE/dX at order 4 (Analytic: 2). Its cost, 4 spline fits instead of 2, is
// 4.1 us vs 2.3 us per call at nb = 128 (-O3), i.e. 0.4 s per 1e5 steps.
// Caveat: d/ds of a uniform spline barely sees the sawtooth (-1)^k (its symbol
// 3 sin(th)/(h (2 + cos th)) vanishes at th = pi), so a marker-scale zigzag meets ~90x less
// restoring force than with Analytic, whose X_ss symbol there is -12/h^2.
#include "membrane/hookean.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace sphib {

HookeanForce::HookeanForce(int nb, double L0, HookeanScheme scheme)
    : nb_(nb), L0_(L0), scheme_(scheme), spline_(nb, L0), X_s_(nb, 2), W_(nb, 2) {}

void HookeanForce::compute(const Mat2& X, double T0, Mat2& f, Vec& T) {
  if (X.rows() != nb_)
    throw std::invalid_argument("HookeanForce: X has " + std::to_string(X.rows()) +
                                " markers, expected nb = " + std::to_string(nb_));
  f.resize(nb_, 2);  // no-op (no allocation) when already nb x 2
  T.resize(nb_);
  const int n = nb_;

  for (int d = 0; d < 2; ++d) {  // X_s (and X_ss) at the knots, one spline per coordinate
    spline_.fit(X.data() + d * n);
    spline_.d1_at_knots(X_s_.data() + d * n);
    if (scheme_ == HookeanScheme::Analytic) spline_.d2_at_knots(W_.data() + d * n);
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
    for (int d = 0; d < 2; ++d) {  // f = d(T tau)/ds, Eq. (50)
      spline_.fit(W_.data() + d * n);
      spline_.d1_at_knots(f.data() + d * n);
    }
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
