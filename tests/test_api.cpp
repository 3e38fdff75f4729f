// The user's surface: a scene built in C++ (the path of cases/embed_example.cpp), the shape
// helpers (from_curve, from_polar, ellipse_fit), the --derive expressions of `sphib sweep`, and
// `sphib check` and `sphib sweep` through the built command.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "app/expression.hpp"
#include "helpers.hpp"
#include "io/run.hpp"
#include "membrane/geometry.hpp"
#include "membrane/polygon.hpp"
#include "membrane/shapes.hpp"

using namespace sphib;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

using sphib_test::slurp;
using sphib_test::temp_dir;

// Runs the command line, returns its exit status and stdout + stderr.
int shell(const std::string& cmd, std::string& output) {
  output.clear();
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return -1;
  char buf[4096];
  while (size_t n = std::fread(buf, 1, sizeof buf, p)) output.append(buf, n);
  const int status = ::pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Points of the ellipse c + R(phi) (a cos t, b sin t), t_k = 2 pi k / n.
Mat2 rotated_ellipse(int n, double a, double b, double phi, double cx, double cy) {
  Mat2 X(n, 2);
  for (int k = 0; k < n; ++k) {
    const double t = 2 * kPi * k / n, x = a * std::cos(t), y = b * std::sin(t);
    X(k, 0) = cx + std::cos(phi) * x - std::sin(phi) * y;
    X(k, 1) = cy + std::sin(phi) * x + std::cos(phi) * y;
  }
  return X;
}

}  // namespace

// The embed example's path: body force field, moving walls, initial velocity, a membrane from a
// shape function and one from a point list, an observer; 5 steps through run_scene.
TEST(Api, SceneBuiltInCodeRunsWithObserverColumn) {
  const fs::path dir = temp_dir("embed");
  Scene s;
  s.title = "api test";
  FluidParams& f = s.sim.fluid;
  f.domain = {-1.0, 1.0, -1.0, 1.0, true, false};
  f.domain.wall_velocity[Top] = {0.5, 0.0};
  f.domain.wall_velocity[Bottom] = {-0.5, 0.0};
  f.nx = f.ny = 24;
  f.mu = 0.2;
  f.dt = 2e-3;
  int force_calls = 0;
  s.sim.body_force_field = [&](double, double y, double t) {
    ++force_calls;
    return Eigen::Vector2d(std::sin(kPi * y) * std::cos(t), 0.0);
  };
  s.sim.initial_velocity = [](double x, double) { return Eigen::Vector2d(0.0, 0.1 * std::sin(kPi * x)); };
  const double h_star = 1.4 * 1.2 * 2.0 / 24;
  s.sim.membranes.push_back({make_membrane(from_polar([](double th) { return 0.25 * (1 + 0.1 * std::cos(3 * th)); }, 48, -0.45, 0.0), 0.25, 1.0), h_star});
  Mat2 pts(5, 2);
  pts << 0.2, -0.15, 0.8, -0.15, 0.85, 0.1, 0.5, 0.2, 0.2, 0.1;
  s.sim.membranes.push_back({make_membrane(from_points(pts, 48), 0.22, 1.0), h_star});
  s.observers.push_back({"m1_polygon_D", [](const Simulation& sim) { return ellipse_fit(sim.membranes()[1].m.X).deformation(); }});
  s.t_end = 1.0;
  s.max_steps = 5;
  RunOptions o;
  o.out_dir = dir.string();
  const nlohmann::json j = run_scene(s, o);
  EXPECT_EQ(j["steps"], 5);
  ASSERT_TRUE(j.contains("m1_polygon_D"));
  EXPECT_GT(j["m1_polygon_D"].get<double>(), 0.05);  // the point list is far from a circle
  EXPECT_EQ(force_calls, 5 * 24 * 24);       // F(x, y, t_n) at every particle, every step
  std::istringstream csv(slurp(dir / "diagnostics.csv"));
  std::string header, row;
  std::getline(csv, header);
  EXPECT_NE(header.find(",m1_polygon_D"), std::string::npos) << header;
  int rows = 0;
  while (std::getline(csv, row)) ++rows;
  EXPECT_EQ(rows, 6);  // t = 0 and every step
  EXPECT_TRUE(fs::exists(dir / "output.h5"));
  EXPECT_TRUE(fs::exists(dir / "output.xdmf"));
  fs::remove_all(dir);
}

