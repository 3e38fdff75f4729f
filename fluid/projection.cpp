#include "fluid/projection.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {
using Clock = std::chrono::steady_clock;

}  // namespace

Fluid::Fluid(const FluidParams& params)
    : prm_(params), lat_(make_lattice(params.domain, params.nx, params.ny)),
      W_(params.h_over_dx * 0.5 * (lat_.dx + lat_.dy)) {
  check_common_params(prm_);
  const int N = lat_.size();

  // Neighbours: images and the pair list, once.
  auto t0 = Clock::now();
  im_ = make_images(lat_, W_.support());
  pairs_ = find_pairs(lat_, im_.x, W_.support());
  setup_.emplace_back("neighbours", seconds_since(t0));

  // Operators, once (Eqs. 27-34). The convection gradient is the divergence's, so Stokes flow
  // assembles nothing more; without convection grad_u is used only for the divergence.
  t0 = Clock::now();
  op_ = build_operators(pairs_, lat_, im_, W_);
  const double a = 0.5 * nu() * prm_.dt;  // Crank-Nicolson factor nu dt / 2 (Eq. 28)
  SpMat I(N, N);
  I.setIdentity();
  const SpMat A_cn = I - a * op_.lap_u.A;  // (I - nu dt/2 lap) u* = ... (Eq. 28)
  // Poisson (Eq. 32) as the SPD system -lap phi = -(rho/dt) div u*. Its null space is the constants
  // (periodic and homogeneous Neumann sides); gauge: phi = 0 at particle `pin_` (row and column
  // replaced by the identity) after projecting the right-hand side onto zero mean, which is the range
  // of the symmetric singular matrix, then phi shifted to zero mean.
  poisson_A_ = -op_.lap_phi;
  for (int k = poisson_A_.outerIndexPtr()[pin_]; k < poisson_A_.outerIndexPtr()[pin_ + 1]; ++k)
    poisson_A_.valuePtr()[k] = poisson_A_.innerIndexPtr()[k] == pin_ ? 1.0 : 0.0;
  for (int i = 0; i < N; ++i)
    for (SpMat::InnerIterator it(poisson_A_, i); it; ++it)
      if (it.col() == pin_ && i != pin_) it.valueRef() = 0.0;
  poisson_A_.prune(0.0);
  if (!same_pattern(op_.lap_u.A, op_.grad_ux.A) || !same_pattern(op_.grad_ux.A, op_.grad_uy.A) ||
      !same_pattern(op_.grad_phix, op_.grad_phiy))
    throw std::logic_error("fluid: the operators do not share one pattern (fused products need it)");
  vel_st_ = find_row_stencil({&op_.lap_u.A, &op_.grad_ux.A, &op_.grad_uy.A});
  phi_st_ = find_row_stencil({&op_.grad_phix, &op_.grad_phiy});
  setup_.emplace_back("assembly", seconds_since(t0));

  t0 = Clock::now();
  // Crank-Nicolson, auto: the eigenvalues of I - a lap lie in [1, 1 + b] with b the Gershgorin
  // bound 2 a max|lap_ii|. For b <= 0.5 (condition number <= 1.5), warm-started Jacobi-PCG
  // reaches round-off in 4-6 iterations (measured iterations per step: b = 0.015: 4.0 (oscillating
  // membrane), 0.15: 5.4; 0.78: 8.2 (equilibrium membrane), 0.93: 14 (Poiseuille)), each a pass
  // over A (1/4 to 1/5 of the factor's non-zeros): cheaper than the two triangular solves.
  // On a lattice periodic in x and walled in y the FFT solver (fluid/fft_poisson.hpp) comes first:
  // at 64 x 64 one solve of u and v takes ~35 us against ~90 us for PCG and ~300 us for CHOLMOD.
  SolverKind cn_kind = prm_.cn_solver;
  std::string cn_fft_why;
  if (cn_kind == SolverKind::Auto || cn_kind == SolverKind::Fft) {
    cn_ = make_fft_solver("Crank-Nicolson", A_cn, lat_, false, &cn_fft_why);
    if (cn_ && cn_kind == SolverKind::Auto) cn_->annotate(" (auto: periodic in x, walled in y)", 0.0);
    if (!cn_ && cn_kind == SolverKind::Fft)
      throw std::invalid_argument("solver.crank_nicolson = \"fft\" does not apply: " + cn_fft_why);
  }
  if (!cn_) {
    const double b = 2.0 * a * op_.lap_u.A.diagonal().cwiseAbs().maxCoeff();
    if (cn_kind == SolverKind::Auto && b <= 0.5) cn_kind = SolverKind::Pcg;
    cn_ = factorize("Crank-Nicolson", A_cn, cn_kind);
    if (prm_.cn_solver == SolverKind::Auto) {
      std::ostringstream note;
      note << " (auto: no FFT solver: " << cn_fft_why << "; Gershgorin bound nu dt max|lap_ii| = " << b
           << (b <= 0.5 ? " <= 0.5)" : " > 0.5)");
      cn_->annotate(note.str(), 0.0);
    }
  }
  cn_iterative_ = cn_->info().nnz_factor == 0;
  // Poisson, auto: on a lattice periodic in x and walled in y the operator is block circulant in x
  // and the FFT solver (fluid/fft_poisson.hpp) solves it in O(N log nx); it takes -lap phi itself
  // (singular, its own gauge), so the pin is left out of the right-hand side. Otherwise CHOLMOD.
  std::string fft_note;
  if (prm_.poisson_solver == SolverKind::Auto || prm_.poisson_solver == SolverKind::Fft) {
    std::string why;
    poisson_ = make_fft_solver("Poisson", -op_.lap_phi, lat_, true, &why);
    if (poisson_) {
      poisson_fft_ = true;
      if (prm_.poisson_solver == SolverKind::Auto) poisson_->annotate(" (auto: periodic in x, walled in y)", 0.0);
    } else if (prm_.poisson_solver == SolverKind::Fft) {
      throw std::invalid_argument("solver.poisson = \"fft\" does not apply: " + why);
    } else {
      fft_note = " (auto: no FFT solver: " + why + ")";
    }
  }
  if (!poisson_) {
    poisson_ = factorize("Poisson", poisson_A_, prm_.poisson_solver);
    if (!fft_note.empty()) poisson_->annotate(fft_note, 0.0);
  }
  setup_.emplace_back("factorisation", seconds_since(t0));

  const int M = im_.size();
  u_ = Mat2::Zero(N, 2);
  du_dx_ = du_dy_ = u_star_ = u_star_old_ = rhs_ = conv_ = conv_old_ = grad_phi_ = Mat2::Zero(N, 2);
  c_wall_ = c_star_ = Mat2::Zero(M, 2);
  image_velocity_offsets(im_, lat_.domain, nullptr, 0.0, c_wall_);  // 2 u_b: images of u^n
  lap_b_rows_ = nonempty_rows(op_.lap_u.B);
  gx_b_rows_ = nonempty_rows(op_.grad_ux.B);
  gy_b_rows_ = nonempty_rows(op_.grad_uy.B);
  conv_wall_x_ = conv_wall_y_ = lap_wall_ = Mat2::Zero(N, 2);  // the wall values' terms, once
  add_image_terms(op_.grad_ux.B, gx_b_rows_, c_wall_, conv_wall_x_);
  add_image_terms(op_.grad_uy.B, gy_b_rows_, c_wall_, conv_wall_y_);
  add_image_terms(op_.lap_u.B, lap_b_rows_, c_wall_, lap_wall_);
  phi_ = p_ = div_ = b_phi_ = Vec::Zero(N);
  V_ = Vec::Constant(N, lat_.volume);

  k_images_ = prof_.phase("images (Eq. 42)");
  k_conv_ = prof_.phase("convection (Eqs. 39-41)");
  k_rhs_ = prof_.phase("viscous rhs (Eq. 28)");
  k_solve_cn_ = prof_.phase("solve Crank-Nicolson");
  k_div_ = prof_.phase("divergence rhs (Eq. 32)");
  k_solve_poisson_ = prof_.phase("solve Poisson");
  k_project_ = prof_.phase("projection (Eq. 34)");
  k_pressure_ = prof_.phase("pressure (Eq. 35)");
}

