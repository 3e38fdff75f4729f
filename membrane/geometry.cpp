#include "membrane/geometry.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace sphib {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Gauss-Legendre 5 points on [-1, 1]: exact for polynomials of degree <= 9.
const double kGL5x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                         0.9061798459386640};
const double kGL5w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                         0.4786286704993665, 0.2369268850561891};

void check_common(const char* who, int nb, double r0) {
  if (nb < 4)
    throw std::invalid_argument(std::string(who) + ": nb = " + std::to_string(nb) +
                                " markers, need nb >= 4");
  if (!(r0 > 0.0) || !std::isfinite(r0))
    throw std::invalid_argument(std::string(who) + ": rest radius r0 = " + std::to_string(r0) +
                                " must be positive and finite");
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}
double orient(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return cross(b - a, c - a);
}
// c lies in the bounding box of segment ab (used once a, b, c are known collinear).
bool in_box(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return std::min(a.x(), b.x()) <= c.x() && c.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= c.y() && c.y() <= std::max(a.y(), b.y());
}
// Closed segments p1p2 and p3p4 share at least one point.
bool segments_meet(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2, const Eigen::Vector2d& p3,
                   const Eigen::Vector2d& p4) {
  const double d1 = orient(p3, p4, p1), d2 = orient(p3, p4, p2);
  const double d3 = orient(p1, p2, p3), d4 = orient(p1, p2, p4);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  return (d1 == 0 && in_box(p3, p4, p1)) || (d2 == 0 && in_box(p3, p4, p2)) ||
         (d3 == 0 && in_box(p1, p2, p3)) || (d4 == 0 && in_box(p1, p2, p4));
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
    for (int g = 0; g < 5; ++g) sum += kGL5w[g] * speed(i, 0.5 * (a + b) + 0.5 * (b - a) * kGL5x[g]);
    return 0.5 * (b - a) * sum;
  }
};

}  // namespace

// ---------------------------------------------------------------- shapes

Membrane circle(int nb, double r0, double cx, double cy, double radius, double T0) {
  check_common("circle", nb, r0);
  if (!(radius > 0.0))
    throw std::invalid_argument("circle: radius = " + std::to_string(radius) + " must be > 0");
  return ellipse(nb, r0, cx, cy, radius, radius, T0);
}

Membrane ellipse(int nb, double r0, double cx, double cy, double rx, double ry, double T0) {
  check_common("ellipse", nb, r0);
  if (!(rx > 0.0) || !(ry > 0.0))
    throw std::invalid_argument("ellipse: half-axes rx = " + std::to_string(rx) + ", ry = " +
                                std::to_string(ry) + " must be > 0");
  Membrane m;
  m.X.resize(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double theta = 2.0 * kPi * k / nb;  // = s_k / r0: uniform in rest arclength
    m.X(k, 0) = cx + rx * std::cos(theta);
    m.X(k, 1) = cy + ry * std::sin(theta);
  }
  m.L0 = 2.0 * kPi * r0;
  m.T0 = T0;
  return m;
}

Membrane from_points(const Mat2& points, int nb, double r0, double T0) {
  check_common("from_points", nb, r0);
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

  Membrane mem;
  mem.X.resize(nb, 2);
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
    mem.X.row(k) = C.point(i, u).transpose();
  }
  if (!is_simple(mem.X) || !(signed_area(mem.X) > 0.0))
    throw std::invalid_argument("from_points: the spline through the points self-intersects "
                                "after resampling (corners too sharp for a cubic spline?)");
  mem.L0 = 2.0 * kPi * r0;
  mem.T0 = T0;
  return mem;
}

Membrane from_curve(const std::function<Eigen::Vector2d(double)>& curve, int nb, double r0, double T0,
                    int samples) {
  check_common("from_curve", nb, r0);
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
    return from_points(P, nb, r0, T0);
  } catch (const std::invalid_argument& e) {
    std::string what = e.what();
    throw std::invalid_argument("from_curve: " + what.substr(what.find(':') + 2));
  }
}

Membrane from_polar(const std::function<double(double)>& r, int nb, double r0, double T0, double cx,
                    double cy) {
  if (!r) throw std::invalid_argument("from_polar: no radius function given");
  return from_curve(
      [&](double t) {
        const double theta = 2.0 * kPi * t, rho = r(theta);
        return Eigen::Vector2d(cx + rho * std::cos(theta), cy + rho * std::sin(theta));
      },
      nb, r0, T0);
}

// ---------------------------------------------------------------- polygon diagnostics

double signed_area(const Mat2& X) {
  const int n = static_cast<int>(X.rows());
  double a = 0.0;
  for (int k = 0, j = n - 1; k < n; j = k++) a += X(j, 0) * X(k, 1) - X(k, 0) * X(j, 1);
  return 0.5 * a;
}

Eigen::Vector2d polygon_centroid(const Mat2& X) {
  const int n = static_cast<int>(X.rows());
  double a = 0.0, mx = 0.0, my = 0.0;
  for (int k = 0, j = n - 1; k < n; j = k++) {
    const double c = X(j, 0) * X(k, 1) - X(k, 0) * X(j, 1);
    a += c;
    mx += (X(j, 0) + X(k, 0)) * c;
    my += (X(j, 1) + X(k, 1)) * c;
  }
  return {mx / (3.0 * a), my / (3.0 * a)};
}

