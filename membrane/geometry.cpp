#include "membrane/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "kernels/lanes.hpp"  // two segments' values, lane by lane
#include "membrane/polygon.hpp"

namespace sphib {

MembraneDiagnostics::MembraneDiagnostics(int nb, double L0)
    : nb_(nb), sx_(nb, L0), sy_(nb, L0) {}

void MembraneDiagnostics::fit(const Mat2& X) {
  if (X.rows() != nb_)
    throw std::invalid_argument("MembraneDiagnostics: X has " + std::to_string(X.rows()) +
                                " markers, expected nb = " + std::to_string(nb_));
  PeriodicSpline::fit_pair(sx_, X.data(), sy_, X.data() + nb_);
}

// Sums g(x, y, x_s, y_s) over Gauss points of every segment, times the weights.
template <class G>
static double integrate(const PeriodicSpline& sx, const PeriodicSpline& sy, G g) {
  const double h = sx.h();
  double sum = 0.0;
  double cx[4], cy[4];
  for (int k = 0; k < sx.n(); ++k) {
    sx.segment(k, cx);
    sy.segment(k, cy);
    for (int q = 0; q < 5; ++q) {
      const double t = 0.5 * h * (1.0 + gauss5::x[q]);
      const double x = cx[0] + t * (cx[1] + t * (cx[2] + t * cx[3]));
      const double y = cy[0] + t * (cy[1] + t * (cy[2] + t * cy[3]));
      const double xs = cx[1] + t * (2.0 * cx[2] + 3.0 * t * cx[3]);
      const double ys = cy[1] + t * (2.0 * cy[2] + 3.0 * t * cy[3]);
      sum += gauss5::w[q] * g(x, y, xs, ys);
    }
  }
  return 0.5 * h * sum;
}

double MembraneDiagnostics::area() const {
  // Integrand of degree 5 per segment: Gauss 5-point is exact.
  return integrate(sx_, sy_, [](double x, double y, double xs, double ys) {
    return 0.5 * (x * ys - y * xs);
  });
}

Eigen::Vector2d MembraneDiagnostics::centroid() const {
  // Green: int x dA = closed int x^2/2 dy, int y dA = -closed int y^2/2 dx (degree 8: exact).
  const double A = area();
  const double mx = integrate(sx_, sy_, [](double x, double, double, double ys) {
    return 0.5 * x * x * ys;
  });
  const double my = integrate(sx_, sy_, [](double, double y, double xs, double) {
    return -0.5 * y * y * xs;
  });
  return {mx / A, my / A};
}

double MembraneDiagnostics::length() const {
  return integrate(sx_, sy_, [](double, double, double xs, double ys) {
    return std::sqrt(xs * xs + ys * ys);  // |X_s| ds
  });
}

// integrate() of (|X_s| - 1)^2 (T/T0, Eq. (47)), half T0 times it: the run-time guard's every step.
// The same expressions and the same sum, in integrate()'s order; the points' values are made first,
// two segments side by side (SSE2 square roots), a chunk of segments at a time.
double elastic_energy(const PeriodicSpline& sx, const PeriodicSpline& sy, double T0) {
  constexpr int kChunk = 64;  // segments (even)
  const double h = sx.h();
  double t[5];
  for (int q = 0; q < 5; ++q) t[q] = 0.5 * h * (1.0 + gauss5::x[q]);
  const int n = sx.n();
  double sum = 0.0;
  for (int k0 = 0; k0 < n; k0 += kChunk) {
    const int m = std::min(kChunk, n - k0);
    alignas(16) double x1[kChunk], x2[kChunk], x3[kChunk], y1[kChunk], y2[kChunk], y3[kChunk], g[kChunk][5];
    for (int j = 0; j < m; ++j) {
      double cx[4], cy[4];
      sx.segment(k0 + j, cx);
      sy.segment(k0 + j, cy);
      x1[j] = cx[1], x2[j] = cx[2], x3[j] = cx[3];
      y1[j] = cy[1], y2[j] = cy[2], y3[j] = cy[3];
    }
    for (int j = m; j < (m + 1) / 2 * 2; ++j) x1[j] = x2[j] = x3[j] = y1[j] = y2[j] = y3[j] = 0.0;  // an odd tail's pad
    for (int j = 0; j < m; j += 2)
      for (int q = 0; q < 5; ++q) {
        const Lanes2 tq = lanes2(t[q]);
        const Lanes2 xs = Lanes2{x1[j], x1[j + 1]} + tq * (lanes2(2.0) * Lanes2{x2[j], x2[j + 1]} +
                                                            lanes2(3.0) * tq * Lanes2{x3[j], x3[j + 1]});
        const Lanes2 ys = Lanes2{y1[j], y1[j + 1]} + tq * (lanes2(2.0) * Lanes2{y2[j], y2[j + 1]} +
                                                            lanes2(3.0) * tq * Lanes2{y3[j], y3[j + 1]});
        const Lanes2 e = sqrt2(xs * xs + ys * ys) - lanes2(1.0);  // T/T0, Eq. (47)
        const Lanes2 e2 = e * e;
        g[j][q] = e2[0];
        g[j + 1][q] = e2[1];
      }
    for (int j = 0; j < m; ++j)
      for (int q = 0; q < 5; ++q) sum += gauss5::w[q] * g[j][q];
  }
  return 0.5 * T0 * (0.5 * h * sum);
}

ShapeMoments MembraneDiagnostics::moments() const {
  // Green: int (x-cx)^2 dA = closed int (x-cx)^3/3 dy, int (y-cy)^2 dA = -closed int (y-cy)^3/3 dx,
  // int (x-cx)(y-cy) dA = closed int (x-cx)^2 (y-cy)/2 dy.
  const double A = area();
  const Eigen::Vector2d c = centroid();
  const double Jxx = integrate(sx_, sy_, [&](double x, double, double, double ys) {
    const double X = x - c.x();
    return X * X * X * ys / 3.0;
  });
  const double Jyy = integrate(sx_, sy_, [&](double, double y, double xs, double) {
    const double Y = y - c.y();
    return -Y * Y * Y * xs / 3.0;
  });
  const double Jxy = integrate(sx_, sy_, [&](double x, double y, double, double ys) {
    const double X = x - c.x();
    return 0.5 * X * X * (y - c.y()) * ys;
  });
  return moment_ellipse(A, c, Jxx, Jxy, Jyy);
}

double MembraneDiagnostics::half_chord(int d, double level) const {
  // Crossings of the spline with {coordinate d == level}; returns half the spread of the
  // other coordinate over them. Each segment cubic is split at its turning points into
  // monotone pieces, and every piece with a sign change is bisected to round-off.
  const PeriodicSpline& sd = d == 0 ? sx_ : sy_;
  const PeriodicSpline& so = d == 0 ? sy_ : sx_;
  const double h = sd.h();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  double c[4], co[4];
  for (int k = 0; k < nb_; ++k) {
    sd.segment(k, c);
    c[0] -= level;
    auto g = [&](double t) { return c[0] + t * (c[1] + t * (c[2] + t * c[3])); };
    double cuts[4] = {0.0, h, h, h};  // piece ends: 0, turning points in (0, h), h
    int nc = 1;
    const double A = 3.0 * c[3], B = 2.0 * c[2], Cc = c[1];  // g' = A t^2 + B t + Cc
    if (A != 0.0) {
      const double disc = B * B - 4.0 * A * Cc;
      if (disc > 0.0) {
        const double sq = std::sqrt(disc);
        double r1 = (-B - sq) / (2.0 * A), r2 = (-B + sq) / (2.0 * A);
        if (r1 > r2) std::swap(r1, r2);
        if (r1 > 0.0 && r1 < h) cuts[nc++] = r1;
        if (r2 > 0.0 && r2 < h) cuts[nc++] = r2;
      }
    } else if (B != 0.0) {
      const double r = -Cc / B;
      if (r > 0.0 && r < h) cuts[nc++] = r;
    }
    cuts[nc++] = h;
    // A value within round-off of the level counts as on it: at a knot the two pieces' values differ
    // in the last bits, and a crossing there would otherwise fall between them and be missed.
    const double eps = 1e-13 * (1.0 + std::fabs(level) + std::fabs(c[0]));
    for (int p = 0; p + 1 < nc; ++p) {
      double a = cuts[p], b = cuts[p + 1], ga = g(a), gb = g(b);
      if (std::fabs(ga) <= eps) ga = 0.0;
      if (std::fabs(gb) <= eps) gb = 0.0;
      if (ga * gb > 0.0) continue;
      double t = ga == 0.0 ? a : b;
      if (ga != 0.0 && gb != 0.0) {
        for (int it = 0; it < 100 && b - a > 1e-16 * h; ++it) {
          const double mid = 0.5 * (a + b), gm = g(mid);
          if ((gm < 0.0) == (ga < 0.0)) {
            a = mid;
            ga = gm;
          } else {
            b = mid;
          }
        }
        t = 0.5 * (a + b);
      }
      so.segment(k, co);
      const double other = co[0] + t * (co[1] + t * (co[2] + t * co[3]));
      lo = std::min(lo, other);
      hi = std::max(hi, other);
    }
  }
  if (!(hi >= lo)) return std::numeric_limits<double>::quiet_NaN();
  return 0.5 * (hi - lo);
}

Eigen::Vector2d MembraneDiagnostics::half_axes(const Eigen::Vector2d& c) const {
  return {half_chord(1, c.y()), half_chord(0, c.x())};  // rx along y = cy, ry along x = cx
}

MembraneShape MembraneDiagnostics::measure(const Mat2& X) {
  fit(X);
  MembraneShape m;
  m.area = area();
  m.area_polygon = signed_area(X);
  const Eigen::Vector2d c = centroid();
  m.cx = c.x();
  m.cy = c.y();
  const Eigen::Vector2d r = half_axes(c);
  m.rx = r.x();
  m.ry = r.y();
  m.length = length();
  m.moments = moments();
  return m;
}

}  // namespace sphib

