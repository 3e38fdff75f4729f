// Scene files: every bad input is refused with a message naming the key and its line; overrides;
// every case in cases/ loads and smoke-runs a few steps.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "io/run.hpp"
#include "helpers.hpp"
#include "io/scene.hpp"
#include "scene_refusal.hpp"

using namespace sphib;

namespace {

const char* const kMinimal = sphib_test::kMinimalScene;

using test::refusal;

}  // namespace

TEST(Scene, MinimalSceneParsesWithDefaults) {
  const Scene s = parse_scene(kMinimal, "scene.toml");
  EXPECT_EQ(s.sim.fluid.nx, 16);
  EXPECT_TRUE(s.sim.fluid.domain.periodic_x);
  EXPECT_FALSE(s.sim.fluid.domain.periodic_y);
  EXPECT_DOUBLE_EQ(s.sim.fluid.h_over_dx, 1.2);
  EXPECT_TRUE(s.membranes.empty());
}

TEST(Scene, UnknownKeyNamesKeyAndLine) {
  const std::string m = refusal(std::string(kMinimal) + "[fluid2]\nmuu = 3\n");
  EXPECT_NE(m.find("scene.toml:12"), std::string::npos) << m;
  EXPECT_NE(m.find("fluid2.muu"), std::string::npos) << m;
  const std::string m2 = refusal(std::string("viscosity = 1\n") + kMinimal);
  EXPECT_NE(m2.find("scene.toml:1"), std::string::npos) << m2;
  EXPECT_NE(m2.find("unknown key 'viscosity'"), std::string::npos) << m2;
}

// A misspelt key next to a required one: the misspelling is named with its line and the nearest
// valid key, not the required key it leaves missing.
TEST(Scene, UnknownKeyIsNamedBeforeMissingOnesWithTheNearestValidKey) {
  const std::string m = refusal("[grid]\nnx = 8\nny = 8\n[fluid]\nrho = 1.0\nmuu = 0.1\n[time]\ndt = 0.1\nend = 1.0\n");
  EXPECT_NE(m.find("scene.toml:6: unknown key 'fluid.muu': did you mean 'mu'?"), std::string::npos) << m;
  EXPECT_EQ(m.find("missing"), std::string::npos) << m;
  // The same name in another table: the full key.
  const std::string m2 = refusal(std::string(kMinimal) + "[output]\ndt = 0.5\n");
  EXPECT_NE(m2.find("scene.toml:12: unknown key 'output.dt': did you mean 'time.dt'?"), std::string::npos) << m2;
  // An entry of [[membranes]]: its own key.
  const std::string m3 = refusal(std::string(kMinimal) + "[[membranes]]\nr0 = 0.2\nT0 = 1.0\nradus = 0.3\n");
  EXPECT_NE(m3.find("scene.toml:14: unknown key 'membranes[0].radus': did you mean 'radius'?"), std::string::npos)
      << m3;
  // An override.
  const std::string m4 = refusal(kMinimal, {"grid.nxx=4"});
  EXPECT_NE(m4.find("(--set grid.nxx): unknown key 'grid.nxx': did you mean 'nx'?"), std::string::npos) << m4;
  // Nothing near: no guess.
  const std::string m5 = refusal(std::string("viscosity = 1\n") + kMinimal);
  EXPECT_NE(m5.find("unknown key 'viscosity'"), std::string::npos) << m5;
  EXPECT_EQ(m5.find("did you mean"), std::string::npos) << m5;
  // A value where a table of keys belongs is a type error, not an unknown key.
  const std::string m6 = refusal(std::string("membrane = 3\n") + kMinimal);
  EXPECT_NE(m6.find("membrane: must be a table"), std::string::npos) << m6;
}

TEST(Scene, WrongTypeNamesKey) {
  const std::string m = refusal(kMinimal, {"grid.nx=\"many\""});
  EXPECT_NE(m.find("grid.nx"), std::string::npos) << m;
  EXPECT_NE(m.find("integer"), std::string::npos) << m;
  const std::string m2 = refusal(kMinimal, {"fluid.convection=3"});
  EXPECT_NE(m2.find("fluid.convection"), std::string::npos) << m2;
}

TEST(Scene, MissingRequiredKeyIsNamed) {
  const std::string m = refusal("[grid]\nnx = 8\nny = 8\n[fluid]\nrho = 1.0\n[time]\ndt = 0.1\nend = 1.0\n");
  EXPECT_NE(m.find("fluid.mu"), std::string::npos) << m;
  EXPECT_NE(m.find("missing"), std::string::npos) << m;
}

