#include "fluid/algebra/linear_solver.hpp"
#include "fluid/common/profile.hpp"
#include "fluid/algebra/products.hpp"

#include <cholmod.h>
#include <umfpack.h>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <chrono>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace sphib {

namespace {

using ColMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Clock = std::chrono::steady_clock;

[[noreturn]] void fail(const SolverInfo& info, const std::string& what) {
  std::ostringstream m;
  m << "linear solver: system '" << info.system << "' (n = " << info.n << ", nnz = " << info.nnz_A
    << ", " << info.method << "): " << what;
  throw std::runtime_error(m.str());
}

class CholmodSolver final : public LinearSolver {
 public:
  bool exact() const override { return true; }
  CholmodSolver(const std::string& system, const SpMat& A, SolverKind kind) {
    cholmod_start(&c_);
    started_ = true;
    c_.print = 0;
    c_.error_handler = nullptr;
    c_.final_ll = 1;  // LL' also for simplicial: a matrix that is not positive definite fails
    c_.supernodal = kind == SolverKind::CholmodSupernodal  ? CHOLMOD_SUPERNODAL
                    : kind == SolverKind::CholmodSimplicial ? CHOLMOD_SIMPLICIAL
                                                             : CHOLMOD_AUTO;
    info_.system = system;
    info_.n = static_cast<int>(A.rows());
    info_.nnz_A = A.nonZeros();
    info_.method = "CHOLMOD";
    lower_ = ColMat(A).triangularView<Eigen::Lower>();
    lower_.makeCompressed();
    info_.nnz_used = lower_.nonZeros();
    cholmod_sparse S = view();
    auto t0 = Clock::now();
    L_ = cholmod_analyze(&S, &c_);
    if (!L_) { release(); fail(info_, "CHOLMOD analysis failed"); }
    info_.analyse_seconds = seconds_since(t0);
    try {
      numeric(S);
    } catch (...) {
      release();
      throw;
    }
    info_.method = L_->is_super ? "CHOLMOD supernodal LL'" : (L_->is_ll ? "CHOLMOD simplicial LL'"
                                                                       : "CHOLMOD simplicial LDL'");
  }
  ~CholmodSolver() override { release(); }
  bool refactorize(const SpMat& A) override {
    if (A.rows() != info_.n || A.cols() != info_.n) fail(info_, "refactorize: the matrix changed size");
    ColMat lower = ColMat(A).triangularView<Eigen::Lower>();
    lower.makeCompressed();
    const int n = info_.n;
    const bool same = lower.nonZeros() == lower_.nonZeros() &&
                      std::equal(lower.outerIndexPtr(), lower.outerIndexPtr() + n + 1, lower_.outerIndexPtr()) &&
                      std::equal(lower.innerIndexPtr(), lower.innerIndexPtr() + lower.nonZeros(), lower_.innerIndexPtr());
    if (same) {
      std::copy(lower.valuePtr(), lower.valuePtr() + lower.nonZeros(), lower_.valuePtr());
    } else {
      lower_.swap(lower);
    }
    info_.nnz_A = A.nonZeros();
    info_.nnz_used = lower_.nonZeros();
    cholmod_sparse S = view();
    if (!same) {  // a new pattern: a new symbolic analysis (fill-reducing ordering and all)
      auto t0 = Clock::now();
      cholmod_factor* L = cholmod_analyze(&S, &c_);
      if (!L) fail(info_, "CHOLMOD analysis failed");
      cholmod_free_factor(&L_, &c_);
      L_ = L;
      info_.analyse_seconds = seconds_since(t0);
    }
    numeric(S);  // the numeric factorisation into the kept (or new) symbolic factor
    return same;
  }
  void release() {
    if (X_) cholmod_free_dense(&X_, &c_);
    if (Y_) cholmod_free_dense(&Y_, &c_);
    if (E_) cholmod_free_dense(&E_, &c_);
    if (L_) cholmod_free_factor(&L_, &c_);
    if (started_) cholmod_finish(&c_);
    started_ = false;
  }
  void solve(const double* B, double* X, int k) override {
    cholmod_dense b{};
    b.nrow = info_.n;
    b.ncol = k;
    b.nzmax = static_cast<size_t>(info_.n) * k;
    b.d = info_.n;
    b.x = const_cast<double*>(B);
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_A, L_, &b, nullptr, &X_, nullptr, &Y_, &E_, &c_)) fail(info_, "solve failed");
    const double* x = static_cast<const double*>(X_->x);
    std::copy(x, x + static_cast<size_t>(info_.n) * k, X);
  }

 private:
  cholmod_sparse view() {  // CHOLMOD's view of lower_ (no copy)
    cholmod_sparse S{};
    S.nrow = S.ncol = info_.n;
    S.nzmax = lower_.nonZeros();
    S.p = lower_.outerIndexPtr();
    S.i = lower_.innerIndexPtr();
    S.x = lower_.valuePtr();
    S.stype = -1;  // symmetric, lower triangle stored
    S.itype = CHOLMOD_INT;
    S.xtype = CHOLMOD_REAL;
    S.dtype = CHOLMOD_DOUBLE;
    S.sorted = 1;
    S.packed = 1;
    return S;
  }
  void numeric(cholmod_sparse& S) {
    const auto t0 = Clock::now();
    cholmod_factorize(&S, L_, &c_);
    info_.factor_seconds = seconds_since(t0);
    if (c_.status == CHOLMOD_NOT_POSDEF || L_->minor < L_->n) {
      std::ostringstream m;
      m << "matrix is not positive definite (CHOLMOD stopped at column " << L_->minor << ")";
      fail(info_, m.str());
    }
    if (c_.status < CHOLMOD_OK) fail(info_, "CHOLMOD factorisation failed");
    info_.nnz_factor = static_cast<long>(c_.lnz);
  }

  cholmod_common c_{};
  bool started_ = false;
  cholmod_factor* L_ = nullptr;
  cholmod_dense *X_ = nullptr, *Y_ = nullptr, *E_ = nullptr;
  ColMat lower_;
};