// A polygon of an ellipse (the affine image of a regular polygon) has exactly the ellipse's axis
// ratio and angle; its half-axes carry the polygon factor sqrt((2 + cos(2 pi/n))/3).
TEST(Api, EllipseFitRecoversRotatedEllipse) {
  for (double phi : {0.0, 0.3, -1.1, kPi / 2}) {
    const int n = 200;
    const double a = 0.8, b = 0.3, cx = 0.4, cy = -1.7;
    const ShapeMoments e = ellipse_fit(rotated_ellipse(n, a, b, phi, cx, cy));
    const double poly = std::sqrt((2 + std::cos(2 * kPi / n)) / 3);
    EXPECT_NEAR(e.L, a * poly, 1e-12) << phi;
    EXPECT_NEAR(e.B, b * poly, 1e-12) << phi;
    EXPECT_NEAR(e.deformation(), (a - b) / (a + b), 1e-12) << phi;
    EXPECT_GT(e.theta, -kPi / 2);
    EXPECT_LE(e.theta, kPi / 2);
    EXPECT_NEAR(std::remainder(e.theta - phi, kPi), 0.0, 1e-12) << phi;  // an axis: modulo pi
    EXPECT_NEAR(e.centroid.x(), cx, 1e-12);
    EXPECT_NEAR(e.centroid.y(), cy, 1e-12);
    EXPECT_NEAR(e.area, signed_area(rotated_ellipse(n, a, b, phi, cx, cy)), 1e-12);
  }
  // A circle: D = 0; a square: the moments of the square (J = A s^2/12), D = 0.
  Mat2 sq(4, 2);
  sq << 0, 0, 2, 0, 2, 2, 0, 2;
  const ShapeMoments s = ellipse_fit(sq);
  EXPECT_NEAR(s.area, 4.0, 1e-15);
  EXPECT_NEAR(s.Jxx, 4.0 * 4.0 / 12.0, 1e-14);
  EXPECT_NEAR(s.Jxy, 0.0, 1e-14);
  EXPECT_NEAR(s.deformation(), 0.0, 1e-14);
}

TEST(Api, MeanAngularVelocityOfARigidRotation) {
  const Mat2 X = rotated_ellipse(64, 0.5, 0.2, 0.4, 1.0, 2.0);
  Mat2 U(64, 2);
  for (int k = 0; k < 64; ++k) U.row(k) << -0.7 * (X(k, 1) - 2.0), 0.7 * (X(k, 0) - 1.0);  // omega = 0.7
  EXPECT_NEAR(mean_angular_velocity(X, U, {1.0, 2.0}), 0.7, 1e-14);
}

TEST(Api, FromCurveAndFromPolarSampleUniformlyInArclength) {
  // A circle as a parametric curve with a non-uniform parameter: markers still uniform in arclength.
  const double R = 0.6;
  auto curve = [&](double t) {
    const double th = 2 * kPi * (t + 0.1 * std::sin(2 * kPi * t));  // speed varies along t
    return Eigen::Vector2d(1.0 + R * std::cos(th), R * std::sin(th));
  };
  const Membrane m = make_membrane(from_curve(curve, 64), 0.5, 3.0);
  ASSERT_EQ(m.nb(), 64);
  EXPECT_DOUBLE_EQ(m.mat.Es, 3.0);
  EXPECT_NEAR(m.L0(), 2 * kPi * 0.5, 1e-14);
  double dmin = 1e9, dmax = 0;
  for (int k = 0; k < 64; ++k) {
    EXPECT_NEAR((m.X.row(k) - Eigen::RowVector2d(1.0, 0.0)).norm(), R, 1e-6);
    const double d = (m.X.row((k + 1) % 64) - m.X.row(k)).norm();
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
  }
  EXPECT_LT(dmax / dmin - 1, 1e-6);
  EXPECT_GT(signed_area(m.X), 0.0);
  // from_polar: a three-lobed shape; every marker on r(theta).
  auto r = [](double th) { return 0.3 * (1 + 0.2 * std::cos(3 * th)); };
  const Membrane p = make_membrane(from_polar(r, 96, -0.5, 0.25), 0.3, 1.0);
  for (int k = 0; k < 96; ++k) {
    const double x = p.X(k, 0) + 0.5, y = p.X(k, 1) - 0.25;
    EXPECT_NEAR(std::hypot(x, y), r(std::atan2(y, x)), 1e-5);
  }
  // Refusals: open curve, clockwise curve.
  EXPECT_THROW(from_curve([](double t) { return Eigen::Vector2d(t, t * t); }, 32), std::invalid_argument);
  EXPECT_THROW(from_curve([](double t) { return Eigen::Vector2d(std::cos(-2 * kPi * t), std::sin(-2 * kPi * t)); }, 32),
               std::invalid_argument);
}