namespace sphib {

AreaKeeper::AreaKeeper(int nb) : nb_(nb), knots_(nb, 1.0), a_(nb), b_(nb), gx_(nb), gy_(nb) {}

void AreaKeeper::gradient(Eigen::Ref<const Mat2> X) {
  if (X.rows() != nb_)
    throw std::invalid_argument("AreaKeeper: " + std::to_string(X.rows()) + " markers, expected nb = " +
                                std::to_string(nb_));
  const double d1 = 49.0 / 144.0, d2 = 7.0 / 90.0, d3 = 1.0 / 720.0;  // int B(t) B'(t - m) dt, m = 1, 2, 3
  const int n = nb_;
  for (int c = 0; c < 2; ++c) {  // grad A = (K y, -K x), K = A^-1 D A^-1
    Vec& g = c == 0 ? gx_ : gy_;
    a_ = 6.0 * X.col(1 - c);
    knots_.solve_141(a_.data(), b_.data());  // the B-spline coefficients A^-1 y, A = circ(1, 4, 1) / 6
    auto D = [&](int i, auto at) {  // (D a)_i = sum_m d_m (a_(i+m) - a_(i-m))
      b_[i] = d1 * (at(i + 1) - at(i - 1)) + d2 * (at(i + 2) - at(i - 2)) + d3 * (at(i + 3) - at(i - 3));
    };
    const auto wrapped = [&](int k) { return a_[(k + n) % n]; };
    const auto inside = [&](int k) { return a_[k]; };
    for (int i = 0; i < std::min(3, n); ++i) D(i, wrapped);
    for (int i = 3; i < n - 3; ++i) D(i, inside);
    for (int i = std::max(3, n - 3); i < n; ++i) D(i, wrapped);
    g = (c == 0 ? 6.0 : -6.0) * b_;
    knots_.solve_141(g.data(), b_.data());
  }
}

double AreaKeeper::rate(Eigen::Ref<const Mat2> X, Eigen::Ref<const Mat2> U) {
  gradient(X);
  if (U.rows() != nb_)
    throw std::invalid_argument("AreaKeeper: " + std::to_string(U.rows()) + " velocities, expected nb = " +
                                std::to_string(nb_));
  return gx_.dot(U.col(0)) + gy_.dot(U.col(1));
}

void AreaKeeper::keep(Eigen::Ref<const Mat2> X_n, Eigen::Ref<const Mat2> U_n, Eigen::Ref<const Mat2> X,
                      Eigen::Ref<Mat2> U) {
  if (X_n.rows() != nb_ || U_n.rows() != nb_ || X.rows() != nb_ || U.rows() != nb_)
    throw std::invalid_argument("AreaKeeper: a step of " + std::to_string(X.rows()) + " markers and " +
                                std::to_string(U.rows()) + " velocities, expected nb = " + std::to_string(nb_));
  mid_ = 0.5 * (X_n + X);
  gradient(mid_);
  const double r = gx_.dot(U_n.col(0) + U.col(0)) + gy_.dot(U_n.col(1) + U.col(1));
  const double g2 = gx_.squaredNorm() + gy_.squaredNorm();
  if (!(g2 > 0.0)) return;  // (all markers at one point: left to the guards)
  const double c = r / g2;  // grad A(X_mid) . (U_n + U - c grad A(X_mid)) = 0
  U.col(0) -= c * gx_;
  U.col(1) -= c * gy_;
}

}  // namespace sphib
