#include "fluid/lagrangian.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {
using Clock = std::chrono::steady_clock;

void check_params(const FluidParams& p) {
  check_common_params(p);
  if (p.lagrangian.reinit_every < 0)
    throw std::invalid_argument("fluid: lagrangian.reinit_every must be >= 0 (0: never)");
  if (!(p.lagrangian.min_kernel_sum >= 0 && p.lagrangian.min_kernel_sum <= 1))
    throw std::invalid_argument("fluid: lagrangian.min_kernel_sum must lie in [0, 1]");
  if (p.projection == Projection::Exact)
    throw std::invalid_argument("fluid: LPSPH has the approximate projection only (fluid.projection = \"approximate\")");
}

// Eq. (61), normalised SPH interpolation of the K columns of f, carried by the points `from`, to the
// points `to`: out(k) = sum_j V f_j W(X_k - x_j) / sum_j V W(X_k - x_j) (uniform V cancels).
void interpolate_normalised(const Domain& d, const CubicSplineKernel& W, const Mat2& from, const Eigen::MatrixXd& f,
                            const Mat2& to, Eigen::MatrixXd& out) {
  const double support = W.support();
  Eigen::Vector2d lo(d.x0, d.y0), hi(d.x1, d.y1);
  if (!d.periodic_x) { lo[0] -= support; hi[0] += support; }  // room for the images
  if (!d.periodic_y) { lo[1] -= support; hi[1] += support; }
  CellGrid grid(lo, hi, d.periodic_x, d.periodic_y, support);
  grid.build(from);
  const int K = static_cast<int>(f.cols());
  out.resize(to.rows(), K);
  Eigen::RowVectorXd num(K);
  for (int k = 0; k < to.rows(); ++k) {
    num.setZero();
    double den = 0;
    grid.for_each_near(to(k, 0), to(k, 1), support, [&](int j, double, double, double r) {
      const double w = W.W(r);  // W(X_k - x_j, h), times V_j in both sums
      num += w * f.row(j);      // numerator of Eq. (61)
      den += w;                 // denominator of Eq. (61)
    });
    if (!(den > 0)) {
      std::ostringstream m;
      m << "LPSPH reinitialisation: lattice point " << k << " at (" << to(k, 0) << ", " << to(k, 1)
        << ") has no particle within 2h";
      throw std::runtime_error(m.str());
    }
    out.row(k) = num / den;
  }
}
// SolverKind::Auto for a matrix factorised again every step: the choice between simplicial and
// supernodal CHOLMOD by the numeric factorisation's time, not the solves' (factorize()'s rule,
// linear_solver.cpp). Measured here (one core, OpenBLAS, busy machine), ms simplicial/supernodal:
// nnz(L) = 1.2e4: 0.45/0.93; 4.2e4: 2.6/3.5; 6.2e4: 1.8/4.5; 9.4e4: 4.4/8.5; 1.5e5: 10.3/9.9;
// 2.0e5: 14.3/12.1; 2.9e5: 24.3/19.5; 3.8e5: 28.9/24.0; 5.9e5: 56.5/35.1. Supernodal above 1.5e5.
std::unique_ptr<LinearSolver> factorize_every_step(const std::string& system, const SpMat& A, SolverKind kind) {
  if (kind != SolverKind::Auto || !is_symmetric(A)) return factorize(system, A, kind);
  constexpr double kSupernodalLnz = 1.5e5;
  auto simplicial = factorize(system, A, SolverKind::CholmodSimplicial);
  std::ostringstream note;
  if (simplicial->info().nnz_factor <= kSupernodalLnz) {
    note << " (LPSPH auto: nnz(L) <= " << kSupernodalLnz << ")";
    simplicial->annotate(note.str(), 0.0);
    return simplicial;
  }
  const double t = simplicial->info().analyse_seconds + simplicial->info().factor_seconds;
  simplicial.reset();
  auto super = factorize(system, A, SolverKind::CholmodSupernodal);
  note << " (LPSPH auto: nnz(L) > " << kSupernodalLnz << ")";
  super->annotate(note.str(), t);
  return super;
}
}  // namespace