class UmfpackSolver final : public LinearSolver {
 public:
  bool exact() const override { return true; }
  UmfpackSolver(const std::string& system, const SpMat& A) : A_(A) {
    A_.makeCompressed();
    info_.system = system;
    info_.method = "UMFPACK LU";
    info_.n = static_cast<int>(A.rows());
    info_.nnz_A = info_.nnz_used = A.nonZeros();
    umfpack_di_defaults(control_);
    try {
      analyse();
      numeric();
    } catch (...) {  // the destructor does not run for a constructor that throws
      if (numeric_) umfpack_di_free_numeric(&numeric_);
      if (symbolic_) umfpack_di_free_symbolic(&symbolic_);
      throw;
    }
    Wi_.resize(info_.n);
    W_.resize(5 * static_cast<size_t>(info_.n));
  }
  ~UmfpackSolver() override {
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    if (symbolic_) umfpack_di_free_symbolic(&symbolic_);
  }
  bool refactorize(const SpMat& A) override {
    if (A.rows() != info_.n || A.cols() != info_.n) fail(info_, "refactorize: the matrix changed size");
    ColMat B(A);
    B.makeCompressed();
    const int n = info_.n;
    const bool same = B.nonZeros() == A_.nonZeros() &&
                      std::equal(B.outerIndexPtr(), B.outerIndexPtr() + n + 1, A_.outerIndexPtr()) &&
                      std::equal(B.innerIndexPtr(), B.innerIndexPtr() + B.nonZeros(), A_.innerIndexPtr());
    if (same) std::copy(B.valuePtr(), B.valuePtr() + B.nonZeros(), A_.valuePtr());
    else A_.swap(B);
    info_.nnz_A = info_.nnz_used = A_.nonZeros();
    if (!same) analyse();
    numeric();
    return same;
  }
  void solve(const double* B, double* X, int k) override {
    for (int c = 0; c < k; ++c) {
      const size_t o = static_cast<size_t>(c) * info_.n;
      const int st = umfpack_di_wsolve(UMFPACK_A, A_.outerIndexPtr(), A_.innerIndexPtr(), A_.valuePtr(), X + o,
                                       B + o, numeric_, control_, nullptr, Wi_.data(), W_.data());
      if (st != UMFPACK_OK) fail(info_, "UMFPACK solve failed (status " + std::to_string(st) + ")");
    }
  }

