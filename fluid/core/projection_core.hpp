#pragma once
// The projection core: ONE PMIII step of Kim & Moin (Eqs. 5-11 discretised as Eqs. 28-42), shared
// by every projection method. A method derives from ProjectionFluid, provides the step's geometry
// (particles, images, pairs, operators, the two solvers) and adds only what differs:
//   EPSPH (eulerian.hpp):   fixed lattice, everything built once; convection (Eqs. 39-41); the
//                           exact projection (exact_projection.hpp) besides the paper's;
//   LPSPH (lagrangian.hpp): moving particles, geometry rebuilt at x* every step, Eq. (37);
//   ISPH (isph.hpp):        moving particles filling part of a tank, Morris wall particles, the
//                           explicit viscous predictor of Afanasiev et al. Eq. (22) (explicit_viscous_),
//                           gravity (accel_), Dirichlet rows p = 0 at a free surface.
//
// One step (step(), in order):
//   begin_step()                      the method's geometry for this step (LPSPH: rebuild at x*)
//   images: c* by Eq. (42)            image offsets of u*: 2 (u_b + dt/rho [grad phi^n]_tau)
//   convection()                      EPSPH: N^{n+1/2} by AB2 (Eq. 39); others carry it by motion
//   viscous predictor, Eq. (28):      (I - a lap) u* = u^n + a lap u^n + a B (c^n + c*)
//                                                      - dt N^{n+1/2} + dt F^n / rho + dt g,  a = nu dt / 2
//     or explicitly (explicit_viscous_, Afanasiev et al. Eq. 22):
//                                     u* = u^n + nu dt (lap u^n + B c^n) + dt F^n / rho + dt g
//     (g: accel_, a uniform acceleration the method applies itself, ISPH's gravity; zero otherwise)
//   project()                         approximate by default (Eqs. 30-34); EPSPH: exact if chosen
//   t += dt; n += 1; end_step()       the method's motion (Eq. 37) and reinitialisation
//
// The approximate projection: -lap phi = -(rho/dt) div u* (Eqs. 30-32) with the gauge of the
// singular operator (fluid/algebra/gauge.hpp: right-hand side onto the range, pinned for a factorisation,
// phi shifted to zero mean) or, for a method with Dirichlet rows, b = 0 on those rows and no gauge;
// u^{n+1} = u* - dt/rho grad phi (Eq. 34). The pressure (Eq. 35) is recovered only when asked for
// (after the explicit predictor p = phi: Afanasiev et al. Eqs. 23-24 solve for p^{n+1} itself).
// Dirichlet rows are eliminated from the Poisson matrix symmetrically by the method
// (eliminate_dirichlet: zero rows and columns, 1 on the diagonal), so that it stays symmetric.
//
// The products go through fluid/algebra/products.hpp (one pass per sparsity pattern; on a lattice the rows
// that are translates of one row as a stencil): every operator of a step must share one pattern
// per image rule, as build_operators and LPSPH's assembly make them.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "fluid/common/boundary.hpp"
#include "fluid/common/free_surface.hpp"
#include "fluid/algebra/gauge.hpp"
#include "kernels/cubic_spline.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/algebra/linear_solver.hpp"
#include "fluid/common/loads.hpp"
#include "fluid/common/neighbours.hpp"
#include "fluid/algebra/operators.hpp"
#include "fluid/algebra/products.hpp"
#include "fluid/common/profile.hpp"
#include "fluid/core/solver.hpp"

namespace sphib {

class ProjectionFluid : public FluidSolver {
 public:
  void step(const Mat2& F) final;
  void set_velocity(const Mat2& u0) override;  // u^0 (also u^{-1} for AB2 and the warm start of u*)

  const Vec& phi() const override { return phi_; }  // phi^n
  // p^{n-1/2} by Eq. (35) from phi() with the Laplacian of the step that made it, zero mean where
  // phi has a gauge; recovered when first asked for after a change of the state (revision()).
  const Vec& p() const final;
  const Mat2& grad_phi() const { return grad_phi_; }
  // max_i |(div u^n)_i| by Eq. (30) with the wall images of u^n (EPSPH's exact projection: its D)
  double max_abs_divergence() const override;

