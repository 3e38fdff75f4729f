#include "fluid/variable_viscosity.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "fluid/products.hpp"
#include "fluid/solver.hpp"

namespace sphib {

namespace {

// Index of column c in row i of A (row-major, sorted columns), or -1.
int entry(const SpMat& A, int i, int c) {
  const int* o = A.outerIndexPtr();
  const int* b = A.innerIndexPtr() + o[i];
  const int* e = A.innerIndexPtr() + o[i + 1];
  const int* p = std::lower_bound(b, e, c);
  return p != e && *p == c ? static_cast<int>(p - A.innerIndexPtr()) : -1;
}

}  // namespace

// Conjugate gradients on C_m, preconditioned by the constant matrix's solver M (C0^-1), warm-started
// from X, each column to |r| <= rtol |b| or a backward error |r| <= 1e-14 (|C_m| |x| + |b|). The
// product C_m x is C0's lattice stencil (products.hpp) with the rows of C_m that differ
// (VariableViscosity::rows) taken from C_m.
class VariableViscosity::Cg final : public LinearSolver {
 public:
  Cg(const VariableViscosity& v, LinearSolver& M) : v_(v), M_(M), H_(Eigen::MatrixXd::Zero(v.N_, 6)) {
    info_.system = "Crank-Nicolson (variable viscosity)";
    info_.n = v.N_;
    info_.nnz_A = v.C_.nonZeros();
    info_.nnz_used = 2 * info_.nnz_A;  // C0 and C_m, kept
    std::ostringstream m;
    m << "CG preconditioned by the constant-viscosity solver (" << M.info().method << "), rtol " << v.prm_.rtol;
    info_.method = m.str();
  }
  bool refactorize(const SpMat&) override { throw std::logic_error("variable viscosity: CG takes C_m in place"); }
  double mean_iterations() const override { return solves_ ? static_cast<double>(iterations_) / solves_ : 0.0; }

  void solve(const double* B, double* X, int k) override {
    if (k != 2) throw std::logic_error("variable viscosity: CG solves both velocity components at once");
    const int n = info_.n;
    R_.resize(n, 2), Z_.resize(n, 2), P_.resize(n, 2), Q_.resize(n, 2);
    Eigen::Map<const Mat2> b(B, n, 2);
    Eigen::Map<Mat2> x(X, n, 2);
    if (count_ >= 3 && last_ == step_ - 1)  // the quadratic extrapolation of the last three steps' u*
      for (int e = 0; e < 2; ++e)
        for (int i = 0; i < n; ++i) x(i, e) = 3.0 * (H_(i, e) - H_(i, 2 + e)) + H_(i, 4 + e);
    v_.product(x.data(), R_.data());
    R_ = b - R_;
    const double normA = v_.norm_C();
    double rz[2], bn[2];
    bool done[2];
    auto converged = [&](int c, double rr, double xx) {
      const double r = std::sqrt(rr);
      return r <= v_.prm_.rtol * bn[c] || r <= kBackward * (normA * std::sqrt(xx) + bn[c]);
    };
    int active = 0;
    for (int c = 0; c < 2; ++c) {
      bn[c] = b.col(c).norm();
      if (bn[c] == 0.0) x.col(c).setZero();
      done[c] = bn[c] == 0.0 || converged(c, R_.col(c).squaredNorm(), x.col(c).squaredNorm());
      active += !done[c];
    }
    if (active) {
      M_.solve(R_.data(), Z_.data(), 2);
      P_ = Z_;
      for (int c = 0; c < 2; ++c) rz[c] = R_.col(c).dot(Z_.col(c));
    }
    int it = 0;
    while (active > 0) {
      if (++it > v_.prm_.max_iter) {
        std::ostringstream m;
        m << "variable viscosity: conjugate gradients on the Crank-Nicolson matrix did not converge in " << v_.prm_.max_iter
          << " iterations (n = " << n << ")";
        throw std::runtime_error(m.str());
      }
      v_.product(P_.data(), Q_.data());
      for (int c = 0; c < 2; ++c) {
        if (done[c]) continue;
        const double alpha = rz[c] / P_.col(c).dot(Q_.col(c));
        double *xc = x.col(c).data(), *rc = R_.col(c).data(), rr = 0, xx = 0;  // one pass
        const double *pc = P_.col(c).data(), *qc = Q_.col(c).data();
        for (int i = 0; i < n; ++i) {
          xc[i] += alpha * pc[i];
          rc[i] -= alpha * qc[i];
          rr += rc[i] * rc[i];
          xx += xc[i] * xc[i];
        }
        if (converged(c, rr, xx)) done[c] = true, --active;
      }
      if (!active) break;
      M_.solve(R_.data(), Z_.data(), 2);
      for (int c = 0; c < 2; ++c) {
        if (done[c]) continue;
        const double rz_new = R_.col(c).dot(Z_.col(c));
        P_.col(c) = Z_.col(c) + (rz_new / rz[c]) * P_.col(c);
        rz[c] = rz_new;
      }
    }
    iterations_ += it;
    ++solves_;
    // the history: u*_n, u*_{n-1}, u*_{n-2} in columns (0, 1), (2, 3), (4, 5)
    if (last_ != step_ - 1) count_ = 0;
    H_.rightCols(4) = H_.leftCols(4).eval();
    H_.leftCols(2) = x;
    count_ = std::min(count_ + 1, 3);
    last_ = step_;
  }

