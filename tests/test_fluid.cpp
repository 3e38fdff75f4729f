// fluid/: kernel (Eq. 19), SPH operators (Eqs. 27-34), wall images (Eq. 42), linear solvers and
// the EPSPH step (Eqs. 28-35). Every tolerance is a measured value (Release build, stated beside
// the test) with a margin; round-off checks say so.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fluid/common/exact.hpp"
#include "fluid/algebra/fft_poisson.hpp"
#include "fluid/common/kernel.hpp"
#include "fluid/algebra/linear_solver.hpp"
#include "fluid/algebra/products.hpp"
#include "fluid/eulerian/eulerian.hpp"

using namespace sphib;

namespace {

constexpr double kPi = 3.14159265358979323846;

double order(double e_coarse, double e_fine, double ratio = 2.0) {
  return std::log(e_coarse / e_fine) / std::log(ratio);
}

// Sums of the kernel over an infinite square lattice of spacing dx around the point
// (ox, oy) dx (offset in spacings): S = sum_j W V, the gradient moments
// m1 = sum_j V r_ij F_ij and M = -sum_j V r_ij r_ij^T F_ij (r_ij = x_i - x_j, j != i).
struct LatticeSums {
  double S = 0;
  Eigen::Vector2d m1 = Eigen::Vector2d::Zero();
  Eigen::Matrix2d M = Eigen::Matrix2d::Zero();
  double m1_scale = 0;  // sum_j V |r_ij| |F_ij|: the size of the terms that cancel in m1
};
LatticeSums lattice_sums(double h_over_dx, double dx, double ox = 0, double oy = 0) {
  const CubicSplineKernel W(h_over_dx * dx);
  const int R = static_cast<int>(std::ceil(2.0 * h_over_dx)) + 2;
  const double V = dx * dx;
  LatticeSums s;
  for (int b = -R; b <= R; ++b)
    for (int a = -R; a <= R; ++a) {
      const double rx = (ox - a) * dx, ry = (oy - b) * dx, r = std::hypot(rx, ry);
      s.S += W.W(r) * V;
      if (r == 0.0) continue;
      const double F = W.F(r);
      s.m1 += V * F * Eigen::Vector2d(rx, ry);
      s.m1_scale += V * std::abs(F) * r;
      s.M(0, 0) -= V * rx * rx * F;
      s.M(0, 1) -= V * rx * ry * F;
      s.M(1, 0) -= V * ry * rx * F;
      s.M(1, 1) -= V * ry * ry * F;
    }
  return s;
}

// The integer offsets (a, b) != 0 of a complete lattice within 2h, sorted.
std::vector<std::pair<int, int>> stencil(double h_over_dx) {
  std::vector<std::pair<int, int>> st;
  const int R = static_cast<int>(std::ceil(2.0 * h_over_dx)) + 1;
  for (int b = -R; b <= R; ++b)
    for (int a = -R; a <= R; ++a)
      if ((a || b) && std::hypot(a, b) < 2.0 * h_over_dx) st.emplace_back(a, b);
  std::sort(st.begin(), st.end());
  return st;
}

FluidParams make_params(int n, double h_over_dx, bool periodic_x, bool periodic_y) {
  FluidParams p;
  p.domain.periodic_x = periodic_x;
  p.domain.periodic_y = periodic_y;
  p.nx = p.ny = n;
  p.h_over_dx = h_over_dx;
  p.rho = 1.0;
  p.mu = 1.0;
  p.dt = 1e-3;
  return p;
}

// Particles farther than 2h from every wall (all of them along periodic axes).
bool interior(const EulerianFluid& f, int i) {
  const Domain& d = f.lattice().domain;
  const double x = f.lattice().x(i, 0), y = f.lattice().x(i, 1), r = 2.0 * f.h();
  const bool in_x = d.periodic_x || (x - d.x0 > r && d.x1 - x > r);
  const bool in_y = d.periodic_y || (y - d.y0 > r && d.y1 - y > r);
  return in_x && in_y;
}

double max_abs(const Mat2& a) { return a.cwiseAbs().maxCoeff(); }

double rms_error(const EulerianFluid& f, double (*exact_u)(double y, double t, const double* prm), const double* prm) {
  const Mat2& x = f.lattice().x;
  double e2 = 0;
  for (int i = 0; i < f.size(); ++i) {
    const double du = f.u()(i, 0) - exact_u(x(i, 1), f.time(), prm), dv = f.u()(i, 1);
    e2 += du * du + dv * dv;
  }
  return std::sqrt(e2 / f.size());
}

}  // namespace

// ======================================================================================
// Kernel: the cubic B-spline of Eq. (19)
// ======================================================================================

// Lattice sum sum_j W(x_i - x_j) dx dy. Measured |S - 1| at a lattice point / max over a
// 10 x 10 grid of offsets inside a cell (a marker anywhere), independent of dx at fixed h/dx:
//   h/dx = 1.2: 2.43e-4 / 3.72e-3;  1.525: 3.49e-3 / 3.94e-3;  2.2: 2.50e-4 / 2.50e-4;
//   3: 2.72e-5 / 2.72e-5.  Tolerance 1.5x the measured value.
TEST(Kernel, LatticeSumIsNearOne) {
  struct Row { double h_over_dx, at_point, anywhere; };
  const Row rows[] = {{1.2, 2.43e-4, 3.72e-3}, {1.525, 3.49e-3, 3.94e-3},
                      {2.2, 2.50e-4, 2.50e-4}, {3.0, 2.72e-5, 2.72e-5}};
  for (const Row& r : rows) {
    for (double dx : {1.0 / 16, 1.0 / 64}) {
      EXPECT_LT(std::abs(lattice_sums(r.h_over_dx, dx).S - 1.0), 1.5 * r.at_point) << r.h_over_dx;
      double worst = 0;
      for (int a = 0; a < 10; ++a)
        for (int b = 0; b < 10; ++b)
          worst = std::max(worst, std::abs(lattice_sums(r.h_over_dx, dx, 0.1 * a, 0.1 * b).S - 1.0));
      EXPECT_LT(worst, 1.5 * r.anywhere) << r.h_over_dx;
      EXPECT_GT(worst, 0.5 * r.anywhere) << "the lattice sum is not exact; a much smaller error means "
                                            "the kernel changed: " << r.h_over_dx;
    }
  }
}