LagrangianFluid::LagrangianFluid(const FluidParams& params)
    : prm_(params), lat_(make_lattice(params.domain, params.nx, params.ny)),
      W_(params.h_over_dx * 0.5 * (lat_.dx + lat_.dy)), x_(lat_.x), x_star_(lat_.x) {
  check_params(prm_);
  const int N = lat_.size();
  u_ = u_star_ = u_star_old_ = rhs_ = grad_phi_ = Mat2::Zero(N, 2);
  phi_ = p_ = div_ = b_phi_ = S_ = Vec::Zero(N);
  V_ = Vec::Constant(N, lat_.volume);

  k_images_ = prof_.phase("images (Eq. 42)");
  k_rhs_ = prof_.phase("viscous rhs (Eq. 28)");
  k_solve_cn_ = prof_.phase("solve Crank-Nicolson");
  k_div_ = prof_.phase("divergence rhs (Eq. 32)");
  k_solve_poisson_ = prof_.phase("solve Poisson");
  k_project_ = prof_.phase("projection (Eq. 34)");
  k_move_ = prof_.phase("move particles (Eq. 37)");
  k_reinit_ = prof_.phase("reinitialisation (Eq. 61)");
  k_neighbours_ = prof_.phase("neighbours and images (cell list)");
  k_assembly_ = prof_.phase("operators (Eqs. 27-34)");
  k_factor_cn_ = prof_.phase("factorise Crank-Nicolson");
  k_factor_poisson_ = prof_.phase("factorise Poisson");
  k_pressure_ = prof_.phase("pressure (Eq. 35)");

  const RebuildSeconds s = rebuild(0.0);  // the first analysis and factorisations
  setup_.emplace_back("neighbours", s.neighbours);
  setup_.emplace_back("assembly", s.assembly);
  setup_.emplace_back("factorisation", s.factorisation_cn + s.factorisation_poisson);
}

