// Results do not depend on the thread count (fluid/common/threads.hpp): a few steps of the main scene on a
// lattice large enough for every threaded path (>= kParallelRows particles: the fused passes by row
// blocks, the lattice solvers by columns, row blocks and wavenumbers, the gauge's row sums, the body
// force, the kinetic energy's sum) give bitwise the same fields with one and two threads; the
// reductions by fixed blocks and the markers' interpolation by blocks of markers cover every entry.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cases/suspension.hpp"
#include "coupling/marker_update.hpp"
#include "coupling/simulation.hpp"
#include "coupling/spread.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/algebra/row_stencil.hpp"
#include "fluid/common/threads.hpp"
#include "io/scene.hpp"

using namespace sphib;

namespace {

struct State {
  Mat2 u, X, F;
  Vec p, phi;
  double ke, umax, divmax;
};

State run(const Scene& scene, int threads, int steps) {
  const ThreadCount count(threads);
  EXPECT_EQ(thread_count(), threads);
  Simulation sim(scene.sim);
  for (int n = 0; n < steps; ++n) sim.step();
  return {sim.fluid().u(), sim.membranes().at(0).m.X, sim.force(), sim.fluid().p(), sim.fluid().phi(),
          sim.fluid().kinetic_energy(), sim.fluid().max_speed(), sim.fluid().max_abs_divergence()};
}

bool same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && (a - b).cwiseAbs().maxCoeff() == 0.0;
}

}  // namespace

// The oscillating membrane (cases/membrane_oscillation.toml) at 96 x 96 with 192 markers, 4 steps of
// a coarse dt (a moving flow from the first step), on its channel (FFT in x + banded in y), in a
// closed box (DCT-II/DST-II in x + banded) and on a doubly periodic box (2-D FFT).
TEST(Threads, TwoThreadsGiveTheBitsOfOne) {
  const std::vector<std::vector<std::string>> domains = {
      {}, {"domain.periodic_x=false", "observe.exact=none"}, {"domain.periodic_y=true", "observe.exact=none"}};
  for (const auto& extra : domains) {
    std::vector<std::string> sets = {"grid.nx=96", "grid.ny=96", "membrane.nb=192", "time.dt=1e-3", "time.end=0.01"};
    sets.insert(sets.end(), extra.begin(), extra.end());
    const Scene scene = load_scene(std::string(SPHIB_SOURCE_DIR) + "/cases/membrane_oscillation.toml", sets);
    ASSERT_GE(96 * 96, kParallelRows);
    const State one = run(scene, 1, 4), two = run(scene, 2, 4);
    const std::string what = extra.empty() ? "channel" : extra[0];
    EXPECT_TRUE(same_bits(one.u, two.u)) << what;
    EXPECT_TRUE(same_bits(one.p, two.p)) << what;
    EXPECT_TRUE(same_bits(one.phi, two.phi)) << what;
    EXPECT_TRUE(same_bits(one.X, two.X)) << what;
    EXPECT_TRUE(same_bits(one.F, two.F)) << what;
    EXPECT_EQ(one.ke, two.ke) << what;  // (a sum by fixed blocks)
    EXPECT_EQ(one.umax, two.umax) << what;
    EXPECT_EQ(one.divmax, two.divmax) << what;
    EXPECT_EQ(one.umax, one.u.rowwise().norm().maxCoeff()) << what;  // by blocks of rows: exact
    EXPECT_GT(one.u.cwiseAbs().maxCoeff(), 0.0) << what;  // the membrane has set the fluid moving
  }
}