 private:
  void analyse() {
    if (symbolic_) umfpack_di_free_symbolic(&symbolic_);
    const auto t0 = Clock::now();
    const int st = umfpack_di_symbolic(info_.n, info_.n, A_.outerIndexPtr(), A_.innerIndexPtr(), A_.valuePtr(),
                                       &symbolic_, control_, nullptr);
    if (st != UMFPACK_OK) {
      if (symbolic_) umfpack_di_free_symbolic(&symbolic_);
      fail(info_, "UMFPACK symbolic analysis failed (status " + std::to_string(st) + ")");
    }
    info_.analyse_seconds = seconds_since(t0);
  }
  void numeric() {
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    const auto t0 = Clock::now();
    const int st = umfpack_di_numeric(A_.outerIndexPtr(), A_.innerIndexPtr(), A_.valuePtr(), symbolic_, &numeric_,
                                      control_, nullptr);
    info_.factor_seconds = seconds_since(t0);
    if (st != UMFPACK_OK && numeric_) umfpack_di_free_numeric(&numeric_);
    if (st == UMFPACK_WARNING_singular_matrix) fail(info_, "matrix is singular");
    if (st != UMFPACK_OK) fail(info_, "UMFPACK factorisation failed (status " + std::to_string(st) + ")");
    int lnz = 0, unz = 0, nr = 0, nc = 0, nzud = 0;
    umfpack_di_get_lunz(&lnz, &unz, &nr, &nc, &nzud, numeric_);
    info_.nnz_factor = static_cast<long>(lnz) + unz;
  }

  ColMat A_;
  void* symbolic_ = nullptr;  // kept for refactorize()
  void* numeric_ = nullptr;
  double control_[UMFPACK_CONTROL];
  std::vector<int> Wi_;
  std::vector<double> W_;
};