LagrangianFluid::RebuildSeconds LagrangianFluid::rebuild(double t) {
  const Domain& d = prm_.domain;
  const int N = lat_.size();
  RebuildSeconds s;
  auto t0 = Clock::now();
  // Images of the current particles (Section 3.3) and the pair list by cell list, O(N). The reach is
  // 2h less 1e-12 relative: pairs at exactly 2h (lattice distances when 2h/dx is an integer, e.g.
  // h = 3 dx) have W = F = 0 but would enter and leave the pattern with the round-off of every move
  // (measured at h = 3 dx: the analysis kept in 1 of 100 Poiseuille steps instead of 100).
  const double reach = W_.support() * (1.0 - 1e-12);
  im_ = make_images(d, x_star_, reach);
  find_pairs(d, x_star_, im_.x, reach, pairs_);
  s.neighbours = seconds_since(t0);

  // Breakdown (Section 5.2.2, Fig. 18): S_i = V (W(0) + sum_j W_ij), images included.
  const double V = lat_.volume;
  int worst = 0;
  for (int i = 0; i < N; ++i) {
    double w = W_.W(0.0);
    for (int k = pairs_.offset[i]; k < pairs_.offset[i + 1]; ++k) w += W_.W(pairs_.r[k]);
    S_[i] = V * w;
    if (S_[i] < S_[worst]) worst = i;
  }
  S_low_ = std::min(S_low_, S_[worst]);
  if (S_[worst] < prm_.lagrangian.min_kernel_sum) {
    std::ostringstream m;
    m.precision(8);
    m << "LPSPH breakdown at t = " << t << ": particle " << worst << " at (" << x_star_(worst, 0)
      << ", " << x_star_(worst, 1) << ") has kernel sum " << S_[worst] << " < " << prm_.lagrangian.min_kernel_sum
      << " (" << pairs_.offset[worst + 1] - pairs_.offset[worst] << " neighbours within 2h, "
      << static_cast<double>(pairs_.size()) / N
      << " on average; particles driven apart; Section 5.2.2, Fig. 18)";
    throw std::runtime_error(m.str());
  }

  // Operators at the new positions (Eqs. 27-34), as build_operators makes them.
  t0 = Clock::now();
  make_pattern();
  const int K = pairs_.size();
  lap_.resize(K);
  gx_.resize(K);
  gy_.resize(K);
  for (int k = 0; k < K; ++k) {
    const double F = W_.F(pairs_.r[k]);  // (1/r) dW/dr
    lap_[k] = 2.0 * V * F;               // Eqs. (28), (31): 2 m (mu_i+mu_j)/(rho_i+rho_j)^2 -> 2 V per unit nu
    gx_[k] = V * pairs_.rx[k] * F;       // Eqs. (27), (30): V (x_i - x_j) F_ij
    gy_[k] = V * pairs_.ry[k] * F;
  }
  assemble(ImageRule::Velocity, lap_, true, op_.lap_u.A, &op_.lap_u.B);
  assemble(ImageRule::Velocity, gx_, false, op_.grad_ux.A, &op_.grad_ux.B);
  assemble(ImageRule::Velocity, gy_, false, op_.grad_uy.A, &op_.grad_uy.B);
  assemble(ImageRule::Scalar, lap_, true, op_.lap_phi, nullptr);
  assemble(ImageRule::Scalar, gx_, false, op_.grad_phix, nullptr);
  assemble(ImageRule::Scalar, gy_, false, op_.grad_phiy, nullptr);
  const int M = im_.size();
  c_wall_.resize(M, 2);
  c_star_.resize(M, 2);
  c_sum_.resize(M, 2);
  image_velocity_offsets(im_, d, nullptr, 0.0, c_wall_);  // 2 u_b: images of u^n
  const double a = 0.5 * nu() * prm_.dt;  // Crank-Nicolson factor nu dt / 2 (Eq. 28)
  A_cn_ = -a * op_.lap_u.A;                // (I - nu dt/2 lap) u* = ... (Eq. 28), same pattern
  for (int i = 0; i < N; ++i) A_cn_.valuePtr()[diag_[i]] += 1.0;
  // Poisson (Eq. 32) as the SPD system -lap phi = -(rho/dt) div u*, gauge as in EPSPH
  // (projection.cpp): the right-hand side projected onto zero mean (the range of the symmetric
  // singular matrix), phi = 0 at particle `pin_` (row and column replaced by the identity), then
  // phi shifted to zero mean. The zeros stay in the pattern (EPSPH prunes them), so that the pattern
  // is the pair list's.
  poisson_A_ = -op_.lap_phi;
  for (int k = poisson_A_.outerIndexPtr()[pin_]; k < poisson_A_.outerIndexPtr()[pin_ + 1]; ++k)
    poisson_A_.valuePtr()[k] = poisson_A_.innerIndexPtr()[k] == pin_ ? 1.0 : 0.0;
  for (int i = 0; i < N; ++i)
    for (SpMat::InnerIterator it(poisson_A_, i); it; ++it)
      if (it.col() == pin_ && i != pin_) it.valueRef() = 0.0;
  s.assembly = seconds_since(t0);

  // Factorisations: the symbolic analysis is kept while the pattern stays the same.
  t0 = Clock::now();
  if (!cn_) {
    cn_ = factorize_every_step("Crank-Nicolson", A_cn_, prm_.cn_solver);
    cn_iterative_ = cn_->info().nnz_factor == 0;
  } else {
    n_reused_cn_ += cn_->refactorize(A_cn_);
  }
  s.factorisation_cn = seconds_since(t0);
  t0 = Clock::now();
  if (!poisson_) {
    poisson_ = factorize_every_step("Poisson", poisson_A_, prm_.poisson_solver);
  } else {
    n_reused_poisson_ += poisson_->refactorize(poisson_A_);
    ++n_refactor_;
  }
  s.factorisation_poisson = seconds_since(t0);
  return s;
}

