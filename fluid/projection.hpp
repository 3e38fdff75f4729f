#pragma once
// The Eulerian projection SPH fluid (EPSPH): the PMIII step of Kim & Moin on fixed particles
// (Eqs. 5-11 discretised as Eqs. 28-42). Everything that does not change in time (lattice, images,
// pairs, operator matrices, the Crank-Nicolson and Poisson factorisations) is built once in the
// constructor; step() is products and triangular solves only, with no allocation.
#include <memory>
#include <vector>

#include "fluid/boundary.hpp"
#include "fluid/kernel.hpp"
#include "fluid/lattice.hpp"
#include "fluid/linear_solver.hpp"
#include "fluid/neighbours.hpp"
#include "fluid/operators.hpp"
#include "fluid/profile.hpp"

namespace sphib {

struct FluidParams {
  Domain domain;
  int nx = 32, ny = 32;
  double h_over_dx = 1.2;  // h = h_over_dx * (dx + dy) / 2
  double rho = 1.0, mu = 1.0;
  double dt = 1e-3;
  bool convection = true;  // false: Stokes flow, the convection operator is not even assembled
  SolverKind cn_solver = SolverKind::Auto, poisson_solver = SolverKind::Auto;
};

class Fluid {
 public:
  explicit Fluid(const FluidParams& params);

  // One PMIII step from t_n to t_{n+1}; F is the external force per unit volume at the particles (N x 2).
  void step(const Mat2& F);

  void set_velocity(const Mat2& u0);  // initial condition u^0 (also taken as u^{-1} for AB2)

  const FluidParams& params() const { return prm_; }
  const Lattice& lattice() const { return lat_; }
  const Images& images() const { return im_; }
  const PairList& pairs() const { return pairs_; }
  const Operators& operators() const { return op_; }
  const CubicSplineKernel& kernel() const { return W_; }
  int size() const { return lat_.size(); }
  double h() const { return W_.h; }
  double nu() const { return prm_.mu / prm_.rho; }

  const Mat2& u() const { return u_; }      // u^{n}
  const Vec& phi() const { return phi_; }   // phi^{n}
  // p^{n-1/2} (Eq. 35), zero mean (gauge); recovered from phi only when asked for, once per step.
  const Vec& p() const;
  const Mat2& grad_phi() const { return grad_phi_; }
  double time() const { return t_; }
  long steps() const { return n_; }

  double max_abs_divergence() const;  // max_i |(div u^n)_i|, Eq. (30) with wall images
  double kinetic_energy() const;      // sum_i rho V |u_i|^2 / 2
  double poisson_residual() const;    // ||A phi - b|| / ||b|| of the last Poisson solve

  std::vector<SolverInfo> solver_info() const;
  double cn_mean_iterations() const { return cn_->mean_iterations(); }
  Profile& profile() { return prof_; }
  const Profile& profile() const { return prof_; }
  double setup_seconds(const std::string& what) const;  // "neighbours", "assembly", "factorisation"

 private:
  FluidParams prm_;
  Lattice lat_;
  CubicSplineKernel W_;
  Images im_;
  PairList pairs_;
  Operators op_;
  std::unique_ptr<LinearSolver> cn_, poisson_;
  SpMat poisson_A_;
  bool cn_iterative_ = false;
  int pin_ = 0;  // gauge: phi is pinned to 0 at this particle, then shifted to zero mean
  std::vector<std::pair<std::string, double>> setup_;

  // state and workspace (sized once)
  Mat2 u_, u_star_, u_star_old_, rhs_, conv_, conv_old_, grad_phi_, c_wall_, c_star_, c_sum_;
  Vec phi_, div_, b_phi_;
  mutable Vec p_;
  mutable long p_step_ = -1;
  double t_ = 0;
  long n_ = 0;
  bool first_ = true;

  mutable Profile prof_;  // timing only: also updated by the lazily recovered pressure
  int k_images_, k_conv_, k_rhs_, k_solve_cn_, k_div_, k_solve_poisson_, k_project_, k_pressure_;
};

}  // namespace sphib