  void begin_step(long n, bool first) {
    step_ = n;
    if (first) count_ = 0;  // a new initial velocity: no history
  }
  void save(NamedArrays& st) const {
    Eigen::MatrixXd c(1, 2);
    c << count_, static_cast<double>(last_);
    st.emplace_back("viscous_start_count", c);
    st.emplace_back("viscous_start_history", H_);
  }
  void load(const NamedArrays& st) {
    const Eigen::MatrixXd& c = state_entry(st, "viscous_start_count", 1, 2);
    H_ = state_entry(st, "viscous_start_history", info_.n, 6);
    count_ = static_cast<int>(c(0, 0));
    last_ = static_cast<long>(c(0, 1));
  }

 private:
  static constexpr double kBackward = 1e-14;
  const VariableViscosity& v_;
  LinearSolver& M_;
  Mat2 R_, Z_, P_, Q_;
  long iterations_ = 0, solves_ = 0;
  Eigen::MatrixXd H_;       // the last three solutions (see solve)
  int count_ = 0;           // how many of them
  long step_ = 0, last_ = -2;  // the step of this solve and of the last one
};

void VariableViscosity::product(const double* x, double* y) const {
  apply2(C0_, x, y, &st_);  // the constant rows as a lattice stencil, then the rows that differ
  const int* o = C_.outerIndexPtr();
  const int* col = C_.innerIndexPtr();
  const double* c = C_.valuePtr();
  const double* x1 = x + N_;
  for (int i : rows_) {
    if (uniform_[i]) {  // C_m row = I - a m_i L row = m_i C0 row + (1 - m_i) e_i
      const double mi = m_[i];
      y[i] = mi * y[i] + (1.0 - mi) * x[i];
      y[N_ + i] = mi * y[N_ + i] + (1.0 - mi) * x1[i];
      continue;
    }
    double s0 = 0, s1 = 0;
    for (int e = o[i]; e < o[i + 1]; ++e) {
      s0 += c[e] * x[col[e]];
      s1 += c[e] * x1[col[e]];
    }
    y[i] = s0;
    y[N_ + i] = s1;
  }
}

double VariableViscosity::norm_C() const {
  if (norm_stale_) {  // the largest absolute row sum: C0's, or a variable row's
    norm_ = norm_C0_;
    const int* o = C_.outerIndexPtr();
    for (int i : rows_) {
      double s = 0;
      for (int e = o[i]; e < o[i + 1]; ++e) s += std::fabs(C_.valuePtr()[e]);
      norm_ = std::max(norm_, s);
    }
    norm_stale_ = false;
  }
  return norm_;
}

VariableViscosity::VariableViscosity(const PairList& P, const Images& im, int N, double V, const CubicSplineKernel& W,
                                     const ImageOp& lap, const SpMat& C0, LinearSolver& C0_solver,
                                     const VariableViscosityParams& prm)
    : P_(P), im_(im), N_(N), prm_(prm), C0_(C0), C_(C0) {
  if (!same_pattern(C0, lap.A)) throw std::logic_error("variable viscosity: C0 must have the Laplacian's pattern");
  C0_.makeCompressed();
  C_.makeCompressed();
  st_ = find_row_stencil({&C0_});
  for (int i = 0; i < N; ++i) {
    double s = 0;
    for (int e = C0_.outerIndexPtr()[i]; e < C0_.outerIndexPtr()[i + 1]; ++e) s += std::fabs(C0_.valuePtr()[e]);
    norm_C0_ = std::max(norm_C0_, s);
  }
  const int K = P.size();
  lap_.resize(K), gx_.resize(K), gy_.resize(K), col_.resize(K), sign_.resize(K), pos_.resize(K);
  for (int k = 0; k < K; ++k) {
    const double F = W.F(P.r[k]);  // (1/r) dW/dr
    lap_[k] = 2.0 * V * F;         // as build_operators: Eqs. (28), (31)
    gx_[k] = V * P.rx[k] * F;      // V (x_i - x_j) F_ij
    gy_[k] = V * P.ry[k] * F;
    const int j = P.j[k];
    col_[k] = j < N ? j : im.parent[j - N];
    sign_[k] = j < N ? 1.0 : im.v_sign[j - N];
  }
  diag_.resize(N);
  std::vector<int> count(N + 1, 0);
  for (int i = 0; i < N; ++i) {
    diag_[i] = entry(C_, i, i);
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      pos_[k] = entry(C_, i, col_[k]);
      if (pos_[k] < 0 || diag_[i] < 0) throw std::logic_error("variable viscosity: a pair outside the Laplacian's pattern");
      ++count[col_[k] + 1];
    }
  }
  // The rows that read m_c: those with a pair whose column is c (rows are also their own column).
  ref_off_.assign(N + 1, 0);
  for (int c = 0; c < N; ++c) ref_off_[c + 1] = ref_off_[c] + count[c + 1];
  ref_.resize(ref_off_[N]);
  std::vector<int> fill(ref_off_.begin(), ref_off_.end() - 1);
  for (int i = 0; i < N; ++i)
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) ref_[fill[col_[k]]++] = i;
  m_ = Vec::Ones(N);
  in_rows_.assign(N, 0);
  uniform_.assign(N, 1);
  mark_.assign(N, 0);
  where_.assign(N, -1);
  T_now_ = T_last_ = Mat2::Zero(N, 2);

  cg_ = std::make_unique<Cg>(*this, C0_solver);
}

