#pragma once
// A viscosity that varies in space on the fixed lattice (EPSPH): mu_i = mu m_i, m = 1 outside the
// region where it differs (a viscosity contrast: coupling/viscosity_contrast.hpp sets m from the
// membranes). The momentum equation with a variable viscosity,
//   rho Du/Dt = -grad p + div(mu (grad u + grad u^T)) + F,
// is, with div u = 0 (d_j (mu d_i u_j) = (d_i u_j)(d_j mu) + mu d_i div u),
//   rho Du/Dt = -grad p + div(mu grad u) + (grad u)^T grad mu + F,    [(grad u)^T grad mu]_i = (d_i u_j)(d_j mu).
// Discretised on the pairs of the fixed lattice (neighbours.hpp), images by Eq. (42):
//   div(mu grad u):  (L_m u)_i = sum_j 2 V m_ij (u_i - u_j) F_ij                    (Eqs. 28, 31)
//     with the pair viscosity m_ij = 2 m_i m_j / (m_i + m_j), the harmonic mean: Morris, Fox & Zhu
//     (J. Comput. Phys. 136:214, 1997) Eq. (10) with Cleary & Monaghan's (J. Comput. Phys. 148:227,
//     1999) mean for a discontinuous coefficient, which keeps the flux continuous across a jump;
//     an image carries its parent's m;
//   (grad u)^T grad mu:  row-local products of the difference-form SPH gradients
//     (grad f)_i = sum_j V (f_j - f_i) (x_i - x_j) F_ij, u with the images of u^n (offsets c^n),
//     m with its parent's value at an image; zero wherever m is uniform.
// In time (the projection core's Eq. 28, a = nu dt / 2, nu = mu / rho, L_m = L + Delta):
//   (I - a L_m) u* = u^n + a L_m u^n + a B_m (c^n + c*) - a Delta (dt/rho) grad phi^n
//                    + nu dt (3/2 T^n - 1/2 T^{n-1}) + ... (the rest of Eq. 28),   T = (grad u)^T grad m:
// Crank-Nicolson on div(mu grad u) with m^n, Adams-Bashforth (as the convection, Eq. 39) on the cross
// term (the first step: Euler). The term in phi^n: the projection (u^{n+1} = u* - dt/rho grad phi)
// leaves the Crank-Nicolson equation for u^{n+1} intact only when (I - a L_m) commutes with grad, as
// the constant (I - a L) does on the lattice (Kim & Moin's PMIII needs no pressure in the predictor
// for that reason); (I - a L_m) grad phi = grad((I - a L) phi) - a Delta grad phi leaves a Delta (dt/rho)
// grad phi^{n+1} in it, an O(dt^2) error per step (first order in time, largest where the pressure
// jumps across a membrane), which the term with the last step's phi^n cancels to O(dt^3). Measured
// (tests/test_viscosity_contrast.cpp): second order in dt for a fixed m.
// The matrix C_m = I - a L_m is solved by conjugate gradients preconditioned by the solver of the
// constant-viscosity matrix C = I - a L (the Crank-Nicolson solver of the fluid, borrowed: FFT on
// the lattice). With m in [m_lo, m_hi] the preconditioned spectrum lies in
// [min(1, m_lo), max(1, m_hi)], whatever dt (Rayleigh quotients of I + a m K against I + a K).
//
// Only what differs from the constant operator is touched: the rows whose pairs see an m != 1
// (rows()), updated in place when m changes (the rows near the particles whose m changed); the
// constant part of the right-hand side is the fluid's own (fused_passes.hpp) and this adds the
// difference in those rows. Where every pair has m_ij = 1 the rows are the constant operator's bit
// for bit (the same sums in the same order: operators.cpp, assemble_pairs; projection_core.cpp,
// crank_nicolson_matrix), so m = 1 everywhere is the constant-viscosity step.
#include <memory>
#include <vector>

#include "fluid/boundary.hpp"
#include "fluid/kernel.hpp"
#include "fluid/linear_solver.hpp"
#include "fluid/neighbours.hpp"
#include "fluid/operators.hpp"
#include "fluid/products.hpp"
#include "fluid/solver.hpp"

namespace sphib {

struct VariableViscosityParams {
  double a = 0.0;     // nu dt / 2 of Eq. (28)
  double rtol = 1e-10;  // CG: |r| <= rtol |b| (or a backward error of 1e-14)
  int max_iter = 500;
};

class VariableViscosity {
 public:
  // The fixed lattice's pairs P and images im (N particles of volume V, kernel W), the constant
  // Laplacian lap (A: the pattern of the matrices made here) and Crank-Nicolson matrix C0 = I - a
  // lap.A, and its solver, the preconditioner (borrowed: it must outlive this object).
  VariableViscosity(const PairList& P, const Images& im, int N, double V, const CubicSplineKernel& W,
                    const ImageOp& lap, const SpMat& C0, LinearSolver& C0_solver, const VariableViscosityParams& prm);
  ~VariableViscosity();

