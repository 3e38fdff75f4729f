#include "fluid/solver.hpp"

#include <stdexcept>

#include "fluid/lagrangian.hpp"
#include "fluid/projection.hpp"
#include "fluid/wcsph.hpp"

namespace sphib {

NamedArrays FluidSolver::state() const {
  throw std::runtime_error("checkpoints are not available for method \"" + params().method + "\"");
}

void FluidSolver::restore(const NamedArrays&) {
  throw std::runtime_error("checkpoints are not available for method \"" + params().method + "\"");
}

std::unique_ptr<FluidSolver> make_fluid(const FluidParams& params) {
  if (params.method == "eulerian") return std::make_unique<Fluid>(params);
  if (params.method == "lagrangian") return std::make_unique<LagrangianFluid>(params);
  if (params.method == "wcsph") return std::make_unique<WcsphFluid>(params);
  throw std::invalid_argument("method: \"" + params.method +
                              "\" is not available (allowed: eulerian, lagrangian, wcsph)");
}

}  // namespace sphib