VariableViscosity::~VariableViscosity() = default;
LinearSolver& VariableViscosity::solver() { return *cg_; }
LinearSolver& VariableViscosity::solver_for_step(long n, bool first) {
  cg_->begin_step(n, first);
  return *cg_;
}
const LinearSolver& VariableViscosity::solver() const { return *cg_; }

void VariableViscosity::assemble_row(int i) {
  // As assemble_pairs (operators.cpp) sums A = lap.A: the (i, col) entries in pair order (images of
  // i onto its diagonal first), then the diagonal sum; C = (-a) A, then + 1 on the diagonal
  // (crank_nicolson_matrix). m_ij = 1 gives the constant row bit for bit.
  double* c = C_.valuePtr();
  const int* o = C_.outerIndexPtr();
  std::fill(c + o[i], c + o[i + 1], 0.0);
  double diag = 0.0;
  for (int k = P_.offset[i]; k < P_.offset[i + 1]; ++k) {
    const double a = lap_[k] * pair_mean(k, i);  // 2 V m_ij F_ij
    diag += a;
    c[pos_[k]] += -sign_[k] * a;  // f_i - f_j, an image f_j = sign f_parent + c_j
  }
  c[diag_[i]] += diag;
  const double ma = -prm_.a;
  for (int e = o[i]; e < o[i + 1]; ++e) c[e] = ma * c[e];
  c[diag_[i]] += 1.0;
}

