// The fast lattice solvers (fluid/algebra/fft_poisson.hpp) on every domain kind and every system EPSPH
// builds, against CHOLMOD on the same matrices. Tolerances are measured values (Release build) with
// a margin, stated beside each test.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "fluid/common/boundary.hpp"
#include "fluid/factory.hpp"
#include "fluid/algebra/fft_poisson.hpp"
#include "fluid/algebra/gauge.hpp"
#include "kernels/cubic_spline.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/common/neighbours.hpp"
#include "fluid/algebra/operators.hpp"
#include "fluid/core/solver.hpp"
#include "fluid/common/threads.hpp"

using namespace sphib;

namespace {

struct DomainCase {
  bool px, py;
  const char* name;
  const char* even_x;  // the x transform expected for an operator with even images, and odd ones
  const char* odd_x;
};
// The channel is the solver's old domain (its results are unchanged, tests/test_fluid.cpp); the
// others are new: closed box, doubly periodic, walls in x and periodic in y.
const DomainCase kDomains[] = {{true, false, "channel", "FFT in x", "FFT in x"},
                               {false, false, "closed box", "DCT-II in x", "DST-II in x"},
                               {true, true, "doubly periodic", "2-D FFT", "2-D FFT"},
                               {false, true, "walls in x, periodic y", "DCT-II in x", "DST-II in x"}};

// The lattice of Eq. (68), its wall images and the operators EPSPH assembles on it (Eqs. 27-34).
struct LatticeOperators {
  Lattice L;
  Operators op;
  int size() const { return L.size(); }
};
LatticeOperators lattice_operators(const DomainCase& d, int nx, int ny, double h_over_dx) {
  Domain dom;
  dom.periodic_x = d.px;
  dom.periodic_y = d.py;
  LatticeOperators lo{make_lattice(dom, nx, ny), {}};
  const CubicSplineKernel W(h_over_dx * 0.5 * (lo.L.dx + lo.L.dy));
  const Images im = make_images(lo.L, W.support());
  lo.op = build_operators(find_pairs(lo.L, im.x, W.support()), lo.L, im, W);
  return lo;
}

// One system EPSPH solves, as fluid/eulerian/exact_projection.cpp builds it, with its null space and the parity of
// its wall images.
struct System {
  std::string name;
  SpMat A;
  NullSpace null;
  bool odd;
  Field field;  // what it acts on: its images by the boundary rule
};

std::vector<System> systems(const LatticeOperators& f) {
  const Operators& op = f.op;
  const Domain& d = f.L.domain;
  const int N = f.size();
  SpMat I(N, N);
  I.setIdentity();
  const double a = 0.5 * f.L.dx * f.L.dx;  // nu dt / 2 of a stiff Crank-Nicolson step
  const SpMat& Gx = op.grad_ux.A;
  const SpMat& Gy = op.grad_uy.A;
  const SpMat GtG_odd = SpMat(Gy.transpose()) * Gy + SpMat(Gx.transpose()) * Gx;
  const SpMat GtG_even = SpMat(op.grad_phiy.transpose()) * op.grad_phiy + SpMat(op.grad_phix.transpose()) * op.grad_phix;
  const bool box = d.periodic_x && d.periodic_y;
  return {{"Crank-Nicolson (Eq. 28, velocity images)", I - a * op.lap_u.A, NullSpace::None, true, Field::VelocityNormal},
          {"Poisson (Eq. 32, Morris Laplacian, scalar images)", -op.lap_phi, NullSpace::Constants, false, Field::Scalar},
          {"stream function of the exact projection (G^T G, odd images)", GtG_odd, NullSpace::GradientStream, true, Field::Stream},
          {"markers' stream function (Morris Laplacian, odd images)", -op.lap_u.A, box ? NullSpace::Constants : NullSpace::None, true, Field::Stream},
          {"G^T G, even images", GtG_even, NullSpace::GradientScalar, false, Field::Scalar}};
}

Vec random_vector(int n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  Vec b(n);
  for (int i = 0; i < n; ++i) b[i] = U(gen);
  return b;
}

// The condition number of A on the complement of its null space, estimated by 30 power iterations
// on A (its largest eigenvalue) and on its pseudo-inverse by `solver` (the smallest non-zero one).
double condition(const SpMat& A, LinearSolver& solver, const Gauge& g) {
  Vec v = random_vector(static_cast<int>(A.rows()), 99), w(A.rows());
  g.project(v);
  double lmax = 0, lmin_inv = 0;
  for (int k = 0; k < 30; ++k) {
    w = A * v;
    lmax = w.norm() / v.norm();
    v = w / w.norm();
  }
  v = random_vector(static_cast<int>(A.rows()), 98);
  g.project(v);
  for (int k = 0; k < 30; ++k) {
    w.setZero();
    solver.solve(v.data(), w.data(), 1);
    g.project(w);
    lmin_inv = w.norm() / v.norm();
    v = w / w.norm();
  }
  return lmax * lmin_inv;
}

}  // namespace

