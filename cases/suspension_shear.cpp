// A suspension of capsules in a sheared box (the scene: cases/suspension.hpp): 100 Hookean capsules
// of 64 markers at area fraction 0.3, placed at random without overlap, between walls sliding at
// -+1/2, periodic in x, at 256 x 256. The contact force (coupling/contact.hpp) keeps them apart.
// Observed: the effective viscosity mu_eff = wall shear stress / G (column mu_eff; its mean over the
// run's second half in summary.json), the least distance between markers of different capsules
// (gap_min at every diagnostics row; contact_min, the least over every step, with contact on) and
// the largest relative area error of a capsule (area_err_max).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "cases/suspension.hpp"
#include "coupling/contact.hpp"
#include "io/run.hpp"
#include "membrane/geometry.hpp"

using namespace sphib;

int main(int argc, char** argv) {
  SuspensionParams p;
  p.contact_strength = 0.1;
  double t_end = 10.0;
  long steps = 0, every = 0;
  std::string out = "out/suspension_shear";
  CLI::App app{"capsule suspension in a sheared box: effective viscosity, gaps, areas"};
  add_suspension_options(app, p);
  app.add_option("--phi", p.phi, "area fraction of the capsules");
  app.add_option("--ca", p.Ca, "capillary number mu G a / T0");
  app.add_option("--cfl", p.cfl, "time step dt = cfl dx / U");
  app.add_option("--seed", p.seed, "seed of the random placement");
  app.add_option("--contact-range", p.contact_range, "its range r0 in lattice spacings");
  app.add_flag("--empty", p.empty, "the same box without capsules");
  app.add_option("--t-end", t_end, "end time in units of 1/G");
  app.add_option("--steps", steps, "stop after this many steps");
  app.add_option("--diagnostics-every", every, "steps between diagnostics rows (0: about 500 rows)");
  app.add_option("--out", out, "output directory");
  CLI11_PARSE(app, argc, argv);

  Scene s = suspension_scene(p);
  s.t_end = t_end, s.max_steps = steps, s.diagnostics_every = every, s.output_interval = t_end;
  const int M = static_cast<int>(s.sim.membranes.size());
  std::vector<int> start{0};
  for (const auto& m : s.sim.membranes) start.push_back(start.back() + m.membrane.nb());
  const double dx = 1.0 / p.nx, a = p.radius();
  std::vector<MembraneDiagnostics> D;
  std::vector<double> A0;
  Mat2 X(start.back(), 2);
  double gap_least = INFINITY, area_worst = 0.0;  // over the diagnostics rows
  s.observers = {
      {"gap_min", [&](const Simulation& sim) {  // least distance between markers of different capsules
         if (M == 0) return double(NAN);
         for (int k = 0; k < M; ++k) X.middleRows(start[k], p.nb) = sim.membranes()[k].m.X;
         const double g = least_marker_distance(X, start, sim.fluid().params().domain, 2 * a);
         gap_least = std::min(gap_least, g);
         return g;
       }},
      {"contact_min", [&](const Simulation& sim) {  // the least over every step so far (contact on)
         return sim.contact() ? sim.contact()->least_distance_so_far() : NAN;
       }},
      {"area_err_max", [&](const Simulation& sim) {  // the largest |A/A(0) - 1| of a capsule
         if (M == 0) return double(NAN);
         double e = 0.0;
         for (int k = 0; k < M; ++k) {
           if (static_cast<int>(D.size()) <= k) D.emplace_back(p.nb, sim.membranes()[k].m.L0());
           const double A = D[k].measure(sim.membranes()[k].m.X).area;
           if (static_cast<int>(A0.size()) <= k) A0.push_back(A);
           e = std::max(e, std::fabs(A / A0[k] - 1.0));
         }
         area_worst = std::max(area_worst, e);
         return e;
       }},
  };
  std::printf("%d capsules of radius %.5f (%.2f dx), %d markers (%.2f per dx), T0 = %.4g, dt = %.4g\n", M, a,
              a / dx, p.nb, p.nb * dx / (2 * M_PI * a), p.T0(), s.sim.fluid.dt);
  RunOptions run;
  run.out_dir = out;
  run.log = &std::cout;
  const nlohmann::json sum = run_scene(s, run);
  std::printf("mu_eff/mu %.4f (mean over the second half %.4f); least marker gap %.3g dx over the rows, "
              "%.3g dx over every step (contact); area error: last %.3g, largest %.3g over the rows; "
              "%.2f ms/step\n",
              sum.value("mu_eff", NAN), sum.value("mu_eff_mean_second_half", NAN), gap_least / dx,
              sum.value("contact_min", NAN) / dx, sum.value("area_err_max", NAN), area_worst,
              1e3 * sum.value("seconds_per_step", NAN));
}
