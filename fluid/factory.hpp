#pragma once
// The fluid method a scene names, made: the one place that knows every method (above them all; the
// methods know only the contract in solver.hpp).
#include <memory>
#include <optional>

#include "fluid/core/solver.hpp"

namespace sphib {

// What is wrong with the free-surface keys for params.method (free_surface_problem and the
// method's own), as (scene key, message); nothing if all is well. make_fluid refuses the same.
std::optional<ParamProblem> free_surface_problem(const FluidParams& params);

// The solver of params.method; it records its timings and report into `profiler` (the run loop's,
// which must outlive it; nullptr: the method keeps its own).
std::unique_ptr<FluidSolver> make_fluid(const FluidParams& params, Profiler* profiler = nullptr);

}  // namespace sphib
