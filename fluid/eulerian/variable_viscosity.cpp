#include "fluid/eulerian/variable_viscosity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace sphib {

// Conjugate gradients on C_m, preconditioned by the constant matrix's solver M (C0^-1 on each
// component), warm-started (see solver_for_step), to |r| <= rtol |b| or a backward error
// |r| <= 1e-14 (|C_m| |x| + |b|), over the 2N unknowns at once (V_m couples the components).
class VariableViscosity::Cg final : public LinearSolver {
 public:
  Cg(const VariableViscosity& v, LinearSolver& M) : v_(v), M_(M) {
    for (Mat2& h : H_) h = Mat2::Zero(v.N_, 2);
    info_.system = "Crank-Nicolson (variable viscosity)";
    info_.n = v.N_;
    info_.nnz_A = 4 * v.C0_.nonZeros();  // (2N x 2N: the blocks of V_m couple u and v)
    info_.nnz_used = v.C0_.nonZeros() + 2 * static_cast<long>(v.P_.size());  // C0 and the pair weights, kept
    std::ostringstream m;
    m << "CG preconditioned by the constant-viscosity solver (" << M.info().method << "), rtol " << v.prm_.rtol
      << "; m > 1 in the central-force form, beta = gamma (1 + kappa (e_x^4 + e_y^4)), kappa = " << v.kappa_
      << ", gamma = " << v.gamma_;
    info_.method = m.str();
  }
  bool refactorize(const SpMat&) override { throw std::logic_error("variable viscosity: CG takes C_m in place"); }
  double mean_iterations() const override { return solves_ ? static_cast<double>(iterations_) / solves_ : 0.0; }

