#pragma once
// The Eulerian projection SPH fluid (EPSPH): the projection core (projection_core.hpp) on particles
// fixed on the lattice of Eq. (68). Everything that does not change in time (lattice, images, pairs,
// operator matrices, their lattice stencils, the Crank-Nicolson and Poisson factorisations) is built
// once in the constructor; a step is products and solves only, with no allocation. What EPSPH adds
// to the core: the convection term (Eqs. 39-41, AB2), the exact projection and the markers' stream
// function (exact_projection.hpp), and the floor of a step.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fluid/eulerian/exact_projection.hpp"
#include "fluid/eulerian/fused_passes.hpp"
#include "fluid/core/projection_core.hpp"
#include "fluid/eulerian/variable_viscosity.hpp"

namespace sphib {

class EulerianFluid final : public ProjectionFluid {
 public:
  // `profiler`: the run loop's (nullptr: its own), where it records its phases, set-up, report
  // and floor.
  explicit EulerianFluid(const FluidParams& params, Profiler* profiler = nullptr);

  // phi^n: the approximate projection's, or (exact projection) recovered when first asked for after
  // a step as the smooth phi~ with the same D G phi (see phi() in eulerian.cpp).
  const Vec& phi() const override;
  // max_i |(D u^n)_i| with the divergence the projection makes zero: D = -G^T (exact projection;
  // differs from Eq. (30) with no-slip images only in the rows within 2h of a wall), or Eq. (30)
  // with the no-slip images of u^n (approximate projection).
  double max_abs_divergence() const override;
  double poisson_residual() const;  // ||A x - b|| / ||b|| of the last step's projection solve
  // The markers' stream function psi_m of u^n (exact_projection.hpp), computed on the first call
  // after a step.
  StreamFunction stream_function() const override;

  // A variable viscosity mu m (fluid/eulerian/variable_viscosity.hpp), made when some m first differs from 1:
  // until then, and whenever every m is 1 again, the constant-viscosity step, unchanged.
  void set_viscosity(const int* at, const double* m, int n) override;
  const VariableViscosity* variable_viscosity() const { return visc_.get(); }
  // Its options (rtol, the form for m > 1: fluid/eulerian/variable_viscosity.hpp) for the next set_viscosity
  // that makes it (benchmarks; a and the rest are the fluid's).
  void set_variable_viscosity_params(const VariableViscosityParams& p) { visc_prm_ = p; }

  std::vector<SolverInfo> solver_info() const override;
  double cn_mean_iterations() const { return cn_->mean_iterations(); }
  // The whole operator matrices (the compact storage assembles them again when first asked for, and
  // keeps them from then on)
  const Operators& operators() const override;
  bool compact_storage() const { return compact_; }
 private:
  // Its report to the profiler: the run-log lines, figures and footprint.
  void report(FluidReport& r) const;
  // The floor of a step: the bare kernels it cannot avoid (the Crank-Nicolson and projection solves
  // and the fused sparse products, on the current fields), handed to the profiler's timer.
  void floor_kernels(FloorTimer& t) const;
  void stream_function_floor_kernels(FloorTimer& t) const;
  void viscous_rhs(const Mat2& F) override;  // Eqs. (28), (39)-(41) in one pass (fluid/eulerian/fused_passes.hpp)
  void project() override;
  LinearSolver& predictor_solver() override { return visc_ && visc_->active() ? visc_->solver_for_step(n_, first_) : *cn_; }
  void extra_state(NamedArrays& st) const override;
  void restore_extra(const NamedArrays& st) override;
  bool exact() const { return prm_.projection == Projection::Exact; }
  void make_phi_solver() const;  // exact projection: the Morris Laplacian's, for phi~ (on demand)
  std::string phi_system() const;  // its name (the solver's log line)
  void pairs_current() const override;  // the pair list again where the compact storage freed it

  // Compact storage (the exact projection with the lattice solvers, solver.* = auto or fft): the
  // operators keep only their stencils' rows, the pair list and the phi gradients are freed after
  // the setup (see the constructor). Off where a solver key forces another solver, with the
  // approximate projection, and once the whole matrices are asked for (operators(), a variable
  // viscosity).
  mutable bool compact_ = false;
  long pairs_count_ = 0;             // the pair list's length (kept when the list is freed)
  RowStencil lap_phi_st_lattice_;    // lap_phi's own stencil (compact storage: the pressure, Eq. 35)

  RowStencil vel_st_lattice_, phi_st_lattice_;  // the lattice rows of the velocity and phi patterns
  ImageRows vel_images_;            // the velocity pattern's blocks with image terms
  Mat2 conv_wall_x_, conv_wall_y_;  // B c^n of grad_ux, grad_uy: the wall values' convection terms
  Mat2 lap_star_;                   // B c* of the Laplacian (this step's images; zero off the wall rows)
  Mat2 conv_old_;                   // N^n kept for AB2 (Eq. 39)
  // Where the velocity components' image parities differ (Images::split, a free-slip side): the wall
  // terms of lap u^n and of the convection gradients with the images' per-component correction, this
  // step's (the constant ones above plus B v_split u^n)
  Mat2 split_c_, split_lw_, split_cwx_, split_cwy_;
  void make_split_crank_nicolson();  // cn_ (x) and cn_v_ (y) from the components' Laplacians
  mutable std::unique_ptr<ExactProjection> streams_;  // made when first needed (approximate projection)
  std::unique_ptr<VariableViscosity> visc_;           // made when a viscosity first differs from mu
  VariableViscosityParams visc_prm_;
  int k_visc_ = -1;                                   // its profile phase (set_viscosity)
  mutable long phi_step_ = 0;  // exact projection: the step phi_ belongs to
  int k_psi_;
};

}  // namespace sphib
