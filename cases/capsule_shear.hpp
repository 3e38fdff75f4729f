#pragma once
// The capsule in simple shear of cases/capsule_shear.cpp (and its unit test): a circular membrane at
// its rest length (radius r0) between walls y = +-H/2 sliding at -+U, periodic in x (length 2H).
#include <cmath>
#include <string>

#include "io/scene.hpp"
#include "membrane/shapes.hpp"

namespace sphib {

struct CapsuleParams {
  double Ca = 0.05;        // mu G r0 / Es
  std::string law = "hookean";
  double eb_hat = 0.0;     // Eb / (Es r0^2): Ca_b = mu G r0^3 / Eb = Ca / eb_hat
  double H = 2.0, r0 = 0.4, rho = 1.0, mu = 1.0, G = 1.0;
  int nx = 64, nb = 0;     // nb = 0: two markers per dx
  double h_star = 0.0;     // the spreading's radius h* (membrane.h_star; 0: 1.4 h, h = 1.2 dx)
  double cfl = 0.0125;     // dt = cfl dx / U, U = G H / 2 the wall speed
  double t_end = 16.0;     // in units of 1/G
  double lambda = 1.0;      // viscosity ratio mu_in / mu_out (membrane.viscosity_ratio; mu = mu_out)
  double viscosity_rtol = FluidParams{}.viscosity_rtol;  // solver.viscosity_rtol: the contrast's Crank-Nicolson CG
  bool paper_pair = false, explicit_force = false, sheared = false, stiff_residual = false;
  bool keep_area = false;  // solver.marker_keep_area: the marker update's area constraint
  MarkerInterpolation interpolation = MarkerInterpolation::Auto;  // (paper_pair: Sph)
  double Es() const { return mu * G * r0 / Ca; }
  double Eb() const { return eb_hat * Es() * r0 * r0; }
  /// The small-deformation theory with bending (docs/membrane_validation.md): Ca_b, D, theta (degrees).
  double Ca_b() const { return eb_hat > 0 ? mu * G * r0 * r0 * r0 / Eb() : NAN; }
  double D_lin() const { return Ca_b() / std::sqrt(9 + 4 * Ca_b() * Ca_b()); }
  double theta_lin_deg() const { return 45 - std::atan(2 * Ca_b() / 3) * 90 / M_PI; }
};

inline Scene capsule_scene(const CapsuleParams& p) {
  Scene s;
  const double U = p.G * p.H / 2, L = 2 * p.H;
  FluidParams& f = s.sim.fluid;
  f.domain = {-L / 2, L / 2, -p.H / 2, p.H / 2, /*periodic_x=*/true, /*periodic_y=*/false};
  f.domain.wall_velocity[Top] = {U, 0.0};
  f.domain.wall_velocity[Bottom] = {-U, 0.0};
  f.nx = p.nx, f.ny = p.nx / 2, f.rho = p.rho, f.mu = p.mu;
  f.viscosity_rtol = p.viscosity_rtol;
  s.sim.interpolation = p.interpolation;
  if (p.paper_pair) {
    f.projection = Projection::Approximate;
    s.sim.interpolation = MarkerInterpolation::Sph;
  }
  const double dx = L / p.nx, h_star = p.h_star > 0 ? p.h_star : 1.4 * f.h_over_dx * dx;
  f.dt = p.cfl * dx / U;
  Material mat;
  mat.law = p.law;
  mat.Es = p.Es();
  mat.Eb = p.Eb();
  const int nb = p.nb > 0 ? p.nb : static_cast<int>(std::lround(2 * M_PI * p.r0 / (0.5 * dx)));  // two per dx
  MembraneSetup m{make_membrane(circle(nb, 0.0, 0.0, /*radius=*/p.r0), circle_reference(p.r0), mat), h_star};
  m.semi_implicit = !p.explicit_force && (mat.Eb > 0 || p.law != "hookean");  // as the scene's default
  m.stiff_residual = m.semi_implicit && p.stiff_residual;
  m.viscosity_ratio = p.lambda;
  s.sim.membranes.push_back(m);
  s.sim.markers.keep_area = p.keep_area;
  if (p.sheared) {
    const double G = p.G;
    s.sim.initial_velocity = [G](double, double y) { return Eigen::Vector2d(G * y, 0.0); };
  }
  s.t_end = p.t_end / p.G;
  return s;
}

}  // namespace sphib