  void solve(const double* B, double* X, int k) override {
    if (k != 2) throw std::logic_error("variable viscosity: CG solves both velocity components at once");
    const int n = info_.n;
    const double a = v_.prm_.a;
    R_.resize(n, 2), Z_.resize(n, 2), P_.resize(n, 2), Q_.resize(n, 2), S_.resize(n, 2);
    Eigen::Map<const Mat2> b(B, n, 2);
    Eigen::Map<Mat2> x(X, n, 2);
    if (count_ >= 3 && last_ == step_ - 1)  // the quadratic extrapolation of the last three steps' u*
      for (int e = 0; e < 2; ++e)
        for (int i = 0; i < n; ++i) x(i, e) = 3.0 * (H_[h0_](i, e) - H_[(h0_ + 1) % 3](i, e)) + H_[(h0_ + 2) % 3](i, e);
    const double normA = v_.norm_C(), bn = b.norm();
    auto converged = [&](double rr, double xx) {
      const double r = std::sqrt(rr);
      return r <= v_.prm_.rtol * bn || r <= kBackward * (normA * std::sqrt(xx) + bn);
    };
    int it = 0;
    if (bn == 0.0) {
      x.setZero();
    } else {
      v_.product(X, R_.data());  // r0 = b - C_m x0, x0 the guess: the one product with the whole of C0
      R_ = b - R_;
      const bool exact = M_.exact();
      if (!converged(R_.squaredNorm(), x.squaredNorm())) {
        // PCG with M = C0^-1: z = C0^-1 r, so C0 z = r and C0 p = r + beta C0 p_old (S) follow
        // without a product with C0; C_m p = C0 p - a V_m p touches rows() only. (M iterative: C0 p
        // is not known that way, the product in full.)
        M_.solve(R_.data(), Z_.data(), 2);
        P_ = Z_;
        if (exact) S_ = R_;
        double rz = dot(R_, Z_);
        while (true) {
          if (++it > v_.prm_.max_iter) {
            std::ostringstream m;
            m << "variable viscosity: conjugate gradients on the Crank-Nicolson matrix did not converge in "
              << v_.prm_.max_iter << " iterations (n = " << n << ", relative residual " << R_.norm() / bn << ")";
            throw std::runtime_error(m.str());
          }
          if (exact) {
            Q_ = S_;
            v_.add_vm(P_.data(), Q_.data(), -a);  // q = C_m p
          } else {
            v_.product(P_.data(), Q_.data());
          }
          const double alpha = rz / dot(P_, Q_);
          double rr = 0, xx = 0;  // one pass: x += alpha p, r -= alpha q, |r|^2, |x|^2
          double *xv = x.data(), *rv = R_.data();
          const double *pv = P_.data(), *qv = Q_.data();
          for (int i = 0; i < 2 * n; ++i) {
            xv[i] += alpha * pv[i];
            rv[i] -= alpha * qv[i];
            rr += rv[i] * rv[i];
            xx += xv[i] * xv[i];
          }
          if (converged(rr, xx)) break;
          M_.solve(R_.data(), Z_.data(), 2);
          const double rz_new = dot(R_, Z_), beta = rz_new / rz;
          double *pw = P_.data(), *sw = S_.data();
          const double *zv = Z_.data();
          for (int i = 0; i < 2 * n; ++i) pw[i] = zv[i] + beta * pw[i];
          if (exact)
            for (int i = 0; i < 2 * n; ++i) sw[i] = rv[i] + beta * sw[i];
          rz = rz_new;
        }
      }
    }
    iterations_ += it;
    ++solves_;
    // the history: u*_n, u*_{n-1}, u*_{n-2} in H_[h0_], H_[h0_ + 1], H_[h0_ + 2] (mod 3)
    if (last_ != step_ - 1) count_ = 0;
    h0_ = (h0_ + 2) % 3;  // the oldest becomes the newest
    H_[h0_] = x;
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
    Eigen::MatrixXd h(info_.n, 6);
    for (int q = 0; q < 3; ++q) h.middleCols(2 * q, 2) = H_[(h0_ + q) % 3];
    st.emplace_back("viscous_start_history", h);
  }
  void load(const NamedArrays& st) {
    const Eigen::MatrixXd& c = state_entry(st, "viscous_start_count", 1, 2);
    const Eigen::MatrixXd& h = state_entry(st, "viscous_start_history", info_.n, 6);
    h0_ = 0;
    for (int q = 0; q < 3; ++q) H_[q] = h.middleCols(2 * q, 2);
    count_ = static_cast<int>(c(0, 0));
    last_ = static_cast<long>(c(0, 1));
  }

 private:
  static constexpr double kBackward = 1e-14;
  static double dot(const Mat2& a, const Mat2& b) { return a.col(0).dot(b.col(0)) + a.col(1).dot(b.col(1)); }
  const VariableViscosity& v_;
  LinearSolver& M_;
  Mat2 R_, Z_, P_, Q_, S_;  // S = C0 p
  long iterations_ = 0, solves_ = 0;
  Mat2 H_[3];               // the last three solutions, the newest H_[h0_] (see solve)
  int h0_ = 0;
  int count_ = 0;           // how many of them
  long step_ = 0, last_ = -2;  // the step of this solve and of the last one
};

