// Free surfaces and loads (fluid/common/free_surface.hpp, fluid/common/loads.hpp, the classic SPH of Afanasiev,
// Makarchuk & Popov 2011 ["A"] in fluid/moving/wcsph_afanasiev.cpp): surface detection on a known block,
// the hydrostatic start, the loads of a still tank, the droplet's RK4 reference, refusals, a
// particle leaving the tank, checkpoints and a dam-break smoke run. Tolerances are measured values
// (Release build) with a margin, stated beside each test.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "fluid/common/exact.hpp"
#include "fluid/common/free_surface.hpp"
#include "fluid/common/loads.hpp"
#include "fluid/moving/wcsph.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"
#include "observe/analysis.hpp"
#include "scene_refusal.hpp"
#include "still_tank_scene.hpp"

using namespace sphib;

namespace {

// nx x ny particles of a lattice of spacing 1 in free space (the tank twice as large, all sides
// open), h = h_over_dx: the flags of `how` on them, and whether particle (i, j) is on the block's
// boundary ring.
std::vector<char> block_flags(SurfaceDetection how, int nx, int ny, double h_over_dx, double beta) {
  Domain d;
  d.x0 = -nx, d.x1 = 2 * nx, d.y0 = -ny, d.y1 = 2 * ny;
  d.periodic_x = d.periodic_y = false;
  d.bounded.fill(SideKind::Open);
  const Lattice L = make_lattice(d, 3 * nx, 3 * ny);
  FluidRegion r;
  r.shape = FluidRegion::Shape::Block;
  r.x0 = 0, r.x1 = nx, r.y0 = 0, r.y1 = ny;
  const ParticleSet set = fill_particles(L, r);
  EXPECT_EQ(set.x.rows(), nx * ny);
  const CubicSplineKernel W(h_over_dx);
  PairSearch search(d, W, static_cast<int>(set.x.rows()), Mat2(0, 2));
  ParticlePairs P;
  search.find(set.x, P);
  SurfaceDetector det(how, beta, W.h);
  std::vector<char> flags;
  det.detect(static_cast<int>(set.x.rows()), P, Vec::Constant(set.x.rows(), 1.0), 1.0, flags);
  return flags;
}

bool on_ring(const Mat2& x, int k, int nx, int ny) {
  const double X = x(k, 0), Y = x(k, 1);  // sites at (i + 1/2, j + 1/2)
  return X < 1 || X > nx - 1 || Y < 1 || Y > ny - 1;
}

using test::refusal;
using test::kStillTank;

}  // namespace

// A block in free space: exactly its outer ring of particles is flagged, by Dilts' algorithm
// (circles of radius h) and by A Eq. (26) with the paper's beta = 0.75, h/dx = 1.1 (and 1.3).
TEST(FreeSurface, DetectionFlagsExactlyTheBoundaryRingOfABlock) {
  for (const double hdx : {1.1, 1.3}) {
    for (const SurfaceDetection how : {SurfaceDetection::Dilts, SurfaceDetection::Divergence}) {
      SCOPED_TRACE(std::to_string(hdx) + (how == SurfaceDetection::Dilts ? " dilts" : " eq26"));
      const int nx = 12, ny = 9;
      const std::vector<char> flags = block_flags(how, nx, ny, hdx, 0.75);
      Domain d;
      d.x0 = -nx, d.x1 = 2 * nx, d.y0 = -ny, d.y1 = 2 * ny;
      d.periodic_x = d.periodic_y = false;
      FluidRegion r;
      r.shape = FluidRegion::Shape::Block;
      r.x0 = 0, r.x1 = nx, r.y0 = 0, r.y1 = ny;
      const Mat2 x = fill_particles(make_lattice(d, 3 * nx, 3 * ny), r).x;
      int wrong = 0;
      for (int k = 0; k < x.rows(); ++k) wrong += flags[k] != on_ring(x, k, nx, ny);
      EXPECT_EQ(wrong, 0);
    }
  }
}

// Dilts' arcs, the exact path (three neighbours 120 degrees apart fail the quick eight-sector
// test): neighbours at distance d cover acos(d / 2R) on either side of their directions, so three
// of them close the circle when that exceeds 60 degrees (d < R) and leave gaps when it does not.
TEST(FreeSurface, DiltsArcsCloseTheCircleExactly) {
  for (const double d : {0.9, 1.1}) {  // acos(0.45) = 63.3 degrees, acos(0.55) = 56.6 degrees
    ParticlePairs P;
    for (int k = 0; k < 3; ++k) {
      const double th = 2.0 * M_PI * k / 3.0 + 0.3;
      P.i.push_back(0);
      P.j.push_back(1 + k);  // fixed points
      P.rx.push_back(-d * std::cos(th));
      P.ry.push_back(-d * std::sin(th));
      P.r.push_back(d);
      P.W.push_back(0.0);
      P.F.push_back(0.0);
    }
    SurfaceDetector det(SurfaceDetection::Dilts, 0.75, 1.0);
    std::vector<char> flags;
    det.detect(1, P, Vec::Ones(1), 1.0, flags);
    EXPECT_EQ(flags[0], d > 1.0 ? 1 : 0) << d;
  }
}

