// The moving-particle infrastructure of LPSPH (and ISPH): the Verlet list (fluid/common/neighbours.hpp), the
// kernel of the assembly pass (fluid/moving/particle_operators.hpp) and the lagged preconditioned CG with its
// policy (fluid/algebra/linear_solver.hpp, fluid/algebra/solver_policy.hpp). Every tolerance is a measured value
// (Release build, stated beside the test) with a margin.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "fluid/factory.hpp"
#include "fluid/moving/lagrangian.hpp"
#include "fluid/moving/particle_operators.hpp"
#include "fluid/algebra/products.hpp"
#include "fluid/algebra/solver_policy.hpp"
#include "io/scene.hpp"

using namespace sphib;

namespace {

std::uint64_t bits(double v) {
  std::uint64_t u;
  std::memcpy(&u, &v, sizeof u);
  return u;
}

// Random particles in the box (uniform: clusters and holes), at least `gap` from every wall.
Mat2 random_particles(const Domain& d, int N, double gap, std::mt19937& gen) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  Mat2 x(N, 2);
  for (int i = 0; i < N; ++i) {
    const double gx = d.periodic_x ? 0.0 : gap, gy = d.periodic_y ? 0.0 : gap;
    x(i, 0) = d.x0 + gx + (d.Lx() - 2 * gx) * U(gen);
    x(i, 1) = d.y0 + gy + (d.Ly() - 2 * gy) * U(gen);
  }
  return x;
}

