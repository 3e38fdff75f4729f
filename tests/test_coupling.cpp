// coupling/: spreading (Eq. 53), interpolation (Eqs. 60-63), the marker update (Eqs. 56-60) and
// the IB step. Every tolerance is a measured value (Release build, stated beside the test) with a
// margin; round-off checks say so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <stdexcept>
#include <string>

#include "coupling/interpolate.hpp"
#include "coupling/simulation.hpp"
#include "coupling/spread.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/common/neighbours.hpp"
#include "membrane/geometry.hpp"
#include "membrane/polygon.hpp"
#include "membrane/shapes.hpp"
#include "observe/analysis.hpp"

using namespace sphib;

namespace {

constexpr double kPi = 3.14159265358979323846;

Domain unit_box(bool periodic_x, bool periodic_y) {
  Domain d;
  d.periodic_x = periodic_x;
  d.periodic_y = periodic_y;
  return d;
}

// A cell grid over the lattice with cells of one lattice spacing, as the Simulation builds it.
CellGrid lattice_grid(const Lattice& L) {
  const Domain& d = L.domain;
  CellGrid g(Eigen::Vector2d(d.x0, d.y0), Eigen::Vector2d(d.x1, d.y1), d.periodic_x, d.periodic_y,
             std::min(L.dx, L.dy));
  g.build(L.x);
  return g;
}

// nb markers on a circle of radius r about (cx, cy) and an arbitrary force density with
// sum_k f_k ds = 2 pi r (1, 0.5) != 0.
void circle_markers(int nb, double r, double cx, double cy, Mat2& X, Mat2& f) {
  X.resize(nb, 2);
  f.resize(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double th = 2.0 * kPi * k / nb;
    X(k, 0) = cx + r * std::cos(th);
    X(k, 1) = cy + r * std::sin(th);
    f(k, 0) = 1.0 + std::cos(th);
    f(k, 1) = 0.5 + std::sin(2.0 * th) + 0.3 * std::sin(th);
  }
}

// Brute-force kernel sum S(X) = sum_i W(X - x_i, h) V over every particle (minimum image).
double kernel_sum(const Lattice& L, const CubicSplineKernel& W, double X, double Y) {
  const Domain& d = L.domain;
  double s = 0;
  for (int i = 0; i < L.size(); ++i) {
    double dx = X - L.x(i, 0), dy = Y - L.x(i, 1);
    if (d.periodic_x) dx -= d.Lx() * std::round(dx / d.Lx());
    if (d.periodic_y) dy -= d.Ly() * std::round(dy / d.Ly());
    s += W.W(std::hypot(dx, dy)) * L.volume;
  }
  return s;
}

}  // namespace

// The cell grid returns exactly the points within the radius (minimum image along periodic
// axes), each once, compared with brute force over 300 random points and 200 random queries.
// Cases: lattice-spaced cells (the markers' grid) with radii up to 0.3 L, and cells of at least
// the radius (find_pairs' grid), radius < L/2.
// The cases with fewer than 3 cells per period and a query disc spanning every cell (span(), "all"
// branch) are the ones a grid that wraps a cell twice gets wrong (missed neighbours).
TEST(Coupling, CellGridQueriesMatchBruteForce) {
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int n = 300;
  Mat2 pts(n, 2);
  for (int i = 0; i < n; ++i) { pts(i, 0) = U(gen); pts(i, 1) = U(gen); }
  struct Case { bool px, py; double cell, radius; };
  const Case cases[] = {
      {true, true, 1.0 / 16, 0.1},  {true, true, 1.0 / 16, 0.3},  {true, false, 1.0 / 32, 0.15},
      {false, false, 1.0 / 16, 0.2}, {true, true, 0.2, 0.2},       {true, true, 0.3, 0.3},
      {true, true, 0.375, 0.375},    {true, false, 0.4, 0.4},      {true, true, 0.3, 0.45}};
  for (const Case& c : cases) {
    CellGrid g(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), c.px, c.py, c.cell);
    g.build(pts);
    int missing = 0, extra = 0, duplicate = 0, wrong_offset = 0;
    for (int q = 0; q < 200; ++q) {
      const double qx = U(gen), qy = U(gen);
      std::multiset<int> got;
      g.for_each_near(qx, qy, c.radius, [&](int j, double dx, double dy, double r) {
        got.insert(j);
        double ex = qx - pts(j, 0), ey = qy - pts(j, 1);
        if (c.px) ex -= std::round(ex);
        if (c.py) ey -= std::round(ey);
        if (std::abs(dx - ex) > 1e-14 || std::abs(dy - ey) > 1e-14 || std::abs(r - std::hypot(ex, ey)) > 1e-14)
          ++wrong_offset;
      });
      for (int j = 0; j < n; ++j) {
        double dx = qx - pts(j, 0), dy = qy - pts(j, 1);
        if (c.px) dx -= std::round(dx);
        if (c.py) dy -= std::round(dy);
        const bool in = dx * dx + dy * dy < c.radius * c.radius;
        const int k = static_cast<int>(got.count(j));
        missing += in && k == 0;
        extra += !in && k > 0;
        duplicate += k > 1;
      }
    }
    EXPECT_EQ(missing, 0) << "cell >= " << c.cell << ", radius " << c.radius << ", periodic " << c.px << c.py;
    EXPECT_EQ(extra, 0) << "cell >= " << c.cell << ", radius " << c.radius;
    EXPECT_EQ(duplicate, 0) << "cell >= " << c.cell << ", radius " << c.radius;
    EXPECT_EQ(wrong_offset, 0) << "cell >= " << c.cell << ", radius " << c.radius;
  }
}