TEST(Scene, InvalidValuesAreRefusedWithRange) {
  for (const char* kv : {"fluid.rho=0", "fluid.mu=-1", "time.dt=0", "grid.nx=1", "kernel.h_over_dx=-2",
                         "time.end=0", "fluid.mu=nan", "fluid.rho=inf"}) {
    const std::string m = refusal(kMinimal, {kv});
    const std::string key = std::string(kv).substr(0, std::string(kv).find('='));
    EXPECT_NE(m.find(key), std::string::npos) << kv << " -> " << m;
    EXPECT_NE(m.find("--set"), std::string::npos) << m;
  }
  EXPECT_NE(refusal(kMinimal, {"observe.exact=vortex"}).find("allowed:"), std::string::npos);
}

TEST(Scene, WallVelocityOnPeriodicSideIsRefused) {
  const std::string m = refusal(std::string(kMinimal) + "[walls]\nleft = [1.0, 0.0]\n");
  EXPECT_NE(m.find("walls.left"), std::string::npos) << m;
  EXPECT_NE(m.find("periodic"), std::string::npos) << m;
}

TEST(Scene, SyntaxErrorHasLine) {
  const std::string m = refusal("[grid\nnx = 3\n");
  EXPECT_NE(m.find("scene.toml:1"), std::string::npos) << m;
}

TEST(Scene, OverridesReachEveryContractKey) {
  const std::string mem = std::string(kMinimal) +
                          "[domain]\nx = [-1.5, 1.5]\ny = [-1.5, 1.5]\n[membrane]\nr0 = 0.5\nT0 = 1.0\n";
  const Scene s = parse_scene(mem, "scene.toml",
                              {"grid.nx=32", "grid.ny=24", "kernel.h_over_dx=1.5", "time.dt=0.002", "time.end=0.5",
                               "fluid.rho=2", "fluid.mu=0.3", "membrane.T0=10", "membrane.r0=0.4", "membrane.nb=64",
                               "membrane.h_star_over_h=0.5", "membrane.fixed=true", "membrane.shape=ellipse",
                               "membrane.rx=0.6", "membrane.ry=0.3"});
  EXPECT_EQ(s.sim.fluid.nx, 32);
  EXPECT_EQ(s.sim.fluid.ny, 24);
  EXPECT_DOUBLE_EQ(s.sim.fluid.h_over_dx, 1.5);
  EXPECT_DOUBLE_EQ(s.sim.fluid.dt, 0.002);
  EXPECT_DOUBLE_EQ(s.t_end, 0.5);
  EXPECT_DOUBLE_EQ(s.sim.fluid.rho, 2.0);
  EXPECT_DOUBLE_EQ(s.sim.fluid.mu, 0.3);
  ASSERT_EQ(s.sim.membranes.size(), 1u);
  const MembraneSetup& m = s.sim.membranes[0];
  EXPECT_DOUBLE_EQ(m.membrane.mat.Es, 10.0);
  EXPECT_DOUBLE_EQ(m.membrane.L0(), 2 * M_PI * 0.4);
  EXPECT_EQ(m.membrane.nb(), 64);
  EXPECT_TRUE(m.fixed);
  const double h = 1.5 * 0.5 * (3.0 / 32 + 3.0 / 24);
  EXPECT_NEAR(m.h_star, 0.5 * h, 1e-14);
  EXPECT_NEAR(m.membrane.X.col(0).maxCoeff(), 0.6, 1e-12);  // ellipse rx
  EXPECT_NEAR(m.membrane.X.col(1).maxCoeff(), 0.3, 1e-3);   // ry (markers at uniform angle)
  const Scene c = parse_scene(mem, "scene.toml", {"membrane.shape=circle", "membrane.radius=0.45"});
  EXPECT_NEAR(c.sim.membranes[0].membrane.X.col(0).maxCoeff(), 0.45, 1e-12);
}

TEST(Scene, BadMembraneIsRefusedWithItsKey) {
  const std::string mem = std::string(kMinimal) + "[membrane]\nr0 = 0.2\nT0 = 1.0\n";
  EXPECT_NE(refusal(mem, {"membrane.nb=3"}).find("membrane.nb"), std::string::npos);
  EXPECT_NE(refusal(mem, {"membrane.T0=-1"}).find("membrane.T0"), std::string::npos);
  EXPECT_NE(refusal(mem, {"membrane.shape=star"}).find("membrane.shape"), std::string::npos);
  // shape = points with a clockwise square: refused by the shape check
  const std::string pts = mem + "shape = \"points\"\npoints = [[0.4,0.4],[0.4,0.6],[0.6,0.6],[0.6,0.4]]\n";
  const std::string m = refusal(pts);
  EXPECT_NE(m.find("membrane.shape"), std::string::npos) << m;
}