// int W dA = int_0^2h 2 pi r W(r) dr: the integrand is a polynomial of degree 4 on [0, h] and on
// [h, 2h], so 5-point Gauss-Legendre per piece is exact. Measured: 2.2e-16. Tolerance 1e-10.
TEST(Kernel, ContinuousIntegralIsOne) {
  const double gx[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  const double gw[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                        0.2369268850561891};
  for (double h : {0.01, 0.7, 3.7}) {
    const CubicSplineKernel W(h);
    double I = 0;
    for (int piece = 0; piece < 2; ++piece)
      for (int q = 0; q < 5; ++q) {
        const double r = h * (piece + 0.5 + 0.5 * gx[q]);
        I += 0.5 * h * gw[q] * 2.0 * kPi * r * W.W(r);
      }
    EXPECT_NEAR(I, 1.0, 1e-10) << "h = " << h;
  }
}

// Zeroth moment of the gradient sum_j V r_ij F_ij = 0 on a full lattice (symmetry: round-off,
// measured < 4e-17 against terms of size ~1e2; tolerance 1e-14 relative to sum |terms|), and the
// second moment M = -sum_j V r r^T F ~ I. Measured M_xx - 1 = M_yy - 1:
//   h/dx = 1.2: -9.21e-3;  1.525: 3.03e-3;  2.2: -2.24e-4;  3: -1.47e-4  (independent of dx);
// M_xy round-off. Tolerance 1.5x measured.
TEST(Kernel, GradientMomentsOnFullLattice) {
  struct Row { double h_over_dx, m2_err; };
  const Row rows[] = {{1.2, 9.21e-3}, {1.525, 3.03e-3}, {2.2, 2.24e-4}, {3.0, 1.47e-4}};
  for (const Row& r : rows)
    for (double dx : {1.0 / 16, 1.0 / 100}) {
      const LatticeSums s = lattice_sums(r.h_over_dx, dx);
      EXPECT_LT(s.m1.norm(), 1e-14 * s.m1_scale) << r.h_over_dx;
      EXPECT_LT(std::abs(s.M(0, 0) - 1.0), 1.5 * r.m2_err) << r.h_over_dx;
      EXPECT_LT(std::abs(s.M(1, 1) - 1.0), 1.5 * r.m2_err) << r.h_over_dx;
      EXPECT_NEAR(s.M(0, 0), s.M(1, 1), 1e-13) << r.h_over_dx;  // square-lattice symmetry
      EXPECT_LT(std::abs(s.M(0, 1)), 1e-13) << r.h_over_dx;
    }
}

// F(r) = (1/r) dW/dr and dW/dr against central differences of W (step 1e-6 h). Measured max
// |FD - exact| / |F(0)|: 1.1e-9 (FD truncation and cancellation). Tolerance 1e-8. The r -> 0
// limit of F is -2 w0 / h^2.
TEST(Kernel, DerivativeMatchesFiniteDifferences) {
  for (double h : {0.05, 0.7}) {
    const CubicSplineKernel W(h);
    const double F0 = std::abs(W.F(0.0)), e = 1e-6 * h;
    EXPECT_NEAR(W.F(0.0), -2.0 * W.w0 / (h * h), 1e-12 * F0);
    EXPECT_NEAR(W.F(1e-9 * h), W.F(0.0), 1e-6 * F0);
    double worst = 0;
    for (int k = 1; k < 400; ++k) {
      const double r = k * 2.0 * h / 400;
      const double fd = (W.W(r + e) - W.W(r - e)) / (2.0 * e);
      worst = std::max(worst, std::abs(fd - W.dWdr(r)) / (F0 * h));
      worst = std::max(worst, std::abs(fd / r - W.F(r)) / F0);
      EXPECT_NEAR(W.F(r) * r, W.dWdr(r), 1e-12 * F0 * h);
    }
    EXPECT_LT(worst, 1e-8) << "h = " << h;
  }
}

// The two-lane forms the markers' loops use (W2, W_F2, W_F_G2: one square root, q = r (1/h), the
// constants folded, no branch) against the scalar W() and F(), over 0 <= r <= 2.2h (200001 points)
// in both lanes: measured max |W2 - W| / W(0) 3.1e-16 and |F2 - F| / |F(0)| 2.7e-16 (h = 0.05625,
// 0.7, 3.7, 1e-3); tolerance 1e-15. G = (1/r) dF/dr against central differences of F (step 1e-6 h,
// r >= 0.01 h, away from the kinks at h and 2h): measured 6.8e-9 of G(h) = 1.5 w0 / h^4; tolerance
// 1e-7. All three are exactly 0 from 2h (1 + 1e-12) on (at 2h (1 + 5e-16) q = r (1/h) may round
// below 2: W ~ 1e-50), and G is 0 at r = 0 (its term G x x^T vanishes there).
TEST(Kernel, TwoLaneFormsMatchTheScalarOnes) {
  for (double h : {0.05625, 0.7, 3.7, 1e-3}) {
    const CubicSplineKernel W(h);
    const double W0 = W.W(0.0), F0 = std::abs(W.F(0.0)), G1 = 1.5 * W.w0 / (h * h * h * h), e = 1e-6 * h;
    double ew = 0, ef = 0, eg = 0;
    for (int k = 0; k <= 200000; k += 2) {
      const double r0 = k * 2.2 * h / 200000, r1 = (k + 1) * 2.2 * h / 200000;
      Lanes2 w, f, g;
      W.W_F_G2(Lanes2{r0 * r0, r1 * r1}, w, f, g);
      const Lanes2 w2 = W.W2(Lanes2{r0 * r0, r1 * r1});
      for (int l = 0; l < 2; ++l) {
        const double r = l ? r1 : r0;
        ew = std::max({ew, std::abs(w[l] - W.W(r)) / W0, std::abs(w2[l] - W.W(r)) / W0});
        ef = std::max(ef, std::abs(f[l] - W.F(r)) / F0);
        if (r > 0.01 * h && std::abs(r - h) > 2 * e && r < 2 * h - 2 * e)
          eg = std::max(eg, std::abs((W.F(r + e) - W.F(r - e)) / (2 * e) / r - g[l]) / G1);
      }
    }
    EXPECT_LT(ew, 1e-15) << h;
    EXPECT_LT(ef, 1e-15) << h;
    EXPECT_LT(eg, 1e-7) << h;
    for (double r2 : {0.0, 4 * h * h * (1 + 1e-12), 9 * h * h, 16 * h * h}) {
      Lanes2 w, f, g;
      W.W_F_G2(lanes2(r2), w, f, g);
      if (r2 == 0.0) {
        EXPECT_EQ(g[0], 0.0);
        continue;
      }
      EXPECT_EQ(w[0], 0.0) << r2;
      EXPECT_EQ(f[0], 0.0) << r2;
      EXPECT_EQ(g[0], 0.0) << r2;
    }
  }
}

// W >= 0 everywhere, W, dW/dr and F are zero at and beyond 2h, and W is continuous there.
TEST(Kernel, NonNegativeWithCompactSupport) {
  const CubicSplineKernel W(0.3);
  EXPECT_DOUBLE_EQ(W.support(), 0.6);
  EXPECT_DOUBLE_EQ(W.W(0.0), W.w0 * 2.0 / 3.0);
  for (int k = 0; k <= 3000; ++k) {
    const double r = k * 0.9 / 3000;  // [0, 3h]
    EXPECT_GE(W.W(r), 0.0) << r;
    EXPECT_LE(W.dWdr(r), 0.0) << r;  // monotone decreasing
    if (r >= 0.6) {
      EXPECT_EQ(W.W(r), 0.0) << r;
      EXPECT_EQ(W.dWdr(r), 0.0) << r;
      EXPECT_EQ(W.F(r), 0.0) << r;
    }
  }
  EXPECT_LT(W.W(0.6 * (1 - 1e-6)), 1e-15 * W.w0);  // (2 - q)^3 / 6 -> 0: continuous at 2h
  EXPECT_GT(W.W(0.6 * (1 - 1e-3)), 0.0);
}

// ======================================================================================
// Operators (Eqs. 27-34) and wall images (Section 3.3)
// ======================================================================================

// Morris Laplacian of y^2 and x^2 (= 2) at particles farther than 2h from the walls of a closed
// box, for lap_phi and lap_u.A (no images reach the interior, so A alone is the operator there).
// On a complete lattice lap(x_a^2)_i = 2 M_aa exactly (the linear part cancels by the zeroth
// moment), so the error is 2 |M - 1|, a lattice-sum error that does NOT shrink with dx at fixed
// h/dx. Measured max |lap - 2|: 1.841e-2 (h/dx = 1.2), 2.941e-4 (h/dx = 3), the same at nx = 16
// and 32. Tolerance 1.5x measured; |lap - 2 M| to round-off (measured < 1e-12; tolerance 1e-10).
TEST(Operators, LaplacianOfQuadraticsInInterior) {
  struct Row { double h_over_dx, err; };
  for (const Row& r : {Row{1.2, 1.841e-2}, Row{3.0, 2.941e-4}}) {
    const EulerianFluid f(make_params(16, r.h_over_dx, false, false));
    const Operators& op = f.operators();
    const Vec x = f.lattice().x.col(0), y = f.lattice().x.col(1);
    const Vec x2 = x.array().square(), y2 = y.array().square();
    const Vec lap[4] = {op.lap_phi * y2, op.lap_phi * x2, op.lap_u.A * y2, op.lap_u.A * x2};
    const double M = lattice_sums(r.h_over_dx, f.lattice().dx).M(0, 0);
    int count = 0;
    for (int i = 0; i < f.size(); ++i) {
      if (!interior(f, i)) continue;
      ++count;
      for (const Vec& l : lap) {
        EXPECT_LT(std::abs(l[i] - 2.0), 1.5 * r.err) << "h/dx " << r.h_over_dx << " particle " << i;
        EXPECT_NEAR(l[i], 2.0 * M, 1e-10) << "h/dx " << r.h_over_dx << " particle " << i;
      }
    }
    EXPECT_GE(count, 16);
  }
}

// The lattice stencil of the fused products (fluid/algebra/products.hpp): the rows it applies as a stencil
// give the same bits as the row-by-row products, and those equal Eigen's products to round-off
// (measured: identical, relative difference 0 in all four cases; tolerance 1e-15 relative).
// Coverage: the interior rows and, in classes, the rows along walls (contiguous blocks) and along
// periodic seams (blocks strided by nx) are stencil rows; only the corners are not (measured 4080
// of 4096 at 64 x 64, h/dx = 1.2, periodic x: 3600 interior rows, 240 wall rows, 240 seam rows).
TEST(Operators, StencilProductsEqualRowByRowProducts) {
  struct Case { int n; double h_over_dx; bool px, py; int min_stencil_rows; };
  for (const Case& c : {Case{64, 1.2, true, false, 4080}, Case{32, 2.25, false, false, 1}, Case{24, 1.2, true, true, 1},
                        Case{16, 3.0, false, false, 0}}) {
    const EulerianFluid f(make_params(c.n, c.h_over_dx, c.px, c.py));
    const Operators& op = f.operators();
    const RowStencil vs = find_row_stencil({&op.lap_u.A, &op.grad_ux.A, &op.grad_uy.A});
    const RowStencil ps = find_row_stencil({&op.grad_phix, &op.grad_phiy});
    EXPECT_GE(vs.stencil_rows(), c.min_stencil_rows) << c.n;
    EXPECT_EQ(vs.stencil_rows() + static_cast<int>(vs.rest.size()), f.size());
    if (c.n == 64) {  // the seam rows come in blocks strided by nx, the wall rows in contiguous ones
      int strided = 0;
      for (const RowStencil::Block& b : vs.blocks) strided += b.stride == c.n ? b.count : 0;
      EXPECT_EQ(strided, 240);
    }
    const int N = f.size();
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> U(-1, 1);
    Mat2 u(N, 2);
    Vec phi(N);
    for (int i = 0; i < N; ++i) { u(i, 0) = U(gen); u(i, 1) = U(gen); phi[i] = U(gen); }
    Mat2 a(N, 2), b(N, 2), a2(N, 2), b2(N, 2);
    Vec d(N), d2(N);
    apply2(op.lap_u.A, u, a, &vs);
    apply2(op.lap_u.A, u, a2);
    EXPECT_TRUE(a == a2) << "apply2, n " << c.n;
    EXPECT_LT((a - op.lap_u.A * u).norm(), 1e-15 * (op.lap_u.A * u).norm());
    gradient2(op.grad_ux.A, op.grad_uy.A, u, a, b, &vs);
    gradient2(op.grad_ux.A, op.grad_uy.A, u, a2, b2);
    EXPECT_TRUE(a == a2 && b == b2) << "gradient2, n " << c.n;
    EXPECT_LT((b - op.grad_uy.A * u).norm(), 1e-15 * (op.grad_uy.A * u).norm());
    divergence(op.grad_ux.A, op.grad_uy.A, u, d, &vs);
    divergence(op.grad_ux.A, op.grad_uy.A, u, d2);
    EXPECT_TRUE(d == d2) << "divergence, n " << c.n;
    gradient(op.grad_phix, op.grad_phiy, phi, a, &ps);
    gradient(op.grad_phix, op.grad_phiy, phi, a2);
    EXPECT_TRUE(a == a2) << "gradient, n " << c.n;
    EXPECT_LT((a.col(0) - op.grad_phix * phi).norm(), 1e-15 * (op.grad_phix * phi).norm());
  }
}

// Gradient (Eq. 27, "sum" form (f_i + f_j)) of f = 2x + 3y in the interior of a closed box:
// on a complete lattice grad f = (2 M_xx, 3 M_yy) exactly. Measured max error over both
// components: 2.762e-2 (h/dx = 1.2), 4.412e-4 (h/dx = 3), independent of nx (16, 32).
// Tolerance 1.5x measured; against (2M, 3M) round-off (tolerance 1e-10).
TEST(Operators, GradientOfLinearFieldInInterior) {
  struct Row { double h_over_dx, err; };
  for (const Row& r : {Row{1.2, 2.762e-2}, Row{3.0, 4.412e-4}}) {
    const EulerianFluid f(make_params(16, r.h_over_dx, false, false));
    const Operators& op = f.operators();
    const Vec lin = 2.0 * f.lattice().x.col(0) + 3.0 * f.lattice().x.col(1);
    const Vec g[4] = {op.grad_phix * lin, op.grad_phiy * lin, op.grad_ux.A * lin, op.grad_uy.A * lin};
    const double M = lattice_sums(r.h_over_dx, f.lattice().dx).M(0, 0);
    for (int i = 0; i < f.size(); ++i) {
      if (!interior(f, i)) continue;
      for (int c = 0; c < 4; ++c) {
        const double exact = (c % 2 == 0) ? 2.0 : 3.0;
        EXPECT_LT(std::abs(g[c][i] - exact), 1.5 * r.err) << "h/dx " << r.h_over_dx << " particle " << i;
        EXPECT_NEAR(g[c][i], exact * M, 1e-10) << "h/dx " << r.h_over_dx << " particle " << i;
      }
    }
  }
}

// With walls (Neumann images phi' = phi, Eq. 9) the scalar Laplacian annihilates constants (zero
// row sums) and is symmetric. Measured max |row sum| / max |diagonal| = 3e-16, asymmetry exactly
// 0. Tolerance 1e-14 (round-off).
TEST(Operators, ScalarLaplacianWithWallsHasZeroRowSumsAndIsSymmetric) {
  for (bool periodic_x : {false, true})
    for (double hr : {1.2, 1.525, 3.0}) {
      const EulerianFluid f(make_params(16, hr, periodic_x, false));
      const SpMat& L = f.operators().lap_phi;
      const double scale = L.diagonal().cwiseAbs().maxCoeff();
      EXPECT_LT((L * Vec::Ones(f.size())).cwiseAbs().maxCoeff(), 1e-14 * scale) << hr;
      const SpMat Lt = L.transpose();
      EXPECT_LE((L - Lt).norm(), 1e-14 * L.norm()) << hr;
      EXPECT_GT(f.images().size(), 0);
    }
}

// The velocity Laplacian with no-slip images (odd reflection, Eq. 42) is symmetric and negative
// definite; the Crank-Nicolson matrix I - (nu dt / 2) lap_u.A is SPD. Its largest eigenvalue
// approximates the first Dirichlet eigenvalue: -2 pi^2 = -19.74 in the closed unit box (measured
// -19.39 at h/dx = 1.2, -18.69 at 3, nx = 16), -pi^2 = -9.87 in the channel periodic in x
// (measured below). Tolerance: within 8% of the continuous value.
TEST(Operators, VelocityLaplacianIsSymmetricNegativeDefinite) {
  for (bool periodic_x : {false, true})
    for (double hr : {1.2, 3.0}) {
      const EulerianFluid f(make_params(16, hr, periodic_x, false));
      const SpMat& A = f.operators().lap_u.A;
      const SpMat At = A.transpose();
      EXPECT_LE((A - At).norm(), 1e-14 * A.norm());
      const Eigen::MatrixXd D(A);
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(D);
      const double lmax = es.eigenvalues().maxCoeff();
      const double lambda1 = periodic_x ? -kPi * kPi : -2.0 * kPi * kPi;
      EXPECT_LT(lmax, 0.0);
      EXPECT_NEAR(lmax, lambda1, 0.08 * std::abs(lambda1)) << "h/dx " << hr << " periodic_x " << periodic_x;
      const double a = 0.5 * 10.0 * 0.1;  // a big nu dt / 2
      const Eigen::MatrixXd cn = Eigen::MatrixXd::Identity(f.size(), f.size()) - a * D;
      Eigen::LLT<Eigen::MatrixXd> llt(cn);
      EXPECT_EQ(llt.info(), Eigen::Success);
    }
}

// Images complete every kernel support: in a box with walls on all four sides (corners
// included) and in a channel, every particle's neighbours within 2h, as lattice offsets, are
// exactly the full-lattice stencil (20 neighbours at h/dx = 1.2, 28 at 1.525, 60 at 2.2, 108 at 3).
TEST(Operators, ImagesCompleteEveryNeighbourhood) {
  for (bool periodic_x : {false, true})
    for (double hr : {1.2, 1.525, 2.2, 3.0}) {
      const EulerianFluid f(make_params(16, hr, periodic_x, false));
      const PairList& P = f.pairs();
      const double dx = f.lattice().dx, dy = f.lattice().dy;
      const auto st = stencil(hr);
      for (int i = 0; i < f.size(); ++i) {
        std::vector<std::pair<int, int>> got;
        for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
          const double a = -P.rx[k] / dx, b = -P.ry[k] / dy;  // x_j - x_i in spacings
          ASSERT_NEAR(a, std::round(a), 1e-9);
          ASSERT_NEAR(b, std::round(b), 1e-9);
          got.emplace_back(static_cast<int>(std::lround(a)), static_cast<int>(std::lround(b)));
        }
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, st) << "h/dx " << hr << " periodic_x " << periodic_x << " particle " << i << " at ("
                           << f.lattice().x(i, 0) << ", " << f.lattice().x(i, 1) << ")";
      }
    }
}

