#include "membrane/shapes.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "membrane/polygon.hpp"
#include "membrane/spline.hpp"

namespace sphib {

namespace {

constexpr double kPi = 3.14159265358979323846;

void check_markers(const char* who, int nb) {
  if (nb < 4)
    throw std::invalid_argument(std::string(who) + ": nb = " + std::to_string(nb) +
                                " markers, need nb >= 4");
}

// Periodic cubic spline through points P_i at chord-length parameters t_i (non-uniform knots).
// Built once by from_points, so it may allocate and use a sparse Cholesky factorisation.
struct ChordSpline {
  int m = 0;
  std::vector<double> h;                 // parameter length of segment i = |P_{i+1} - P_i|
  std::vector<Eigen::Vector4d> cx, cy;   // power-form coefficients of segment i

  explicit ChordSpline(const Mat2& P) : m(static_cast<int>(P.rows())), h(m), cx(m), cy(m) {
    for (int i = 0; i < m; ++i) h[i] = (P.row((i + 1) % m) - P.row(i)).norm();
    // h_{i-1}/6 M_{i-1} + (h_{i-1} + h_i)/3 M_i + h_i/6 M_{i+1} = (y_{i+1}-y_i)/h_i - (y_i-y_{i-1})/h_{i-1}
    std::vector<Eigen::Triplet<double>> trip;
    for (int i = 0; i < m; ++i) {
      const int im = (i + m - 1) % m, ip = (i + 1) % m;
      trip.emplace_back(i, im, h[im] / 6.0);
      trip.emplace_back(i, i, (h[im] + h[i]) / 3.0);
      trip.emplace_back(i, ip, h[i] / 6.0);
    }
    Eigen::SparseMatrix<double> A(m, m);
    A.setFromTriplets(trip.begin(), trip.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
    for (int d = 0; d < 2; ++d) {
      Vec r(m);
      for (int i = 0; i < m; ++i) {
        const int im = (i + m - 1) % m, ip = (i + 1) % m;
        r[i] = (P(ip, d) - P(i, d)) / h[i] - (P(i, d) - P(im, d)) / h[im];
      }
      const Vec M = ldlt.solve(r);
      std::vector<Eigen::Vector4d>& c = d == 0 ? cx : cy;
      for (int i = 0; i < m; ++i) {
        const int ip = (i + 1) % m;
        c[i] << P(i, d), (P(ip, d) - P(i, d)) / h[i] - h[i] * (2.0 * M[i] + M[ip]) / 6.0,
            0.5 * M[i], (M[ip] - M[i]) / (6.0 * h[i]);
      }
    }
  }
  Eigen::Vector2d point(int i, double u) const {
    return {cx[i][0] + u * (cx[i][1] + u * (cx[i][2] + u * cx[i][3])),
            cy[i][0] + u * (cy[i][1] + u * (cy[i][2] + u * cy[i][3]))};
  }
  double speed(int i, double u) const {  // |dC/dt|
    const double xt = cx[i][1] + u * (2.0 * cx[i][2] + 3.0 * u * cx[i][3]);
    const double yt = cy[i][1] + u * (2.0 * cy[i][2] + 3.0 * u * cy[i][3]);
    return std::hypot(xt, yt);
  }
  double arclength(int i, double a, double b) const {  // int_a^b |C'| du, Gauss 5-point
    double sum = 0.0;
    for (int g = 0; g < 5; ++g) sum += gauss5::w[g] * speed(i, 0.5 * (a + b) + 0.5 * (b - a) * gauss5::x[g]);
    return 0.5 * (b - a) * sum;
  }
};

}  // namespace

Mat2 circle(int nb, double cx, double cy, double radius) {
  check_markers("circle", nb);
  if (!(radius > 0.0))
    throw std::invalid_argument("circle: radius = " + std::to_string(radius) + " must be > 0");
  return ellipse(nb, cx, cy, radius, radius);
}

Mat2 ellipse(int nb, double cx, double cy, double rx, double ry) {
  check_markers("ellipse", nb);
  if (!(rx > 0.0) || !(ry > 0.0))
    throw std::invalid_argument("ellipse: half-axes rx = " + std::to_string(rx) + ", ry = " +
                                std::to_string(ry) + " must be > 0");
  Mat2 X(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double theta = 2.0 * kPi * k / nb;  // uniform in rest arclength
    X(k, 0) = cx + rx * std::cos(theta);
    X(k, 1) = cy + ry * std::sin(theta);
  }
  return X;
}

Mat2 ellipse_by_arclength(int nb, double cx, double cy, double rx, double ry) {
  const Mat2 E = ellipse(nb, cx, cy, rx, ry);  // checks nb, rx, ry
  // s(theta) = int_0^theta |C'(t)| dt, |C'| = sqrt(rx^2 sin^2 + ry^2 cos^2), tabulated on q panels of
  // Gauss 5-point (the integrand is analytic: the table is exact to round-off), then inverted per
  // marker by Newton's method inside its panel.
  auto speed = [&](double t) { return std::hypot(rx * std::sin(t), ry * std::cos(t)); };
  auto panel = [&](double a, double b) {
    double sum = 0.0;
    for (int g = 0; g < 5; ++g) sum += gauss5::w[g] * speed(0.5 * (a + b) + 0.5 * (b - a) * gauss5::x[g]);
    return 0.5 * (b - a) * sum;
  };
  const int q = 16 * nb;
  const double dth = 2.0 * kPi / q;
  std::vector<double> cum(q + 1, 0.0);
  for (int i = 0; i < q; ++i) cum[i + 1] = cum[i] + panel(i * dth, (i + 1) * dth);
  const double length = cum[q];
  Mat2 X = E;
  int i = 0;
  for (int k = 1; k < nb; ++k) {
    const double sigma = length * k / nb;
    while (cum[i + 1] < sigma) ++i;
    double th = i * dth + dth * (sigma - cum[i]) / (cum[i + 1] - cum[i]);
    for (int it = 0; it < 20; ++it) {
      const double step = (cum[i] + panel(i * dth, th) - sigma) / speed(th);
      th -= step;
      if (std::abs(step) < 1e-15) break;
    }
    X(k, 0) = cx + rx * std::cos(th);
    X(k, 1) = cy + ry * std::sin(th);
  }
  return X;
}

Mat2 from_points(const Mat2& points, int nb) {
  check_markers("from_points", nb);
  if (!points.allFinite())
    throw std::invalid_argument("from_points: points contain NaN or infinite values");
  Mat2 P = points;
  if (P.rows() >= 2 && P.row(0) == P.row(P.rows() - 1))  // closing point repeated: drop it
    P.conservativeResize(P.rows() - 1, 2);
  const int m = static_cast<int>(P.rows());
  if (m < 4)
    throw std::invalid_argument("from_points: " + std::to_string(m) +
                                " distinct points, need at least 4 for a periodic cubic spline");
  for (int i = 0; i < m; ++i)
    if (P.row(i) == P.row((i + 1) % m))
      throw std::invalid_argument("from_points: points " + std::to_string(i) + " and " +
                                  std::to_string((i + 1) % m) + " coincide");
  if (!is_simple(P))
    throw std::invalid_argument("from_points: the closed polygon through the points "
                                "self-intersects");
  const double A = signed_area(P);
  if (!(A > 0.0))
    throw std::invalid_argument("from_points: points are ordered clockwise (signed area " +
                                std::to_string(A) + "); give them anticlockwise");

  // Arclength table over q sub-intervals per segment, then invert it marker by marker.
  const ChordSpline C(P);
  constexpr int q = 8;
  std::vector<double> cum(static_cast<size_t>(m) * q + 1, 0.0);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < q; ++j) {
      const size_t idx = static_cast<size_t>(i) * q + j;
      cum[idx + 1] = cum[idx] + C.arclength(i, C.h[i] * j / q, C.h[i] * (j + 1) / q);
    }
  const double length = cum.back();