void Fluid::set_velocity(const Mat2& u0) {
  ++revision_;
  if (u0.rows() != u_.rows()) throw std::invalid_argument("fluid: initial velocity has the wrong size");
  u_ = u0;
  first_ = true;
}

void Fluid::step(const Mat2& F) {
  ++revision_;
  const double dt = prm_.dt, rho = prm_.rho, a = 0.5 * nu() * dt;
  const Operators& op = op_;
  {
    ScopedTimer tm(prof_, k_images_);
    // Eq. (42): images of u* carry 2 (u_b + dt/rho [grad phi~]_tau) - u*, with phi~ = phi^n.
    image_velocity_offsets(im_, lat_.domain, &grad_phi_, dt / rho, c_star_);
  }
  const int N = size();
  if (prm_.convection) {
    ScopedTimer tm(prof_, k_conv_);
    // Eqs. (40)-(41): (u.grad)u_i = u_i (d/dx)u + v_i (d/dy)u with images of u^n (wall values);
    // Eq. (39): AB2, 3/2 N^n - 1/2 N^{n-1} (first step: Euler, N^{-1} = N^0); conv_old_ keeps N^n.
    gradient2(op.grad_ux.A, op.grad_uy.A, u_, du_dx_, du_dy_, &vel_st_);  // one pass for the four derivatives
    for (int c = 0; c < 2; ++c)
      for (int i = 0; i < N; ++i) {
        const double n = (du_dx_(i, c) + conv_wall_x_(i, c)) * u_(i, 0) + (du_dy_(i, c) + conv_wall_y_(i, c)) * u_(i, 1);
        conv_(i, c) = 1.5 * n - 0.5 * (first_ ? n : conv_old_(i, c));
        conv_old_(i, c) = n;
      }
  }
  {
    ScopedTimer tm(prof_, k_rhs_);
    // Eq. (28): (I - a lap) u* = u^n + a lap u^n + a B (c^n + c*) - dt (u.grad u)^{n+1/2} + dt F^n / rho
    apply2(op.lap_u.A, u_, rhs_, &vel_st_);  // lap u^n, both components in one pass
    add_image_terms(op.lap_u.B, lap_b_rows_, c_star_, rhs_);
    const double k = dt / rho, kc = prm_.convection ? dt : 0.0;
    for (int c = 0; c < 2; ++c)
      for (int i = 0; i < N; ++i)
        rhs_(i, c) = (rhs_(i, c) + lap_wall_(i, c)) * a + u_(i, c) + k * F(i, c) - kc * conv_(i, c);
  }
  {
    ScopedTimer tm(prof_, k_solve_cn_);
    // u and v: two right-hand sides of one factorisation. An iterative solver starts from the
    // linear extrapolation 2 u*_{n-1} - u*_{n-2} (direct solvers ignore it).
    if (cn_iterative_) {
      u_star_old_ = 2.0 * u_star_ - u_star_old_;
      u_star_old_.swap(u_star_);  // u_star_ = guess, u_star_old_ = u*_{n-1}
    }
    cn_->solve(rhs_.data(), u_star_.data(), 2);
  }
  {
    ScopedTimer tm(prof_, k_div_);
    // Eq. (30): div u* with images of u* (offsets c*); Eq. (32): -lap phi = -(rho/dt) div u*
    divergence(op.grad_ux.A, op.grad_uy.A, u_star_, div_, &vel_st_);
    add_image_terms(op.grad_ux.B, gx_b_rows_, c_star_.col(0).data(), div_.data());
    add_image_terms(op.grad_uy.B, gy_b_rows_, c_star_.col(1).data(), div_.data());
    double sum = 0;
    for (int i = 0; i < N; ++i) sum += b_phi_[i] = (-rho / dt) * div_[i];
    const double mean = sum / N;
    for (int i = 0; i < N; ++i) b_phi_[i] -= mean;  // onto the range of the singular operator (gauge, see constructor)
    if (!poisson_fft_) b_phi_[pin_] = 0.0;
  }
  {
    ScopedTimer tm(prof_, k_solve_poisson_);
    poisson_->solve(b_phi_.data(), phi_.data(), 1);
    phi_.array() -= phi_.mean();
  }
  {
    ScopedTimer tm(prof_, k_project_);
    // Eq. (34): u^{n+1} = u* - dt/rho grad phi^{n+1}, images phi_i' = phi_i
    gradient(op.grad_phix, op.grad_phiy, phi_, grad_phi_, &phi_st_);
    u_.noalias() = u_star_ - (dt / rho) * grad_phi_;
  }
  first_ = false;
  t_ += dt;
  ++n_;
}