void LagrangianFluid::make_pattern() {
  const int N = lat_.size();
  const PairList& P = pairs_;
  outer_.assign(N + 1, 0);
  outer_b_.assign(N + 1, 0);
  inner_.clear();
  inner_b_.clear();
  slot_.resize(P.size());
  diag_.resize(N);
  std::vector<int> cols;
  for (int i = 0; i < N; ++i) {
    cols.assign(1, i);  // the f_i part of every pair term
    int images = 0;
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const int j = P.j[k];
      if (j < N) {
        cols.push_back(j);
      } else {  // an image couples i to its parent, and (velocity) to its offset c_m
        cols.push_back(im_.parent[j - N]);
        inner_b_.push_back(j - N);  // increasing in m: the pairs are sorted by j
        ++images;
      }
    }
    std::sort(cols.begin(), cols.end());
    cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
    const int begin = outer_[i];
    inner_.insert(inner_.end(), cols.begin(), cols.end());
    outer_[i + 1] = begin + static_cast<int>(cols.size());
    outer_b_[i + 1] = outer_b_[i] + images;
    auto where = [&](int col) {
      return begin + static_cast<int>(std::lower_bound(cols.begin(), cols.end(), col) - cols.begin());
    };
    diag_[i] = where(i);
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const int j = P.j[k];
      slot_[k] = where(j < N ? j : im_.parent[j - N]);
    }
  }
}

void LagrangianFluid::assemble(ImageRule rule, const std::vector<double>& a, bool difference, SpMat& A,
                               SpMat* B) const {
  const int N = lat_.size(), M = im_.size();
  auto shape = [](SpMat& S, int rows, int cols, const std::vector<int>& outer, const std::vector<int>& inner) {
    S.resize(rows, cols);  // compressed and empty
    S.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
    std::copy(outer.begin(), outer.end(), S.outerIndexPtr());
    std::copy(inner.begin(), inner.end(), S.innerIndexPtr());
    std::fill(S.valuePtr(), S.valuePtr() + inner.size(), 0.0);
  };
  shape(A, N, N, outer_, inner_);
  const bool velocity = rule == ImageRule::Velocity;
  if (B) shape(*B, N, M, outer_b_, inner_b_);
  double* va = A.valuePtr();
  double* vb = B ? B->valuePtr() : nullptr;
  const double s_ij = difference ? -1.0 : 1.0;  // f_i - f_j  or  f_i + f_j
  int b = 0;                                    // B's entries are the image pairs, in order
  for (int i = 0; i < N; ++i)
    for (int k = pairs_.offset[i]; k < pairs_.offset[i + 1]; ++k) {
      const int j = pairs_.j[k];
      va[diag_[i]] += a[k];  // the f_i part
      if (j < N) {
        va[slot_[k]] += s_ij * a[k];
      } else {  // image: f_j = sign f_p + c_j
        const double sign = velocity ? im_.v_sign[j - N] : 1.0;
        va[slot_[k]] += s_ij * sign * a[k];
        if (vb) vb[b] = s_ij * a[k];
        ++b;
      }
    }
}

void LagrangianFluid::wrap_into_domain(Mat2& X, double t) const {
  const Domain& d = prm_.domain;
  for (int i = 0; i < X.rows(); ++i) {
    double& x = X(i, 0);
    double& y = X(i, 1);
    if (d.periodic_x) {  // particles that leave at one end re-enter at the other (Section 5)
      x -= d.Lx() * std::floor((x - d.x0) / d.Lx());
      if (x >= d.x1) x = d.x0;  // round-off of the line above
    }
    if (d.periodic_y) {
      y -= d.Ly() * std::floor((y - d.y0) / d.Ly());
      if (y >= d.y1) y = d.y0;
    }
    const bool out_x = !d.periodic_x && !(x > d.x0 && x < d.x1);
    const bool out_y = !d.periodic_y && !(y > d.y0 && y < d.y1);
    if (out_x || out_y) {
      std::ostringstream m;
      m << "LPSPH: particle " << i << " left the domain through a wall at t = " << t << ": now at (" << x << ", " << y << "), domain [" << d.x0 << ", " << d.x1 << "] x [" << d.y0 << ", "
        << d.y1 << "]";
      throw std::runtime_error(m.str());
    }
  }
}

