// Suspensions: many membranes as one set of markers (spreading, interpolation and the marker update
// give bit for bit what they give membrane by membrane), the contact force (coupling/contact.hpp:
// equal and opposite, zero beyond its range, growing as membranes approach, found by its cell list
// as by brute force), two capsules brought together by a shear flow kept apart, the random placement
// (membrane/packing.hpp), the walls' shear stress (fluid/common/loads.hpp) and the [contact] scene keys.
// Every tolerance is a measured value with a margin, stated beside it; round-off checks say so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <string>

#include "coupling/contact.hpp"
#include "coupling/interpolate.hpp"
#include "coupling/marker_update.hpp"
#include "coupling/simulation.hpp"
#include "coupling/spread.hpp"
#include "fluid/common/loads.hpp"
#include "helpers.hpp"
#include "io/run.hpp"
#include "io/scene_checks.hpp"
#include "membrane/geometry.hpp"
#include "membrane/packing.hpp"
#include "membrane/polygon.hpp"
#include "membrane/shapes.hpp"
#include "scene_refusal.hpp"

using namespace sphib;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A sheared unit box, periodic in x, walls y = 0, 1 sliding at -+U/2, n x n particles, fluid in
// Couette flow; membranes of radius a at the centres c (Hookean, at rest, T0), nb markers each.
SimulationParams sheared_box(int n, const std::vector<Eigen::Vector2d>& c, double a, int nb, double T0,
                             double U = 1.0) {
  SimulationParams p;
  FluidParams& f = p.fluid;
  f.domain = {0.0, 1.0, 0.0, 1.0, true, false};
  f.domain.wall_velocity[Top] = {U / 2, 0.0};
  f.domain.wall_velocity[Bottom] = {-U / 2, 0.0};
  f.nx = f.ny = n;
  f.rho = f.mu = 1.0;
  f.dt = 0.25 / n / U;
  p.initial_velocity = [U](double, double y) { return Eigen::Vector2d(U * (y - 0.5), 0.0); };
  const double h_star = 1.4 * f.h_over_dx / n;
  for (const auto& ck : c) p.membranes.push_back({make_membrane(circle(nb, ck.x(), ck.y(), a), a, T0), h_star});
  return p;
}

// The markers of several membranes concatenated, and their rows.
void concatenate(const std::vector<Mat2>& X, Mat2& all, std::vector<int>& start) {
  start.assign(1, 0);
  for (const Mat2& x : X) start.push_back(start.back() + static_cast<int>(x.rows()));
  all.resize(start.back(), 2);
  for (size_t k = 0; k < X.size(); ++k) all.middleRows(start[k], X[k].rows()) = X[k];
}

}  // namespace

// ---- one set of markers