// The lattice mode of the grid (use_lattice: index arithmetic on the fixed lattice, what the
// markers of EPSPH query) finds exactly the lattice points within the radius, with the
// minimum-image offsets, for queries anywhere (also outside the box along a periodic axis).
// Offsets from indices against stored positions: measured max difference 3.3e-16; tolerance 1e-13.
TEST(Coupling, LatticeQueriesMatchBruteForce) {
  std::mt19937 gen(5);
  struct Case { bool px, py; int nx, ny; double radius; };
  for (const Case& c : {Case{true, false, 16, 12, 0.15}, Case{true, true, 20, 20, 0.3}, Case{false, false, 10, 14, 0.25},
                        Case{false, true, 12, 16, 0.2}}) {
    Domain d;
    d.periodic_x = c.px;
    d.periodic_y = c.py;
    const Lattice L = make_lattice(d, c.nx, c.ny);
    CellGrid g(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), c.px, c.py, std::min(L.dx, L.dy));
    g.use_lattice(L);
    std::uniform_real_distribution<double> U(-0.2, 1.2);
    int missing = 0, extra = 0, duplicate = 0, wrong_offset = 0;
    for (int q = 0; q < 300; ++q) {
      const double qx = c.px ? U(gen) : 0.5 * (U(gen) + 0.2), qy = c.py ? U(gen) : 0.5 * (U(gen) + 0.2);
      std::multiset<int> got;
      g.for_each_near(qx, qy, c.radius, [&](int j, double dx, double dy, double r) {
        got.insert(j);
        double ex = qx - L.x(j, 0), ey = qy - L.x(j, 1);
        if (c.px) ex -= std::round(ex);
        if (c.py) ey -= std::round(ey);
        if (std::abs(dx - ex) > 1e-13 || std::abs(dy - ey) > 1e-13 || std::abs(r - std::hypot(ex, ey)) > 1e-13)
          ++wrong_offset;
      });
      for (int j = 0; j < L.size(); ++j) {
        double dx = qx - L.x(j, 0), dy = qy - L.x(j, 1);
        if (c.px) dx -= std::round(dx);
        if (c.py) dy -= std::round(dy);
        const double r2 = dx * dx + dy * dy, R2 = c.radius * c.radius;
        if (std::abs(r2 - R2) < 1e-12) continue;  // on the circle: either answer is right
        const bool in = r2 < R2;
        const int k = static_cast<int>(got.count(j));
        missing += in && k == 0;
        extra += !in && k > 0;
        duplicate += k > 1;
      }
    }
    EXPECT_EQ(missing, 0) << "periodic " << c.px << c.py;
    EXPECT_EQ(extra, 0) << "periodic " << c.px << c.py;
    EXPECT_EQ(duplicate, 0) << "periodic " << c.px << c.py;
    EXPECT_EQ(wrong_offset, 0) << "periodic " << c.px << c.py;
  }
}

// The four ways a lattice meets the unit box (periodic or walled along each axis), each with a cell
// grid on it: f(px, py, lattice, grid).
template <class F>
void for_each_boundary_case(F&& f) {
  struct Case { bool px, py; int nx, ny; };
  for (const Case& c : {Case{true, false, 16, 12}, Case{true, true, 20, 20}, Case{false, false, 10, 14},
                        Case{false, true, 12, 16}}) {
    Domain d;
    d.periodic_x = c.px;
    d.periodic_y = c.py;
    const Lattice L = make_lattice(d, c.nx, c.ny);
    CellGrid g(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), c.px, c.py, std::min(L.dx, L.dy));
    f(c.px, c.py, L, g);
  }
}

// CellGrid::gather_near (the markers' loops) returns exactly the points of for_each_near, in its
// order, with the same offsets and r2 = dx^2 + dy^2, in lattice mode (no branch per point) and
// with cells: 300 random queries per case, radii up to 0.3. Exact equality: the same expressions.
TEST(Coupling, GatherNearMatchesForEachNear) {
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> U(-0.2, 1.2), R(0.02, 0.3);
  for_each_boundary_case([&](bool px, bool py, const Lattice& L, const CellGrid& empty) {
    for (bool lattice : {true, false}) {
      CellGrid g = empty;
      if (lattice) g.use_lattice(L);
      else g.build(L.x);
      NearPoints near;
      int mismatches = 0, points = 0;
      for (int q = 0; q < 300; ++q) {
        const double qx = U(gen), qy = U(gen), radius = std::min(R(gen), 0.45);
        std::vector<int> j;
        std::vector<double> dx, dy;
        g.for_each_near(qx, qy, radius, [&](int jj, double x, double y, double) {
          j.push_back(jj);
          dx.push_back(x);
          dy.push_back(y);
        });
        g.gather_near(qx, qy, radius, near);
        mismatches += near.n != static_cast<int>(j.size());
        for (int m = 0; m < std::min<int>(near.n, static_cast<int>(j.size())); ++m)
          mismatches += near.j[m] != j[m] || near.dx[m] != dx[m] || near.dy[m] != dy[m] ||
                        near.r2[m] != dx[m] * dx[m] + dy[m] * dy[m];
        mismatches += static_cast<int>(near.j.size()) <= near.n;  // room for a padding point
        points += near.n;
      }
      EXPECT_EQ(mismatches, 0) << "periodic " << px << py << " lattice " << lattice;
      EXPECT_GT(points, 300) << "periodic " << px << py;
    }
  });
}

// CellGrid::lattice_box with a range of row bases (a thread's share of the spreading) gives the whole
// box's rows whose base lies in the range, in their order, and the whole box's columns when a row is
// kept: 300 random queries per case, split at random points of the lattice. Exact equality.
TEST(Coupling, LatticeBoxRowRangeIsTheWholeBoxsRowsInRange) {
  std::mt19937 gen(12);
  std::uniform_real_distribution<double> U(-0.2, 1.2), R(0.02, 0.3), S(0.0, 1.0);
  for_each_boundary_case([&](bool px, bool py, const Lattice& L, CellGrid& g) {
    g.use_lattice(L);
    const long N = static_cast<long>(L.nx) * L.ny;
    CellGrid::LatticeBox whole, part;
    int mismatches = 0, kept = 0, empty = 0;
    for (int q = 0; q < 300; ++q) {
      const double qx = U(gen), qy = U(gen), radius = std::min(R(gen), 0.45);
      long lo = static_cast<long>(S(gen) * N), hi = static_cast<long>(S(gen) * N);
      if (lo > hi) std::swap(lo, hi);
      g.lattice_box(qx, qy, radius, whole);
      g.lattice_box(qx, qy, radius, lo, hi, part);
      int r = 0;
      for (int w = 0; w < whole.nrow; ++w) {
        if (whole.base[w] < lo || whole.base[w] >= hi) continue;
        mismatches += r >= part.nrow || part.base[r] != whole.base[w] || part.ry[r] != whole.ry[w];
        ++r;
      }
      mismatches += r != part.nrow;
      if (part.nrow == 0) {
        ++empty;
        continue;
      }
      ++kept;
      mismatches += part.ncol != whole.ncol;
      for (int k = 0; k < std::min(part.ncol, whole.ncol); ++k)
        mismatches += part.col[k] != whole.col[k] || part.cdx[k] != whole.cdx[k];
    }
    EXPECT_EQ(mismatches, 0) << "periodic " << px << py;
    EXPECT_GT(kept, 10) << "periodic " << px << py;
    EXPECT_GT(empty, 10) << "periodic " << px << py;
  });
}

