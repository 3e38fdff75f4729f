// ISPH with a free surface (fluid/moving/isph.hpp, Afanasiev, Makarchuk & Popov 2011 ["A"], Sections
// 3.3-3.6): a still tank, a short start-up Poiseuille flow against Eq. (36), the surface of A Eq. (26)
// on a block, checkpoints, refusals and a particle leaving the tank. Tolerances are measured values
// (Release build) with a margin, stated beside each test.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <string>

#include "fluid/moving/isph.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"
#include "scene_refusal.hpp"
#include "still_tank_scene.hpp"

using namespace sphib;

namespace {

// The free-surface tests' still tank by ISPH (dt = 1e-3: the explicit viscosity's bound is far).
const std::vector<std::string> kIsph = {"method=isph", "time.dt=1e-3"};

Scene tank(std::vector<std::string> sets = {}) {
  sets.insert(sets.begin(), kIsph.begin(), kIsph.end());
  return parse_scene(test::kStillTank, "tank.toml", sets);
}

std::string refused(std::vector<std::string> sets) {
  sets.insert(sets.begin(), kIsph.begin(), kIsph.end());
  return test::refusal(test::kStillTank, sets);
}


}  // namespace

// The consistent scheme (isph.scheme, the default: isph.hpp) keeps water at rest at rest: the pressure
// gradient is exact for the hydrostatic pressure on the lattice, the Poisson rows beside the surface
// read their missing neighbours as mirror images, and the walls' Lennard-Jones push starts inside the
// spacing. Measured, 20 x 10 particles, 500 steps: max speed 5.5e-14 m/s (the paper's operators:
// 0.0146), the wall forces equal to their t = 0 values to round-off (left 1030.05 N/m, floor 4905).
TEST(Isph, ConsistentSchemeKeepsATankAtRest) {
  Scene s = tank();
  IsphFluid f(s.sim.fluid);
  const test::StillTankRun run = test::run_still_tank(f, 500);
  EXPECT_LT(f.u().rowwise().norm().maxCoeff(), 1e-12);
  for (Side side : {Left, Right, Bottom}) EXPECT_NEAR(run.end[side], run.start[side], 1e-9 * run.start[side]) << side;
  EXPECT_LT(run.worst_side_change, 1e-6);
  Scene paper = tank({"isph.scheme=paper"});
  IsphFluid g(paper.sim.fluid);
  test::run_still_tank(g, 500);
  EXPECT_GT(g.u().rowwise().norm().maxCoeff(), 1e-3);  // what the consistent operators remove
}

// Water at rest, 20 x 10 particles, 500 steps (t = 0.5): the wall forces stay hydrostatic and the
// particles nearly still (the paper's scheme; the consistent one: above). Measured: max speed 0.0146 m/s (free fall would reach 4.9 m/s; without the
// wall repulsion and the surface gradient of isph.cpp 0.17 at 40 x 20), side force 1020 N/m against
// rho g H^2 / 2 = 1226 (-16.8%: Eq. 32's sum over the inner wall row of a 10-row column, 1146 at
// t = 0), right - left 0.29 N/m (0.25 at the Poisson rtol 1e-14), bottom 4862 against
// rho g H L = 4905 (-0.9%), |load| at most 27.9.
TEST(Isph, StillTankStaysNearRestWithHydrostaticLoads) {
  Scene s = tank({"isph.scheme=paper"});
  IsphFluid f(s.sim.fluid);
  const double side = 1000.0 * 9.81 * 0.5 * 0.5 / 2.0, bottom = 1000.0 * 9.81 * 0.5;
  const test::StillTankRun run = test::run_still_tank(f, 500);
  const WallForces& Fe = run.end;
  const double worst_load = run.worst_side_change;
  EXPECT_TRUE(std::isnan(run.start[Top]));  // open
  EXPECT_LT(f.u().rowwise().norm().maxCoeff(), 0.03);
  EXPECT_NEAR(Fe[Left], side, 0.20 * side);
  EXPECT_NEAR(Fe[Right], Fe[Left], 1e-3 * side);  // the tank is symmetric (to the solver's round-off)
  EXPECT_NEAR(Fe[Bottom], bottom, 0.02 * bottom);
  EXPECT_LT(worst_load, 40.0);
  // the pressure at the bottom row: hydrostatic rho g (y_top - y) to the top row's p = 0 (measured
  // within 1.01%)
  const Vec& p = f.p();
  for (int i = 0; i < f.size(); ++i)
    if (f.x()(i, 1) < 0.03) EXPECT_NEAR(p[i], 1000.0 * 9.81 * (0.475 - f.x()(i, 1)), 0.02 * 4660.0) << i;
}