// The reductions by fixed blocks (fluid/common/threads.hpp) take every entry: the maximum is the
// one-pass maximum exactly wherever it lies (first, middle, last entry), the sum the one-pass sum
// up to its rounding (measured: 3.9e-16 relative for these 100003 positive entries; the test allows
// 1e-13, far below the 1e-5 that one dropped entry of the 100003 makes, 1.6e-2 one dropped block),
// both the same bits for one and two threads.
TEST(Threads, ReductionsByBlocksTakeEveryEntry) {
  const long n = 100003;  // blocks of 1563, the last one short
  std::mt19937 gen(28);
  std::uniform_real_distribution<double> U(0.5, 1.0);
  Vec v(n);
  for (long i = 0; i < n; ++i) v[i] = U(gen);
  const auto sum = [&](long at, long m) { return v.segment(at, m).sum(); };
  const auto max = [&](long at, long m) { return v.segment(at, m).maxCoeff(); };
  for (long top : {0L, n / 2, n - 1}) {
    Vec w = v;
    v[top] = 2.0;
    double s[2], m[2];
    for (int t : {1, 2}) {
      const ThreadCount count(t);
      s[t - 1] = sum_by_blocks(n, sum);
      m[t - 1] = max_by_blocks(n, max);
    }
    EXPECT_EQ(s[0], s[1]) << top;
    EXPECT_EQ(m[0], m[1]) << top;
    EXPECT_EQ(m[0], 2.0) << top;
    EXPECT_NEAR(s[0], v.sum(), 1e-13 * v.sum()) << top;
    v = w;
  }
}

// The markers' velocity by blocks of markers (Simulation::marker_velocity from 512 points, by the
// threads) is each point's own interpolation: 1300 points of the flow after 4 steps, with their
// gradients, bitwise those of one point at a time, for the divergence-free (with h and with the
// spreading's h*) and the B-spline interpolation, one and two threads. A point with no fluid particle near is named as one call names
// it: the first such point, numbered among all the points.
TEST(Threads, MarkerVelocityByBlocksIsEachMarkersOwn) {
  for (const char* interp : {"divergence_free", "bspline", "spreading_kernel"}) {
    const std::vector<std::string> sets = {"grid.nx=96", "grid.ny=96", "membrane.nb=192", "time.dt=1e-3",
                                           "coupling.interpolation=" + std::string(interp)};
    const Scene scene = load_scene(std::string(SPHIB_SOURCE_DIR) + "/cases/membrane_oscillation.toml", sets);
    Simulation sim(scene.sim);
    for (int n = 0; n < 4; ++n) sim.step();
    const int n = 1300;  // 5 blocks of 256 and one of 20
    Mat2 X(n, 2);
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> U(-1.2, 1.2);
    for (int k = 0; k < n; ++k) X.row(k) << U(gen), U(gen);
    Mat2 U1(n, 2), Ur;
    Jacobians d1(n, 4), dr;
    Mat2 Xk(1, 2), Uk(1, 2);
    Jacobians dk;
    for (int k = 0; k < n; ++k) {  // one point at a time: one call, no blocks
      Xk = X.row(k);
      ASSERT_TRUE(sim.marker_velocity(Xk, Uk, &dk));
      U1.row(k) = Uk;
      d1.row(k) = dk;
    }
    for (int t : {1, 2}) {
      const ThreadCount count(t);
      ASSERT_TRUE(sim.marker_velocity(X, Ur, &dr));
      EXPECT_TRUE(same_bits(Ur, U1)) << interp << ", " << t << " threads";
      EXPECT_TRUE(same_bits(dr, d1)) << interp << ", " << t << " threads";
      Mat2 Xbad = X;
      Xbad(900, 1) = 10.0;  // above the top wall: no particle within 2h (and a later one too)
      Xbad(1290, 1) = 10.0;
      try {
        sim.marker_velocity(Xbad, Ur);
        ADD_FAILURE() << interp << ": a point with no fluid near was not refused";
      } catch (const MarkerError& e) {
        EXPECT_EQ(e.marker, 900) << interp << ", " << t << " threads";
      }
    }
    EXPECT_GT(U1.cwiseAbs().maxCoeff(), 0.0) << interp;  // the flow moves
  }
}

