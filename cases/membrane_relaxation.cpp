// Relaxation of a slightly deformed circular membrane with bending (docs/membrane_validation.md,
// "Relaxation of modes 2 and 3"). A membrane at rest on its reference circle of radius R = r0 is
// released from r(theta) = R (1 + eps cos(n theta)), markers uniform in the arclength of that shape
// (the length-keeping displacement of the circle's material points, rho + i n eta = 0); fluid at
// rest in [-L/2, L/2]^2, periodic in x, walls at y = +-L/2. The mode decays at the Stokes rate
//   sigma_n = n ((n^2 - 1) Eb / R^2 + Tbar) / (4 mu R)          (Tbar = 0 at rest)
// whatever the tension law; the stretching mode (rate n E / (4 mu R), E = dT/dlambda at rest) is not
// excited by this start, and decays much faster with the default Es. Measured: the mode's amplitude
// a_n (cases/membrane_relaxation.hpp: = eps for the shape above) and its decay rate, a least-squares
// fit of log a_n(t) while a_n falls from exp(-0.5) to exp(-3) of its start.
// Defaults: R = 0.5, L = 4, mu = 1, rho = 0.01 (the Stokes limit: sigma R^2 rho/mu < 0.02), Skalak
// Es = 10, C = 1 (stretching rates 40 and 60 for modes 2 and 3, against bending's 1.2 and 4.8), Eb = 0.1,
// eps = 0.02, two markers per dx, h* = 1.4 h, dt = 5e-4.
//   membrane_relaxation [--mode 2,3] [--nx 32,64,128] [--length 4] [--out DIR] ...      (--help)
// Writes DIR/n<mode>_nx<nx>/ (each run) and DIR/table.csv; prints the table with the observed order
// of the rate error in h between successive nx.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cases/membrane_relaxation.hpp"
#include "io/run.hpp"

using namespace sphib;

int main(int argc, char** argv) {
  std::vector<int> modes{2, 3}, nxs{32, 64, 128};
  std::string out = "out/membrane_relaxation", interp = "auto";
  RelaxationParams p;
  bool explicit_force = false;
  long steps = 0;
  CLI::App app{"relaxation of a slightly deformed circular membrane with bending: decay rate of modes n"};
  app.add_option("--mode", modes, "modes n (comma-separated)")->delimiter(',');
  app.add_option("--nx", nxs, "particles per side (comma-separated)")->delimiter(',');
  app.add_option("--length", p.L, "domain side L (walls at y = +-L/2, periodic in x)");
  app.add_option("--law", p.law, "tension law (membrane.law)");
  app.add_option("--Es", p.Es, "the law's modulus");
  app.add_option("--Eb", p.Eb, "bending modulus")->check(CLI::PositiveNumber);
  app.add_option("--mu", p.mu, "viscosity");
  app.add_option("--rho", p.rho, "density");
  app.add_option("--eps", p.eps, "relative amplitude of the initial mode");
  app.add_option("--dt", p.dt, "time step");
  app.add_option("--markers-per-dx", p.markers_per_dx, "markers per lattice spacing (rest spacing)");
  app.add_option("--h-star-over-h", p.h_star_over_h, "h* / h");
  app.add_option("--out", out, "output directory");
  app.add_option("--steps", steps, "stop each run after this many steps (smoke test)");
  app.add_flag("--explicit", explicit_force, "explicit membrane force (no stiff-force filter)");
  app.add_option("--interpolation", interp, "marker velocity (coupling.interpolation): auto (bspline with bending), "
                 "bspline, divergence_free, sph, spreading_kernel (the curl with the kernel of radius h*)")
      ->check(CLI::IsMember({"auto", "bspline", "divergence_free", "sph", "spreading_kernel"}));
  CLI11_PARSE(app, argc, argv);
  p.semi_implicit = !explicit_force;
  p.interpolation = interp == "bspline"           ? MarkerInterpolation::BSpline
                    : interp == "divergence_free" ? MarkerInterpolation::DivergenceFree
                    : interp == "sph"             ? MarkerInterpolation::Sph
                    : interp == "spreading_kernel" ? MarkerInterpolation::SpreadingKernel
                                                  : MarkerInterpolation::Auto;

  std::filesystem::create_directories(out);
  std::ofstream table(out + "/table.csv.part");
  table << "mode,nx,dx,nb,sigma,sigma_stokes,rel_error,area_relative_error,steps,wall_seconds\n";
  std::printf("%4s %5s %8s %5s %10s %10s %10s %7s %10s %7s\n", "n", "nx", "dx", "nb", "sigma", "Stokes", "rel.err",
              "order", "area_err", "s");
  for (int n : modes) {
    double last_err = NAN, last_dx = NAN;
    for (int nx : nxs) {
      p.mode = n, p.nx = nx;
      Scene s = relaxation_scene(p);
      char name[64];
      std::snprintf(name, sizeof name, "n%d_nx%d", n, nx);
      s.title = std::string("membrane relaxation, ") + name;
      s.max_steps = steps;
      std::vector<std::pair<double, double>> hist;  // t, a_n
      s.observers = {{"a_n", [&](const Simulation& sim) {
                        hist.push_back({sim.time(), mode_amplitude(sim.membranes()[0].m.X, n)});
                        return hist.back().second;
                      }}};
      RunOptions run;
      run.out_dir = out + "/" + name;
      const nlohmann::json summary = run_scene(s, run);
      const double dx = p.L / nx, rate = decay_rate(hist), sigma = p.stokes_rate(), err = rate / sigma - 1.0;
      const double order = std::log(std::fabs(last_err / err)) / std::log(last_dx / dx);
      const int nb = s.sim.membranes[0].membrane.nb();
      std::printf("%4d %5d %8.5f %5d %10.6f %10.6f %10.2e %7.2f %10.2e %7.1f\n", n, nx, dx, nb, rate, sigma, err, order,
                  summary["area_relative_error"].get<double>(), summary["wall_seconds"].get<double>());
      std::fflush(stdout);  // (a later run that blows up must not take this line with it)
      table << n << "," << nx << "," << dx << "," << nb << "," << rate << "," << sigma << "," << err << ","
            << summary["area_relative_error"] << "," << summary["steps"] << "," << summary["wall_seconds"] << "\n";
      last_err = err, last_dx = dx;
    }
  }
  table.close();
  std::filesystem::rename(out + "/table.csv.part", out + "/table.csv");
  std::printf("table: %s/table.csv, runs: %s/n*_nx*/\n", out.c_str(), out.c_str());
}