TEST(Scene, KeyListingDocumentsTheContractKeys) {
  const std::string keys = describe_scene_keys();
  for (const char* k : {"grid.nx", "grid.ny", "kernel.h_over_dx", "time.dt", "time.end", "fluid.rho", "fluid.mu",
                        "membrane.T0", "membrane.r0", "membrane.nb", "membrane.h_star_over_h", "membrane.fixed",
                        "membrane.shape", "membrane.radius", "membrane.rx", "membrane.ry"})
    EXPECT_NE(keys.find(std::string("`") + k + "`"), std::string::npos) << k;
}

// Every case smoke-runs a few steps and writes its outputs.
TEST(Scene, EveryCaseSmokeRuns) {
  namespace fs = std::filesystem;
  const fs::path cases = fs::path(SPHIB_SOURCE_DIR) / "cases";
  int n = 0;
  for (const auto& entry : fs::directory_iterator(cases)) {
    if (entry.path().extension() != ".toml") continue;
    ++n;
    SCOPED_TRACE(entry.path().string());
    Scene s = load_scene(entry.path().string(), {"time.max_steps=3"});
    RunOptions opt;
    opt.out_dir = (fs::temp_directory_path() / ("sphib_smoke_" + entry.path().stem().string())).string();
    fs::remove_all(opt.out_dir);
    const nlohmann::json j = run_scene(s, opt);
    EXPECT_EQ(j["steps"].get<long>(), 3);
    EXPECT_TRUE(fs::exists(fs::path(opt.out_dir) / "output.h5"));
    EXPECT_TRUE(fs::exists(fs::path(opt.out_dir) / "output.xdmf"));
    EXPECT_TRUE(fs::exists(fs::path(opt.out_dir) / "diagnostics.csv"));
    EXPECT_TRUE(fs::exists(fs::path(opt.out_dir) / "summary.json"));
    for (const char* k : {"steps", "wall_seconds", "seconds_per_step"}) EXPECT_TRUE(j.contains(k)) << k;
    // The loop is the steps' time plus the opening and closing writes (timed apart), nothing counted twice
    const double writes = j["profile_seconds"]["opening and closing writes"].get<double>();
    const double steps = 3 * j["seconds_per_step"].get<double>(), loop = j["loop_seconds"].get<double>();
    EXPECT_GT(writes, 0.0);
    EXPECT_GT(steps, 0.0);
    EXPECT_LE(steps + writes, loop);
    EXPECT_GT(steps + writes, 0.95 * loop);
    fs::remove_all(opt.out_dir);
  }
  EXPECT_GE(n, 6);
}

// Every key the scene reads is resolved, given or not, in one canonical text: a key set explicitly to
// its default (a low item of issue 17: a restart was refused for it) resolves as its absence, and an
// integer given for a number key as that number.
TEST(Scene, ResolvedKeysAreCanonicalWithOrWithoutDefaults) {
  auto resolved = [](const Scene& s) { return std::map<std::string, std::string>(s.resolved.begin(), s.resolved.end()); };
  const auto bare = resolved(parse_scene(kMinimal, "scene.toml"));
  const auto set = resolved(parse_scene(kMinimal, "scene.toml",
                                        {"solver.marker_eps=1e-12", "kernel.h_over_dx=1.2", "fluid.mu=1", "walls.top=[0, 0.0]",
                                         "solver.poisson=\"auto\"", "time.max_steps=0", "domain.periodic_x=true"}));
  EXPECT_EQ(bare, set);
  EXPECT_EQ(bare.at("solver.marker_eps"), "1e-12");
  EXPECT_EQ(bare.at("fluid.mu"), "1");
  EXPECT_EQ(bare.at("walls.top"), "[0, 0]");
  EXPECT_EQ(resolved(parse_scene(kMinimal, "scene.toml", {"fluid.mu=0.1"})).at("fluid.mu"), "0.1");
}

// Integers at the edge of their ranges: the largest values that fit are accepted where they are
// harmless (time.end = 1e16 with time.max_steps, output.diagnostics_every past the run's length).
TEST(Scene, IntegersAtTheirLimitsAndLongEndsWithAStepLimit) {
  EXPECT_EQ(parse_scene(kMinimal, "scene.toml", {"solver.marker_max_iter=2147483647"}).sim.markers.max_iter, 2147483647);
  EXPECT_NE(refusal(kMinimal, {"solver.marker_max_iter=2147483648"}).find("solver.marker_max_iter: value 2147483648 is out of range"),
            std::string::npos);
  const Scene s = parse_scene(kMinimal, "scene.toml", {"time.end=1e16", "time.max_steps=10", "output.diagnostics_every=9000000000"});
  EXPECT_EQ(s.max_steps, 10);
  EXPECT_EQ(s.diagnostics_every, 9000000000L);
  EXPECT_NE(refusal(kMinimal, {"time.end=1e16"}).find("time.end: needs 1e+19 steps"), std::string::npos);
}
