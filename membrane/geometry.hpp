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

}  // namespace sphib