  const Images& images() const { return im_; }        // of the last step's positions
  const PairList& pairs() const {
    pairs_current();
    return pairs_;
  }
  // (lap_phi made first where the method keeps it in A_phi; EPSPH's compact storage: the whole
  // matrices assembled again, eulerian.hpp)
  virtual const Operators& operators() const;
  virtual std::vector<SolverInfo> solver_info() const;

  // The state after step n: u^n, phi^n, grad phi^n (Eq. 42 needs it), the last two u* (the warm
  // start of an iterative solver), t_n, n, and what the method adds (extra_state).
  NamedArrays state() const final;
  void restore(const NamedArrays& state) final;

 protected:
  // The lattice's particles (Eq. 68), fixed or moving; `profiler` the run loop's (FluidSolver).
  ProjectionFluid(const FluidParams& params, bool particles_move, Profiler* profiler);
  // N particles of volume V each (a fluid region filling part of the lattice's domain: ISPH).
  ProjectionFluid(const FluidParams& params, bool particles_move, Profiler* profiler, int N, double V);

  // The profile phases of the moving-particle methods (LPSPH, ISPH): the labels of the first three
  // are the method's (its equations); the two factorisation phases are named alike for both.
  struct MovingPhases {
    int move, neighbours, assembly, factor_cn, factor_poisson;
  };
  MovingPhases moving_phases(const char* move, const char* neighbours, const char* assembly);

  // --- what a method provides -------------------------------------------------------------------
  virtual void begin_step() {}  // the step's geometry (may throw a breakdown before anything changes)
  virtual void convection() {}  // fills conv_ (N^{n+1/2}); the rhs subtracts it when convective_
  // Eq. (28)'s right-hand side into rhs_ (EPSPH: one pass with the convection, fluid/eulerian/fused_passes.hpp);
  // with explicit_viscous_ the method's override puts u* itself into u_star_ (ISPH: Afanasiev et al.
  // Eq. 22) and there is no Crank-Nicolson solve.
  virtual void viscous_rhs(const Mat2& F);
  virtual void project() { project_approximate(); }
  // The solver of Eq. (28)'s matrix this step: cn_, or (EPSPH with a variable viscosity) the CG on
  // the variable matrix (fluid/eulerian/variable_viscosity.hpp).
  virtual LinearSolver& predictor_solver() { return *cn_; }
  virtual void end_step() {}    // after t and n have advanced
  virtual void extra_state(NamedArrays&) const {}
  virtual void restore_extra(const NamedArrays&) {}  // (after the core's part: t_ and n_ are set)
  // The offsets c of the neighbours that are not particles (f_j = sign_j f_parent + c_j: operators.hpp)
  // for the velocity: by default the images' of Eq. (42), 2 (u_b + dt/rho [grad phi]_tau) (without the
  // tangential term when grad_phi is null).
  virtual void velocity_offsets(const Mat2* grad_phi, Mat2& c) const;

  // --- the parts of the step ------------------------------------------------------------------
  // After the method (re)built im_, pairs_ and op_: the rows of the image operators, the wall part
  // of Eq. (42) (c^n = 2 u_b) and its Laplacian term, and the products' stencils (optional).
  void operators_changed(const RowStencil* vel_st = nullptr, const RowStencil* phi_st = nullptr);
  // After new values of the operators in the same patterns (moving particles between list builds):
  // the wall part B c^n of the Laplacian again (zero for walls at rest).
  void operator_values_changed();
  void add_acceleration(Mat2& v) const;  // v += dt accel_ (a no-op for a zero accel_)
  void image_offsets();        // Eq. (42): c* of u*
  void viscous_predictor(const Mat2& F);  // Eq. (28) and the Crank-Nicolson solve
  void project_approximate();  // Eqs. (30)-(34)
  // Eq. (30) with images whose offsets are c: d = D u + B c
  void divergence_with_images(const Mat2& u, const Mat2& c, Vec& d) const;
  mutable Mat2 split_div_;  // its image values with the components' own parities (Images::split)
  void add_setup(const std::string& what, double seconds) { profiler().add_setup(what, seconds); }
  double a_cn() const { return 0.5 * nu() * prm_.dt; }  // Crank-Nicolson factor nu dt / 2 (Eq. 28)
  SpMat crank_nicolson_matrix() const;  // I - a lap (Eq. 28), the pattern of lap_u.A
  SpMat crank_nicolson_matrix(const SpMat& lap) const;  // I - a lap for the given lap
  // A with the rows and columns of dirichlet_rows_ zeroed and 1 on their diagonal (in place, the
  // pattern kept): symmetric when A is, and with b = 0 on those rows phi = 0 there.
  void eliminate_dirichlet(SpMat& A);

