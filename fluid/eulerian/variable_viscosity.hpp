#pragma once
// A viscosity that varies in space on the fixed lattice (EPSPH): mu_i = mu m_i, m = 1 outside the
// region where it differs (a viscosity contrast: coupling/viscosity_contrast.hpp sets m from the
// membranes). The momentum equation with a variable viscosity,
//   rho Du/Dt = -grad p + div(mu (grad u + grad u^T)) + F,                                   (1)
// is, with div u = 0 (d_j (mu d_i u_j) = (d_i u_j)(d_j mu) + mu d_i div u),
//   rho Du/Dt = -grad p + div(mu grad u) + (grad u)^T grad mu + F.                          (2)
// The viscous term is split as mu (L + V_m): L the constant Morris Laplacian of the fluid (Eqs. 28,
// 31, images by Eq. 42) and V_m what m != 1 adds, a sum over the fixed pairs (neighbours.hpp) of
// blocks on u_ij = u_i - u_j, nonzero only for pairs that see an m != 1:
//   (V_m u)_i = sum_j 2 V F_ij (m_ij - 1) K_ij u_ij,   m_ij = 2 m_i m_j / (m_i + m_j),
// the pair viscosity the harmonic mean (Cleary & Monaghan, J. Comput. Phys. 148:227, 1999, for a
// discontinuous coefficient; Morris, Fox & Zhu, J. Comput. Phys. 136:214, 1997, Eq. 10 for the
// pair form), an image taking its parent's m, and
//   m_ij >= 1: K_ij = beta(e_ij) e_ij e_ij^T, the central-force form of the whole stress (1):
//     sum_j 2 V F_ij w_ij beta (u_ij . e_ij) e_ij ~ div(w (grad u + grad u^T + I div u)) for a smooth
//     w (Espanol & Revenga, Phys. Rev. E 67:026705, 2003, Eq. 40 with a pair coefficient; Monaghan,
//     Rep. Prog. Phys. 68:1703, 2005, Section 6), i.e. div(w (grad u + grad u^T)) for div u = 0. Its
//     fourth moments must be isotropic, which the lattice's are not at h ~ dx (xxxx/xxyy = 3.98 at
//     h = 1.2 dx, 3 when isotropic): beta(e) = gamma (1 + kappa (e_x^4 + e_y^4)), with kappa and
//     gamma from the lattice's own sums so that sum_j 2 V F beta (u_ij . e) e ~ s2 (lap u + 2 grad div u),
//     s2 the Morris Laplacian's own scale (its second moment), > 0 for h >= 0.8 dx. Each block is
//     positive semi-definite, so L + V_m is negative semi-definite for every m >= 1: Crank-Nicolson
//     is stable for any lambda >= 1 (with the gradient form below for m > 1 it is not: explicit,
//     it blows up beyond nu (lambda - 1) dt / dx^2 ~ 2; implicit, L + V_m has positive eigenvalues).
//     Image pairs keep the form below (membranes stay 2h from walls: m = 1 there).
//   m_ij < 1: K_ij = I, the Morris form of div((m - 1) grad u), and the cross term (grad u)^T grad m_-,
//     m_- = min(m, 1), explicit: row-local products of the difference-form gradients
//     (grad f)_i = sum_j V (f_j - f_i) (x_i - x_j) F_ij (u with the images of u^n, m with its parent's
//     value at an image; zero where m_- is uniform). Explicit it is stable while
//     nu (1 - m) dt / dx^2 is below about 2 (m < 1: below nu dt / dx^2); the central-force form
//     would not be definite there (1 + (m - 1) beta < 0 along e for m < 3/4).
// In time (the projection core's Eq. 28, a = nu dt / 2, nu = mu / rho):
//   (I - a (L + V_m)) u* = (rest of Eq. 28) + a V_m (u^n; c^n + c*) - a V_m (dt/rho) grad phi^n
//                          + nu dt (3/2 T^n - 1/2 T^{n-1}),   T = (grad u)^T grad m_-:
// Crank-Nicolson on V_m with m^n, Adams-Bashforth (as the convection, Eq. 39) on T (the first step:
// Euler). The term in phi^n: the projection (u^{n+1} = u* - dt/rho grad phi) leaves the
// Crank-Nicolson equation for u^{n+1} intact only when (I - a (L + V_m)) commutes with grad, as
// I - a L does on the lattice (Kim & Moin's PMIII needs no pressure in the predictor for that
// reason); the rest, a V_m (dt/rho) grad phi^{n+1}, is an O(dt^2) error per step (first order in time,
// largest where the pressure jumps across a membrane), which the term with the last step's phi^n
// cancels to O(dt^3). Measured (tests/test_viscosity_contrast.cpp): second order in dt for a fixed m.
// The matrix C_m = I - a (L + V_m) (2N unknowns: V_m couples u and v) is solved by conjugate gradients
// preconditioned by the solver of the constant matrix C = I - a L (the fluid's Crank-Nicolson
// solver, borrowed: FFT on the lattice, one per component).
//
// Only what differs from the constant operator is touched: the rows whose pairs see an m != 1
// (rows()), their pair weights updated when m changes (the rows near the particles whose m
// changed); the constant part of the right-hand side is the fluid's own (fused_passes.hpp). With
// every m = 1 nothing differs: the constant-viscosity step, bit for bit.
#include <memory>
#include <vector>