// Every system on every domain kind takes the fast path, with the transform the images ask for
// (DCT-II for even images, DST-II for odd ones, FFT along periodic axes), and solves like CHOLMOD on
// the pinned matrix, for right-hand sides in the range of A (null components projected out):
//  - backward error eta = ||A x - b||_inf / (||A||_inf ||x||_inf) at round-off;
//  - the solution, null components removed, within round-off times the condition number kappa of A
//    (on the complement of its null space) of CHOLMOD's: |x - y|_inf / |y|_inf <= c kappa u.
// G^T G is ill-conditioned at h = 2.25 dx (kappa 4.8e9: its gradient's symbol nearly vanishes at
// theta ~ 2 pi dx / h, where the kernel's transform has its first zero), so both solvers can only
// agree to ~1e-7 there; the other systems have kappa 1.5 (Crank-Nicolson) to 190 (Morris Laplacian).
// Three lattices: non-square, odd n_x, and a wide kernel (G^T G reaches 8 sites).
// Measured over all 120 solves (3 lattices, 4 domains, 5 systems, 2 right-hand sides): eta <= 1.3e-15;
// |x - y| / |y| <= 3.8e-13 where kappa < 1e3 (<= 2.9e-15 for Crank-Nicolson) and <= 7.3e-7 for
// G^T G at h = 2.25 dx; c = |x - y| / (|y| kappa u) <= 42 (u = 1.1e-16). Tolerances eta < 1e-14, c < 400.
TEST(FftSolver, MatchesCholmodOnEveryDomainAndSystem) {
  struct Size { int nx, ny; double h_over_dx; };
  for (const Size& s : {Size{24, 20, 1.2}, Size{17, 22, 1.2}, Size{32, 28, 2.25}})
    for (const DomainCase& dc : kDomains) {
      const LatticeOperators f = lattice_operators(dc, s.nx, s.ny, s.h_over_dx);
      for (const System& sys : systems(f)) {
        SCOPED_TRACE(std::string(dc.name) + ", " + sys.name + ", " + std::to_string(s.nx) + " x " + std::to_string(s.ny));
        const Gauge g(f.L, sys.null);
        std::string why;
        auto fft = make_fft_solver(sys.name, sys.A, f.L, sys.field, g.dimension() > 0, &why);
        ASSERT_TRUE(fft) << why;
        EXPECT_NE(fft->info().method.find(sys.odd ? dc.odd_x : dc.even_x), std::string::npos) << fft->info().method;
        const double kappa = condition(sys.A, *fft, g);
        const double a_inf = (sys.A.cwiseAbs() * Vec::Ones(f.size())).maxCoeff();
        auto chol = factorize(sys.name, g.dimension() > 0 ? g.pinned(sys.A) : sys.A, SolverKind::CholmodSimplicial);
        for (unsigned r = 0; r < 2; ++r) {
          Vec b = random_vector(f.size(), 11 + r);
          g.project(b);
          Vec x = Vec::Zero(f.size()), y = Vec::Zero(f.size()), bp = b;
          fft->solve(b.data(), x.data(), 1);
          const double eta = (sys.A * x - b).cwiseAbs().maxCoeff() / (a_inf * x.cwiseAbs().maxCoeff());
          EXPECT_LT(eta, 1e-14);
          g.pin_rhs(bp);
          chol->solve(bp.data(), y.data(), 1);
          g.project(x);
          g.project(y);
          const double diff = (x - y).cwiseAbs().maxCoeff() / y.cwiseAbs().maxCoeff();
          EXPECT_LT(diff, 400 * kappa * 1.1e-16) << "kappa " << kappa;
        }
      }
    }
}

