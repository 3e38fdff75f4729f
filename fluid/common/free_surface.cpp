#include "fluid/common/free_surface.hpp"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

bool supports_free_surface(FluidMethod method) { return method == FluidMethod::Wcsph || method == FluidMethod::Isph; }

bool has_free_surface(const Domain& d, const FreeSurfaceParams& fs) {
  return fs.fill.shape != FluidRegion::Shape::Domain || d.any_open();
}

SurfaceDetection detection_for(FluidMethod method, const Domain& d, const FreeSurfaceParams& fs) {
  if (fs.detection != SurfaceDetection::Auto) return fs.detection;
  if (!has_free_surface(d, fs)) return SurfaceDetection::None;
  return method == FluidMethod::Isph ? SurfaceDetection::Divergence : SurfaceDetection::Dilts;  // A Section 3.5
}

namespace {

[[noreturn]] void refuse(const std::string& key, const std::string& what) {
  throw std::invalid_argument(key + ": " + what);
}

// The region's corners (a circle: its bounding box), for the checks and the hydrostatic top.
std::array<Eigen::Vector2d, 4> corners(const FluidRegion& r, const Domain& d) {
  double x0 = d.x0, x1 = d.x1, y0 = d.y0, y1 = d.y1;
  if (r.shape == FluidRegion::Shape::Block) x0 = r.x0, x1 = r.x1, y0 = r.y0, y1 = r.y1;
  if (r.shape == FluidRegion::Shape::Circle) {
    x0 = r.centre.x() - r.radius, x1 = r.centre.x() + r.radius;
    y0 = r.centre.y() - r.radius, y1 = r.centre.y() + r.radius;
  }
  return {Eigen::Vector2d(x0, y0), Eigen::Vector2d(x1, y0), Eigen::Vector2d(x0, y1), Eigen::Vector2d(x1, y1)};
}

// The fluid region must lie in the tank.
std::optional<ParamProblem> region_problem(const FluidRegion& r, const Domain& d) {
  if (r.shape == FluidRegion::Shape::Domain) return std::nullopt;
  const bool block = r.shape == FluidRegion::Shape::Block;
  if (block && !(r.x1 > r.x0)) return ParamProblem{"fill.x", "must satisfy x0 < x1"};
  if (block && !(r.y1 > r.y0)) return ParamProblem{"fill.y", "must satisfy y0 < y1"};
  if (!block && !(r.radius > 0)) return ParamProblem{"fill.radius", "must be positive"};
  const auto c = corners(r, d);
  const double tol = 1e-12 * std::max(d.Lx(), d.Ly());
  auto outside = [&](const char* key, const char* axis) {
    std::ostringstream m;
    m << "the fluid region [" << c[0].x() << ", " << c[3].x() << "] x [" << c[0].y() << ", " << c[3].y()
      << "] is not inside the tank [" << d.x0 << ", " << d.x1 << "] x [" << d.y0 << ", " << d.y1 << "] (along " << axis
      << ")";
    return ParamProblem{key, m.str()};
  };
  if (c[0].x() < d.x0 - tol || c[3].x() > d.x1 + tol) return outside(block ? "fill.x" : "fill.radius", "x");
  if (c[0].y() < d.y0 - tol || c[3].y() > d.y1 + tol) return outside(block ? "fill.y" : "fill.radius", "y");
  return std::nullopt;
}

void check_inside(const FluidRegion& r, const Domain& d) {
  if (const auto e = region_problem(r, d)) refuse(e->key, e->what);
}

}  // namespace