TEST(Suspension, OneSetSpreadsAndInterpolatesAsMembraneByMembrane) {
  // Three membranes of different sizes, one across the periodic seam; the lattice's index boxes
  // (EPSPH) and the cell grid (moving particles) both: bit for bit (==), as the passes are per marker.
  SimulationParams p = sheared_box(48, {{0.3, 0.4}, {0.7, 0.6}, {0.98, 0.35}}, 0.12, 40, 1.0);
  Simulation sim(p);
  for (int s = 0; s < 3; ++s) sim.step();  // a flow that is not Couette's alone
  const FluidSolver& fl = sim.fluid();
  std::vector<Mat2> X, f;
  std::vector<double> ds;
  for (const auto& m : sim.membranes()) X.push_back(m.m.X), f.push_back(m.f), ds.push_back(m.m.ds());
  Mat2 Xa, P;
  std::vector<int> start;
  concatenate(X, Xa, start);
  P.resize(Xa.rows(), 2);
  for (size_t k = 0; k < X.size(); ++k) P.middleRows(start[k], X[k].rows()) = f[k] * ds[k];
  const Domain& d = fl.params().domain;
  for (bool lattice : {true, false}) {
    SCOPED_TRACE(lattice ? "lattice boxes" : "cell grid");
    CellGrid grid(Eigen::Vector2d(d.x0, d.y0), Eigen::Vector2d(d.x1, d.y1), d.periodic_x, d.periodic_y, fl.lattice().dx);
    if (lattice) grid.use_lattice(fl.lattice());
    else grid.build(fl.x());
    const CubicSplineKernel& W = sim.membranes()[0].W_star;
    Mat2 F1 = Mat2::Zero(fl.size(), 2), F2 = F1;
    for (size_t k = 0; k < X.size(); ++k) spread_force(grid, W, X[k], f[k], ds[k], F1);
    spread_point_forces(grid, W, Xa, P, F2);
    EXPECT_EQ((F1 - F2).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_GT(F1.cwiseAbs().maxCoeff(), 0.0);
    const StreamFunction sf = fl.stream_function();
    Mat2 U1(Xa.rows(), 2), U2(Xa.rows(), 2), Uk;
    Jacobians J1(Xa.rows(), 4), J2, Jk;
    for (int kind = 0; kind < 3; ++kind) {
      if (kind == 1 && !lattice) continue;  // B-splines need the lattice's index boxes
      for (size_t k = 0; k < X.size(); ++k) {
        Uk.resize(X[k].rows(), 2);
        if (kind == 0) interpolate_curl(grid, fl.kernel(), *sf.psi, sf.mean, X[k], Uk, &Jk);
        if (kind == 1) interpolate_curl_bspline(grid, fl.lattice().dx, fl.lattice().dy, *sf.psi, sf.mean, X[k], Uk, &Jk);
        if (kind == 2) interpolate_velocity(grid, fl.kernel(), fl.volumes(), fl.u(), X[k], Uk);
        U1.middleRows(start[k], X[k].rows()) = Uk;
        if (kind < 2) J1.middleRows(start[k], X[k].rows()) = Jk;
      }
      if (kind == 0) interpolate_curl(grid, fl.kernel(), *sf.psi, sf.mean, Xa, U2, &J2);
      if (kind == 1) interpolate_curl_bspline(grid, fl.lattice().dx, fl.lattice().dy, *sf.psi, sf.mean, Xa, U2, &J2);
      if (kind == 2) interpolate_velocity(grid, fl.kernel(), fl.volumes(), fl.u(), Xa, U2);
      EXPECT_EQ((U1 - U2).cwiseAbs().maxCoeff(), 0.0) << kind;
      if (kind < 2) EXPECT_EQ((J1 - J2).cwiseAbs().maxCoeff(), 0.0) << kind;
    }
  }
}

TEST(Suspension, OneSetMarkerUpdateIsEachMembranesOwn) {
  // advance_markers with the membranes as groups of one set gives each membrane's own update bit
  // for bit, here with groups that take different numbers of iterations (a slow and a fast flow),
  // by the fixed-point step and by the Newton step.
  auto field = [](const Mat2& X, Mat2& U, Jacobians* dU) {  // u = (sin y, 0.3 cos x) * (1 + 30 [x > 0.5])
    if (dU) dU->resize(X.rows(), 4);
    for (int k = 0; k < X.rows(); ++k) {
      const double s = X(k, 0) > 0.5 ? 31.0 : 1.0, x = X(k, 0), y = X(k, 1);
      U(k, 0) = s * std::sin(3 * y);
      U(k, 1) = s * 0.3 * std::cos(3 * x);
      if (dU) (*dU).row(k) << 0.0, 3 * s * std::cos(3 * y), -0.9 * s * std::sin(3 * x), 0.0;
    }
    return dU != nullptr;
  };
  std::vector<Mat2> X{circle(16, 0.25, 0.5, 0.1), circle(24, 0.75, 0.5, 0.1), circle(16, 0.25, 0.2, 0.05)};
  for (bool newton : {false, true}) {
    MarkerUpdateParams prm;
    prm.max_move = 0.05;
    prm.newton = newton;
    if (newton) prm.linear_step = 1e-9;  // (the groups differ in their Newton steps below this)
    const double dt = 1e-3;
    Mat2 Xa, Ua, Upa, Xn, U;
    std::vector<int> start;
    std::vector<Mat2> Un(X.size()), Up(X.size());
    for (size_t k = 0; k < X.size(); ++k) {
      Un[k].resize(X[k].rows(), 2);
      field(X[k], Un[k], nullptr);
      Up[k] = 0.98 * Un[k];
    }
    concatenate(X, Xa, start);
    concatenate(Un, Ua, start);
    concatenate(Up, Upa, start);
    MarkerWork w;
    U.resize(Xa.rows(), 2);
    advance_markers(field, Ua, &Upa, dt, prm, 1, Xa, Xn, U, w, &start);
    std::set<int> iterations;
    for (size_t k = 0; k < X.size(); ++k) {
      Mat2 Xk = X[k], Xnk, Uk(X[k].rows(), 2);
      MarkerWork wk;
      const MarkerUpdateResult r = advance_markers(field, Un[k], &Up[k], dt, prm, 1, Xk, Xnk, Uk, wk);
      EXPECT_EQ((Xk - Xa.middleRows(start[k], X[k].rows())).cwiseAbs().maxCoeff(), 0.0) << k;
      EXPECT_EQ((Uk - U.middleRows(start[k], X[k].rows())).cwiseAbs().maxCoeff(), 0.0) << k;
      EXPECT_EQ(r.iterations, w.results[k].iterations) << k;
      EXPECT_EQ(r.interpolations, w.results[k].interpolations) << k;
      EXPECT_EQ(r.residual, w.results[k].residual) << k;
      EXPECT_EQ(r.linearised, w.results[k].linearised) << k;
      iterations.insert(r.interpolations);
    }
    EXPECT_GT(iterations.size(), 1u) << "the groups should differ in their iterations";
  }
}

// The Newton step of the marker update (solver.marker_newton, coupling/marker_update.hpp) in a
// sheared box with four capsules like the suspension case's (64^2, radius 5 dx, 64 markers, Ca 0.1,
// dt = 0.5 dx/U, B-spline interpolation), 300 steps, linear_step 1e-4: every step after the first
// two is accepted after one interpolation (the fixed point with the library's defaults: measured
// 2.118 interpolations per step). Eq. (59)'s true residual (U^{n+1} interpolated again at X^{n+1}):
// measured max 4.9e-15 over steps 1-299, 5.4e-13 at step 0 (Eq. 58's predictor, O(dt^2) from the
// root: the largest Newton step); the linearised U^{n+1}(X^{n+1}) against that interpolation:
// measured 6.1e-13 (|U| <= 0.5); the markers after 300 steps against the fixed point's: 1.6e-11
// apart. Tolerances: 2e-14, eps (1e-12), 2e-12, 1e-10.
TEST(Suspension, NewtonStepMeetsTheToleranceWithOneInterpolation) {
  const int n = 64;
  const double a = 5.0 / n;
  const std::vector<Eigen::Vector2d> c{{0.3, 0.3}, {0.45, 0.42}, {0.6, 0.58}, {0.75, 0.7}};
  SimulationParams p = sheared_box(n, c, a, 64, a / 0.1);
  p.fluid.dt = 0.5 / n;
  p.interpolation = MarkerInterpolation::BSpline;
  SimulationParams q = p;
  p.markers.newton = true;
  p.markers.linear_step = 1e-4;
  Simulation sim(p), ref(q);
  const int steps = 300;
  double worst_g = 0, worst_U = 0, first_g = 0;  // steps 1.., and step 0 (its predictor is Eq. 58's)
  int accepted = 0;
  for (int s = 0; s < steps; ++s) {
    sim.step();
    ref.step();
    for (const MembraneState& m : sim.membranes()) {
      Mat2 U(m.m.nb(), 2);
      sim.marker_velocity(m.m.X, U);
      const double g = (m.m.X - m.X_n - 0.5 * p.fluid.dt * (m.U_n + U)).rowwise().norm().maxCoeff();
      if (s == 0) {
        first_g = std::max(first_g, g);
        continue;
      }
      worst_U = std::max(worst_U, (U - m.U).cwiseAbs().maxCoeff());
      worst_g = std::max(worst_g, g);
      accepted += s >= 2 && m.last.linearised && m.last.interpolations == 1;
    }
  }
  double dX = 0, ref_interp = 0;
  for (size_t k = 0; k < c.size(); ++k) {
    dX = std::max(dX, (sim.membranes()[k].m.X - ref.membranes()[k].m.X).cwiseAbs().maxCoeff());
    ref_interp += static_cast<double>(ref.membranes()[k].interpolations) / steps / c.size();
  }
  std::printf("Newton: true residual %.3g (step 0: %.3g), U %.3g, markers %.3g from the fixed point's (%.3f "
              "interpolations per step), %d of %d accepted after one\n", worst_g, first_g, worst_U, dX, ref_interp, accepted,
              static_cast<int>((steps - 2) * c.size()));
  EXPECT_EQ(accepted, static_cast<int>((steps - 2) * c.size()));
  EXPECT_GT(ref_interp, 2.0);
  EXPECT_LT(first_g, p.markers.eps);
  EXPECT_LT(worst_g, 2e-14);
  EXPECT_LT(worst_U, 2e-12);
  EXPECT_LT(dX, 1e-10);
  // the scene key: off by default
  const std::string scene = std::string(SPHIB_SOURCE_DIR) + "/cases/membrane_oscillation.toml";
  EXPECT_FALSE(load_scene(scene).sim.markers.newton);
  EXPECT_TRUE(load_scene(scene, {"solver.marker_newton=true"}).sim.markers.newton);
}

TEST(Suspension, MarkerUpdateErrorsNameTheMembraneAndItsMarker) {
  // Marker 5 of the second of two membranes (one set) given a wild velocity history: the extrapolated
  // predictor moves it by more than a lattice spacing, and the update refuses it, naming it.
  SimulationParams p = sheared_box(32, {{0.3, 0.5}, {0.7, 0.5}}, 0.1, 32, 1.0);
  Simulation sim(p);
  sim.step();
  Mat2 U = sim.membranes()[1].U_n;
  U(5, 0) = 1e3;
  sim.set_marker_history(1, U);
  try {
    sim.step();
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("membrane 1: blow-up at step 2: marker 5 would move"), std::string::npos) << m;
    return;
  }
  ADD_FAILURE() << "the step was not refused";
}