// Two columns at once (two threads under OpenMP from kParallelRows rows: 96 x 96 here) give
// bitwise the columns of two single solves, on the new paths (2-D FFT, DST-II + banded).
TEST(FftSolver, TwoColumnsEqualTwoSingleSolves) {
  for (const DomainCase& dc : {kDomains[1], kDomains[2], kDomains[3]}) {
    const LatticeOperators f = lattice_operators(dc, 96, 96, 1.2);
    const System cn = systems(f)[0];
    std::string why;
    auto fft = make_fft_solver(cn.name, cn.A, f.L, cn.field, false, &why);
    ASSERT_TRUE(fft) << why;
    Eigen::MatrixXd B(f.size(), 2), X = Eigen::MatrixXd::Zero(f.size(), 2);
    B.col(0) = random_vector(f.size(), 1);
    B.col(1) = random_vector(f.size(), 2);
    fft->solve(B.data(), X.data(), 2);
    for (int c = 0; c < 2; ++c) {
      Vec x = Vec::Zero(f.size());
      fft->solve(B.col(c).data(), x.data(), 1);
      EXPECT_EQ((X.col(c) - x).cwiseAbs().maxCoeff(), 0.0) << dc.name;
    }
  }
}

// One column on two threads (row blocks of the transforms, ranges of wavenumbers of the banded
// substitutions) gives bitwise the one-thread solution, on the walled-y domains (the banded solver:
// FFT and DCT-II/DST-II in x), every system; 98 x 100 (>= kParallelRows) makes a last row block
// shorter than the others and an odd split of the wavenumbers. Two columns (one per thread) too.
TEST(FftSolver, TwoThreadsGiveTheBitsOfOne) {
  for (const DomainCase& dc : {kDomains[0], kDomains[1]}) {
    const LatticeOperators f = lattice_operators(dc, 98, 100, 1.2);
    ASSERT_GE(f.size(), kParallelRows);
    for (const System& sys : systems(f)) {
      const Gauge g(f.L, sys.null);
      std::string why;
      auto fft = make_fft_solver(sys.name, sys.A, f.L, sys.field, g.dimension() > 0, &why);
      ASSERT_TRUE(fft) << dc.name << ", " << sys.name << ": " << why;
      const int N = f.size();
      Eigen::MatrixXd B(N, 2);
      for (int c = 0; c < 2; ++c) {
        Vec b = random_vector(N, 11 + c);
        g.project(b);
        B.col(c) = b;
      }
      Eigen::MatrixXd X[2];
      for (int t = 0; t < 2; ++t) {
        const ThreadCount threads(t + 1);
        X[t] = Eigen::MatrixXd::Zero(N, 2);
        fft->solve(B.data(), X[t].data(), 1);  // a column at a time
        fft->solve(B.col(1).data(), X[t].col(1).data(), 1);
      }
      EXPECT_EQ((X[0] - X[1]).cwiseAbs().maxCoeff(), 0.0) << dc.name << ", " << sys.name;
      EXPECT_GT(X[0].cwiseAbs().maxCoeff(), 0.0);
      Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(N, 2);
      {
        const ThreadCount threads(2);
        fft->solve(B.data(), Y.data(), 2);  // two columns, one per thread
      }
      EXPECT_EQ((X[0] - Y).cwiseAbs().maxCoeff(), 0.0) << dc.name << ", " << sys.name;
    }
  }
}