namespace {

// The markers' sums as they were written before the two-lane loops: W() and F() per point inside
// for_each_near, summed in its order.
void curl_per_point(const CellGrid& grid, const CubicSplineKernel& W, const Vec& psi, const Mat2& X, Mat2& U) {
  for (int k = 0; k < X.rows(); ++k) {
    double s = 0, sp = 0, gx = 0, gy = 0, gpx = 0, gpy = 0;
    grid.for_each_near(X(k, 0), X(k, 1), W.support(), [&](int j, double dx, double dy, double r) {
      const double w = W.W(r), F = W.F(r), p = psi[j];
      s += w;
      sp += p * w;
      gx += F * dx;
      gy += F * dy;
      gpx += p * F * dx;
      gpy += p * F * dy;
    });
    const double ph = sp / s;
    U(k, 0) = (gpy - ph * gy) / s;
    U(k, 1) = -(gpx - ph * gx) / s;
  }
}

void spread_per_point(const CellGrid& grid, const CubicSplineKernel& W, const Mat2& X, const Mat2& f, double ds,
                      Mat2& F) {
  for (int k = 0; k < X.rows(); ++k)
    grid.for_each_near(X(k, 0), X(k, 1), W.support(), [&](int i, double, double, double r) {
      F(i, 0) += f(k, 0) * ds * W.W(r);
      F(i, 1) += f(k, 1) * ds * W.W(r);
    });
}

}  // namespace

// The markers' two-lane loops (coupling/neighbourhood.hpp: gathered points, branch-free kernel,
// sums in two lanes) against the per-point sums above, on a circle across the periodic seam, a
// channel and a doubly periodic box, h/dx = 1.2, 1.525, 3 and 6.72 (the spreading kernel's widest in
// the capsule study, 13.4 spacings across, on 64^2), lattice queries and cell queries.
// Measured max relative difference: divergence-free interpolation 3.3e-15, spreading 3.4e-16
// (the kernel's last bits and the summation order); lattice and cell queries bit for bit alike.
// Tolerances 1e-14 and 5e-15. The interpolated velocity's divergence (its gradient's trace) is 0.
TEST(Coupling, MarkerLoopsMatchThePerPointSums) {
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> R(0.0, 1.0);
  for (bool py : {false, true})
    for (double h_over_dx : {1.2, 1.525, 3.0, 6.72}) {
      const int n = h_over_dx > 4 ? 64 : 32;  // the widest support, 13.4 spacings, below half a period
      const Lattice L = make_lattice(unit_box(true, py), n, n);
      CellGrid lat(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), true, py, L.dx);
      lat.use_lattice(L);
      const CellGrid cells = lattice_grid(L);
      const CubicSplineKernel W(h_over_dx * L.dx);
      Vec psi(L.size());
      for (int i = 0; i < L.size(); ++i)
        psi[i] = std::sin(2 * kPi * L.x(i, 0)) * std::cos(2 * kPi * L.x(i, 1)) + 0.01 * R(gen);
      Mat2 X, f;
      circle_markers(64, 0.25, 0.93, 0.5, X, f);
      Mat2 U(64, 2), Uc(64, 2), Ur(64, 2);
      Jacobians J;
      interpolate_curl(lat, W, psi, Eigen::Vector2d::Zero(), X, U, &J);
      interpolate_curl(cells, W, psi, Eigen::Vector2d::Zero(), X, Uc);
      curl_per_point(lat, W, psi, X, Ur);
      Mat2 F = Mat2::Zero(L.size(), 2), Fc = F, Fr = F;
      spread_force(lat, W, X, f, 0.02, F);
      spread_force(cells, W, X, f, 0.02, Fc);
      spread_per_point(lat, W, X, f, 0.02, Fr);
      const double Umax = U.cwiseAbs().maxCoeff(), Fmax = F.cwiseAbs().maxCoeff();
      EXPECT_LT((U - Ur).cwiseAbs().maxCoeff(), 1e-14 * Umax) << h_over_dx << " " << py;
      EXPECT_LT((F - Fr).cwiseAbs().maxCoeff(), 5e-15 * Fmax) << h_over_dx << " " << py;
      EXPECT_EQ((U - Uc).cwiseAbs().maxCoeff(), 0.0) << h_over_dx << " " << py;
      EXPECT_EQ((F - Fc).cwiseAbs().maxCoeff(), 0.0) << h_over_dx << " " << py;
      EXPECT_EQ((J.col(0) + J.col(3)).cwiseAbs().maxCoeff(), 0.0) << h_over_dx << " " << py;  // divergence-free
    }
}

