#pragma once
// Periodic cubic spline in the Lagrangian coordinate s (Section 4.2.1: "we use a cubic
// spline interpolation of the markers and obtain all these derivatives directly from the
// interpolating polynomials").
#include <Eigen/Core>

namespace sphib {

// The same aliases as fluid/common/types.hpp (membrane/ must not include fluid/); identical alias
// redeclarations are legal C++, so both headers may appear in one translation unit.
using Vec = Eigen::VectorXd;
using Mat2 = Eigen::Matrix<double, Eigen::Dynamic, 2>;

// Gauss-Legendre 5-point rule on [-1, 1]: exact for polynomials of degree <= 9 (integrals over
// spline segments).
namespace gauss5 {
inline constexpr double x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                0.9061798459386640};
inline constexpr double w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                0.4786286704993665, 0.2369268850561891};
}  // namespace gauss5

/// Periodic cubic spline through n >= 4 values y_k at uniform knots s_k = k*h, h = L/n,
/// period L. The knot second derivatives M solve the cyclic system
///   M_{k-1} + 4 M_k + M_{k+1} = 6 (y_{k+1} - 2 y_k + y_{k-1}) / h^2,
/// whose circulant matrix factors once as (1/rho)(I + rho S)(I + rho S^T), rho = 2 - sqrt(3)
/// (S the cyclic shift): fit() is two stable O(n) sweeps and never allocates.
class PeriodicSpline {
 public:
  PeriodicSpline(int n, double L);  // throws std::invalid_argument if n < 4 or L <= 0

  /// Interpolate y[k*stride], k = 0..n-1. O(n), no heap allocation.
  void fit(const double* y, int stride = 1);
  /// a.fit(ya) and b.fit(yb) (unit strides) in one pass: the two sweeps' recurrences are serial,
  /// so running both splines' side by side halves the time; the same arithmetic, the same bits.
  /// a and b must have the same n and period.
  static void fit_pair(PeriodicSpline& a, const double* ya, PeriodicSpline& b, const double* yb);
  /// Whether the last fit() interpolated exactly (bit for bit) these values y[k], k = 0..n-1.
  bool fitted_to(const double* y) const;

  // Evaluation at any s (wrapped into [0, L)).
  double value(double s) const;
  double d1(double s) const;  // dS/ds
  double d2(double s) const;  // d2S/ds2
  void eval(double s, double& v, double& v_s, double& v_ss) const;

  // Knot values, vectorised: out[k*stride], k = 0..n-1 (caller's storage).
  void d1_at_knots(double* out, int stride = 1) const;  // error O(h^4) for smooth data
  void d2_at_knots(double* out, int stride = 1) const;  // = M_k, error O(h^2)

  /// Power-form coefficients of segment k: S(s_k + t) = c[0] + c[1] t + c[2] t^2 + c[3] t^3,
  /// 0 <= t <= h. k is wrapped periodically.
  void segment(int k, double c[4]) const;

  /// The knots' cyclic system alone: circ(1, 4, 1) z = r for any r (n values), z in place of r, with
  /// the fit's factorisation and sweeps; work holds n values. (A cubic B-spline's interpolation
  /// matrix is circ(1, 4, 1) / 6.)
  void solve_141(double* r, double* work) const;

  int n() const { return n_; }
  double period() const { return L_; }
  double h() const { return h_; }

 private:
  int wrap(int k) const { return ((k % n_) + n_) % n_; }
  void locate(double s, int& k, double& t) const;  // s = s_k + t, 0 <= t < h
  template <int C>
  static void fit_splines(PeriodicSpline* const* sp, const double* const* y, int stride);
  template <int C>
  static void solve_cyclic(const PeriodicSpline& P, double* const* M, double* const* w);

  int n_;
  double L_, h_;
  double rho_;  // 2 - sqrt(3)
  Vec pw_;      // (-rho)^j / (1 - (-rho)^n), truncated where it underflows below 1e-18
  Vec y_, M_, w_;
};

}  // namespace sphib