// Single images are mirror reflections across their wall (velocity sign -1); corner images
// (images of images) are point reflections through the corner (sign +1), and equal the mirror of
// each single image across the other wall.
TEST(Operators, CornerImagesArePointReflections) {
  const EulerianFluid f(make_params(16, 1.525, false, false));
  const Images& im = f.images();
  const Domain& d = f.lattice().domain;
  const Mat2& x = f.lattice().x;
  int corners = 0;
  for (int k = 0; k < im.size(); ++k) {
    const int p = im.parent[k];
    const double px = x(p, 0), py = x(p, 1);
    const double wx = (px - d.x0 < d.x1 - px) ? d.x0 : d.x1;  // nearest vertical wall
    const double wy = (py - d.y0 < d.y1 - py) ? d.y0 : d.y1;
    if (im.wall[k] < 0) {
      ++corners;
      EXPECT_EQ(im.v_sign[k], 1.0);
      EXPECT_EQ(im.s_sign[k], 1.0);
      EXPECT_NEAR(im.x(k, 0), 2.0 * wx - px, 1e-14);
      EXPECT_NEAR(im.x(k, 1), 2.0 * wy - py, 1e-14);
      // image of the image: the single images of p, reflected across the other wall
      int singles = 0;
      for (int m = 0; m < im.size(); ++m) {
        if (im.parent[m] != p || im.wall[m] < 0) continue;
        ++singles;
        const bool vertical = im.wall[m] == Left || im.wall[m] == Right;
        const double rx = vertical ? im.x(m, 0) : 2.0 * wx - im.x(m, 0);
        const double ry = vertical ? 2.0 * wy - im.x(m, 1) : im.x(m, 1);
        EXPECT_NEAR(rx, im.x(k, 0), 1e-14);
        EXPECT_NEAR(ry, im.x(k, 1), 1e-14);
      }
      EXPECT_EQ(singles, 2) << "particle " << p;
    } else {
      EXPECT_EQ(im.v_sign[k], -1.0);
      EXPECT_EQ(im.s_sign[k], 1.0);
      const Side s = static_cast<Side>(im.wall[k]);
      const double w = s == Left ? d.x0 : s == Right ? d.x1 : s == Bottom ? d.y0 : d.y1;
      if (s == Left || s == Right) {
        EXPECT_NEAR(im.x(k, 0), 2.0 * w - px, 1e-14);
        EXPECT_EQ(im.x(k, 1), py);
      } else {
        EXPECT_EQ(im.x(k, 0), px);
        EXPECT_NEAR(im.x(k, 1), 2.0 * w - py, 1e-14);
      }
    }
  }
  // h/dx = 1.525: 2h = 3.05 dx, so 3 rows of particles near each wall and 3 x 3 per corner.
  EXPECT_EQ(corners, 4 * 9);
}

