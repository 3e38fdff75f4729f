#include "fluid/core/solver.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fluid/common/loads.hpp"
#include "fluid/algebra/row_stencil.hpp"  // kParallelRows
#include "fluid/common/threads.hpp"

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
  // fixed blocks (sum_by_blocks: the same bits for any thread count)
  const long n = u_.size();
  if (n < 2L * kParallelRows) return 0.5 * mass_ * u_.squaredNorm();
  return 0.5 * mass_ * sum_by_blocks(n, [&](long at, long m) {
    return Eigen::Map<const Eigen::VectorXd>(u_.data() + at, m).squaredNorm();
  });
}

double FluidSolver::max_speed() const {
  // max_i |u_i|; above kParallelRows particles by the threads in fixed blocks of rows, as the root of
  // the largest |u_i|^2 (one square root, not N: a correctly rounded root is monotone, so the same
  // bits as the largest of Eigen's row norms; max_by_blocks: a maximum is exact)
  const long N = u_.rows();
  if (N < kParallelRows) return u_.rowwise().norm().maxCoeff();
  return std::sqrt(
      max_by_blocks(N, [&](long at, long m) { return u_.middleRows(at, m).rowwise().squaredNorm().maxCoeff(); }));
}

double FluidSolver::max_abs(const Vec& d) {
  const long n = d.size();
  if (n < kParallelRows) return d.cwiseAbs().maxCoeff();
  return max_by_blocks(n, [&](long at, long m) { return d.segment(at, m).cwiseAbs().maxCoeff(); });
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
