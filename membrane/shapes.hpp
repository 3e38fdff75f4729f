#pragma once
// Membrane shapes: nb marker positions (nb x 2, anticlockwise), geometry only. The material (rest
// reference, law) is the caller's: make_membrane (membrane.hpp) turns markers into a Membrane.
#include <Eigen/Core>
#include <functional>

#include "membrane/spline.hpp"  // Mat2

namespace sphib {

/// Circle, X_k = c + radius (cos, sin)(2 pi k/nb). With rest radius r0 = radius it is the rest
/// state (Eq. 64); with radius = re > r0 the stretched equilibrium.
Mat2 circle(int nb, double cx, double cy, double radius);

/// Axis-aligned ellipse, X_k = c + (rx cos, ry sin)(theta_k), theta_k = 2 pi k/nb. The markers are
/// uniform in theta, which is uniform in rest arclength whatever the shape: on an ellipse the
/// stretch |X_s| is non-uniform along the membrane, as in the paper.
Mat2 ellipse(int nb, double cx, double cy, double rx, double ry);

/// The same ellipse with its markers uniform in its own arclength (X_k at arclength k L/nb from
/// (cx + rx, cy), L the perimeter; to ~1e-13 of L): the rest spacing of a membrane whose rest
/// length is the ellipse's perimeter (an inextensible membrane starts without a stretch).
Mat2 ellipse_by_arclength(int nb, double cx, double cy, double rx, double ry);

/// An arbitrary closed curve through points (m x 2, anticlockwise, first point not repeated
/// at the end, though a repeated closing point is dropped): a periodic cubic spline in the
/// chord-length parameter, resampled at nb markers uniformly spaced in its arclength.
/// Throws std::invalid_argument for m < 4, non-finite values, repeated consecutive points,
/// self-intersection or clockwise orientation.
Mat2 from_points(const Mat2& points, int nb);

/// A closed parametric curve C(t), t in [0, 1), anticlockwise (C(1) = C(0)): sampled at
/// `samples` points uniform in t (0: max(16 nb, 256)) and passed to from_points, so the nb
/// markers are uniform in the arclength of the curve. Throws std::invalid_argument as
/// from_points does, and if C(1) differs from C(0) by more than 1e-6 of the curve's size.
Mat2 from_curve(const std::function<Eigen::Vector2d(double)>& curve, int nb, int samples = 0);

/// A star-shaped curve given by its radius r(theta) about (cx, cy), theta in [0, 2 pi):
/// C(t) = c + r(2 pi t) (cos, sin)(2 pi t), through from_curve.
Mat2 from_polar(const std::function<double(double)>& r, int nb, double cx = 0.0, double cy = 0.0);

}  // namespace sphib
