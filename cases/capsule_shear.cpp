// A capsule in simple shear flow: a circular membrane at its rest length (radius = r0) between walls
// y = +-H/2 sliding at -+U, periodic in x (length L = 2H; cases/capsule_shear.hpp). Shear rate
// G = 2U/H; capillary number Ca = mu G r0 / Es (Es: the law's modulus, the Hookean T0); bending
// modulus Eb = eb_hat Es r0^2, i.e. the bending capillary number Ca_b = mu G r0^3 / Eb = Ca / eb_hat.
// The capsule becomes an inclined ellipse round which its membrane rotates. Observed: Taylor
// deformation D = (L - B)/(L + B) and inclination theta of the ellipse with the same second moments of
// area (ellipse_fit); tank-treading frequency omega (mean angular velocity of the markers about the
// centroid, < 0 clockwise). The table: means over the last quarter of each run, with the standard
// deviation and drift of D over it. With bending, D_lin is the small-deformation theory of a 2-D
// capsule in unbounded Stokes flow (docs/membrane_validation.md): D = Ca_b / sqrt(9 + 4 Ca_b^2),
// theta = 45 - atan(2 Ca_b/3)/2 degrees, whatever the tension law. Without bending a ring at rest
// length has no linear resistance to the shape change (D does not scale with Ca): no theory column.
// Defaults: H = 2, U = 1 (G = 1), r0 = 0.4, rho = 1, mu = 1 (Re = rho G r0^2/mu = 0.16), Hookean
// without bending, 64 x 32 particles, two markers per dx, t_end = 16/G, dt = 0.0125 dx/U, fluid at
// rest at t = 0 (--sheared: the developed shear), one viscosity (--lambda: mu_in / mu_out).
// Writes DIR/ca_<Ca>/ (each run) and DIR/table.csv.
#include <CLI/CLI.hpp>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cases/capsule_shear.hpp"
#include "io/run.hpp"
#include "membrane/polygon.hpp"

using namespace sphib;