TEST(Operators, BoxNarrowerThanFourHIsRefused) {
  // One image layer per wall is complete only if no particle is within 2h of two opposite walls:
  // a walled extent below 4h is refused with a message naming the limit.
  try {
    const EulerianFluid f(make_params(6, 2.2, false, false));
    FAIL() << "a 6 x 6 box with h/dx = 2.2 (extent < 4h) was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("4h"), std::string::npos) << e.what();
  }
}

// ======================================================================================
// Solver: CHOLMOD and UMFPACK behind LinearSolver
// ======================================================================================

namespace {

// 2-D five-point Laplacian on an m x m grid plus a shift: SPD. With c != 0, an upwinded
// convection term makes it non-symmetric (still non-singular, diagonally dominant).
SpMat model_matrix(int m, double shift, double c) {
  std::vector<Triplet> t;
  auto id = [m](int i, int j) { return i + m * j; };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      t.emplace_back(id(i, j), id(i, j), 4.0 + shift + c);
      if (i > 0) t.emplace_back(id(i, j), id(i - 1, j), -1.0 - c);
      if (i < m - 1) t.emplace_back(id(i, j), id(i + 1, j), -1.0);
      if (j > 0) t.emplace_back(id(i, j), id(i, j - 1), -1.0);
      if (j < m - 1) t.emplace_back(id(i, j), id(i, j + 1), -1.0);
    }
  SpMat A(m * m, m * m);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

double rel_residual(const SpMat& A, const Eigen::MatrixXd& X, const Eigen::MatrixXd& B) {
  return (A * X - B).norm() / B.norm();
}

}  // namespace

