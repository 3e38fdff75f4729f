#include "fluid/factory.hpp"

#include <stdexcept>

#include "fluid/eulerian.hpp"
#include "fluid/isph.hpp"
#include "fluid/lagrangian.hpp"
#include "fluid/wcsph.hpp"

namespace sphib {

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