std::optional<ParamProblem> free_surface_problem(FluidMethod method, const Domain& d, const FreeSurfaceParams& fs,
                                                 const Eigen::Vector2d& g) {
  const bool free = has_free_surface(d, fs), gravity = g.norm() != 0;
  if (!supports_free_surface(method)) {
    const std::string none = std::string("method \"") + to_string(method) + "\" has no free surface (methods with one: wcsph, isph)";
    if (fs.fill.shape != FluidRegion::Shape::Domain) return ParamProblem{"fill.shape", "a partly filled tank: " + none};
    if (d.any_open()) return ParamProblem{"domain.open", "an open side: " + none};
    if (gravity) return ParamProblem{"fluid.gravity", none + " (a body force rho g is fluid.body_force)"};
  }
  if (!std::isfinite(g.x()) || !std::isfinite(g.y())) return ParamProblem{"fluid.gravity", "must be finite"};
  for (int a = 0; a < 2; ++a) {
    const double ga = g[a];
    if (ga == 0) continue;
    if (a == 0 ? d.periodic_x : d.periodic_y)
      return ParamProblem{"fluid.gravity", std::string("has a component along the periodic ") + (a == 0 ? "x" : "y") +
                                               " axis, where no wall holds the fluid (a driving force is fluid.body_force)"};
    const Side towards = a == 0 ? (ga < 0 ? Left : Right) : (ga < 0 ? Bottom : Top);
    if (d.is_open(towards))
      return ParamProblem{"fluid.gravity", std::string("points at the open ") + side_name(towards) +
                                               " side: no wall holds the fluid"};
  }
  if (!(fs.beta > 0 && fs.beta < 1)) return ParamProblem{"free_surface.beta", "must be in (0, 1) (A Eq. 26: 2 beta below the bulk value 2)"};
  if (!(fs.dilts_radius > 0 && fs.dilts_radius <= 1))
    return ParamProblem{"free_surface.dilts_radius", "must be in (0, 1] (a neighbour covers an arc within 2R <= 2h)"};
  if (free) return region_problem(fs.fill, d);
  return std::nullopt;
}

ParticleSet fill_particles(const Lattice& L, const FluidRegion& r) {
  ParticleSet s;
  s.volume = L.dx * L.dy;
  if (r.shape == FluidRegion::Shape::Domain) {
    s.x = L.x;
    return s;
  }
  check_inside(r, L.domain);
  std::vector<Eigen::Vector2d> pts;
  if (r.shape == FluidRegion::Shape::Circle && r.arrangement == FluidRegion::Arrangement::Rings) {
    if (std::fabs(L.dx - L.dy) > 1e-9 * L.dx) refuse("fill.arrangement", "\"rings\" needs a square lattice (dx = dy)");
    const int n = static_cast<int>(std::lround(r.radius / L.dx - 0.5));
    pts.push_back(r.centre);
    for (int k = 1; k <= n; ++k)
      for (int j = 0; j < 6 * k; ++j) {
        const double th = 2.0 * M_PI * j / (6.0 * k);
        pts.push_back(r.centre + k * L.dx * Eigen::Vector2d(std::cos(th), std::sin(th)));
      }
    s.volume = M_PI * L.dx * L.dx / 3.0;  // ring k's annulus 2 pi k dx^2 over its 6k particles
  } else {
    for (int i = 0; i < L.size(); ++i) {
      const Eigen::Vector2d p = L.x.row(i).transpose();
      const bool in = r.shape == FluidRegion::Shape::Block
                          ? p.x() >= r.x0 && p.x() <= r.x1 && p.y() >= r.y0 && p.y() <= r.y1
                          : (p - r.centre).norm() <= r.radius;
      if (in) pts.push_back(p);
    }
  }
  if (pts.empty() && r.shape == FluidRegion::Shape::Block) {  // name the extent that misses the lattice
    bool column = false, row = false;
    for (int i = 0; i < L.size(); ++i) {
      column |= L.x(i, 0) >= r.x0 && L.x(i, 0) <= r.x1;
      row |= L.x(i, 1) >= r.y0 && L.x(i, 1) <= r.y1;
    }
    refuse(column && !row ? "fill.y" : "fill.x", "the fluid region holds no particle of the lattice");
  }
  if (pts.empty()) refuse("fill.radius", "the fluid region holds no particle of the lattice");
  s.x.resize(static_cast<int>(pts.size()), 2);
  for (size_t k = 0; k < pts.size(); ++k) s.x.row(static_cast<int>(k)) = pts[k].transpose();
  return s;
}

Vec hydrostatic_depth(const Mat2& x, const FluidRegion& r, const Domain& d, const Eigen::Vector2d& g) {
  Vec depth = Vec::Zero(x.rows());
  const double gn = g.norm();
  if (gn == 0) return depth;
  const Eigen::Vector2d e = g / gn;
  double top = INFINITY;  // min over the region of x . e: its highest point against gravity
  if (r.shape == FluidRegion::Shape::Circle) top = r.centre.dot(e) - r.radius;
  else
    for (const auto& c : corners(r, d)) top = std::min(top, c.dot(e));
  for (int i = 0; i < x.rows(); ++i) depth[i] = x.row(i).dot(e.transpose()) - top;
  return depth;
}

double fluid_height(const FluidRegion& r, const Domain& d, const Eigen::Vector2d& g) {
  const double gn = g.norm();
  if (gn == 0) return 0.0;
  if (r.shape == FluidRegion::Shape::Circle) return 2.0 * r.radius;
  const Eigen::Vector2d e = g / gn;
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& c : corners(r, d)) lo = std::min(lo, c.dot(e)), hi = std::max(hi, c.dot(e));
  return hi - lo;
}

