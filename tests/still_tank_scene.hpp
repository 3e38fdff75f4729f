#pragma once
// The still tank of the free-surface tests (test_free_surface.cpp, test_isph.cpp): 20 x 10 particles
// of water in an open 1 m tank under gravity, classic SPH's keys (ISPH ignores the [wcsph] table);
// and their checkpoint check.
#include <gtest/gtest.h>

#include "fluid/solver.hpp"

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
