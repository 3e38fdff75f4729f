#include "observe/guards.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {

[[noreturn]] void stop(const Simulation& sim, const std::string& what) {
  std::ostringstream m;
  m << what << " at step " << sim.steps() << " (t = " << sim.time() << ")";
  throw std::runtime_error(m.str());
}

[[noreturn]] void blow_up(const Simulation& sim, const std::ostringstream& what) {
  std::ostringstream m;
  m << "blow-up at step " << sim.steps() << " (t = " << sim.time() << "): " << what.str();
  throw std::runtime_error(m.str());
}

bool unforced(const SimulationParams& p) {
  if (p.membranes.empty() || p.body_force_field || p.body_force.norm() != 0.0) return false;
  if (p.fluid.domain.any_through()) return false;  // an inflow drives the flow
  for (int k = 0; k < 4; ++k)
    if (p.fluid.domain.is_wall(static_cast<Side>(k)) && p.fluid.domain.wall_velocity[k].norm() != 0.0) return false;
  return true;
}

}  // namespace

Guards::Guards(const SimulationParams& params, const Simulation& sim)
    : h_min_(std::min(sim.fluid().lattice().dx, sim.fluid().lattice().dy)), v_min_(sim.fluid().volumes().minCoeff()) {
  for (const auto& ms : sim.membranes()) E_.push_back(ms.force);
  if (unforced(params)) {
    const double E0 = sim.fluid().kinetic_energy() + elastic_energy(sim);
    energy_bound_ = E0 > 0 ? 10.0 * E0 : 0.0;
  }
}

double Guards::elastic_energy(const Simulation& sim) {
  double E = 0;
  for (size_t k = 0; k < E_.size(); ++k) {
    const MembraneState& s = sim.membranes()[k];
    if (s.force.fitted_to(s.m.X)) {  // the force's splines of these markers (every step: its end fits them)
      E += s.force.energy().total();
      continue;
    }
    E_[k].fit_energy(s.m.X);
    E += E_[k].energy().total();
  }
  return E;
}

void Guards::check(const Simulation& sim) {
  const FluidSolver& fl = sim.fluid();
  const FluidParams& fp = fl.params();
  const double ke = fl.kinetic_energy();
  if (!std::isfinite(ke)) stop(sim, "the velocity field became non-finite");
  // No particle may move by more than a lattice spacing in one step (u_max dt < dx). The explicit
  // convection (AB2) and the marker update are unstable long before that.
  const double v_min = fl.particles_move() ? fl.volumes().minCoeff() : v_min_;
  const double cfl = std::sqrt(2.0 * ke / (fp.rho * v_min)) * fp.dt / h_min_;
  if (cfl > 1.0) {
    const double umax = fl.max_speed();
    if (umax * fp.dt > h_min_) {
      std::ostringstream m;
      m << "max |u| = " << umax << " moves a particle by " << umax * fp.dt / h_min_
        << " lattice spacings in one step (limit 1)";
      blow_up(sim, m);
    }
  }
  for (size_t k = 0; k < sim.membranes().size(); ++k)
    if (!sim.membranes()[k].m.X.allFinite()) stop(sim, "membrane " + std::to_string(k) + " markers became non-finite");
  // Unforced membranes can only lose energy (viscous dissipation): a total energy past ten times
  // its initial value is a blow-up of the explicit elastic force, caught before fields overflow.
  if (energy_bound_ > 0) {
    const double E = ke + elastic_energy(sim);
    if (!(E <= energy_bound_)) {
      std::ostringstream m;
      m << "kinetic + elastic energy " << E << " exceeds ten times its initial value (" << energy_bound_ / 10.0
        << ") in an unforced flow";
      blow_up(sim, m);
    }
  }
}

}  // namespace sphib
