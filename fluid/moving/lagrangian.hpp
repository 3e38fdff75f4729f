#pragma once
// The Lagrangian projection SPH fluid (LPSPH, Section 3.1): the projection core's PMIII step
// (projection_core.hpp: Eqs. 28-35, images by Eq. 42) on particles that move with the fluid, Eq. (37)
//     x_i^{n+1} = x_i^n + dt/2 (u_i^{n+1} + u_i^n),
// wrapped into the periodic box. The convection term is carried by the particle motion and is not
// discretised. Volumes V = dx dy stay constant (incompressible: constant mass and density).
//
// What EPSPH builds once is rebuilt here at the beginning of every step: the images (Section 3.3:
// "the positions of the image particles need to be reassigned at the beginning of each time step"),
// the pairs, the operator matrices and both systems, with the moving-particle machinery ISPH shares:
//   - a Verlet list (neighbours.hpp, VerletList): images and candidate pairs within 2h + skin,
//     built by cell list when the particles have moved apart by the skin (adaptive, between 0.01
//     and 0.3 2h: see lagrangian.cpp), moved bit for bit as a fresh search in between;
//   - one pass over the candidates (particle_operators.hpp) for the six operators, the two systems
//     and the kernel sums, the pattern made again only after a build;
//   - the solvers of the one policy (solver_policy.hpp, Refactor::EveryStep): conjugate gradients
//     warm-started and preconditioned by the FFT solver of the initial lattice (where the domain
//     has one) or by a lagged CHOLMOD factor refactorised when the iterations grow, reading the
//     matrices in place. describe() and figures() say which, how many iterations per solve and
//     how often a preconditioner was factorised; a direct solver asked for (solver.* = cholmod_*)
//     is refactorised every step, its symbolic analysis kept while the pattern stays.
// Its cost against EPSPH's: bench/lpsph_comparison, docs/validation/lpsph.md.
//
// Where: the paper does not say at which positions the sums of a step are taken. We take the
// predicted positions x* = x^n + dt u^n (the idea of Cummins & Rudman's SPH projection method), so
// that the projection makes u^{n+1} divergence-free where the particles will be: x^{n+1} - x* =
// dt/2 (u^{n+1} - u^n) = O(dt^2). Taken at x^n instead, the pressure lags one step behind the
// convective acceleration, an O(dt) velocity error (docs/method/choices.md, "LPSPH: the positions of
// a step's sums").
// The operators, images, pairs and kernel sums shown below are those of the last step's x*.
//
// Optional reinitialisation (Section 5.2.1, Figs. 9 C-D): every `reinit_every` steps the particles go
// back onto the lattice, and u, phi and grad phi (Eq. 42 needs it) are interpolated there from the
// old particles and their images by normalised SPH interpolation, Eq. (61) (interpolation.hpp).
//
// Breakdown (Section 5.2.2, Fig. 18): particles driven apart leave holes in which the quadrature
// fails. At every rebuild the kernel sum S_i = sum_j V W_ij (images and i itself included; 1 on a
// lattice) of every particle is checked against params.lagrangian.min_kernel_sum; a step whose
// positions x* bring one below throws std::runtime_error naming the time t_{n+1}, the particle and
// its position, before it changes anything (the solver keeps the state of t_n; the sums come from the
// assembly's pass, and the geometry is put back at the last x* that passed). A particle beyond a
// wall throws as well.
#include <vector>

#include "fluid/moving/particle_operators.hpp"
#include "fluid/core/projection_core.hpp"

namespace sphib {

class LagrangianFluid final : public ProjectionFluid {
 public:
  // Particles on the lattice (Eq. 68), at rest; `profiler`: the run loop's (nullptr: its own).
  explicit LagrangianFluid(const FluidParams& params, Profiler* profiler = nullptr);

  // Puts the particles at x (N x 2, wrapped into the periodic box) and rebuilds there; throws like
  // step() for a particle beyond a wall or a kernel sum below the threshold. The fields stay with
  // their particles. (Tests, restarts.)
  void set_positions(const Mat2& x);
  // Figs. 9 C-D: the particles back onto the lattice, u, phi and grad phi interpolated by Eq. (61).
  void reinitialise();

  // x(): x^n
  // images(), pairs(), operators() (the core's): at x* of the last step (x^n before any step)
  double neighbours_per_particle() const;  // within 2h
  const VerletList& verlet() const { return verlet_; }
  // S_i = sum_j V W_ij at x*, images and j = i included (after a breakdown: the failing x*'s)
  const Vec& kernel_sums() const { return S_; }
  double lowest_kernel_sum() const { return S_low_; }  // over the run so far

  long refactorisations() const { return n_refactor_; }           // new matrices after the constructor's
  // of them, the solver kept its symbolic analysis (a direct solver; always for an iterative one)
  long symbolic_reused_cn() const { return n_reused_cn_; }
  long symbolic_reused_poisson() const { return n_reused_poisson_; }
  long reinitialisations() const { return n_reinit_; }

 private:
  // Its report to the profiler: the run-log lines and the figures.
  std::vector<std::string> describe() const;
  std::vector<std::pair<std::string, double>> figures() const;
  struct RebuildSeconds { double neighbours = 0, assembly = 0, factorisation_cn = 0, factorisation_poisson = 0; };
  // Rebuilds at x* = x^n + dt u^n (a breakdown throws here, the state unchanged), then the u^n half of
  // Eq. (37).
  void begin_step() override;
  void end_step() override;  // the u^{n+1} half of Eq. (37); reinitialisation when due
  void extra_state(NamedArrays& st) const override;  // positions and counters
  void restore_extra(const NamedArrays& st) override;
  // Images, pairs, kernel sums (breakdown at time t), operators, factorisations at x_star_.
  // ahead: also the step's first products behind the assembly (products_ahead)
  RebuildSeconds rebuild(double t, bool jump = false, bool ahead = false);  // jump: the positions did not move by a step
  void check_kernel_sums(double t);
  bool geometry(bool jump, bool sums, RebuildSeconds* s, bool ahead = false);
  void products_ahead(int i0, int i1);  // rows [i0, i1)
  void pairs_current() const override;  // pairs_'s rx, ry, r at x_star_ (the moves leave them)
  int neighbours_within(int i) const;  // of particle i, closer than 2h
  void wrap_into_domain(Mat2& x, double t) const;  // periodic wrap; a particle beyond a wall throws
  void onto_lattice();       // Eq. (61): fields to the lattice points, x_ = lattice

  Mat2 x_star_;  // the step's predicted positions x* (images, pairs, operators); x^n is the base's x_
  VerletList verlet_;
  ParticleOperators assembly_;
  SpMat A_cn_, A_phi_;  // the two systems of the step (Eqs. 28, 32), kept: values only while the pattern stays
  Mat2 cn_x0_, cn_ax0_;  // products_ahead's: the Crank-Nicolson start and A_cn times it
  Vec phi_x0_, phi_ax0_;  // phi^n (the Poisson start) and A_phi phi^n
  std::vector<double> x4_;  // u^n and the Crank-Nicolson start interleaved, 4 per particle
  mutable bool pairs_stale_ = false;  // pairs_'s rx, ry, r lag behind x_star_ (pairs_current)
  Mat2 x_star_good_;  // the last x* whose kernel sums passed (a breakdown puts the geometry back there)
  Vec S_;
  double S_low_ = 1.0;
  long n_refactor_ = 0, n_reused_cn_ = 0, n_reused_poisson_ = 0, n_reinit_ = 0;
  MovingPhases k_;
  int k_reinit_;
};

}  // namespace sphib