// ---- the contact force

TEST(Suspension, ContactForceIsEqualAndOppositeAndFoundByItsCellList) {
  // Random markers of four membranes in a box periodic in x, crowded near the seam: the cell list
  // finds the pairs brute force finds (the force agrees to round-off: 5.8e-16 of the largest,
  // measured), the total force of the pairs is zero to round-off (|sum f ds| / sum |f ds| measured
  // 2.1e-17), and the least distance is brute force's to the last bit or so.
  Domain d;
  d.periodic_x = true;
  d.periodic_y = false;
  ContactParams cp;
  cp.strength = 2.0;
  cp.range = 0.05;
  cp.walls = false;
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Mat2> X(4);
  for (auto& x : X) {
    x.resize(200, 2);
    for (int k = 0; k < 200; ++k) x.row(k) << std::fmod(0.9 + 0.2 * u(g), 1.0), 0.3 + 0.4 * u(g);
  }
  Mat2 Xa;
  std::vector<int> start;
  concatenate(X, Xa, start);
  const std::vector<double> ds{0.01, 0.02, 0.015, 0.01};
  ContactForce c(cp, d);
  Mat2 f = Mat2::Zero(Xa.rows(), 2);
  c.add(Xa, start, ds, f);
  // brute force
  Mat2 fb = Mat2::Zero(Xa.rows(), 2);
  double least = INFINITY;
  long pairs = 0;
  auto owner = [&](int i) { return static_cast<int>(std::upper_bound(start.begin(), start.end(), i) - start.begin()) - 1; };
  for (int i = 0; i < Xa.rows(); ++i)
    for (int j = i + 1; j < Xa.rows(); ++j) {
      if (owner(i) == owner(j)) continue;
      double dx = Xa(i, 0) - Xa(j, 0), dy = Xa(i, 1) - Xa(j, 1);
      dx -= std::round(dx);
      const double r = std::hypot(dx, dy);
      if (r >= cp.range) continue;
      ++pairs;
      least = std::min(least, r);
      const double phi = morse_repulsion(cp, r) / r;
      fb.row(i) += phi * Eigen::RowVector2d(dx, dy) * ds[owner(j)];
      fb.row(j) -= phi * Eigen::RowVector2d(dx, dy) * ds[owner(i)];
    }
  ASSERT_GT(pairs, 100);
  EXPECT_EQ(c.pairs(), pairs);
  EXPECT_NEAR(c.least_distance(), least, 1e-16);  // (from wrapped coordinates: the last bit may differ)
  EXPECT_LE((f - fb).cwiseAbs().maxCoeff(), 1e-13 * fb.cwiseAbs().maxCoeff());
  Eigen::RowVector2d total = Eigen::RowVector2d::Zero();
  double size = 0.0;
  for (int i = 0; i < Xa.rows(); ++i) {
    total += f.row(i) * ds[owner(i)];
    size += f.row(i).norm() * ds[owner(i)];
  }
  EXPECT_LE(total.norm(), 1e-14 * size) << total;
  EXPECT_NEAR(least_marker_distance(Xa, start, d, cp.range), least, 1e-16);
}

