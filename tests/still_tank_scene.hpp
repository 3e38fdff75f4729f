#pragma once
// The still tank of the free-surface tests (test_free_surface.cpp, test_isph.cpp): 20 x 10 particles
// of water in an open 1 m tank under gravity, classic SPH's keys (ISPH ignores the [wcsph] table);
// and their checkpoint check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <stdexcept>
#include <string>

#include "coupling/simulation.hpp"
#include "fluid/core/solver.hpp"

namespace sphib::test {

// A method with particles of its own (Fluid: WcsphFluid, IsphFluid) restored from the state after
// `steps` steps continues bit for bit for `steps` more; returns the kinetic energy at the end (the
// caller checks there was motion to compare).
template <class Fluid>
double restart_continues_bit_for_bit(const FluidParams& params, int steps) {
  Fluid a(params);
  const Mat2 F = Mat2::Zero(a.size(), 2);
  for (int n = 0; n < steps; ++n) a.step(F);
  Fluid b(params);
  b.restore(a.state());
  EXPECT_EQ((b.p() - a.p()).cwiseAbs().maxCoeff(), 0.0);
  for (int n = 0; n < steps; ++n) {
    a.step(F);
    b.step(F);
  }
  EXPECT_EQ((b.x() - a.x()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((b.u() - a.u()).cwiseAbs().maxCoeff(), 0.0);
  return a.kinetic_energy();
}

// A tank of fluid left alone for `steps` steps: its wall forces (Eq. 32) at the start and the end and
// the largest change of the side walls' forces on the way.
struct StillTankRun {
  WallForces start, end;
  double worst_side_change = 0;
};
template <class Fluid>
StillTankRun run_still_tank(Fluid& f, int steps) {
  StillTankRun r;
  r.start = f.wall_forces();
  const Mat2 F = Mat2::Zero(f.size(), 2);
  for (int n = 0; n < steps; ++n) {
    f.step(F);
    const WallForces Fn = f.wall_forces();
    r.worst_side_change = std::max({r.worst_side_change, std::fabs(Fn[Left] - r.start[Left]),
                                    std::fabs(Fn[Right] - r.start[Right])});
  }
  r.end = f.wall_forces();
  return r;
}

// Steps `sim` (a drop thrown towards an open side) until keep_in_tank stops it; its message, or ""
// after a test failure (non-finite fields, or the drop still inside after `steps` steps).
inline std::string message_when_it_leaves(Simulation& sim, int steps) {
  try {
    for (int n = 0; n < steps; ++n) {
      sim.step();
      if (!(sim.fluid().u().allFinite() && sim.fluid().p().allFinite())) {
        ADD_FAILURE() << "non-finite fields at step " << n;
        return "";
      }
    }
    ADD_FAILURE() << "the drop did not leave";
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

inline const char* kStillTank = R"(
method = "wcsph"
[domain]
x = [0.0, 1.0]
y = [0.0, 1.0]
periodic_x = false
open = ["top"]
[grid]
nx = 20
ny = 20
[kernel]
h_over_dx = 1.3
[fill]
shape = "block"
y = [0.0, 0.5]
[fluid]
rho = 1000.0
mu = 1.0
gravity = [0.0, -9.81]
[wcsph]
eos = "tait"
integrator = "predictor_corrector"
wall_pressure = "extrapolated"
alpha = 0.1
[time]
dt = 4e-4
end = 1.0
)";

}  // namespace sphib::test
