#pragma once
// The diagnostics of Section 5.2 on the spline through the markers: enclosed area, centroid,
// half-axes rx and ry, length, the ellipse of the same second moments (Taylor deformation D and
// inclination). The elastic energy is the law's (force.hpp). Shapes are in shapes.hpp, polygon
// diagnostics in polygon.hpp.
#include <Eigen/Core>

#include "membrane/polygon.hpp"  // ShapeMoments
#include "membrane/spline.hpp"

namespace sphib {

struct MembraneShape {
  double area = 0.0;          // enclosed by the spline curve (exact)
  double area_polygon = 0.0;  // shoelace rule, O(h^2)
  double cx = 0.0, cy = 0.0;  // area centroid of the spline curve (exact)
  double rx = 0.0, ry = 0.0;  // half chords along y = cy and x = cx
  double length = 0.0;        // current length of the spline curve
  double energy = 0.0;        // elastic energy (set by the caller from the membrane's law)
  ShapeMoments moments;       // second moments of the enclosed area and their ellipse (D, inclination)
};

/// T0/2 int (|X_s| - 1)^2 ds of the curve (sx(s), sy(s)): the paper's Hookean energy (Eq. 47's
/// tension on the circle reference; f = -dE/dX). Other laws: MembraneForce::energy.
double elastic_energy(const PeriodicSpline& sx, const PeriodicSpline& sy, double T0);

/// Spline-based shape diagnostics of one membrane. Holds its splines: after construction
/// fit() and the queries do not allocate.
class MembraneDiagnostics {
 public:
  MembraneDiagnostics(int nb, double L0);

  void fit(const Mat2& X);  // X: nb x 2, labelled by rest arclength

  double area() const;              // (1/2) closed int (x y' - y x') ds, Gauss 5-pt: exact
  Eigen::Vector2d centroid() const; // (1/A) closed int (x^2 y'/2, -y^2 x'/2) ds: exact
  double length() const;            // int |X_s| ds, Gauss 5-pt per segment
  /// Central second moments of the enclosed area by Green's theorem on the spline (Gauss 5-point:
  /// degree 11 per segment, so not exact, error ~1e-12 on smooth shapes), and the ellipse with the
  /// same moments: L, B, inclination theta, deformation D = (L - B)/(L + B).
  ShapeMoments moments() const;
  /// Half-chords of the curve along the horizontal and vertical lines through c: (rx, ry).
  /// With more than two crossings the outermost are used; NaN if a line misses the curve.
  Eigen::Vector2d half_axes(const Eigen::Vector2d& c) const;

  MembraneShape measure(const Mat2& X);  // fit + everything but the energy, centroid from spline

 private:
  double half_chord(int d, double level) const;  // crossings of coordinate d == level

  int nb_;
  PeriodicSpline sx_, sy_;
};

/// Keeps the area enclosed by the spline curve through a membrane's markers (as MembraneDiagnostics
/// measures it) through each trapezoidal marker step: the marker update's area constraint
/// (solver.marker_keep_area, coupling/marker_update.hpp). The curve through X (uniform knots)
/// encloses A = (1/2) closed int (x y' - y x') ds = x^T K y, K_ij = closed int phi_i phi_j' ds with
/// phi_i the periodic cubic spline's cardinal functions: K is circulant and antisymmetric, the same
/// for every curve of nb markers, and K = A^-1 D A^-1 with A the B-splines' interpolation matrix
/// circ(1/6, 4/6, 1/6) and D_ij = int B_i B_j' (taps 49/144, 7/90, 1/720 at distances 1, 2, 3). So
///   grad A = (K y, -K x),    dA/dt = grad A . U = closed int (u y' - v x') ds    (u, v: splines through U)
/// exactly, and, A being quadratic, over a step from X^n to X
///   A(X) - A(X^n) = grad A(X_mid) . (X - X^n),   X_mid = (X^n + X) / 2,
/// exactly. The trapezoidal step moves X - X^n = dt/2 (U^n + U), so keep() makes grad A(X_mid) .
/// (U^n + U) zero: it subtracts from U the least change (in sum_k |dU_k|^2) that does, c grad A(X_mid),
/// a normal velocity along the curve. A divergence-free velocity carries no net flux through the closed
/// curve, so c grad A is the markers' own error in carrying that flux (the spline through U against the
/// velocity between the markers, and the trapezoidal rule's in time), not a force.
class AreaKeeper {
 public:
  explicit AreaKeeper(int nb);  // throws std::invalid_argument if nb < 4 (PeriodicSpline's)
  /// U (nb x 2: one membrane's U^{n+1} at X, a marker update's iterate) minus c grad A(X_mid), with
  /// X_n and U_n the step's start and its velocities there.
  void keep(Eigen::Ref<const Mat2> X_n, Eigen::Ref<const Mat2> U_n, Eigen::Ref<const Mat2> X, Eigen::Ref<Mat2> U);
  /// dA/dt of the curve through X when the markers move with U.
  double rate(Eigen::Ref<const Mat2> X, Eigen::Ref<const Mat2> U);

 private:
  void gradient(Eigen::Ref<const Mat2> X);  // grad A into gx_, gy_
  int nb_;
  PeriodicSpline knots_;  // (its cyclic solve)
  Vec a_, b_;  // workspace
  Vec gx_, gy_;
  Mat2 mid_;   // X_mid
};

}  // namespace sphib
