#pragma once
// Membrane shapes and the diagnostics of Section 5.2 (enclosed area, centroid, half-axes
// rx and ry, length, elastic energy).
#include <Eigen/Core>

#include "membrane/hookean.hpp"
#include "membrane/spline.hpp"

namespace sphib {

// ---- Shapes. Each returns nb markers labelled by rest arclength s_k = k*L0/nb, L0 = 2 pi r0.

/// Circle of the given radius, X_k = c + radius (cos, sin)(2 pi k/nb), anticlockwise.
/// radius == r0 is the rest state (Eq. 64); radius = re > r0 the stretched equilibrium.
Membrane circle(int nb, double r0, double cx, double cy, double radius, double T0);

/// Axis-aligned ellipse, X_k = c + (rx cos, ry sin)(theta_k), theta_k = 2 pi k/nb.
/// The rest labelling stays uniform in s whatever the initial shape, so on an ellipse the
/// stretch |X_s| is non-uniform along the membrane: this is what the paper does.
Membrane ellipse(int nb, double r0, double cx, double cy, double rx, double ry, double T0);

/// An arbitrary closed curve through points (m x 2, anticlockwise, first point not repeated
/// at the end, though a repeated closing point is dropped): a periodic cubic spline in the
/// chord-length parameter, resampled at nb markers uniformly spaced in its arclength.
/// Throws std::invalid_argument for m < 4, non-finite values, repeated consecutive points,
/// self-intersection or clockwise orientation.
Membrane from_points(const Mat2& points, int nb, double r0, double T0);

// ---- Polygon diagnostics (the markers joined by straight segments).

double signed_area(const Mat2& X);           // shoelace rule, > 0 anticlockwise
Eigen::Vector2d polygon_centroid(const Mat2& X);
bool is_simple(const Mat2& X);               // no two edges meet except neighbours at a vertex

// ---- Spline diagnostics.

struct MembraneShape {
  double area = 0.0;          // enclosed by the spline curve (exact)
  double area_polygon = 0.0;  // shoelace rule, O(h^2)
  double cx = 0.0, cy = 0.0;  // area centroid of the spline curve (exact)
  double rx = 0.0, ry = 0.0;  // half chords along y = cy and x = cx
  double length = 0.0;        // current length of the spline curve
  double energy = 0.0;        // T0/2 int_0^L0 (|X_s| - 1)^2 ds
};

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
