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
  // The projection (Eqs. 32-34). Exact: u^{n+1} is the orthogonal projection of u* onto D u = 0,
  // with D = -G^T the divergence of a vector field whose wall images mirror it (tangential part even,
  // normal part odd). Its kernel is spanned by the curls (Gy psi, -Gx psi) of stream functions with
  // odd images (psi constant along each wall; D of such a curl is 0 identically), the uniform flux
  // of a channel, and the alternating velocity modes G does not see (fluid/gauge.hpp). So the
  // projection is made through psi: the least-squares psi of u* (normal equations with G^T G, odd
  // images), u^{n+1} = its curl plus u*'s components along those modes, and G phi = rho/dt (u* -
  // u^{n+1}) (Eq. 34 read backwards). D u^{n+1} = 0 to solver precision; the same psi moves the
  // markers (stream_function()); phi itself (G^T G phi = G^T G phi) is solved only when the pressure
  // or phi is asked for. An orthogonal projection cannot amplify anything, however small the
  // eigenvalues of G^T G near its grid-scale null modes. (With the no-slip divergence of Eq. (30),
  // tangential images odd, the projection would be oblique and, with those tiny eigenvalues,
  // unstable: measured on Poiseuille at h = 3 dx. The two divergences differ only within 2h of a wall.)
  // Approximate (the paper): -lap phi = -(rho/dt) div u* (Eqs. 31-32) with Eq. (30)'s divergence,
  // u^{n+1} = u* - dt/rho G phi (Eq. 34).
  // The null spaces (fluid/gauge.hpp) are fixed by projecting right-hand sides onto their
  // complement, pinning one particle per null vector for a direct factorisation, and removing the
  // null components from the solution.
  const bool exact = prm_.projection == Projection::Exact;
  if (exact) {
    for (int k = 0; k < 4; ++k) {
      const Side w = static_cast<Side>(k);
      const int nrm = (w == Left || w == Right) ? 0 : 1;
      if (prm_.domain.is_wall(w) && prm_.domain.wall_velocity[k][nrm] != 0.0)
        throw std::invalid_argument(std::string("walls.") + (w == Left ? "left" : w == Right ? "right" : w == Bottom ? "bottom" : "top") +
                                    ": a wall velocity with a normal component lets fluid through the wall; "
                                    "the exact projection (fluid.projection = \"exact\") needs impermeable walls");
    }
    div_x_ = -SpMat(op_.grad_phix.transpose());
    div_y_ = -SpMat(op_.grad_phiy.transpose());
    div_st_ = find_row_stencil({&div_x_, &div_y_});
    gauge_phi_ = Gauge(lat_, NullSpace::Constants);
    vmodes_ = VelocityModes(lat_);
  } else {
    gauge_ = Gauge(lat_, NullSpace::Constants);
  }
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
    if (cn_ && cn_kind == SolverKind::Auto) cn_->annotate(" (auto)", 0.0);
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
  // Exact projection: the stream function's system (make_psi_solver), phi's only when asked for.
  if (exact) make_psi_solver();
  else poisson_ = poisson_solver("Poisson", -op_.lap_phi, gauge_, prm_.poisson_solver, &poisson_fft_);
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
  grad_psi_ = Mat2::Zero(N, 2);
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
      if (kind == SolverKind::Auto) s->annotate(" (auto)", 0.0);
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
  if (prm_.projection == Projection::Exact) project_exact();
  else project_approximate();
  first_ = false;
  t_ += dt;
  ++n_;
  if (prm_.projection == Projection::Exact) cu_revision_ = revision_;  // C^T u* = C^T u^{n+1}
}