VariableViscosity::VariableViscosity(const PairList& P, const Images& im, int N, double V, const CubicSplineKernel& W,
                                     const SpMat& C0, LinearSolver& C0_solver, const VariableViscosityParams& prm)
    : P_(P), im_(im), N_(N), prm_(prm), C0_(C0) {
  C0_.makeCompressed();
  st_ = find_row_stencil({&C0_});
  for (int i = 0; i < N; ++i) {
    double s = 0;
    for (int e = C0_.outerIndexPtr()[i]; e < C0_.outerIndexPtr()[i + 1]; ++e) s += std::fabs(C0_.valuePtr()[e]);
    norm_C0_ = std::max(norm_C0_, s);
  }
  const int K = P.size();
  lap_.resize(K), gx_.resize(K), gy_.resize(K), ex_.resize(K), ey_.resize(K), beta_.assign(K, 0.0);
  col_.resize(K), sign_.resize(K);
  bxx_.assign(K, 0.0), bxy_.assign(K, 0.0), byy_.assign(K, 0.0);
  for (int k = 0; k < K; ++k) {
    const double F = W.F(P.r[k]);  // (1/r) dW/dr
    lap_[k] = 2.0 * V * F;         // as build_operators: Eqs. (28), (31)
    gx_[k] = V * P.rx[k] * F;      // V (x_i - x_j) F_ij
    gy_[k] = V * P.ry[k] * F;
    ex_[k] = P.rx[k] / P.r[k];
    ey_[k] = P.ry[k] / P.r[k];
    const int j = P.j[k];
    col_[k] = j < N ? j : im.parent[j - N];
    sign_[k] = j < N ? 1.0 : im.v_sign[j - N];
  }
  // beta(e) = gamma (1 + kappa (e_x^4 + e_y^4)) from the moments of a full row (one with the most
  // pairs and no image): sum_j (-V F) beta r_a r_b r_c r_d / r^2 = s2 (delta_ab delta_cd + delta_ac
  // delta_bd + delta_ad delta_bc), s2 = sum_j (-V F) r_x^2 (the Morris Laplacian's scale): xxxx = 3 s2,
  // xxyy = s2 (x and y averaged: exact on a square lattice).
  int full = -1, most = -1;
  for (int i = 0; i < N; ++i) {
    bool images = false;
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) images |= P.j[k] >= N;
    if (!images && P.offset[i + 1] - P.offset[i] > most) most = P.offset[i + 1] - P.offset[i], full = i;
  }
  double s2 = 0, A4 = 0, A22 = 0, B4 = 0, B22 = 0;
  for (int k = full < 0 ? 0 : P.offset[full]; full >= 0 && k < P.offset[full + 1]; ++k) {
    const double w = -0.5 * lap_[k] * P.r[k] * P.r[k], x2 = ex_[k] * ex_[k], y2 = ey_[k] * ey_[k], t = x2 * x2 + y2 * y2;
    s2 += 0.5 * w * (x2 + y2);
    A4 += 0.5 * w * (x2 * x2 + y2 * y2);
    A22 += w * x2 * y2;
    B4 += 0.5 * w * (x2 * x2 + y2 * y2) * t;
    B22 += w * x2 * y2 * t;
  }
  if (!(B4 - 3 * B22 != 0.0) || !(A22 != 0.0)) {
    kappa_ = -2.0;  // no pairs off the lattice axes (h < dx / sqrt(2)): refused below
  } else {
    kappa_ = (3 * A22 - A4) / (B4 - 3 * B22);
    gamma_ = s2 / (A22 + kappa_ * B22);
  }
  if (!(kappa_ > -1.0) || !(gamma_ > 0))
    throw std::invalid_argument("kernel.h_over_dx: a viscosity contrast needs h >= 0.8 (dx + dy)/2 (its stress form "
                                "needs neighbours off the lattice axes)");
  for (int k = 0; k < K; ++k)
    if (P.j[k] < N) {
      const double x2 = ex_[k] * ex_[k], y2 = ey_[k] * ey_[k];
      beta_[k] = gamma_ * (1.0 + kappa_ * (x2 * x2 + y2 * y2));
    }
  // The rows that read m_c: those with a pair whose column is c (rows are also their own column).
  std::vector<int> count(N + 1, 0);
  for (int k = 0; k < K; ++k) ++count[col_[k] + 1];
  ref_off_.assign(N + 1, 0);
  for (int c = 0; c < N; ++c) ref_off_[c + 1] = ref_off_[c] + count[c + 1];
  ref_.resize(ref_off_[N]);
  std::vector<int> fill(ref_off_.begin(), ref_off_.end() - 1);
  for (int i = 0; i < N; ++i)
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) ref_[fill[col_[k]]++] = i;
  m_ = Vec::Ones(N);
  m_cap_ = prm.central ? 1.0 : std::numeric_limits<double>::infinity();
  in_rows_.assign(N, 0);
  cross_.assign(N, 0);
  mark_.assign(N, 0);
  where_.assign(N, -1);
  T_now_ = T_last_ = Mat2::Zero(N, 2);
  cg_ = std::make_unique<Cg>(*this, C0_solver);
}