// Every kind solves an SPD system. Measured relative residuals 3e-16 .. 6e-16 (direct),
// < 1e-14 (Jacobi-PCG, its stopping rule). Tolerance 1e-12.
TEST(Solver, SolvesSpdSystemWithEveryKind) {
  const SpMat A = model_matrix(15, 0.1, 0.0);
  ASSERT_TRUE(is_symmetric(A));
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), 1);
  struct K { SolverKind kind; const char* method; };
  for (const K& k : {K{SolverKind::Auto, "CHOLMOD"}, K{SolverKind::CholmodSupernodal, "CHOLMOD supernodal"},
                     K{SolverKind::CholmodSimplicial, "CHOLMOD simplicial"}, K{SolverKind::Umfpack, "UMFPACK"},
                     K{SolverKind::Pcg, "Jacobi-PCG"}}) {
    auto s = factorize("SPD test", A, k.kind);
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(A.rows(), 1);  // the initial guess of an iterative solver
    s->solve(B.data(), X.data(), 1);
    EXPECT_LT(rel_residual(A, X, B), 1e-12) << s->info().method;
    EXPECT_EQ(s->info().method.rfind(k.method, 0), 0u) << s->info().method;
    EXPECT_EQ(s->info().system, "SPD test");
    EXPECT_EQ(s->info().n, A.rows());
    EXPECT_EQ(s->info().nnz_A, A.nonZeros());
  }
}

// Auto sends a non-symmetric matrix to UMFPACK. Measured relative residual 4e-16. Tolerance 1e-12.
TEST(Solver, AutoPicksUmfpackForNonSymmetricSystem) {
  const SpMat A = model_matrix(15, 0.0, 0.7);
  ASSERT_FALSE(is_symmetric(A));
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), 1);
  for (SolverKind kind : {SolverKind::Auto, SolverKind::Umfpack}) {
    auto s = factorize("non-symmetric test", A, kind);
    EXPECT_EQ(s->info().method, "UMFPACK LU");
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(A.rows(), 1);
    s->solve(B.data(), X.data(), 1);
    EXPECT_LT(rel_residual(A, X, B), 1e-12);
  }
}

// A symmetric matrix that is not positive definite (diag(2, 2, -1, 2, 2), and [[1, 2], [2, 1]])
// given to CHOLMOD (supernodal LL', or Auto, whose simplicial factorisation is LL' too)
// throws std::runtime_error naming the system.
TEST(Solver, CholmodRejectsIndefiniteMatrix) {
  SpMat D(5, 5);
  for (int i = 0; i < 5; ++i) D.insert(i, i) = (i == 2) ? -1.0 : 2.0;
  SpMat A(2, 2);
  A.insert(0, 0) = 1; A.insert(0, 1) = 2; A.insert(1, 0) = 2; A.insert(1, 1) = 1;
  for (SolverKind kind : {SolverKind::CholmodSupernodal, SolverKind::Auto})
    for (const SpMat* M : {&D, &A}) {
      try {
        factorize("Indefinite test system", *M, kind);
        ADD_FAILURE() << "no exception for an indefinite matrix";
      } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("Indefinite test system"), std::string::npos) << what;
        EXPECT_NE(what.find("not positive definite"), std::string::npos) << what;
      }
    }
}