  // m_i at the particles at[0..n) (the others keep theirs; every m is 1 at first); m > 0 finite.
  void set(const int* at, const double* m, int n);
  const Vec& m() const { return m_; }
  // The rows whose pairs see an m != 1 (unordered): where L_m and C_m differ from the constant ones.
  const std::vector<int>& rows() const { return rows_; }
  bool active() const { return !rows_.empty(); }

  // rhs += a ((L_m - L) u^n + (B_m - B)(c^n + c*) - (L_m - L) kg g) + k (3/2 T^n - 1/2 T^{n-1}) in the
  // rows concerned (T^{n-1} = T^n when `first`), T = (grad u^n)^T grad m, g = grad phi^n (the last
  // projection's), kg = dt / rho; u, c_n, c_star, g, rhs as the fluid's (N x 2, M x 2). Keeps T^n for
  // the next step.
  void add_rhs(const Mat2& u, const Mat2& c_n, const Mat2& c_star, const Mat2& g, double kg, double k, bool first,
               Mat2& rhs);
  // (grad u)^T grad m at every particle (zero where m is uniform), u with images of offsets c.
  void cross_term(const Mat2& u, const Mat2& c, Mat2& T) const;
  // (L_m u + B_m c) at every particle: the discrete div(m grad u) (tests, diagnostics).
  void laplacian(const Mat2& u, const Mat2& c, Mat2& out) const;

  const SpMat& matrix() const { return C_; }  // C_m = I - a L_m
  LinearSolver& solver();  // CG on C_m, preconditioned by C0's solver
  const LinearSolver& solver() const;
  // y = C_m x for both columns of x (N x 2, column-major)
  void product(const double* x, double* y) const;

  // The solver for step n (first: the first step after a new initial velocity): CG started from the
  // quadratic extrapolation of the u* of the three steps before when it solved them, else from the
  // caller's guess.
  LinearSolver& solver_for_step(long n, bool first);

  // What the next steps need (checkpoints): the cross term T^n of the last add_rhs (the next step's
  // T^{n-1}) and the CG's last three solutions; and its restoration.
  void save(NamedArrays& st) const;
  void load(const NamedArrays& st);

 private:
  class Cg;
  double norm_C() const;  // max_i sum_j |C_m(i, j)| (the CG's backward error)
  double pair_mean(int k, int i) const {  // m_ij (harmonic mean; an image carries its parent's m)
    const double mi = m_[i], mj = m_[col_[k]];
    return mi == mj ? mi : 2.0 * mi * mj / (mi + mj);
  }
  void assemble_row(int i);      // the row i of C_m from m
  // T = (grad u)^T grad m and D = (L_m - L)(u; c (+ c*)) in row i
  void row_terms(int i, const Mat2& u, const Mat2& c, const Mat2* c_star, const Mat2* g, double T[2], double D[2]) const;

  const PairList& P_;
  const Images& im_;
  int N_;
  VariableViscosityParams prm_;
  std::vector<double> lap_, gx_, gy_;  // per pair: 2 V F_ij, V rx F_ij, V ry F_ij
  std::vector<int> col_;               // per pair: the particle j, or the image's parent
  std::vector<double> sign_;           // per pair: 1, or the image's velocity sign (Eq. 42)
  std::vector<int> pos_, diag_;        // per pair: its entry (i, col) in C_m; per row: (i, i)
  std::vector<int> ref_off_, ref_;     // rows that read m_c: ref_[ref_off_[c] .. ref_off_[c + 1])
  SpMat C0_, C_;                       // C0 = I - a lap.A; C_m = I - a A_m, A_m L_m's particle part (one pattern)
  RowStencil st_;                      // C0's lattice stencil (products.hpp)
  double norm_C0_ = 0;
  mutable double norm_ = 0;
  mutable bool norm_stale_ = true;
  Vec m_;
  std::vector<char> in_rows_, mark_, uniform_;  // uniform_[i]: every pair of row i sees m_i
  std::vector<int> rows_, where_, touched_;  // where_[i]: i's place in rows_
  Mat2 T_now_, T_last_;                       // T^n and T^{n-1} (zero outside t_rows_)
  Mat2 g_scaled_;                             // (dt/rho) grad phi^n
  std::vector<int> t_rows_now_, t_rows_last_;
  std::unique_ptr<Cg> cg_;
};

}  // namespace sphib
