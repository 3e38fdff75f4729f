#pragma once
// Hookean membrane (Section 4.2.1): tension Eq. (47), tangent Eq. (48), force density Eq. (50).
#include "membrane/spline.hpp"

namespace sphib {

/// A closed membrane: nb markers X_k labelled by rest arclength s_k = k*L0/nb (uniform in s),
/// rest length L0 = 2*pi*r0, Young's modulus T0 of Eq. (47).
struct Membrane {
  Mat2 X;
  double L0 = 0.0;
  double T0 = 0.0;
  int nb() const { return static_cast<int>(X.rows()); }
  double ds() const { return L0 / nb(); }
};

/// The membrane with markers X (uniform in rest arclength, e.g. from shapes.hpp) whose rest state
/// is a circle of radius r0: L0 = 2 pi r0. Throws std::invalid_argument unless nb >= 4 and r0 is
/// positive and finite.
Membrane make_membrane(Mat2 X, double r0, double T0);

/// How d(T tau)/ds of Eq. (50) is taken from the markers.
enum class HookeanScheme {
  ProductSpline,  // spline of T tau, differentiated at the knots: O(h^4), sum_k f_k = 0 exactly
  Analytic,       // chain rule on the spline of X (needs X_ss at the knots): O(h^2)
};

/// Elastic force density per unit REST arclength, f = d(T tau)/ds (Eq. 50), at the markers.
/// Owns its splines and workspace: compute() is O(nb) and allocation-free once f and T have
/// size nb (they are resized on the first call only).
class HookeanForce {
 public:
  HookeanForce(int nb, double L0, HookeanScheme scheme = HookeanScheme::ProductSpline);

  /// f_k = d(T tau)/ds (Eq. 50) and T_k = T0 (|X_s| - 1) (Eq. 47) at each marker.
  void compute(const Mat2& X, double T0, Mat2& f, Vec& T);
  void compute(const Membrane& m, Mat2& f, Vec& T) { compute(m.X, m.T0, f, T); }

  int nb() const { return nb_; }
  double ds() const { return L0_ / nb_; }
  HookeanScheme scheme() const { return scheme_; }
  /// The splines of X's coordinates (d = 0, 1) that the last compute() fitted, and whether that
  /// was to these markers (bit for bit): the diagnostics of the same X can use them.
  const PeriodicSpline& spline(int d) const { return d == 0 ? sx_ : sy_; }
  bool fitted_to(const Mat2& X) const {
    return X.rows() == nb_ && sx_.fitted_to(X.data()) && sy_.fitted_to(X.data() + nb_);
  }

 private:
  int nb_;
  double L0_;
  HookeanScheme scheme_;
  PeriodicSpline sx_, sy_;  // of X and Y
  PeriodicSpline wx_, wy_;  // of W's coordinates (ProductSpline)
  Mat2 X_s_, W_;           // X_s at the knots; W = T tau (ProductSpline) or X_ss (Analytic)
};

}  // namespace sphib
