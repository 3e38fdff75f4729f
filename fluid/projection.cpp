#include "fluid/projection.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
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
  if (prm_.projection == Projection::Auto) prm_.projection = Projection::Exact;
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
  // Poisson (Eq. 32) as a symmetric semi-definite system A phi = -(rho/dt) D u*.
  // Exact projection: D = -G^T, the divergence of a vector field whose wall images mirror it (tangential
  // part even, normal part odd), and A = G^T G = -D G, so that u^{n+1} = u* - dt/rho G phi is the
  // orthogonal projection of u* onto D u = 0: D u^{n+1} = 0 to solver precision, and the projection
  // cannot amplify anything, however small the eigenvalues of A near its grid-scale null modes.
  // (The velocity divergence of Eq. (30) takes no-slip images, tangential part odd; with it the
  // projection would be oblique and, with A's tiny eigenvalues, unstable: measured on Poiseuille at
  // h = 3 dx. The two differ only in the rows within 2h of a wall.)
  // Approximate (the paper): A = -lap phi (Eq. 31), D from Eq. (30).
  // The null space (fluid/gauge.hpp) is fixed by projecting the right-hand side onto its complement,
  // pinning phi = 0 at one particle per null vector for a direct factorisation, and removing the
  // null components from phi after the solve.
  const bool exact = prm_.projection == Projection::Exact;
  SpMat A_phi;
  if (exact) {
    div_x_ = -SpMat(op_.grad_phix.transpose());
    div_y_ = -SpMat(op_.grad_phiy.transpose());
    div_st_ = find_row_stencil({&div_x_, &div_y_});
    A_phi = -(SpMat(div_x_ * op_.grad_phix) + SpMat(div_y_ * op_.grad_phiy));
  } else {
    A_phi = -op_.lap_phi;
  }
  gauge_ = Gauge(lat_, exact ? NullSpace::GradientEvenImages : NullSpace::Constants);
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
  // and the FFT solver (fluid/fft_poisson.hpp) solves it in O(N log nx); it takes the singular
  // operator itself (its own gauge), so no pin enters the right-hand side. Otherwise CHOLMOD.
  poisson_ = poisson_solver(exact ? "Poisson (exact projection, G^T G)" : "Poisson", A_phi, gauge_,
                            prm_.poisson_solver, &poisson_fft_);
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
  c_normal_ = Mat2::Zero(M, 2);
  for (int m = 0; m < M; ++m) {  // the exact projection's images: u_n' = 2 u_w.n - u_n (corners: walls at rest)
    const int w = im_.wall[m];
    if (w < 0) continue;
    const int nrm = (w == Left || w == Right) ? 0 : 1;
    c_normal_(m, nrm) = 2.0 * lat_.domain.wall_velocity[w][nrm];
  }
  V_ = Vec::Constant(N, lat_.volume);

  k_images_ = prof_.phase("images (Eq. 42)");
  k_conv_ = prof_.phase("convection (Eqs. 39-41)");
  k_rhs_ = prof_.phase("viscous rhs (Eq. 28)");
  k_solve_cn_ = prof_.phase("solve Crank-Nicolson");
  k_div_ = prof_.phase("divergence rhs (Eq. 32)");
  k_solve_poisson_ = prof_.phase("solve Poisson");
  k_project_ = prof_.phase("projection (Eq. 34)");
  k_pressure_ = prof_.phase("pressure (Eq. 35)");
  k_psi_ = prof_.phase("stream function");
}

