#pragma once
// Membrane shapes and the diagnostics of Section 5.2 (enclosed area, centroid, half-axes
// rx and ry, length, elastic energy).
#include <Eigen/Core>
#include <functional>

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

/// A closed parametric curve C(t), t in [0, 1), anticlockwise (C(1) = C(0)): sampled at
/// `samples` points uniform in t (0: max(16 nb, 256)) and passed to from_points, so the nb
/// markers are uniform in the arclength of the curve. Throws std::invalid_argument as
/// from_points does, and if C(1) differs from C(0) by more than 1e-6 of the curve's size.
Membrane from_curve(const std::function<Eigen::Vector2d(double)>& curve, int nb, double r0, double T0,
                    int samples = 0);

/// A star-shaped curve given by its radius r(theta) about (cx, cy), theta in [0, 2 pi):
/// C(t) = c + r(2 pi t) (cos, sin)(2 pi t), through from_curve.
Membrane from_polar(const std::function<double(double)>& r, int nb, double r0, double T0, double cx = 0.0,
                    double cy = 0.0);

// ---- Polygon diagnostics (the markers joined by straight segments).

double signed_area(const Mat2& X);           // shoelace rule, > 0 anticlockwise
Eigen::Vector2d polygon_centroid(const Mat2& X);
bool is_simple(const Mat2& X);               // no two edges meet except neighbours at a vertex

/// Area moments of the region enclosed by the polygon X (exact for the polygon) and the ellipse
/// with the same moments: for an ellipse (or the affine image of a regular polygon) L, B and
/// theta are its own, up to the polygon's isotropic factor sqrt((2 + cos(2 pi/nb))/3).
struct ShapeMoments {
  double area = 0.0;                       // A = int dA
  Eigen::Vector2d centroid{0.0, 0.0};      // (1/A) int x dA
  double Jxx = 0.0, Jxy = 0.0, Jyy = 0.0;  // central second moments int (x-cx)^2 dA, int (x-cx)(y-cy) dA, ...
  double L = 0.0, B = 0.0;                 // half-axes 2 sqrt(lambda/A), lambda the eigenvalues of J; L >= B
  double theta = 0.0;                      // major axis to the x axis, in (-pi/2, pi/2]: tan 2theta = 2Jxy/(Jxx-Jyy)
  double deformation() const { return (L - B) / (L + B); }  // Taylor deformation D = (L - B)/(L + B)
};
ShapeMoments ellipse_fit(const Mat2& X);

/// Mean angular velocity of the markers about c: (1/nb) sum_k (X_k - c) x U_k / |X_k - c|^2.
/// For markers uniform in rest arclength on a steadily tank-treading membrane this is its
/// tank-treading frequency (2 pi over the time a marker takes to go round), > 0 anticlockwise.
double mean_angular_velocity(const Mat2& X, const Mat2& U, const Eigen::Vector2d& c);

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
