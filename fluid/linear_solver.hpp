#pragma once
// One small interface for the linear systems of a step: factorise once, solve often.
// Contract: a LinearSolver is built from a matrix (analysed and factorised there, once), then
// solve(B, X, k) solves A X = B for k right-hand sides without allocating after the first call.
// CHOLMOD takes symmetric positive definite systems, UMFPACK any other.
#include <memory>
#include <string>

#include "fluid/types.hpp"

namespace sphib {

// Fft: the periodic-lattice Poisson solver of fluid/fft_poisson.hpp (EPSPH only; built there, not by
// factorize()).
enum class SolverKind { Auto, CholmodSupernodal, CholmodSimplicial, Umfpack, Pcg, Fft };

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
  // A new matrix of the same size and kind (LPSPH: every step). The symbolic analysis (ordering,
  // elimination tree, supernodes) is kept when A has the sparsity pattern of the analysed matrix,
  // then only the numeric factorisation is redone; returns whether it was kept (always true for an
  // iterative solver, which has none). Failures throw as factorize() does.
  virtual bool refactorize(const SpMat& A) = 0;
  // Appends a note to the method (e.g. why it was chosen) and the set-up time of the others.
  void annotate(const std::string& note, double extra_factor_seconds) {
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

}  // namespace sphib
