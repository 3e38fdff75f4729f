// Relaxation of a slightly deformed circular membrane with bending (docs/membrane_validation.md,
// "Relaxation of modes 2 and 3"). A membrane at rest on its reference circle of radius R = r0 is
// released from r(theta) = R (1 + eps cos(n theta)), markers uniform in the arclength of that shape
// (the length-keeping displacement of the circle's material points, rho + i n eta = 0); fluid at
// rest in [-L/2, L/2]^2, periodic in x, walls at y = +-L/2. The mode decays at the Stokes rate
//   sigma_n = n ((n^2 - 1) Eb / R^2 + Tbar) / (4 mu R)          (Tbar = 0 at rest)
// whatever the tension law; the stretching mode (rate n E / (4 mu R), E = dT/dlambda at rest) is not
// excited by this start, and decays much faster with the default Es. Measured: the mode's amplitude
// a_n = |int (z - c)^n dA| / (pi R^{n+2}) (z = x + i y about the area centroid c, R = sqrt(A/pi); = eps for
// the shape above, to first order) and its decay
// rate, a least-squares fit of log a_n(t) while a_n falls from exp(-0.5) to exp(-3) of its start.
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

#include "io/run.hpp"
#include "cases/membrane_modes.hpp"
#include "membrane/shapes.hpp"

using namespace sphib;

int main(int argc, char** argv) {
  std::vector<int> modes{2, 3}, nxs{32, 64, 128};
  std::string out = "out/membrane_relaxation", law = "skalak";
  double L = 4.0, R = 0.5, mu = 1.0, rho = 0.01, Es = 10.0, Eb = 0.1, eps = 0.02, dt = 5e-4, t_end = 0.0;
  double markers_per_dx = 2.0, hsh = 1.4;
  bool explicit_force = false;
  long steps = 0;
  std::string interp = "auto";
  CLI::App app{"relaxation of a slightly deformed circular membrane with bending: decay rate of modes n"};
  app.add_option("--mode", modes, "modes n (comma-separated)")->delimiter(',');
  app.add_option("--nx", nxs, "particles per side (comma-separated)")->delimiter(',');
  app.add_option("--length", L, "domain side L (walls at y = +-L/2, periodic in x)");
  app.add_option("--law", law, "tension law (membrane.law)");
  app.add_option("--Es", Es, "the law's modulus");
  app.add_option("--Eb", Eb, "bending modulus")->check(CLI::PositiveNumber);
  app.add_option("--mu", mu, "viscosity");
  app.add_option("--rho", rho, "density");
  app.add_option("--eps", eps, "relative amplitude of the initial mode");
  app.add_option("--dt", dt, "time step");
  app.add_option("--t-end", t_end, "end time (0: 3.5 / sigma_n)");
  app.add_option("--markers-per-dx", markers_per_dx, "markers per lattice spacing (rest spacing)");
  app.add_option("--h-star-over-h", hsh, "h* / h");
  app.add_option("--out", out, "output directory");
  app.add_option("--steps", steps, "stop each run after this many steps (smoke test)");
  app.add_flag("--explicit", explicit_force, "explicit membrane force (no stiff-force filter)");
  app.add_option("--interpolation", interp, "marker velocity (coupling.interpolation): auto (bspline with bending), "
                 "bspline, divergence_free, sph")->check(CLI::IsMember({"auto", "bspline", "divergence_free", "sph"}));
  CLI11_PARSE(app, argc, argv);

  std::filesystem::create_directories(out);
  std::ofstream table(out + "/table.csv.part");
  table << "mode,nx,dx,nb,sigma,sigma_stokes,rel_error,amplitude0,area_relative_error,steps,wall_seconds\n";
  std::printf("%4s %5s %8s %5s %10s %10s %10s %7s %10s %7s\n", "n", "nx", "dx", "nb", "sigma", "Stokes", "rel.err",
              "order", "area_err", "s");
  for (int n : modes) {
    const double sigma = n * (n * n - 1) * Eb / (R * R) / (4 * mu * R);  // the Stokes rate (Tbar = 0)
    double last_err = NAN, last_dx = NAN;
    for (int nx : nxs) {
      Scene s;
      char name[64];
      std::snprintf(name, sizeof name, "n%d_nx%d", n, nx);
      s.title = std::string("membrane relaxation, ") + name;
      FluidParams& f = s.sim.fluid;
      f.domain = {-L / 2, L / 2, -L / 2, L / 2, /*periodic_x=*/true, /*periodic_y=*/false};
      f.nx = nx, f.ny = nx, f.rho = rho, f.mu = mu, f.dt = dt;
      s.sim.interpolation = interp == "bspline"           ? MarkerInterpolation::BSpline
                            : interp == "divergence_free" ? MarkerInterpolation::DivergenceFree
                            : interp == "sph"             ? MarkerInterpolation::Sph
                                                          : MarkerInterpolation::Auto;
      const double dx = L / nx;
      const int nb = static_cast<int>(std::lround(markers_per_dx * 2 * M_PI * R / dx));
      const Mat2 X = from_polar([&](double th) { return R * (1 + eps * std::cos(n * th)); }, nb);
      Material mat;
      mat.law = law, mat.Es = Es, mat.Eb = Eb;
      MembraneSetup m{make_membrane(X, circle_reference(R), mat), hsh * f.h_over_dx * dx};
      m.semi_implicit = !explicit_force;
      s.sim.membranes.push_back(m);
      s.t_end = t_end > 0 ? t_end : 3.5 / sigma, s.max_steps = steps;
      s.diagnostics_every = std::max(1L, std::lround(s.t_end / dt / 400));

      std::vector<std::pair<double, double>> hist;  // t, a_n
      s.observers = {{"a_n", [&](const Simulation& sim) {
                        hist.push_back({sim.time(), mode_amplitude(sim.membranes()[0].m.X, n)});
                        return hist.back().second;
                      }}};
      RunOptions run;
      run.out_dir = out + "/" + name;
      const nlohmann::json summary = run_scene(s, run);
      // least squares of log a_n on t while a_n / a_n(0) is in [e^-3, e^-0.5]
      const double a0 = hist.front().second;
      double st = 0, sa = 0, stt = 0, sta = 0, c = 0;
      for (const auto& [t, a] : hist)
        if (a <= a0 * std::exp(-0.5) && a >= a0 * std::exp(-3.0)) {
          st += t, sa += std::log(a), stt += t * t, sta += t * std::log(a), ++c;
        }
      const double rate = c >= 3 ? -(c * sta - st * sa) / (c * stt - st * st) : NAN;
      const double err = rate / sigma - 1.0;
      const double order = std::log(std::fabs(last_err / err)) / std::log(last_dx / dx);
      std::printf("%4d %5d %8.5f %5d %10.6f %10.6f %10.2e %7.2f %10.2e %7.1f\n", n, nx, dx, nb, rate, sigma, err, order,
                  summary["area_relative_error"].get<double>(), summary["wall_seconds"].get<double>());
      std::fflush(stdout);  // (a later run that blows up must not take this line with it)
      table << n << "," << nx << "," << dx << "," << nb << "," << rate << "," << sigma << "," << err << "," << a0 << ","
            << summary["area_relative_error"] << "," << summary["steps"] << "," << summary["wall_seconds"] << "\n";
      last_err = err, last_dx = dx;
    }
  }
  table.close();
  std::filesystem::rename(out + "/table.csv.part", out + "/table.csv");
  std::printf("table: %s/table.csv, runs: %s/n*_nx*/\n", out.c_str(), out.c_str());
}
