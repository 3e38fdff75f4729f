#pragma once
// The Eulerian projection SPH fluid (EPSPH): the PMIII step of Kim & Moin on fixed particles
// (Eqs. 5-11 discretised as Eqs. 28-42). Everything that does not change in time (lattice, images,
// pairs, operator matrices, the Crank-Nicolson and Poisson factorisations) is built once in the
// constructor; step() is products and triangular solves only, with no allocation.
#include <memory>
#include <vector>

#include "fluid/boundary.hpp"
#include "fluid/fft_poisson.hpp"
#include "fluid/gauge.hpp"
#include "fluid/kernel.hpp"
#include "fluid/lattice.hpp"
#include "fluid/linear_solver.hpp"
#include "fluid/neighbours.hpp"
#include "fluid/operators.hpp"
#include "fluid/products.hpp"
#include "fluid/profile.hpp"
#include "fluid/solver.hpp"

namespace sphib {

class Fluid final : public FluidSolver {
 public:
  explicit Fluid(const FluidParams& params);

  // One PMIII step from t_n to t_{n+1}; F is the external force per unit volume at the particles (N x 2).
  void step(const Mat2& F) override;

  void set_velocity(const Mat2& u0) override;  // initial condition u^0 (also taken as u^{-1} for AB2)

  const FluidParams& params() const override { return prm_; }
  const Lattice& lattice() const override { return lat_; }
  const Images& images() const { return im_; }
  const PairList& pairs() const { return pairs_; }
  const Operators& operators() const { return op_; }
  const CubicSplineKernel& kernel() const override { return W_; }
  bool particles_move() const override { return false; }
  const Mat2& x() const override { return lat_.x; }
  const Vec& volumes() const override { return V_; }

  const Mat2& u() const override { return u_; }      // u^{n}
  const Vec& phi() const override;  // phi^{n} (exact projection: solved when first asked for)
  // p^{n-1/2} (Eq. 35), zero mean (gauge); recovered from phi only when asked for, once per step.
  const Vec& p() const override;
  const Mat2& grad_phi() const { return grad_phi_; }
  double time() const override { return t_; }
  long steps() const override { return n_; }

  // max_i |(D u^n)_i| with the divergence the projection makes zero: D = -G^T (exact projection;
  // differs from Eq. (30) with no-slip images only in the rows within 2h of a wall), or Eq. (30)
  // with the no-slip images of u^n (approximate projection).
  double max_abs_divergence() const override;
  double kinetic_energy() const override;      // sum_i rho V |u_i|^2 / 2
  double poisson_residual() const;             // ||A phi - b|| / ||b|| of the last Poisson solve
  // The stream function the markers follow (computed on the first call after a step): psi_m with
  // -lap psi_m = C^T u (the Morris Laplacian of Eq. 31 with odd images: psi_m constant along each
  // wall, 0 on the bottom or left wall and the flux on the other; C^T u = Gy^T u - Gx^T v, the
  // discrete vorticity). Its curl is divergence-free and, like Eq. (63), smooths u at the scale h;
  // the least-squares psi of the exact projection (u = its curl exactly) would instead give the
  // markers the grid-scale velocity unsmoothed, amplified by 1/|G| near the gradient's null modes
  // (measured: a membrane with narrow spreading, h* = h/2, blows up within 20 steps).
  StreamFunction stream_function() const override;
  bool has_stream_function() const override { return true; }

  std::vector<SolverInfo> solver_info() const;
  double cn_mean_iterations() const { return cn_->mean_iterations(); }
  std::vector<std::string> describe() const override;
  std::vector<std::pair<std::string, double>> figures() const override;
  Profile& profile() const override { return prof_; }
  double setup_seconds(const std::string& what) const override;  // "neighbours", "assembly", "factorisation"
  std::optional<Footprint> footprint() const override;
  NamedArrays state() const override;
  // The floor of a step: the bare kernels it cannot avoid (the Crank-Nicolson and Poisson solves
  // and the fused sparse products, on the current fields), each timed alone, best of `reps`.
  double floor_seconds(int reps = 20) const override;
  void restore(const NamedArrays& state) override;

