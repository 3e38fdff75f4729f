#pragma once
// The Lagrangian projection SPH fluid (LPSPH, Section 3.1): the PMIII step of EPSPH (Eqs. 28-35,
// images by Eq. 42) on particles that move with the fluid, Eq. (37)
//     x_i^{n+1} = x_i^n + dt/2 (u_i^{n+1} + u_i^n),
// wrapped into the periodic box. The convection term is carried by the particle motion and is not
// discretised. Volumes V = dx dy stay constant (incompressible: constant mass and density).
//
// What EPSPH builds once is rebuilt here at the beginning of every step: the images (Section 3.3:
// "the positions of the image particles need to be reassigned at the beginning of each time step"),
// the pair list (cell list, O(N)), the operator matrices and both factorisations. The factorisations
// keep CHOLMOD's symbolic analysis while the sparsity pattern does not change
// (LinearSolver::refactorize); describe() says in how many steps it could.
//
// Where: the paper does not say at which positions the sums of a step are taken. We take the
// predicted positions x* = x^n + dt u^n (the idea of Cummins & Rudman's SPH projection method), so
// that the projection makes u^{n+1} divergence-free where the particles will be: x^{n+1} - x* =
// dt/2 (u^{n+1} - u^n) = O(dt^2). Taken at x^n instead, the pressure lags one step behind the
// convective acceleration, an O(dt) velocity error. Measured on Taylor-Green (fully periodic,
// nx = 32, h = 2 dx, nu = 0.01, u_max = 1, dt = 2e-3), rms error at t = 0.01: sums at x^n 7.1e-3,
// at x* 8.8e-4, EPSPH 9.6e-4. (For the unidirectional Poiseuille problem, and for the oscillating
// membrane at dt = 1e-4, the two agree to 3 digits.)
// The operators, images, pairs and kernel sums shown below are those of the last step's x*.
//
// Optional reinitialisation (Section 5.2.1, Figs. 9 C-D): every `reinit_every` steps the particles go
// back onto the lattice, and u, phi and grad phi (Eq. 42 needs it) are interpolated there from the
// old particles and their images by normalised SPH interpolation, Eq. (61).
//
// Breakdown (Section 5.2.2, Fig. 18): particles driven apart leave holes in which the quadrature
// fails. At every rebuild the kernel sum S_i = sum_j V W_ij (images and i itself included; 1 on a
// lattice) of every particle is checked against params.lagrangian.min_kernel_sum; a step whose
// positions x* bring one below throws std::runtime_error naming the time t_{n+1}, the particle and
// its position, before it changes anything (the solver keeps the state of t_n). A particle beyond a
// wall throws as well.
#include <memory>
#include <vector>

#include "fluid/boundary.hpp"
#include "fluid/kernel.hpp"
#include "fluid/lattice.hpp"
#include "fluid/linear_solver.hpp"
#include "fluid/neighbours.hpp"
#include "fluid/operators.hpp"
#include "fluid/profile.hpp"
#include "fluid/solver.hpp"

namespace sphib {

class LagrangianFluid final : public FluidSolver {
 public:
  explicit LagrangianFluid(const FluidParams& params);  // particles on the lattice (Eq. 68), at rest

  // Rebuilds everything at x* = x^n + dt u^n (a breakdown throws here, the state unchanged), one
  // PMIII step from t_n to t_{n+1} there, then the particles move by Eq. (37) and, when due, go back
  // onto the lattice.
  void step(const Mat2& F) override;
  void set_velocity(const Mat2& u0) override;  // u^0 at the current positions

  // Puts the particles at x (N x 2, wrapped into the periodic box) and rebuilds there; throws like
  // step() for a particle beyond a wall or a kernel sum below the threshold. The fields stay with
  // their particles. (Tests, restarts.)
  void set_positions(const Mat2& x);
  // Figs. 9 C-D: the particles back onto the lattice, u, phi and grad phi interpolated by Eq. (61).
  void reinitialise();

  const FluidParams& params() const override { return prm_; }
  const Lattice& lattice() const override { return lat_; }  // the initial positions
  const CubicSplineKernel& kernel() const override { return W_; }
  bool particles_move() const override { return true; }
  const Mat2& x() const override { return x_; }  // x^n
  const Vec& volumes() const override { return V_; }
  const Images& images() const { return im_; }      // at x* of the last step (x^n before any step)
  const PairList& pairs() const { return pairs_; }  // at x*
  const Operators& operators() const { return op_; }  // at x*