// Conjugate gradients with the Jacobi preconditioner, warm-started from X. For the
// Crank-Nicolson matrix I - (nu dt/2) lap, whose condition number is 1 + O(nu dt/dx^2), a few
// iterations reach round-off when nu dt/dx^2 is small (the membrane cases).
class PcgSolver final : public LinearSolver {
 public:
  PcgSolver(const std::string& system, const SpMat& A, double rtol = 1e-14, int max_iter = 500)
      : own_(A), rtol_(rtol), max_iter_(max_iter) {
    info_.system = system;
    info_.n = static_cast<int>(A.rows());
    info_.nnz_A = info_.nnz_used = A.nonZeros();
    info_.nnz_factor = 0;
    info_.method = "Jacobi-PCG";
    if ((own_.diagonal().array() <= 0).any()) fail(info_, "conjugate gradients need a positive diagonal");
    inv_diag_ = own_.diagonal().cwiseInverse();
    st_ = find_row_stencil({&own_});
  }
  bool refactorize(const SpMat& A) override {  // nothing to analyse: the matrix and its diagonal
    own_ = A;
    A_ = &own_;
    return take(own_);
  }
  bool refactorize_in_place(const SpMat& A) override {
    A_ = &A;
    return take(A);
  }
  // The k columns are k independent CG iterations run in lockstep, so that each iteration reads
  // the matrix once for all of them.
  void solve(const double* B, double* X, int k) override {
    const int n = info_.n;
    if (R_.cols() != k) { R_.resize(n, k); P_.resize(n, k); Q_.resize(n, k); }
    Eigen::Map<const Eigen::MatrixXd> b(B, n, k);
    Eigen::Map<Eigen::MatrixXd> x(X, n, k);
    if (k == 2) {  // one pass over the matrix for both columns
      apply2(*A_, x.data(), R_.data(), &st_);
      R_ = b - R_;
    } else {
      R_.noalias() = b - *A_ * x;
    }
    P_ = inv_diag_.asDiagonal() * R_;  // z = D^-1 r, the first direction
    double rz[8], bnorm[8];
    bool done[8];
    if (k > 8) fail(info_, "at most 8 right-hand sides at once");
    int active = 0;
    for (int c = 0; c < k; ++c) {
      rz[c] = R_.col(c).dot(P_.col(c));
      bnorm[c] = b.col(c).norm();
      done[c] = R_.col(c).norm() <= rtol_ * bnorm[c];
      active += !done[c];
    }
    int it = 0;
    while (active > 0) {
      if (++it > max_iter_) {
        std::ostringstream m;
        m << "conjugate gradients did not converge in " << max_iter_ << " iterations";
        fail(info_, m.str());
      }
      if (k == 2) apply2(*A_, P_.data(), Q_.data(), &st_);
      else Q_.noalias() = *A_ * P_;
      for (int c = 0; c < k; ++c) {
        if (done[c]) continue;
        const double alpha = rz[c] / P_.col(c).dot(Q_.col(c));
        // One pass: x += alpha p, r -= alpha q, |r|^2 and r.z with z = D^-1 r (not stored); a
        // second: p = z + beta p.
        double* xc = x.col(c).data();
        double *rc = R_.col(c).data(), *pc = P_.col(c).data();
        const double *qc = Q_.col(c).data(), *id = inv_diag_.data();
        double rr = 0, rz_new = 0;
        for (int i = 0; i < n; ++i) {
          xc[i] += alpha * pc[i];
          const double r = rc[i] - alpha * qc[i];
          rc[i] = r;
          rr += r * r;
          rz_new += r * (id[i] * r);
        }
        if (std::sqrt(rr) <= rtol_ * bnorm[c]) { done[c] = true; --active; continue; }
        const double beta = rz_new / rz[c];
        for (int i = 0; i < n; ++i) pc[i] = id[i] * rc[i] + beta * pc[i];
        rz[c] = rz_new;
      }
    }
    iterations_ += it;
    ++solves_;
  }
  double mean_iterations() const override { return solves_ ? static_cast<double>(iterations_) / solves_ : 0.0; }

 private:
  // A new matrix: its diagonal; no stencil (the rows of moving particles are not translates).
  bool take(const SpMat& A) {
    if (A.rows() != info_.n || A.cols() != info_.n) fail(info_, "refactorize: the matrix changed size");
    if ((A.diagonal().array() <= 0).any()) fail(info_, "conjugate gradients need a positive diagonal");
    info_.nnz_A = info_.nnz_used = A.nonZeros();
    inv_diag_ = A.diagonal().cwiseInverse();
    st_ = RowStencil{};
    return true;
  }
  SpMat own_;
  const SpMat* A_ = &own_;  // own_, or the caller's matrix (refactorize_in_place)
  RowStencil st_;  // A's lattice rows (fluid/algebra/products.hpp)
  Vec inv_diag_;
  Eigen::MatrixXd R_, P_, Q_;
  double rtol_;
  int max_iter_;
  long iterations_ = 0, solves_ = 0;
};

// Conjugate gradients preconditioned by a solver of a nearby matrix (linear_solver.hpp, lagged_pcg).
// The k columns run in lockstep (one pass over A and one preconditioner solve for all of them).
// Stopping: |r| <= rtol |b|, or the normwise backward error |r| / (|A| |x| + |b|) at the level a
// direct solver reaches (kBackward, |A| the largest absolute row sum): for a smooth x of an
// ill-conditioned A (a Poisson problem) |b| = |A x| is much smaller than |A| |x| and rtol |b| can lie
// below what the rounding of r = b - A x can show (kBackward = 1e-14, a margin of 5 above where CG
// stagnates: docs/method/choices.md, "Solvers: the thresholds").
class LaggedPcg final : public LinearSolver {
 public:
  static constexpr double kBackward = 1e-14;

