// Pressure probes on the walls (observe/probes.cpp; observe.probes, probe_names, probe_size,
// probe_window): the reading of a fluid at rest, the time window's running mean, and refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/run.hpp"
#include "io/scene.hpp"
#include "helpers.hpp"
#include "scene_refusal.hpp"
#include "still_tank_scene.hpp"

using namespace sphib;

namespace {

// The still tank of the free-surface tests by ISPH (20 x 10 particles, dt = 1e-3), run for `steps`
// steps with the extra keys; the summary, and the diagnostics' column `col` (every step).
struct ProbeRun {
  nlohmann::json summary;
  std::vector<double> t, col;
};
ProbeRun run(std::vector<std::string> sets, int steps, const std::string& col) {
  sets.insert(sets.begin(), {"method=isph", "time.dt=1e-3", "output.diagnostics_every=1",
                             "time.max_steps=" + std::to_string(steps)});
  const Scene s = parse_scene(test::kStillTank, "tank.toml", sets);
  RunOptions opt;
  opt.out_dir = (sphib_test::temp_dir("probes") / "run").string();  // this process's own: ctest runs the tests at once
  ProbeRun r;
  r.summary = run_scene(s, opt);
  std::ifstream in(opt.out_dir + "/diagnostics.csv");
  std::string line;
  std::getline(in, line);
  int ct = -1, cc = -1, k = 0;
  for (std::stringstream h(line); std::getline(h, line, ','); ++k) {
    if (line == "t") ct = k;
    if (line == col) cc = k;
  }
  EXPECT_GE(cc, 0) << "no column " << col;
  while (std::getline(in, line)) {
    std::vector<double> v;
    for (std::stringstream row(line); std::getline(row, line, ',');) v.push_back(std::stod(line));
    r.t.push_back(v.at(ct));
    r.col.push_back(v.at(cc));
  }
  std::filesystem::remove_all(opt.out_dir);
  return r;
}

}  // namespace

// Water at rest (ISPH's consistent scheme keeps it so to round-off): a probe on the left wall at
// y = 0.1 reads rho g (y_top - y) with y_top = 0.475 the Dirichlet top row, whatever its sensor width
// (the mean of a linear pressure over a segment is its centre's) and window; one on the floor reads
// rho g y_top. Measured: equal to 1e-12 relative at every step.
TEST(Probes, ReadTheHydrostaticPressureOfATankAtRest) {
  const ProbeRun r = run({"observe.probes=[[0.0, 0.1], [0.5, 0.0]]", "observe.probe_names=[\"side\", \"floor\"]",
                     "observe.probe_size=0.1", "observe.probe_window=0.01"},
                    50, "probe_side");
  const double side = 1000.0 * 9.81 * (0.475 - 0.1), floor = 1000.0 * 9.81 * 0.475;
  ASSERT_EQ(r.col.size(), 51u);
  for (double p : r.col) EXPECT_NEAR(p, side, 1e-9 * side);
  EXPECT_NEAR(r.summary["probe_side_max"].get<double>(), side, 1e-9 * side);
  EXPECT_NEAR(r.summary["probe_floor_max"].get<double>(), floor, 1e-9 * floor);
  EXPECT_EQ(r.summary["probe_size"].get<double>(), 0.1);
}

// The window: a collapsing column (the block of the left 0.4 m) read by a probe on the floor at
// x = 0.2; with probe_window = 0.005 each reading is the mean of the step readings (probe_window = 0)
// of t - 0.005 ... t, i.e. of the last six steps (dt = 1e-3; exact to round-off), and the summary's
// peak is the largest windowed reading and its time.
TEST(Probes, WindowIsTheRunningMeanOfTheStepReadings) {
  const std::vector<std::string> keys = {"fill.x=[0.0, 0.4]", "observe.probes=[[0.2, 0.0]]"};
  std::vector<std::string> a = keys, b = keys;
  b.push_back("observe.probe_window=0.005");
  const ProbeRun step = run(a, 40, "probe_1"), win = run(b, 40, "probe_1");
  ASSERT_EQ(step.col.size(), win.col.size());
  double peak = -INFINITY, peak_t = 0;
  for (size_t k = 0; k < win.col.size(); ++k) {
    double sum = 0;
    int n = 0;
    for (size_t q = 0; q <= k; ++q)
      if (step.t[q] >= step.t[k] - 0.005 - 1e-12) sum += step.col[q], ++n;
    EXPECT_NEAR(win.col[k], sum / n, 1e-9 * std::fabs(sum / n)) << "t = " << win.t[k];
    if (win.col[k] > peak) peak = win.col[k], peak_t = win.t[k];
  }
  EXPECT_GT(std::fabs(step.col.back() - step.col.front()), 10.0);  // the reading changes: something to average
  EXPECT_NEAR(win.summary["probe_1_max"].get<double>(), peak, 1e-9 * peak);
  EXPECT_NEAR(win.summary["probe_1_max_t"].get<double>(), peak_t, 1e-12);
}

TEST(Probes, BadProbesAreRefusedByKey) {
  auto refused = [](std::vector<std::string> sets) {
    sets.insert(sets.begin(), "method=isph");
    return test::refusal(test::kStillTank, sets);
  };
  auto expect = [](const std::string& msg, const std::string& key, const std::string& what) {
    EXPECT_NE(msg.find(key), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  };
  expect(refused({"observe.probes=[[0.5, 0.5]]"}), "observe.probes", "not on a wall");
  expect(refused({"observe.probes=[[0.5, 1.0]]"}), "observe.probes", "not on a wall");  // the open top
  expect(refused({"observe.probes=[[0.0, 1.5]]"}), "observe.probes", "not on a wall");  // beyond the wall
  expect(refused({"observe.probes=[[0.0]]"}), "observe.probes", "[x, y]");
  expect(refused({"observe.probes=[[0.0, 0.1]]", "observe.probe_names=[\"a\", \"b\"]"}), "observe.probe_names",
         "every probe");
  expect(refused({"observe.probe_names=[\"a\"]"}), "observe.probe_names", "lists none");
  expect(refused({"observe.probes=[[0.0, 0.1], [0.0, 0.2]]", "observe.probe_names=[\"a\", \"a\"]"}),
         "observe.probe_names", "twice");
  expect(refused({"observe.probes=[[0.0, 0.1]]", "observe.probe_size=-1"}), "observe.probe_size", "");
  expect(refused({"observe.probes=[[0.0, 0.1]]", "observe.probe_window=-1"}), "observe.probe_window", "");
}