// A singular matrix: CHOLMOD (every kind) and UMFPACK throw, naming the system.
TEST(Solver, SingularMatrixThrowsNamingTheSystem) {
  SpMat S(3, 3);
  S.insert(0, 0) = 1; S.insert(0, 1) = 1; S.insert(1, 0) = 1; S.insert(1, 1) = 1; S.insert(2, 2) = 1;
  for (SolverKind kind : {SolverKind::Auto, SolverKind::CholmodSimplicial, SolverKind::CholmodSupernodal,
                          SolverKind::Umfpack}) {
    try {
      factorize("Singular test system", S, kind);
      ADD_FAILURE() << "no exception for a singular matrix";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("Singular test system"), std::string::npos) << e.what();
    }
  }
}

// Simplicial CHOLMOD is asked for LL' (Common.final_ll), so an indefinite matrix fails as the
// supernodal one does, instead of passing as LDL'.
TEST(Solver, CholmodSimplicialRejectsIndefiniteMatrix) {
  SpMat D(5, 5);
  for (int i = 0; i < 5; ++i) D.insert(i, i) = (i == 2) ? -1.0 : 2.0;
  EXPECT_THROW(factorize("Indefinite test system", D, SolverKind::CholmodSimplicial), std::runtime_error);
  SpMat N(3, 3);
  for (int i = 0; i < 3; ++i) N.insert(i, i) = -1.0;
  EXPECT_THROW(factorize("Negative definite test system", N, SolverKind::CholmodSimplicial), std::runtime_error);
}

// solve(B, X, 2) equals two single solves. Measured max difference: 1.7e-16 (supernodal, the
// multi-column triangular solve rounds differently), 0 otherwise. Tolerance 1e-14 relative.
TEST(Solver, TwoRightHandSidesEqualTwoSolves) {
  const SpMat A = model_matrix(15, 0.1, 0.0);
  const int n = static_cast<int>(A.rows());
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, 2);
  for (SolverKind kind : {SolverKind::Auto, SolverKind::CholmodSupernodal, SolverKind::CholmodSimplicial,
                          SolverKind::Umfpack, SolverKind::Pcg}) {
    auto s = factorize("two rhs", A, kind);
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, 2);
    s->solve(B.data(), X.data(), 2);
    for (int c = 0; c < 2; ++c) {
      const Vec b = B.col(c);
      Vec x = Vec::Zero(n);
      s->solve(b.data(), x.data(), 1);
      EXPECT_LT((X.col(c) - x).cwiseAbs().maxCoeff(), 1e-14 * x.cwiseAbs().maxCoeff()) << s->info().method;
    }
    EXPECT_LT(rel_residual(A, X, B), 1e-12) << s->info().method;
  }
}

// The periodic-lattice Poisson solver (fluid/algebra/fft_poisson.hpp) on -lap phi of a channel (periodic x,
// walls in y): for random right-hand sides of zero mean it leaves a residual at round-off and
// agrees with CHOLMOD on the pinned system up to the constant. Measured: residual 5.7e-16 .. 1.6e-15,
// difference 7e-15 .. 5.5e-14 of max |phi| (16 x 16, 24 x 20; h/dx 1.2, 2.25). Tolerances 1e-12, 1e-11.
TEST(Solver, FftSolverMatchesCholmodOnChannels) {
  struct Case { int nx, ny; double h_over_dx; };
  for (const Case& c : {Case{16, 16, 1.2}, Case{24, 20, 2.25}}) {
    FluidParams p = make_params(c.nx, c.h_over_dx, true, false);
    p.ny = c.ny;
    const EulerianFluid f(p);
    const SpMat A = -f.operators().lap_phi;
    std::string why;
    auto fft = make_fft_solver("Poisson", A, f.lattice(), Field::Scalar, true, &why);
    ASSERT_TRUE(fft) << why;
    const int n = f.size(), pin = 0;
    SpMat Ap = A;  // the pinned system the CHOLMOD path solves
    for (int i = 0; i < n; ++i)
      for (SpMat::InnerIterator it(Ap, i); it; ++it)
        if (i == pin || it.col() == pin) it.valueRef() = (i == it.col()) ? 1.0 : 0.0;
    auto chol = factorize("Poisson", Ap);
    std::mt19937 gen(3);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int r = 0; r < 3; ++r) {
      Vec b(n);
      for (int i = 0; i < n; ++i) b[i] = U(gen);
      b.array() -= b.mean();
      Vec x = Vec::Zero(n), y = Vec::Zero(n);
      fft->solve(b.data(), x.data(), 1);
      EXPECT_LT((A * x - b).norm(), 1e-12 * b.norm()) << c.nx;
      Vec bp = b;
      bp[pin] = 0.0;
      chol->solve(bp.data(), y.data(), 1);
      x.array() -= x.mean();
      y.array() -= y.mean();
      EXPECT_LT((x - y).cwiseAbs().maxCoeff(), 1e-11 * y.cwiseAbs().maxCoeff()) << c.nx;
    }
  }
}

// The same solver on a definite system, the Crank-Nicolson matrix I - (nu dt/2) lap_u with its
// velocity images (Eq. 28), two columns at once: equal to CHOLMOD's solution to round-off.
// Measured: max difference 1.2e-15 and 2.2e-15 of max |x| (16 x 16, a = 0.5; 24 x 20, a = 5). Tolerance 1e-12.
TEST(Solver, FftSolverSolvesCrankNicolsonLikeCholmod) {
  struct Case { int nx, ny; double a; };
  for (const Case& c : {Case{16, 16, 0.5}, Case{24, 20, 5.0}}) {
    FluidParams p = make_params(c.nx, 1.2, true, false);
    p.ny = c.ny;
    const EulerianFluid f(p);
    SpMat I(f.size(), f.size());
    I.setIdentity();
    const SpMat A = I - (c.a * f.lattice().dx * f.lattice().dx) * f.operators().lap_u.A;
    std::string why;
    auto fft = make_fft_solver("Crank-Nicolson", A, f.lattice(), Field::VelocityNormal, false, &why);
    ASSERT_TRUE(fft) << why;
    auto chol = factorize("Crank-Nicolson", A, SolverKind::CholmodSimplicial);
    const Eigen::MatrixXd B = Eigen::MatrixXd::Random(f.size(), 2);
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(f.size(), 2), Y = X;
    fft->solve(B.data(), X.data(), 2);
    chol->solve(B.data(), Y.data(), 2);
    EXPECT_LT((X - Y).cwiseAbs().maxCoeff(), 1e-12 * Y.cwiseAbs().maxCoeff()) << c.nx;
  }
}