// Eq. (26)'s sum is the divergence of position: 2 in the bulk up to the lattice quadrature of the
// kernel, about 1 on a flat side; A's threshold 2 beta = 1.5 lies between. Measured at h/dx = 1.3:
// bulk 2.0211, side 1.2788.
TEST(FreeSurface, PositionDivergenceIsTwoInsideAndAboutOneOnASide) {
  Domain d;
  d.x0 = -10, d.x1 = 20, d.y0 = -10, d.y1 = 20;
  d.periodic_x = d.periodic_y = false;
  FluidRegion r;
  r.shape = FluidRegion::Shape::Block;
  r.x0 = 0, r.x1 = 10, r.y0 = 0, r.y1 = 10;
  const Mat2 x = fill_particles(make_lattice(d, 30, 30), r).x;
  const CubicSplineKernel W(1.3);
  PairSearch search(d, W, 100, Mat2(0, 2));
  ParticlePairs P;
  search.find(x, P);
  SurfaceDetector det(SurfaceDetection::Divergence, 0.75, W.h);
  std::vector<char> flags;
  det.detect(100, P, Vec::Ones(100), 1.0, flags);
  const Vec& div = det.position_divergence();
  EXPECT_NEAR(div[55], 2.0211, 1e-3);  // (5.5, 5.5): a complete support
  EXPECT_NEAR(div[5], 1.2788, 1e-3);   // (5.5, 0.5): the bottom side
}

// Walls complete the support: a block against the left and bottom walls of a tank is flagged only
// on its top row and right column (Dilts, through the solver).
TEST(FreeSurface, WallsAreNotAFreeSurface) {
  Scene s = parse_scene(kStillTank, "still.toml", {"fill.x=[0.0, 0.5]"});
  WcsphFluid f(s.sim.fluid);
  ASSERT_NE(f.surface(), nullptr);
  const std::vector<char>& flags = *f.surface();
  int wrong = 0;
  for (int k = 0; k < f.size(); ++k) {
    const bool top = f.x()(k, 1) > 0.45, right = f.x()(k, 0) > 0.45;
    wrong += flags[k] != (top || right);
  }
  EXPECT_EQ(f.size(), 100);
  EXPECT_EQ(wrong, 0);
}

// A Eq. (28): the initial density gives the hydrostatic pressure rho0 g depth exactly (round-off)
// below the surface row (p = 0 there).
TEST(FreeSurface, HydrostaticInitialPressure) {
  Scene s = parse_scene(kStillTank, "still.toml");
  WcsphFluid f(s.sim.fluid);
  double worst = 0;
  for (int k = 0; k < f.size(); ++k) {
    if ((*f.surface())[k]) continue;
    const double p_exact = 1000.0 * 9.81 * (0.5 - f.x()(k, 1));
    worst = std::max(worst, std::fabs(f.p()[k] - p_exact) / (1000.0 * 9.81 * 0.5));
  }
  EXPECT_LT(worst, 1e-12);  // measured 1.8e-15
  EXPECT_EQ(std::count(f.surface()->begin(), f.surface()->end(), 1), 20);  // the top row
}