VariableViscosity::~VariableViscosity() = default;
LinearSolver& VariableViscosity::solver() { return *cg_; }
const LinearSolver& VariableViscosity::solver() const { return *cg_; }
LinearSolver& VariableViscosity::solver_for_step(long n, bool first) {
  cg_->begin_step(n, first);
  return *cg_;
}

void VariableViscosity::weigh_row(int i) {
  bool differs = false, cross = false;
  const double mi = m_[i], mi_minus = std::min(mi, m_cap_);
  for (int k = P_.offset[i]; k < P_.offset[i + 1]; ++k) {
    const double mij = pair_mean(k, i);
    const double w = lap_[k] * (mij - 1.0);  // 2 V F_ij (m_ij - 1)
    if (prm_.central && mij >= 1.0 && beta_[k] > 0.0) {  // the central-force block w beta e e^T
      const double wb = w * beta_[k];
      bxx_[k] = wb * ex_[k] * ex_[k];
      bxy_[k] = wb * ex_[k] * ey_[k];
      byy_[k] = wb * ey_[k] * ey_[k];
    } else {  // the Morris block w I
      bxx_[k] = byy_[k] = w;
      bxy_[k] = 0.0;
    }
    differs |= mij != 1.0;
    cross |= std::min(m_[col_[k]], m_cap_) != mi_minus;
  }
  cross_[i] = cross;
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

void VariableViscosity::set(const int* at, const double* m, int n) {
  touched_.clear();
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
    weigh_row(i);
  }
}

template <class Value, class Offset>
void VariableViscosity::row_v(int i, Value&& f, Offset&& c, double out[2]) const {
  // sum over the pairs of the block B_k on f_i - f_j, f_j = sign f_parent + c at an image (Eq. 42)
  const double fi0 = f(i, 0), fi1 = f(i, 1);
  double s0 = 0, s1 = 0;
  for (int k = P_.offset[i]; k < P_.offset[i + 1]; ++k) {
    const int j = P_.j[k], p = col_[k];
    const double d0 = fi0 - (j < N_ ? f(p, 0) : sign_[k] * f(p, 0) + c(j - N_, 0));
    const double d1 = fi1 - (j < N_ ? f(p, 1) : sign_[k] * f(p, 1) + c(j - N_, 1));
    s0 += bxx_[k] * d0 + bxy_[k] * d1;
    s1 += bxy_[k] * d0 + byy_[k] * d1;
  }
  out[0] = s0;
  out[1] = s1;
}

void VariableViscosity::product(const double* x, double* y) const {
  apply2(C0_, x, y, &st_);  // (I - a L) x as a lattice stencil, then - a V_m x in the rows it touches
  add_vm(x, y, -prm_.a);
}

void VariableViscosity::add_vm(const double* x, double* y, double c) const {
  const double* x1 = x + N_;
  for (int i : rows_) {  // row_v without image offsets, on plain arrays
    const double xi0 = x[i], xi1 = x1[i];
    double s0 = 0, s1 = 0;
    for (int k = P_.offset[i]; k < P_.offset[i + 1]; ++k) {
      const int p = col_[k];
      const double d0 = xi0 - sign_[k] * x[p], d1 = xi1 - sign_[k] * x1[p];
      s0 += bxx_[k] * d0 + bxy_[k] * d1;
      s1 += bxy_[k] * d0 + byy_[k] * d1;
    }
    y[i] += c * s0;
    y[N_ + i] += c * s1;
  }
}