// The gradient dU/dX of the divergence-free marker velocity (interpolate_curl with dU) against
// central differences of U (step 1e-6 h), same cases and h/dx = 6.72 (the spreading kernel's
// widest in the capsule study): measured max error 2.0e-9 of max |dU/dX| (4.8e-10 at 6.72; the
// differences' truncation and round-off); tolerance 1e-8. Its trace (the divergence) is 0
// exactly, and U is bit for bit the U computed without the gradient.
TEST(Coupling, CurlInterpolationGradientMatchesFiniteDifferences) {
  for (bool py : {false, true})
    for (double h_over_dx : {1.2, 1.525, 3.0, 6.72}) {
      const Lattice L = make_lattice(unit_box(true, py), 32, 32);
      const CellGrid grid = lattice_grid(L);
      const CubicSplineKernel W(h_over_dx * L.dx);
      Vec psi(L.size());
      for (int i = 0; i < L.size(); ++i)
        psi[i] = std::sin(2 * kPi * L.x(i, 0)) * std::cos(2 * kPi * L.x(i, 1)) + 0.3 * L.x(i, 1);
      Mat2 X, f;
      circle_markers(64, 0.25, 0.93, 0.5, X, f);
      Mat2 U(64, 2), U0(64, 2);
      Jacobians J;
      const Eigen::Vector2d mean(0.1, -0.2);
      interpolate_curl(grid, W, psi, mean, X, U, &J);
      interpolate_curl(grid, W, psi, mean, X, U0);
      EXPECT_EQ((U - U0).cwiseAbs().maxCoeff(), 0.0);
      const double Jmax = J.cwiseAbs().maxCoeff(), e = 1e-6 * W.h;
      double worst = 0;
      for (int a = 0; a < 2; ++a) {
        Mat2 Xp = X, Xm = X, Up(64, 2), Um(64, 2);
        Xp.col(a).array() += e;
        Xm.col(a).array() -= e;
        interpolate_curl(grid, W, psi, mean, Xp, Up);
        interpolate_curl(grid, W, psi, mean, Xm, Um);
        for (int k = 0; k < 64; ++k)
          for (int c = 0; c < 2; ++c) worst = std::max(worst, std::abs((Up(k, c) - Um(k, c)) / (2 * e) - J(k, 2 * c + a)));
      }
      EXPECT_LT(worst, 1e-8 * Jmax) << h_over_dx << " " << py;
      EXPECT_EQ((J.col(0) + J.col(3)).cwiseAbs().maxCoeff(), 0.0);
    }
}

// ------------------------------------------------------------------ the spreading kernel's curl
// (coupling.interpolation = "spreading_kernel": interpolate_curl with the kernel of radius h*, the
// spreading's, at h*/dx = 1.68, 3.36 and 6.72: the capsule's h* = 0.105 on its 64 x 32, 128 x 64 and
// 256 x 128 lattices.)

namespace {
constexpr double kHsOverDx[] = {1.68, 3.36, 6.72};
}  // namespace

// A uniform flow, psi = d x + e y (no mean: the flow is all in psi). The normalised kernel sum
// reproduces constants exactly (the gauge of psi does not matter) but not linear functions: at a
// point X, grad psi_h = -(sum_j (x_j - X) (x_j - X)^T F_j) d / sum_j W_j for psi = d . x, and the
// lattice sums meet the continuous identity (integration by parts: int r r^T F = -I int W) only to
// the lattice-sum (aliasing) error of the kernel, also at lattice points; it falls fast as h*/dx
// grows (Poisson summation: the kernel's transform at the lattice wavenumber). The wider kernel is
// the remedy here; an exact reproduction of linear psi would need a moving-least-squares psi_h.
// Max |U - (e, -d)| / |(d, e)| over 200 random points in [-0.5, 0.5]^2 and at a lattice point, 64^2
// lattice on [-1, 1]^2, measured at h*/dx = 1.68, 3.36, 6.72: 1.748e-2, 1.226e-3, 1.000e-4 (at the
// lattice point 1.19e-2, 7.30e-4, 6.07e-5), a factor 12-14 per doubling. Tolerance 1.1x measured,
// and a fall of at least 8x per doubling.
TEST(SpreadingKernelCurl, UniformFlowToTheLatticeSumError) {
  Domain d;
  d.x0 = -1, d.x1 = 1, d.y0 = -1, d.y1 = 1;
  d.periodic_x = d.periodic_y = true;
  const Lattice L = make_lattice(d, 64, 64);
  CellGrid grid(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1), true, true, L.dx);
  grid.use_lattice(L);
  const double dd = 1.1, e = -0.4;
  Vec psi(L.size());
  for (int i = 0; i < L.size(); ++i) psi[i] = dd * L.x(i, 0) + e * L.x(i, 1);
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> R(-0.5, 0.5);
  Mat2 X(200, 2), U(200, 2);
  for (int k = 0; k < 200; ++k) X.row(k) << R(gen), R(gen);
  X.row(0) << L.x(64 * 32 + 32, 0), L.x(64 * 32 + 32, 1);  // a lattice point
  const double measured[] = {1.748e-2, 1.226e-3, 1.000e-4};
  double last = 0;
  for (int n = 0; n < 3; ++n) {
    const double hs = kHsOverDx[n];
    interpolate_curl(grid, CubicSplineKernel(hs * L.dx), psi, Eigen::Vector2d::Zero(), X, U);
    double worst = 0;
    for (int k = 0; k < 200; ++k) worst = std::max(worst, std::hypot(U(k, 0) - e, U(k, 1) + dd));
    worst /= std::hypot(dd, e);
    EXPECT_LT(worst, 1.1 * measured[n]) << hs;
    EXPECT_GT(worst, 0.5 * measured[n]) << hs;  // not exact: the theory above says why
    if (last > 0) EXPECT_LT(worst, last / 8) << hs;
    last = worst;
  }
}