int main(int argc, char** argv) {
  std::vector<double> cas{0.05, 0.1, 0.2};
  std::string out = "out/capsule_shear";
  CapsuleParams p;
  long steps = 0;
  std::string interp = "auto";
  CLI::App app{"capsule in simple shear: D(Ca), theta(Ca), tank-treading frequency"};
  app.add_option("--ca", cas, "capillary numbers mu G r0 / Es (comma-separated)")->delimiter(',');
  app.add_option("--law", p.law, "tension law (membrane.law): hookean, neo_hookean, skalak, inextensible");
  app.add_option("--eb-hat", p.eb_hat, "bending modulus Eb / (Es r0^2) (0: no bending)")->check(CLI::NonNegativeNumber);
  app.add_option("--out", out, "output directory");
  app.add_option("--steps", steps, "stop each run after this many steps (smoke test)");
  app.add_option("--nx", p.nx, "particles along x (ny = nx/2)");
  app.add_option("--nb", p.nb, "markers (0: two per dx)");
  app.add_option("--h-star", p.h_star, "the spreading kernel's radius h* (membrane.h_star; 0: 1.4 h = 1.68 dx)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--height", p.H, "channel height H (domain H x 2H, r0 = 0.4, confinement 2 r0/H)");
  app.add_option("--t-end", p.t_end, "end time in units of 1/G");
  app.add_option("--rho", p.rho, "fluid density (Re = rho G r0^2 / mu; 1: Re = 0.16)")->check(CLI::PositiveNumber);
  app.add_option("--cfl", p.cfl, "time step dt = cfl dx / U, U = G H/2 the wall speed");
  app.add_option("--lambda", p.lambda, "viscosity ratio mu_in / mu_out of the capsule's fluid (membrane.viscosity_ratio)")
      ->check(CLI::Range(0.01, 100.0));
  app.add_flag("--paper-pair", p.paper_pair, "the paper's approximate projection and SPH interpolation (Eq. 63)");
  app.add_flag("--explicit", p.explicit_force, "explicit membrane force (no stiff-force filter)");
  app.add_option("--viscosity-rtol", p.viscosity_rtol, "the viscosity contrast's CG tolerance (solver.viscosity_rtol)")
      ->check(CLI::Range(1e-16, 1e-4));
  app.add_flag("--keep-area", p.keep_area, "the marker update's area constraint (solver.marker_keep_area)");
  app.add_flag("--stiff-residual", p.stiff_residual, "the stiff-force filter with its model's residual (membrane.stiff_residual)");
  app.add_option("--interpolation", interp, "marker velocity (coupling.interpolation): auto (bspline with bending), "
                 "bspline, divergence_free, sph, spreading_kernel (the curl with the kernel of radius h*)")
      ->check(CLI::IsMember({"auto", "bspline", "divergence_free", "sph", "spreading_kernel"}));
  app.add_flag("--sheared", p.sheared, "start from the developed shear u = (G y, 0) (default: at rest; the flow "
               "develops from the walls in ~H^2/(10 nu))");
  CLI11_PARSE(app, argc, argv);
  p.interpolation = interp == "bspline"           ? MarkerInterpolation::BSpline
                    : interp == "divergence_free" ? MarkerInterpolation::DivergenceFree
                    : interp == "sph"             ? MarkerInterpolation::Sph
                    : interp == "spreading_kernel" ? MarkerInterpolation::SpreadingKernel
                                                  : MarkerInterpolation::Auto;

  std::filesystem::create_directories(out);
  std::ofstream table(out + "/table.csv.part");
  table << "Ca,Es,Eb,Ca_b,D,D_sd,D_drift,theta_deg,omega_over_G,D_lin,theta_lin_deg,area_relative_error,steps,"
           "wall_seconds\n";
  std::printf("%7s %8s %8s %8s %8s %9s %8s %8s %8s %8s %10s %7s\n", "Ca", "Ca_b", "D", "D sd", "D/D_lin", "drift",
              "theta", "th_lin", "omega/G", "D_lin", "area_err", "s");
  for (double Ca : cas) {
    p.Ca = Ca;
    Scene s = capsule_scene(p);
    char name[64];
    if (p.lambda == 1.0) std::snprintf(name, sizeof name, "ca_%g", Ca);
    else std::snprintf(name, sizeof name, "ca_%g_lambda_%g", Ca, p.lambda);
    s.title = std::string("capsule in shear flow, ") + name;
    s.max_steps = steps;
    std::vector<std::array<double, 4>> hist;  // t, D, theta, omega at every diagnostics row
    s.observers = {
        {"D", [&](const Simulation& sim) {
           const auto& ms = sim.membranes()[0];
           const ShapeMoments e = ellipse_fit(ms.m.X);
           hist.push_back({sim.time(), e.deformation(), e.theta, mean_angular_velocity(ms.m.X, ms.U, e.centroid)});
           return e.deformation();
         }},
        {"theta_deg", [&](const Simulation&) { return hist.back()[2] * 180 / M_PI; }},
        {"omega_over_G", [&](const Simulation&) { return hist.back()[3] / p.G; }},
    };
    RunOptions run;
    run.out_dir = out + "/" + name;
    const nlohmann::json summary = run_scene(s, run);

    std::array<double, 4> mean{}, first{};  // over t >= 3/4 t_final
    double D2 = 0.0;
    int k = 0;
    for (const auto& r : hist)
      if (r[0] >= 0.75 * hist.back()[0]) {
        if (k++ == 0) first = r;
        for (int c = 1; c < 4; ++c) mean[c] += r[c];
        D2 += r[1] * r[1];
      }
    const double D = mean[1] / k, D_sd = std::sqrt(std::max(D2 / k - D * D, 0.0));
    const double theta = mean[2] / k * 180 / M_PI, w = mean[3] / k / p.G;
    const double drift = hist.back()[1] - first[1], area_err = summary["area_relative_error"];
    std::printf("%7g %8.4g %8.5f %8.1e %8.4f %9.1e %8.3f %8.3f %8.4f %8.5f %10.2e %7.1f\n", Ca, p.Ca_b(), D, D_sd,
                D / p.D_lin(), drift, theta, p.theta_lin_deg(), w, p.D_lin(), area_err,
                summary["wall_seconds"].get<double>());
    std::fflush(stdout);  // (a later run that blows up must not take this line with it)
    table << Ca << "," << p.Es() << "," << p.Eb() << "," << p.Ca_b() << "," << D << "," << D_sd << "," << drift << ","
          << theta << "," << w << "," << p.D_lin() << "," << p.theta_lin_deg() << "," << area_err << ","
          << summary["steps"] << "," << summary["wall_seconds"] << "\n";
  }
  table.close();
  std::filesystem::rename(out + "/table.csv.part", out + "/table.csv");
  std::printf("table: %s/table.csv, runs: %s/ca_*/\n", out.c_str(), out.c_str());
}