TEST(Api, SweepExpressions) {
  using namespace sphib::app;
  auto eval = [](const std::string& e) { return format_number(evaluate(e)); };
  EXPECT_EQ(eval("40"), "40");                    // an integer key stays an integer
  EXPECT_EQ(eval("0.3/40"), "0.0075");
  EXPECT_EQ(eval("0.1*3/40"), "0.0075000000000000015");  // what Python prints too
  EXPECT_EQ(eval("2*(3+4)-1"), "13");
  EXPECT_EQ(eval("-2**2"), "-4");                 // Python: ** binds tighter than unary minus
  EXPECT_EQ(eval("2**3**2"), "512");              // right-associative
  EXPECT_EQ(eval("2**-1"), "0.5");
  EXPECT_EQ(eval("6/3"), "2.0");                  // '/' gives a float, as in Python 3
  EXPECT_EQ(eval("sqrt(16)"), "4.0");
  EXPECT_EQ(eval("1e-05"), "1e-05");
  EXPECT_EQ(eval(" ( 1 + 2 ) * -3 "), "-9");
  EXPECT_DOUBLE_EQ(evaluate("2*pi").value, 2 * kPi);
  EXPECT_EQ(format_number({0.1 + 0.2, false}), "0.30000000000000004");  // round-trips
  EXPECT_EQ(substitute("0.1*3/{grid.nx}", {{"grid.nx", "40"}}), "0.1*3/40");
  EXPECT_THROW(substitute("{fluid.mu}", {{"grid.nx", "40"}}), ExpressionError);
  for (const char* bad : {"1/0", "sqrt(-1)", "2 +", "(1", "foo(2)", "1 2", "3 $ 4", ""})
    EXPECT_THROW(evaluate(bad), ExpressionError) << bad;
}

// `sphib check`: counts, the memory estimate, and warnings for a dt above the CFL and elastic limits.
TEST(Api, CheckReportsMemoryAndWarnsAboveTheTimeStepLimits) {
  const fs::path dir = temp_dir("check");
  std::ofstream(dir / "scene.toml") << R"(
[domain]
x = [0.0, 1.0]
y = [0.0, 1.0]
[walls]
top = [2.0, 0.0]
[grid]
nx = 20
ny = 20
[fluid]
rho = 1.0
mu = 0.1
[membrane]
radius = 0.25
r0 = 0.2
T0 = 5.0
nb = 64
centre = [0.5, 0.5]
[time]
dt = 1e-4
end = 1.0
)";
  const std::string cmd = std::string(SPHIB_BINARY) + " check " + (dir / "scene.toml").string();
  std::string out;
  ASSERT_EQ(shell(cmd, out), 0) << out;
  for (const char* s : {"particles 400", "images", "neighbours per particle", "markers per grid spacing",
                        "dx / rest spacing", "memory estimate", "non-zeros", "convective CFL", "elastic limit"})
    EXPECT_NE(out.find(s), std::string::npos) << s << " missing in:\n" << out;
  EXPECT_EQ(out.find("WARNING"), std::string::npos) << out;
  // dx = 0.05 and the lid moves at 2: dt = 0.05 > dx / U = 0.025.
  ASSERT_EQ(shell(cmd + " --set time.dt=0.05", out), 0) << out;
  EXPECT_NE(out.find("WARNING: convective CFL"), std::string::npos) << out;
  EXPECT_NE(out.find("WARNING: membrane 0 elastic limit"), std::string::npos) << out;
  // A kernel narrower than 0.9 lattice spacings: a warning (issue 17, item 11: 0.51-0.7 ran with badly
  // wrong results and none); 0.5 and below: refused naming the key.
  ASSERT_EQ(shell(cmd + " --set kernel.h_over_dx=0.8", out), 0) << out;
  EXPECT_NE(out.find("WARNING: kernel.h_over_dx = 0.8 gives h = 0.8 max(dx, dy): below 0.9"), std::string::npos) << out;
  ASSERT_EQ(shell(cmd + " --set kernel.h_over_dx=0.9", out), 0) << out;
  EXPECT_EQ(out.find("WARNING"), std::string::npos) << out;
  EXPECT_EQ(shell(cmd + " --set kernel.h_over_dx=0.5", out), 2) << out;
  EXPECT_NE(out.find("kernel.h_over_dx: value 0.5 leaves particles without a neighbour"), std::string::npos) << out;
  // A bad scene: exit status 2 with the key named.
  EXPECT_EQ(shell(cmd + " --set fluid.mu=-1", out), 2) << out;
  EXPECT_NE(out.find("fluid.mu"), std::string::npos) << out;
  fs::remove_all(dir);
}