// The pairing's adjointness. Spreading (Eq. 53) and the marker interpolation are adjoint when
//   sum_i V u_i . F_i  =  sum_k P_k . U(X_k),   F_i = sum_k P_k W(x_i - X_k, h*),  P_k = f_k ds.
// For the unnormalised SPH interpolation of u with the same kernel this holds exactly (the test
// UnnormalisedInterpolationIsAdjointOfSpreading). The curl interpolates psi, not u, so no identity
// holds exactly on the lattice; the continuous one does: both sides are sum_k P_k . (W* conv u)(X_k),
// since W* conv curl psi = curl (W* conv psi). With the kernel of radius h* the lattice sums approach
// it at the lattice-sum error; a narrower interpolation (the B-splines, about dx wide; the fluid's h)
// misses the smoothing of the spreading by O((k h*)^2) and moves away from it as h* grows. Measured:
// a smooth flow u = curl psi, psi = sin(2 pi x) cos(2 pi y) / (2 pi) + 0.1 sin(4 pi y) / (4 pi),
// sampled exactly at the lattice points (64^2 periodic unit box), circle r = 0.25 across the seam,
// 64 markers; relative mismatch |lhs - rhs| / sum_k |P_k| |U_k| at h*/dx = 1.68, 3.36, 6.72:
//   kernel of radius h*: 3.397e-4, 2.920e-5, 2.738e-6 (a factor 11-12 per doubling);
//   B-splines:           1.292e-4, 8.147e-4, 3.075e-3;  the fluid's kernel h = 1.2 dx: 7.5e-4, 1.4e-3, 3.8e-3.
// Tolerance 1.1x measured for the kernel of radius h*, a fall of at least 8x per doubling, and the
// B-splines' mismatch growing and above 10x the kernel's from h*/dx = 3.36 on.
TEST(SpreadingKernelCurl, PairedWithSpreadingToTheLatticeSumError) {
  const Lattice L = make_lattice(unit_box(true, true), 64, 64);
  CellGrid grid(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), true, true, L.dx);
  grid.use_lattice(L);
  Vec psi(L.size());
  Mat2 u(L.size(), 2);
  for (int i = 0; i < L.size(); ++i) {
    const double x = L.x(i, 0), y = L.x(i, 1);
    psi[i] = std::sin(2 * kPi * x) * std::cos(2 * kPi * y) / (2 * kPi) + 0.1 * std::sin(4 * kPi * y) / (4 * kPi);
    u(i, 0) = -std::sin(2 * kPi * x) * std::sin(2 * kPi * y) + 0.1 * std::cos(4 * kPi * y);  // d psi/dy
    u(i, 1) = -std::cos(2 * kPi * x) * std::cos(2 * kPi * y);                                // -d psi/dx
  }
  Mat2 X, f;
  circle_markers(64, 0.25, 0.93, 0.5, X, f);
  const double ds = 2.0 * kPi * 0.25 / 64;
  const double measured[] = {3.397e-4, 2.920e-5, 2.738e-6};
  double last = 0, last_b = 0;
  for (int n = 0; n < 3; ++n) {
    const double hs = kHsOverDx[n];
    const CubicSplineKernel W_star(hs * L.dx);
    Mat2 F = Mat2::Zero(L.size(), 2), U(64, 2), Ub(64, 2);
    spread_force(grid, W_star, X, f, ds, F);
    const double lhs = L.volume * (F.array() * u.array()).sum();
    interpolate_curl(grid, W_star, psi, Eigen::Vector2d::Zero(), X, U);
    interpolate_curl_bspline(grid, L.dx, L.dy, psi, Eigen::Vector2d::Zero(), X, Ub);
    const double scale = ds * (f.array().abs() * U.array().abs()).sum();
    const double m = std::abs(lhs - ds * (f.array() * U.array()).sum()) / scale;
    const double mb = std::abs(lhs - ds * (f.array() * Ub.array()).sum()) / scale;
    EXPECT_LT(m, 1.1 * measured[n]) << hs;
    if (last > 0) {
      EXPECT_LT(m, last / 8) << hs;
      EXPECT_GT(mb, last_b) << hs;
      EXPECT_GT(mb, 10 * m) << hs;
    }
    last = m;
    last_b = mb;
  }
}

// Spreading conserves the total force up to the lattice kernel sums: sum_i F_i V =
// sum_k f_k ds S(X_k) exactly (round-off; measured 1e-16, tolerance 1e-13 relative), and
// S(X_k) - 1 is the lattice-sum error, so |sum_i F_i V - sum_k f_k ds| / |sum_k f_k ds| measured
// (circle r = 0.25 about (0.5, 0.47), nb = 64, periodic box nx = 32):
//   h*/dx = 1.2: 2.61e-5;  1.525: 2.69e-4;  2.0: 6.21e-6;  3.0: 3.33e-6.  Tolerance 1.5x measured.
TEST(Coupling, SpreadingConservesTotalForce) {
  const Lattice L = make_lattice(unit_box(true, true), 32, 32);
  const CellGrid grid = lattice_grid(L);
  Mat2 X, f;
  circle_markers(64, 0.25, 0.5, 0.47, X, f);
  const double ds = 2.0 * kPi * 0.25 / 64;
  const Eigen::Vector2d total_f = f.colwise().sum().transpose() * ds;
  struct Row { double hs_over_dx, err; };
  for (const Row& r : {Row{1.2, 2.61e-5}, Row{1.525, 2.69e-4}, Row{2.0, 6.21e-6}, Row{3.0, 3.33e-6}}) {
    const CubicSplineKernel W_star(r.hs_over_dx * L.dx);
    Mat2 F = Mat2::Zero(L.size(), 2);
    spread_force(grid, W_star, X, f, ds, F);
    const Eigen::Vector2d total_F = F.colwise().sum().transpose() * L.volume;
    Eigen::Vector2d with_sums = Eigen::Vector2d::Zero();
    for (int k = 0; k < X.rows(); ++k)
      with_sums += f.row(k).transpose() * ds * kernel_sum(L, W_star, X(k, 0), X(k, 1));
    EXPECT_LT((total_F - with_sums).norm(), 1e-13 * total_f.norm()) << r.hs_over_dx;
    EXPECT_LT((total_F - total_f).norm(), 1.5 * r.err * total_f.norm()) << r.hs_over_dx;
  }
}

// <S f, u>_V = sum_i V F_i . u_i equals sum_k ds f_k . (I u)_k for the UNnormalised
// interpolation with the same kernel (h* = h): the two are adjoint. Random u; periodic box and a
// channel. Measured relative difference 3e-16 .. 1.4e-14. Tolerance 1e-12 (round-off).
TEST(Coupling, UnnormalisedInterpolationIsAdjointOfSpreading) {
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (bool periodic_y : {true, false})
    for (double h_over_dx : {1.2, 1.525, 3.0}) {
      const Lattice L = make_lattice(unit_box(true, periodic_y), 32, 32);
      const CellGrid grid = lattice_grid(L);
      const CubicSplineKernel W(h_over_dx * L.dx);
      Mat2 X, f;
      circle_markers(64, 0.25, 0.93, 0.5, X, f);  // across the periodic seam x = 1
      const double ds = 2.0 * kPi * 0.25 / 64;
      Mat2 u(L.size(), 2);
      for (int i = 0; i < L.size(); ++i) { u(i, 0) = U(gen); u(i, 1) = U(gen); }
      Mat2 F = Mat2::Zero(L.size(), 2), Iu(X.rows(), 2);
      spread_force(grid, W, X, f, ds, F);
      interpolate_velocity(grid, W, L.volume, u, X, Iu, /*normalised=*/false);
      const double Sf_u = L.volume * (F.array() * u.array()).sum();
      const double f_Iu = ds * (f.array() * Iu.array()).sum();
      const double scale = L.volume * (F.array().abs() * u.array().abs()).sum();
      EXPECT_NEAR(Sf_u, f_Iu, 1e-12 * scale) << "h/dx " << h_over_dx << " periodic_y " << periodic_y;
    }
}

