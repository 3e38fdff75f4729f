#pragma once
// The diagnostics of Section 5.2 on the spline through the markers: enclosed area, centroid,
// half-axes rx and ry, length, elastic energy. Shapes are in shapes.hpp, polygon diagnostics in
// polygon.hpp.
#include <Eigen/Core>

#include "membrane/spline.hpp"

namespace sphib {

struct MembraneShape {
  double area = 0.0;          // enclosed by the spline curve (exact)
  double area_polygon = 0.0;  // shoelace rule, O(h^2)
  double cx = 0.0, cy = 0.0;  // area centroid of the spline curve (exact)
  double rx = 0.0, ry = 0.0;  // half chords along y = cy and x = cx
  double length = 0.0;        // current length of the spline curve
  double energy = 0.0;        // T0/2 int_0^L0 (|X_s| - 1)^2 ds
};

/// T0/2 int (|X_s| - 1)^2 ds of the curve (sx(s), sy(s)) (Eq. 47's tension; f = -dE/dX).
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
  double energy(double T0) const;   // T0/2 int (|X_s| - 1)^2 ds; f = -dE/dX
  /// Half-chords of the curve along the horizontal and vertical lines through c: (rx, ry).
  /// With more than two crossings the outermost are used; NaN if a line misses the curve.
  Eigen::Vector2d half_axes(const Eigen::Vector2d& c) const;

  MembraneShape measure(const Mat2& X, double T0);  // fit + everything, centroid from spline

 private:
  double half_chord(int d, double level) const;  // crossings of coordinate d == level

  int nb_;
  PeriodicSpline sx_, sy_;
};

}  // namespace sphib