// The spreading on the lattice by the threads (coupling/spread.cpp: from 256 markers, each thread
// adding into its own lattice rows) gives every point its markers' terms in the serial order: 1000
// markers spread at once into a 96 x 96 lattice equal, bit for bit, the same markers spread one at a
// time (the serial path), with one and two threads, on a channel and a doubly periodic box (rows
// wrapping across the box).
TEST(Threads, SpreadingByRowsIsTheSerialSum) {
  for (bool py : {false, true}) {
    Domain d;  // [0, 1]^2
    d.periodic_x = true;
    d.periodic_y = py;
    const Lattice L = make_lattice(d, 96, 96);
    ASSERT_GE(L.size(), kParallelRows);
    CellGrid g(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), true, py, std::min(L.dx, L.dy));
    g.use_lattice(L);
    const CubicSplineKernel W(2.0 * L.dx);  // h* = 2 dx: support 4 dx
    const int n = 1000;
    Mat2 X(n, 2), P(n, 2), F0(L.size(), 2);
    std::mt19937 gen(3);
    std::uniform_real_distribution<double> U(0.0, 1.0), V(0.1, 0.9), S(-1.0, 1.0);
    for (int k = 0; k < n; ++k) X.row(k) << U(gen), py ? U(gen) : V(gen);  // off the walls by 2h* without py
    for (int k = 0; k < n; ++k) P.row(k) << S(gen), S(gen);
    for (int i = 0; i < L.size(); ++i) F0.row(i) << S(gen), S(gen);
    Mat2 ref = F0, Xk(1, 2), Pk(1, 2);
    for (int k = 0; k < n; ++k) {
      Xk = X.row(k);
      Pk = P.row(k);
      spread_point_forces(g, W, Xk, Pk, ref);
    }
    for (int t : {1, 2}) {
      const ThreadCount count(t);
      Mat2 F = F0;
      spread_point_forces(g, W, X, P, F);
      EXPECT_TRUE(same_bits(F, ref)) << "periodic_y " << py << ", " << t << " threads";
    }
    EXPECT_GT((ref - F0).cwiseAbs().maxCoeff(), 0.0);
  }
}

// The membranes' elastic forces by the threads (Simulation::elastic_forces: from 512 markers in two or
// more membranes, the membranes shared out) are each membrane's own: 16 capsules of 64 markers in a
// sheared 64^2 box (cases/suspension.hpp, contact on), 3 steps, give bitwise the same forces,
// tensions, markers and flow with one and two threads.
TEST(Threads, ElasticForcesByMembranesAreEachMembranesOwn) {
  SuspensionParams p;
  p.count = 16;
  p.nx = 64;
  p.contact_strength = 0.1;
  const Scene scene = suspension_scene(p);
  std::vector<Mat2> f[2], X[2];
  std::vector<Vec> T[2];
  Mat2 u[2];
  for (int t : {1, 2}) {
    const ThreadCount count(t);
    Simulation sim(scene.sim);
    ASSERT_EQ(sim.membranes().size(), 16u);
    for (int n = 0; n < 3; ++n) sim.step();
    for (const auto& m : sim.membranes()) f[t - 1].push_back(m.f), X[t - 1].push_back(m.m.X), T[t - 1].push_back(m.T);
    u[t - 1] = sim.fluid().u();
  }
  for (size_t k = 0; k < 16; ++k) {
    EXPECT_TRUE(same_bits(f[0][k], f[1][k])) << "membrane " << k;
    EXPECT_TRUE(same_bits(T[0][k], T[1][k])) << "membrane " << k;
    EXPECT_TRUE(same_bits(X[0][k], X[1][k])) << "membrane " << k;
  }
  EXPECT_TRUE(same_bits(u[0], u[1]));
  EXPECT_GT(f[0][0].cwiseAbs().maxCoeff(), 0.0);  // the capsules are loaded
}