// Normalised interpolation (Eq. 63) of a constant field is exact anywhere: near and on the
// periodic seams and corners, and next to walls (where the kernel support is cut).
// Measured error 7.8e-16; tolerance 1e-14 (round-off). The unnormalised form is not exact
// (error = the lattice-sum error, measured up to 3.7e-3 at h/dx = 1.2), which the test checks
// too so that it could see a normalisation that does nothing.
TEST(Coupling, NormalisedInterpolationOfConstantIsExact) {
  for (bool periodic_y : {true, false}) {
    const Lattice L = make_lattice(unit_box(true, periodic_y), 16, 16);
    const CellGrid grid = lattice_grid(L);
    const CubicSplineKernel W(1.2 * L.dx);
    Mat2 u(L.size(), 2);
    u.col(0).setConstant(0.7);
    u.col(1).setConstant(-1.3);
    Mat2 X(9, 2);
    X << 0.0, 0.0,  1e-3, 0.999,  0.999, 0.5,  0.5, 1e-9,  0.33, 0.77,  1.0, 1.0,  0.9999999, 1e-7,
        1.02, 0.5,  -0.01, 0.31;  // the last two outside [0, 1) in x: wrapped by the grid
    Mat2 U(X.rows(), 2), U_raw(X.rows(), 2);
    interpolate_velocity(grid, W, L.volume, u, X, U, true);
    interpolate_velocity(grid, W, L.volume, u, X, U_raw, false);
    double worst_raw = 0;
    for (int k = 0; k < X.rows(); ++k) {
      EXPECT_NEAR(U(k, 0), 0.7, 1e-14) << "marker " << k << " periodic_y " << periodic_y;
      EXPECT_NEAR(U(k, 1), -1.3, 1e-14) << "marker " << k << " periodic_y " << periodic_y;
      worst_raw = std::max(worst_raw, std::abs(U_raw(k, 0) / 0.7 - 1.0));
    }
    EXPECT_GT(worst_raw, 1e-5);  // near a wall the cut support makes it O(1)
  }
}

namespace {

SimulationParams periodic_ib(int n, double dt) {
  SimulationParams sp;
  sp.fluid.domain = unit_box(true, true);
  sp.fluid.nx = sp.fluid.ny = n;
  sp.fluid.h_over_dx = 1.2;
  sp.fluid.rho = 1.0;
  sp.fluid.mu = 0.1;
  sp.fluid.dt = dt;
  sp.fluid.convection = true;
  return sp;
}

// A circle at its rest length as the discrete rest state: the spline's |X_s| at the knots of a
// circle sampled at s_k = k L0/nb is 1 - 5.2e-7 at nb = 64 (not 1), so T = -5.2e-6 T0 and the
// membrane relaxes by ~1e-7. Rescaling L0 by that |X_s| makes T vanish to round-off.
Membrane discrete_rest_circle(int nb, double r0, double cx, double cy, double T0) {
  Membrane m = make_membrane(circle(nb, cx, cy, r0), r0, T0);
  MembraneForce H(m);
  Mat2 f;
  Vec T;
  H.compute(m.X, f, T);
  m.ref.L0 *= 1.0 + T.mean() / T0;  // |X_s| scales as 1/L0
  return m;
}

}  // namespace

// A membrane (circle at rest length r0 = 0.2, nb = 64, T0 = 10, h* = 0.05) in a uniform flow
// (1, 0.5) in a periodic box (nx = 16, mu = 0.1, dt = 0.01, convection on), crossing the seam
// x = 1, translates with the flow. After 20 steps (t = 0.2), measured with the exact projection,
// SPH interpolation (Eq. 63) / divergence-free (the uniform flow is the stream function's mean):
//   centroid - (c0 + U t): 2.6e-10 / 2.1e-10;  max marker deviation from X0 + U t: 5.3e-9 / 2.7e-9;
//   rx - rx0: 1.6e-9 / 9.2e-10, ry - ry0: 3.0e-9 / 1.4e-9, area - area0: 8.3e-10 / 3.0e-14 (the
//   relaxation of the rest circle, see discrete_rest_circle; with the discrete rest state all of
//   these are < 1e-15). (The approximate projection with Eq. (63): 8.6e-10, 8.4e-8, 7.7e-8, 8.2e-8,
//   9.9e-8.)
// Tolerance 1.5x measured (the area of the divergence-free run: 1e-12, round-off).
TEST(Coupling, MembraneTranslatesWithUniformFlow) {
  struct Row { MarkerInterpolation interp; double centroid, markers, rx, ry, area; };
  for (const Row& r : {Row{MarkerInterpolation::Sph, 2.6e-10, 5.3e-9, 1.6e-9, 3.0e-9, 8.3e-10},
                       Row{MarkerInterpolation::DivergenceFree, 2.1e-10, 2.7e-9, 9.2e-10, 1.4e-9, 6.7e-13}}) {
    SimulationParams sp = periodic_ib(16, 0.01);
    sp.interpolation = r.interp;
    MembraneSetup ms;
    ms.membrane = make_membrane(circle(64, 0.75, 0.6, 0.2), 0.2, 10.0);
    ms.h_star = 0.05;
    sp.membranes.push_back(ms);
    Simulation sim(sp);
    const Eigen::Vector2d U0(1.0, 0.5);
    Mat2 u0(sim.fluid().size(), 2);
    u0.col(0).setConstant(U0.x());
    u0.col(1).setConstant(U0.y());
    sim.fluid().set_velocity(u0);
    MembraneDiagnostics D(64, ms.membrane.L0());
    const MembraneShape s0 = D.measure(ms.membrane.X);
    for (int s = 0; s < 20; ++s) sim.step();
    ASSERT_NEAR(sim.time(), 0.2, 1e-12);
    const Mat2& X = sim.membranes()[0].m.X;
    const MembraneShape s1 = D.measure(X);
    const Eigen::Vector2d moved = Eigen::Vector2d(s1.cx, s1.cy) - Eigen::Vector2d(s0.cx, s0.cy);
    Mat2 X_expected = ms.membrane.X;
    X_expected.col(0).array() += U0.x() * sim.time();
    X_expected.col(1).array() += U0.y() * sim.time();
    EXPECT_LT((moved - U0 * sim.time()).norm(), 1.5 * r.centroid);
    EXPECT_LT((X - X_expected).cwiseAbs().maxCoeff(), 1.5 * r.markers);
    EXPECT_LT(std::abs(s1.rx - s0.rx), 1.5 * r.rx);
    EXPECT_LT(std::abs(s1.ry - s0.ry), 1.5 * r.ry);
    EXPECT_LT(std::abs(s1.area - s0.area), 1.5 * r.area);
    EXPECT_GT(X.col(0).maxCoeff(), 1.0);  // it did cross the seam
  }
}