// ======================================================================================
// Fluid: the PMIII step (Eqs. 28-35)
// ======================================================================================

// One step from a random (divergent) velocity: the Poisson system is solved to round-off
// (measured residual 8e-16; tolerance 1e-10) and the divergence drops, but only by a modest
// factor: the Poisson operator is the Morris Laplacian, not div(grad), and the two disagree
// most on the grid-scale content of a random field. Measured max|div u^1| / max|div u^0| =
// 0.579 (channel), 0.574 (periodic box), nx = 16, h/dx = 1.2. Tolerance 1.15x measured.
// (The exact projection takes it to round-off: tests/test_projection.cpp.)
TEST(Fluid, ProjectionOfRandomFieldReducesDivergence) {
  struct Row { bool periodic_y; double ratio; };
  for (const Row& r : {Row{false, 0.579}, Row{true, 0.574}}) {
    FluidParams p = make_params(16, 1.2, true, r.periodic_y);
    p.projection = Projection::Approximate;
    p.mu = 1e-3;
    p.convection = false;
    EulerianFluid f(p);
    const int N = f.size();
    std::mt19937 gen(42);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    Mat2 u0(N, 2);
    for (int i = 0; i < N; ++i) { u0(i, 0) = U(gen); u0(i, 1) = U(gen); }
    f.set_velocity(u0);
    const double d0 = f.max_abs_divergence();
    f.step(Mat2::Zero(N, 2));
    EXPECT_LT(f.poisson_residual(), 1e-10);
    EXPECT_LT(f.max_abs_divergence(), 1.15 * r.ratio * d0) << "periodic_y " << r.periodic_y;
  }
}

// Convergence of the approximate projection on a smooth divergent field in a periodic box
// (u = sin 2pi x + cos(2pi(x + y))/2, v = sin 2pi y cos 2pi x), h/dx = 1.525, one step.
// Measured max|div u^1|: 1.480 (nx = 16), 0.3891 (32): order 1.93 (then 0.0701, 0.0134 at
// 64, 128: orders 2.47, 2.38); ratio to max|div u^0| 0.120, 0.0292. At h/dx = 1.2 the
// residual saturates at the lattice moment error (1.07, 0.381, 0.189, 0.141 for nx = 16..128).
// With walls the first particle row keeps an O(1) divergence (0.94, 0.99, 1.01 at nx = 16, 32,
// 64, channel, h/dx = 1.2): the tangential slip of the first projection step seen through the
// odd velocity images, so this test uses the periodic box.
// Tolerance: order > 1.7; ratio at nx = 32 below 1.5x measured.
TEST(Fluid, ProjectionDivergenceDecreasesUnderRefinement) {
  double div1[2], ratio[2];
  for (int c = 0; c < 2; ++c) {
    FluidParams p = make_params(16 << c, 1.525, true, true);
    p.projection = Projection::Approximate;
    p.mu = 1e-3;
    p.convection = false;
    EulerianFluid f(p);
    const int N = f.size();
    const Mat2& x = f.lattice().x;
    Mat2 u0(N, 2);
    for (int i = 0; i < N; ++i) {
      u0(i, 0) = std::sin(2 * kPi * x(i, 0)) + 0.5 * std::cos(2 * kPi * (x(i, 0) + x(i, 1)));
      u0(i, 1) = std::sin(2 * kPi * x(i, 1)) * std::cos(2 * kPi * x(i, 0));
    }
    f.set_velocity(u0);
    const double d0 = f.max_abs_divergence();
    f.step(Mat2::Zero(N, 2));
    EXPECT_LT(f.poisson_residual(), 1e-10);
    div1[c] = f.max_abs_divergence();
    ratio[c] = div1[c] / d0;
  }
  EXPECT_GT(order(div1[0], div1[1]), 1.7) << div1[0] << " " << div1[1];
  EXPECT_LT(ratio[1], 1.5 * 0.0292);
}

namespace {

constexpr double kRe = 0.0125;  // Section 5.1: rho u_max H / mu

double poiseuille(double y, double t, const double*) { return exact::poiseuille_u(y, t, kRe); }
double couette(double y, double t, const double* nu) { return exact::couette_u(y, t, *nu, 1.0, 1.0); }

// Start-up Poiseuille flow, dimensionless (Section 4.1): channel [0,1]^2 periodic in x, walls at
// y = 0, 1; rho = 1, mu = 1/Re, F = (8/Re, 0) so that u_max = F H^2 / (8 mu) = 1.
std::unique_ptr<EulerianFluid> run_poiseuille(int n, double h_over_dx, double dt, int steps, bool convection,
                                              SolverKind cn = SolverKind::Auto) {
  FluidParams p = make_params(n, h_over_dx, true, false);
  p.cn_solver = cn;
  p.rho = 1.0;
  p.mu = 1.0 / kRe;
  p.dt = dt;
  p.convection = convection;
  auto f = std::make_unique<EulerianFluid>(p);  // (a fluid is not copied or moved: its profiler knows it)
  Mat2 F(f->size(), 2);
  F.col(0).setConstant(8.0 / kRe);
  F.col(1).setZero();
  for (int s = 0; s < steps; ++s) f->step(F);
  return f;
}

}  // namespace

// rms velocity error against Eq. (44) at t = 0.0125 (flow essentially developed) with
// h/dx = 3, where the O(h^2) smoothing error dominates (paper, Fig. 7 and Eq. 74).
// dt = 1.25e-4 (100 steps; the paper's 1.25e-6 would take 1e4): measured rms
//   nx = 16: 2.5613e-2   24: 1.1154e-2   32: 6.2352e-3
//   orders 16->24: 2.05, 24->32: 2.02, 16->32: 2.04;
// at dt = 1.25e-5 the errors are 2.5613e-2 and 6.2350e-3 (differences 1e-5, 4e-5 relative):
// the error is spatial. (At h/dx = 1.525: 5.13e-3, 1.46e-3, 9.60e-4: discretisation and
// smoothing errors mix, orders 3.1 and 1.45, as the paper's ansatz (73) predicts.)
// Tolerance: rms at nx = 16 below 1.1x measured; every observed order above 1.8.
TEST(Fluid, PoiseuilleConvergesSecondOrderAtLargeSmoothingLength) {
  const int ns[3] = {16, 24, 32};
  double e[3];
  for (int c = 0; c < 3; ++c) {
    const auto fluid = run_poiseuille(ns[c], 3.0, 1.25e-4, 100, false);
    const EulerianFluid& f = *fluid;
    ASSERT_NEAR(f.time(), 0.0125, 1e-12);
    e[c] = rms_error(f, poiseuille, nullptr);
  }
  EXPECT_LT(e[0], 1.1 * 2.5613e-2);
  EXPECT_GT(order(e[0], e[1], 1.5), 1.8) << e[0] << " " << e[1];
  EXPECT_GT(order(e[1], e[2], 4.0 / 3.0), 1.8) << e[1] << " " << e[2];
  EXPECT_GT(order(e[0], e[2]), 1.8) << e[0] << " " << e[2];
  EXPECT_LT(order(e[0], e[2]), 2.3) << e[0] << " " << e[2];  // not better than the smoothing order
}