  LaggedPcg(const std::string& system, const SpMat& A, std::unique_ptr<LinearSolver> start, Factorise factorise,
            NullSpaceHooks null, LaggedPcgOptions opt)
      : own_(A), M_(std::move(start)), factorise_(std::move(factorise)), null_(std::move(null)), opt_(opt) {
    own_.makeCompressed();
    info_.system = system;
    info_.n = static_cast<int>(own_.rows());
    info_.nnz_A = info_.nnz_used = own_.nonZeros();
    info_.nnz_factor = 0;  // iterative: the caller's warm start counts (fluid/core/projection_core.cpp)
    norm_A();
    if (!M_) refresh();
    start_method_ = M_->info().method;
    describe_method();
  }

  bool refactorize(const SpMat& A) override {
    if (A.rows() != info_.n || A.cols() != info_.n) fail(info_, "refactorize: the matrix changed size");
    if (A_ == &own_ && same_pattern(A, own_)) std::copy(A.valuePtr(), A.valuePtr() + A.nonZeros(), own_.valuePtr());
    else { own_ = A; own_.makeCompressed(); }
    A_ = &own_;
    info_.nnz_A = info_.nnz_used = own_.nonZeros();
    return true;  // nothing to analyse: the preconditioner is refreshed by the iteration counts
  }
  bool refactorize_in_place(const SpMat& A) override {
    if (A.rows() != info_.n || A.cols() != info_.n) fail(info_, "refactorize: the matrix changed size");
    if (!A.isCompressed()) return refactorize(A);
    A_ = &A;
    info_.nnz_A = info_.nnz_used = A.nonZeros();
    return true;
  }

  void solve(const double* B, double* X, int k) override {
    const int n = info_.n;
    if (k > 8) fail(info_, "at most 8 right-hand sides at once");
    if (R_.cols() != k) { R_.resize(n, k); Z_.resize(n, k); P_.resize(n, k); Q_.resize(n, k); }
    Eigen::Map<const Eigen::MatrixXd> b(B, n, k);
    Eigen::Map<Eigen::MatrixXd> x(X, n, k);
    if (ahead_.A == A_ && ahead_.k == k && std::memcmp(ahead_.X0, X, sizeof(double) * n * k) == 0) {
      R_ = b - Eigen::Map<const Eigen::MatrixXd>(ahead_.AX0, n, k);  // A X computed by the caller
    } else {
      product(x.data(), R_.data(), k);
      R_ = b - R_;
    }
    ahead_ = {};
    double rz[8], bnorm[8], xnorm[8];
    bool done[8];
    int active = 0;
    for (int c = 0; c < k; ++c) {
      bnorm[c] = b.col(c).norm();
      if (bnorm[c] == 0.0) x.col(c).setZero();  // (a singular A: the solution orthogonal to its null space)
      xnorm[c] = x.col(c).norm();
      done[c] = bnorm[c] == 0.0 || converged(R_.col(c).norm(), bnorm[c], xnorm[c]);
      active += !done[c];
    }
    int it = 0;
    double worst_rel = 0, worst_eta = 0;  // of the last column updated (for the failure message)
    if (active) {
      precondition(R_.data(), Z_.data(), k);
      P_ = Z_;
      for (int c = 0; c < k; ++c) rz[c] = R_.col(c).dot(Z_.col(c));
    }
    while (active > 0) {
      if (++it > opt_.max_iter) {
        std::ostringstream m;
        m << "preconditioned conjugate gradients did not converge in " << opt_.max_iter
          << " iterations (relative residual " << worst_rel << ", backward error " << worst_eta << ")";
        fail(info_, m.str());
      }
      product(P_.data(), Q_.data(), k);
      for (int c = 0; c < k; ++c) {
        if (done[c]) continue;
        const double alpha = rz[c] / P_.col(c).dot(Q_.col(c));
        // One pass: x += alpha p, r -= alpha q, |x|^2, |r|^2.
        double *xc = x.col(c).data(), *rc = R_.col(c).data();
        const double *pc = P_.col(c).data(), *qc = Q_.col(c).data();
        double rr = 0, xx = 0;
        for (int i = 0; i < n; ++i) {
          xc[i] += alpha * pc[i];
          rc[i] -= alpha * qc[i];
          rr += rc[i] * rc[i];
          xx += xc[i] * xc[i];
        }
        if (converged(std::sqrt(rr), bnorm[c], std::sqrt(xx))) { done[c] = true; --active; }
        worst_rel = std::sqrt(rr) / bnorm[c];
        worst_eta = std::sqrt(rr) / (norm_A_ * std::sqrt(xx) + bnorm[c]);
      }
      if (!active) break;
      precondition(R_.data(), Z_.data(), k);
      for (int c = 0; c < k; ++c) {
        if (done[c]) continue;
        const double rz_new = R_.col(c).dot(Z_.col(c));
        const double beta = rz_new / rz[c];
        P_.col(c) = Z_.col(c) + beta * P_.col(c);
        rz[c] = rz_new;
      }
    }
    iterations_ += it;
    ++solves_;
    last_iterations_ = it;
    if (it > opt_.refresh_iterations) refresh();  // for the next solves
  }

