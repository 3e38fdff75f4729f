#pragma once
// Diagnostics of the polygon through the markers (straight segments): area, centroid, simplicity,
// the ellipse of the same area moments, the mean angular velocity.
#include <Eigen/Core>

#include "membrane/spline.hpp"  // Mat2

namespace sphib {

double signed_area(const Mat2& X);           // shoelace rule, > 0 anticlockwise
Eigen::Vector2d polygon_centroid(const Mat2& X);
bool is_simple(const Mat2& X);               // no two edges meet except neighbours at a vertex: O(n log n)
bool is_simple_plain(const Mat2& X);         // the same by testing every pair of edges: O(n^2)

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
/// The ellipse of area A, centroid c and central second moments Jxx, Jxy, Jyy (any closed curve's).
ShapeMoments moment_ellipse(double A, const Eigen::Vector2d& c, double Jxx, double Jxy, double Jyy);

/// Mean angular velocity of the markers about c: (1/nb) sum_k (X_k - c) x U_k / |X_k - c|^2.
/// For markers uniform in rest arclength on a steadily tank-treading membrane this is its
/// tank-treading frequency (2 pi over the time a marker takes to go round), > 0 anticlockwise.
double mean_angular_velocity(const Mat2& X, const Mat2& U, const Eigen::Vector2d& c);

}  // namespace sphib