// A still tank (20 x 10 particles, 1 s, 2500 steps) stays near rest, and its wall loads are the
// hydrostatic forces: left and right rho g H^2 / 2 = 1226.25 N/m, bottom rho g (H + dy/2) L (A Eq. 32
// sums the wall row half a spacing below the floor); the load of A Eq. (31) stays near zero. Two
// surfaces: Tait's pressure at the surface particles too (detection none; measured: max speed at
// t = 1 0.0022 m/s, forces 1230.66 and 5151.49, |load| up to 6.8 on a side), and A's p = 0 on the
// Dilts surface, which needs more artificial viscosity (alpha = 0.3; alpha = 0.1 lets a circulation
// grow to 0.25 m/s by t = 4): 0.0035 m/s, 1223.87 and 5188.92, |load| up to 44.5. Free fall would
// reach 9.81 m/s.
TEST(FreeSurface, StillTankStaysNearRestWithHydrostaticLoads) {
  struct Variant {
    std::vector<std::string> sets;
    double speed, side_tol, bottom_tol, load_tol;
  };
  const double side = 1000.0 * 9.81 * 0.5 * 0.5 / 2.0, bottom = 1000.0 * 9.81 * (0.5 + 0.025) * 1.0;
  for (const Variant& v : {Variant{{"free_surface.detection=none"}, 0.005, 0.006, 0.001, 10.0},
                           Variant{{"wcsph.alpha=0.3"}, 0.006, 0.005, 0.012, 60.0}}) {
    SCOPED_TRACE(v.sets[0]);
    Scene s = parse_scene(kStillTank, "still.toml", v.sets);
    WcsphFluid f(s.sim.fluid);
    const test::StillTankRun run = test::run_still_tank(f, 2500);
    const WallForces& Fe = run.end;
    const double worst_load = run.worst_side_change;
    EXPECT_TRUE(std::isnan(run.start[Top]));  // open
    EXPECT_LT(f.u().rowwise().norm().maxCoeff(), v.speed);
    EXPECT_NEAR(Fe[Left], side, v.side_tol * side);
    EXPECT_NEAR(Fe[Right], Fe[Left], 1e-6 * side);  // the tank is symmetric
    EXPECT_NEAR(Fe[Bottom], bottom, v.bottom_tol * bottom);
    EXPECT_LT(worst_load, v.load_tol);
  }
}

// delta-SPH's diffusion (wcsph.delta, Antuono et al. 2012) vanishes on the hydrostatic start: its
// renormalised-gradient term cancels the pairwise difference of a linear density, also where the
// surface cuts the support. Over two steps the density with delta = 0.1 differs from that without by
// 1.6e-8 rho0 (measured; the Tait profile is not exactly linear). The still tank with Tait's pressure
// at the surface then stays near rest: measured max speed at t = 1 0.0041 m/s (0.0022 without delta).
TEST(FreeSurface, DeltaSphLeavesAFluidAtRestAtRest) {
  Scene a = parse_scene(kStillTank, "still.toml", {"free_surface.detection=none"});
  Scene b = parse_scene(kStillTank, "still.toml", {"free_surface.detection=none", "wcsph.delta=0.1"});
  WcsphFluid fa(a.sim.fluid), fb(b.sim.fluid);
  const Mat2 F = Mat2::Zero(fa.size(), 2);
  for (int n = 0; n < 2; ++n) {
    fa.step(F);
    fb.step(F);
  }
  EXPECT_LT((fa.phi() - fb.phi()).cwiseAbs().maxCoeff(), 1e-7 * 1000.0);
  EXPECT_GT((fa.phi() - fb.phi()).cwiseAbs().maxCoeff(), 0.0);  // the term is there
  test::run_still_tank(fb, 2500);
  EXPECT_LT(fb.u().rowwise().norm().maxCoeff(), 0.006);
}

// The load of image-wall methods: the Shepard interpolation of p at the wall line. A hydrostatic
// field on a 20 x 20 lattice in [0, 1]^2: the side walls get rho g H^2 / 2 to the lattice's
// quadrature (measured 0.4%), the bottom the pressure a weighted 0.56 spacing above the floor.
TEST(FreeSurface, InterpolatedWallForcesOfAHydrostaticField) {
  Domain d;
  d.periodic_x = false;
  const Lattice L = make_lattice(d, 20, 20);
  Vec p(L.size());
  for (int k = 0; k < L.size(); ++k) p[k] = 1000.0 * 9.81 * (1.0 - L.x(k, 1));
  const WallForces F = wall_forces_by_interpolation(d, L.x, Vec::Constant(L.size(), L.volume), p,
                                                    CubicSplineKernel(1.3 * L.dx), L.dx, L.dy);
  const double side = 1000.0 * 9.81 / 2.0;
  EXPECT_NEAR(F[Left], side, 0.01 * side);
  EXPECT_NEAR(F[Right], F[Left], 1e-9 * side);
  EXPECT_NEAR(F[Bottom], 1000.0 * 9.81 * (1.0 - 0.56 * L.dy), 0.01 * 1000.0 * 9.81);
  EXPECT_NEAR(F[Top], 1000.0 * 9.81 * 0.56 * L.dy, 0.01 * 1000.0 * 9.81);
}