void LagrangianFluid::set_velocity(const Mat2& u0) {
  ++revision_;
  if (u0.rows() != u_.rows()) throw std::invalid_argument("fluid: initial velocity has the wrong size");
  u_ = u0;
  u_star_ = u_star_old_ = u0;  // PCG warm start
}

void LagrangianFluid::set_positions(const Mat2& x) {
  if (x.rows() != x_.rows()) throw std::invalid_argument("LPSPH: positions have the wrong size");
  x_ = x;
  wrap_into_domain(x_, t_);
  x_star_ = x_;
  rebuild(t_);
  p_step_ = -1;
}

void LagrangianFluid::step(const Mat2& F) {
  ++revision_;
  const double dt = prm_.dt, rho = prm_.rho, a = 0.5 * nu() * dt;
  {
    // The step's geometry at the predicted positions x* = x^n + dt u^n (see the header): images,
    // pairs, operators, factorisations. A breakdown throws here, before anything has changed.
    x_star_ = x_ + dt * u_;
    wrap_into_domain(x_star_, t_ + dt);
    const RebuildSeconds s = rebuild(t_ + dt);
    prof_.add(k_neighbours_, s.neighbours);
    prof_.add(k_assembly_, s.assembly);
    prof_.add(k_factor_cn_, s.factorisation_cn);
    prof_.add(k_factor_poisson_, s.factorisation_poisson);
  }
  const Operators& op = op_;  // at x*
  {
    ScopedTimer tm(prof_, k_images_);
    // Eq. (42): images of u* carry 2 (u_b + dt/rho [grad phi~]_tau) - u*, with phi~ = phi^n.
    image_velocity_offsets(im_, prm_.domain, &grad_phi_, dt / rho, c_star_);
    c_sum_ = c_wall_ + c_star_;
  }
  {
    ScopedTimer tm(prof_, k_rhs_);
    // Eq. (28): (I - a lap) u* = u^n + a lap u^n + a B (c^n + c*) + dt F^n / rho
    // (Lagrangian: no convection term, the particles carry it)
    rhs_.noalias() = op.lap_u.A * u_;
    rhs_.noalias() += op.lap_u.B * c_sum_;
    rhs_ *= a;
    rhs_ += u_;
    rhs_ += (dt / rho) * F;
  }
  {
    ScopedTimer tm(prof_, k_solve_cn_);
    if (cn_iterative_) {  // warm start from 2 u*_{n-1} - u*_{n-2} (direct solvers ignore it)
      u_star_old_ = 2.0 * u_star_ - u_star_old_;
      u_star_old_.swap(u_star_);
    }
    cn_->solve(rhs_.data(), u_star_.data(), 2);
  }
  {
    ScopedTimer tm(prof_, k_div_);
    // Eq. (30): div u* with images of u* (offsets c*); Eq. (32): -lap phi = -(rho/dt) div u*
    div_.noalias() = op.grad_ux.A * u_star_.col(0);
    div_.noalias() += op.grad_uy.A * u_star_.col(1);
    div_.noalias() += op.grad_ux.B * c_star_.col(0);
    div_.noalias() += op.grad_uy.B * c_star_.col(1);
    b_phi_ = (-rho / dt) * div_;
    b_phi_.array() -= b_phi_.mean();  // onto the range of the singular operator (gauge, see rebuild)
    b_phi_[pin_] = 0.0;
  }
  {
    ScopedTimer tm(prof_, k_solve_poisson_);
    poisson_->solve(b_phi_.data(), phi_.data(), 1);
    phi_.array() -= phi_.mean();
  }
  {
    ScopedTimer tm(prof_, k_move_);
    x_ += (0.5 * dt) * u_;  // Eq. (37), the u^n half
  }
  {
    ScopedTimer tm(prof_, k_project_);
    // Eq. (34): u^{n+1} = u* - dt/rho grad phi^{n+1}, images phi_i' = phi_i
    grad_phi_.col(0).noalias() = op.grad_phix * phi_;
    grad_phi_.col(1).noalias() = op.grad_phiy * phi_;
    u_ = u_star_ - (dt / rho) * grad_phi_;
  }
  t_ += dt;
  ++n_;
  {
    ScopedTimer tm(prof_, k_move_);
    x_ += (0.5 * dt) * u_;  // Eq. (37), the u^{n+1} half
    wrap_into_domain(x_, t_);
  }
  const int every = prm_.lagrangian.reinit_every;
  if (every > 0 && n_ % every == 0) {  // Figs. 9 C-D
    ScopedTimer tm(prof_, k_reinit_);
    onto_lattice();
  }
}