const Vec& Fluid::p() const {
  if (p_step_ != n_) {
    ScopedTimer tm(prof_, k_pressure_);
    pressure_from_phi(op_.lap_phi, phi_, 0.5 * nu() * prm_.dt, p_);  // Eq. (35)
    p_step_ = n_;
  }
  return p_;
}

double Fluid::max_abs_divergence() const {
  Vec d(size());
  divergence(op_.grad_ux.A, op_.grad_uy.A, u_, d, &vel_st_);
  add_image_terms(op_.grad_ux.B, gx_b_rows_, c_wall_.col(0).data(), d.data());
  add_image_terms(op_.grad_uy.B, gy_b_rows_, c_wall_.col(1).data(), d.data());
  return d.cwiseAbs().maxCoeff();
}

double Fluid::kinetic_energy() const { return 0.5 * prm_.rho * lat_.volume * u_.squaredNorm(); }

double Fluid::poisson_residual() const {
  const double nb = b_phi_.norm();
  Vec r;
  if (poisson_fft_) {
    r = -(op_.lap_phi * phi_) - b_phi_;  // the operator the FFT solver solves: -lap phi
  } else {
    Vec phi_pinned = phi_.array() - phi_[pin_];
    r = poisson_A_ * phi_pinned - b_phi_;
  }
  return nb > 0 ? r.norm() / nb : r.norm();
}