// The solvers transform the right-hand side in place and write the solution directly when the
// arrays have the alignment FFTW planned for, and go through their own workspaces otherwise: both
// paths give the same bits, and the right-hand side is left as it was. Every system on every domain
// kind, from and to arrays one double off an aligned address (the copies) and aligned ones.
TEST(FftSolver, AlignedAndMisalignedArraysGiveTheSameBits) {
  for (const DomainCase& dc : kDomains) {
    const LatticeOperators f = lattice_operators(dc, 24, 20, 1.2);
    for (const System& sys : systems(f)) {
      const Gauge g(f.L, sys.null);
      std::string why;
      auto fft = make_fft_solver(sys.name, sys.A, f.L, sys.field, g.dimension() > 0, &why);
      ASSERT_TRUE(fft) << dc.name << ", " << sys.name << ": " << why;
      const int N = f.size();
      Vec b = random_vector(N, 7);
      g.project(b);
      Vec x = Vec::Zero(N), b_shifted = Vec::Zero(N + 1), x_shifted = Vec::Zero(N + 1);
      b_shifted.tail(N) = b;
      fft->solve(b.data(), x.data(), 1);
      fft->solve(b_shifted.data() + 1, x_shifted.data() + 1, 1);
      EXPECT_EQ((x - x_shifted.tail(N)).cwiseAbs().maxCoeff(), 0.0) << dc.name << ", " << sys.name;
      EXPECT_EQ((b - b_shifted.tail(N)).cwiseAbs().maxCoeff(), 0.0) << dc.name << ", " << sys.name << ": input changed";
      EXPECT_GT(x.cwiseAbs().maxCoeff(), 0.0);
    }
  }
}

// Walls of different parities (the quarter-wave transforms, DCT-IV and DST-IV): phi's Laplacian
// with its images at the right wall made odd (even left, odd right) and the velocity's
// Crank-Nicolson matrix with its images at the right wall made even (odd left, even right), on a
// closed box (banded in y) and on walls in x with y periodic (diagonal), n_x even and odd, against
// CHOLMOD. Tolerances as MatchesCholmodOnEveryDomainAndSystem's (measured here: eta <= 6.8e-16,
// |x_fft - x_cholmod| / |x| <= 1.7 kappa u, kappa 93-756).
TEST(FftSolver, MixedWallParitiesTakeTheQuarterWaveTransforms) {
  struct Size { int nx, ny; };
  for (const DomainCase& dc : {kDomains[1], kDomains[3]})
    for (const Size& sz : {Size{24, 20}, Size{17, 22}}) {
      Domain dom;
      dom.periodic_x = dc.px;
      dom.periodic_y = dc.py;
      const Lattice L = make_lattice(dom, sz.nx, sz.ny);
      const CubicSplineKernel W(1.2 * 0.5 * (L.dx + L.dy));
      Images im = make_images(L, W.support());
      for (int k = 0; k < im.size(); ++k)  // the right wall's images (and corners beyond it) flip parity
        if (im.x(k, 0) > dom.x1) {
          im.s_sign[k] = -im.s_sign[k];
          im.v_sign[k] = -im.v_sign[k];
        }
      const Operators op = build_operators(find_pairs(L, im.x, W.support()), L, im, W);
      const int N = L.size();
      SpMat I(N, N);
      I.setIdentity();
      struct Mixed { std::string name; SpMat A; XParities xp; const char* transform; };
      const Mixed systems[] = {{"Poisson, even left, odd right", -op.lap_phi, {1, -1}, "DCT-IV in x"},
                               {"Crank-Nicolson, odd left, even right", I - 0.3 * op.lap_u.A, {-1, 1}, "DST-IV in x"}};
      for (const Mixed& sys : systems) {
        SCOPED_TRACE(std::string(dc.name) + ", " + sys.name + ", n_x = " + std::to_string(sz.nx));
        std::string why;
        auto fft = make_fft_solver(sys.name, sys.A, L, sys.xp, false, &why);
        ASSERT_TRUE(fft) << why;
        EXPECT_NE(fft->info().method.find(sys.transform), std::string::npos) << fft->info().method;
        // the same matrix with the parities of one wall only is refused, naming them
        EXPECT_FALSE(make_fft_solver(sys.name, sys.A, L, XParities{sys.xp.left, sys.xp.left}, false, &why));
        const Gauge none;
        const double kappa = condition(sys.A, *fft, none);
        const double a_inf = (sys.A.cwiseAbs() * Vec::Ones(N)).maxCoeff();
        auto chol = factorize(sys.name, sys.A, SolverKind::CholmodSimplicial);
        for (unsigned r = 0; r < 2; ++r) {
          const Vec b = random_vector(N, 21 + r);
          Vec x = Vec::Zero(N), y = Vec::Zero(N);
          fft->solve(b.data(), x.data(), 1);
          chol->solve(b.data(), y.data(), 1);
          const double eta = (sys.A * x - b).cwiseAbs().maxCoeff() / (a_inf * x.cwiseAbs().maxCoeff());
          const double diff = (x - y).cwiseAbs().maxCoeff() / y.cwiseAbs().maxCoeff();
          EXPECT_LT(eta, 1e-14);
          EXPECT_LT(diff, 400 * kappa * 1.1e-16) << "kappa " << kappa;
        }
      }
    }
}

