#pragma once
// One small interface for the linear systems of a step: factorise once, solve often.
// Contract: a LinearSolver is built from a matrix (analysed and factorised there, once), then
// solve(B, X, k) solves A X = B for k right-hand sides without allocating after the first call.
// CHOLMOD takes symmetric positive definite systems, UMFPACK any other.
#include <functional>
#include <memory>
#include <string>

#include "fluid/common/params.hpp"
#include "fluid/common/types.hpp"

namespace sphib {

struct SolverInfo {
  std::string system;   // which system ("Crank-Nicolson", "Poisson")
  std::string method;   // which factorisation it got
  int n = 0;
  long nnz_A = 0;       // non-zeros of A (both triangles)
  long nnz_used = 0;    // non-zeros the factorisation reads: the lower triangle (CHOLMOD) or all
  long nnz_factor = 0;  // non-zeros of L (CHOLMOD) or L + U (UMFPACK); 0 for an iterative solver
  double fill() const { return nnz_used ? static_cast<double>(nnz_factor) / nnz_used : 0.0; }
  double analyse_seconds = 0, factor_seconds = 0;
  std::string describe() const;  // one line for the run log
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  // Solves A X = B; B and X are n x k column-major arrays. On entry X holds an initial guess,
  // which iterative solvers use (warm start) and direct ones ignore.
  virtual void solve(const double* B, double* X, int k) = 0;
  const SolverInfo& info() const { return info_; }
  virtual double mean_iterations() const { return 0.0; }  // iterative solvers: per solve so far
  // true when solve() gives A^-1 B to round-off (a factorisation or a fast transform), false when
  // it stops at a tolerance (iterative)
  virtual bool exact() const { return false; }
  // Preconditioned iterations (lagged_pcg): numeric factorisations of the preconditioner since the
  // solver was made, and of them those that kept the symbolic analysis. 0 for the others.
  virtual long preconditioner_factorisations() const { return 0; }
  virtual long preconditioner_analyses_kept() const { return 0; }
  // A new matrix of the same size and kind (LPSPH: every step). The symbolic analysis (ordering,
  // elimination tree, supernodes) is kept when A has the sparsity pattern of the analysed matrix,
  // then only the numeric factorisation is redone; returns whether it was kept (always true for an
  // iterative solver, which has none). Failures throw as factorize() does.
  virtual bool refactorize(const SpMat& A) = 0;
  // refactorize(A) for a caller that keeps A alive and unchanged until the next refactorisation (or
  // the solver's end): an iterative solver then reads A where it is instead of copying it (moving
  // particles assemble their matrices in place every step). Direct solvers copy as refactorize().
  virtual bool refactorize_in_place(const SpMat& A) { return refactorize(A); }
  // The product A X0 for the start X0 of the next solve, computed by the caller where it is cheap
  // (LPSPH: row block by row block behind the assembly, while A's values are in cache) with the
  // bits of lagged_pcg's own product (two columns: apply2's rows, products.hpp; one: Eigen's A x, 0 +
  // each row's sum). An iterative solver whose matrix is A (the same object, read in place)
  // and whose start equals X0 bit for bit takes AX0 (n x k) instead of computing A X0 itself, the
  // same bits; else, and for direct solvers, it is ignored. For that next solve only: the caller
  // keeps X0 and AX0 alive and A unchanged until then.
  virtual void start_product(const SpMat& A, const double* X0, const double* AX0, int k) {
    (void)A, (void)X0, (void)AX0, (void)k;
  }
  // Appends a note to the method (e.g. why it was chosen) and the set-up time of the others.
  virtual void annotate(const std::string& note, double extra_factor_seconds) {
    info_.method += note;
    info_.factor_seconds += extra_factor_seconds;
  }

 protected:
  SolverInfo info_;
};

// Auto: a symmetric A gets CHOLMOD (simplicial for a small factor, supernodal for a large one:
// cholmod_by_factor_size with 8e5, a rule measured on this machine), any other UMFPACK.
// Pcg (Jacobi-preconditioned conjugate gradients, warm-started) is chosen only explicitly.
// Failures (not positive definite, singular, CG not converging) throw std::runtime_error
// naming the system and its size.
std::unique_ptr<LinearSolver> factorize(const std::string& system, const SpMat& A,
                                        SolverKind kind = SolverKind::Auto);

// CHOLMOD, simplicial when its factor has at most `supernodal_lnz` non-zeros, else supernodal (a
// simplicial factorisation, then discarded, tells nnz(L)); `rule` names the choice in the log line.
std::unique_ptr<LinearSolver> cholmod_by_factor_size(const std::string& system, const SpMat& A, double supernodal_lnz,
                                                     const std::string& rule);

bool is_symmetric(const SpMat& A, double rel_tol = 1e-12);

// ---- Conjugate gradients for a matrix that changes every step (moving particles: LPSPH, ISPH) ----
// refactorize(A) only takes the new matrix (its values, when the pattern is unchanged); solve() runs
// CG on it, warm-started from X, preconditioned by a solver M of a nearby matrix, to
// |b - A x| <= rtol |b| per column:
//   the `start` solver, if given (the FFT solver of the fixed lattice: particles near their lattice
//     points make A close to the lattice's matrix), else a factorisation of A itself;
//   a solve that needs more than `refresh_iterations` iterations (the matrix has drifted from M's)
//     refreshes M: a new factorisation of the current A by `factorise` for the next solves (the same
//     CHOLMOD object refactorised, its symbolic analysis kept while A's pattern stays).
// Singular A (symmetric semi-definite, right-hand sides orthogonal to its null space): `null`
// removes the null components of the preconditioned residual, and a factorisation is of the
// definite matrix `null.definite(A)` with the right-hand side `null.pin_rhs(r)` (the gauge's pins,
// fluid/algebra/gauge.hpp); the `start` solver takes the singular operator itself. The solution is then
// unique up to the null space (the caller fixes it).
struct NullSpaceHooks {
  std::function<void(double*)> project;             // v minus its null components
  std::function<SpMat(const SpMat&)> definite;     // the matrix to factorise (pins: identity rows)
  std::function<void(double*)> pin_rhs;            // its right-hand side (zero at the pins)
  bool singular() const { return static_cast<bool>(project); }
};

struct LaggedPcgOptions {
  double rtol = 1e-13;
  int max_iter = 500;
  int refresh_iterations = 8;
};

using Factorise = std::function<std::unique_ptr<LinearSolver>(const std::string& system, const SpMat& A)>;

std::unique_ptr<LinearSolver> lagged_pcg(const std::string& system, const SpMat& A, std::unique_ptr<LinearSolver> start,
                                         Factorise factorise, NullSpaceHooks null, LaggedPcgOptions opt);

}  // namespace sphib
