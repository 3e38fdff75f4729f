#pragma once
// The scene of a capsule suspension in a sheared box, shared by cases/suspension_shear.cpp (the run
// and its observations) and bench/suspension.cpp (its step against the same box without capsules):
// `count` circular Hookean capsules at rest (radius a, area fraction phi of the unit box), placed at
// random without overlap (seeded: membrane/packing.hpp) between walls y = 0, 1 sliding at -+U/2
// (shear rate G = U), periodic in x, the fluid starting in plain Couette flow u = G (y - 1/2).
// Dimensionless: L = H = 1, U = G = 1, rho = 1, mu = 1 (particle Reynolds number rho G a^2/mu ~ 1e-3),
// T0 = mu G a / Ca, nx x nx particles, dt = cfl dx / U, h* = 1.4 h (h_star).
#include <cmath>
#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

#include "io/scene.hpp"
#include "membrane/membrane.hpp"
#include "membrane/packing.hpp"
#include "membrane/shapes.hpp"

namespace sphib {

struct SuspensionParams {
  int count = 100, nb = 64, nx = 256;
  double phi = 0.3, Ca = 0.1, cfl = 0.5;
  double h_star = 1.4;  // the spreading's h* in units of the fluid's h
  double Eb = 0.0;  // bending modulus in units of T0 a^2 (0: none; > 0: semi-implicit, coupling/stiff_force.hpp)
  std::uint64_t seed = 1;
  double contact_strength = 0.0;  // De in units of T0 (0: no contact force)
  double contact_range = 2.0;     // r0 in lattice spacings; also the least gap between capsules at the start
  std::string interpolation = "bspline";  // marker velocity: bspline, divergence_free or spreading_kernel
  // The marker update (solver.marker_eps, solver.marker_linear_step, solver.marker_newton): Newton
  // steps accepted up to 1e-4 lattice spacings, one interpolation per step (the library's fixed-point
  // step with linear_step 1e-6 takes a second one every step here: docs/suspensions.md)
  double marker_eps = 1e-12, linear_step = 1e-4;
  bool newton = true;
  bool keep_area = false;  // solver.marker_keep_area: the marker update's area constraint
  bool empty = false;             // the same box without capsules
  double radius() const { return std::sqrt(phi / (count * M_PI)); }  // the capsules fill phi of the unit box
  double T0() const { return 1.0 * 1.0 * radius() / Ca; }          // mu G a / Ca
};

inline Scene suspension_scene(const SuspensionParams& p) {
  const double U = 1.0, G = U, a = p.radius();
  Scene s;
  s.title = "capsule suspension in shear flow";
  FluidParams& f = s.sim.fluid;
  f.domain = {0.0, 1.0, 0.0, 1.0, /*periodic_x=*/true, /*periodic_y=*/false};
  f.domain.wall_velocity[Top] = {U / 2, 0.0};
  f.domain.wall_velocity[Bottom] = {-U / 2, 0.0};
  f.nx = f.ny = p.nx, f.rho = 1.0, f.mu = 1.0;
  const double dx = 1.0 / p.nx, h = f.h_over_dx * dx, h_star = p.h_star * h;
  f.dt = p.cfl * dx / U;
  s.sim.initial_velocity = [G](double, double y) { return Eigen::Vector2d(G * (y - 0.5), 0.0); };  // Couette
  s.sim.interpolation = p.interpolation == "bspline"            ? MarkerInterpolation::BSpline
                         : p.interpolation == "spreading_kernel" ? MarkerInterpolation::SpreadingKernel
                                                                 : MarkerInterpolation::DivergenceFree;
  s.sim.markers.eps = p.marker_eps;
  s.sim.markers.linear_step = p.linear_step;
  s.sim.markers.newton = p.newton;
  s.sim.markers.keep_area = p.keep_area;
  s.loads = true;  // shear_<wall> and mu_eff (observe/loads.cpp)
  s.fields = {"u", "v"};
  if (p.empty) return s;
  DiskPacking pack;
  pack.count = p.count, pack.radius = a, pack.seed = p.seed;
  pack.gap = p.contact_range * dx;
  pack.wall_gap = 2.0 * std::max(h, h_star);  // the start keeps max(2h, 2h*) off the walls
  const Eigen::MatrixX2d c = random_disks(pack);
  Material mat = hookean(p.T0());
  mat.Eb = p.Eb * p.T0() * a * a;
  for (int k = 0; k < p.count; ++k)
    s.sim.membranes.push_back({make_membrane(circle(p.nb, c(k, 0), c(k, 1), a), circle_reference(a), mat), h_star,
                               /*fixed=*/false, /*semi_implicit=*/p.Eb > 0});
  if (p.contact_strength > 0) s.sim.contact = {p.contact_strength * p.T0(), p.contact_range * dx, 0.0, true};
  return s;
}

// The command-line options of the suspension that its case and its benchmark share.
inline void add_suspension_options(CLI::App& app, SuspensionParams& p) {
  app.add_option("--count", p.count, "capsules");
  app.add_option("--nb", p.nb, "markers per capsule");
  app.add_option("--nx", p.nx, "particles along x and y");
  app.add_option("--contact-strength", p.contact_strength, "De of the contact force in units of T0 (0: off)");
  app.add_option("--marker-eps", p.marker_eps, "solver.marker_eps");
  app.add_option("--eb", p.Eb, "bending modulus in units of T0 a^2 (semi-implicit)");
  app.add_option("--linear-step", p.linear_step, "solver.marker_linear_step");
  app.add_option("--h-star", p.h_star, "the spreading's h* in units of the fluid's h");
  app.add_option("--newton", p.newton, "solver.marker_newton (true/false)");
  app.add_flag("--keep-area", p.keep_area, "the marker update's area constraint (solver.marker_keep_area)");
  app.add_option("--interpolation", p.interpolation,
                 "marker velocity: bspline, divergence_free (SPH kernel of h) or spreading_kernel (SPH kernel of h*)")
      ->check(CLI::IsMember({"bspline", "divergence_free", "spreading_kernel"}));
}

}  // namespace sphib