// `sphib sweep` in process: 2 x 2 runs of 3 steps, derived key, table with orders.
TEST(Api, SweepRunsEveryCombinationAndTabulates) {
  const fs::path dir = temp_dir("sweep");
  const std::string scene = std::string(SPHIB_SOURCE_DIR) + "/cases/couette.toml";
  const std::string cmd = std::string(SPHIB_BINARY) + " sweep " + scene +
                          " --vary grid.nx=8,16 --vary fluid.mu=1,0.5 --derive grid.ny={grid.nx}" +
                          " --derive time.dt=0.01/{grid.nx} --set time.max_steps=3 --report rms_error,max_div_u --quiet" +
                          " --out " + (dir / "sw").string();
  std::string out;
  ASSERT_EQ(shell(cmd, out), 0) << out;
  const std::string csv = slurp(dir / "sw" / "sweep.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "grid.nx,fluid.mu,grid.ny,time.dt,rms_error,max_div_u,steps,wall_seconds,run");
  EXPECT_NE(csv.find("\n8,1,8,0.00125,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n16,0.5,16,0.000625,"), std::string::npos) << csv;
  for (int k = 0; k < 4; ++k) {
    char run[16];
    std::snprintf(run, sizeof run, "run_%03d", k);
    EXPECT_TRUE(fs::exists(dir / "sw" / run / "summary.json")) << run;
  }
  const std::string md = slurp(dir / "sw" / "sweep.md");
  EXPECT_NE(md.find("| order rms_error |"), std::string::npos) << md;
  EXPECT_NE(out.find("| grid.nx | fluid.mu |"), std::string::npos) << out;
  // A second call reuses the runs; an unknown key is refused (exit 2) before anything runs.
  ASSERT_EQ(shell(cmd, out), 0) << out;
  EXPECT_EQ(shell(std::string(SPHIB_BINARY) + " sweep " + scene + " --vary grid.nz=8 --report steps --out " +
                      (dir / "bad").string(), out), 2) << out;
  EXPECT_FALSE(fs::exists(dir / "bad" / "run_000"));
  EXPECT_EQ(shell(std::string(SPHIB_BINARY) + " sweep " + scene + " --vary grid.nx=8 --derive time.dt=1/ --report steps --out " +
                      (dir / "bad").string(), out), 2) << out;
  // Issue 17, low item: --report nosuchfield gave an empty column, --report steps a second steps
  // column. A field the first run's summary lacks is refused naming what it has; steps appears once.
  const std::string few = std::string(SPHIB_BINARY) + " sweep " + scene + " --vary grid.nx=8,16 --set time.max_steps=2 --quiet --out " +
                          (dir / "rep").string();
  EXPECT_EQ(shell(few + " --report rms_error,nosuchfield", out), 2) << out;
  EXPECT_NE(out.find("--report nosuchfield: " + (dir / "rep" / "run_000").string() + "/summary.json has no such field (it has: "),
            std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "rep" / "run_001")) << "the sweep went on after the refusal";
  ASSERT_EQ(shell(few + " --report steps,rms_error", out), 0) << out;
  const std::string rep = slurp(dir / "rep" / "sweep.csv");
  EXPECT_EQ(rep.substr(0, rep.find('\n')), "grid.nx,steps,rms_error,wall_seconds,run");
  fs::remove_all(dir);
}

TEST(Api, VersionAndUsageExitCodes) {
  std::string out;
  EXPECT_EQ(shell(std::string(SPHIB_BINARY) + " --version", out), 0);
  EXPECT_NE(out.find("sphib "), std::string::npos) << out;
  EXPECT_EQ(shell(std::string(SPHIB_BINARY) + " run", out), 2) << out;            // missing scene
  EXPECT_EQ(shell(std::string(SPHIB_BINARY) + " frobnicate", out), 2) << out;     // unknown command
  EXPECT_EQ(shell(std::string(SPHIB_BINARY) + " run /nonexistent.toml", out), 2) << out;
}