// A block of 12 x 6 particles in the corner of the tank: A Eq. (26) with beta = 0.75 marks
// exactly its top row and its right column (the free sides), none next to the walls (the Morris wall
// particles complete their support). Measured: 17 particles, the ring of the free sides.
TEST(Isph, SurfaceOfABlockIsItsFreeSides) {
  Scene s = tank({"fill.x=[0.0, 0.6]", "fill.y=[0.0, 0.3]"});
  IsphFluid f(s.sim.fluid);
  ASSERT_EQ(f.size(), 12 * 6);
  const std::vector<char>& flags = *f.surface();
  for (int k = 0; k < f.size(); ++k) {
    const bool free_side = f.x()(k, 0) > 0.55 || f.x()(k, 1) > 0.25;
    EXPECT_EQ(flags[k] != 0, free_side) << "particle at " << f.x()(k, 0) << ", " << f.x()(k, 1);
  }
}

// The start-up Poiseuille flow of A Section 6.1 (cases/poiseuille_afanasiev_isph.toml) at N = 15^2 to
// t = 0.1: the relative L2 error against Eq. (36) at the same time. Measured 0.0156; the centre-line
// speed 7.7e-6 m/s.
TEST(Isph, ShortPoiseuilleMatchesEq36) {
  namespace fs = std::filesystem;
  Scene s = load_scene(std::string(SPHIB_SOURCE_DIR) + "/cases/poiseuille_afanasiev_isph.toml",
                       {"grid.nx=15", "grid.ny=15", "time.end=0.1"});
  RunOptions opt;
  opt.out_dir = (fs::temp_directory_path() / "sphib_isph_poiseuille").string();
  fs::remove_all(opt.out_dir);
  const nlohmann::json j = run_scene(s, opt);
  EXPECT_LT(j["profile_error"].get<double>(), 0.025);
  EXPECT_GT(j["max_speed"].get<double>(), 5e-6);  // the flow has started (steady: 1.25e-5)
  // A full tank's singular Poisson operator: the default is CG on its range (the gauge's constants
  // removed), not a CHOLMOD factorisation every step; the same profile as CHOLMOD's to the CG's
  // tolerance (measured: 1 iteration per solve, profile errors equal to 1e-12 relative).
  EXPECT_GT(j.value("poisson_cg_iterations", 0.0), 0.0);
  fs::remove_all(opt.out_dir);
  Scene d = load_scene(std::string(SPHIB_SOURCE_DIR) + "/cases/poiseuille_afanasiev_isph.toml",
                       {"grid.nx=15", "grid.ny=15", "time.end=0.1", "solver.poisson=cholmod_supernodal"});
  const nlohmann::json k = run_scene(d, opt);
  EXPECT_NEAR(j["profile_error"].get<double>(), k["profile_error"].get<double>(), 1e-6 * k["profile_error"].get<double>());
  fs::remove_all(opt.out_dir);
}

// Checkpoints with the direct Poisson solver: a restored ISPH continues bit for bit (the Verlet
// list's state restored: the same candidates, patterns and factorisations).
TEST(Isph, CheckpointContinuesBitForBit) {
  Scene s = tank({"fill.x=[0.0, 0.4]", "solver.poisson=cholmod_supernodal"});
  // the column collapses (measured 19.9): something to compare
  EXPECT_GT(test::restart_continues_bit_for_bit<IsphFluid>(s.sim.fluid, 30), 1.0);
}

TEST(Isph, BadInputIsRefusedByKey) {
  auto expect = [](const std::string& m, const std::string& key, const std::string& what) {
    EXPECT_NE(m.find(key), std::string::npos) << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
  };
  expect(refused({"free_surface.beta=1.2"}), "free_surface.beta", "out of range");
  expect(refused({"free_surface.beta=0"}), "free_surface.beta", "out of range");
  expect(refused({"fill.y=[0.0, 1.5]"}), "fill.y", "is not inside the tank");
  expect(refused({"fluid.gravity=[1.0, -9.81]", "domain.periodic_x=true"}), "fluid.gravity", "periodic x");
  expect(refused({"free_surface.detection=dilts"}), "free_surface.detection", "not available for isph");
  expect(refused({"free_surface.detection=none"}), "free_surface.detection", "Dirichlet");
  expect(refused({"isph.viscous=implicit"}), "isph.viscous", "implicit");
  expect(refused({"isph.poisson_rtol=0"}), "isph.poisson_rtol", "out of range");
  expect(refused({"isph.poisson_rtol=0.01"}), "isph.poisson_rtol", "out of range");
  expect(refused({"isph.poisson_refresh=0"}), "isph.poisson_refresh", "out of range");
  expect(refused({"isph.poisson_refresh=2.5"}), "isph.poisson_refresh", "integer");
  expect(refused({"solver.crank_nicolson=cholmod_supernodal"}), "solver.crank_nicolson", "explicit");
  expect(refused({"solver.poisson=pcg_fft"}), "solver.poisson", "pcg_fft");
  expect(refused({"isph.scheme=exact"}), "isph.scheme", "not allowed");
  expect(refused({"isph.shifting=lind"}), "isph.shifting", "not allowed");
  expect(refused({"isph.shifting_A=0"}), "isph.shifting_A", "out of range");
  expect(refused({"fluid.projection=exact"}), "fluid.projection", "exact");
}

