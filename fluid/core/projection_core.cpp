#include "fluid/core/projection_core.hpp"

#include <stdexcept>

namespace sphib {

ProjectionFluid::ProjectionFluid(const FluidParams& params, bool particles_move, Profiler* profiler)
    : ProjectionFluid(params, particles_move, profiler, -1, 0.0) {}

ProjectionFluid::ProjectionFluid(const FluidParams& params, bool particles_move, Profiler* profiler, int particles,
                                 double volume)
    : FluidSolver(params, particles_move, profiler), prof_(FluidSolver::profiler()) {
  check_common_params(prm_);
  const int N = particles < 0 ? lat_.size() : particles;  // (-1: the lattice's)
  volume_ = particles < 0 ? lat_.volume : volume;
  V_ = Vec::Constant(N, volume_);
  mass_ = prm_.rho * volume_;
  u_ = u_star_ = u_star_old_ = rhs_ = conv_ = grad_phi_ = Mat2::Zero(N, 2);
  phi_ = p_ = div_ = b_phi_ = Vec::Zero(N);
  k_images_ = prof_.phase("images (Eq. 42)");
  k_rhs_ = prof_.phase("viscous rhs (Eq. 28)");
  k_solve_cn_ = prof_.phase("solve Crank-Nicolson");
  k_div_ = prof_.phase("divergence rhs (Eq. 32)");
  k_solve_poisson_ = prof_.phase("solve Poisson");
  k_project_ = prof_.phase("projection (Eq. 34)");
  k_pressure_ = prof_.on_demand_phase("pressure (Eq. 35)");
}

ProjectionFluid::MovingPhases ProjectionFluid::moving_phases(const char* move, const char* neighbours,
                                                            const char* assembly) {
  MovingPhases k;
  k.move = prof_.phase(move);
  k.neighbours = prof_.phase(neighbours);
  k.assembly = prof_.phase(assembly);
  k.factor_cn = prof_.phase("new matrix: Crank-Nicolson solver");
  k.factor_poisson = prof_.phase("new matrix: Poisson solver");
  return k;
}

void ProjectionFluid::operators_changed(const RowStencil* vel_st, const RowStencil* phi_st) {
  vel_st_ = vel_st;
  phi_st_ = phi_st;
  if (!same_pattern(op_.lap_u.A, op_.grad_ux.A) || !same_pattern(op_.grad_ux.A, op_.grad_uy.A) ||
      ((op_.grad_phix.size() != 0 || op_.grad_phiy.size() != 0) && !same_pattern(op_.grad_phix, op_.grad_phiy)))
    throw std::logic_error("fluid: the operators do not share one pattern (fused products need it)");
  lap_b_rows_ = nonempty_rows(op_.lap_u.B);
  gx_b_rows_ = nonempty_rows(op_.grad_ux.B);
  gy_b_rows_ = nonempty_rows(op_.grad_uy.B);
  const int N = static_cast<int>(u_.rows()), M = im_.size();
  c_wall_.setZero(M, 2);
  c_star_.setZero(M, 2);
  velocity_offsets(nullptr, c_wall_);  // 2 u_b: images of u^n
  lap_wall_.setZero(N, 2);
  add_image_terms(op_.lap_u.B, lap_b_rows_, c_wall_, lap_wall_);
}

void ProjectionFluid::operator_values_changed() {
  if (c_wall_.size() == 0 || c_wall_.cwiseAbs().maxCoeff() == 0) return;
  lap_wall_.setZero();
  add_image_terms(op_.lap_u.B, lap_b_rows_, c_wall_, lap_wall_);
}

void ProjectionFluid::velocity_offsets(const Mat2* grad_phi, Mat2& c) const {
  image_velocity_offsets(im_, prm_.domain, grad_phi, grad_phi ? prm_.dt / prm_.rho : 0.0, c);
}

void ProjectionFluid::eliminate_dirichlet(SpMat& A) {
  dirichlet_mask_.assign(A.rows(), 0);
  for (int i : dirichlet_rows_) dirichlet_mask_[i] = 1;
  const int* o = A.outerIndexPtr();
  const int* c = A.innerIndexPtr();
  double* a = A.valuePtr();
  for (int i = 0; i < A.outerSize(); ++i)
    for (int k = o[i]; k < o[i + 1]; ++k)
      if (dirichlet_mask_[i] || dirichlet_mask_[c[k]]) a[k] = c[k] == i ? 1.0 : 0.0;  // phi_i = 0, symmetric
}

SpMat ProjectionFluid::crank_nicolson_matrix() const { return crank_nicolson_matrix(op_.lap_u.A); }

SpMat ProjectionFluid::crank_nicolson_matrix(const SpMat& lap) const {
  SpMat A = lap;  // (I - nu dt/2 lap) u* = ... (Eq. 28), same pattern as lap (diagonal in it)
  A *= -a_cn();           // (in place: an assigned -a lap would grow its own storage to twice)
  for (int i = 0; i < A.outerSize(); ++i) A.coeffRef(i, i) += 1.0;
  return A;
}

void ProjectionFluid::set_velocity(const Mat2& u0) {
  ++revision_;
  if (u0.rows() != u_.rows()) throw std::invalid_argument("fluid: initial velocity has the wrong size");
  u_ = u0;
  u_star_ = u_star_old_ = u0;  // the warm start of an iterative Crank-Nicolson solver
  first_ = true;
}

void ProjectionFluid::step(const Mat2& F) {
  ++revision_;
  begin_step();
  image_offsets();
  convection();
  viscous_predictor(F);
  project();
  first_ = false;
  t_ += prm_.dt;
  ++n_;
  end_step();
}

void ProjectionFluid::image_offsets() {
  ScopedTimer tm(prof_, k_images_);
  // Eq. (42): images of u* carry 2 (u_b + dt/rho [grad phi~]_tau) - u*, with phi~ = phi^n.
  velocity_offsets(&grad_phi_, c_star_);
}

void ProjectionFluid::viscous_rhs(const Mat2& F) {
  const double dt = prm_.dt, a = a_cn();
  const int N = size();
  ScopedTimer tm(prof_, k_rhs_);
  // Eq. (28): (I - a lap) u* = u^n + a lap u^n + a B (c^n + c*) - dt (u.grad u)^{n+1/2} + dt F^n / rho
  if (!lap_u_ahead_) apply2(op_.lap_u.A, u_, rhs_, vel_st_);  // lap u^n, both components in one pass
  lap_u_ahead_ = false;
  add_image_terms(op_.lap_u.B, lap_b_rows_, c_star_, rhs_);
  const double k = dt / prm_.rho, kc = convective_ ? dt : 0.0;
  for (int c = 0; c < 2; ++c)
    for (int i = 0; i < N; ++i)
      rhs_(i, c) = (rhs_(i, c) + lap_wall_(i, c)) * a + u_(i, c) + k * F(i, c) - kc * conv_(i, c);
  add_acceleration(rhs_);
}

void ProjectionFluid::add_acceleration(Mat2& v) const {
  for (int c = 0; c < 2; ++c)  // + dt g (ISPH's gravity, Afanasiev et al. Eq. 22)
    if (accel_[c] != 0.0) v.col(c).array() += prm_.dt * accel_[c];
}

void ProjectionFluid::viscous_predictor(const Mat2& F) {
  viscous_rhs(F);
  if (explicit_viscous_) return;  // viscous_rhs gave u* itself (ISPH: Afanasiev et al. Eq. 22)
  ScopedTimer tm(prof_, k_solve_cn_);
  // u and v: two right-hand sides of one factorisation. An iterative solver starts from the
  // linear extrapolation 2 u*_{n-1} - u*_{n-2} (direct solvers ignore it).
  LinearSolver& cn = predictor_solver();
  if (cn.info().nnz_factor == 0) {
    u_star_old_ = 2.0 * u_star_ - u_star_old_;
    u_star_old_.swap(u_star_);  // u_star_ = guess, u_star_old_ = u*_{n-1}
  }
  if (cn_v_) {  // the components' own matrices (their image parities differ: Images::split)
    const int N = size();
    cn.solve(rhs_.data(), u_star_.data(), 1);
    cn_v_->solve(rhs_.data() + N, u_star_.data() + N, 1);
  } else {
    cn.solve(rhs_.data(), u_star_.data(), 2);
  }
}

void ProjectionFluid::divergence_with_images(const Mat2& u, const Mat2& c, Vec& d) const {
  divergence(op_.grad_ux.A, op_.grad_uy.A, u, d, vel_st_);  // Eq. (30)
  if (im_.split()) {  // the components' own parities where they differ from the operators' (boundary.hpp)
    split_div_ = c;
    add_split_images(im_, u, split_div_);
  }
  const Mat2& cc = im_.split() ? split_div_ : c;
  add_image_terms(op_.grad_ux.B, gx_b_rows_, cc.col(0).data(), d.data());
  add_image_terms(op_.grad_uy.B, gy_b_rows_, cc.col(1).data(), d.data());
}

void ProjectionFluid::project_approximate() {
  const double dt = prm_.dt, rho = prm_.rho;
  const int N = size();
  const bool gauge = gauge_.dimension() > 0;
  {
    ScopedTimer tm(prof_, k_div_);
    // Eq. (30): div u* with images of u* (offsets c*); Eq. (32): -lap phi = -(rho/dt) div u*
    divergence_with_images(u_star_, c_star_, div_);
    for (int i = 0; i < N; ++i) b_phi_[i] = (-rho / dt) * div_[i];
    if (gauge) {
      gauge_.project(b_phi_);  // onto the range of the singular operator
      if (!poisson_unpinned_) gauge_.pin_rhs(b_phi_);
    }
    for (int i : dirichlet_rows_) b_phi_[i] = 0.0;  // phi = 0 on a free surface
  }
  {
    ScopedTimer tm(prof_, k_solve_poisson_);
    poisson_->solve(b_phi_.data(), phi_.data(), 1);
    if (gauge) phi_.array() -= phi_.mean();
    for (int i : dirichlet_rows_) phi_[i] = 0.0;  // the exact solution there (CG leaves round-off)
  }
  ScopedTimer tm(prof_, k_project_);
  // Eq. (34): u^{n+1} = u* - dt/rho grad phi^{n+1}, images phi_i' = phi_i
  if (phi_ops_stale_ && phi_ops_from_) {  // (see phi_ops_from_) grad_u's rows, then the rows with images
    gradient(op_.grad_ux.A, op_.grad_uy.A, phi_, grad_phi_, phi_st_);
    gradient_rows(op_.grad_phix, op_.grad_phiy, phi_, grad_phi_, gx_b_rows_);
  } else {
    gradient(op_.grad_phix, op_.grad_phiy, phi_, grad_phi_, phi_st_);
  }
  u_.noalias() = u_star_ - (dt / rho) * grad_phi_;
}

const Operators& ProjectionFluid::operators() const {
  if (phi_ops_stale_ && phi_ops_from_) {
    const SpMat& A = *phi_ops_from_;  // the same pattern (ParticleOperators::shape)
    if (op_.lap_phi.nonZeros() != A.nonZeros()) throw std::logic_error("lap_phi: A_phi has another pattern");
    for (Eigen::Index k = 0; k < A.nonZeros(); ++k) op_.lap_phi.valuePtr()[k] = -A.valuePtr()[k];
    const int* o = op_.grad_phix.outerIndexPtr();
    auto image_row = gx_b_rows_.begin();  // the rows with images, increasing
    for (int i = 0; i < size(); ++i) {
      if (image_row != gx_b_rows_.end() && *image_row == i) {
        ++image_row;
        continue;
      }
      std::copy(op_.grad_ux.A.valuePtr() + o[i], op_.grad_ux.A.valuePtr() + o[i + 1], op_.grad_phix.valuePtr() + o[i]);
      std::copy(op_.grad_uy.A.valuePtr() + o[i], op_.grad_uy.A.valuePtr() + o[i + 1], op_.grad_phiy.valuePtr() + o[i]);
    }
    phi_ops_stale_ = false;
  }
  return op_;
}

const Vec& ProjectionFluid::p() const {
  if (p_revision_ != revision_) {
    ScopedTimer tm(prof_, k_pressure_);
    if (explicit_viscous_) p_ = phi();  // Afanasiev et al. Eqs. (23)-(24): phi is p^{n+1}
    else if (lap_phi_st_) pressure_from_phi(op_.lap_phi, phi(), a_cn(), p_, lap_phi_st_);  // Eq. (35), by stencil
    else pressure_from_phi(operators().lap_phi, phi(), a_cn(), p_);  // Eq. (35)
    p_revision_ = revision_;
  }
  return p_;
}

double ProjectionFluid::max_abs_divergence() const {
  Vec d(size());
  divergence_with_images(u_, c_wall_, d);  // Eq. (30) with the no-slip images of u^n
  return max_abs(d);
}

std::vector<SolverInfo> ProjectionFluid::solver_info() const {
  std::vector<SolverInfo> v;
  if (cn_) v.push_back(cn_->info());
  if (poisson_) v.push_back(poisson_->info());
  return v;
}

NamedArrays ProjectionFluid::state() const {
  Eigen::MatrixXd clock(1, 3);
  clock << t_, static_cast<double>(n_), first_ ? 1.0 : 0.0;
  NamedArrays st{{"u", u_},           {"phi", phi()},              {"grad_phi", grad_phi_},
                 {"u_star", u_star_}, {"u_star_old", u_star_old_}, {"clock", clock}};
  extra_state(st);
  return st;
}

void ProjectionFluid::restore(const NamedArrays& state) {
  ++revision_;
  const int N = size();
  u_ = state_entry(state, "u", N, 2);
  phi_ = state_entry(state, "phi", N, 1);
  grad_phi_ = state_entry(state, "grad_phi", N, 2);
  u_star_ = state_entry(state, "u_star", N, 2);
  u_star_old_ = state_entry(state, "u_star_old", N, 2);
  const Eigen::MatrixXd& clock = state_entry(state, "clock", 1, 3);
  t_ = clock(0, 0);
  n_ = static_cast<long>(clock(0, 1));
  first_ = clock(0, 2) != 0.0;
  restore_extra(state);
}

}  // namespace sphib
