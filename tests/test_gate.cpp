// A dam break's gate for ISPH (GateParams, walls.hpp append_gate, isph.hpp): it holds a column at rest
// until it lifts, lets the water out under it, and leaves the tank when its lower edge is 2h above the
// water. Bad gate keys are refused by name. Tolerances are measured values (Release build) with a
// margin, stated beside each test.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "fluid/moving/isph.hpp"
#include "fluid/moving/wcsph.hpp"
#include "io/scene.hpp"
#include "scene_refusal.hpp"
#include "still_tank_scene.hpp"

using namespace sphib;

namespace {

// The still tank's water (1 m tank, dx = 0.05) as a column 0.4 m wide and 0.5 m high behind a gate on
// the lattice line x = 0.4.
const std::vector<std::string> kColumn = {"method=isph", "time.dt=1e-3", "fill.x=[0.0, 0.4]"};

Scene column(std::vector<std::string> sets) {
  sets.insert(sets.begin(), kColumn.begin(), kColumn.end());
  return parse_scene(test::kStillTank, "column.toml", sets);
}

// The same column by WCSPH (the still tank's keys: predictor-corrector, Tait, dt = 4e-4).
Scene wcsph_column(std::vector<std::string> sets) {
  sets.insert(sets.begin(), "fill.x=[0.0, 0.4]");
  return parse_scene(test::kStillTank, "column.toml", sets);
}

std::string refused(std::vector<std::string> sets) {
  sets.insert(sets.begin(), kColumn.begin(), kColumn.end());
  return test::refusal(test::kStillTank, sets);
}

double max_speed(const FluidSolver& f) { return f.u().rowwise().norm().maxCoeff(); }

}  // namespace

// A gate that does not lift within the run holds the column as the tank's walls hold a tank at rest.
// Measured, 8 x 10 particles, 300 steps (t = 0.3): max speed 2.1e-14 m/s with the gate; without it
// the column collapses (max speed 3.35 m/s).
TEST(Gate, HoldsAColumnAtRestUntilItLifts) {
  Scene s = column({"gate.x=0.4", "gate.speed=1.0", "gate.start=10.0"});
  IsphFluid f(s.sim.fluid);
  ASSERT_EQ(f.size(), 8 * 10);
  const Mat2 F = Mat2::Zero(f.size(), 2);
  for (int n = 0; n < 300; ++n) f.step(F);
  EXPECT_LT(max_speed(f), 1e-10);
  EXPECT_LT(f.x().col(0).maxCoeff(), 0.4);
  Scene free = column({});
  IsphFluid g(free.sim.fluid);
  for (int n = 0; n < 300; ++n) g.step(F);
  EXPECT_GT(max_speed(g), 0.5);  // what the gate holds back
}

// Lifted at 2 m/s from t = 0.05, the gate stays in place before its start (the water still), lets the
// water out under it, and is removed at the first step whose lower edge, 2 (t - 0.05) above the floor,
// lies more than 2h above the highest particle (the walls then the tank's alone). Measured: removed at
// step 303 (lower edge 0.506 m, highest particle 0.376 m, 2h = 0.13 m).
TEST(Gate, LeavesTheTankOnSchedule) {
  Scene s = column({"gate.x=0.4", "gate.speed=2.0", "gate.start=0.05"});
  IsphFluid f(s.sim.fluid);
  Scene none = column({});
  const int tank_walls = IsphFluid(none.sim.fluid).walls().size();
  ASSERT_GT(f.walls().size(), tank_walls);
  const double support = 2.0 * f.kernel().h, dt = 1e-3;
  const Mat2 F = Mat2::Zero(f.size(), 2);
  int removed = -1;
  for (int n = 1; n <= 500 && removed < 0; ++n) {
    const double y_top = (f.x() + dt * f.u()).col(1).maxCoeff();  // x* of the step (the criterion's)
    f.step(F);
    const double edge = 2.0 * std::max(0.0, n * dt - 0.05);
    if (n * dt < 0.05 - 0.5 * dt) {  // (the step that ends at 0.05 may see the gate start by round-off)
      EXPECT_LT(max_speed(f), 1e-10) << n;
      EXPECT_GT(f.walls().size(), tank_walls) << n;
    }
    if (f.walls().size() == tank_walls) {
      removed = n;
      EXPECT_GT(edge, y_top + support) << n;
      EXPECT_LE(edge - 2.0 * dt, y_top + support + 0.02) << n;  // not long after (the top falls meanwhile)
    }
  }
  EXPECT_GT(removed, 0);
  EXPECT_GT(f.x().col(0).maxCoeff(), 0.6);  // the water has run out under the gate
}

