#pragma once
// Stream functions on the fixed lattice (EPSPH): the exact projection and the markers' stream function.
//
// The exact projection (fluid.projection = "exact"). u^{n+1} is the orthogonal projection of u*
// onto the kernel of the discrete divergence D = -G^T (even images: tangential part even, normal
// part odd). Its kernel is spanned by the curls C psi = (Gy psi, -Gx psi) of stream functions with
// odd images (psi constant along each wall; D of such a curl is 0 identically), the uniform flux of
// a channel, and the alternating velocity modes G does not see (fluid/algebra/gauge.hpp). So the projection
// is made through psi: the least-squares psi of u* (normal equations C^T C psi = C^T u*, i.e. G^T G
// with odd images), u^{n+1} = its curl plus u*'s components along those modes, and
// G phi = rho/dt (u* - u^{n+1}) (Eq. 34 read backwards). D u^{n+1} = 0 to solver precision. An
// orthogonal projection cannot amplify anything, however small the eigenvalues of G^T G near its
// grid-scale null modes. (With the no-slip divergence of Eq. (30), tangential images odd, the
// projection would be oblique and, with those tiny eigenvalues, unstable: measured on Poiseuille at
// h = 3 dx. The two divergences differ only within 2h of a wall.)
//
// Flow through the sides (an inflow and an outflow between walls): psi's images carry prescribed
// values c (image_stream_offsets, fluid/common/boundary.hpp: psi = int_0^s u_in along the inflow,
// constant on each wall, the two constants differing by the inflow's flux; even images, dpsi/dn = 0,
// on the outflow), and the flux term above with Q = 1 is that of c: u^{n+1} = C psi + b,
// b = (By c, -Bx c), psi the least-squares solution of C^T C psi = C^T (u* - b). The curl of the
// extended psi is divergence-free on the extended lattice, so D u^{n+1} = D b, the inflow's source
// (nonzero only next to the inflow); velocity_divergence reports D u - D b.
//
// The markers' stream function psi_m (stream_function(), either projection): -lap psi_m = C^T u / m,
// lap the Morris Laplacian of Eq. (31) with the velocity's images (psi_m constant along each wall, 0
// on the bottom or left wall and the flux on the other; with flow through the sides the values c), C^T u = Gy^T u - Gx^T v the discrete vorticity, m
// the lattice normalisation of G. Its curl is divergence-free and, like Eq. (63), smooths u at the
// scale h; the least-squares psi (u = its curl exactly) would instead give the markers the
// grid-scale velocity unsmoothed, amplified by 1/|G| near the gradient's null modes (measured: a
// membrane with narrow spreading, h* = h/2, blows up within 20 steps).
#include <memory>

#include "fluid/eulerian/fused_passes.hpp"
#include "fluid/algebra/gauge.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/algebra/linear_solver.hpp"
#include "fluid/common/neighbours.hpp"
#include "fluid/algebra/operators.hpp"
#include "fluid/algebra/products.hpp"
#include "fluid/core/solver.hpp"

namespace sphib {

class ExactProjection {
 public:
  // The lattice method's geometry (kept by reference: it outlives this), the lattice normalisation
  // m of its gradient (gradient_normalisation) and the Poisson solver kind. `projection`: the exact
  // projection is in use (else only the markers' stream function is). `compact` (EPSPH's compact
  // storage, eulerian.hpp; with `projection`): op's velocity operators hold only their stencil's
  // rows (vel_st's: stencil_rows_only), the divergence and the transposed gradients keep only their
  // stencils' rows, and the solvers are made by make_solvers(), which the owner calls after freeing
  // what it no longer needs.
  // `div` (with `projection`): the divergence made beforehand by make_divergence from the phi
  // gradients, taken over (they may then be freed before this is made); else it is made from op's.
  struct Divergence {
    SpMat x, y;  // Dx, Dy (D = -G^T), one pattern
    RowStencil st;
  };
  ExactProjection(const Lattice& lat, const Images& im, const Operators& op, double m, const RowStencil* vel_st,
                  SolverKind kind, bool projection, bool compact = false, Divergence* div = nullptr);
  // D = -G^T from the phi gradients (Gx, Gy: grad_phix, grad_phiy) and its stencil; `compact`: only
  // the stencil's rows kept (stencil_rows_only)
  static Divergence make_divergence(const SpMat& grad_phix, const SpMat& grad_phiy, bool compact);
  // The same, compact, from the phi gradients kept compact by their stencil `st` (stencil_rows_only):
  // the transposes a block of rows at a time, never whole (the same stencil and kept rows)
  static Divergence divergence_by_blocks(const SpMat& grad_phix, const SpMat& grad_phiy, const RowStencil& st);
  // The lattice normalisation of the SPH gradient, G x = m (m - 1 = -9.2e-3 at h = 1.2 dx, 3.0e-3 at
  // 1.525 dx, -2.2e-4 at 2.2 dx: tests/test_fluid.cpp), from an interior particle's pairs.
  static double gradient_normalisation(const Lattice& lat, const PairList& pairs, const CubicSplineKernel& W);
  static double gradient_normalisation(const LatticePairs& pairs, const CubicSplineKernel& W);  // (the same)
  void make_solvers();  // the normal equations' and the markers' (a compact constructor's are deferred)
  // The markers' solver alone (make_solvers makes it too if not made yet).
  void make_markers_solver();