// The structure check can fail, and says where: a channel's matrix that is not a translate along x
// (one coefficient moved); one coefficient of a closed box's corner row (row 0:
// both x and y images folded in) or of a wall row moved by 1e-6; a matrix whose x images are not the
// boundary rule's for its field (the sum of an even-image and an odd-image operator; phi's operator
// said to act on a stream function); a stencil that reaches a wall
// from the middle of a narrow closed box (no row free of images to take the model from); a matrix
// said to be singular that is not, and the reverse. And the scene key asks for it in vain: a closed
// box of 12 x 12 with h = 2.25 dx, where the exact projection's G^T G (half-width 8) is as wide as
// the lattice.
TEST(FftSolver, RefusesWhatItCannotSolve) {
  {
    const LatticeOperators ch = lattice_operators(kDomains[0], 16, 16, 1.2);
    SpMat A = -ch.op.lap_phi;
    A.coeffRef(40, 40) *= 1.0 + 1e-6;
    std::string why;
    EXPECT_FALSE(make_fft_solver("Poisson", A, ch.L, Field::Scalar, true, &why));
    EXPECT_NE(why.find("row 40 "), std::string::npos) << why;
    EXPECT_NE(why.find("not block circulant"), std::string::npos) << why;
  }
  {
    FluidParams p;
    p.domain.periodic_x = p.domain.periodic_y = false;
    p.nx = p.ny = 12;
    p.h_over_dx = 2.25;
    p.projection = Projection::Exact;
    p.poisson_solver = SolverKind::Fft;
    try {
      make_fluid(p);
      ADD_FAILURE() << "solver.poisson = fft accepted where G^T G is as wide as the lattice";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("solver.poisson"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("as wide as the lattice"), std::string::npos) << e.what();
    }
  }
  const LatticeOperators box = lattice_operators(kDomains[1], 16, 16, 1.2);
  const SpMat P = -box.op.lap_phi;
  for (int row : {0, 16 * 7}) {  // the corner, and the left wall's row in the middle of the box
    SpMat A = P;
    A.coeffRef(row, row) *= 1.0 + 1e-6;
    std::string why;
    EXPECT_FALSE(make_fft_solver("Poisson", A, box.L, Field::Scalar, true, &why));
    EXPECT_NE(why.find("row " + std::to_string(row) + " "), std::string::npos) << why;
  }
  // The rows are checked in one pass, each as soon as its lattice row's reference row (between x
  // walls the middle one) has passed: rows before it and after it, one coefficient moved or one
  // entry of the model missing (set to 0 and pruned), in the closed box, the doubly periodic box and
  // walls in x with y periodic (whose one reference row is the 8th: rows 0-7 wait for it).
  for (const DomainCase& dc : {kDomains[1], kDomains[2], kDomains[3]}) {
    const LatticeOperators f = lattice_operators(dc, 16, 16, 1.2);
    const SpMat Q = -f.op.lap_phi;
    for (int row : {3, 16 * 5 + 3, 16 * 5 + 12}) {
      for (bool missing : {false, true}) {
        SpMat A = Q;
        if (missing) {
          A.coeffRef(row, row + 1) = 0.0;
          A.prune(0.0, 0.0);
        } else {
          A.coeffRef(row, row + 1) *= 1.0 + 1e-6;
        }
        std::string why;
        EXPECT_FALSE(make_fft_solver("Poisson", A, f.L, Field::Scalar, true, &why)) << dc.name << " " << row;
        EXPECT_NE(why.find("row " + std::to_string(row) + (missing ? " lacks" : " is not")), std::string::npos) << why;
      }
    }
  }
  {
    std::string why;
    const SpMat mixed = P - box.op.lap_u.A;
    EXPECT_FALSE(make_fft_solver("mixed", mixed, box.L, Field::Scalar, true, &why));
    EXPECT_NE(why.find("even images folded in"), std::string::npos) << why;
  }
  {  // the transform is the boundary rule's: phi's operator offered as a stream function's (odd images)
    std::string why;
    EXPECT_FALSE(make_fft_solver("Poisson as a stream function", P, box.L, Field::Stream, true, &why));
    EXPECT_NE(why.find("odd images folded in"), std::string::npos) << why;
  }
  {
    const LatticeOperators narrow = lattice_operators(kDomains[3], 12, 24, 2.25);  // G^T G: half-width 8 of 12 sites
    const System gtg = systems(narrow)[2];
    std::string why;
    EXPECT_FALSE(make_fft_solver(gtg.name, gtg.A, narrow.L, gtg.field, true, &why));
    EXPECT_NE(why.find("reaches a wall"), std::string::npos) << why;
  }
  for (const DomainCase& dc : {kDomains[1], kDomains[2]}) {
    const LatticeOperators f = lattice_operators(dc, 16, 16, 1.2);
    const System cn = systems(f)[0], poisson = systems(f)[1];
    std::string why;
    EXPECT_FALSE(make_fft_solver(cn.name, cn.A, f.L, cn.field, true, &why)) << dc.name;
    EXPECT_NE(why.find("said to be singular"), std::string::npos) << why;
    EXPECT_FALSE(make_fft_solver(poisson.name, poisson.A, f.L, poisson.field, false, &why)) << dc.name;
    EXPECT_NE(why.find("not positive definite"), std::string::npos) << why;
  }
}