std::unique_ptr<LinearSolver> Fluid::poisson_solver(const std::string& system, const SpMat& A, const Gauge& g,
                                                    SolverKind kind, bool* fft) const {
  std::string why;
  *fft = false;
  if (kind == SolverKind::Auto || kind == SolverKind::Fft) {
    auto s = make_fft_solver(system, A, lat_, g.dimension() > 0, &why);
    if (s) {
      *fft = true;
      if (kind == SolverKind::Auto) s->annotate(" (auto: periodic in x, walled in y)", 0.0);
      return s;
    }
    if (kind == SolverKind::Fft) throw std::invalid_argument("solver.poisson = \"fft\" does not apply: " + why);
    why = " (auto: no FFT solver: " + why + ")";
  }
  const SpMat P = g.dimension() > 0 ? g.pinned(A) : A;
  auto s = factorize(system, P, kind);
  if (!why.empty()) s->annotate(why, 0.0);
  return s;
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
    if (prm_.projection == Projection::Exact) {
      exact_divergence(u_star_, div_);  // D u*, D = -G^T (constructor)
    } else {
      // Eq. (30): div u* with images of u* (offsets c*)
      divergence(op.grad_ux.A, op.grad_uy.A, u_star_, div_, &vel_st_);
      add_image_terms(op.grad_ux.B, gx_b_rows_, c_star_.col(0).data(), div_.data());
      add_image_terms(op.grad_uy.B, gy_b_rows_, c_star_.col(1).data(), div_.data());
    }
    // Eq. (32): A phi = -(rho/dt) D u*
    for (int i = 0; i < N; ++i) b_phi_[i] = (-rho / dt) * div_[i];
    gauge_.project(b_phi_);  // onto the range of the singular operator (gauge, see constructor)
    if (!poisson_fft_) gauge_.pin_rhs(b_phi_);
  }
  {
    ScopedTimer tm(prof_, k_solve_poisson_);
    poisson_->solve(b_phi_.data(), phi_.data(), 1);
    if (gauge_.dimension() == 1) phi_.array() -= phi_.mean();
    else gauge_.project(phi_);
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

void Fluid::exact_divergence(const Mat2& u, Vec& d) const {
  divergence(div_x_, div_y_, u, d, &div_st_);
  add_image_terms(op_.grad_ux.B, gx_b_rows_, c_normal_.col(0).data(), d.data());
  add_image_terms(op_.grad_uy.B, gy_b_rows_, c_normal_.col(1).data(), d.data());
}

const Vec& Fluid::p() const {
  if (p_step_ != n_) {
    ScopedTimer tm(prof_, k_pressure_);
    const double a = 0.5 * nu() * prm_.dt;
    if (prm_.projection == Projection::Approximate) {
      pressure_from_phi(op_.lap_phi, phi_, a, p_);  // Eq. (35)
    } else {
      // Eq. (35) with the Laplacian of the exact projection, D G = -G^T G:
      // p = phi + (nu dt/2) G^T G phi. phi's null components are removed (fluid/gauge.hpp), so
      // no checkerboard remains (tests/test_projection.cpp).
      p_.noalias() = div_x_ * grad_phi_.col(0);  // -G^T G phi = D G phi, G phi = grad_phi_
      p_.noalias() += div_y_ * grad_phi_.col(1);
      p_ = phi_ - a * p_;
    }
    p_step_ = n_;
  }
  return p_;
}

double Fluid::max_abs_divergence() const {
  Vec d(size());
  if (prm_.projection == Projection::Exact) {
    exact_divergence(u_, d);  // the divergence the projection makes zero
  } else {  // Eq. (30) with the no-slip images of u^n
    divergence(op_.grad_ux.A, op_.grad_uy.A, u_, d, &vel_st_);
    add_image_terms(op_.grad_ux.B, gx_b_rows_, c_wall_.col(0).data(), d.data());
    add_image_terms(op_.grad_uy.B, gy_b_rows_, c_wall_.col(1).data(), d.data());
  }
  return d.cwiseAbs().maxCoeff();
}

void Fluid::make_psi_solver() const {
  // psi's images are odd (psi = psi_w on the wall): the velocity rule's operators, whose B takes
  // the offsets 2 psi_w. Normal equations of min |(Gy psi + By c, -(Gx psi + Bx c)) - u|^2:
  //   (Gy^T Gy + Gx^T Gx) psi = Gy^T u - Gx^T v - Q (Gy^T By + Gx^T Bx) c1,
  // c1 the offsets of unit flux Q (2 on the images of the top wall, or of the right wall).
  const SpMat& Gx = op_.grad_ux.A;
  const SpMat& Gy = op_.grad_uy.A;
  psi_ty_ = Gy.transpose();
  psi_tx_ = -SpMat(Gx.transpose());
  psi_st_ = find_row_stencil({&psi_ty_, &psi_tx_});
  const Domain& d = lat_.domain;
  const bool periodic = d.periodic_x && d.periodic_y;
  psi_gauge_ = Gauge(lat_, NullSpace::GradientOddImages);
  const SpMat A = psi_ty_ * Gy + SpMat(Gx.transpose()) * Gx;
  bool fft = false;
  psi_solver_ = poisson_solver("stream function (G^T G, odd images)", A, psi_gauge_,
                               prm_.poisson_solver == SolverKind::Fft ? SolverKind::Auto : prm_.poisson_solver,
                               &fft);
  psi_fft_ = fft;
  const int N = size(), M = im_.size();
  psi_flux_ = Vec::Zero(N);
  psi_ = b_psi_ = Vec::Zero(N);
  const Side far = d.periodic_x && !d.periodic_y ? Top : Right;  // the wall that carries psi = Q
  if (!periodic && (d.periodic_x != d.periodic_y)) {
    Vec c1 = Vec::Zero(M);
    for (int m = 0; m < M; ++m)
      if (im_.wall[m] == far) c1[m] = 2.0;
    const Vec by = op_.grad_uy.B * c1, bx = op_.grad_ux.B * c1;
    psi_flux_ = psi_ty_ * by - psi_tx_ * bx;  // Gy^T By c1 + Gx^T Bx c1
    // The flux Q by least squares too: with C psi + Q b1 the velocity of (psi, Q) (b1 = (By c1,
    // -Bx c1)), the best Q for u is <u, r1> / <r1, r1> with r1 = (I - P_C) b1 = C psi1 + b1,
    // psi1 = -(C^T C)^{-1} C^T b1 (P_C the orthogonal projection onto the curls). (The flux from the
    // mean velocity would be off by the lattice's second kernel moment: G of a linear function is
    // not exactly its slope.)
    Vec b = -psi_flux_, psi1 = Vec::Zero(N);
    psi_gauge_.project(b);
    if (!psi_fft_) psi_gauge_.pin_rhs(b);
    psi_solver_->solve(b.data(), psi1.data(), 1);
    psi_gauge_.project(psi1);
    psi_r1_.resize(N, 2);
    psi_r1_.col(0) = Gy * psi1 + by;
    psi_r1_.col(1) = -(Gx * psi1 + bx);
    psi_r1_ /= psi_r1_.squaredNorm();
  }
}

StreamFunction Fluid::stream_function() const {
  if (psi_revision_ != revision_) {
    ScopedTimer tm(prof_, k_psi_);
    if (!psi_solver_) make_psi_solver();
    const Domain& d = lat_.domain;
    divergence(psi_ty_, psi_tx_, u_, b_psi_, &psi_st_);  // Gy^T u - Gx^T v
    psi_mean_.setZero();
    if (d.periodic_x && d.periodic_y) {
      psi_mean_ << u_.col(0).mean(), u_.col(1).mean();  // the uniform flow; G^T of a constant is 0
    } else if (d.periodic_x || d.periodic_y) {
      // psi on the far wall: the flux (int u dy along a channel in x, -int v dx in y), the least-squares
      // value (make_psi_solver)
      const double Q = u_.cwiseProduct(psi_r1_).sum();
      b_psi_.noalias() -= Q * psi_flux_;
    }
    psi_gauge_.project(b_psi_);
    if (!psi_fft_) psi_gauge_.pin_rhs(b_psi_);
    psi_solver_->solve(b_psi_.data(), psi_.data(), 1);
    psi_gauge_.project(psi_);
    psi_revision_ = revision_;
  }
  return {&psi_, psi_mean_};
}

double Fluid::kinetic_energy() const { return 0.5 * prm_.rho * lat_.volume * u_.squaredNorm(); }

double Fluid::poisson_residual() const {
  // ||A phi - b|| / ||b|| with the unpinned operator and the right-hand side of the last step
  Vec b = (-prm_.rho / prm_.dt) * div_;
  gauge_.project(b);
  Vec r;
  if (prm_.projection == Projection::Exact) {
    r = op_.grad_phix.transpose() * grad_phi_.col(0);  // G^T G phi, G phi = grad_phi_
    r.noalias() += op_.grad_phiy.transpose() * grad_phi_.col(1);
  } else {
    r = -(op_.lap_phi * phi_);
  }
  r -= b;
  const double nb = b.norm();
  return nb > 0 ? r.norm() / nb : r.norm();
}

std::vector<SolverInfo> Fluid::solver_info() const {
  std::vector<SolverInfo> v{cn_->info(), poisson_->info()};
  if (psi_solver_) v.push_back(psi_solver_->info());
  return v;
}

std::vector<std::string> Fluid::describe() const {
  std::ostringstream m;
  m << "EPSPH: " << lat_.nx << " x " << lat_.ny << " = " << size() << " fixed particles, " << im_.size()
    << " images, h = " << W_.h << " (" << prm_.h_over_dx << " (dx+dy)/2), "
    << static_cast<double>(pairs_.size()) / size() << " neighbours per particle, convection "
    << (prm_.convection ? "on" : "off (Stokes)") << ", "
    << (prm_.projection == Projection::Exact ? "exact projection (Poisson operator D G)"
                                              : "approximate projection (Poisson operator: Morris Laplacian)") << "; products: " << vel_st_.stencil_rows() << " velocity and "
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
  return {{"u", u_},           {"conv_old", conv_old_},     {"phi", phi_},        {"grad_phi", grad_phi_},
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