void VariableViscosity::set(const int* at, const double* m, int n) {
  touched_.clear();
  norm_stale_ = true;
  auto touch = [&](int r) {
    if (!mark_[r]) { mark_[r] = 1; touched_.push_back(r); }
  };
  for (int q = 0; q < n; ++q) {
    const int c = at[q];
    if (c < 0 || c >= N_) throw std::invalid_argument("variable viscosity: particle index out of range");
    if (!(m[q] > 0) || !std::isfinite(m[q]))
      throw std::invalid_argument("variable viscosity: m must be positive and finite (got " + std::to_string(m[q]) + ")");
    if (m[q] == m_[c]) continue;
    m_[c] = m[q];
    touch(c);
    for (int r = ref_off_[c]; r < ref_off_[c + 1]; ++r) touch(ref_[r]);
  }
  for (int i : touched_) {
    mark_[i] = 0;
    assemble_row(i);
    bool uniform = true;  // every pair sees m_i: the row is m_i times the constant one (off the diagonal)
    for (int k = P_.offset[i]; k < P_.offset[i + 1] && uniform; ++k) uniform = m_[col_[k]] == m_[i];
    const bool differs = !uniform || m_[i] != 1.0;
    uniform_[i] = uniform;
    if (differs && !in_rows_[i]) {
      in_rows_[i] = 1;
      where_[i] = static_cast<int>(rows_.size());
      rows_.push_back(i);
    } else if (!differs && in_rows_[i]) {  // out of the list: the last row takes its place
      in_rows_[i] = 0;
      const int last = rows_.back();
      rows_[where_[i]] = last;
      where_[last] = where_[i];
      rows_.pop_back();
      where_[i] = -1;
    }
  }
}

void VariableViscosity::row_terms(int i, const Mat2& u, const Mat2& c, const Mat2* c_star, const Mat2* g,
                                  double T[2], double D[2]) const {
  // One pass over the pairs of row i: the difference-form gradients (grad f)_i = sum_j V (f_j - f_i)
  // (x_i - x_j) F_ij of m and of both velocity components, and D = (L_m - L)(u; c + c*) - (L_m - L) g
  // (when given), an image of u carrying sign u_parent + c (Eq. 42), of g sign g_parent, of m its
  // parent's m. A uniform row (every pair sees m_i) has grad m = 0: T = 0.
  const double mi = m_[i];
  double gm[2] = {0, 0}, gu[2][2] = {{0, 0}, {0, 0}}, d[2] = {0, 0};  // gu[d][e] = d_e u_d
  const bool uniform = uniform_[i];
  for (int k = P_.offset[i]; k < P_.offset[i + 1]; ++k) {
    const int j = P_.j[k], p = col_[k];
    const bool image = j >= N_;
    double uj[2];
    for (int e = 0; e < 2; ++e) uj[e] = image ? sign_[k] * u(p, e) + c(j - N_, e) : u(p, e);
    const double w = lap_[k] * (pair_mean(k, i) - 1.0);  // 2 V (m_ij - 1) F_ij
    if (w != 0.0)
      for (int e = 0; e < 2; ++e) {
        double f = u(i, e) - (c_star && image ? uj[e] + (*c_star)(j - N_, e) : uj[e]);
        if (g) f -= (*g)(i, e) - (image ? sign_[k] : 1.0) * (*g)(p, e);
        d[e] += w * f;
      }
    if (uniform) continue;
    const double dm = m_[p] - mi;
    gm[0] += dm * gx_[k];
    gm[1] += dm * gy_[k];
    for (int e = 0; e < 2; ++e) {
      const double du = uj[e] - u(i, e);
      gu[e][0] += du * gx_[k];
      gu[e][1] += du * gy_[k];
    }
  }
  // [(grad u)^T grad m]_e = (d_e u_d)(d_d m)
  T[0] = gu[0][0] * gm[0] + gu[1][0] * gm[1];
  T[1] = gu[0][1] * gm[0] + gu[1][1] * gm[1];
  D[0] = d[0];
  D[1] = d[1];
}