// coupling.interpolation = "spreading_kernel" in a run: a stretched ellipse (semi-axes 0.3, 0.2, rest
// radius 0.2, T0 = 10, 64 markers, h* = 2.4 dx) relaxes towards a circle in a periodic box (nx = 16,
// to t = 0.2). Its marker velocity is the curl of psi by the kernel of radius h* (the interpolation
// length the stiff-force filter is told is h*), divergence-free: the enclosed area changes only by
// the time integration of the markers, measured |area - area0| / area0 = 1.921e-5 at dt = 0.01 and
// 2.137e-6 at dt = 0.005 (a factor 9 on halving dt; divergence_free with the fluid's h: 2.974e-5).
// Tolerances 1.5x measured, and at least a factor 1/0.35 on halving dt. Free membranes with
// different h* are refused by name; a fixed membrane (no interpolation) may have its own.
TEST(SpreadingKernelCurl, RingKeepsItsAreaAndFreeMembranesShareOneRadius) {
  double change[3];
  for (int n = 0; n < 3; ++n) {  // spreading kernel at dt, at dt/2; divergence_free at dt
    const double dt = n == 1 ? 0.005 : 0.01;
    SimulationParams sp = periodic_ib(16, dt);
    sp.interpolation = n < 2 ? MarkerInterpolation::SpreadingKernel : MarkerInterpolation::DivergenceFree;
    MembraneSetup ms;
    ms.membrane = make_membrane(ellipse(64, 0.5, 0.5, 0.3, 0.2), 0.2, 10.0);
    ms.h_star = 2.4 / 16;
    sp.membranes.push_back(ms);
    Simulation sim(sp);
    if (n < 2) EXPECT_EQ(sim.interpolation_length(), ms.h_star);
    MembraneDiagnostics D(64, ms.membrane.L0());
    const double a0 = D.measure(sim.membranes()[0].m.X).area;
    while (sim.time() < 0.2 - 1e-9) sim.step();
    change[n] = std::abs(D.measure(sim.membranes()[0].m.X).area / a0 - 1.0);
    EXPECT_GT((sim.membranes()[0].m.X - ms.membrane.X).cwiseAbs().maxCoeff(), 1e-3);  // it did move
  }
  EXPECT_LT(change[0], 1.5 * 1.921e-5);
  EXPECT_LT(change[1], 0.35 * change[0]);  // second order in dt: the time integration's
  SimulationParams sp = periodic_ib(16, 0.01);
  sp.interpolation = MarkerInterpolation::SpreadingKernel;
  MembraneSetup a, b;
  a.membrane = make_membrane(circle(32, 0.3, 0.5, 0.1), 0.1, 1.0);
  b.membrane = make_membrane(circle(32, 0.7, 0.5, 0.1), 0.1, 1.0);
  a.h_star = 0.1;
  b.h_star = 0.12;
  sp.membranes = {a, b};
  try {
    Simulation sim(sp);
    ADD_FAILURE() << "two free membranes with different h* accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("h_star = 0.12"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("spreading_kernel"), std::string::npos) << e.what();
  }
  sp.membranes[1].fixed = true;
  EXPECT_NO_THROW(Simulation{sp});
}

// A membrane in its discrete rest state in a fluid at rest stays at rest: measured max |u| and
// max marker displacement after 20 steps (nx = 16, dt = 0.01, divergence-free markers): exact
// projection 5.0e-14 and 6.7e-16, approximate 7.9e-14 and 6.7e-16. Tolerances 1e-12 and 1e-14
// (round-off). The geometric rest circle (L0 = 2 pi r0 exactly) instead relaxes its spline tension
// -5.2e-6 T0: measured max |u| = 3.06e-7 / 2.13e-6, marker displacement 6.96e-9 / 6.96e-9
// (exact / approximate; tolerance 1.5x; with Eq. (63): 9.4e-7, 8.8e-8).
TEST(Coupling, MembraneAtRestStaysAtRest) {
  for (Projection pr : {Projection::Exact, Projection::Approximate})
    for (bool discrete : {true, false}) {
      const bool exact = pr == Projection::Exact;
      SimulationParams sp = periodic_ib(16, 0.01);
      sp.fluid.projection = pr;
      MembraneSetup ms;
      ms.membrane = discrete ? discrete_rest_circle(64, 0.2, 0.5, 0.5, 10.0) : make_membrane(circle(64, 0.5, 0.5, 0.2), 0.2, 10.0);
      ms.h_star = 0.05;
      sp.membranes.push_back(ms);
      Simulation sim(sp);
      for (int s = 0; s < 20; ++s) sim.step();
      const double u_max = sim.fluid().u().cwiseAbs().maxCoeff();
      const double dX = (sim.membranes()[0].m.X - ms.membrane.X).cwiseAbs().maxCoeff();
      if (discrete) {
        EXPECT_LT(u_max, 1e-12) << "exact " << exact;
        EXPECT_LT(dX, 1e-14) << "exact " << exact;
      } else {
        EXPECT_LT(u_max, 1.5 * (exact ? 3.06e-7 : 2.13e-6)) << "exact " << exact;
        EXPECT_LT(dX, 1.5 * 6.96e-9) << "exact " << exact;
      }
    }
}