#include "fluid/common/boundary.hpp"
#include "kernels/cubic_spline.hpp"
#include "fluid/algebra/linear_solver.hpp"
#include "fluid/common/neighbours.hpp"
#include "fluid/algebra/products.hpp"
#include "fluid/core/solver.hpp"

namespace sphib {

struct VariableViscosityParams {
  double a = 0.0;       // nu dt / 2 of Eq. (28)
  double rtol = 1e-8;   // CG: |r| <= rtol |b| (or a backward error of 1e-14)
  int max_iter = 500;
  // false: the Morris form and the explicit cross term for m > 1 too (for comparison only: it blows
  // up beyond nu (lambda - 1) dt / dx^2 ~ 2)
  bool central = true;
};

class VariableViscosity {
 public:
  // The fixed lattice's pairs P and images im (N particles of volume V, kernel W), the constant
  // Crank-Nicolson matrix C0 = I - a L and its solver, the preconditioner (borrowed: it must outlive
  // this object).
  VariableViscosity(const PairList& P, const Images& im, int N, double V, const CubicSplineKernel& W, const SpMat& C0,
                    LinearSolver& C0_solver, const VariableViscosityParams& prm);
  ~VariableViscosity();

  // m_i at the particles at[0..n) (the others keep theirs; every m is 1 at first); m > 0 finite.
  void set(const int* at, const double* m, int n);
  const Vec& m() const { return m_; }
  // The rows whose pairs see an m != 1 (unordered): where V_m is not zero.
  const std::vector<int>& rows() const { return rows_; }
  bool active() const { return !rows_.empty(); }

  // rhs += a V_m (u^n - kg g; c^n + c*) + k (3/2 T^n - 1/2 T^{n-1}) in the rows concerned (T^{n-1} =
  // T^n when `first`), T = (grad u^n)^T grad m_-, g = grad phi^n (the last projection's), kg = dt /
  // rho, k = nu dt; u, c_n, c_star, g, rhs as the fluid's (N x 2, M x 2). Keeps T^n for the next step.
  void add_rhs(const Mat2& u, const Mat2& c_n, const Mat2& c_star, const Mat2& g, double kg, double k, bool first,
               Mat2& rhs);
  // What m adds to the discrete viscous term, V_m u + (grad u)^T grad m_-, at every particle, u with
  // images of offsets c: with the fluid's L u, the discrete div(m (grad u + grad u^T)) (tests).
  void added_viscous_term(const Mat2& u, const Mat2& c, Mat2& out) const;