  double mean_iterations() const override { return solves_ ? static_cast<double>(iterations_) / solves_ : 0.0; }
  void start_product(const SpMat& A, const double* X0, const double* AX0, int k) override { ahead_ = {&A, X0, AX0, k}; }
  void annotate(const std::string& note, double) override {  // kept through the refreshes
    note_ += note;
    describe_method();
  }
  long preconditioner_factorisations() const override { return factorisations_; }
  long preconditioner_analyses_kept() const override { return kept_; }

 private:
  bool converged(double rnorm, double bnorm, double xnorm) const {
    return rnorm <= opt_.rtol * bnorm || rnorm <= kBackward * (norm_A_ * xnorm + bnorm);
  }
  void norm_A() {  // the largest absolute row sum
    norm_A_ = 0;
    const int* o = A_->outerIndexPtr();
    const double* a = A_->valuePtr();
    for (int i = 0; i < info_.n; ++i) {
      double s = 0;
      for (int k = o[i]; k < o[i + 1]; ++k) s += std::fabs(a[k]);
      norm_A_ = std::max(norm_A_, s);
    }
  }
  void product(const double* v, double* y, int k) const {  // y = A v, k columns
    const int n = info_.n;
    if (k == 2) { apply2(*A_, v, y); return; }
    for (int c = 0; c < k; ++c)
      Eigen::Map<Vec>(y + static_cast<size_t>(c) * n, n).noalias() = *A_ * Eigen::Map<const Vec>(v + static_cast<size_t>(c) * n, n);
  }
  // Z = M^-1 R; a factorisation of the pinned matrix takes the pinned residual; then the null
  // components are removed (symmetric on the range of A: see linear_solver.hpp).
  void precondition(const double* R, double* Z, int k) {
    const int n = info_.n;
    if (factored_ && null_.singular()) {
      W_ = Eigen::Map<const Eigen::MatrixXd>(R, n, k);
      for (int c = 0; c < k; ++c) null_.pin_rhs(W_.col(c).data());
      M_->solve(W_.data(), Z, k);
    } else {
      M_->solve(R, Z, k);
    }
    if (null_.singular())
      for (int c = 0; c < k; ++c) null_.project(Z + static_cast<size_t>(c) * n);
  }
  // M = a factorisation of the current A (of its definite form when singular); the same CHOLMOD
  // object is refactorised when M is already ours.
  void refresh() {
    const SpMat D = null_.singular() ? null_.definite(*A_) : SpMat();
    const SpMat& F = null_.singular() ? D : *A_;
    if (factored_) {
      kept_ += M_->refactorize(F);
    } else {
      M_ = factorise_(info_.system, F);
      factored_ = true;
    }
    ++factorisations_;
    norm_A();
    describe_method();
  }
  void describe_method() {
    std::ostringstream m;
    m << "CG preconditioned by ";
    if (factored_) m << "a lagged " << M_->info().method << " factor, refactorised when a solve needs more than " << opt_.refresh_iterations << " iterations";
    else m << start_method_ << " of the fixed lattice (to a lagged CHOLMOD factor when a solve needs more than "
           << opt_.refresh_iterations << " iterations)";
    m << ", rtol " << opt_.rtol << note_;
    info_.method = m.str();
    info_.analyse_seconds = M_->info().analyse_seconds;
    info_.factor_seconds = M_->info().factor_seconds;
  }

