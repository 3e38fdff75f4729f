// A capsule in simple shear flow: a circular Hookean membrane at its rest length (radius = r0)
// between walls y = +-H/2 sliding at -+U, periodic in x. Shear rate G = 2U/H; capillary number
// Ca = mu G r0 / T0. The capsule becomes an inclined ellipse round which its membrane rotates.
// Observed: Taylor deformation D = (L - B)/(L + B) and inclination theta of the ellipse with the
// membrane polygon's area moments (ellipse_fit); tank-treading frequency omega (mean angular
// velocity of the markers about the centroid, < 0 clockwise). The table: means over the last
// quarter of each run, with the standard deviation and drift of D over it (unsteady or not yet
// steady). Writes DIR/ca_<Ca>/ (each run) and DIR/table.csv.
// Dimensionless: H = 2, L = 4, U = 1 (G = 1), r0 = 0.4 (2 r0/H = 0.4), rho = 1, mu = 1
// (Re = rho G r0^2/mu = 0.16), T0 = mu G r0/Ca, 64 x 32 particles, t_end = 16/G, dt = 0.0125 dx/U.
// No small-deformation formula for a 2-D tension-only ring is used: at rest length the circle
// already encloses the most area for its length, so it cannot deform without stretching, and any
// area the method loses (column area_err) lets it deform more: read D with area_err beside it.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "io/run.hpp"
#include "membrane/polygon.hpp"
#include "membrane/shapes.hpp"

using namespace sphib;

int main(int argc, char** argv) {
  std::vector<double> cas{0.05, 0.1, 0.2};
  std::string out = "out/capsule_shear";
  long steps = 0;
  int nx = 64;
  double t_end = 16.0, cfl = 0.0125, lambda = 1.0;
  CLI::App app{"capsule in simple shear: D(Ca), theta(Ca), tank-treading frequency"};
  app.add_option("--ca", cas, "capillary numbers mu G r0 / T0 (comma-separated)")->delimiter(',');
  app.add_option("--out", out, "output directory");
  app.add_option("--steps", steps, "stop each run after this many steps (smoke test)");
  app.add_option("--nx", nx, "particles along x (ny = nx/2)");
  app.add_option("--t-end", t_end, "end time in units of 1/G");
  app.add_option("--cfl", cfl, "time step dt = cfl dx / U");
  app.add_option("--lambda", lambda, "viscosity ratio mu_in / mu_out of the capsule's fluid (method eulerian)");
  bool paper = false;
  app.add_flag("--paper-pair", paper, "the paper's approximate projection and SPH interpolation (Eq. 63)");
  CLI11_PARSE(app, argc, argv);

  const double H = 2.0, L = 4.0, U = 1.0, G = 2.0 * U / H, r0 = 0.4, rho = 1.0, mu = 1.0;
  std::filesystem::create_directories(out);
  std::ofstream table(out + "/table.csv.part");
  table << "Ca,T0,D,D_sd,D_drift,theta_deg,omega_over_G,area_relative_error,steps,wall_seconds\n";
  std::printf("%6s %6s %8s %8s %9s %9s %9s %10s %7s\n", "Ca", "T0", "D", "D sd", "D drift", "theta", "omega/G",
              "area_err", "s");
  for (double Ca : cas) {
    Scene s;
    char name[64];
    if (lambda == 1.0) std::snprintf(name, sizeof name, "ca_%g", Ca);
    else std::snprintf(name, sizeof name, "ca_%g_lambda_%g", Ca, lambda);
    s.title = std::string("capsule in shear flow, ") + name;
    FluidParams& f = s.sim.fluid;
    f.domain = {-L / 2, L / 2, -H / 2, H / 2, /*periodic_x=*/true, /*periodic_y=*/false};
    f.domain.wall_velocity[Top] = {U, 0.0};
    f.domain.wall_velocity[Bottom] = {-U, 0.0};
    f.nx = nx, f.ny = nx / 2, f.rho = rho, f.mu = mu;
    if (paper) {
      f.projection = Projection::Approximate;
      s.sim.interpolation = MarkerInterpolation::Sph;
    }
    const double dx = L / nx, h_star = 1.4 * f.h_over_dx * dx, T0 = mu * G * r0 / Ca;
    f.dt = cfl * dx / U;  // below the elastic limit max(sqrt(rho h*^3/T0), 10 mu h*/T0) of `sphib check`
    const int nb = static_cast<int>(std::lround(2 * M_PI * r0 / (0.5 * dx)));  // two markers per dx
    s.sim.membranes.push_back({make_membrane(circle(nb, 0.0, 0.0, /*radius=*/r0), r0, T0), h_star});
    s.sim.membranes.back().viscosity_ratio = lambda;
    s.t_end = t_end / G, s.max_steps = steps;

    std::vector<std::array<double, 4>> hist;  // t, D, theta, omega at every diagnostics row
    s.observers = {
        {"D", [&](const Simulation& sim) {
           const auto& m = sim.membranes()[0];
           const ShapeMoments e = ellipse_fit(m.m.X);
           hist.push_back({sim.time(), e.deformation(), e.theta, mean_angular_velocity(m.m.X, m.U, e.centroid)});
           return e.deformation();
         }},
        {"theta_deg", [&](const Simulation&) { return hist.back()[2] * 180 / M_PI; }},
        {"omega_over_G", [&](const Simulation&) { return hist.back()[3] / G; }},
    };
    RunOptions run;
    run.out_dir = out + "/" + name;
    const nlohmann::json summary = run_scene(s, run);

    std::array<double, 4> mean{}, first{};  // over t >= 3/4 t_final
    double D2 = 0.0;
    int n = 0;
    for (const auto& r : hist)
      if (r[0] >= 0.75 * hist.back()[0]) {
        if (n++ == 0) first = r;
        for (int k = 1; k < 4; ++k) mean[k] += r[k];
        D2 += r[1] * r[1];
      }
    const double D = mean[1] / n, D_sd = std::sqrt(std::max(D2 / n - D * D, 0.0));
    const double theta = mean[2] / n * 180 / M_PI, w = mean[3] / n / G;
    const double drift = hist.back()[1] - first[1], area_err = summary["area_relative_error"];
    std::printf("%6g %6g %8.4f %8.4f %9.1e %9.2f %9.4f %10.2e %7.1f\n", Ca, T0, D, D_sd, drift, theta, w, area_err,
                summary["wall_seconds"].get<double>());
    table << Ca << "," << T0 << "," << D << "," << D_sd << "," << drift << "," << theta << "," << w << "," << area_err
          << "," << summary["steps"] << "," << summary["wall_seconds"] << "\n";
  }
  table.close();
  std::filesystem::rename(out + "/table.csv.part", out + "/table.csv");
  std::printf("table: %s/table.csv, runs: %s/ca_*/\n", out.c_str(), out.c_str());
}