void LagrangianFluid::onto_lattice() {
  const Domain& d = prm_.domain;
  const int N = lat_.size();
  // The old particles and their images, with the values Eq. (61) averages: u^{n+1} images by
  // Eq. (42) without the phi~ term (the wall value, as for u^n in the step), phi_i' = phi_i
  // (Neumann), and grad phi_i' the mirror image of grad phi_i (the normal component changes sign).
  const Images im = make_images(d, x_, W_.support());
  const int M = im.size();
  Mat2 from(N + M, 2), c(M, 2);
  from.topRows(N) = x_;
  if (M) from.bottomRows(M) = im.x;
  image_velocity_offsets(im, d, nullptr, 0.0, c);
  Eigen::MatrixXd f(N + M, 5), g;  // u, v, phi, dphi/dx, dphi/dy
  f.block(0, 0, N, 2) = u_;
  f.col(2).head(N) = phi_;
  f.block(0, 3, N, 2) = grad_phi_;
  for (int m = 0; m < M; ++m) {
    const int p = im.parent[m], w = im.wall[m];
    f(N + m, 0) = im.v_sign[m] * u_(p, 0) + c(m, 0);
    f(N + m, 1) = im.v_sign[m] * u_(p, 1) + c(m, 1);
    f(N + m, 2) = phi_[p];
    const bool flip_x = w < 0 || w == Left || w == Right, flip_y = w < 0 || w == Bottom || w == Top;
    f(N + m, 3) = flip_x ? -grad_phi_(p, 0) : grad_phi_(p, 0);
    f(N + m, 4) = flip_y ? -grad_phi_(p, 1) : grad_phi_(p, 1);
  }
  interpolate_normalised(d, W_, from, f, lat_.x, g);  // Eq. (61) at the lattice points
  u_ = g.leftCols(2);
  phi_ = g.col(2);
  phi_.array() -= phi_.mean();  // gauge
  grad_phi_ = g.rightCols(2);
  u_star_ = u_star_old_ = u_;  // PCG warm start
  x_ = lat_.x;
  ++n_reinit_;
}

void LagrangianFluid::reinitialise() {
  onto_lattice();
  x_star_ = x_;
  rebuild(t_);
  p_step_ = -1;
}

const Vec& LagrangianFluid::p() const {
  if (p_step_ != n_) {
    ScopedTimer tm(prof_, k_pressure_);
    pressure_from_phi(op_.lap_phi, phi_, 0.5 * nu() * prm_.dt, p_);  // Eq. (35)
    p_step_ = n_;
  }
  return p_;
}

double LagrangianFluid::max_abs_divergence() const {
  Vec d = op_.grad_ux.A * u_.col(0) + op_.grad_uy.A * u_.col(1) + op_.grad_ux.B * c_wall_.col(0) +
          op_.grad_uy.B * c_wall_.col(1);
  return d.cwiseAbs().maxCoeff();
}

double LagrangianFluid::kinetic_energy() const { return 0.5 * prm_.rho * lat_.volume * u_.squaredNorm(); }

std::vector<SolverInfo> LagrangianFluid::solver_info() const { return {cn_->info(), poisson_->info()}; }

