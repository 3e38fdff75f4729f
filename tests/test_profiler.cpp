// The fluid contract's data and the Profiler the run loop hands to a method (fluid/core/solver.hpp,
// fluid/common/profile.hpp): every method records its phases, set-up, report and floor there; the base
// class computes the kinetic energy from the particle mass; a profiler outlives its method.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "fluid/factory.hpp"
#include "fluid/common/profile.hpp"
#include "fluid/core/solver.hpp"

using namespace sphib;

namespace {

// A 12 x 12 box with walls on every side, at rest: small enough for every method.
FluidParams params_for(FluidMethod m) {
  FluidParams p;
  p.method = m;
  p.nx = p.ny = 12;
  p.h_over_dx = 1.5;
  p.rho = 1.0;
  p.mu = 0.1;
  p.wcsph.u_scale = 1.0;
  p.wcsph.c = 10.0;
  p.dt = m == FluidMethod::Wcsph ? 1e-4 : 1e-3;
  return p;
}

bool has_line(const FluidReport& r) { return !r.lines.empty() && !r.lines.front().empty(); }

}  // namespace

TEST(Profiler, PhasesOnDemandAreNotPartOfTheStep) {
  Profiler p;
  const int a = p.phase("a"), b = p.on_demand_phase("b");
  p.add(a, 1.0);
  p.add(b, 0.25);
  p.add(a, 0.5);
  EXPECT_EQ(p.step_seconds(), 1.5);
  EXPECT_EQ(p.total(), 1.75);
  p.add_setup("assembly", 0.125);
  EXPECT_EQ(p.setup_seconds("assembly"), 0.125);
  EXPECT_EQ(p.setup_seconds("factorisation"), 0.0);
}

TEST(Profiler, FloorTimesTheRegisteredKernels) {
  Profiler p;
  EXPECT_EQ(p.floor_seconds(3), 0.0);  // none registered
  int calls = 0;
  p.set_floor([&](FloorTimer& t) {
    t.kernel([&] { ++calls; });
    t.kernel([&] { ++calls; });
    t.add(1.0);
  });
  const double f = p.floor_seconds(3);
  EXPECT_EQ(calls, 6);  // two kernels, best of 3 each
  EXPECT_GE(f, 1.0);
  p.detach();
  EXPECT_EQ(p.floor_seconds(3), 0.0);
}

// Every method: the data the base holds, the kinetic energy sum_i m |u_i|^2 / 2 from its particle
// mass, and its report and set-up recorded into the profiler it was handed, which keeps the timings
// and forgets the method's functions when the method goes.
TEST(Profiler, EveryMethodRecordsIntoTheProfilerItIsHanded) {
  for (FluidMethod m : {FluidMethod::Eulerian, FluidMethod::Lagrangian, FluidMethod::Isph, FluidMethod::Wcsph}) {
    SCOPED_TRACE(to_string(m));
    Profiler prof;
    {
      const FluidParams p = params_for(m);
      std::unique_ptr<FluidSolver> f = make_fluid(p, &prof);
      EXPECT_EQ(&f->profiler(), &prof);
      EXPECT_EQ(f->particles_move(), m != FluidMethod::Eulerian);
      if (!f->particles_move()) EXPECT_EQ(&f->x(), &f->lattice().x);  // fixed particles: the lattice's sites
      EXPECT_EQ(f->size(), f->x().rows());
      EXPECT_EQ(f->volumes().size(), f->size());
      EXPECT_EQ(f->has_stream_function(), m == FluidMethod::Eulerian);
      EXPECT_EQ(f->supports_variable_viscosity(), m == FluidMethod::Eulerian);

      Mat2 u0 = Mat2::Zero(f->size(), 2);
      u0.col(0).setConstant(0.01);
      f->set_velocity(u0);
      // sum_i m |u_i|^2 / 2 over the particles, m = rho V (projection methods) or WCSPH's m
      const double V = m == FluidMethod::Wcsph ? f->volumes()[0] * f->phi()[0] : p.rho * f->volumes()[0];
      EXPECT_NEAR(f->kinetic_energy(), 0.5 * V * 1e-4 * f->size(), 1e-12 * V * f->size());

      const Mat2 F = Mat2::Zero(f->size(), 2);
      for (int s = 0; s < 2; ++s) f->step(F);
      EXPECT_EQ(f->steps(), 2);
      EXPECT_GT(prof.step_seconds(), 0.0);
      EXPECT_GT(prof.names().size(), 0u);
      const FluidReport r = prof.report();
      EXPECT_TRUE(has_line(r));
      EXPECT_FALSE(r.figures.empty());
      EXPECT_EQ(r.footprint.has_value(), m == FluidMethod::Eulerian);
      EXPECT_EQ(prof.floor_seconds(2) > 0, m == FluidMethod::Eulerian);  // only EPSPH registers a floor
    }
    // the method is gone: its timings stay, its report and floor with it
    EXPECT_GT(prof.step_seconds(), 0.0);
    EXPECT_TRUE(prof.report().lines.empty());
    EXPECT_EQ(prof.floor_seconds(2), 0.0);
  }
}

// Without a profiler handed over, a method keeps its own.
TEST(Profiler, AMethodWithoutOneKeepsItsOwn) {
  auto f = make_fluid(params_for(FluidMethod::Eulerian));
  f->step(Mat2::Zero(f->size(), 2));
  EXPECT_GT(f->profiler().step_seconds(), 0.0);
  EXPECT_TRUE(has_line(f->profiler().report()));
}
