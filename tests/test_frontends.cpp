// What the front ends share with the scene reader: membranes built by a program checked as a file's
// (io/scene.hpp build_scene, the Python module's path), the key listing as JSON (`sphib keys --json`),
// and `sphib check` on the free-surface methods (memory model of the fluid particles, gravity as a
// velocity scale).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "io/check.hpp"
#include "io/footprint.hpp"
#include "io/scene.hpp"
#include "membrane/shapes.hpp"

using namespace sphib;

namespace {

const std::string kSource = SPHIB_SOURCE_DIR;
const std::vector<std::string> kChannel{"grid.nx=16",    "grid.ny=16",   "fluid.rho=1.0",
                                        "fluid.mu=1.0",  "time.dt=1e-3", "time.end=0.01"};

std::string refusal(const std::vector<ProgramMembrane>& m, const std::string& path = "") {
  try {
    build_scene(path, "scene", path.empty() ? kChannel : std::vector<std::string>{}, m);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ProgramMembranes, AreCheckedWithTheScenesOwn) {
  const ProgramMembrane a{make_membrane(circle(64, 0.4, 0.5, 0.2), 0.2, 1.0)};
  const Scene one = build_scene("", "scene", kChannel, {a});
  ASSERT_EQ(one.sim.membranes.size(), 1u);
  EXPECT_DOUBLE_EQ(one.sim.membranes[0].h_star, 1.4 * 1.2 / 16);  // h_star_over_h h, h = 1.2 dx
  const ProgramMembrane b{make_membrane(circle(64, 0.6, 0.5, 0.2), 0.2, 1.0)};
  EXPECT_NE(refusal({a, b}).find("scene: membranes[1]: membrane 1 crosses or touches membrane 0"), std::string::npos)
      << refusal({a, b});
  ProgramMembrane c{make_membrane(circle(64, 0.8, 0.2, 0.1), 0.1, 1.0)};
  c.membrane.mat.Es = -1;
  EXPECT_EQ(refusal({a, c}), "scene: membranes[1].T0: value -1 is out of range (allowed: >= 0)");
  ProgramMembrane d{make_membrane(circle(64, 0.8, 0.2, 0.1), 0.1, 1.0)};
  d.h_star = -0.1;
  EXPECT_EQ(refusal({d}), "scene: membranes[0].h_star: value -0.1 is out of range (allowed: >= 0)");
  // After a file's membrane the count goes on; a file's checks still name the file.
  const std::string osc = kSource + "/cases/membrane_oscillation.toml";
  const ProgramMembrane inside{make_membrane(circle(64, 0.75, 0.0, 0.2), 0.2, 1.0)};  // across its edge
  EXPECT_NE(refusal({inside}, osc).find(osc + ": membranes[1]: membrane 1 crosses or touches membrane 0"), std::string::npos);
  const std::string tank = kSource + "/cases/still_tank_isph.toml";
  EXPECT_NE(refusal({ProgramMembrane{make_membrane(circle(64, 0.5, 0.2, 0.05), 0.05, 1.0)}}, tank)
                .find("membranes in a free-surface scene are not supported"),
            std::string::npos);
}

TEST(KeysJson, ListsEveryKeyWithTypedDefaults) {
  const auto keys = nlohmann::json::parse(scene_keys_json());
  std::istringstream rows(describe_scene_keys());
  size_t n = 0;
  for (std::string line; std::getline(rows, line);) ++n;
  ASSERT_EQ(keys.size(), n);  // one entry per row of `sphib keys`
  auto key = [&](const std::string& name) {
    for (const auto& k : keys)
      if (k["name"] == name) return k;
    ADD_FAILURE() << name << " not listed";
    return nlohmann::json{};
  };
  EXPECT_EQ(key("grid.nx")["type"], "integer");
  EXPECT_TRUE(key("grid.nx")["required"].get<bool>());
  EXPECT_TRUE(key("grid.nx")["default"].is_null());
  EXPECT_EQ(key("kernel.h_over_dx")["default"], 1.2);
  EXPECT_EQ(key("fluid.convection")["default"], true);
  EXPECT_EQ(key("solver.poisson")["default"], "auto");
  EXPECT_EQ(key("domain.x")["default"], nlohmann::json::array({0, 1}));
  EXPECT_EQ(key("membrane.nb")["range"], "[4, 1000000]");
  for (const auto& k : keys) {
    EXPECT_FALSE(k["help"].get<std::string>().empty()) << k["name"];
    EXPECT_FALSE(k["type"].get<std::string>().empty()) << k["name"];
  }
}

TEST(Check, FreeSurfaceScenesAreEstimatedByTheirFluidParticles) {
  // The dam break (200 x 800 lattice sites, 5000 fluid particles) was estimated at 1.07 GB from the
  // lattice and not built; its measured peak is 48-50 MB (/usr/bin/time -v, 2 steps) and the
  // estimate 56 MB.
  const Scene dam = load_scene(kSource + "/cases/dam_break.toml");
  const MemoryEstimate e = estimate_memory(dam);
  EXPECT_EQ(e.particles, 5000);
  EXPECT_EQ(e.path, "ISPH");
  // The fluid's share (5000 x 20 neighbours x 19 log2(5000) B = 23 MB); the rest is this process's
  // resident memory, larger under a sanitizer, so it is not bounded here.
  EXPECT_LT(e.fluid, 40e6);
  EXPECT_GT(e.fluid, 15e6);
  std::ostringstream out;
  EXPECT_EQ(check_scene(dam, out), 0) << out.str();
  EXPECT_EQ(out.str().find("not built"), std::string::npos) << out.str();
  // Gravity is the velocity scale: 2 sqrt(g H) = 2 sqrt(9.81 x 0.292) = 3.38 m/s.
  EXPECT_NE(out.str().find("with U = 3.38 (gravity"), std::string::npos) << out.str();
  EXPECT_EQ(out.str().find("no velocity scale"), std::string::npos);
  EXPECT_NE(out.str().find("explicit viscous limit"), std::string::npos);
  // WCSPH: the same particles, and its acoustic limit shown.
  std::ostringstream w;
  check_scene(load_scene(kSource + "/cases/dam_break_wcsph.toml"), w);
  EXPECT_NE(w.str().find("5000 particles"), std::string::npos) << w.str();
  EXPECT_NE(w.str().find("acoustic and viscous limit (Coelho et al. Eq. 19)"), std::string::npos) << w.str();
}