// ---- Surface detection

SurfaceDetector::SurfaceDetector(SurfaceDetection method, double beta, double radius)
    : method_(method), beta_(beta), R_(radius) {}

void SurfaceDetector::detect(int N, const ParticlePairs& P, const Vec& V, double V_fixed, std::vector<char>& flags) {
  flags.assign(N, 0);
  if (method_ == SurfaceDetection::Divergence) divergence(N, P, V, V_fixed, flags);
  if (method_ == SurfaceDetection::Dilts) dilts(N, P, flags);
}

void SurfaceDetector::divergence(int N, const ParticlePairs& P, const Vec& V, double V_fixed, std::vector<char>& flags) {
  div_r_.setZero(N);
  for (int k = 0; k < P.size(); ++k) {
    const int i = P.i[k], j = P.j[k];
    const double t = -P.r[k] * P.r[k] * P.F[k];  // -(x_i - x_j) . grad_i W_ij = -r^2 F_ij > 0
    div_r_[i] += (j < N ? V[j] : V_fixed) * t;
    if (j < N) div_r_[j] += V[i] * t;  // the same from j: (x_j - x_i) . grad_j W_ji
  }
  flag_divergence(div_r_, flags);
}

void SurfaceDetector::flag_divergence(const Vec& div_r, std::vector<char>& flags) const {
  flags.resize(div_r.size());
  for (int i = 0; i < div_r.size(); ++i) flags[i] = div_r[i] < 2.0 * beta_;  // A Eq. (26)
}

namespace {
// The pseudo-angle of the direction (x, y): a number in [0, 4) that grows with the angle from +x
// counter-clockwise (the quadrant plus a ratio), so that arcs are compared without trigonometry;
// opposite directions differ by 2.
double pseudo_angle(double x, double y) {
  if (y >= 0) return x >= 0 ? y / (x + y) : 1.0 + (-x) / (y - x);
  return x < 0 ? 2.0 + (-y) / (-x - y) : 3.0 + x / (x - y);
}

// The arc of the circle of radius R around a particle covered by a neighbour at x_j - x_i = (vx, vy),
// distance d < 2R: the directions within acos(d / 2R) of (vx, vy) (Dilts), as the pseudo-angles
// [lo, hi] of its ends (hi may pass 4 when the arc crosses +x).
std::pair<double, double> dilts_arc(double vx, double vy, double d, double R) {
  const double c = d / (2.0 * R), s = std::sqrt(1.0 - c * c);  // cos, sin of the half-angle
  const double lo = pseudo_angle(c * vx + s * vy, c * vy - s * vx);  // (vx, vy) turned by -alpha
  double hi = pseudo_angle(c * vx - s * vy, c * vy + s * vx);        // and by +alpha
  if (hi < lo) hi += 4.0;
  return {lo, hi};
}

// The sectors [k/16, (k+1)/16] (64 sectors of the pseudo-angle) inside the open arc (lo, hi), as bits.
std::uint64_t sectors_inside(double lo, double hi) {
  const double a = lo * 16.0, b = hi * 16.0;  // >= 0: truncation is floor
  const int k0 = static_cast<int>(a) + 1, kb = static_cast<int>(b), k1 = (kb < b ? kb + 1 : kb) - 2;
  auto bits = [](int a, int b) {  // bits a..b, 0 <= a <= b <= 63
    return (~std::uint64_t{0} >> (63 - (b - a))) << a;
  };
  if (k1 < k0) return 0;
  if (k1 < 64) return bits(k0, k1);
  if (k0 >= 64) return bits(k0 - 64, k1 - 64);
  return bits(k0, 63) | bits(0, k1 - 64);
}

// The octant (0..7) of the direction (x, y), octant k holding the directions within 22.5 degrees
// of k 45 degrees (the lattice's eight nearest neighbours at their centres); a direction on the
// border of two octants may go to either.
int octant(double x, double y) {
  const double c = 0.92387953251128674, s = 0.38268343236508978;  // cos, sin of 22.5 degrees
  const double u = c * x + s * y, v = c * y - s * x;              // turned by -22.5 degrees
  if (v >= 0) return u > 0 ? (v < u ? 1 : 2) : (v > -u ? 3 : 4);
  return u < 0 ? (-v < -u ? 5 : 6) : (-v > u ? 7 : 0);
}
}  // namespace

