#include "app/check.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "io/scene_checks.hpp"
#include "membrane/geometry.hpp"

namespace sphib::app {

namespace {

std::string num(double v, int digits = 3) {
  std::ostringstream s;
  s << std::setprecision(digits) << v;
  return s.str();
}

std::string bytes(double b) {
  const char* unit[] = {"B", "kB", "MB", "GB", "TB"};
  int k = 0;
  while (b >= 1000 && k < 4) { b /= 1000; ++k; }
  return num(b) + " " + unit[k];
}

double figure(const FluidSolver& f, const std::string& name, double def) {
  for (const auto& [k, v] : f.figures())
    if (k == name) return v;
  return def;
}

}  // namespace

int check_scene(const Scene& scene, std::ostream& out) {
  Simulation sim(scene.sim);  // builds everything: refuses what cannot run
  const FluidSolver& f = sim.fluid();
  const FluidParams& fp = f.params();
  const int N = f.size();
  const double dx = f.lattice().dx, dy = f.lattice().dy;
  int warnings = 0;

  out << (scene.path.empty() ? scene.title : scene.path) << ": ok\n";
  for (const auto& line : f.describe()) out << "  " << line << "\n";
  const double images = figure(f, "images", NAN), neighbours = figure(f, "neighbours_per_particle", NAN);
  out << "  particles " << N << " (" << fp.nx << " x " << fp.ny << ", dx = " << num(dx) << ", dy = " << num(dy)
      << "), images " << (std::isnan(images) ? std::string("(none: ") + fp.method + ")" : num(images, 10))
      << ", neighbours per particle " << num(neighbours) << ", h = " << num(f.h()) << "\n";

  // ---- Membranes: marker spacing against the lattice
  for (size_t k = 0; k < sim.membranes().size(); ++k) {
    const auto& m = sim.membranes()[k];
    const int nb = m.m.nb();
    double current = 0;  // mean chord between neighbouring markers
    for (int i = 0; i < nb; ++i) current += (m.m.X.row((i + 1) % nb) - m.m.X.row(i)).norm();
    current /= nb;
    out << "  membrane " << k << ": " << nb << " markers, T0 = " << m.m.T0 << ", h* = " << num(m.h_star)
        << (m.fixed ? ", fixed" : "") << "; markers per grid spacing: dx / rest spacing = " << num(dx / m.m.ds())
        << ", dx / current spacing = " << num(dx / current) << "\n";
  }

  // ---- Memory estimate (EPSPH: what the fixed-particle method keeps for the whole run)
  if (const auto kept = f.footprint()) {
    const double b_op = 12.0 * kept->operator_nonzeros, b_fac = 12.0 * kept->factor_nonzeros;
    const double b_pairs = 28.0 * kept->pairs + 4.0 * (N + 1);
    const double b_fields = 8.0 * (34.0 * N + 8.0 * (std::isnan(images) ? 0.0 : images));
    out << "  memory estimate: " << bytes(b_op + b_fac + b_pairs + b_fields) << " = operators " << bytes(b_op)
        << " (" << kept->operator_nonzeros << " non-zeros) + factors " << bytes(b_fac) << " (" << kept->factor_nonzeros
        << " non-zeros) + pair list " << bytes(b_pairs) << " (" << kept->pairs << " pairs) + fields " << bytes(b_fields)
        << "\n    (counts: every non-zero of the operator matrices, of the Cholesky/LU factors and of the kept"
           " Poisson matrix at 12 bytes (8-byte value + 4-byte index); each pair at 28 bytes (index, x_ij, r);"
           " 34 doubles per particle (u, u*, AB2 and Crank-Nicolson work arrays, phi, p, forces, positions) and"
           " 8 per image. Not counted: solver workspaces, HDF5 buffers, the membranes.)\n";
  } else {
    out << "  memory estimate: not available for method " << fp.method
        << " (its operators are rebuilt every step)\n";
  }

  warnings += time_step_warnings(scene, sim, out);
  return warnings;
}

int time_step_warnings(const Scene& scene, const Simulation& sim, std::ostream& out) {
  const FluidSolver& f = sim.fluid();
  const FluidParams& fp = f.params();
  const Domain& d = fp.domain;
  const int N = f.size();
  const double dx = f.lattice().dx, dy = f.lattice().dy, h_min = std::min(dx, dy), dt = fp.dt;
  int warnings = 0;
  if (const std::string w = kernel_warning(fp); !w.empty()) {
    ++warnings;
    out << "    WARNING: " << w << "\n";
  }
  // Markers farther apart than a lattice spacing let fluid through between them (documented
  // limit: markers per grid spacing >= 1, i.e. the largest marker spacing <= min(dx, dy)).
  for (size_t k = 0; k < sim.membranes().size(); ++k) {
    const auto& m = sim.membranes()[k];
    const int nb = m.m.nb();
    double widest = 0;
    for (int i = 0; i < nb; ++i) widest = std::max(widest, (m.m.X.row((i + 1) % nb) - m.m.X.row(i)).norm());
    if (widest > h_min) {
      ++warnings;
      out << "    WARNING: membrane " << k << ": markers up to " << num(widest) << " apart, more than a lattice "
          << "spacing (" << num(h_min) << "): raise membrane.nb to at least " << static_cast<int>(std::ceil(nb * widest / h_min)) << "\n";
    }
  }
  // ---- Velocity scale U for the convective CFL limit dt < h_min / U
  struct Scale { double U; std::string from; };
  std::vector<Scale> scales;
  double U_wall = 0;
  for (int s = 0; s < 4; ++s)
    if (d.is_wall(static_cast<Side>(s))) U_wall = std::max(U_wall, d.wall_velocity[s].norm());
  scales.push_back({U_wall, "wall velocity"});
  scales.push_back({f.u().rowwise().norm().maxCoeff(), "initial velocity"});
  double F = scene.sim.body_force.norm();
  if (scene.sim.body_force_field) {
    F = 0;
    for (int i = 0; i < N; ++i) F = std::max(F, scene.sim.body_force_field(f.x()(i, 0), f.x()(i, 1), 0.0).norm());
  }
  if (F > 0) {
    // Poiseuille centre-line F L^2/(8 mu) across the narrowest walled extent, reached after the
    // viscous time; before that (or without walls) free acceleration F t_end / rho.
    double U_F = F * scene.t_end / fp.rho;
    const double L = std::min(d.periodic_y ? INFINITY : d.Ly(), d.periodic_x ? INFINITY : d.Lx());
    if (std::isfinite(L)) U_F = std::min(U_F, F * L * L / (8.0 * fp.mu));
    scales.push_back({U_F, "body force: min(F L^2/(8 mu), F t_end/rho)"});
  }
  for (size_t k = 0; k < sim.membranes().size(); ++k) {
    const auto& m = sim.membranes()[k];
    if (m.fixed || m.m.T0 <= 0) continue;
    // The elastic energy E released into the fluid: the Stokes speed T0 eps_max/(4 mu) of the
    // largest strain (a line force density f at wavenumber k moves a line at f/(4 mu k), here
    // f ~ T0 eps k), or, if smaller, the inertial speed sqrt(2 E/(rho A)) of the enclosed area A.
    HookeanForce hooke(m.m.nb(), m.m.L0);
    Mat2 fk;
    Vec T;
    hooke.compute(m.m.X, m.m.T0, fk, T);
    MembraneDiagnostics diag(m.m.nb(), m.m.L0);
    const MembraneShape s = diag.measure(m.m.X, m.m.T0);
    const double eps = T.cwiseAbs().maxCoeff() / m.m.T0;
    const double U_m = std::min(m.m.T0 * eps / (4.0 * fp.mu), std::sqrt(2.0 * s.energy / (fp.rho * s.area)));
    scales.push_back({U_m, "membrane " + std::to_string(k) + ": min(T0 eps_max/(4 mu), sqrt(2 E_el/(rho A)))"});
  }
  const auto top = *std::max_element(scales.begin(), scales.end(), [](auto& a, auto& b) { return a.U < b.U; });
  out << "  time step dt = " << dt << ":\n";
  if (top.U > 0) {
    const double limit = h_min / top.U;
    const bool over = dt > limit;
    warnings += over;
    out << "    " << (over ? "WARNING: " : "") << "convective CFL: dt < min(dx, dy) / U = " << num(limit)
        << " with U = " << num(top.U) << " (" << top.from << ")" << (over ? ": dt exceeds it" : ": ok") << "\n";
  } else {
    out << "    convective CFL: no velocity scale (fluid at rest, no forcing)\n";
  }
  // Explicit elastic limit. The membrane force is explicit in X^n (Eq. 50 at t_n), so the stiffest
  // membrane mode the spreading kernel passes (wavenumber k ~ 1/h*) limits dt, as in every explicit
  // IB method. Two scalings: inertial, T0 k^3 dt^2 / rho below a constant (a stretching wave with
  // the fluid's added mass rho/k; the T0 dt^2/h scaling of the explicit-IB stability analysis of
  // Hua & Peskin 2021, arXiv:2111.15065), and viscous, dt below a constant times mu/(T0 k) (the
  // Stokes relaxation rate of that mode). The constants are NOT from a source: they were measured
  // with this code, a factor-of-two guide, not a bound (README: "sphib check", "Stability at the
  // extremes"). The inertial constant depends on the pair: the paper's (approximate projection,
  // Eq. 63 markers) leaks area and with it elastic energy, which lets it run with dt about 3 times
  // larger (bench/stability_map, fitted in h* form: 0.32 conservative, about 1 paper's).
  const bool paper_pair = sim.interpolation() == MarkerInterpolation::Sph &&
                          (fp.projection == Projection::Approximate ||
                           (fp.projection == Projection::Auto && sim.fluid().particles_move()));
  const double c_i = paper_pair ? 1.0 : 0.3;
  for (size_t k = 0; k < sim.membranes().size(); ++k) {
    const auto& m = sim.membranes()[k];
    if (m.fixed || m.m.T0 <= 0) continue;
    const double hs = m.h_star;
    const double inertial = c_i * std::sqrt(fp.rho * hs * hs * hs / m.m.T0), viscous = 10.0 * fp.mu * hs / m.m.T0;
    const double limit = std::max(inertial, viscous);
    const bool over = dt > limit;
    warnings += over;
    out << "    " << (over ? "WARNING: " : "") << "membrane " << k
        << " elastic limit (measured estimate, explicit membrane force): dt < max(" << c_i
        << " sqrt(rho h*^3/T0), 10 mu h*/T0) = " << num(limit) << (over ? ": dt exceeds it" : ": ok") << "\n";
  }
  return warnings;
}

}  // namespace sphib::app