// The droplet's reference: RK4 of A Eq. (42) keeps the energy integral c^2 (1 + a^-4) = 2 (the
// kinetic energy of Eq. 40's flow; its derivative vanishes by Eq. 42) and matches the quadrature of
// t(a) = int_1^a sqrt(s^4 + 1) / (sqrt(2) s^2) ds; it converges at fourth order.
TEST(FreeSurface, DropletRk4Reference) {
  exact::DropletAxis rk;
  rk.advance_to(0.8);
  EXPECT_NEAR(rk.c * rk.c * (1.0 + std::pow(rk.a, -4)), 2.0, 1e-12);
  // Simpson's rule for t(a) at the RK4 a(0.8)
  const int n = 20000;
  double t = 0;
  const double h = (rk.a - 1.0) / n;
  auto f = [](double s) { return std::sqrt(s * s * s * s + 1.0) / (std::sqrt(2.0) * s * s); };
  for (int k = 0; k <= n; ++k) t += (k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0)) * f(1.0 + k * h);
  EXPECT_NEAR(t * h / 3.0, 0.8, 1e-12);  // measured 1e-15
  exact::DropletAxis coarse, half;
  coarse.advance_to(0.8, 0.1);
  half.advance_to(0.8, 0.05);
  const double order = std::log2(std::fabs(coarse.a - rk.a) / std::fabs(half.a - rk.a));
  EXPECT_NEAR(order, 4.0, 0.3);
}

// Free-surface particles take rho = rho0 with p = 0: without it the continuity equation compresses
// the tips of the stretching droplet (721 particles, no density smoothing) until the density guard
// stops the run at t = 0.76 (|rho/rho0 - 1| = 0.25); with it the run reaches t = 0.8 with a
// density variation of 0.026 and a(0.8) within 0.56% of the RK4 solution (measured).
TEST(FreeSurface, DropletWithoutSmoothingKeepsItsDensity) {
  namespace fs = std::filesystem;
  Scene s = load_scene(std::string(SPHIB_SOURCE_DIR) + "/cases/droplet_wcsph.toml",
                       {"grid.nx=93", "grid.ny=93", "time.dt=9.8e-4", "time.end=0.8", "wcsph.smooth_every=0",
                        "output.times=[]"});
  RunOptions opt;
  opt.out_dir = (fs::temp_directory_path() / "sphib_droplet_smoke").string();
  fs::remove_all(opt.out_dir);
  const nlohmann::json j = run_scene(s, opt);
  EXPECT_EQ(j["particles"].get<int>(), 721);  // 15 rings
  EXPECT_LT(j["max_density_variation"].get<double>(), 0.04);
  EXPECT_LT(j["droplet_axis_error"].get<double>(), 0.008);
  fs::remove_all(opt.out_dir);
}

// Bad input is refused by key and line.
TEST(FreeSurface, BadInputIsRefusedByKey) {
  auto expect = [](const std::string& m, const std::string& key, const std::string& what) {
    EXPECT_NE(m.find(key), std::string::npos) << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
  };
  expect(refusal(kStillTank, {"method=eulerian", "wcsph.integrator=leapfrog"}), "fill.shape", "has no free surface");
  expect(refusal(kStillTank, {"method=lagrangian", "fill.shape=domain"}), "domain.open", "has no free surface");
  expect(refusal(kStillTank, {"free_surface.beta=1.2"}), "free_surface.beta", "out of range");
  expect(refusal(kStillTank, {"free_surface.beta=1"}), "free_surface.beta", "out of range");
  expect(refusal(kStillTank, {"fill.y=[0.0, 1.5]"}), "fill.y", "is not inside the tank");
  expect(refusal(kStillTank, {"fill.x=[-0.5, 0.5]"}), "fill.x", "is not inside the tank");
  expect(refusal(kStillTank, {"fluid.gravity=[1.0, -9.81]", "domain.periodic_x=true"}), "fluid.gravity", "periodic x");
  expect(refusal(kStillTank, {"fluid.gravity=[0.0, 9.81]"}), "fluid.gravity", "open top");
  expect(refusal(kStillTank, {"wcsph.integrator=leapfrog"}), "wcsph.integrator", "predictor_corrector");
  expect(refusal(kStillTank, {"wcsph.eos=morris"}), "wcsph.eos", "tait");
  expect(refusal(kStillTank, {"wcsph.delta=-0.1"}), "wcsph.delta", "out of range");
  expect(refusal(kStillTank, {"wcsph.delta=0.1", "wcsph.integrator=leapfrog", "fill.shape=domain", "domain.open=[]",
                              "fluid.gravity=[0.0, 0.0]"}),
         "wcsph.delta", "predictor_corrector");
  expect(refusal(kStillTank, {"domain.open=[\"left\"]", "domain.periodic_x=true"}), "domain.open", "periodic");
  expect(refusal(kStillTank, {"walls.top=[1.0, 0.0]"}), "walls.top", "open side");
  expect(refusal(std::string(kStillTank) + "[membrane]\nr0 = 0.1\nT0 = 1.0\n"), "membrane", "not supported");
  // the line of the offending key
  const std::string m = refusal(std::string(kStillTank) + "[free_surface]\nbeta = 0.0\n");
  EXPECT_NE(m.find("scene.toml:29: free_surface.beta"), std::string::npos) << m;
}

