// Membranes in a flow of your own: a scene built in C++ and run by the library's loop and output.
// Sliding walls y = +-1 (periodic in x), a body force F(x, y, t), an initial vortex, a membrane
// from a shape function r(theta), one from a point list, and an observer of our choice.
#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>

#include "io/run.hpp"
#include "membrane/polygon.hpp"
#include "membrane/shapes.hpp"

int main(int argc, char** argv) {
  using namespace sphib;
  using V2 = Eigen::Vector2d;
  Scene s;
  s.title = "two membranes between sliding walls, forced by F(x, y, t)";
  RunOptions run;
  run.out_dir = "out/embed_example";
  run.log = &std::cerr;
  CLI::App app{s.title};
  app.add_option("--steps", s.max_steps, "stop after this many steps");
  app.add_option("--out", run.out_dir, "output directory");
  CLI11_PARSE(app, argc, argv);

  FluidParams& f = s.sim.fluid;
  f.domain = {-1.0, 1.0, -1.0, 1.0, /*periodic_x=*/true, /*periodic_y=*/false};
  f.domain.wall_velocity[Top] = V2(0.5, 0.0), f.domain.wall_velocity[Bottom] = V2(-0.5, 0.0);
  f.nx = f.ny = 40, f.mu = 0.2, f.dt = 2e-3;  // dx = 0.05, h = 1.2 dx
  s.sim.body_force_field = [](double, double y, double t) { return V2(std::sin(M_PI * y) * std::cos(2 * t), 0); };
  s.sim.initial_velocity = [](double x, double y) { return V2(0, 0.2 * std::sin(M_PI * x) * std::cos(M_PI * y / 2)); };
  const double T0 = 2.0, h_star = 1.4 * 0.06;
  s.sim.membranes.push_back({make_membrane(from_polar([](double th) { return 0.25 * (1 + 0.15 * std::cos(3 * th)); }, 64, -0.5, 0), 0.25, T0), h_star});
  Mat2 bean(6, 2);
  bean << 0.25, -0.2, 0.75, -0.25, 0.8, 0.1, 0.6, 0.3, 0.45, 0.05, 0.3, 0.25;
  s.sim.membranes.push_back({make_membrane(from_points(bean, 64), /*r0=*/0.35, T0), h_star});
  s.observers.push_back({"m1_deformation", [](const Simulation& sim) { return ellipse_fit(sim.membranes()[1].m.X).deformation(); }});
  s.t_end = 2.0, s.output_interval = 0.25;
  run_scene(s, run);
}
