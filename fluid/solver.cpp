#include "fluid/solver.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fluid/eulerian.hpp"
#include "fluid/isph.hpp"
#include "fluid/lagrangian.hpp"
#include "fluid/wcsph.hpp"

namespace sphib {

void positive_param(double v, const char* key) {
  if (!(v > 0) || !std::isfinite(v)) {
    std::ostringstream m;
    m << "fluid: " << key << " must be positive and finite (got " << v << ")";
    throw std::invalid_argument(m.str());
  }
}

void check_common_params(const FluidParams& p) {
  positive_param(p.rho, "fluid.rho");
  positive_param(p.mu, "fluid.mu");
  positive_param(p.dt, "time.dt");
  positive_param(p.h_over_dx, "kernel.h_over_dx");
}

const Eigen::MatrixXd& state_entry(const NamedArrays& state, const std::string& name, Eigen::Index rows,
                                   Eigen::Index cols) {
  for (const auto& [k, v] : state)
    if (k == name) {
      if (v.rows() != rows || v.cols() != cols)
        throw std::runtime_error("checkpoint: " + name + " has the wrong size for this lattice");
      return v;
    }
  throw std::runtime_error("checkpoint: no " + name + " in the fluid state");
}

NamedArrays FluidSolver::state() const {
  throw std::runtime_error("checkpoints are not available for method \"" + params().method + "\"");
}

void FluidSolver::restore(const NamedArrays&) {
  throw std::runtime_error("checkpoints are not available for method \"" + params().method + "\"");
}

void FluidSolver::set_viscosity(const int*, const double*, int) {
  throw std::invalid_argument("a variable viscosity (membrane.viscosity_ratio != 1) is not available for method \"" +
                              params().method + "\" (use method = \"eulerian\")");
}

WallForces FluidSolver::wall_forces() const {
  return wall_forces_by_interpolation(params().domain, x(), volumes(), p(), kernel(), lattice().dx, lattice().dy);
}

std::optional<ParamProblem> free_surface_problem(const FluidParams& p) {
  if (p.method == "wcsph") return wcsph_free_surface_problem(p);
  if (p.method == "isph") return isph_problem(p);
  return free_surface_problem(p.method, p.domain, p.free_surface, p.gravity);
}

std::unique_ptr<FluidSolver> make_fluid(const FluidParams& params) {
  if (const auto e = free_surface_problem(params)) throw std::invalid_argument(e->key + ": " + e->what);
  if (params.method == "eulerian") return std::make_unique<EulerianFluid>(params);
  if (params.method == "lagrangian") return std::make_unique<LagrangianFluid>(params);
  if (params.method == "wcsph") return std::make_unique<WcsphFluid>(params);
  if (params.method == "isph") return std::make_unique<IsphFluid>(params);
  throw std::invalid_argument("method: \"" + params.method +
                              "\" is not available (allowed: eulerian, lagrangian, wcsph, isph)");
}

}  // namespace sphib