void SurfaceDetector::dilts(int N, const ParticlePairs& P, std::vector<char>& flags) {
  // Quick sufficient tests first: the 64 sectors of the circle that lie wholly inside some
  // neighbour's arc; a particle whose sectors are all covered is covered. Only the others (the
  // surface and a few disordered particles) get the exact test of their arcs. No trigonometry: the
  // arcs' ends are the direction turned by +-acos(d / 2R), compared by pseudo-angle.
  const double two_R = 2.0 * R_, r_min = 1e-12 * R_;
  const std::uint64_t all = ~std::uint64_t{0};
  // Cheaper still, first: a neighbour closer than sqrt(2) R covers more than 45 degrees on either
  // side of its direction, so the whole octant around it; eight such octants cover the circle
  // (a particle inside a regular lattice), marked as all sectors.
  sectors_.assign(N, 0);
  const double r_octant = std::sqrt(2.0) * R_;
  for (int k = 0; k < P.size(); ++k) {
    if (P.r[k] >= r_octant || P.r[k] < r_min) continue;
    const int o = octant(-P.rx[k], -P.ry[k]);  // from i towards j
    sectors_[P.i[k]] |= std::uint64_t{1} << o;
    if (P.j[k] < N) sectors_[P.j[k]] |= std::uint64_t{1} << ((o + 4) % 8);
  }
  for (auto& m : sectors_) m = m == 0xFF ? all : 0;
  for (int k = 0; k < P.size(); ++k) {
    if (P.r[k] >= two_R || P.r[k] < r_min) continue;
    const int i = P.i[k], j = P.j[k];
    const bool need_i = sectors_[i] != all, need_j = j < N && sectors_[j] != all;  // not yet covered
    if (!need_i && !need_j) continue;
    const auto [lo, hi] = dilts_arc(-P.rx[k], -P.ry[k], P.r[k], R_);  // i's circle, towards j
    if (need_i) sectors_[i] |= sectors_inside(lo, hi);
    if (need_j) sectors_[j] |= sectors_inside(lo + 2.0, hi + 2.0);  // j's circle, towards i
  }
  auto exact = [&](int i) { return i < N && sectors_[i] != all; };
  // The arcs of the particles the quick test left (both ends of a particle pair).
  first_.assign(N + 1, 0);
  for (int k = 0; k < P.size(); ++k) {
    if (P.r[k] >= two_R || P.r[k] < r_min) continue;
    if (exact(P.i[k])) ++first_[P.i[k] + 1];
    if (exact(P.j[k])) ++first_[P.j[k] + 1];
  }
  for (int i = 0; i < N; ++i) first_[i + 1] += first_[i];
  fill_.assign(first_.begin(), first_.end() - 1);
  lo_.resize(first_[N]);
  hi_.resize(first_[N]);
  for (int k = 0; k < P.size(); ++k) {
    if (P.r[k] >= two_R || P.r[k] < r_min || !(exact(P.i[k]) || exact(P.j[k]))) continue;
    const auto [lo, hi] = dilts_arc(-P.rx[k], -P.ry[k], P.r[k], R_);
    if (exact(P.i[k])) {
      const int a = fill_[P.i[k]]++;
      lo_[a] = lo;
      hi_[a] = hi;
    }
    if (exact(P.j[k])) {  // the opposite direction: pseudo-angles + 2
      const int b = fill_[P.j[k]]++;
      lo_[b] = lo + 2.0 >= 4.0 ? lo - 2.0 : lo + 2.0;
      hi_[b] = lo_[b] + (hi - lo);
    }
  }
  for (int i = 0; i < N; ++i) flags[i] = exact(i) && !circle_covered(first_[i], first_[i + 1]);
}

bool SurfaceDetector::circle_covered(int begin, int end) {
  const double full = 4.0, eps = 1e-12;  // pseudo-angles
  arcs_.clear();
  for (int a = begin; a < end; ++a) {
    arcs_.emplace_back(lo_[a], hi_[a]);
    if (hi_[a] > full) arcs_.emplace_back(lo_[a] - full, hi_[a] - full);  // the part past 4, from 0
  }
  std::sort(arcs_.begin(), arcs_.end());
  double covered = 0;  // [0, covered] is covered
  for (const auto& [lo, hi] : arcs_) {
    if (lo > covered + eps) return false;  // a gap
    covered = std::max(covered, hi);
    if (covered >= full - eps) return true;
  }
  return covered >= full - eps;
}

}  // namespace sphib