// The pairs of particle i closer than `reach`, as (neighbour, rx, ry, r) with the neighbour named
// by what it is (a particle: its index; an image: N + parent + N * (1 + wall)), so that lists whose
// images are numbered differently compare.
using Near = std::vector<std::tuple<long, std::uint64_t, std::uint64_t, std::uint64_t>>;
Near within(const PairList& P, const Images& im, int N, int i, double reach) {
  Near out;
  for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
    if (!(P.r[k] < reach)) continue;
    const int j = P.j[k];
    const long who = j < N ? j : N + im.parent[j - N] + static_cast<long>(N) * (2 + im.wall[j - N]);
    out.emplace_back(who, bits(P.rx[k]), bits(P.ry[k]), bits(P.r[k]));
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

// ======================================================================================
// The kernel of the assembly pass
// ======================================================================================

// KernelWF evaluates W and F = (1/r) dW/dr of the cubic spline (Eq. 19) with one q = r / h and the
// factor w0 / h^2 hoisted; it must give the kernel's own bits (CubicSplineKernel::W and ::F), so
// that LPSPH's operators and kernel sums are those of build_operators. 2e5 random r in [0, 2.2 h]
// for three h, and the branch points.
TEST(MovingParticles, KernelWFIsTheKernelBitForBit) {
  std::mt19937 gen(3);
  for (double h : {0.0123, 0.075, 1.0 / 3.0}) {
    const CubicSplineKernel W(h);
    const KernelWF K(W);
    std::uniform_real_distribution<double> U(0.0, 2.2 * h);
    std::vector<double> rs{0.0, h, 2.0 * h, std::nextafter(h, 0.0), std::nextafter(2.0 * h, 0.0), 2.2 * h};
    for (int s = 0; s < 200000; ++s) rs.push_back(U(gen));
    for (double r : rs) {
      double w = -1;
      const double F = K.F(r, &w);
      ASSERT_EQ(bits(F), bits(W.F(r))) << "h " << h << " r " << r;
      ASSERT_EQ(bits(w), bits(W.W(r))) << "h " << h << " r " << r;
      ASSERT_EQ(bits(K.F(r)), bits(F));
    }
  }
}

// ======================================================================================
// The Verlet list
// ======================================================================================

// 400 random particles (uniform: clusters and holes) in three layouts (channel, closed box, doubly
// periodic, the box not at the origin) move 300 steps in a swirl plus a shear plus a random jitter,
// wrapped across periodic seams and kept off the walls. After every step the pairs closer than the
// reach of two lists, one with a fixed skin (0.02) and one adaptive (in [0.002, 0.05]), are exactly
// those of a fresh cell-list search (find_pairs on make_images at the reach): the same neighbours
// (images by parent and wall) and bit for bit the same x_i - x_j and r. Between builds the
// candidates and the images (the pattern) do not change. Measured builds in 300 steps (a step moves
// a particle by up to ~0.001): fixed 36 / 36 / 35, adaptive 33 / 33 / 33 (its skin settles at
// 0.022: sqrt(2 v reach), v ~ 0.0024 per step the spread of the displacements, jitter included);
// tolerance: reused (fewer than 100 builds), and built again at least 10 times (the flow carries
// particles across the skin).
TEST(MovingParticles, VerletListEqualsAFreshSearchAfterManyMoves) {
  std::mt19937 gen(17);
  std::normal_distribution<double> jitter(0.0, 2e-4);
  struct Layout { bool px, py; };
  const double reach = 0.1;
  for (Layout lay : {Layout{true, false}, Layout{false, false}, Layout{true, true}}) {
    Domain d;
    d.x0 = -0.3; d.x1 = 0.7; d.y0 = 1.0; d.y1 = 2.0;
    d.periodic_x = lay.px;
    d.periodic_y = lay.py;
    const int N = 400;
    Mat2 x = random_particles(d, N, 0.01, gen);
    VerletList lists[2] = {VerletList(d, reach, 0.02), VerletList(d, reach, 0.002, 0.05)};
    Images im[2];
    PairList P[2];
    std::vector<int> j_built[2], parent_built[2];
    for (int step = 0; step <= 300; ++step) {
      if (step > 0) {
        for (int i = 0; i < N; ++i) {
          const double X = x(i, 0) - 0.2, Y = x(i, 1) - 1.5;
          x(i, 0) += 2e-3 * (-Y + 0.5 * Y) + jitter(gen);  // swirl and shear
          x(i, 1) += 2e-3 * X + jitter(gen);
          if (d.periodic_x) x(i, 0) -= d.Lx() * std::floor((x(i, 0) - d.x0) / d.Lx());
          if (d.periodic_y) x(i, 1) -= d.Ly() * std::floor((x(i, 1) - d.y0) / d.Ly());
          if (!d.periodic_x) x(i, 0) = std::clamp(x(i, 0), d.x0 + 1e-3, d.x1 - 1e-3);
          if (!d.periodic_y) x(i, 1) = std::clamp(x(i, 1), d.y0 + 1e-3, d.y1 - 1e-3);
        }
      }
      const Images fresh_im = make_images(d, x, reach);
      PairList fresh;
      find_pairs(d, x, fresh_im.x, reach, fresh);
      for (int l = 0; l < 2; ++l) {
        if (lists[l].update(x, im[l], P[l])) {
          j_built[l] = P[l].j;
          parent_built[l] = im[l].parent;
        } else {
          ASSERT_EQ(P[l].j, j_built[l]) << "the candidates changed between builds, step " << step;
          ASSERT_EQ(im[l].parent, parent_built[l]) << "the images changed between builds, step " << step;
        }
        for (int i = 0; i < N; ++i)
          ASSERT_EQ(within(P[l], im[l], N, i, reach), within(fresh, fresh_im, N, i, reach))
              << "list " << l << " particle " << i << " step " << step << " periodic " << lay.px << lay.py;
      }
    }
    for (const VerletList& list : lists) {
      EXPECT_EQ(list.builds() + list.updates(), 301);
      EXPECT_LT(list.builds(), 100) << "periodic " << lay.px << lay.py;
      EXPECT_GE(list.builds(), 10) << "periodic " << lay.px << lay.py;
    }
  }
}

// The adaptive skin: particles sheared at a steady rate (a channel, the rows sliding: x += g y per
// step) move apart at the relative speed v = g (y_max - y_min) and settle on the skin
// sqrt(2 v reach) of VerletList's rule, within its bounds [0.002, 0.05]: g = 1e-5 gives the lower
// bound, g = 4e-4 (v = 3.6e-4) 0.0085 (measured 0.0085, the spread over whole steps), g = 0.02 the
// upper bound. Tolerance 5%.
TEST(MovingParticles, VerletSkinFollowsTheRelativeSpeed) {
  std::mt19937 gen(8);
  const double reach = 0.1;
  for (double g : {1e-5, 4e-4, 0.02}) {
    Domain d;
    d.periodic_x = true;
    d.periodic_y = false;
    Mat2 x = random_particles(d, 300, 0.05, gen);
    const double v = g * (x.col(1).maxCoeff() - x.col(1).minCoeff());
    VerletList list(d, reach, 0.002, 0.05);
    Images im;
    PairList P;
    for (int step = 0; step < 400; ++step) {
      for (int i = 0; i < x.rows(); ++i) x(i, 0) = x(i, 0) + g * x(i, 1) - std::floor(x(i, 0) + g * x(i, 1));
      list.update(x, im, P);
    }
    const double expected = std::clamp(std::sqrt(2.0 * v * reach), 0.002, 0.05);
    EXPECT_NEAR(list.skin(), expected, 0.05 * expected) << "g = " << g;
  }
}

// The build criterion: a uniform translation (doubly periodic box, 40 skins in all) never builds
// again; in a channel whose particles start far from the walls, a translation towards a wall builds
// again once particles come within reach of it without images (the displacements alone, all equal,
// would not say so), and the pairs then equal a fresh search.
TEST(MovingParticles, VerletListBuildsWhenItMust) {
  std::mt19937 gen(5);
  const double reach = 0.1, skin = 0.02;
  {
    Domain d;
    d.periodic_x = d.periodic_y = true;
    Mat2 x = random_particles(d, 300, 0.0, gen);
    VerletList list(d, reach, skin);
    Images im;
    PairList P;
    list.update(x, im, P);
    for (int step = 0; step < 80; ++step) {
      x.col(0).array() += 0.01;  // 0.8 in all
      x.col(1).array() += 0.004;
      for (int i = 0; i < x.rows(); ++i)
        for (int a = 0; a < 2; ++a) x(i, a) -= std::floor(x(i, a));
      EXPECT_FALSE(list.update(x, im, P)) << step;
    }
    EXPECT_EQ(list.builds(), 1);
  }
  {
    Domain d;  // [0, 1]^2, periodic in x, walls in y
    d.periodic_x = true;
    d.periodic_y = false;
    Mat2 x = random_particles(d, 300, 0.0, gen);
    x.col(1) = 0.4 + 0.2 * x.col(1).array();  // y in [0.4, 0.6]: no particle within reach + skin of a wall
    VerletList list(d, reach, skin);
    Images im;
    PairList P;
    list.update(x, im, P);
    EXPECT_EQ(im.size(), 0);
    int first = -1;
    for (int step = 0; step < 40 && first < 0; ++step) {
      x.col(1).array() -= 0.01;
      if (list.update(x, im, P)) first = step;
    }
    // The lowest particle is near y = 0.4: within reach of the bottom wall after ~30 steps of 0.01.
    const double lowest = x.col(1).minCoeff();
    EXPECT_LT(lowest, reach);
    EXPECT_GT(lowest + 0.01, reach);  // built at the step that brought it within reach, not later
    EXPECT_GE(first, 0);
    const Images fresh_im = make_images(d, x, reach);
    PairList fresh;
    find_pairs(d, x, fresh_im.x, reach, fresh);
    EXPECT_GT(fresh_im.size(), 0);
    for (int i = 0; i < x.rows(); ++i)
      ASSERT_EQ(within(P, im, 300, i, reach), within(fresh, fresh_im, 300, i, reach)) << i;
  }
}

// LPSPH's operators keep their pattern between builds of the list (values only) and equal a fresh
// assembly from a fresh search at every step: a sheared channel (Couette, nx = 16, h = 1.2 dx,
// 120 steps of dt = 2e-3). Measured: 13 builds, the pattern kept in the other 107 steps; lap_phi
// within 1.6e-16 relative of build_operators' (which keeps the vanishing terms of candidates between
// the reach, 2h (1 - 1e-12), and 2h); tolerance 1e-12.
TEST(MovingParticles, LpsphPatternStableBetweenBuildsAndValuesAsFresh) {
  FluidParams p;
  p.method = FluidMethod::Lagrangian;
  p.domain.periodic_x = true;
  p.domain.periodic_y = false;
  p.domain.wall_velocity[Top] = Eigen::Vector2d(1.0, 0.0);
  p.nx = p.ny = 16;
  p.h_over_dx = 1.2;
  p.rho = p.mu = 1.0;
  p.dt = 2e-3;
  LagrangianFluid f(p);
  const Mat2 F = Mat2::Zero(f.size(), 2);
  long builds = f.verlet().builds();
  std::vector<int> inner(f.operators().lap_u.A.innerIndexPtr(),
                         f.operators().lap_u.A.innerIndexPtr() + f.operators().lap_u.A.nonZeros());
  int unchanged = 0;
  for (int s = 0; s < 120; ++s) {
    f.step(F);
    const SpMat& A = f.operators().lap_u.A;
    const std::vector<int> now(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
    if (f.verlet().builds() == builds) {
      ASSERT_EQ(now, inner) << "the pattern changed without a build, step " << s;
      ++unchanged;
    }
    builds = f.verlet().builds();
    inner = now;
    // A fresh search at the step's positions, assembled as build_operators does.
    const Images im = f.images();
    const Operators ref = build_operators(f.pairs(), f.lattice(), im, f.kernel());
    const double d = (Eigen::MatrixXd(f.operators().lap_phi) - Eigen::MatrixXd(ref.lap_phi)).cwiseAbs().maxCoeff();
    ASSERT_LE(d, 1e-12 * Eigen::MatrixXd(ref.lap_phi).cwiseAbs().maxCoeff()) << s;
  }
  EXPECT_GT(unchanged, 80);  // measured 107
}

// ======================================================================================
// Conjugate gradients preconditioned by a lagged factorisation or the lattice's FFT solver
// ======================================================================================

namespace {

FluidParams box(bool px, int n) {
  FluidParams p;
  p.method = FluidMethod::Lagrangian;
  p.domain.periodic_x = px;
  p.domain.periodic_y = false;
  p.nx = p.ny = n;
  p.h_over_dx = 1.525;
  p.rho = 1.0;
  p.mu = 1.0;
  p.dt = 1e-3;
  return p;
}

// The lattice displaced by amplitude a (in dx) along a smooth field plus a fixed random one (seeded
// once per test), so that growing amplitudes move the particles continuously.
struct Displacement {
  Mat2 R;
  Displacement(const Lattice& L, unsigned seed) : R(L.size(), 2) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (int i = 0; i < R.rows(); ++i) R(i, 0) = U(gen), R(i, 1) = U(gen);
  }
  Mat2 operator()(const Lattice& L, double a) const {
    Mat2 x = L.x;
    for (int i = 0; i < x.rows(); ++i) {
      const double X = L.x(i, 0), Y = L.x(i, 1);
      x(i, 0) += a * L.dx * (0.7 * std::sin(6.28 * Y) + 0.3 * R(i, 0));
      x(i, 1) += a * L.dy * (0.4 * std::sin(6.28 * X) * std::sin(3.14 * Y) + 0.3 * R(i, 1));
    }
    return x;
  }
};

}  // namespace

// The Poisson system of LPSPH (Eq. 32, singular: the constants) on a closed box, nx = 24, at
// positions that drift from the lattice: pcg_cholmod against a fresh CHOLMOD factorisation of the
// pinned matrix at every position. Small drifts (amplitude growing by 0.004 dx per solve) keep the
// lagged factor (one factorisation, at the start), a jump of 0.3 dx refreshes it once, and every
// solution equals the direct one. Measured: max relative difference 1.5e-13 (after removing the
// mean); tolerance 1e-11. Iterations (to 1e-14): 4-5 before the jump, 13 at it (above 8:
// refreshed), then 4.
TEST(MovingParticles, LaggedCholmodConvergesToTheDirectSolutionAndRefreshes) {
  LagrangianFluid f(box(false, 24));
  const Lattice& L = f.lattice();
  const Displacement displaced(L, 9);
  const Gauge g(L, NullSpace::Constants);
  const int N = L.size();
  SpMat A0 = -f.operators().lap_phi;
  SystemSolver s = singular_solver("Poisson", Field::Scalar, A0, g, SolverKind::PcgCholmod, nullptr, Refactor::EveryStep);
  ASSERT_TRUE(s.unpinned);
  EXPECT_EQ(s.solver->preconditioner_factorisations(), 1);
  Vec phi = Vec::Zero(N);
  double worst = 0;
  long before_jump = -1;
  for (int k = 1; k <= 12; ++k) {
    const double a = k <= 8 ? 0.004 * k : 0.3 + 0.004 * k;
    if (k == 9) before_jump = s.solver->preconditioner_factorisations();
    f.set_positions(displaced(L, a));
    const SpMat A = -f.operators().lap_phi;
    s.solver->refactorize(A);
    Vec b(N);  // a smooth right-hand side on the range (zero mean)
    for (int i = 0; i < N; ++i) b[i] = std::cos(3.0 * L.x(i, 0)) * std::sin(2.0 * L.x(i, 1)) + 0.1 * L.x(i, 1);
    g.project(b);
    s.solver->solve(b.data(), phi.data(), 1);
    phi.array() -= phi.mean();
    Vec bp = b, ref(N);
    g.pin_rhs(bp);
    factorize("direct", g.pinned(A), SolverKind::CholmodSupernodal)->solve(bp.data(), ref.data(), 1);
    ref.array() -= ref.mean();
    worst = std::max(worst, (phi - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-11);
  EXPECT_EQ(before_jump, 1);                                // the small drifts kept the first factor
  EXPECT_EQ(s.solver->preconditioner_factorisations(), 2);  // the jump refreshed it, once
}

// I - a lap_u.A of f's operators now (Eq. 28)
SpMat crank_nicolson_of(const LagrangianFluid& f, double a) {
  SpMat A = -a * f.operators().lap_u.A;
  for (int i = 0; i < A.rows(); ++i) A.coeffRef(i, i) += 1.0;
  return A;
}

// The Crank-Nicolson system (definite) on a channel with pcg_fft: preconditioned by the FFT solver
// of the lattice's matrix, it solves near-lattice positions in a few iterations without any
// factorisation; far from the lattice (0.45 dx, random) the iterations exceed 8 and the
// preconditioner becomes a CHOLMOD factor. Every solution equals a direct solve. nx = 24,
// a = nu dt / 2 = 0.05. Measured: 6 iterations near the lattice (to 1e-14, from a cold start), 12 at
// 0.45 dx (refreshed), then 4 at 0.46 dx; relative difference to CHOLMOD 2.8e-14; tolerance 1e-12.
TEST(MovingParticles, LatticePreconditionerGivesWayToALaggedFactorFarFromTheLattice) {
  FluidParams p = box(true, 24);
  p.mu = 100.0;
  LagrangianFluid f(p);
  const Lattice& L = f.lattice();
  const Displacement displaced(L, 2);
  const double a = 0.5 * p.mu / p.rho * p.dt;
  const int N = L.size();
  auto cn = [&]() { return crank_nicolson_of(f, a); };
  const SpMat A0 = cn();
  auto s = crank_nicolson_solver(A0, f.operators().lap_u.A, a, SolverKind::PcgFft, nullptr, Refactor::EveryStep,
                                 {&L, &A0});
  EXPECT_NE(s->info().method.find("FFT"), std::string::npos) << s->info().method;
  Mat2 b(N, 2), u = Mat2::Zero(N, 2);
  for (int i = 0; i < N; ++i) {
    b(i, 0) = 1.0 + std::sin(6.28 * L.x(i, 1));
    b(i, 1) = std::cos(6.28 * L.x(i, 0));
  }
  double worst = 0;
  for (double amp : {0.02, 0.05, 0.45, 0.46}) {
    f.set_positions(displaced(L, amp));
    const SpMat A = cn();
    s->refactorize(A);
    if (amp == 0.45) EXPECT_EQ(s->preconditioner_factorisations(), 0);  // the lattice's solver so far
    s->solve(b.data(), u.data(), 2);
    Mat2 ref(N, 2);
    factorize("direct", A, SolverKind::CholmodSupernodal)->solve(b.data(), ref.data(), 2);
    worst = std::max(worst, (u - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(s->preconditioner_factorisations(), 1);  // refreshed once, after the 0.45 dx solve
  EXPECT_NE(s->info().method.find("lagged CHOLMOD"), std::string::npos) << s->info().method;
}

// start_product (LPSPH computes A X0 behind the assembly, fluid/moving/lagrangian.cpp): a lagged PCG given
// A X0 for its start X0, made as its own product makes it (two columns: apply2; one: Eigen's A x),
// returns the bits of its own solve; a wrong A X0 is taken when X0 is the start (so the check can fail) and
// ignored when it is not, as is a hint for another matrix object.
TEST(MovingParticles, LaggedPcgTakesTheCallersStartProductBitForBit) {
  FluidParams p = box(true, 24);
  p.mu = 100.0;
  LagrangianFluid f(p);
  const Lattice& L = f.lattice();
  const int N = L.size();
  const double a = 0.5 * p.mu / p.rho * p.dt;
  auto cn = [&]() { return crank_nicolson_of(f, a); };
  const SpMat A0 = cn();
  auto s = crank_nicolson_solver(A0, f.operators().lap_u.A, a, SolverKind::PcgFft, nullptr, Refactor::EveryStep,
                                 {&L, &A0});
  f.set_positions(Displacement(L, 2)(L, 0.05));
  const SpMat A = cn(), A_copy = A;
  s->refactorize_in_place(A);
  Mat2 b(N, 2), x0(N, 2);
  for (int i = 0; i < N; ++i) {
    b(i, 0) = 1.0 + std::sin(6.28 * L.x(i, 1));
    b(i, 1) = std::cos(6.28 * L.x(i, 0));
    x0(i, 0) = 0.9 * b(i, 0) + 0.01 * L.x(i, 0);
    x0(i, 1) = 0.9 * b(i, 1);
  }
  auto same = [](const double* u, const double* v, int n) { return std::memcmp(u, v, sizeof(double) * n) == 0; };
  for (int k : {2, 1}) {
    Mat2 ax(N, 2), wrong(N, 2), other = x0;
    if (k == 2) apply2(A, x0.data(), ax.data());
    else ax.col(0) = A * x0.col(0);
    wrong = 2.0 * ax;
    other(7, 0) += 1e-3;
    auto solve = [&](const SpMat* hint_A, const double* X0, const double* AX0) {
      Mat2 u = x0;
      if (hint_A) s->start_product(*hint_A, X0, AX0, k);
      s->solve(b.data(), u.data(), k);
      return u;
    };
    const Mat2 plain = solve(nullptr, nullptr, nullptr);
    EXPECT_TRUE(same(solve(&A, x0.data(), ax.data()).data(), plain.data(), N * k)) << k;
    EXPECT_FALSE(same(solve(&A, x0.data(), wrong.data()).data(), plain.data(), N * k)) << k;
    EXPECT_TRUE(same(solve(&A, other.data(), wrong.data()).data(), plain.data(), N * k)) << k;
    EXPECT_TRUE(same(solve(&A_copy, x0.data(), wrong.data()).data(), plain.data(), N * k)) << k;
  }
}

// The solver keys: pcg_fft where no lattice FFT solver applies, and either kind for a fixed lattice,
// are refused naming the key; LPSPH runs with each kind forced.
TEST(MovingParticles, SolverKindsAreRefusedWhereTheyDoNotApply) {
  // pcg_fft needs the lattice solver of the initial lattice (fft_poisson.hpp): it has one on every
  // domain kind, but not when the stencil reaches a wall from the lattice's middle (8 sites, 2h = 4 dx)
  FluidParams p = box(false, 8);
  p.h_over_dx = 2.0;
  p.poisson_solver = SolverKind::PcgFft;
  try {
    LagrangianFluid f(p);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("solver.poisson = \"pcg_fft\" does not apply"), std::string::npos) << e.what();
  }
  FluidParams e = box(true, 12);
  e.method = FluidMethod::Eulerian;
  e.cn_solver = SolverKind::PcgCholmod;
  try {
    make_fluid(e);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& ex) {
    EXPECT_NE(std::string(ex.what()).find("solver.crank_nicolson"), std::string::npos) << ex.what();
    EXPECT_NE(std::string(ex.what()).find("moving particles"), std::string::npos) << ex.what();
  }
  for (SolverKind k : {SolverKind::PcgCholmod, SolverKind::PcgFft}) {
    FluidParams q = box(true, 12);
    q.cn_solver = q.poisson_solver = k;
    LagrangianFluid f(q);
    const Mat2 F = Mat2::Constant(f.size(), 2, 1.0);
    for (int s = 0; s < 5; ++s) f.step(F);
    EXPECT_GT(f.u().cwiseAbs().maxCoeff(), 0.0);
    for (const auto& si : f.solver_info()) EXPECT_NE(si.method.find("CG preconditioned"), std::string::npos) << si.method;
  }
}

// LPSPH with the new solvers against the solvers that refactorise every step (CHOLMOD, forced):
// start-up Poiseuille, nx = 16, h = 1.525 dx, dt = 1.25e-6, 2000 steps. The velocity agrees to
// round-off; phi (a difference of nearly equal terms here: the flow is unidirectional, phi is noise
// of the divergence amplified by rho / dt) as closely as two direct solvers agree. Measured:
// |du| / |u| 1.6e-14, |dphi| / |phi| 3.6e-10 (CHOLMOD supernodal against simplicial, both
// refactorising: 9.1e-14 and 1.6e-9); tolerances 1e-12 and 1e-8.
TEST(MovingParticles, LpsphAgreesWithTheRefactorisingSolvers) {
  FluidParams p = box(true, 16);
  p.mu = 80.0;
  p.dt = 1.25e-6;
  FluidParams d = p;
  d.cn_solver = d.poisson_solver = SolverKind::CholmodSupernodal;
  LagrangianFluid a(p), b(d);
  const Mat2 F = [&] {
    Mat2 f = Mat2::Zero(a.size(), 2);
    f.col(0).setConstant(640.0);
    return f;
  }();
  for (int s = 0; s < 2000; ++s) {
    a.step(F);
    b.step(F);
  }
  EXPECT_LT((a.u() - b.u()).cwiseAbs().maxCoeff() / b.u().cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((a.phi() - b.phi()).cwiseAbs().maxCoeff() / b.phi().cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT((a.x() - b.x()).cwiseAbs().maxCoeff(), 1e-15);
}