  // The exact projection of u*, in three parts (timed apart by the caller):
  // C^T u* and the flux Q of u*: the normal equations' right-hand side (the fluid at `revision`)
  void rhs(const Mat2& u_star, long revision);
  void solve();                  // the least-squares psi
  // u^{n+1} = C psi + Q b1 + u*'s alternating modes (and mean); G phi^{n+1} = rho/dt (u* - u^{n+1}).
  void velocity(const Mat2& u_star, double dt_over_rho, Mat2& u, Mat2& grad_phi);
  // D f with the divergence the exact projection makes zero (D = -G^T, even images).
  void divergence(const Mat2& f, Vec& d) const;
  // The divergence of a velocity u the projection made: D u, and with flow through the sides D u
  // minus the inflow's source D b (b = (By c, -Bx c), the velocity of psi's prescribed image parts
  // alone): D b = -Dx's image part of the inflow's normal velocity as psi prescribes it (2 Gy psi_in
  // on the images), nonzero only near the inflow; D u - D b = D (C psi) = 0.
  void velocity_divergence(const Mat2& u, Vec& d) const;
  // The markers' psi_m of u (solved when u's revision differs from the last one's).
  StreamFunction markers(const Mat2& u, long revision);
  double normal_equations_residual(const Mat2& u_star);  // ||C^T C psi - C^T u*|| / ||C^T u*||
  // The bare kernels of one exact projection (C^T u*, the psi solve, its curl), each timed alone,
  // best of `reps` (the fluid step's floor).
  double floor_seconds(const Mat2& u_star, Mat2& work, int reps) const;
  // The markers' psi_m solve alone, best of `reps` (after markers()).
  double markers_floor_seconds(int reps) const;
  bool has_psi_solver() const { return psi_solver_ != nullptr; }
  const LinearSolver& psi_solver() const { return *psi_solver_; }
  int divergence_stencil_rows() const { return div_st_.stencil_rows(); }
  // Checkpoints: C^T u* and its flux of the last step (the markers' stream function of u^{n+1}).
  void save(NamedArrays& st) const;
  void load(const NamedArrays& st, long revision);

 private:
  void make_psi_solver();
  static void finish_divergence(Divergence& d, bool compact);  // D = -(the transposes), its stencil
  void curl_transpose(const Mat2& u);  // cu_ = C^T u, Q_ = the least-squares flux of u
  void psi_rhs();                      // b_psi_ = cu_ - Q_ (flux term), projected
  double flux(const Mat2& u) const;    // Q of u: the channel's least-squares flux, 1 with open sides, else 0

  const Lattice& lat_;
  const Images& im_;
  const Operators& op_;
  const RowStencil* vel_st_;
  SolverKind kind_;
  bool projection_, compact_;
  // the divergence D = -G^T (Dx, Dy, one pattern, their stencil), the velocity modes it does not see
  SpMat div_x_, div_y_;
  RowStencil div_st_;
  VelocityModes vmodes_;
  std::vector<unsigned char> parity_;  // 2 (i_y & 1) + (i_x & 1): the modes' parity class of each particle
  ImageRows vel_images_;               // the velocity pattern's blocks with image terms (Gx, Gy)
  // the least-squares psi: its normal equations' solver, the transposed velocity gradients (Gy^T,
  // -Gx^T) that make their right-hand side, the wall term per unit flux, the flux's direction
  std::unique_ptr<LinearSolver> psi_solver_;
  Gauge psi_gauge_;
  bool psi_unpinned_ = false;
  SpMat psi_ty_, psi_tx_;
  RowStencil psi_st_;
  Vec psi_, psi_flux_, b_psi_, psi_by1_, psi_bx1_;
  Mat2 psi_r1_;  // the least-squares flux Q = sum u . psi_r1_ (make_psi_solver)
  Vec div_source_;  // flow through the sides: D b, the inflow's source in D u (velocity_divergence)
  double Q_ = 0;
  Eigen::Vector2d mean_ = Eigen::Vector2d::Zero();  // the uniform flow of a doubly periodic box
  // the markers' psi_m: its solver, the wall term per unit flux, C^T u and Q of the last state (exact
  // projection: of u*, equal to u^{n+1}'s up to round-off)
  std::unique_ptr<LinearSolver> mpsi_solver_;
  Gauge mpsi_gauge_;
  bool mpsi_unpinned_ = false;
  Vec psi_m_, mpsi_flux_, cu_, b_m_;
  double mpsi_scale_ = 1;
  long cu_revision_ = -1, psi_revision_ = -1;
  long bm_revision_ = -1;  // the state whose b_m_ rhs() made (where psi_m's right-hand side is one pass)
  bool markers_in_one_pass() const;
};

}  // namespace sphib