std::vector<SolverInfo> Fluid::solver_info() const { return {cn_->info(), poisson_->info()}; }

std::vector<std::string> Fluid::describe() const {
  std::ostringstream m;
  m << "EPSPH: " << lat_.nx << " x " << lat_.ny << " = " << size() << " fixed particles, " << im_.size()
    << " images, h = " << W_.h << " (" << prm_.h_over_dx << " (dx+dy)/2), "
    << static_cast<double>(pairs_.size()) / size() << " neighbours per particle, convection "
    << (prm_.convection ? "on" : "off (Stokes)") << "; products: " << vel_st_.stencil_rows() << " velocity and "
    << phi_st_.stencil_rows() << " phi rows of " << size() << " applied as a lattice stencil";
  std::vector<std::string> lines{m.str()};
  for (const auto& si : solver_info()) lines.push_back(si.describe());
  return lines;
}

std::vector<std::pair<std::string, double>> Fluid::figures() const {
  std::vector<std::pair<std::string, double>> f{{"images", im_.size()},
                                                {"neighbours_per_particle", static_cast<double>(pairs_.size()) / size()}};
  if (cn_->mean_iterations() > 0) f.emplace_back("crank_nicolson_cg_iterations", cn_->mean_iterations());
  return f;
}

double Fluid::floor_seconds(int reps) const {
  const Operators& op = op_;
  Mat2 a = u_, b = u_, c = u_, x = u_star_;
  Vec d(size()), f = phi_;
  auto best = [&](auto&& kernel) {
    double t = 1e300;
    for (int r = 0; r < reps; ++r) {
      const auto t0 = Clock::now();
      kernel();
      t = std::min(t, seconds_since(t0));
    }
    return t;
  };
  double total = 0;
  if (prm_.convection) total += best([&] { gradient2(op.grad_ux.A, op.grad_uy.A, u_, a, b, &vel_st_); });
  total += best([&] { apply2(op.lap_u.A, u_, c, &vel_st_); });
  total += best([&] { divergence(op.grad_ux.A, op.grad_uy.A, u_star_, d, &vel_st_); });
  total += best([&] { gradient(op.grad_phix, op.grad_phiy, phi_, a, &phi_st_); });
  total += best([&] {
    x = u_star_;  // the same warm start a step gives an iterative solver
    cn_->solve(rhs_.data(), x.data(), 2);
  });
  total += best([&] { poisson_->solve(b_phi_.data(), f.data(), 1); });
  return total;
}

// The state after step n: u^n, the convection N^n kept for AB2 (Eq. 39), phi^n and grad phi^n
// (Eq. 42), the last two u* (the warm start of an iterative Crank-Nicolson solver), t_n and n.
NamedArrays Fluid::state() const {
  Eigen::MatrixXd clock(1, 3);
  clock << t_, static_cast<double>(n_), first_ ? 1.0 : 0.0;
  return {{"u", u_},           {"conv_old", conv_old_}, {"phi", phi_},   {"grad_phi", grad_phi_},
          {"u_star", u_star_}, {"u_star_old", u_star_old_}, {"clock", clock}};
}

void Fluid::restore(const NamedArrays& state) {
  ++revision_;
  auto get = [&](const std::string& name, Eigen::Index rows, Eigen::Index cols) -> const Eigen::MatrixXd& {
    return state_entry(state, name, rows, cols);
  };
  const int N = size();
  u_ = get("u", N, 2);
  conv_old_ = get("conv_old", N, 2);
  phi_ = get("phi", N, 1);
  grad_phi_ = get("grad_phi", N, 2);
  u_star_ = get("u_star", N, 2);
  u_star_old_ = get("u_star_old", N, 2);
  const Eigen::MatrixXd& clock = get("clock", 1, 3);
  t_ = clock(0, 0);
  n_ = static_cast<long>(clock(0, 1));
  first_ = clock(0, 2) != 0.0;
  p_step_ = -1;
}

double Fluid::setup_seconds(const std::string& what) const {
  for (const auto& [k, s] : setup_)
    if (k == what) return s;
  return 0.0;
}

}  // namespace sphib
