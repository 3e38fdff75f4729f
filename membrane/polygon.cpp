#include "membrane/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

namespace sphib {

namespace {

constexpr double kPi = 3.14159265358979323846;

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

}  // namespace

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

bool is_simple_plain(const Mat2& X) {
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

namespace {

// An edge k (X_k -> X_{k+1}) with its endpoints in sweep order (p before q: smaller x, then y).
struct SweepEdge {
  Eigen::Vector2d p, q;
  int id;
  double slope() const { return p.x() == q.x() ? INFINITY : (q.y() - p.y()) / (q.x() - p.x()); }
  double y_at(double x) const {  // a vertical edge: its lower end
    return p.x() == q.x() ? p.y() : p.y() + (q.y() - p.y()) * ((x - p.x()) / (q.x() - p.x()));
  }
};

// Bottom to top at the later of the two left ends (ties: as just right of it, by slope; then by id):
// a consistent order for edges that do not cross, which is all the sweep keeps.
struct EdgeBelow {
  bool operator()(const SweepEdge* a, const SweepEdge* b) const {
    if (a->id == b->id) return false;
    const double x = std::max(a->p.x(), b->p.x());
    const double ya = a->y_at(x), yb = b->y_at(x);
    if (ya != yb) return ya < yb;
    const double sa = a->slope(), sb = b->slope();
    if (sa != sb) return sa < sb;
    return a->id < b->id;
  }
};

}  // namespace

// Shamos and Hoey (1976): a sweep from left to right keeps the edges it crosses in bottom-to-top
// order (a balanced tree); the first meeting of two edges is between edges that are neighbours in
// that order when one of them arrives or leaves, so only those pairs are tested: O(n log n).
bool is_simple(const Mat2& X) {
  const int n = static_cast<int>(X.rows());
  if (n < 3) return false;
  auto P = [&](int k) -> Eigen::Vector2d { return X.row(k % n).transpose(); };
  auto before = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  };
  std::vector<SweepEdge> edges(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d a = P(i), b = P(i + 1), c = P(i + 2);
    if (!a.allFinite()) return false;
    if (a == b) return false;                                               // degenerate edge
    if (orient(a, b, c) == 0.0 && (a - b).dot(c - b) > 0.0) return false;  // folds back onto its neighbour
    edges[i] = before(a, b) ? SweepEdge{a, b, i} : SweepEdge{b, a, i};
  }
  // Two vertices at one point (not neighbours: those were refused above) touch.
  std::vector<int> order(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return before(P(a), P(b)); });
  for (int k = 0; k + 1 < n; ++k)
    if (P(order[k]) == P(order[k + 1])) return false;
  // Events: each edge arrives at p and leaves at q; at one point, arrivals first (edges that only
  // touch there are both present).
  struct Event {
    Eigen::Vector2d at;
    bool leaves;
    int id;
  };
  std::vector<Event> events;
  events.reserve(2 * static_cast<size_t>(n));
  for (const SweepEdge& e : edges) events.push_back({e.p, false, e.id}), events.push_back({e.q, true, e.id});
  std::sort(events.begin(), events.end(), [&](const Event& a, const Event& b) {
    if (a.at.x() != b.at.x()) return a.at.x() < b.at.x();
    if (a.leaves != b.leaves) return !a.leaves;
    return a.at.y() < b.at.y();
  });
  auto neighbours = [n](int i, int j) { return std::abs(i - j) == 1 || std::abs(i - j) == n - 1; };
  auto meet = [&](const SweepEdge* a, const SweepEdge* b) {
    return !neighbours(a->id, b->id) && segments_meet(a->p, a->q, b->p, b->q);
  };
  std::set<const SweepEdge*, EdgeBelow> active;
  std::vector<std::set<const SweepEdge*, EdgeBelow>::iterator> where(static_cast<size_t>(n));
  for (const Event& ev : events) {
    const SweepEdge* e = &edges[ev.id];
    if (!ev.leaves) {
      const auto above = active.lower_bound(e);
      if (above != active.end() && meet(*above, e)) return false;
      if (above != active.begin() && meet(*std::prev(above), e)) return false;
      where[ev.id] = active.insert(above, e);
    } else {
      const auto it = where[ev.id];
      const auto above = std::next(it);
      if (it != active.begin() && above != active.end() && meet(*std::prev(it), *above)) return false;
      active.erase(it);
    }
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
  const double A = 0.5 * a;
  const double cx = mx / (3.0 * a), cy = my / (3.0 * a);  // about o
  // Parallel axes: central moments = moments about o - A (c - o)(c - o)^T.
  return moment_ellipse(A, o + Eigen::Vector2d(cx, cy), ixx / 12.0 - A * cx * cx, ixy / 24.0 - A * cx * cy,
                        iyy / 12.0 - A * cy * cy);
}

ShapeMoments moment_ellipse(double A, const Eigen::Vector2d& c, double Jxx, double Jxy, double Jyy) {
  ShapeMoments s;
  s.area = A;
  s.centroid = c;
  s.Jxx = Jxx;
  s.Jyy = Jyy;
  s.Jxy = Jxy;
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

}  // namespace sphib
