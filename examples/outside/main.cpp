// A program outside the sphib tree: a circular membrane, stretched to 1.2 times its rest radius,
// relaxes in a periodic channel; a few steps, then its area and the kinetic energy.
#include <cstdio>

#include <sphib/coupling/simulation.hpp>
#include <sphib/membrane/polygon.hpp>
#include <sphib/membrane/shapes.hpp>
#include <sphib/sphib_version.hpp>

int main() {
  sphib::SimulationParams P;
  P.fluid.domain = {-1.0, 1.0, -1.0, 1.0, /*periodic_x=*/true, /*periodic_y=*/false};
  P.fluid.nx = P.fluid.ny = 24;
  P.fluid.mu = 0.5;
  P.fluid.dt = 2e-3;
  const double r0 = 0.4;
  P.membranes.push_back({sphib::make_membrane(sphib::circle(48, 0.0, 0.0, 1.2 * r0), r0, /*T0=*/1.0), /*h_star=*/0.14});
  sphib::Simulation sim(P);
  const double A0 = sphib::signed_area(sim.membranes()[0].m.X);
  for (int n = 0; n < 10; ++n) sim.step();
  const double A = sphib::signed_area(sim.membranes()[0].m.X);
  std::printf("sphib %s: %ld steps, t = %g, area %.6f (t = 0: %.6f), kinetic energy %.3e\n", SPHIB_VERSION,
              sim.steps(), sim.time(), A, A0, sim.fluid().kinetic_energy());
  return sim.steps() == 10 && A > 0.0 ? 0 : 1;
}