  SpMat own_;
  const SpMat* A_ = &own_;  // own_, or the caller's matrix (refactorize_in_place)
  double norm_A_ = 0;  // |A| (largest absolute row sum) at the last refresh of M (and at the start)
  std::unique_ptr<LinearSolver> M_;
  bool factored_ = false;  // M_ is a factorisation made here (else the start solver)
  std::string start_method_, note_;
  Factorise factorise_;
  NullSpaceHooks null_;
  LaggedPcgOptions opt_;
  struct Ahead {  // start_product's
    const SpMat* A = nullptr;
    const double *X0 = nullptr, *AX0 = nullptr;
    int k = 0;
  } ahead_;
  Eigen::MatrixXd R_, Z_, P_, Q_, W_;
  long iterations_ = 0, solves_ = 0, factorisations_ = 0, kept_ = 0;
  int last_iterations_ = 0;
};

}  // namespace

std::string SolverInfo::describe() const {
  std::ostringstream m;
  m << system << ": " << method << ", n = " << n << ", nnz(A) = " << nnz_A;
  if (nnz_factor)
    m << ", nnz(factor) = " << nnz_factor << " (fill " << fill() << "x the "
      << (nnz_used < nnz_A ? "lower triangle" : "matrix") << ")";
  else
    m << ", no factorisation";
  m << ", analysis " << analyse_seconds << " s, factorisation " << factor_seconds << " s";
  return m.str();
}

bool is_symmetric(const SpMat& A, double rel_tol) {
  if (A.rows() != A.cols()) return false;
  const SpMat At = A.transpose();
  return (A - At).norm() <= rel_tol * A.norm();
}

std::unique_ptr<LinearSolver> factorize(const std::string& system, const SpMat& A, SolverKind kind) {
  if (kind == SolverKind::Umfpack || (kind == SolverKind::Auto && !is_symmetric(A)))
    return std::make_unique<UmfpackSolver>(system, A);
  if (kind == SolverKind::Pcg) return std::make_unique<PcgSolver>(system, A);
  if (kind == SolverKind::Fft)
    throw std::invalid_argument("linear solver: system '" + system + "': the FFT solver needs the fixed lattice (EPSPH)");
  if (kind != SolverKind::Auto) return std::make_unique<CholmodSolver>(system, A, kind);
  // Auto, deterministic: simplicial up to 8e5 non-zeros in L, supernodal above (measured on this
  // machine: docs/performance/index.md, "Solvers, chosen automatically").
  return cholmod_by_factor_size(system, A, 8e5, "auto");
}

std::unique_ptr<LinearSolver> lagged_pcg(const std::string& system, const SpMat& A, std::unique_ptr<LinearSolver> start,
                                         Factorise factorise, NullSpaceHooks null, LaggedPcgOptions opt) {
  return std::make_unique<LaggedPcg>(system, A, std::move(start), std::move(factorise), std::move(null), opt);
}

std::unique_ptr<LinearSolver> cholmod_by_factor_size(const std::string& system, const SpMat& A, double supernodal_lnz,
                                                     const std::string& rule) {
  auto simplicial = std::make_unique<CholmodSolver>(system, A, SolverKind::CholmodSimplicial);
  std::ostringstream note;
  if (simplicial->info().nnz_factor <= supernodal_lnz) {
    note << " (" << rule << ": nnz(L) <= " << supernodal_lnz << ")";
    simplicial->annotate(note.str(), 0.0);
    return simplicial;
  }
  const double t = simplicial->info().factor_seconds + simplicial->info().analyse_seconds;
  simplicial.reset();
  auto super = std::make_unique<CholmodSolver>(system, A, SolverKind::CholmodSupernodal);
  note << " (" << rule << ": nnz(L) > " << supernodal_lnz << ")";
  super->annotate(note.str(), t);
  return super;
}

}  // namespace sphib