void VariableViscosity::add_rhs(const Mat2& u, const Mat2& c_n, const Mat2& c_star, const Mat2& g, double kg, double k,
                                bool first, Mat2& rhs) {
  // T^n in the rows of m^n; T^{n-1} is kept (zero outside its rows)
  T_last_.swap(T_now_);
  t_rows_last_.swap(t_rows_now_);
  for (int i : t_rows_now_) T_now_.row(i).setZero();  // T^{n-2}'s rows
  t_rows_now_ = rows_;
  const double a = prm_.a;
  g_scaled_ = kg * g;  // (dt/rho) grad phi^n
  for (int i : rows_) {
    double T[2], D[2];
    row_terms(i, u, c_n, &c_star, &g_scaled_, T, D);
    T_now_(i, 0) = T[0];
    T_now_(i, 1) = T[1];
    // a (L_m - L) u^n with images of u^n (c^n) and the image terms of u* (c*) of Eq. (28), less
    // a (L_m - L) (dt/rho) grad phi^n (the commutator of the projection: see the header)
    rhs(i, 0) += a * D[0];
    rhs(i, 1) += a * D[1];
  }
  // + nu dt (3/2 T^n - 1/2 T^{n-1}) (Eq. 39's AB2; the first step: Euler)
  if (first) {
    for (int i : t_rows_now_) rhs.row(i) += k * T_now_.row(i);
    return;
  }
  for (int i : t_rows_now_) rhs.row(i) += (1.5 * k) * T_now_.row(i);
  for (int i : t_rows_last_) rhs.row(i) -= (0.5 * k) * T_last_.row(i);
}

void VariableViscosity::cross_term(const Mat2& u, const Mat2& c, Mat2& T) const {
  T.setZero(N_, 2);
  for (int i : rows_) {
    double t[2], d[2];
    row_terms(i, u, c, nullptr, nullptr, t, d);
    T(i, 0) = t[0];
    T(i, 1) = t[1];
  }
}

void VariableViscosity::laplacian(const Mat2& u, const Mat2& c, Mat2& out) const {
  out.setZero(N_, 2);
  for (int i = 0; i < N_; ++i)
    for (int k = P_.offset[i]; k < P_.offset[i + 1]; ++k) {
      const int j = P_.j[k], p = col_[k];
      const double w = lap_[k] * pair_mean(k, i);
      for (int e = 0; e < 2; ++e) {
        const double uj = j < N_ ? u(p, e) : sign_[k] * u(p, e) + c(j - N_, e);
        out(i, e) += w * (u(i, e) - uj);
      }
    }
}

void VariableViscosity::save(NamedArrays& st) const {
  st.emplace_back("viscous_cross_old", T_now_);  // T^n, the next step's T^{n-1}
  cg_->save(st);
}

void VariableViscosity::load(const NamedArrays& st) {
  const Mat2 T = state_entry(st, "viscous_cross_old", N_, 2);
  for (int i : t_rows_now_) T_now_.row(i).setZero();
  t_rows_now_.clear();
  for (int i = 0; i < N_; ++i)
    if (T(i, 0) != 0.0 || T(i, 1) != 0.0) {
      T_now_.row(i) = T.row(i);
      t_rows_now_.push_back(i);
    }
  cg_->load(st);
}

}  // namespace sphib
