#pragma once
// The membrane's force density at its markers, from any tension law with or without bending
// (law.hpp):
//   f = d/ds [ (T(lambda) + T_b) tau + Q n ],   T_b = -Eb/2 (kappa^2 - kappa0^2),   Q = -(1/|X_s|) d/ds m,
//   m = Eb (kappa - kappa0) (laws/bending.hpp), lambda = |X_s| / a,
// per unit label s (Eqs. 47-50 of the paper for the Hookean law). Every d/ds is the derivative at
// the knots of a periodic cubic spline (PeriodicSpline): X -> X_s -> X_ss (kappa) -> m_s, and the
// bracket W -> f. The knot derivative of a spline is O(h^4) where its second derivative is O(h^2), so
// two first derivatives beat one second one; knot derivatives telescope, so sum_k f_k ds = 0 to
// round-off on any shape (momentum is conserved) with or without bending.
// Caveat: d/ds of a uniform spline barely sees the sawtooth (-1)^k (its symbol
// 3 sin(th)/(h (2 + cos th)) vanishes at th = pi), so a marker-scale zigzag meets ~90x less restoring
// force than with HookeanScheme::Analytic, whose X_ss symbol there is -12/h^2.
#include <memory>

#include "membrane/membrane.hpp"

namespace sphib {

/// The geometry of the spline through the markers at its knots: X_s, |X_s| and, when asked for,
/// X_ss (the knot derivative of the spline of X_s) and the signed curvature
/// kappa = (X_s x X_ss)/|X_s|^3 (> 0 on an anticlockwise circle). Holds its splines: fit() does not
/// allocate after the first call.
struct KnotGeometry {
  KnotGeometry(int nb, double L0);
  void fit(const Mat2& X, bool curvature);
  PeriodicSpline sx, sy;  // of X's coordinates
  PeriodicSpline bx, by;  // of X_s's coordinates (curvature only)
  Mat2 X_s, X_ss;
  Vec norm, kappa;        // |X_s|, kappa (curvature only)
};

/// How d(T tau)/ds is taken for the Hookean law without bending on the paper's reference.
enum class HookeanScheme {
  ProductSpline,  // spline of T tau, differentiated at the knots: O(h^4), sum_k f_k = 0 exactly
  Analytic,       // chain rule on the spline of X (needs X_ss at the knots): O(h^2)
};

/// What the stiff-force filter (coupling/stiff_force.hpp) and `sphib check` need of the membrane's
/// stiffness at its current state.
struct MembraneStiffness {
  double Et = 0.0;      // max_k dT/dlambda, the stretching modulus
  double T_mean = 0.0;  // mean tension (a tension T > 0 resists normal modes like T k^2)
  double Eb = 0.0;      // bending modulus
  double length = 0.0;  // current length sum_k |X_s|_k ds
};

/// The elastic energy of the markers' spline, in its two parts.
struct MembraneEnergy {
  double stretching = 0.0;  // int W(lambda) a ds
  double bending = 0.0;     // Eb/2 int (kappa - kappa0)^2 |X_s| ds
  double total() const { return stretching + bending; }
};

/// Force density f (per unit label s) and tension T = T(lambda) at the markers of a membrane. Owns
/// its splines and workspace: compute() is O(nb) and allocation-free once f and T have size nb.
/// Copies share the (immutable) law.
class MembraneForce {
 public:
  explicit MembraneForce(const Membrane& m, HookeanScheme scheme = HookeanScheme::ProductSpline);

  void compute(const Mat2& X, Mat2& f, Vec& T);
  /// Of the markers of the last compute() (or of X after fit_energy(X)), Gauss 5-point per segment.
  MembraneEnergy energy() const;
  /// Fits X's splines (and with bending those of X_s; no force) for energy(), unless the last
  /// compute() was of these markers.
  void fit_energy(const Mat2& X);
  /// Of the markers of the last compute().
  MembraneStiffness stiffness() const;

  int nb() const { return nb_; }
  double ds() const { return ref_.L0 / nb_; }
  const Material& material() const { return mat_; }
  const Reference& reference() const { return ref_; }
  const KnotGeometry& geometry() const { return geo_; }
  /// The splines of X's coordinates (d = 0, 1) the last compute() fitted, and whether that was to
  /// these markers (bit for bit): diagnostics of the same X can use them.
  const PeriodicSpline& spline(int d) const { return d == 0 ? geo_.sx : geo_.sy; }
  bool fitted_to(const Mat2& X) const {
    return X.rows() == nb_ && geo_.sx.fitted_to(X.data()) && geo_.sy.fitted_to(X.data() + nb_);
  }

 private:
  bool paper_hookean() const;  // the Hookean law on the paper's reference without bending
  double kappa0(int k) const { return mat_.spontaneous ? mat_.spontaneous_curvature : ref_.kappa(k); }

  int nb_;
  Reference ref_;
  Material mat_;
  HookeanScheme scheme_;
  std::shared_ptr<const TensionLaw> law_;
  KnotGeometry geo_;
  PeriodicSpline mspline_;  // of the bending moment m (bending only)
  PeriodicSpline wx_, wy_;  // of W's coordinates
  PeriodicSpline ax_, kx_;  // of the reference's a and kappa0 along s (energy; when not uniform)
  Mat2 W_;                  // (T + T_b) tau + Q n at the knots (ProductSpline) or X_ss (Analytic)
  Vec m_, m_s_, lambda_;
  Vec cos_, sin_;           // cos, sin (2 pi j/nb): the tension's discrete Fourier transform (tension_cutoff)
  Vec tc_, ts_;             // its cosine and sine coefficients
  void cut_tension(Vec& T);  // Material::tension_cutoff
};

}  // namespace sphib