// Unidirectional flow: u.grad u = 0, so convection on and off agree to round-off.
// Measured max |u_on - u_off| = 1.8e-12 with max |u| = 1.02; max |v| = 6.8e-12 (the exact
// projection makes u^{n+1} as the curl of a stream function solved every step: round-off times the
// condition of its system; the approximate projection: 2.8e-17 and 8e-17). Tolerance 1e-10.
// The Crank-Nicolson solver is pinned: Auto may time its way to Jacobi-PCG in one run and to
// CHOLMOD in the other, which differ at the PCG tolerance (1e-14 x condition number).
TEST(Fluid, PoiseuilleConvectionOnEqualsOff) {
  const auto on_fluid = run_poiseuille(16, 3.0, 1.25e-4, 100, true, SolverKind::CholmodSupernodal);
  const auto off_fluid = run_poiseuille(16, 3.0, 1.25e-4, 100, false, SolverKind::CholmodSupernodal);
  const EulerianFluid &on = *on_fluid, &off = *off_fluid;
  EXPECT_GT(max_abs(off.u()), 0.9);
  EXPECT_LT(max_abs(on.u() - off.u()), 1e-10);
  EXPECT_LT(on.u().col(1).cwiseAbs().maxCoeff(), 1e-10);
}

// Couette flow from rest, top wall moving at (1, 0), rho = mu = 1, nx = 16, h/dx = 1.2,
// dt = 1e-3, convection on. Measured rms error against the series: 2.568e-3 at t = 0.1,
// 2.281e-4 at t = 0.5 (dt = 1e-4: 2.570e-3, 2.282e-4: spatial error). The steady linear
// profile is reproduced exactly by the odd wall images, so the error decays with the transient.
// Tolerance 1.25x measured.
TEST(Fluid, CouetteMatchesSeries) {
  FluidParams p = make_params(16, 1.2, true, false);
  p.domain.wall_velocity[Top] = Eigen::Vector2d(1.0, 0.0);
  p.dt = 1e-3;
  EulerianFluid f(p);
  const double nu = f.nu();
  const Mat2 F = Mat2::Zero(f.size(), 2);
  for (int s = 0; s < 100; ++s) f.step(F);
  ASSERT_NEAR(f.time(), 0.1, 1e-12);
  EXPECT_LT(rms_error(f, couette, &nu), 1.25 * 2.568e-3);
  for (int s = 100; s < 500; ++s) f.step(F);
  ASSERT_NEAR(f.time(), 0.5, 1e-12);
  EXPECT_LT(rms_error(f, couette, &nu), 1.25 * 2.281e-4);
  EXPECT_LT(f.u().col(1).cwiseAbs().maxCoeff(), 1e-13);  // measured 3.6e-16
}

// A fluid at rest with no force and walls at rest stays exactly at rest (every term is zero).
TEST(Fluid, RestStaysExactlyAtRest) {
  for (bool periodic_x : {true, false}) {
    FluidParams p = make_params(16, 1.2, periodic_x, false);
    p.convection = true;
    EulerianFluid f(p);
    const Mat2 F = Mat2::Zero(f.size(), 2);
    for (int s = 0; s < 5; ++s) f.step(F);
    EXPECT_EQ(max_abs(f.u()), 0.0);
    EXPECT_EQ(f.phi().cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(f.p().cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(f.steps(), 5);
  }
}

// Galilean check: a uniform flow (1, 0.5) in a fully periodic box with convection on is a
// solution (grad u = 0 by the zeroth moment, lap u = 0). Measured max deviation after 20 steps
// (dt = 0.01, mu = 0.1, nx = 16): 7.1e-15. Tolerance 1e-12 (round-off).
TEST(Fluid, UniformFlowIsPreservedInPeriodicBox) {
  FluidParams p = make_params(16, 1.2, true, true);
  p.mu = 0.1;
  p.dt = 0.01;
  p.convection = true;
  EulerianFluid f(p);
  Mat2 u0(f.size(), 2);
  u0.col(0).setConstant(1.0);
  u0.col(1).setConstant(0.5);
  f.set_velocity(u0);
  for (int s = 0; s < 20; ++s) f.step(Mat2::Zero(f.size(), 2));
  EXPECT_LT(max_abs(f.u() - u0), 1e-12);
  EXPECT_LT(f.max_abs_divergence(), 1e-10);
}

// Stored reference values (regression, tight): the start-up Poiseuille flow of the test above at
// nx = 16, h/dx = 3, after 10 and 20 steps of 1.25e-4 (t = 1.25e-3, 2.5e-3: the transient, where the
// Crank-Nicolson factor a = nu dt/2 of Eq. (28) shows; a developed flow does not depend on it).
// The numbers are this build's (CHOLMOD and FFT solvers agree to 1e-13 here); tolerance 1e-8
// relative. They change only when the EPSPH numerics change on purpose: rerun with
// SPHIB_PRINT_REFERENCES=1 to print them anew. (The mutation a -> 1.001 a passed every viscous
// test before this one; measured, it moves umax by 3.7e-4 and 6.6e-4 and the rms by 7e-3 and 1.7e-2.)
TEST(Fluid, PoiseuilleTransientMatchesStoredValues) {
  const double stored_rms[2] = {0.015106018188279138, 0.018966107776308812};
  const double stored_umax[2] = {0.61531064786472145, 0.86505676547841337};
  for (int k = 0; k < 2; ++k) {
    const auto fluid = run_poiseuille(16, 3.0, 1.25e-4, 10 * (k + 1), false, SolverKind::CholmodSupernodal);
    const EulerianFluid& f = *fluid;
    const double rms = rms_error(f, poiseuille, nullptr), umax = f.u().col(0).maxCoeff();
    if (std::getenv("SPHIB_PRINT_REFERENCES")) std::printf("steps %d: rms %.17g umax %.17g\n", 10 * (k + 1), rms, umax);
    EXPECT_NEAR(rms, stored_rms[k], 1e-8 * stored_rms[k]) << "steps " << 10 * (k + 1);
    EXPECT_NEAR(umax, stored_umax[k], 1e-8 * stored_umax[k]) << "steps " << 10 * (k + 1);
  }
}