// The fluid picks the fast path by itself (`auto`) on every domain kind and steps like CHOLMOD:
// u after 5 steps from a random field with convection on, the Crank-Nicolson and stream-function
// systems by FFT/DCT/DST against CHOLMOD for both. Measured max |u_fft - u_cholmod|: 1.5e-13
// (doubly periodic), 2.1e-13 (walls in x), 4.3e-13 (channel), 2.2e-12 (closed box), max |u| 0.93-0.98:
// the exact projection's G^T G (kappa ~1e4 at h = 1.2 dx) sets the round-off. Tolerance 1e-10.
TEST(FftSolver, FluidStepsLikeCholmodOnEveryDomain) {
  for (const DomainCase& dc : kDomains) {
    Mat2 u[2];
    for (int s = 0; s < 2; ++s) {
      FluidParams p;
      p.domain.periodic_x = dc.px;
      p.domain.periodic_y = dc.py;
      p.nx = 20;
      p.ny = 18;
      p.mu = 0.05;
      p.convection = true;
      p.projection = Projection::Exact;
      p.cn_solver = p.poisson_solver = s ? SolverKind::CholmodSimplicial : SolverKind::Auto;
      auto f = make_fluid(p);
      if (s == 0)
        for (const std::string& line : f->profiler().report().lines)  // the run log's lines: one per solver
          EXPECT_EQ(line.find("CHOLMOD"), std::string::npos) << dc.name << ": " << line;
      Mat2 u0(f->size(), 2);
      u0.col(0) = random_vector(f->size(), 5);
      u0.col(1) = random_vector(f->size(), 6);
      f->set_velocity(u0);
      for (int k = 0; k < 5; ++k) f->step(Mat2::Zero(f->size(), 2));
      u[s] = f->u();
    }
    EXPECT_LT((u[0] - u[1]).cwiseAbs().maxCoeff(), 1e-10) << dc.name;
  }
}
