#include "fluid/linear_solver.hpp"

#include <cholmod.h>
#include <umfpack.h>

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace sphib {

namespace {

using ColMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

[[noreturn]] void fail(const SolverInfo& info, const std::string& what) {
  std::ostringstream m;
  m << "linear solver: system '" << info.system << "' (n = " << info.n << ", nnz = " << info.nnz_A
    << ", " << info.method << "): " << what;
  throw std::runtime_error(m.str());
}

class CholmodSolver final : public LinearSolver {
 public:
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
    cholmod_sparse S{};
    S.nrow = S.ncol = A.rows();
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
    auto t0 = Clock::now();
    L_ = cholmod_analyze(&S, &c_);
    if (!L_) { release(); fail(info_, "CHOLMOD analysis failed"); }
    info_.analyse_seconds = since(t0);
    t0 = Clock::now();
    cholmod_factorize(&S, L_, &c_);
    info_.factor_seconds = since(t0);
    if (c_.status == CHOLMOD_NOT_POSDEF || L_->minor < L_->n) {
      std::ostringstream m;
      m << "matrix is not positive definite (CHOLMOD stopped at column " << L_->minor << ")";
      release();
      fail(info_, m.str());
    }
    if (c_.status < CHOLMOD_OK) { release(); fail(info_, "CHOLMOD factorisation failed"); }
    info_.method = L_->is_super ? "CHOLMOD supernodal LL'" : (L_->is_ll ? "CHOLMOD simplicial LL'"
                                                                       : "CHOLMOD simplicial LDL'");
    info_.nnz_factor = static_cast<long>(c_.lnz);
  }
  ~CholmodSolver() override { release(); }
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
  cholmod_common c_{};
  bool started_ = false;
  cholmod_factor* L_ = nullptr;
  cholmod_dense *X_ = nullptr, *Y_ = nullptr, *E_ = nullptr;
  ColMat lower_;
};

class UmfpackSolver final : public LinearSolver {
 public:
  UmfpackSolver(const std::string& system, const SpMat& A) : A_(A) {
    A_.makeCompressed();
    info_.system = system;
    info_.method = "UMFPACK LU";
    info_.n = static_cast<int>(A.rows());
    info_.nnz_A = info_.nnz_used = A.nonZeros();
    umfpack_di_defaults(control_);
    void* symbolic = nullptr;
    auto t0 = Clock::now();
    int st = umfpack_di_symbolic(info_.n, info_.n, A_.outerIndexPtr(), A_.innerIndexPtr(), A_.valuePtr(),
                                 &symbolic, control_, nullptr);
    if (st != UMFPACK_OK) {
      if (symbolic) umfpack_di_free_symbolic(&symbolic);
      fail(info_, "UMFPACK symbolic analysis failed (status " + std::to_string(st) + ")");
    }
    info_.analyse_seconds = since(t0);
    t0 = Clock::now();
    st = umfpack_di_numeric(A_.outerIndexPtr(), A_.innerIndexPtr(), A_.valuePtr(), symbolic, &numeric_,
                            control_, nullptr);
    umfpack_di_free_symbolic(&symbolic);
    info_.factor_seconds = since(t0);
    if (st != UMFPACK_OK && numeric_) umfpack_di_free_numeric(&numeric_);
    if (st == UMFPACK_WARNING_singular_matrix) fail(info_, "matrix is singular");
    if (st != UMFPACK_OK) fail(info_, "UMFPACK factorisation failed (status " + std::to_string(st) + ")");
    int lnz = 0, unz = 0, nr = 0, nc = 0, nzud = 0;
    umfpack_di_get_lunz(&lnz, &unz, &nr, &nc, &nzud, numeric_);
    info_.nnz_factor = static_cast<long>(lnz) + unz;
    Wi_.resize(info_.n);
    W_.resize(5 * static_cast<size_t>(info_.n));
  }
  ~UmfpackSolver() override {
    if (numeric_) umfpack_di_free_numeric(&numeric_);
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
  ColMat A_;
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
      : A_(A), rtol_(rtol), max_iter_(max_iter) {
    info_.system = system;
    info_.n = static_cast<int>(A.rows());
    info_.nnz_A = A.nonZeros();
    info_.nnz_factor = 0;
    info_.method = "Jacobi-PCG";
    inv_diag_ = A_.diagonal().cwiseInverse();
    if (!inv_diag_.allFinite() || (A_.diagonal().array() <= 0).any())
      fail(info_, "conjugate gradients need a positive diagonal");
    r_.resize(info_.n); z_.resize(info_.n); p_.resize(info_.n); q_.resize(info_.n);
  }
  void solve(const double* B, double* X, int k) override {
    for (int c = 0; c < k; ++c) {
      Eigen::Map<const Vec> b(B + static_cast<size_t>(c) * info_.n, info_.n);
      Eigen::Map<Vec> x(X + static_cast<size_t>(c) * info_.n, info_.n);
      const double bnorm = b.norm();
      if (bnorm == 0.0) { x.setZero(); continue; }
      r_.noalias() = b - A_ * x;
      z_ = inv_diag_.cwiseProduct(r_);
      p_ = z_;
      double rz = r_.dot(z_);
      int it = 0;
      while (r_.norm() > rtol_ * bnorm) {
        if (++it > max_iter_) {
          std::ostringstream m;
          m << "conjugate gradients did not converge in " << max_iter_ << " iterations (residual "
            << r_.norm() / bnorm << ")";
          fail(info_, m.str());
        }
        q_.noalias() = A_ * p_;
        const double alpha = rz / p_.dot(q_);
        x += alpha * p_;
        r_ -= alpha * q_;
        z_ = inv_diag_.cwiseProduct(r_);
        const double rz_new = r_.dot(z_);
        p_ = z_ + (rz_new / rz) * p_;
        rz = rz_new;
      }
      iterations_ += it;
      ++solves_;
    }
  }
  double mean_iterations() const { return solves_ ? static_cast<double>(iterations_) / solves_ : 0.0; }

 private:
  SpMat A_;
  Vec inv_diag_, r_, z_, p_, q_;
  double rtol_;
  int max_iter_;
  long iterations_ = 0, solves_ = 0;
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

std::unique_ptr<LinearSolver> factorize(const std::string& system, const SpMat& A, SolverKind kind,
                                        bool allow_pcg) {
  if (kind == SolverKind::Umfpack || (kind == SolverKind::Auto && !is_symmetric(A)))
    return std::make_unique<UmfpackSolver>(system, A);
  if (kind == SolverKind::Pcg) return std::make_unique<PcgSolver>(system, A);
  if (kind != SolverKind::Auto) return std::make_unique<CholmodSolver>(system, A, kind);
  // Auto: time each candidate on a two-column solve, as in a step, and keep the fastest.
  std::vector<std::unique_ptr<LinearSolver>> cand;
  cand.push_back(std::make_unique<CholmodSolver>(system, A, SolverKind::CholmodSupernodal));
  cand.push_back(std::make_unique<CholmodSolver>(system, A, SolverKind::CholmodSimplicial));
  if (allow_pcg) cand.push_back(std::make_unique<PcgSolver>(system, A));
  const int n = static_cast<int>(A.rows());
  Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, 2), X(n, 2);
  std::vector<double> best(cand.size(), 1e300);
  for (size_t c = 0; c < cand.size(); ++c) {
    X.setZero();
    cand[c]->solve(B.data(), X.data(), 2);  // warm-up (allocates CHOLMOD's workspace)
    for (int rep = 0; rep < 5; ++rep) {
      X.setZero();  // CG from a zero guess: its worst case, a time step warm-starts it
      const auto t0 = Clock::now();
      cand[c]->solve(B.data(), X.data(), 2);
      best[c] = std::min(best[c], since(t0));
    }
  }
  const size_t w = std::min_element(best.begin(), best.end()) - best.begin();
  std::ostringstream note;
  note << " (auto, us per 2-column solve:";
  double extra = 0;
  for (size_t c = 0; c < cand.size(); ++c) {
    note << (c ? ", " : " ") << (c == 0 ? "supernodal " : c == 1 ? "simplicial " : "PCG ") << 1e6 * best[c];
    if (c != w) extra += cand[c]->info().factor_seconds;
  }
  note << ")";
  cand[w]->annotate(note.str(), extra);
  return std::move(cand[w]);
}

}  // namespace sphib