void Fluid::project_approximate() {
  const double dt = prm_.dt, rho = prm_.rho;
  const Operators& op = op_;
  const int N = size();
  {
    ScopedTimer tm(prof_, k_div_);
    // Eq. (30): div u* with images of u* (offsets c*); Eq. (32): -lap phi = -(rho/dt) div u*
    divergence(op.grad_ux.A, op.grad_uy.A, u_star_, div_, &vel_st_);
    add_image_terms(op.grad_ux.B, gx_b_rows_, c_star_.col(0).data(), div_.data());
    add_image_terms(op.grad_uy.B, gy_b_rows_, c_star_.col(1).data(), div_.data());
    for (int i = 0; i < N; ++i) b_phi_[i] = (-rho / dt) * div_[i];
    gauge_.project(b_phi_);  // onto the range of the singular operator (gauge, see constructor)
    if (!poisson_fft_) gauge_.pin_rhs(b_phi_);
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
}

void Fluid::project_exact() {
  const double dt = prm_.dt, rho = prm_.rho;
  const Operators& op = op_;
  const int N = size();
  {
    ScopedTimer tm(prof_, k_div_);
    curl_transpose(u_star_);
    psi_rhs();  // the normal equations' right-hand side C^T u* - Q ..., in b_psi_
    if (!psi_fft_) psi_gauge_.pin_rhs(b_psi_);
  }
  const double Q = Q_;
  {
    ScopedTimer tm(prof_, k_solve_poisson_);
    psi_solver_->solve(b_psi_.data(), psi_.data(), 1);
    psi_gauge_.project(psi_);
  }
  {
    ScopedTimer tm(prof_, k_project_);
    // u^{n+1} = (Gy psi + Q By c1, -(Gx psi + Q Bx c1)) + u*'s alternating modes (and mean)
    gradient(op.grad_ux.A, op.grad_uy.A, psi_, grad_psi_, &vel_st_);
    for (int i = 0; i < N; ++i) {
      u_(i, 0) = grad_psi_(i, 1) + Q * psi_by1_[i];
      u_(i, 1) = -(grad_psi_(i, 0) + Q * psi_bx1_[i]);
    }
    vmodes_.add_components(u_star_, u_);
    psi_mean_.setZero();
    if (lat_.domain.periodic_x && lat_.domain.periodic_y) psi_mean_ << u_star_.col(0).mean(), u_star_.col(1).mean();
    // Eq. (34): G phi^{n+1} = rho/dt (u* - u^{n+1}); phi itself on demand (phi())
    grad_phi_ = (rho / dt) * (u_star_ - u_);
    phi_step_ = -1;
  }
}

void Fluid::curl_transpose(const Mat2& u) const {
  divergence(psi_ty_, psi_tx_, u, cu_, &psi_st_);  // Gy^T u - Gx^T v (= C^T u)
  // psi on the far wall: the flux (int u dy along a channel in x, -int v dx in y), the least-squares
  // value (make_psi_solver)
  const Domain& d = lat_.domain;
  Q_ = d.periodic_x != d.periodic_y ? u.cwiseProduct(psi_r1_).sum() : 0.0;
}

void Fluid::psi_rhs() const {
  b_psi_ = cu_;
  if (Q_ != 0.0) b_psi_.noalias() -= Q_ * psi_flux_;
  psi_gauge_.project(b_psi_);  // G^T of a uniform flow is 0 on a periodic box: its mean is the stream function's U
}

void Fluid::exact_divergence(const Mat2& u, Vec& d) const { divergence(div_x_, div_y_, u, d, &div_st_); }

const Vec& Fluid::phi() const {
  if (prm_.projection == Projection::Exact && phi_step_ != n_) {
    // The projection's own phi (G^T G phi = -(rho/dt) D u*) is determined up to the components G
    // hardly sees, which G^T G's tiny eigenvalues near its null modes amplify: measured, a fixed
    // membrane at h = 2.25 dx gives a pressure jump of 9.7 instead of 1. Its velocity is immune (it
    // sees only G phi), but phi and p are taken as the smooth phi~ with the same D G phi:
    //   -lap phi~ = G^T (G phi) = -D (G phi),   lap the Morris Laplacian of Eq. (31),
    // i.e. the approximate projection's phi for the same u* (jump 1.0000 at 70 x 70, Section 5.2.1).
    if (!poisson_)
      poisson_ = poisson_solver("Poisson (Morris Laplacian: phi and p of the exact projection)", -op_.lap_phi,
                                gauge_phi_, prm_.poisson_solver, &poisson_fft_);
    exact_divergence(grad_phi_, b_phi_);  // D G phi = -G^T G phi, G phi = rho/dt (u* - u^{n+1})
    b_phi_ *= -1.0;
    gauge_phi_.project(b_phi_);
    if (!poisson_fft_) gauge_phi_.pin_rhs(b_phi_);
    poisson_->solve(b_phi_.data(), phi_.data(), 1);
    phi_.array() -= phi_.mean();
    phi_step_ = n_;
  }
  return phi_;
}

const Vec& Fluid::p() const {
  if (p_step_ != n_) {
    ScopedTimer tm(prof_, k_pressure_);
    const double a = 0.5 * nu() * prm_.dt;
    if (prm_.projection == Projection::Approximate) {
      pressure_from_phi(op_.lap_phi, phi_, a, p_);  // Eq. (35)
    } else {
      pressure_from_phi(op_.lap_phi, phi(), a, p_);  // Eq. (35) on phi~ (see phi())
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
  psi_gauge_ = Gauge(lat_, NullSpace::GradientOddImages);
  const SpMat A = psi_ty_ * Gy + SpMat(Gx.transpose()) * Gx;
  psi_solver_ = poisson_solver(prm_.projection == Projection::Exact ? "Poisson (exact projection: the stream function, G^T G, odd images)"
                                                                    : "stream function (G^T G, odd images)",
                               A, psi_gauge_, prm_.poisson_solver, &psi_fft_);
  const int N = size(), M = im_.size();
  psi_ = b_psi_ = psi_flux_ = psi_by1_ = psi_bx1_ = Vec::Zero(N);
  psi_r1_ = Mat2::Zero(N, 2);
  if (d.periodic_x != d.periodic_y) {
    const Side far = d.periodic_x ? Top : Right;  // the wall that carries psi = Q
    Vec c1 = Vec::Zero(M);
    for (int m = 0; m < M; ++m)
      if (im_.wall[m] == far) c1[m] = 2.0;
    psi_by1_ = op_.grad_uy.B * c1;
    psi_bx1_ = op_.grad_ux.B * c1;
    psi_flux_ = psi_ty_ * psi_by1_ - psi_tx_ * psi_bx1_;  // Gy^T By c1 + Gx^T Bx c1
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
    psi_r1_.col(0) = Gy * psi1 + psi_by1_;
    psi_r1_.col(1) = -(Gx * psi1 + psi_bx1_);
    psi_r1_ /= psi_r1_.squaredNorm();
    mpsi_flux_ = op_.lap_u.B * c1;  // lap of psi_m's wall values per unit flux
  } else {
    mpsi_flux_ = Vec::Zero(N);
  }
  // The markers' psi_m: -lap psi_m = C^T u, lap with odd images (lap_u.A, Eq. 31): definite with a
  // wall, the constants its null space on a doubly periodic box.
  mpsi_gauge_ = Gauge(lat_, d.periodic_x && d.periodic_y ? NullSpace::Constants : NullSpace::None);
  mpsi_solver_ = poisson_solver("stream function of the markers (Morris Laplacian, odd images)", -op_.lap_u.A,
                                mpsi_gauge_, prm_.poisson_solver, &mpsi_fft_);
  // The lattice normalisation of the SPH gradient, G x = m (m - 1 = -9.2e-3 at h = 1.2 dx, 3.0e-3 at
  // 1.525 dx, -2.2e-4 at 2.2 dx: tests/test_fluid.cpp), from an interior particle. The curl of psi_m
  // reproduces u at long waves as G G^T / lap ~ m: psi_m is divided by m, so that it does exactly
  // (without, the markers moved 0.8% off the fluid's velocity at h = 1.2 dx, at every resolution).
  {
    const int i = lat_.nx / 2 + lat_.nx * (lat_.ny / 2);
    double mx = 0;
    for (int k = pairs_.offset[i]; k < pairs_.offset[i + 1]; ++k)
      mx -= lat_.volume * W_.F(pairs_.r[k]) * pairs_.rx[k] * pairs_.rx[k];
    mpsi_scale_ = 1.0 / mx;
  }
  psi_m_ = cu_ = b_m_ = Vec::Zero(N);
}

StreamFunction Fluid::stream_function() const {
  if (psi_revision_ != revision_) {
    ScopedTimer tm(prof_, k_psi_);
    if (!psi_solver_) make_psi_solver();
    if (cu_revision_ != revision_) curl_transpose(u_);  // the exact projection's step made it already
    // -lap psi_m = C^T u with psi_m's wall values (0 and Q): -(A psi_m + Q B c1) = C^T u
    b_m_ = cu_;
    if (Q_ != 0.0) b_m_.noalias() += Q_ * mpsi_flux_;
    mpsi_gauge_.project(b_m_);
    if (!mpsi_fft_) mpsi_gauge_.pin_rhs(b_m_);
    b_m_ *= mpsi_scale_;  // psi_m / m (make_psi_solver)
    mpsi_solver_->solve(b_m_.data(), psi_m_.data(), 1);
    mpsi_gauge_.project(psi_m_);
    psi_mean_.setZero();
    if (lat_.domain.periodic_x && lat_.domain.periodic_y) psi_mean_ << u_.col(0).mean(), u_.col(1).mean();
    psi_revision_ = revision_;
  }
  return {&psi_m_, psi_mean_};
}

double Fluid::kinetic_energy() const { return 0.5 * prm_.rho * lat_.volume * u_.squaredNorm(); }

double Fluid::poisson_residual() const {
  // ||A x - b|| / ||b|| with the unpinned operator and the right-hand side of the last step:
  // the stream function's normal equations (exact projection) or Eq. (32)
  Vec r, b;
  if (prm_.projection == Projection::Exact) {
    curl_transpose(u_star_);
    psi_rhs();
    b = b_psi_;
    r = psi_ty_ * (op_.grad_uy.A * psi_);  // Gy^T Gy psi + Gx^T Gx psi
    r.noalias() -= psi_tx_ * (op_.grad_ux.A * psi_);
  } else {
    b = (-prm_.rho / prm_.dt) * div_;
    gauge_.project(b);
    r = -(op_.lap_phi * phi_);
  }
  r -= b;
  const double nb = b.norm();
  return nb > 0 ? r.norm() / nb : r.norm();
}

std::vector<SolverInfo> Fluid::solver_info() const {
  std::vector<SolverInfo> v{cn_->info()};
  if (psi_solver_ && prm_.projection == Projection::Exact) v.push_back(psi_solver_->info());
  if (poisson_) v.push_back(poisson_->info());
  if (psi_solver_ && prm_.projection != Projection::Exact) v.push_back(psi_solver_->info());
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
  if (prm_.projection == Projection::Exact) m << " (D = -G^T: " << div_st_.stencil_rows() << " rows)";
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
  total += best([&] {
    x = u_star_;  // the same warm start a step gives an iterative solver
    cn_->solve(rhs_.data(), x.data(), 2);
  });
  if (prm_.projection == Projection::Exact) {  // C^T u*, the stream function's solve, its curl
    Vec b = b_psi_;
    total += best([&] { divergence(psi_ty_, psi_tx_, u_star_, d, &psi_st_); });
    total += best([&] { psi_solver_->solve(b.data(), f.data(), 1); });
    total += best([&] { gradient(op.grad_ux.A, op.grad_uy.A, psi_, a, &vel_st_); });
  } else {
    total += best([&] { divergence(op.grad_ux.A, op.grad_uy.A, u_star_, d, &vel_st_); });
    total += best([&] { poisson_->solve(b_phi_.data(), f.data(), 1); });
    total += best([&] { gradient(op.grad_phix, op.grad_phiy, phi_, a, &phi_st_); });
  }
  return total;
}

// The state after step n: u^n, the convection N^n kept for AB2 (Eq. 39), phi^n and grad phi^n
// (Eq. 42), the last two u* (the warm start of an iterative Crank-Nicolson solver), t_n and n.
NamedArrays Fluid::state() const {
  Eigen::MatrixXd clock(1, 3);
  clock << t_, static_cast<double>(n_), first_ ? 1.0 : 0.0;
  NamedArrays st{{"u", u_},           {"conv_old", conv_old_},     {"phi", phi()},  {"grad_phi", grad_phi_},
                 {"u_star", u_star_}, {"u_star_old", u_star_old_}, {"clock", clock}};
  if (prm_.projection == Projection::Exact) {  // C^T u* and its flux: the markers' stream function
    Eigen::MatrixXd q(1, 1);
    q(0, 0) = Q_;
    st.emplace_back("curl_transpose_u_star", cu_);
    st.emplace_back("flux", q);
  }
  return st;
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
  phi_step_ = n_;
  if (prm_.projection == Projection::Exact) {
    cu_ = get("curl_transpose_u_star", N, 1);
    Q_ = get("flux", 1, 1)(0, 0);
    cu_revision_ = revision_;
  }
}

double Fluid::setup_seconds(const std::string& what) const {
  for (const auto& [k, s] : setup_)
    if (k == what) return s;
  return 0.0;
}

std::optional<FluidSolver::Footprint> Fluid::footprint() const {
  auto nnz = [](const SpMat& A) { return static_cast<long>(A.nonZeros()); };
  Footprint f;
  f.operator_nonzeros = nnz(op_.lap_u.A) + nnz(op_.lap_u.B) + nnz(op_.grad_ux.A) + nnz(op_.grad_ux.B) +
                        nnz(op_.grad_uy.A) + nnz(op_.grad_uy.B) + nnz(op_.lap_phi) + nnz(op_.grad_phix) +
                        nnz(op_.grad_phiy);
  for (const auto& si : solver_info()) {
    f.factor_nonzeros += si.nnz_factor ? si.nnz_factor : si.nnz_used;  // an iterative solver keeps A itself
    if (si.system == "Poisson") f.factor_nonzeros += si.nnz_A;         // kept for the residual check
  }
  f.pairs = static_cast<long>(pairs_.size());
  return f;
}

}  // namespace sphib
