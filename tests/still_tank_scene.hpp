#pragma once
// The still tank of the free-surface tests (test_free_surface.cpp, test_isph.cpp): 20 x 10 particles
// of water in an open 1 m tank under gravity, classic SPH's keys (ISPH ignores the [wcsph] table).
namespace sphib::test {

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