// Fixed-membrane mode (Section 5.2.1): a stretched ellipse drives a flow but its markers do not
// move, bit for bit; the same membrane left free does move.
TEST(Coupling, FixedMembraneMarkersStayExactlyInPlace) {
  for (bool fixed : {true, false}) {
    SimulationParams sp = periodic_ib(16, 0.01);
    MembraneSetup ms;
    ms.membrane = make_membrane(ellipse(64, 0.5, 0.5, 0.28, 0.18), 0.2, 10.0);
    ms.h_star = 0.05;
    ms.fixed = fixed;
    sp.membranes.push_back(ms);
    Simulation sim(sp);
    for (int s = 0; s < 10; ++s) sim.step();
    const double dX = (sim.membranes()[0].m.X - ms.membrane.X).cwiseAbs().maxCoeff();
    EXPECT_GT(sim.fluid().u().cwiseAbs().maxCoeff(), 1e-3);
    if (fixed) EXPECT_EQ(dX, 0.0);
    else EXPECT_GT(dX, 1e-4);
  }
}

// With max_iter = 0 and eps = 0 the fixed-point iteration cannot converge: the IB step throws
// std::runtime_error naming the membrane, the step (the first) and the residual. The defaults converge.
TEST(Coupling, MarkerUpdateFailureThrowsNamingTheStep) {
  for (bool fail : {true, false}) {
    SimulationParams sp = periodic_ib(16, 0.01);
    MembraneSetup ms;
    ms.membrane = make_membrane(ellipse(64, 0.5, 0.5, 0.28, 0.18), 0.2, 10.0);
    ms.h_star = 0.05;
    sp.membranes.push_back(ms);
    if (fail) {
      sp.markers.max_iter = 0;
      sp.markers.eps = 0.0;
    }
    Simulation sim(sp);
    if (!fail) {
      EXPECT_NO_THROW(sim.step());
      EXPECT_LE(sim.membranes()[0].last.residual, sp.markers.eps);
      continue;
    }
    try {
      sim.step();
      ADD_FAILURE() << "the marker update did not throw";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("marker update"), std::string::npos) << what;
      EXPECT_NE(what.find("step 1"), std::string::npos) << what;
      EXPECT_NE(what.find("membrane 0"), std::string::npos) << what;
    }
  }
}

// The oscillation fit (observe/oscillation.cpp) on a synthetic rx(t): a release transient (rx(0)
// below the first maximum, as the membrane released from rest first overshoots), a damped ringing of period 1.53 whose swing shrinks by 0.2 per period, and
// a leak drift of -0.3% per unit time. Period and decay come from the ringing only: the drift and
// the transient, which used to shorten the period to ~1.44, do not bias them. The only error is
// the 0.01 sampling of the diagnostics (extrema at the sample times): tolerances 0.01 and 0.03.
TEST(Coupling, OscillationFitReadsTheRingingNotTheDrift) {
  Simulation sim(periodic_ib(8, 0.01));
  auto summary = [&](double drift) {
    Series s;
    s.columns = {"t", "m0_rx"};
    const double P = 1.53, lambda = -std::log(0.2) / P;
    for (int k = 0; k <= 1000; ++k) {
      const double t = 0.01 * k;
      const double ring = 0.14 * std::exp(-lambda * t) * std::cos(2 * M_PI * (t - 0.73) / P + M_PI);
      s.rows.push_back({t, 0.61 + ring - drift * 0.61 * t});
    }
    s.rows[0][1] = 0.60;  // below the transient's maximum
    nlohmann::json j;
    oscillation_fit()->summarize(sim, s, j);
    return j;
  };
  for (double drift : {0.0, 0.003}) {
    const nlohmann::json j = summary(drift);
    ASSERT_FALSE(j["period"].is_null()) << drift;
    EXPECT_NEAR(j["period"].get<double>(), 1.53, 0.01) << drift;
    EXPECT_NEAR(j["amplitude_decay"].get<double>(), 0.2, 0.03) << drift;
    std::printf("drift %g: period %.4f decay %.4f extrema %d\n", drift, j["period"].get<double>(),
                j["amplitude_decay"].get<double>(), j["extrema"].get<int>());
  }
}

// The coupling's floor (Simulation::coupling_floor_seconds) times its kernels on copies: a run that
// measures it mid-way continues bit for bit as one that does not (markers, fluid, forces); without
// membranes it is 0, with a free membrane positive (it times at least the spreading and interpolation).
TEST(Coupling, CouplingFloorLeavesTheStateAsItWas) {
  auto scene = [](bool membrane) {
    SimulationParams sp = periodic_ib(16, 0.01);
    if (membrane) {
      MembraneSetup ms;
      ms.membrane = make_membrane(ellipse(64, 0.5, 0.5, 0.28, 0.18), 0.2, 10.0);
      ms.h_star = 0.05;
      sp.membranes.push_back(ms);
    }
    return sp;
  };
  EXPECT_EQ(Simulation(scene(false)).coupling_floor_seconds(3), 0.0);
  Simulation a(scene(true)), b(scene(true));
  for (int s = 0; s < 5; ++s) {
    a.step();
    b.step();
  }
  EXPECT_GT(b.coupling_floor_seconds(3), 0.0);
  EXPECT_EQ((a.force() - b.force()).cwiseAbs().maxCoeff(), 0.0);  // the spreading went to a copy
  for (int s = 0; s < 5; ++s) {
    a.step();
    b.step();
  }
  EXPECT_EQ((a.membranes()[0].m.X - b.membranes()[0].m.X).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((a.membranes()[0].f - b.membranes()[0].f).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((a.fluid().u() - b.fluid().u()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((a.force() - b.force()).cwiseAbs().maxCoeff(), 0.0);
}