std::vector<std::string> LagrangianFluid::describe() const {
  std::ostringstream m;
  const int N = size();
  m << "LPSPH: " << lat_.nx << " x " << lat_.ny << " = " << N << " moving particles (Eq. 37), " << im_.size()
    << " images now, h = " << W_.h << " (" << prm_.h_over_dx << " (dx+dy)/2), "
    << static_cast<double>(pairs_.size()) / N
    << " neighbours per particle now; convection carried by the particle motion (no convection term); "
       "neighbours (cell list), images, operators and factorisations rebuilt every step at the predicted "
       "positions x* = x^n + dt u^n";
  std::vector<std::string> lines{m.str()};
  std::ostringstream r;
  r << "LPSPH: reinitialisation onto the lattice (Eq. 61) ";
  if (prm_.lagrangian.reinit_every > 0)
    r << "every " << prm_.lagrangian.reinit_every << " steps (" << n_reinit_ << " so far)";
  else
    r << "never";
  r << "; breakdown when a kernel sum falls below " << prm_.lagrangian.min_kernel_sum << " (lowest so far "
    << S_low_ << ", now " << S_.minCoeff() << ")";
  lines.push_back(r.str());
  std::ostringstream s;
  s << "LPSPH: symbolic analysis reused in " << n_reused_cn_ << " of " << n_refactor_
    << " steps (Crank-Nicolson) and " << n_reused_poisson_ << " of " << n_refactor_
    << " (Poisson): the sparsity pattern is unchanged while no pair enters or leaves 2h";
  lines.push_back(s.str());
  for (const auto& si : solver_info()) lines.push_back(si.describe() + " (the latest refactorisation)");
  return lines;
}

std::vector<std::pair<std::string, double>> LagrangianFluid::figures() const {
  std::vector<std::pair<std::string, double>> f{
      {"images", im_.size()},
      {"neighbours_per_particle", static_cast<double>(pairs_.size()) / size()},
      {"kernel_sum_min", S_.minCoeff()},
      {"kernel_sum_lowest", S_low_},
      {"refactorised_steps", static_cast<double>(n_refactor_)},
      {"symbolic_reused_steps_crank_nicolson", static_cast<double>(n_reused_cn_)},
      {"symbolic_reused_steps_poisson", static_cast<double>(n_reused_poisson_)},
      {"reinitialisations", static_cast<double>(n_reinit_)}};
  if (cn_->mean_iterations() > 0) f.emplace_back("crank_nicolson_cg_iterations", cn_->mean_iterations());
  return f;
}

NamedArrays LagrangianFluid::state() const {
  Eigen::MatrixXd clock(1, 7);
  clock << t_, static_cast<double>(n_), S_low_, static_cast<double>(n_refactor_), static_cast<double>(n_reused_cn_),
      static_cast<double>(n_reused_poisson_), static_cast<double>(n_reinit_);
  return {{"x", x_},           {"u", u_},                   {"phi", phi_},    {"grad_phi", grad_phi_},
          {"u_star", u_star_}, {"u_star_old", u_star_old_}, {"clock", clock}};
}

void LagrangianFluid::restore(const NamedArrays& state) {
  ++revision_;
  auto get = [&](const std::string& name, Eigen::Index rows, Eigen::Index cols) -> const Eigen::MatrixXd& {
    return state_entry(state, name, rows, cols);
  };
  const int N = size();
  const Eigen::MatrixXd& clock = get("clock", 1, 7);
  x_ = get("x", N, 2);
  u_ = get("u", N, 2);
  phi_ = get("phi", N, 1);
  grad_phi_ = get("grad_phi", N, 2);
  u_star_ = get("u_star", N, 2);
  u_star_old_ = get("u_star_old", N, 2);
  t_ = clock(0, 0);
  n_ = static_cast<long>(clock(0, 1));
  x_star_ = x_;
  rebuild(t_);  // the next step rebuilds at its own x* before using anything
  S_low_ = clock(0, 2);
  n_refactor_ = static_cast<long>(clock(0, 3));
  n_reused_cn_ = static_cast<long>(clock(0, 4));
  n_reused_poisson_ = static_cast<long>(clock(0, 5));
  n_reinit_ = static_cast<long>(clock(0, 6));
  p_step_ = -1;
}

double LagrangianFluid::setup_seconds(const std::string& what) const {
  for (const auto& [k, s] : setup_)
    if (k == what) return s;
  return 0.0;
}

}  // namespace sphib
