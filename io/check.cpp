#include "io/check.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "io/footprint.hpp"
#include "io/scene_checks.hpp"
#include "fluid/common/free_surface.hpp"
#include "fluid/moving/wcsph.hpp"
#include "membrane/force.hpp"
#include "membrane/geometry.hpp"

namespace sphib {

namespace {

std::string num(double v, int digits = 3) {
  std::ostringstream s;
  s << std::setprecision(digits) << v;
  return s.str();
}

std::string bytes(double b) { return bytes_text(b); }

double figure(const FluidSolver& f, const std::string& name, double def) {
  for (const auto& [k, v] : f.profiler().report().figures)
    if (k == name) return v;
  return def;
}

}  // namespace

namespace {

// Above this estimated peak `sphib check` does not build the simulation (at 1024^2 that took 56 s
// and 3.8 GB): it reports from the scene, the lattice and the membranes alone.
constexpr double kBuildBytes = 1e9;

// What the report and the warnings read: the lattice, the flow at t = 0, the membranes and the
// marker interpolation, from a built simulation or from the scene alone.
struct Picture {
  const FluidParams& fp;
  double dx, dy;
  const Mat2& x;  // particle positions at t = 0
  const Mat2& u;  // velocity at t = 0
  const std::vector<MembraneState>& membranes;
  bool paper_pair;  // the paper's projection and interpolation (its elastic limit is looser)
};

void report_membranes(const Picture& p, std::ostream& out) {
  for (size_t k = 0; k < p.membranes.size(); ++k) {
    const auto& m = p.membranes[k];
    const int nb = m.m.nb();
    double current = 0;  // mean chord between neighbouring markers
    for (int i = 0; i < nb; ++i) current += (m.m.X.row((i + 1) % nb) - m.m.X.row(i)).norm();
    current /= nb;
    out << "  membrane " << k << ": " << nb << " markers, " << describe(m.m.mat) << ", h* = " << num(m.h_star)
        << (m.fixed ? ", fixed" : "") << "; markers per grid spacing: dx / rest spacing = " << num(p.dx / m.m.ds())
        << ", dx / current spacing = " << num(p.dx / current) << "\n";
  }
}

// The estimate of io/footprint against the machine; a WARNING (counted) when sphib run would refuse it.
int report_memory(const Scene& scene, const MemoryEstimate& e, std::ostream& out) {
  const MachineMemory m = machine_memory();
  out << "  memory estimate: " << bytes(e.bytes) << " at the run's peak = " << bytes(e.base)
      << " (this process and the run's fixed overhead) + " << e.particles << " particles x ";
  if (e.per_particle > 0) out << "(" << num(e.per_particle) << " bytes + ";
  out << e.neighbours << " neighbours x " << num(e.per_neighbour) << " bytes" << (e.per_particle > 0 ? ")" : "") << " ("
      << e.path << ", measured: documentation, \"Memory\")";
  if (e.marker_count > 0)
    out << " + " << e.marker_count << " markers: " << bytes(e.markers) << " (measured: documentation, \"Data safety\", \"Memory\")";
  out << "; machine: "
      << bytes(m.bytes) << " (" << m.source << ")";
  if (scene.memory_limit_gb > 0) out << ", limits.memory_gb = " << scene.memory_limit_gb;
  out << "\n";
  const std::string why = memory_problem(scene, e, m);
  if (!why.empty()) out << "    WARNING: sphib run will refuse it: " << why << "\n";
  return why.empty() ? 0 : 1;
}

// The built simulation's own account: its factorisations, images, neighbours and kept non-zeros.
void report_built(const Simulation& sim, std::ostream& out) {
  const FluidSolver& f = sim.fluid();
  const FluidParams& fp = f.params();
  for (const auto& line : f.profiler().report().lines) out << "  " << line << "\n";
  const double images = figure(f, "images", NAN), neighbours = figure(f, "neighbours_per_particle", NAN);
  out << "  particles " << f.size() << " (" << fp.nx << " x " << fp.ny << ", dx = " << num(f.lattice().dx)
      << ", dy = " << num(f.lattice().dy) << "), images "
      << (std::isnan(images) ? std::string("(none: ") + to_string(fp.method) + ")" : num(images, 10))
      << (std::isnan(neighbours) ? std::string() : ", neighbours per particle " + num(neighbours)) << ", h = " << num(f.h())
      << "\n";
  if (const auto kept = f.profiler().report().footprint)
    out << "  kept for the run: " << kept->operator_nonzeros << " operator non-zeros, " << kept->factor_nonzeros
        << " factor non-zeros, " << kept->pairs << " pairs\n";
}

bool paper_pair_of(const FluidParams& fp, MarkerInterpolation interp, bool particles_move) {
  return interp == MarkerInterpolation::Sph &&
         (fp.projection == Projection::Approximate || (fp.projection == Projection::Auto && particles_move));
}

int warnings_for(const Scene& scene, const Picture& p, std::ostream& out);

}  // namespace

int check_scene(const Scene& scene, std::ostream& out, bool build) {
  const MemoryEstimate e = estimate_memory(scene);
  out << (scene.path.empty() ? scene.title : scene.path) << ": ok\n";
  if (build || e.bytes <= kBuildBytes) {
    const Simulation sim(scene.sim);  // builds everything: refuses what cannot run
    report_built(sim, out);
    const Picture p{sim.fluid().params(), sim.fluid().lattice().dx, sim.fluid().lattice().dy, sim.fluid().x(),
                    sim.fluid().u(), sim.membranes(),
                    paper_pair_of(sim.fluid().params(), sim.interpolation(), sim.fluid().particles_move())};
    report_membranes(p, out);
    return report_memory(scene, e, out) + warnings_for(scene, p, out);
  }
  // Too large to build here: the lattice, the flow at t = 0 and the membranes from the scene alone.
  const FluidParams& fp = scene.sim.fluid;
  const Lattice L = make_lattice(fp.domain, fp.nx, fp.ny);
  Mat2 u0 = Mat2::Zero(L.size(), 2);
  if (scene.sim.initial_velocity)
    for (int i = 0; i < L.size(); ++i) u0.row(i) = scene.sim.initial_velocity(L.x(i, 0), L.x(i, 1)).transpose();
  std::vector<MembraneState> membranes(scene.sim.membranes.begin(), scene.sim.membranes.end());
  MarkerInterpolation interp = scene.sim.interpolation;
  if (interp == MarkerInterpolation::Auto) interp = fp.method == FluidMethod::Eulerian ? MarkerInterpolation::DivergenceFree : MarkerInterpolation::Sph;  // (B-splines too: not the paper's pair)
  const Picture p{fp, L.dx, L.dy, L.x, u0, membranes, paper_pair_of(fp, interp, fp.method != FluidMethod::Eulerian)};
  out << "  not built: its estimated peak, " << bytes(e.bytes) << ", is above " << bytes(kBuildBytes)
      << " (sphib check --build builds it: the factorisations, and a membrane too close to a wall, are then checked too)\n"
      << "  particles " << L.size() << " (" << fp.nx << " x " << fp.ny << ", dx = " << num(L.dx) << ", dy = " << num(L.dy)
      << "), lattice neighbours per particle " << e.neighbours << ", h = " << num(fp.h_over_dx * 0.5 * (L.dx + L.dy)) << "\n";
  report_membranes(p, out);
  return report_memory(scene, e, out) + warnings_for(scene, p, out);
}

int time_step_warnings(const Scene& scene, const Simulation& sim, std::ostream& out) {
  const FluidSolver& f = sim.fluid();
  const Picture p{f.params(), f.lattice().dx, f.lattice().dy, f.x(), f.u(), sim.membranes(),
                  paper_pair_of(f.params(), sim.interpolation(), f.particles_move())};
  return warnings_for(scene, p, out);
}

namespace {

int warnings_for(const Scene& scene, const Picture& p, std::ostream& out) {
  const FluidParams& fp = p.fp;
  const Domain& d = fp.domain;
  const int N = static_cast<int>(p.x.rows());
  const double dx = p.dx, dy = p.dy, h_min = std::min(dx, dy), dt = fp.dt;
  int warnings = 0;
  if (const std::string w = kernel_warning(fp); !w.empty()) {
    ++warnings;
    out << "    WARNING: " << w << "\n";
  }
  // Markers farther apart than a lattice spacing let fluid through between them (documented
  // limit: markers per grid spacing >= 1, i.e. the largest marker spacing <= min(dx, dy)).
  for (size_t k = 0; k < p.membranes.size(); ++k) {
    const auto& m = p.membranes[k];
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
    if (d.is_wall(static_cast<Side>(s)) || d.kind(static_cast<Side>(s)) == SideKind::Inflow)
      U_wall = std::max(U_wall, d.wall_velocity[s].norm());
  scales.push_back({U_wall, "wall velocity"});
  scales.push_back({p.u.rowwise().norm().maxCoeff(), "initial velocity"});
  double F = scene.sim.body_force.norm();
  if (scene.sim.body_force_field) {
    F = 0;
    for (int i = 0; i < N; ++i) F = std::max(F, scene.sim.body_force_field(p.x(i, 0), p.x(i, 1), 0.0).norm());
  }
  if (F > 0) {
    // Poiseuille centre-line F L^2/(8 mu) across the narrowest walled extent, reached after the
    // viscous time; before that (or without walls) free acceleration F t_end / rho.
    double U_F = F * scene.t_end / fp.rho;
    const double L = std::min(d.periodic_y ? INFINITY : d.Ly(), d.periodic_x ? INFINITY : d.Lx());
    if (std::isfinite(L)) U_F = std::min(U_F, F * L * L / (8.0 * fp.mu));
    scales.push_back({U_F, "body force: min(F L^2/(8 mu), F t_end/rho)"});
  }
  if (const double g = fp.gravity.norm(); g > 0) {
    // A column of height H along g released: the dam-break front's speed 2 sqrt(g H) (Ritter's
    // shallow-water solution), the largest a free surface falling under gravity reaches in bulk.
    const double H = fluid_height(fp.free_surface.fill, d, fp.gravity);
    scales.push_back({2.0 * std::sqrt(g * H), "gravity: 2 sqrt(|g| H), H = " + num(H) + " the fluid's height along g"});
  }
  for (size_t k = 0; k < p.membranes.size(); ++k) {
    const auto& m = p.membranes[k];
    if (m.fixed) continue;
    // The elastic energy E released into the fluid: the Stokes speed of the largest stress (a line
    // force density f at wavenumber k moves a line at f/(4 mu k); the tension T gives f ~ T k, the
    // bending moment m f ~ m k^2 with k ~ 1/R on a membrane of length 2 pi R), or, if smaller, the
    // inertial speed sqrt(2 E/(rho A)) of the enclosed area A.
    MembraneForce force(m.m);
    Mat2 fk;
    Vec T;
    force.compute(m.m.X, fk, T);
    MembraneDiagnostics diag(m.m.nb(), m.m.L0());
    const MembraneShape s = diag.measure(m.m.X);
    const MembraneStiffness st = force.stiffness();
    double moment = 0.0;  // max |Eb (kappa - kappa0)| at the markers
    if (st.Eb > 0) {
      KnotGeometry g(m.m.nb(), m.m.L0());
      g.fit(m.m.X, true);
      for (int i = 0; i < m.m.nb(); ++i) {
        const double k0 = m.m.mat.spontaneous ? m.m.mat.spontaneous_curvature : m.m.ref.kappa(i);
        moment = std::max(moment, st.Eb * std::fabs(g.kappa[i] - k0));
      }
    }
    constexpr double kPi = 3.14159265358979323846;
    const double stress = T.cwiseAbs().maxCoeff() + moment * 2.0 * kPi / st.length;
    if (!(stress > 0)) continue;
    const double U_m = std::min(stress / (4.0 * fp.mu), std::sqrt(2.0 * force.energy().total() / (fp.rho * s.area)));
    scales.push_back({U_m, "membrane " + std::to_string(k) + ": min((max|T| + max|m|/R)/(4 mu), sqrt(2 E_el/(rho A)))"});
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
  const double h = fp.h_over_dx * 0.5 * (dx + dy), nu = fp.mu / fp.rho;
  if (fp.method == FluidMethod::Wcsph) {
    // The solver refuses a dt above this limit (fluid/moving/wcsph.hpp): a WARNING only for a scene too large to build here.
    const double c = wcsph_sound_speed(fp), limit = coelho_dt_limit(h, c, nu);
    const bool over = dt > limit;
    warnings += over;
    out << "    " << (over ? "WARNING: " : "") << "acoustic and viscous limit (Coelho et al. Eq. 19): dt < min(0.25 h/c, "
        << "0.125 h^2/nu) = " << num(limit) << " with c = " << num(c) << (over ? ": dt exceeds it (sphib run refuses it)" : ": ok")
        << "\n";
  } else if (fp.method == FluidMethod::Isph && fp.isph.viscous == IsphViscous::Explicit) {
    // The explicit viscous predictor (Afanasiev et al. Eq. 22) is a forward-Euler diffusion step.
    const double limit = 0.125 * h * h / nu;
    const bool over = dt > limit;
    warnings += over;
    out << "    " << (over ? "WARNING: " : "") << "explicit viscous limit: dt < 0.125 h^2/nu = " << num(limit)
        << (over ? ": dt exceeds it (isph.viscous = \"crank_nicolson\" lifts it)" : ": ok") << "\n";
  }
  // Explicit elastic limit. The membrane force is explicit in X^n (Eq. 50 at t_n), so the stiffest
  // membrane mode the spreading kernel passes (wavenumber k ~ 1/h*) limits dt, as in every explicit
  // IB method. Two scalings: inertial, T0 k^3 dt^2 / rho below a constant (a stretching wave with
  // the fluid's added mass rho/k; the T0 dt^2/h scaling of the explicit-IB stability analysis of
  // Hua & Peskin 2021, arXiv:2111.15065), and viscous, dt below a constant times mu/(T0 k) (the
  // Stokes relaxation rate of that mode). The constants are NOT from a source: they were measured
  // with this code, a factor-of-two guide, not a bound (docs/guide/check_and_sweeps.md,
  // docs/performance/stability.md). The inertial constant depends on the pair: the paper's (approximate projection,
  // Eq. 63 markers) leaks area and with it elastic energy, which lets it run with dt about 3 times
  // larger (bench/stability_map, fitted in h* form: 0.32 conservative, about 1 paper's).
  const double c_i = p.paper_pair ? 1.0 : 0.3;
  // Bending: the same two scalings for a bending mode k ~ 1/h* (the stiffness Eb k^4 in place of T0 k^2):
  // inertial, Eb k^5 dt^2 / rho below a constant (added mass 2 rho/k), viscous, dt below a constant times
  // mu/(Eb k^3). Constants fitted to the measured limits (bench/stability_map --parts B: the released
  // ellipse with T0 = 1, explicit force, Nx = 24-64; docs/membrane_validation.md, "Stability"): a guide
  // within a factor 1.5, not a bound. The step scales like h*^3 (measured exponent 2.9).
  constexpr double kBendCi = 0.07, kBendCv = 4.0;
  for (size_t k = 0; k < p.membranes.size(); ++k) {
    const auto& m = p.membranes[k];
    MembraneForce force(m.m);
    Mat2 fk;
    Vec T;
    force.compute(m.m.X, fk, T);
    const MembraneStiffness st = force.stiffness();
    if (m.fixed) continue;
    const double hs = m.h_star;
    // The stiff-force filter (membrane.semi_implicit) takes the stiff modes implicitly: it lifts both
    // explicit limits (bench/stability_map part B: semi-implicit runs reach the flow's own limit).
    const bool lifted = m.filter != nullptr;
    if (st.Et > 0) {
      const double inertial = c_i * std::sqrt(fp.rho * hs * hs * hs / st.Et), viscous = 10.0 * fp.mu * hs / st.Et;
      const double limit = std::max(inertial, viscous);
      const bool over = dt > limit && !lifted;
      warnings += over;
      out << "    " << (over ? "WARNING: " : "") << "membrane " << k
          << " elastic limit (measured estimate, explicit membrane force): dt < max(" << c_i
          << " sqrt(rho h*^3/T0), 10 mu h*/T0) = " << num(limit)
          << (lifted ? (dt > limit ? ": dt exceeds it, lifted by semi_implicit" : ": ok (semi_implicit lifts it)")
                     : over ? ": dt exceeds it" : ": ok")
          << "\n";
    }
    if (st.Eb > 0) {
      const double inertial = kBendCi * std::sqrt(fp.rho * std::pow(hs, 5) / st.Eb),
                   viscous = kBendCv * fp.mu * hs * hs * hs / st.Eb;
      const double limit = std::max(inertial, viscous);
      // The filter's lift needs markers no denser than ~2 per lattice spacing: at 3 and 4 it rose the
      // limit only 4-6x (bench/stability_map part B, Eb = 1 and 10).
      const double per_dx = p.dx / m.m.ds();
      const bool dense = lifted && per_dx > 2.2 && dt > limit;
      const bool over = (dt > limit && !lifted) || dense;
      warnings += over;
      out << "    " << (over ? "WARNING: " : "") << "membrane " << k
          << " bending limit (measured estimate, explicit membrane force): dt < max(" << kBendCi
          << " sqrt(rho h*^5/Eb), " << kBendCv << " mu h*^3/Eb) = " << num(limit)
          << (dense    ? ": dt exceeds it, and semi_implicit lifts it only with markers no denser than 2 per lattice "
                         "spacing (here " + num(per_dx) + "): lower membrane.nb"
              : lifted ? (dt > limit ? ": dt exceeds it, lifted by semi_implicit" : ": ok (semi_implicit lifts it)")
              : over   ? ": dt exceeds it (set membrane.semi_implicit = true)"
                       : ": ok")
          << "\n";
    }
  }
  return warnings;
}

}  // namespace

}  // namespace sphib