bool is_simple(const Mat2& X) {
  const int n = static_cast<int>(X.rows());
  if (n < 3) return false;
  auto P = [&](int k) -> Eigen::Vector2d { return X.row(k % n).transpose(); };
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d a = P(i), b = P(i + 1), c = P(i + 2);
    if (a == b) return false;                                   // degenerate edge
    if (orient(a, b, c) == 0.0 && (a - b).dot(c - b) > 0.0) return false;  // folds back
    const int jmax = (i == 0) ? n - 1 : n;                      // edge n-1 neighbours edge 0
    for (int j = i + 2; j < jmax; ++j)
      if (segments_meet(a, b, P(j), P(j + 1))) return false;
  }
  return true;
}

ShapeMoments ellipse_fit(const Mat2& X) {
  // Green's theorem on each edge (x_j, y_j) -> (x_k, y_k), c = x_j y_k - x_k y_j, with the
  // coordinates taken about the vertex mean o (less cancellation):
  //   2A = sum c,  6A cx = sum c (x_j + x_k),
  //   12 int x^2 dA = sum c (x_j^2 + x_j x_k + x_k^2),
  //   24 int xy dA = sum c (2 x_j y_j + x_j y_k + x_k y_j + 2 x_k y_k).
  const int n = static_cast<int>(X.rows());
  ShapeMoments s;
  if (n < 3) return s;
  const Eigen::Vector2d o = X.colwise().mean().transpose();
  double a = 0, mx = 0, my = 0, ixx = 0, iyy = 0, ixy = 0;
  for (int k = 0, j = n - 1; k < n; j = k++) {
    const double xj = X(j, 0) - o.x(), yj = X(j, 1) - o.y(), xk = X(k, 0) - o.x(), yk = X(k, 1) - o.y();
    const double c = xj * yk - xk * yj;
    a += c;
    mx += c * (xj + xk);
    my += c * (yj + yk);
    ixx += c * (xj * xj + xj * xk + xk * xk);
    iyy += c * (yj * yj + yj * yk + yk * yk);
    ixy += c * (2.0 * xj * yj + xj * yk + xk * yj + 2.0 * xk * yk);
  }
  s.area = 0.5 * a;
  const double cx = mx / (3.0 * a), cy = my / (3.0 * a);  // about o
  s.centroid = o + Eigen::Vector2d(cx, cy);
  // Parallel axes: central moments = moments about o - A (c - o)(c - o)^T.
  s.Jxx = ixx / 12.0 - s.area * cx * cx;
  s.Jyy = iyy / 12.0 - s.area * cy * cy;
  s.Jxy = ixy / 24.0 - s.area * cx * cy;
  // Eigenvalues of J; an ellipse of half-axes (L, B) has lambda = A L^2/4, A B^2/4.
  const double mean = 0.5 * (s.Jxx + s.Jyy), dev = std::hypot(0.5 * (s.Jxx - s.Jyy), s.Jxy);
  s.L = 2.0 * std::sqrt(std::max(mean + dev, 0.0) / s.area);
  s.B = 2.0 * std::sqrt(std::max(mean - dev, 0.0) / s.area);
  s.theta = 0.5 * std::atan2(2.0 * s.Jxy, s.Jxx - s.Jyy);
  if (s.theta <= -0.5 * kPi) s.theta += kPi;  // atan2(-0, x < 0): keep (-pi/2, pi/2]
  return s;
}

double mean_angular_velocity(const Mat2& X, const Mat2& U, const Eigen::Vector2d& c) {
  const int n = static_cast<int>(X.rows());
  double w = 0.0;
  for (int k = 0; k < n; ++k) {
    const double rx = X(k, 0) - c.x(), ry = X(k, 1) - c.y();
    w += (rx * U(k, 1) - ry * U(k, 0)) / (rx * rx + ry * ry);  // (X - c) x U / |X - c|^2
  }
  return n ? w / n : 0.0;
}

// ---------------------------------------------------------------- spline diagnostics

MembraneDiagnostics::MembraneDiagnostics(int nb, double L0)
    : nb_(nb), sx_(nb, L0), sy_(nb, L0) {}

void MembraneDiagnostics::fit(const Mat2& X) {
  if (X.rows() != nb_)
    throw std::invalid_argument("MembraneDiagnostics: X has " + std::to_string(X.rows()) +
                                " markers, expected nb = " + std::to_string(nb_));
  sx_.fit(X.data());
  sy_.fit(X.data() + nb_);
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
      const double t = 0.5 * h * (1.0 + kGL5x[q]);
      const double x = cx[0] + t * (cx[1] + t * (cx[2] + t * cx[3]));
      const double y = cy[0] + t * (cy[1] + t * (cy[2] + t * cy[3]));
      const double xs = cx[1] + t * (2.0 * cx[2] + 3.0 * t * cx[3]);
      const double ys = cy[1] + t * (2.0 * cy[2] + 3.0 * t * cy[3]);
      sum += kGL5w[q] * g(x, y, xs, ys);
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

double MembraneDiagnostics::energy(double T0) const {
  return 0.5 * T0 * integrate(sx_, sy_, [](double, double, double xs, double ys) {
    const double e = std::sqrt(xs * xs + ys * ys) - 1.0;  // T/T0, Eq. (47)
    return e * e;
  });
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

MembraneShape MembraneDiagnostics::measure(const Mat2& X, double T0) {
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
  m.energy = energy(T0);
  return m;
}

}  // namespace sphib
