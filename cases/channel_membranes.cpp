// Two capsules carried by a pressure-driven channel flow: walls y = +-H/2 at rest, periodic in x,
// a uniform body force F (the mean pressure gradient) that drives the Poiseuille flow
// u(y) = U (1 - 4 y^2/H^2), U = F H^2/(8 mu), which is also the initial velocity. Two circular
// Hookean membranes at rest length, one on the centre line, one off it, are carried along.
// Observed, per membrane k: velocity of its markers' mean (mk_u, mk_v), the ratio of mk_u to the
// undisturbed flow at its centroid (mk_lag), Taylor deformation mk_D and inclination
// mk_theta_deg (ellipse_fit); run_scene adds centroids mk_cx, mk_cy, area errors and more.
//
// Dimensionless: H = 1, L = 4, U = 1, rho = 1, mu = 1 (Re = rho U H / mu = 1); radius a = 0.15
// (2a/H = 0.3); Ca = mu (U/H) a / T0 = 0.1; capsule 0 at (-1, 0), capsule 1 at (0.5, 0.2).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "io/run.hpp"
#include "membrane/polygon.hpp"
#include "membrane/shapes.hpp"

using namespace sphib;

int main(int argc, char** argv) {
  Scene s;
  s.title = "two capsules in pressure-driven channel flow";
  RunOptions run;
  run.out_dir = "out/channel_membranes";
  run.log = &std::cerr;
  double Ca = 0.1, cfl = 0.025;
  int nx = 128;
  CLI::App app{s.title};
  app.add_option("--steps", s.max_steps, "stop after this many steps (smoke test)");
  app.add_option("--out", run.out_dir, "output directory");
  app.add_option("--ca", Ca, "capillary number mu (U/H) a / T0");
  app.add_option("--nx", nx, "particles along x (ny = nx/4)");
  app.add_option("--cfl", cfl, "time step dt = cfl dx / U");
  double per_dx = 2.0;
  app.add_option("--markers-per-dx", per_dx, "markers per lattice spacing along the membranes");
  bool paper = false;
  app.add_flag("--paper-pair", paper, "the paper's approximate projection and SPH interpolation (Eq. 63)");
  CLI11_PARSE(app, argc, argv);

  const double H = 1.0, L = 4.0, U = 1.0, rho = 1.0, mu = 1.0, a = 0.15;
  const double F = 8.0 * mu * U / (H * H), T0 = mu * (U / H) * a / Ca;
  FluidParams& f = s.sim.fluid;
  f.domain = {-L / 2, L / 2, -H / 2, H / 2, /*periodic_x=*/true, /*periodic_y=*/false};
  f.nx = nx, f.ny = nx / 4, f.rho = rho, f.mu = mu;
  const double dx = L / nx, h = f.h_over_dx * dx;
  f.dt = cfl * dx / U;
  if (paper) {
    f.projection = Projection::Approximate;
    s.sim.interpolation = MarkerInterpolation::Sph;
  }
  s.sim.body_force = {F, 0.0};
  auto u_poiseuille = [=](double y) { return U * (1.0 - 4.0 * y * y / (H * H)); };
  s.sim.initial_velocity = [=](double, double y) { return Eigen::Vector2d(u_poiseuille(y), 0.0); };
  const int nb = static_cast<int>(std::lround(2 * M_PI * a * per_dx / dx));
  for (const Eigen::Vector2d& c : {Eigen::Vector2d(-1.0, 0.0), Eigen::Vector2d(0.5, 0.2)})
    s.sim.membranes.push_back({make_membrane(circle(nb, c.x(), c.y(), a), a, T0), /*h_star=*/1.4 * h});
  s.t_end = 4.0 * H / U;
  s.output_interval = 0.5;

  for (int k = 0; k < 2; ++k) {
    const std::string m = "m" + std::to_string(k) + "_";
    auto vel = [k](const Simulation& sim) -> Eigen::Vector2d { return sim.membranes()[k].U.colwise().mean(); };
    auto shape = [k](const Simulation& sim) { return ellipse_fit(sim.membranes()[k].m.X); };
    s.observers.push_back({m + "u", [=](const Simulation& sim) { return vel(sim).x(); }});
    s.observers.push_back({m + "v", [=](const Simulation& sim) { return vel(sim).y(); }});
    s.observers.push_back({m + "lag", [=](const Simulation& sim) { return vel(sim).x() / u_poiseuille(shape(sim).centroid.y()); }});
    s.observers.push_back({m + "theta_deg", [=](const Simulation& sim) { return shape(sim).theta * 180 / M_PI; }});
  }
  const nlohmann::json summary = run_scene(s, run);

  // A table over time from the run's diagnostics.csv.
  std::ifstream in(run.out_dir + "/diagnostics.csv");
  std::string line, cell;
  std::vector<std::string> cols;
  std::vector<std::vector<double>> rows;
  for (bool header = true; std::getline(in, line); header = false) {
    std::stringstream ss(line);
    if (!header) rows.emplace_back();
    while (std::getline(ss, cell, ',')) header ? cols.push_back(cell) : rows.back().push_back(std::stod(cell));
  }
  const std::vector<std::string> show{"t", "m0_u", "m0_lag", "m0_D", "m1_u", "m1_v", "m1_lag", "m1_cy", "m1_D", "m1_theta_deg"};
  for (const auto& c : show) std::printf("%13s", c.c_str());
  std::printf("\n");
  auto print = [&](const std::vector<double>& r) {
    for (const auto& c : show) std::printf("%13.4f", r[std::find(cols.begin(), cols.end(), c) - cols.begin()]);
    std::printf("\n");
  };
  for (size_t i = 0; i + 1 < rows.size(); i += std::max<size_t>(1, rows.size() / 8)) print(rows[i]);
  print(rows.back());
  std::printf("area error of membrane 0 at the end: %.2e; %ld steps, %.1f s\n",
              summary["area_relative_error"].get<double>(), summary["steps"].get<long>(),
              summary["wall_seconds"].get<double>());
}