// A particle leaving the tank through an open side stops the run with a diagnostic, never NaNs: a
// drop thrown sideways in an open box, and a splash of one particle (no neighbours at all).
TEST(FreeSurface, ParticleLeavingTheTankStops) {
  for (const char* radius : {"fill.radius=0.12", "fill.radius=0.01"}) {
    SCOPED_TRACE(radius);
    Scene s = parse_scene(kStillTank, "still.toml",
                          {"domain.open=[\"left\", \"right\", \"bottom\", \"top\"]", "fluid.gravity=[0.0, 0.0]",
                           "fill.shape=circle", "fill.centre=[0.525, 0.525]", radius, "wcsph.u_scale=1.0",
                           "fill.velocity_gradient=[[0.0, 0.0], [0.0, 0.0]]"});
    s.sim.initial_velocity = [](double, double) { return Eigen::Vector2d(2.0, 0.0); };
    Simulation sim(s.sim);
    EXPECT_EQ(sim.fluid().size() == 1, std::string(radius) == "fill.radius=0.01");
    const std::string m = test::message_when_it_leaves(sim, 1000);
    EXPECT_NE(m.find("left the tank through its open right side"), std::string::npos) << m;
  }
}

// Checkpoints of A's predictor-corrector: a restored solver continues bit for bit.
TEST(FreeSurface, CheckpointContinuesBitForBit) {
  Scene s = parse_scene(kStillTank, "still.toml", {"fill.x=[0.0, 0.4]", "wcsph.smooth_every=7"});
  // the column collapses: something to compare
  EXPECT_GT(test::restart_continues_bit_for_bit<WcsphFluid>(s.sim.fluid, 30), 1e-3);
}

// The surge front on the floor: a block of 10 x 4 particles (spacing 1, the first row half a spacing
// above the floor y = 0) ends at x = 9. A particle on the floor 2.8 spacings ahead of it, as in the ISPH
// dam break at t = 0.195, is alone within the support 2h = 2.6 and is no front; 2 spacings ahead it is
// (it then has the block's corner particle within reach). A particle ahead above the band never is.
TEST(FreeSurface, SurgeFrontSkipsDetachedParticles) {
  Mat2 x(42, 2);
  for (int k = 0; k < 40; ++k) x.row(k) << k % 10, 0.5 + k / 10;
  x.row(40) << 30.0, 5.0;  // above the band
  x.row(41) << 11.8, 0.5;
  EXPECT_EQ(surge_front_x(x, 0.0, 2.0, 2.6), 9.0);
  x(41, 0) = 11.0;
  EXPECT_EQ(surge_front_x(x, 0.0, 2.0, 2.6), 11.0);
  EXPECT_EQ(surge_front_x(x.topRows(1), 0.0, 2.0, 2.6), 0.0);  // alone: its own x
  EXPECT_EQ(surge_front_x(x.middleRows(40, 1), 0.0, 2.0, 2.6), -INFINITY);  // nothing in the band
}

// The dam break (cases/dam_break_wcsph.toml) at a/10: 200 steps run, the front leaves the column's
// foot and the left wall's load drops as the column collapses. Measured at t = 0.04: front_x 0.1595
// (a = 0.146), load_left -297 N/m (of rho g (2a)^2 / 2 = 418 N/m at rest).
TEST(FreeSurface, DamBreakSmokeRun) {
  namespace fs = std::filesystem;
  Scene s = load_scene(std::string(SPHIB_SOURCE_DIR) + "/cases/dam_break_wcsph.toml",
                       {"grid.nx=40", "grid.ny=80", "time.dt=2e-4", "time.max_steps=200", "output.times=[]"});
  RunOptions opt;
  opt.out_dir = (fs::temp_directory_path() / "sphib_dam_break_smoke").string();
  fs::remove_all(opt.out_dir);
  const nlohmann::json j = run_scene(s, opt);
  EXPECT_EQ(j["particles"].get<int>(), 200);
  EXPECT_GT(j["front_x"].get<double>(), 0.150);
  EXPECT_LT(j["load_left"].get<double>(), -150.0);
  EXPECT_TRUE(j.contains("load_right") && j.contains("load_bottom") && !j.contains("load_top"));
  fs::remove_all(opt.out_dir);
}