// WCSPH: the gate holds the column as the tank's walls hold a tank (the weakly compressible water
// settles at small speeds), and leaves on the same schedule. Measured, 8 x 10 particles, 500 steps
// (t = 0.2): max speed 0.0164 m/s with the gate, 0.0170 in the tank's 20 x 10 at rest without a gate;
// without the gate the column collapses (2.19 m/s). Lifted at 2 m/s from t = 0.05: removed at step 764
// (lower edge 0.511 m, highest particle 0.380 m).
TEST(Gate, WcsphHoldsAColumnAndLeaves) {
  Scene s = wcsph_column({"gate.x=0.4", "gate.speed=1.0", "gate.start=10.0"});
  WcsphFluid f(s.sim.fluid);
  ASSERT_EQ(f.size(), 8 * 10);
  const Mat2 F = Mat2::Zero(f.size(), 2);
  for (int n = 0; n < 500; ++n) f.step(F);
  EXPECT_LT(f.x().col(0).maxCoeff(), 0.4);
  Scene free = wcsph_column({});
  WcsphFluid g(free.sim.fluid);
  const int tank_walls = g.wall_x().rows();
  for (int n = 0; n < 500; ++n) g.step(F);
  Scene tank = parse_scene(test::kStillTank, "tank.toml", {});  // the tank's water at rest, without a gate
  WcsphFluid k(tank.sim.fluid);
  const Mat2 Fk = Mat2::Zero(k.size(), 2);
  for (int n = 0; n < 500; ++n) k.step(Fk);
  EXPECT_LT(max_speed(f), 1.5 * max_speed(k));  // as still as a tank
  EXPECT_GT(max_speed(g), 0.5);  // what the gate holds back

  Scene l = wcsph_column({"gate.x=0.4", "gate.speed=2.0", "gate.start=0.05"});
  WcsphFluid h(l.sim.fluid);
  EXPECT_GT(h.wall_x().rows(), tank_walls);
  const double support = 2.0 * h.kernel().h, dt = 4e-4;
  int removed = -1;
  for (int n = 0; n < 1500 && removed < 0; ++n) {
    const double y_top = h.x().col(1).maxCoeff(), t = n * dt;  // the step's evaluation at x^n, t^n
    h.step(F);
    if (h.wall_x().rows() == tank_walls) {
      removed = n;
      EXPECT_GT(2.0 * (t - 0.05), y_top + support) << n;
      EXPECT_LE(2.0 * (t - dt - 0.05), y_top + support + 0.01) << n;
    }
  }
  EXPECT_GT(removed, 0);
  EXPECT_GT(h.x().col(0).maxCoeff(), 0.6);  // the water has run out under the gate
}

// A gate lifted so fast that it is gone at the first step releases the column as no gate does: the
// plate carries no velocity into the pairs (walls.hpp), so nothing of it stays in the flow. Measured,
// 100 steps (ISPH) and 250 (WCSPH), t = 0.1: positions within 9.1e-9 m (ISPH) and 2.5e-4 m (WCSPH, its
// first evaluation at t = 0 has the gate) of the run without a gate, dx = 0.05 m.
TEST(Gate, GoneAtOnceIsNoGate) {
  Scene s = column({"gate.x=0.4", "gate.speed=1000.0"}), n = column({});
  IsphFluid f(s.sim.fluid), g(n.sim.fluid);
  const Mat2 F = Mat2::Zero(f.size(), 2);
  for (int k = 0; k < 100; ++k) {
    f.step(F);
    g.step(F);
  }
  EXPECT_GT(g.x().col(0).maxCoeff(), 0.43);  // the column has moved (measured 0.456; 0.375 at t = 0)
  EXPECT_LT((f.x() - g.x()).cwiseAbs().maxCoeff(), 1e-6);
  Scene sw = wcsph_column({"gate.x=0.4", "gate.speed=1000.0"}), nw = wcsph_column({});
  WcsphFluid a(sw.sim.fluid), b(nw.sim.fluid);
  for (int k = 0; k < 250; ++k) {
    a.step(F);
    b.step(F);
  }
  EXPECT_GT(b.x().col(0).maxCoeff(), 0.42);  // measured 0.439
  EXPECT_LT((a.x() - b.x()).cwiseAbs().maxCoeff(), 1e-3);
}

// A checkpoint taken while the gate moves: the restored run places the gate where it was and continues
// bit for bit (ISPH with the direct Poisson solver, as Isph.CheckpointContinuesBitForBit; WCSPH).
TEST(Gate, CheckpointWhileItLiftsContinuesBitForBit) {
  Scene s = column({"gate.x=0.4", "gate.speed=2.0", "gate.start=0.01", "solver.poisson=cholmod_supernodal"});
  EXPECT_GT(test::restart_continues_bit_for_bit<IsphFluid>(s.sim.fluid, 30), 0.1);
  Scene w = wcsph_column({"gate.x=0.4", "gate.speed=2.0", "gate.start=0.01"});
  EXPECT_GT(test::restart_continues_bit_for_bit<WcsphFluid>(w.sim.fluid, 60), 0.1);
}

TEST(Gate, BadInputIsRefusedByKey) {
  auto expect = [](const std::string& m, const std::string& key, const std::string& what) {
    EXPECT_NE(m.find(key), std::string::npos) << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
  };
  expect(refused({"gate.x=0.4"}), "gate.speed", "missing");
  expect(refused({"gate.speed=1.0"}), "gate.x", "missing");
  expect(refused({"gate.x=0.4", "gate.speed=0"}), "gate.speed", "out of range");
  expect(refused({"gate.x=0.4", "gate.speed=1.0", "gate.start=-1"}), "gate.start", "out of range");
  expect(refused({"gate.x=1.5", "gate.speed=1.0"}), "gate.x", "inside the domain");
  expect(refused({"gate.x=0.3", "gate.speed=1.0"}), "gate.x", "low side");
  expect(refused({"gate.x=0.4", "gate.speed=1.0", "gate.lift=2"}), "gate.lift", "unknown");
  expect(test::refusal(test::kStillTank, {"method=lagrangian", "fill.x=[0.0, 0.4]", "gate.x=0.4", "gate.speed=1.0"}),
         "gate", "\"isph\" and \"wcsph\" only");
  expect(test::refusal(test::kStillTank, {"fill.x=[0.0, 0.4]", "gate.x=0.3", "gate.speed=1.0"}), "gate.x", "low side");
}