  const Mat2& u() const override { return u_; }     // u^n
  const Vec& phi() const override { return phi_; }  // phi^n
  // p^{n-1/2} (Eq. 35) from phi^n with the Laplacian of the step that made it (at x*), zero mean;
  // recovered only when asked for, once per step.
  const Vec& p() const override;
  const Mat2& grad_phi() const { return grad_phi_; }
  double time() const override { return t_; }
  long steps() const override { return n_; }

  double max_abs_divergence() const override;  // max_i |(div u^n)_i|, Eq. (30) at x* (where u^n was projected)
  double kinetic_energy() const override;      // sum_i rho V |u_i|^2 / 2
  const Vec& kernel_sums() const { return S_; }  // S_i = sum_j V W_ij at x*, images and j = i included
  double lowest_kernel_sum() const { return S_low_; }  // over the run so far

  long refactorisations() const { return n_refactor_; }           // rebuilds after the constructor's
  long symbolic_reused_cn() const { return n_reused_cn_; }        // of them, with the analysis kept
  long symbolic_reused_poisson() const { return n_reused_poisson_; }
  long reinitialisations() const { return n_reinit_; }

  std::vector<SolverInfo> solver_info() const;
  std::vector<std::string> describe() const override;
  std::vector<std::pair<std::string, double>> figures() const override;
  Profile& profile() const override { return prof_; }
  double setup_seconds(const std::string& what) const override;  // "neighbours", "assembly", "factorisation"
  // Checkpoints: positions, fields and the clock; restore() rebuilds at the positions.
  NamedArrays state() const override;
  void restore(const NamedArrays& state) override;

 private:
  struct RebuildSeconds { double neighbours = 0, assembly = 0, factorisation_cn = 0, factorisation_poisson = 0; };
  // Images, pairs, kernel sums (breakdown at time t), operators, factorisations at x_star_.
  RebuildSeconds rebuild(double t);
  // The operators of build_operators (operators.hpp), assembled straight into compressed rows: one
  // pattern from the pair list for every operator (A: particle i, its neighbours and the parents of
  // its image neighbours; B: i and its image neighbours; explicit zeros are kept), then each
  // operator's values by scattering the pair terms into it.
  void make_pattern();
  void assemble(ImageRule rule, const std::vector<double>& a, bool difference, SpMat& A, SpMat* B) const;
  void wrap_into_domain(Mat2& x, double t) const;  // periodic wrap; a particle beyond a wall throws
  void onto_lattice();       // Eq. (61): fields to the lattice points, x_ = lattice

  FluidParams prm_;
  Lattice lat_;
  CubicSplineKernel W_;
  Mat2 x_, x_star_;  // x^n, and the step's predicted positions x* (images, pairs, operators)
  Images im_;
  PairList pairs_;
  Operators op_;
  std::vector<int> outer_, inner_, slot_, diag_, outer_b_, inner_b_;  // the pattern (make_pattern)
  std::vector<double> lap_, gx_, gy_;                                 // pair coefficients
  std::unique_ptr<LinearSolver> cn_, poisson_;
  SpMat A_cn_, poisson_A_;
  bool cn_iterative_ = false;
  int pin_ = 0;  // gauge: phi is pinned to 0 at this particle, then shifted to zero mean
  std::vector<std::pair<std::string, double>> setup_;

  Mat2 u_, u_star_, u_star_old_, rhs_, grad_phi_, c_wall_, c_star_, c_sum_;
  Vec phi_, div_, b_phi_, V_, S_;
  mutable Vec p_;
  mutable long p_step_ = -1;
  double t_ = 0;
  long n_ = 0;
  double S_low_ = 1.0;
  long n_refactor_ = 0, n_reused_cn_ = 0, n_reused_poisson_ = 0, n_reinit_ = 0;

  mutable Profile prof_;
  int k_images_, k_rhs_, k_solve_cn_, k_div_, k_solve_poisson_, k_project_, k_move_, k_reinit_, k_neighbours_,
      k_assembly_, k_factor_cn_, k_factor_poisson_, k_pressure_;
};

}  // namespace sphib
