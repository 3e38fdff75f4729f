// Inflow and outflow sides (fluid/common/boundary_rule.hpp: SideKind::Inflow, SideKind::Outflow) on
// the fixed lattice (EPSPH): a channel with a parabolic inflow on the left and an outflow on the
// right carries the Poiseuille parabola; bad scenes are refused naming the key.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "fluid/factory.hpp"
#include "fluid/core/solver.hpp"
#include "scene_refusal.hpp"

using namespace sphib;
using test::refusal;

namespace {

// A channel [0, 4] x [0, 1], no-slip walls at y = 0 and 1, inflow 4 y (1 - y) on the left, outflow on
// the right, Stokes flow (rho = mu = 1), n particles across.
FluidParams open_channel(int n) {
  FluidParams p;
  p.domain.x0 = 0.0, p.domain.x1 = 4.0, p.domain.y0 = 0.0, p.domain.y1 = 1.0;
  p.domain.periodic_x = p.domain.periodic_y = false;
  p.domain.bounded[Left] = SideKind::Inflow;
  p.domain.bounded[Right] = SideKind::Outflow;
  p.domain.inflow_profile = InflowProfile::Parabolic;
  p.domain.wall_velocity[Left] = Eigen::Vector2d(1.0, 0.0);
  p.nx = 4 * n;
  p.ny = n;
  p.h_over_dx = 1.525;
  p.rho = p.mu = 1.0;
  p.dt = 2e-3;
  p.convection = false;
  return p;
}

struct Errors {
  double u, u_mid, v;  // max |u - 4 y (1 - y)| over every particle and over 1 <= x <= 3, max |v| (u_max = 1)
  double dpdx;         // the pressure gradient along the middle row between x = 1 and 3 (exact: -8 mu u_max / H^2)
};

// From rest to t = 1.5 (the slowest viscous mode decays as exp(-pi^2 t): 4e-7 by then).
Errors run_open_channel(int n) {
  const FluidParams p = open_channel(n);
  auto f = make_fluid(p);
  const int N = f->lattice().size();
  f->set_velocity(Mat2::Zero(N, 2));
  const Mat2 F = Mat2::Zero(N, 2);
  for (int s = 0; s < 750; ++s) f->step(F);
  Errors e{0, 0, 0, 0};
  const Mat2& x = f->lattice().x;
  for (int i = 0; i < N; ++i) {
    const double y = x(i, 1), d = std::fabs(f->u()(i, 0) - 4.0 * y * (1.0 - y));
    e.u = std::max(e.u, d);
    if (x(i, 0) >= 1.0 && x(i, 0) <= 3.0) e.u_mid = std::max(e.u_mid, d);
    e.v = std::max(e.v, std::fabs(f->u()(i, 1)));
  }
  const int nx = p.nx, j = n / 2, i1 = nx / 4, i3 = 3 * nx / 4;  // columns at x = 1 + dx/2 and 3 + dx/2
  e.dpdx = (f->p()[i3 + nx * j] - f->p()[i1 + nx * j]) / (x(i3, 0) - x(i1, 0));
  return e;
}

}  // namespace

// The parabola entering on the left leaves unchanged on the right: the Stokes solution of the
// open channel is the Poiseuille profile with the linear pressure dp/dx = -8 mu u_max / H^2 = -8.
// Measured (n = 16, 32 across): max |u - u_exact| away from the ends (1 <= x <= 3) 7.50e-3, 1.91e-3
// (order 1.97); over every particle 2.75e-2, 1.31e-2 (a layer at the inflow, order 1.07); max |v|
// 1.29e-2, 4.40e-3; dp/dx -7.9813, -7.9945. Tolerances: those at n = 32 with a margin of about 25%.
TEST(OpenChannel, InflowOutflowCarryThePoiseuilleParabola) {
  const Errors e16 = run_open_channel(16), e32 = run_open_channel(32);
  EXPECT_LT(e32.u_mid, 2.5e-3);
  EXPECT_GT(std::log2(e16.u_mid / e32.u_mid), 1.8);
  EXPECT_LT(e32.u, 1.6e-2);
  EXPECT_LT(e32.v, 5.5e-3);
  EXPECT_LT(std::fabs(e32.dpdx + 8.0), 7e-3);
}

// Only EPSPH has them; the exact projection (a stream function constant along walls) refuses them.
TEST(OpenChannel, MethodsAndProjectionsThatCannotRefuse) {
  FluidParams p = open_channel(8);
  p.method = FluidMethod::Wcsph;
  try {
    make_fluid(p);
    ADD_FAILURE() << "wcsph accepted an inflow";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("domain.inflow"), std::string::npos) << e.what();
  }
  p.method = FluidMethod::Eulerian;
  p.projection = Projection::Exact;
  try {
    make_fluid(p);
    ADD_FAILURE() << "the exact projection accepted an inflow";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("fluid.projection"), std::string::npos) << e.what();
  }
}

// Bad scenes: each refusal names the key.
TEST(OpenChannel, BadScenesAreRefusedNamingTheKey) {
  const std::string scene = R"(
[domain]
x = [0.0, 4.0]
y = [0.0, 1.0]
periodic_x = false
inflow = ["left"]
outflow = ["right"]
inflow_profile = "parabolic"
[walls]
left = [1.0, 0.0]
[grid]
nx = 32
ny = 8
[fluid]
rho = 1.0
mu = 1.0
[time]
dt = 1e-3
end = 0.01
)";
  EXPECT_EQ(refusal(scene), "");
  auto expect = [](const std::string& m, const std::string& key, const std::string& what) {
    EXPECT_NE(m.find(key), std::string::npos) << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
  };
  expect(refusal(scene, {"domain.periodic_x=true"}), "domain.inflow", "periodic");
  expect(refusal(scene, {"domain.inflow_profile=\"none\""}), "domain.inflow_profile", "needs its profile");
  expect(refusal(scene, {"walls.left=[0.0, 0.0]"}), "walls.left", "pointing into the domain");
  expect(refusal(scene, {"walls.right=[1.0, 0.0]"}), "walls.right", "outflow side");
  expect(refusal(scene, {"domain.outflow=[\"left\"]"}), "domain.outflow", "already inflow");
  expect(refusal(scene, {"method=\"wcsph\""}), "domain.inflow", "eulerian");
  expect(refusal(scene, {"fluid.projection=\"exact\""}), "fluid.projection", "approximate");
  expect(refusal(scene, {"domain.inflow=[]", "walls.left=[0.0, 0.0]"}), "domain.inflow_profile", "without an inflow side");
}