 private:
  FluidParams prm_;
  Lattice lat_;
  CubicSplineKernel W_;
  Images im_;
  PairList pairs_;
  Operators op_;
  RowStencil vel_st_, phi_st_;  // the lattice rows of the velocity and phi operator patterns
  std::vector<int> lap_b_rows_, gx_b_rows_, gy_b_rows_;  // rows of the image operators' B with entries
  Mat2 conv_wall_x_, conv_wall_y_, lap_wall_;  // B c_wall of grad_ux, grad_uy, lap_u: constant
  std::unique_ptr<LinearSolver> cn_;
  mutable std::unique_ptr<LinearSolver> poisson_;  // exact projection: made when phi is first asked for
  bool cn_iterative_ = false;
  mutable bool poisson_fft_ = false;  // the FFT solver of the unpinned operator (no pin in the right-hand side)
  Gauge gauge_;      // of the Poisson operator in use (fluid/gauge.hpp)
  Gauge gauge_phi_;  // exact projection: of phi~'s Morris Laplacian (the constants)
  // Exact projection: the divergence D = -G^T (Dx, Dy, one pattern, their stencil), the velocity
  // modes it does not see, phi made on demand (phi_step_: the step it belongs to).
  SpMat div_x_, div_y_;
  RowStencil div_st_;
  VelocityModes vmodes_;
  mutable long phi_step_ = 0;
  Mat2 grad_psi_;
  void project_exact();
  void project_approximate();
  void curl_transpose(const Mat2& u) const;  // cu_ = C^T u, Q_ = the least-squares flux of u
  void psi_rhs() const;  // b_psi_ = cu_ - Q_ (flux term), projected
  void exact_divergence(const Mat2& u, Vec& d) const;  // D u with the normal offsets
  // The stream function (stream_function()): its normal equations' solver, the transposed
  // velocity gradients (Gy^T, -Gx^T) that make their right-hand side, and the wall term per unit flux.
  mutable std::unique_ptr<LinearSolver> psi_solver_;
  mutable Gauge psi_gauge_;
  mutable bool psi_fft_ = false;
  mutable SpMat psi_ty_, psi_tx_;
  mutable RowStencil psi_st_;
  mutable Vec psi_, psi_flux_, b_psi_, psi_by1_, psi_bx1_;
  // the markers' psi_m (stream_function()): its solver, the wall term per unit flux, C^T u and Q of
  // the last step (exact projection: of u*, equal to u^{n+1}'s up to round-off)
  mutable std::unique_ptr<LinearSolver> mpsi_solver_;
  mutable Gauge mpsi_gauge_;
  mutable bool mpsi_fft_ = false;
  mutable Vec psi_m_, mpsi_flux_, cu_, b_m_;
  mutable double Q_ = 0, mpsi_scale_ = 1;
  mutable long cu_revision_ = -1;
  mutable Mat2 psi_r1_;  // the least-squares flux Q = sum u . psi_r1_ (make_psi_solver)
  mutable Eigen::Vector2d psi_mean_ = Eigen::Vector2d::Zero();
  mutable long psi_revision_ = -1;
  void make_psi_solver() const;
  // The Poisson solver of operator A, singular with the null space of gauge g: FFT (periodic x,
  // walls y) when kind allows and A has the structure, else CHOLMOD on A pinned by g.
  std::unique_ptr<LinearSolver> poisson_solver(const std::string& system, const SpMat& A, const Gauge& g,
                                               SolverKind kind, bool* fft) const;
  std::vector<std::pair<std::string, double>> setup_;

  // state and workspace (sized once)
  Mat2 u_, u_star_, u_star_old_, du_dx_, du_dy_, rhs_, conv_, conv_old_, grad_phi_, c_wall_, c_star_;
  mutable Vec phi_, b_phi_;
  Vec div_, V_;
  mutable Vec p_;
  mutable long p_step_ = -1;
  double t_ = 0;
  long n_ = 0;
  bool first_ = true;

  mutable Profile prof_;  // timing only: also updated by the lazily recovered pressure
  int k_images_, k_conv_, k_rhs_, k_solve_cn_, k_div_, k_solve_poisson_, k_project_, k_pressure_, k_psi_;
};

}  // namespace sphib