  double volume_;  // of every particle (V_)
  // the step's geometry (the method builds it; operators_changed() derives the rest)
  Images im_;
  mutable PairList pairs_;  // mutable: a method may bring its rx, ry, r up to date when asked (pairs_current)
  virtual void pairs_current() const {}  // LPSPH: its Verlet moves leave pairs_'s rx, ry, r
  mutable Operators op_;  // mutable: the phi operators made when asked for (phi_ops_from_)
  // A method whose assembly writes the phi operators only in the rows with images
  // (ProjectionSystems::phi_rows: LPSPH) points this to its A_phi = -lap_phi and sets phi_ops_stale_
  // after each assembly: the projection's gradient then takes grad_ux.A, grad_uy.A in the other rows
  // (the same values there), and operators() and p() fill lap_phi = -A_phi and those rows of
  // grad_phix, grad_phiy (the same bits) when first asked for.
  const SpMat* phi_ops_from_ = nullptr;
  mutable bool phi_ops_stale_ = false;
  const RowStencil* vel_st_ = nullptr;  // stencils of the velocity / phi patterns (EPSPH)
  const RowStencil* phi_st_ = nullptr;
  const RowStencil* lap_phi_st_ = nullptr;  // lap_phi's own (EPSPH's compact storage): p() by stencil
  std::vector<int> lap_b_rows_, gx_b_rows_, gy_b_rows_;  // rows of the image operators' B with entries
  Mat2 c_wall_, c_star_, lap_wall_;  // c^n = 2 u_b, c*, and B c^n of the Laplacian (constant per geometry)
  // the solvers of the step: Crank-Nicolson, and the approximate projection's Poisson with its gauge
  // (EPSPH's exact projection makes the Poisson solver only when phi is first asked for: mutable)
  std::unique_ptr<LinearSolver> cn_;
  // the y component's Crank-Nicolson solver where the components' image parities differ
  // (Images::split: a free-slip side), cn_ then the x component's; else null (one solver for both)
  std::unique_ptr<LinearSolver> cn_v_;
  mutable std::unique_ptr<LinearSolver> poisson_;
  Gauge gauge_;
  mutable bool poisson_unpinned_ = false;  // the Poisson solver takes the singular operator (FFT): no pin
  std::vector<int> dirichlet_rows_;      // Poisson rows replaced by phi_i = 0 (a free surface)
  bool explicit_viscous_ = false;        // Afanasiev et al. Eq. (22) instead of Crank-Nicolson (no cn_)
  Eigen::Vector2d accel_ = Eigen::Vector2d::Zero();  // uniform acceleration added to u* (ISPH: gravity)
  // state and workspace
  Mat2 u_star_, u_star_old_, rhs_, conv_, grad_phi_;
  Vec div_;
  mutable Vec phi_, b_phi_;
  bool first_ = true;  // no N^{n-1} yet (AB2 starts with Euler)
  bool convective_ = false;  // the method discretises convection (EPSPH); moving particles carry it
  // rhs_ already holds lap_u.A u^n, apply2's bits, for this step's viscous_rhs (LPSPH computes it
  // behind the assembly); viscous_rhs clears it
  bool lap_u_ahead_ = false;

  Profiler& prof_;  // profiler(): the run loop's
  int k_images_, k_rhs_, k_solve_cn_, k_div_, k_solve_poisson_, k_project_, k_pressure_;

 private:
  std::vector<char> dirichlet_mask_;  // eliminate_dirichlet's workspace
  mutable Vec p_;
  mutable long p_revision_ = -1;  // the state p_ belongs to
};

}  // namespace sphib
