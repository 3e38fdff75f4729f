#include "fluid/core/solver.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fluid/common/loads.hpp"
#include "fluid/algebra/row_stencil.hpp"  // kParallelRows

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

double FluidSolver::kinetic_energy() const {
  // sum_i |u_i|^2: below kParallelRows particles in one sum (Eigen's order); above, by the threads in
  // kBlocks fixed blocks, each summed alone, the blocks' sums added in block order (the same bits
  // for any thread count)
  const long n = u_.size();
  if (n < 2L * kParallelRows) return 0.5 * mass_ * u_.squaredNorm();
  constexpr int kBlocks = 64;
  const long len = (n + kBlocks - 1) / kBlocks;
  double part[kBlocks];
#pragma omp parallel for schedule(static)
  for (int b = 0; b < kBlocks; ++b) {
    const long at = std::min(n, b * len), m = std::min(n, at + len) - at;
    part[b] = Eigen::Map<const Eigen::VectorXd>(u_.data() + at, m).squaredNorm();
  }
  double s = 0;
  for (double v : part) s += v;
  return 0.5 * mass_ * s;
}

FluidSolver::FluidSolver(const FluidParams& params, bool particles_move, Profiler* profiler)
    : prm_(params), lat_(make_lattice(params.domain, params.nx, params.ny)),
      W_(params.h_over_dx * 0.5 * (lat_.dx + lat_.dy)), moves_(particles_move),
      own_profiler_(profiler ? nullptr : std::make_unique<Profiler>()),
      profiler_(profiler ? profiler : own_profiler_.get()) {}

FluidSolver::~FluidSolver() { profiler_->detach(); }  // the run loop's profiler outlives the method

void FluidSolver::set_viscosity(const int*, const double*, int) {
  throw std::invalid_argument("a variable viscosity (membrane.viscosity_ratio != 1) is not available for method \"" +
                              std::string(to_string(params().method)) + "\" (use method = \"eulerian\")");
}

WallForces FluidSolver::wall_forces() const {
  return wall_forces_by_interpolation(params().domain, x(), volumes(), p(), kernel(), lattice().dx, lattice().dy);
}

}  // namespace sphib
