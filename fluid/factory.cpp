#include "fluid/factory.hpp"

#include <stdexcept>

#include "fluid/eulerian/eulerian.hpp"
#include "fluid/moving/isph.hpp"
#include "fluid/moving/lagrangian.hpp"
#include "fluid/moving/wcsph.hpp"

namespace sphib {

std::optional<ParamProblem> free_surface_problem(const FluidParams& p) {
  if (p.method == FluidMethod::Wcsph) return wcsph_free_surface_problem(p);
  if (p.method == FluidMethod::Isph) return isph_problem(p);
  return free_surface_problem(p.method, p.domain, p.free_surface, p.gravity);
}

std::unique_ptr<FluidSolver> make_fluid(const FluidParams& params, Profiler* profiler) {
  if (const auto e = free_surface_problem(params)) throw std::invalid_argument(e->key + ": " + e->what);
  if (params.domain.any_through() && params.method != FluidMethod::Eulerian)
    throw std::invalid_argument(std::string("domain.inflow/domain.outflow: inflow and outflow sides are available for "
                                            "method \"eulerian\" only (not \"") + to_string(params.method) + "\")");
  for (int k = 0; k < 4; ++k)
    if (params.domain.kind(static_cast<Side>(k)) == SideKind::FreeSlip && params.method != FluidMethod::Eulerian)
      throw std::invalid_argument(std::string("domain.free_slip: a free-slip side (\"") + side_name(static_cast<Side>(k)) +
                                  "\") is available for method \"eulerian\" only (not \"" + to_string(params.method) + "\")");
  switch (params.method) {
    case FluidMethod::Eulerian: return std::make_unique<EulerianFluid>(params, profiler);
    case FluidMethod::Lagrangian: return std::make_unique<LagrangianFluid>(params, profiler);
    case FluidMethod::Wcsph: return std::make_unique<WcsphFluid>(params, WcsphOptions{}, profiler);
    case FluidMethod::Isph: return std::make_unique<IsphFluid>(params, profiler);
  }
  throw std::invalid_argument("method: not one of eulerian, lagrangian, wcsph, isph");
}

}  // namespace sphib