// A drop thrown sideways in an open box leaves it: the run stops naming the particle and the side.
TEST(Isph, ParticleLeavingTheTankStops) {
  Scene s = tank({"domain.open=[\"left\", \"right\", \"bottom\", \"top\"]", "fluid.gravity=[0.0, 0.0]",
                         "fill.shape=circle", "fill.centre=[0.525, 0.525]", "fill.radius=0.12"});
  s.sim.initial_velocity = [](double, double) { return Eigen::Vector2d(2.0, 0.0); };
  Simulation sim(s.sim);
  const std::string m = test::message_when_it_leaves(sim, 1000);
  EXPECT_NE(m.find("ISPH: particle"), std::string::npos) << m;
  EXPECT_NE(m.find("left the tank through its open right side"), std::string::npos) << m;
}

// The pressure gradient along a floor (isph.hpp): p = p0 + G x + rho g (H - y), a tangential gradient
// G over the hydrostatic pressure, on the still tank's lattice (20 x 10 particles, h = 1.3 dx, as the
// dam break's), read by the step's gradient at the columns more than 4h from the side walls (whose
// floor wall particles have a full fluid support), row by row from the floor. The consistent scheme's
// wall particles carry the fluid's pressure extrapolated to them (Adami et al. 2012), so every row
// gets G and -rho g (measured: to 1e-15 relative). With the pair rule p_w = p_i + rho g . (x_w - x_i)
// (the paper's scheme) the wall pairs add nothing along the floor and the rows within 2h of it get
// only their fluid neighbours' part: G_x / G measured 0.7735 (row 1) and 0.9997 (row 2) against the
// full support's 1.0105 (row 3, M0, the sum form's lattice moment, which the paper's scheme does not
// divide by).
TEST(Isph, PressureGradientAlongTheFloorIsTheFluids) {
  const double rho = 1000.0, g = 9.81, G = 2000.0, H = 0.5, p0 = 100.0;
  auto rows = [&](const std::vector<std::string>& sets) {
    Scene s = tank(sets);
    IsphFluid f(s.sim.fluid);
    const Mat2& x = f.x();
    Vec p(f.size());
    for (int i = 0; i < f.size(); ++i) p[i] = p0 + G * x(i, 0) + rho * g * (H - x(i, 1));
    const Mat2 grad = f.pressure_gradient(p);
    const double dx = 0.05, reach = 4.0 * 1.3 * dx;
    std::array<double, 3> gx{}, gy{};  // each row's G_x / G (its columns' mean) and |G_y / (-rho g) - 1|
    std::array<double, 3> lo{9, 9, 9}, hi{-9, -9, -9}, ylo{0, 0, 0};
    for (int i = 0; i < f.size(); ++i) {
      const int row = static_cast<int>(std::floor(x(i, 1) / dx));
      if (row > 2 || x(i, 0) < reach || x(i, 0) > 1.0 - reach) continue;
      lo[row] = std::min(lo[row], grad(i, 0) / G);
      hi[row] = std::max(hi[row], grad(i, 0) / G);
      ylo[row] = std::max(ylo[row], std::fabs(grad(i, 1) / (-rho * g) - 1.0));
    }
    for (int r = 0; r < 3; ++r) {
      gx[r] = 0.5 * (lo[r] + hi[r]);
      gy[r] = ylo[r];
      std::printf("row %d: G_x / G in [%.6f, %.6f], |G_y / (-rho g) - 1| <= %.2e\n", r + 1, lo[r], hi[r], ylo[r]);
      EXPECT_LT(hi[r] - lo[r], 1e-9) << r;  // the same at every interior column of a row
    }
    return std::make_pair(gx, gy);
  };
  const auto [cx, cy] = rows({});
  for (int r = 0; r < 3; ++r) {
    EXPECT_NEAR(cx[r], 1.0, 1e-12) << r;
    EXPECT_LT(cy[r], 1e-12) << r;
  }
  const auto [px, py] = rows({"isph.scheme=paper"});
  EXPECT_NEAR(px[0], 0.7735, 1e-4);
  EXPECT_NEAR(px[1], 0.9997, 1e-4);
  EXPECT_NEAR(px[2], 1.0105, 1e-4);
}