  Mat2 X(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double sigma = length * k / nb;  // target arclength of marker k
    size_t idx = static_cast<size_t>(std::upper_bound(cum.begin(), cum.end(), sigma) - cum.begin());
    idx = std::min(std::max<size_t>(idx, 1), cum.size() - 1) - 1;
    const int i = static_cast<int>(idx / q), j = static_cast<int>(idx % q);
    double a = C.h[i] * j / q, b = C.h[i] * (j + 1) / q;  // bracket of the parameter u
    const double ua = a;
    double u = a + (b - a) * (sigma - cum[idx]) / std::max(cum[idx + 1] - cum[idx], 1e-300);
    for (int it = 0; it < 50; ++it) {  // safeguarded Newton on cum + int_ua^u |C'| = sigma
      const double F = cum[idx] + C.arclength(i, ua, u) - sigma;
      if (std::abs(F) <= 1e-15 * length) break;
      (F > 0 ? b : a) = u;
      const double un = u - F / C.speed(i, u);
      u = (un > a && un < b) ? un : 0.5 * (a + b);
    }
    X.row(k) = C.point(i, u).transpose();
  }
  if (!is_simple(X) || !(signed_area(X) > 0.0))
    throw std::invalid_argument("from_points: the spline through the points self-intersects "
                                "after resampling (corners too sharp for a cubic spline?)");
  return X;
}

Mat2 from_curve(const std::function<Eigen::Vector2d(double)>& curve, int nb, int samples) {
  check_markers("from_curve", nb);
  if (!curve) throw std::invalid_argument("from_curve: no curve given");
  const int m = samples > 0 ? samples : std::max(16 * nb, 256);
  if (m < 4) throw std::invalid_argument("from_curve: needs at least 4 samples");
  Mat2 P(m, 2);
  for (int i = 0; i < m; ++i) P.row(i) = curve(static_cast<double>(i) / m).transpose();
  if (!P.allFinite()) throw std::invalid_argument("from_curve: the curve has NaN or infinite points");
  const double size = (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
  const Eigen::Vector2d gap = curve(1.0) - P.row(0).transpose();
  if (!(gap.norm() <= 1e-6 * size))
    throw std::invalid_argument("from_curve: the curve is not closed: |C(1) - C(0)| = " +
                                std::to_string(gap.norm()) + " (t runs over [0, 1))");
  try {
    return from_points(P, nb);
  } catch (const std::invalid_argument& e) {
    std::string what = e.what();
    throw std::invalid_argument("from_curve: " + what.substr(what.find(':') + 2));
  }
}

Mat2 from_polar(const std::function<double(double)>& r, int nb, double cx, double cy) {
  if (!r) throw std::invalid_argument("from_polar: no radius function given");
  return from_curve(
      [&](double t) {
        const double theta = 2.0 * kPi * t, rho = r(theta);
        return Eigen::Vector2d(cx + rho * std::cos(theta), cy + rho * std::sin(theta));
      },
      nb);
}

}  // namespace sphib