void VariableViscosity::row_cross(int i, const Mat2& u, const Mat2& c, double T[2]) const {
  // (grad f)_i = sum_j V (f_j - f_i) (x_i - x_j) F_ij of m_- and of both velocity components
  const double mi = std::min(m_[i], m_cap_);
  double gm[2] = {0, 0}, gu[2][2] = {{0, 0}, {0, 0}};  // gu[d][e] = d_e u_d
  for (int k = P_.offset[i]; k < P_.offset[i + 1]; ++k) {
    const int j = P_.j[k], p = col_[k];
    const double dm = std::min(m_[p], m_cap_) - mi;
    gm[0] += dm * gx_[k];
    gm[1] += dm * gy_[k];
    for (int e = 0; e < 2; ++e) {
      const double du = (j < N_ ? u(p, e) : sign_[k] * u(p, e) + c(j - N_, e)) - u(i, e);
      gu[e][0] += du * gx_[k];
      gu[e][1] += du * gy_[k];
    }
  }
  // [(grad u)^T grad m_-]_e = (d_e u_d)(d_d m_-)
  T[0] = gu[0][0] * gm[0] + gu[1][0] * gm[1];
  T[1] = gu[0][1] * gm[0] + gu[1][1] * gm[1];
}

double VariableViscosity::norm_C() const {
  // C0's, plus the sum of the blocks' absolute values over the pairs of the rows that differ
  double n = norm_C0_;
  for (int i : rows_) {
    double s = 0;
    for (int k = P_.offset[i]; k < P_.offset[i + 1]; ++k)
      s += std::fabs(bxx_[k]) + 2 * std::fabs(bxy_[k]) + std::fabs(byy_[k]);
    n = std::max(n, norm_C0_ + 2.0 * prm_.a * s);
  }
  return n;
}

void VariableViscosity::add_rhs(const Mat2& u, const Mat2& c_n, const Mat2& c_star, const Mat2& g, double kg, double k,
                                bool first, Mat2& rhs) {
  T_last_.swap(T_now_);  // T^n in the rows where grad m_- != 0; T^{n-1} kept (zero outside its rows)
  t_rows_last_.swap(t_rows_now_);
  for (int i : t_rows_now_) T_now_.row(i).setZero();  // T^{n-2}'s rows
  t_rows_now_.clear();
  // a V_m (u^n - (dt/rho) grad phi^n) with the images of u^n (c^n) and the image terms of u* (c*)
  // of Eq. (28); grad phi's images without offsets (the commutator of the projection: see the header)
  auto f = [&](int p, int e) { return u(p, e) - kg * g(p, e); };
  auto c = [&](int q, int e) { return c_n(q, e) + c_star(q, e); };
  const double a = prm_.a;
  for (int i : rows_) {
    double v[2];
    row_v(i, f, c, v);
    rhs(i, 0) += a * v[0];
    rhs(i, 1) += a * v[1];
    if (cross_[i]) {
      double T[2];
      row_cross(i, u, c_n, T);
      T_now_(i, 0) = T[0];
      T_now_(i, 1) = T[1];
      t_rows_now_.push_back(i);
    }
  }
  // + nu dt (3/2 T^n - 1/2 T^{n-1}) (Eq. 39's AB2; the first step: Euler)
  if (first) {
    for (int i : t_rows_now_) rhs.row(i) += k * T_now_.row(i);
    return;
  }
  for (int i : t_rows_now_) rhs.row(i) += (1.5 * k) * T_now_.row(i);
  for (int i : t_rows_last_) rhs.row(i) -= (0.5 * k) * T_last_.row(i);
}

void VariableViscosity::added_viscous_term(const Mat2& u, const Mat2& c, Mat2& out) const {
  out.setZero(N_, 2);
  auto f = [&](int p, int e) { return u(p, e); };
  auto off = [&](int q, int e) { return c(q, e); };
  for (int i : rows_) {
    double v[2], T[2] = {0, 0};
    row_v(i, f, off, v);
    if (cross_[i]) row_cross(i, u, c, T);
    out(i, 0) = v[0] + T[0];
    out(i, 1) = v[1] + T[1];
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