TEST(Suspension, ContactForceIsZeroBeyondItsRangeAndGrowsAsMembranesApproach) {
  Domain d;  // unit box, periodic in x, walls in y
  ContactParams cp;
  cp.strength = 1.0;
  cp.range = 0.04;
  cp.walls = false;
  ContactForce c(cp, d);
  EXPECT_EQ(morse_repulsion(cp, cp.range), 0.0);
  EXPECT_EQ(morse_repulsion(cp, 2 * cp.range), 0.0);
  double last = 0.0;
  for (double gap : {0.05, 0.04, 0.035, 0.03, 0.02, 0.01, 0.005, 0.001}) {
    SCOPED_TRACE(gap);
    // two circles of radius 0.1 side by side, gap apart
    Mat2 X;
    std::vector<int> start;
    concatenate({circle(64, 0.4, 0.5, 0.1), circle(64, 0.6 + gap, 0.5, 0.1)}, X, start);
    Mat2 f = Mat2::Zero(X.rows(), 2);
    c.add(X, start, {2 * kPi * 0.1 / 64, 2 * kPi * 0.1 / 64}, f);
    const double push = f.topRows(64).col(0).sum();  // on the left circle, along x
    if (gap >= cp.range) {
      EXPECT_EQ(f.cwiseAbs().maxCoeff(), 0.0);
      continue;
    }
    EXPECT_LT(push, 0.0);  // to the left: away from the other
    EXPECT_GT(-push, last);
    last = -push;
    EXPECT_NEAR(f.bottomRows(64).col(0).sum(), -push, 1e-12 * last);  // equal and opposite (same ds; 1.8e-16 measured)
  }
  // a wall pushes a marker within range off, inwards, and none beyond
  ContactParams cw = cp;
  cw.walls = true;
  ContactForce w(cw, d);
  Mat2 X(3, 2), f = Mat2::Zero(3, 2);
  X << 0.5, 0.01, 0.5, 0.5, 0.5, 0.98;
  w.add(X, {0, 1, 2, 3}, {0.01, 0.01, 0.01}, f);
  EXPECT_GT(f(0, 1), 0.0);
  EXPECT_EQ(f(1, 1), 0.0);
  EXPECT_LT(f(2, 1), 0.0);
  EXPECT_EQ(f.col(0).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Suspension, ContactKeepsTwoCapsulesDrivenTogetherApart) {
  // Two capsules side by side (radius 0.1, 48 markers, T0 = 1, 64^2, dx = 1/64) driven together by a
  // cellular flow: a body force f0 curl psi, psi = -sin(2 pi x) sin(2 pi y), f0 = 60, whose
  // stagnation point at the box's centre squeezes them along x. Without the contact force they press
  // into each other (least distance between their markers over 400 steps measured 0.149 dx; run on,
  // they pass through each other, 1e-5 dx at step 1429); with contact.strength = 300 (range 2 dx)
  // the least distance is 1.11 dx (reached at step 119) and their outlines never meet.
  const double a = 0.1, dx = 1.0 / 64;
  double least[2];
  for (int with : {0, 1}) {
    SimulationParams p = sheared_box(64, {{0.35, 0.5}, {0.65, 0.5}}, a, 48, 1.0, 0.0);
    p.fluid.dt = 1e-3;
    p.body_force_field = [](double x, double y, double) {
      const double f0 = 60.0;
      return Eigen::Vector2d(-f0 * 2 * kPi * std::sin(2 * kPi * x) * std::cos(2 * kPi * y),
                             f0 * 2 * kPi * std::cos(2 * kPi * x) * std::sin(2 * kPi * y));
    };
    if (with) p.contact = {300.0, 2 * dx, 0.0, true};
    Simulation sim(p);
    least[with] = INFINITY;
    Mat2 X;
    std::vector<int> start;
    for (int s = 0; s < 400; ++s) {
      sim.step();
      concatenate({sim.membranes()[0].m.X, sim.membranes()[1].m.X}, X, start);
      least[with] = std::min(least[with], least_marker_distance(X, start, p.fluid.domain, 0.2));
      if (with) ASSERT_TRUE(membranes_cross({{sim.membranes()[0].m, 0.01}, {sim.membranes()[1].m, 0.01}}, p.fluid.domain).empty()) << s;
    }
    if (with) EXPECT_EQ(sim.contact()->least_distance_so_far(), least[with]);  // its own record, every step
  }
  std::printf("least distance without contact %g dx, with %g dx\n", least[0] / dx, least[1] / dx);
  EXPECT_LT(least[0], 0.3 * dx);
  EXPECT_GT(least[1], 1.0 * dx);
}

// ---- the random placement, the walls' shear stress, the scene keys

TEST(Suspension, RandomDisksAreReproducibleAndDoNotOverlap) {
  DiskPacking p;
  p.count = 100;
  p.radius = std::sqrt(0.3 / (100 * kPi));
  p.gap = 0.01;
  p.wall_gap = 0.02;
  const Eigen::MatrixX2d c = random_disks(p);
  EXPECT_GE(least_disk_gap(c, p), p.gap);
  EXPECT_GE(c.col(1).minCoeff(), p.y0 + p.radius + p.wall_gap);
  EXPECT_LE(c.col(1).maxCoeff(), p.y1 - p.radius - p.wall_gap);
  EXPECT_EQ((random_disks(p) - c).cwiseAbs().maxCoeff(), 0.0);  // the same seed, the same centres
  p.seed = 2;
  EXPECT_GT((random_disks(p) - c).cwiseAbs().maxCoeff(), 0.0);
  p.count = 400;  // area fraction 1.2: refused, naming what was asked
  p.max_attempts = 20000;
  try {
    random_disks(p);
    ADD_FAILURE() << "an impossible packing was not refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("area fraction"), std::string::npos) << e.what();
  }
}

TEST(Suspension, WallShearStressOfCouetteFlowIsMuTimesTheShearRate) {
  // Plain Couette flow in its steady state (the initial linear profile, five steps on): mu G on both
  // walls, to the solves' round-off (relative errors measured 4.5e-13 bottom, 2.0e-15 top).
  SimulationParams p = sheared_box(32, {}, 0.1, 16, 1.0, 2.0);
  p.fluid.mu = 0.7;
  Simulation sim(p);
  for (int s = 0; s < 5; ++s) sim.step();
  const WallForces tau = wall_shear_stress(sim.fluid().lattice(), sim.fluid().u(), p.fluid.mu);
  EXPECT_NEAR(tau[Bottom], 0.7 * 2.0, 1.4e-11);
  EXPECT_NEAR(tau[Top], 0.7 * 2.0, 1.4e-11);
  EXPECT_TRUE(std::isnan(tau[Left]) && std::isnan(tau[Right]));
}

TEST(Suspension, LoadsOfACouetteRunGiveItsViscosity) {
  // cases/couette.toml (top wall sliding, mu = 1) with observe.loads: the columns shear_bottom,
  // shear_top and mu_eff, and at t = 1.5 the wall stresses mu U / l = 1 (measured 1 -+ 7.3e-7: the
  // last of the start-up, antisymmetric) and mu_eff, their mean over U / l, 1 (measured 1 + 5e-13).
  const std::string scene = std::string(SPHIB_SOURCE_DIR) + "/cases/couette.toml";
  const Scene s = load_scene(scene, {"observe.loads=true", "time.dt=1e-3", "time.end=1.5"});
  RunOptions opt;
  opt.out_dir = sphib_test::temp_dir("couette_loads").string();
  const nlohmann::json j = run_scene(s, opt);
  const std::string csv = sphib_test::slurp(std::filesystem::path(opt.out_dir) / "diagnostics.csv");
  const std::string header = csv.substr(0, csv.find('\n'));
  for (const char* c : {"shear_bottom", "shear_top", "mu_eff"}) EXPECT_NE(header.find(c), std::string::npos) << c;
  EXPECT_NEAR(j["mu_eff"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(j["shear_bottom"].get<double>(), 1.0, 1e-5);
  EXPECT_NEAR(j["shear_top"].get<double>(), 1.0, 1e-5);
}

TEST(Suspension, ContactKeysAreReadAndBadOnesRefusedByName) {
  const std::string scene = R"(
[domain]
x = [0.0, 1.0]
y = [0.0, 1.0]
[grid]
nx = 32
ny = 32
[fluid]
rho = 1.0
mu = 1.0
[time]
dt = 1e-3
end = 0.01
[[membranes]]
centre = [0.3, 0.5]
r0 = 0.1
T0 = 1.0
nb = 32
[[membranes]]
centre = [0.7, 0.5]
r0 = 0.1
T0 = 1.0
nb = 32
)";
  using sphib::test::refusal;
  EXPECT_EQ(refusal(scene), "");
  const Scene s = parse_scene(scene, "scene.toml", {"contact.strength=2"});
  EXPECT_EQ(s.sim.contact.strength, 2.0);
  EXPECT_DOUBLE_EQ(s.sim.contact.range, 2.0 / 32);  // the default: two lattice spacings
  EXPECT_TRUE(s.sim.contact.walls);
  EXPECT_FALSE(parse_scene(scene, "scene.toml").sim.contact.on());  // off by default
  for (const char* bad : {"contact.strength=-1", "contact.range=-0.1", "contact.beta=-2", "contact.walls=3",
                          "contact.range=0.5", "contact.strength=nan"}) {
    const std::string m = refusal(scene, {bad});
    const std::string key = std::string(bad).substr(0, std::string(bad).find('='));
    EXPECT_NE(m.find(key), std::string::npos) << bad << ": " << m;
  }
  EXPECT_NE(refusal(scene, {"contact.stength=1"}).find("contact.stength"), std::string::npos);
  // no membranes to push
  const std::string none = scene.substr(0, scene.find("[[membranes]]"));
  EXPECT_NE(refusal(none, {"contact.strength=1"}).find("contact.strength"), std::string::npos);
}

// AreaKeeper::rate (membrane/geometry.hpp) is the derivative of the spline curve's enclosed area
// along U: the area is quadratic in X, so the central difference (A(X + e U) - A(X - e U)) / 2e is
// exact but for rounding. A wavy ellipse of 40 markers, a smooth U with a net outflow: measured
// 4.0e-12 relative to |dA/dt| = 0.426 (e = 1e-4: the area's rounding over 2e). keep() on a step from
// X^n to X = X^n + dt/2 (U^n + U) makes the step keep the area: grad A(X_mid) . (U^n + U) is then
// measured 0, the area of X^n + dt/2 (U^n + U) (U as kept, at the step's root) equals A(X^n)
// to measured 2.2e-16 relative (3.6e-2 without), and what it removed (largest component 0.328) is
// c grad A(X_mid), grad A by central differences of the area marker by marker: measured 5.2e-11 of it
// apart (their rounding).
TEST(Suspension, AreaKeeperHoldsTheAreaOfATrapezoidalStep) {
  const int nb = 40;
  Mat2 X(nb, 2), U(nb, 2), Un(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double t = 2 * M_PI * k / nb, r = 1 + 0.1 * std::cos(3 * t);
    X.row(k) << 0.3 + 0.5 * r * std::cos(t), -0.2 + 0.3 * r * std::sin(t);
    U.row(k) << 0.7 * X(k, 0) + std::sin(2 * X(k, 1)), 0.2 * X(k, 1) - 0.4 * X(k, 0) * X(k, 0);
    Un.row(k) << 0.5 * U(k, 0) + 0.1 * X(k, 1), 0.8 * U(k, 1);
  }
  MembraneDiagnostics D(nb, 2.5);
  AreaKeeper keeper(nb);
  const double e = 1e-4, rate = keeper.rate(X, U);
  Mat2 Xp = X + e * U, Xm = X - e * U;
  const double fd = (D.measure(Xp).area - D.measure(Xm).area) / (2 * e);
  EXPECT_GT(std::fabs(rate), 0.3);
  EXPECT_LT(std::fabs(rate - fd), 4e-11 * std::fabs(rate));  // measured 4.0e-12
  const double dt = 0.05, A0 = D.measure(X).area;
  const double free_change = std::fabs(D.measure(Mat2(X + 0.5 * dt * (Un + U))).area / A0 - 1);
  Mat2 V = U, X1 = X;
  for (int it = 0; it < 60; ++it) {  // the step's root with U (here independent of X) kept at each iterate
    X1 = X + 0.5 * dt * (Un + V);
    V = U;
    keeper.keep(X, Un, X1, V);
  }
  X1 = X + 0.5 * dt * (Un + V);
  const Mat2 mid = 0.5 * (X + X1);
  const double kept_rate = keeper.rate(mid, Un + V);
  const double kept_change = std::fabs(D.measure(Mat2(X + 0.5 * dt * (Un + V))).area / A0 - 1);
  EXPECT_GT(free_change, 1e-3);
  EXPECT_LT(std::fabs(kept_rate), 1e-14);  // measured 0
  EXPECT_LT(kept_change, 1e-14);           // measured 2.2e-16
  double worst = 0.0, scale = 0.0, c = 0.0;
  for (int k = 0; k < nb; ++k)
    for (int d = 0; d < 2; ++d) {
      Mat2 P = mid, Q = mid;
      P(k, d) += e;
      Q(k, d) -= e;
      const double g = (D.measure(P).area - D.measure(Q).area) / (2 * e);
      if (k == 0 && d == 0) c = (U(k, d) - V(k, d)) / g;
      worst = std::max(worst, std::fabs(U(k, d) - V(k, d) - c * g));
      scale = std::max(scale, std::fabs(U(k, d) - V(k, d)));
    }
  EXPECT_GT(scale, 0.01);
  EXPECT_LT(worst, 1e-9 * scale);  // measured 5.2e-11
}

// The marker update's area constraint (MarkerUpdateParams::keep_area, coupling/marker_update.hpp) on
// a membrane of 16 markers carried by the cellular flow psi = sin(pi x) sin(pi y) / pi (exactly
// divergence-free: the true curve keeps its area) from t = 0 to 1: without it the spline's area drifts
// by the markers' spacing (measured 6.21e-5 and 6.28e-5 at dt = 0.02 and 0.01: not the step's); with
// it every step keeps the area to the update's residual (|g| <= eps = 1e-12 per marker, some 1e-12 of
// the area a step): measured 6.9e-11 and 6.4e-13. Tolerances: the drift above 3e-5, the kept error
// below 1e-9.
TEST(Suspension, KeepAreaHoldsTheEnclosedAreaAtAnyStep) {
  auto cellular = [](const Mat2& X, Mat2& U, Jacobians*) {
    for (int k = 0; k < X.rows(); ++k) {
      const double x = M_PI * X(k, 0), y = M_PI * X(k, 1);
      U(k, 0) = std::sin(x) * std::cos(y);
      U(k, 1) = -std::cos(x) * std::sin(y);
    }
    return false;
  };
  const int nb = 16;
  const double r = 0.2, L0 = 2 * M_PI * r;
  auto run = [&](bool keep, double dt, double& err) {
    Mat2 X = circle(nb, 0.45, 0.4, r), Xn, U(nb, 2), Un(nb, 2), Up(nb, 2);
    MarkerUpdateParams prm;
    prm.max_move = 0.1;
    MarkerWork w;
    AreaKeeper keeper(nb);
    MembraneDiagnostics D(nb, L0);
    const double A0 = D.measure(X).area;
    const MarkerConstraint constrain = [&](int, Eigen::Ref<const Mat2> Xa, Eigen::Ref<const Mat2> Ua,
                                           Eigen::Ref<const Mat2> Xg, Eigen::Ref<Mat2> Ug) { keeper.keep(Xa, Ua, Xg, Ug); };
    cellular(X, Un, nullptr);
    const int steps = static_cast<int>(std::lround(1.0 / dt));
    for (int n = 0; n < steps; ++n) {
      advance_markers(cellular, Un, n ? &Up : nullptr, dt, prm, n, X, Xn, U, w, nullptr, keep ? &constrain : nullptr);
      Up = Un;
      Un = U;
    }
    err = std::fabs(D.measure(X).area / A0 - 1);
  };
  double free1, free2, kept1, kept2;
  run(false, 0.02, free1);
  run(false, 0.01, free2);
  run(true, 0.02, kept1);
  run(true, 0.01, kept2);
  std::printf("area error at t = 1: free %.3g, %.3g; kept %.3g, %.3g (dt = 0.02, 0.01)\n", free1, free2, kept1, kept2);
  EXPECT_GT(free2, 3e-5);  // the drift the constraint removes
  EXPECT_LT(kept1, 1e-9);
  EXPECT_LT(kept2, 1e-9);
}
