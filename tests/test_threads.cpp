// Results do not depend on the thread count (fluid/common/threads.hpp): a few steps of the main scene on a
// lattice large enough for every threaded path (>= kParallelRows particles: the fused passes by row
// blocks, the lattice solvers by columns, row blocks and wavenumbers, the gauge's row sums, the body
// force, the kinetic energy's sum) give bitwise the same fields with one and two threads.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "coupling/simulation.hpp"
#include "fluid/algebra/row_stencil.hpp"
#include "fluid/common/threads.hpp"
#include "io/scene.hpp"

using namespace sphib;

namespace {

struct State {
  Mat2 u, X, F;
  Vec p, phi;
  double ke;
};

State run(const Scene& scene, int threads, int steps) {
  const ThreadCount count(threads);
  EXPECT_EQ(thread_count(), threads);
  Simulation sim(scene.sim);
  for (int n = 0; n < steps; ++n) sim.step();
  return {sim.fluid().u(), sim.membranes().at(0).m.X, sim.force(), sim.fluid().p(), sim.fluid().phi(),
          sim.fluid().kinetic_energy()};
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
    EXPECT_GT(one.u.cwiseAbs().maxCoeff(), 0.0) << what;  // the membrane has set the fluid moving
  }
}