  // y = C_m x, x and y N x 2 (column-major)
  void product(const double* x, double* y) const;
  // y += c V_m x in rows() (the other rows of V_m x are zero), x and y N x 2 (column-major)
  void add_vm(const double* x, double* y, double c) const;
  LinearSolver& solver();  // CG on C_m, preconditioned by C0's solver
  const LinearSolver& solver() const;
  // The solver for step n (first: the first step after a new initial velocity): CG started from the
  // quadratic extrapolation of the u* of the three steps before when it solved them, else from the
  // caller's guess. With C0's solver exact (a transform or a factorisation), the CG multiplies by the
  // whole of C0 once per solve (the first residual): C0 p follows from C0 z = r (z = C0^-1 r), and
  // C_m p = C0 p - a V_m p touches rows() only.
  LinearSolver& solver_for_step(long n, bool first);
  double beta_kappa() const { return kappa_; }  // beta(e) = gamma (1 + kappa (e_x^4 + e_y^4))
  double beta_gamma() const { return gamma_; }

  // What the next steps need (checkpoints): the cross term T^n of the last add_rhs (the next step's
  // T^{n-1}) and the CG's last three solutions; and its restoration.
  void save(NamedArrays& st) const;
  void load(const NamedArrays& st);

 private:
  class Cg;
  double pair_mean(int k, int i) const {  // m_ij (harmonic mean; an image carries its parent's m)
    const double mi = m_[i], mj = m_[col_[k]];
    return mi == mj ? mi : 2.0 * mi * mj / (mi + mj);
  }
  void weigh_row(int i);  // the pair weights w_k of row i from m
  // out_i = (V_m f)_i with f(p, e) the value of component e at particle p and c(q, e) the offset of
  // image q: the block of pair k on f_i - f_j, f_j = sign f_parent + c at an image
  template <class Value, class Offset>
  void row_v(int i, Value&& f, Offset&& c, double out[2]) const;
  void row_cross(int i, const Mat2& u, const Mat2& c, double T[2]) const;  // (grad u)^T grad m_- in row i
  double norm_C() const;  // an upper bound of max_i sum_j |C_m(i, j)| (the CG's backward error)

  const PairList& P_;
  const Images& im_;
  int N_;
  VariableViscosityParams prm_;
  SpMat C0_;                               // I - a L
  RowStencil st_;                          // its lattice stencil (products.hpp)
  double norm_C0_ = 0, kappa_ = 0, gamma_ = 0;
  std::vector<double> lap_, gx_, gy_;      // per pair: 2 V F_ij, V rx F_ij, V ry F_ij
  std::vector<double> ex_, ey_, beta_;     // per pair: e_ij and beta(e_ij) (0 at an image: Morris form)
  // per pair: the block B = 2 V F_ij (m_ij - 1) (beta e e^T (m_ij >= 1, not an image) or I), its xx,
  // xy and yy entries (weigh_row)
  std::vector<double> bxx_, bxy_, byy_;
  std::vector<int> col_;                   // per pair: the particle j, or the image's parent
  std::vector<double> sign_;               // per pair: 1, or the image's velocity sign (Eq. 42)
  std::vector<int> ref_off_, ref_;         // rows that read m_c: ref_[ref_off_[c] .. ref_off_[c + 1])
  Vec m_;
  std::vector<char> in_rows_, mark_, cross_;  // cross_[i]: row i has a nonzero grad m_-
  double m_cap_ = 1.0;                        // m_- = min(m, m_cap_) (infinity without the central form)
  std::vector<int> rows_, where_, touched_;   // where_[i]: i's place in rows_
  Mat2 T_now_, T_last_;                       // T^n and T^{n-1} (zero outside their rows)
  std::vector<int> t_rows_now_, t_rows_last_;
  std::unique_ptr<Cg> cg_;
};

}  // namespace sphib
