#include "fluid/moving/lagrangian.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fluid/common/interpolation.hpp"
#include "fluid/algebra/solver_policy.hpp"
#include "kernels/sparse_rows.hpp"

namespace sphib {

namespace {
void check_params(const FluidParams& p) {
  if (p.lagrangian.reinit_every < 0)
    throw std::invalid_argument("fluid: lagrangian.reinit_every must be >= 0 (0: never)");
  if (!(p.lagrangian.min_kernel_sum >= 0 && p.lagrangian.min_kernel_sum <= 1))
    throw std::invalid_argument("fluid: lagrangian.min_kernel_sum must lie in [0, 1]");
  if (p.projection == Projection::Exact)
    throw std::invalid_argument("fluid: LPSPH has the approximate projection only (fluid.projection = \"approximate\")");
}

}  // namespace

// The Verlet skin (neighbours.hpp), adaptive between 0.01 and 0.3 of the support 2h: a thin skin
// keeps the candidates to the neighbours within 2h (every candidate is an entry in every product and
// solve), a slow flow then rebuilds rarely, and a fast flow widens it (docs/method/choices.md,
// "LPSPH: the Verlet skin").
constexpr double kSkinMin = 0.01, kSkinMax = 0.3;

LagrangianFluid::LagrangianFluid(const FluidParams& params, Profiler* profiler)
    : ProjectionFluid(params, true, profiler), x_star_(lat_.x),
      verlet_(prm_.domain, W_.support() * (1.0 - 1e-12), kSkinMin * W_.support(), kSkinMax * W_.support()) {
  x_ = lat_.x;
  check_params(prm_);
  S_ = Vec::Zero(lat_.size());
  gauge_ = Gauge(lat_, NullSpace::Constants);  // of the Poisson operator, the Morris Laplacian
  k_ = moving_phases("move particles (Eq. 37)", "neighbours and images (Verlet list)",
                     "operators, systems, kernel sums (Eqs. 27-34)");
  k_reinit_ = prof_.phase("reinitialisation (Eq. 61)");
  const RebuildSeconds s = rebuild(0.0);  // the first analysis and factorisations
  add_setup("neighbours", s.neighbours);
  add_setup("assembly", s.assembly);
  add_setup("factorisation", s.factorisation_cn + s.factorisation_poisson);
  prof_.set_reporter([this](FluidReport& r) {
    r.lines = describe();
    r.figures = figures();
  });
}

// Breakdown (Section 5.2.2, Fig. 18): the kernel sums S_i = V (W(0) + sum_j W_ij), images included
// and only the pairs closer than the reach (the Verlet candidates beyond it have W = 0), come from the
// assembly's pass (ParticleOperators::assemble). Below the threshold the geometry goes back to the
// last positions that passed, so that nothing the state depends on has changed, and the step throws.
void LagrangianFluid::check_kernel_sums(double t) {
  Eigen::Index worst = 0;
  const double S_min = S_.minCoeff(&worst);
  S_low_ = std::min(S_low_, S_min);
  if (S_min >= prm_.lagrangian.min_kernel_sum) {
    x_star_good_ = x_star_;
    return;
  }
  std::ostringstream m;
  m.precision(8);
  m << "LPSPH breakdown at t = " << t << ": particle " << worst << " at (" << x_star_(worst, 0) << ", "
    << x_star_(worst, 1) << ") has kernel sum " << S_min << " < " << prm_.lagrangian.min_kernel_sum << " ("
    << neighbours_within(static_cast<int>(worst)) << " neighbours within 2h, " << neighbours_per_particle()
    << " on average; particles driven apart; Section 5.2.2, Fig. 18)";
  if (x_star_good_.rows() == x_star_.rows()) {  // (kernel_sums() keeps the failing sums)
    x_star_ = x_star_good_;
    geometry(false, false, nullptr);
  }
  throw std::runtime_error(m.str());
}

// Images and pairs at x_star_ (the Verlet list), the operators, the two systems and the kernel sums
// (when asked) in one pass, and the core's derived data; returns whether the list was built.
bool LagrangianFluid::geometry(bool jump, bool sums, RebuildSeconds* s, bool ahead) {
  auto t0 = Profile::Clock::now();
  // Images of the current particles (Section 3.3) and the pairs by the Verlet list (neighbours.hpp):
  // built by cell list, O(N), when the particles have moved by about the skin, else moved. The reach
  // is 2h less 1e-12 relative: pairs at exactly 2h (lattice distances when 2h/dx is an integer, e.g.
  // h = 3 dx) have W = F = 0 but would enter and leave with the round-off of every move.
  // Operators at the new positions (Eqs. 27-34), as build_operators makes them, the pattern only
  // after a build of the list; with them the two systems of the step, I - a lap (Eq. 28) and the
  // Poisson matrix -lap phi (Eq. 32: the symmetric semi-definite -lap phi = -(rho/dt) div u*).
  // Row block by row block behind the list's moves, while the blocks' pairs are in cache (the
  // neighbours' time then includes the moves, the assembly's the blocks' operators).
  // The phi operators' values only in the rows with images; in the others they are -A_phi and
  // grad_ux.A, grad_uy.A (projection_core.hpp, phi_ops_from_): three arrays less to write per step.
  const ProjectionSystems sys{a_cn(), &A_cn_, &A_phi_, false};
  phi_ops_from_ = &A_phi_;
  phi_ops_stale_ = true;
  double assembly_seconds = 0;
  // The moves hand the blocks' rx, ry, r to the pass and leave pairs_'s (pairs_current()).
  const bool built = verlet_.update(x_star_, im_, pairs_, jump, [&](int i0, int i1, bool new_list, const PairGeometry& g) {
    const auto ta = Profile::Clock::now();
    if (i0 == 0) assembly_.prepare(pairs_, im_, lat_.size(), new_list, op_, sys);
    assembly_.assemble_rows(pairs_, g, im_, lat_.size(), W_, lat_.volume, verlet_.reach(), i0, i1, op_, sys,
                            sums ? S_.data() : nullptr);
    if (ahead) products_ahead(i0, i1);
    assembly_seconds += seconds_since(ta);
  });
  pairs_stale_ = !built;
  if (s) s->neighbours = seconds_since(t0) - assembly_seconds;
  t0 = Profile::Clock::now();
  // The core's derived data (projection_core.hpp): after a build of the list all of it; between
  // builds the images, their walls and the patterns are the same, and only the wall part of the
  // Laplacian, B c^n (Eq. 42 with c^n = 2 u_b), follows the values (zero for walls at rest).
  if (built || lap_wall_.rows() != lat_.size()) {
    operators_changed();
  } else if (c_wall_.size() && c_wall_.cwiseAbs().maxCoeff() > 0) {
    lap_wall_.setZero();
    add_image_terms(op_.lap_u.B, lap_b_rows_, c_wall_, lap_wall_);
  }
  if (s) s->assembly = assembly_seconds + seconds_since(t0);
  return built;
}

// The products that the step's first passes would make, row block by row block behind the assembly
// while the rows' values are in cache, instead of three more passes over the matrices from memory
// (at 64^2 each pass took about as long as a tenth of the step): lap_u.A u^n for Eq. (28)'s
// right-hand side (viscous_rhs takes it), and for the starts of the two iterative solves the
// products they begin with (start_product): A_cn times the extrapolation 2 u*_{n-1} - u*_{n-2}
// that viscous_predictor computes, A_phi times phi^n. The same bits as those passes (the solver's
// product: linear_solver.hpp, start_product).
// One pass over the rows' common pattern (kernels/sparse_rows.hpp; the inputs interleaved by
// rebuild, x4_).
void LagrangianFluid::products_ahead(int i0, int i1) {
  const int N = size();
  const SpMat& L = op_.lap_u.A;
  const Rows3 in{L.outerIndexPtr(), L.innerIndexPtr(), L.valuePtr(), A_cn_.valuePtr(), A_phi_.valuePtr(),
                 x4_.data(), phi_x0_.data()};
  double* out[5] = {rhs_.data(), rhs_.data() + N, cn_ax0_.data(), cn_ax0_.data() + N, phi_ax0_.data()};
  rows3(in, out, i0, i1);
}

LagrangianFluid::RebuildSeconds LagrangianFluid::rebuild(double t, bool jump, bool ahead) {
  RebuildSeconds s;
  if (ahead) {  // the starts of the solves, as viscous_predictor and project_approximate take them
    cn_x0_ = 2.0 * u_star_ - u_star_old_;
    phi_x0_ = phi_;
    x4_.resize(4 * size());
    for (int i = 0; i < size(); ++i) {
      x4_[4 * i] = u_(i, 0);
      x4_[4 * i + 1] = u_(i, 1);
      x4_[4 * i + 2] = cn_x0_(i, 0);
      x4_[4 * i + 3] = cn_x0_(i, 1);
    }
    cn_ax0_.resize(size(), 2);
    phi_ax0_.resize(size());
  }
  geometry(jump, true, &s, ahead);
  check_kernel_sums(t);
  auto t0 = Profile::Clock::now();

  // The solvers (solver_policy.hpp): made by the constructor's rebuild, at the lattice points, so that
  // the matrices there are the lattice reference of an FFT preconditioner; refactorised every step.
  t0 = Profile::Clock::now();
  if (!cn_) {
    if (x_star_ != lat_.x) throw std::logic_error("LPSPH: the solvers are made at the lattice points");
    cn_ = crank_nicolson_solver(A_cn_, op_.lap_u.A, a_cn(), prm_.cn_solver, nullptr, Refactor::EveryStep, {&lat_, &A_cn_});
  } else {
    n_reused_cn_ += cn_->refactorize_in_place(A_cn_);  // kept until the next rebuild
  }
  s.factorisation_cn = seconds_since(t0);
  t0 = Profile::Clock::now();
  if (!poisson_) {
    SystemSolver p = singular_solver("Poisson", Field::Scalar, A_phi_, gauge_, prm_.poisson_solver, nullptr, Refactor::EveryStep, {&lat_, &A_phi_});
    poisson_ = std::move(p.solver);
    poisson_unpinned_ = p.unpinned;
  } else {
    if (poisson_unpinned_) n_reused_poisson_ += poisson_->refactorize_in_place(A_phi_);
    else n_reused_poisson_ += poisson_->refactorize(gauge_.pinned(A_phi_, false));
    ++n_refactor_;
  }
  s.factorisation_poisson = seconds_since(t0);
  if (ahead) {
    lap_u_ahead_ = true;
    cn_->start_product(A_cn_, cn_x0_.data(), cn_ax0_.data(), 2);
    poisson_->start_product(A_phi_, phi_x0_.data(), phi_ax0_.data(), 1);
  }
  return s;
}

double LagrangianFluid::neighbours_per_particle() const {
  long n = 0;
  for (int i = 0; i < size(); ++i) n += neighbours_within(i);
  return static_cast<double>(n) / size();
}

int LagrangianFluid::neighbours_within(int i) const {
  const PairList& P = pairs();
  int n = 0;
  for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) n += P.r[k] < verlet_.reach();
  return n;
}

void LagrangianFluid::pairs_current() const {
  if (!pairs_stale_) return;
  verlet_.move_pairs_to(x_star_, im_, pairs_);
  pairs_stale_ = false;
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

void LagrangianFluid::set_positions(const Mat2& x) {
  if (x.rows() != x_.rows()) throw std::invalid_argument("LPSPH: positions have the wrong size");
  x_ = x;
  wrap_into_domain(x_, t_);
  x_star_ = x_;
  rebuild(t_, true);
  ++revision_;
}

void LagrangianFluid::begin_step() {
  const double dt = prm_.dt;
  // The step's geometry at the predicted positions x* = x^n + dt u^n (see the header): images,
  // pairs, operators, factorisations. A breakdown throws here, before anything has changed.
  x_star_ = x_ + dt * u_;
  wrap_into_domain(x_star_, t_ + dt);
  const RebuildSeconds s = rebuild(t_ + dt, false, true);
  prof_.add(k_.neighbours, s.neighbours);
  prof_.add(k_.assembly, s.assembly);
  prof_.add(k_.factor_cn, s.factorisation_cn);
  prof_.add(k_.factor_poisson, s.factorisation_poisson);
  ScopedTimer tm(prof_, k_.move);
  x_ += (0.5 * dt) * u_;  // Eq. (37), the u^n half
}

void LagrangianFluid::end_step() {
  {
    ScopedTimer tm(prof_, k_.move);
    x_ += (0.5 * prm_.dt) * u_;  // Eq. (37), the u^{n+1} half
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
    f(N + m, 2) = im.s_sign[m] * phi_[p];  // the scalar's parity (boundary_rule.hpp)
    const bool flip_x = w < 0 || w == Left || w == Right, flip_y = w < 0 || w == Bottom || w == Top;
    f(N + m, 3) = im.s_sign[m] * (flip_x ? -grad_phi_(p, 0) : grad_phi_(p, 0));
    f(N + m, 4) = im.s_sign[m] * (flip_y ? -grad_phi_(p, 1) : grad_phi_(p, 1));
  }
  Eigen::Vector2d lo(d.x0, d.y0), hi(d.x1, d.y1);
  const double support = W_.support();
  if (!d.periodic_x) { lo[0] -= support; hi[0] += support; }  // room for the images
  if (!d.periodic_y) { lo[1] -= support; hi[1] += support; }
  CellGrid grid(lo, hi, d.periodic_x, d.periodic_y, support);
  grid.build(from);
  g.resize(N, 5);
  interpolate_normalised<5>(grid, W_, UniformVolume{lat_.volume}, f, lat_.x, g, true,
                            "LPSPH reinitialisation: lattice point");  // Eq. (61) at the lattice points
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
  rebuild(t_, true);
  ++revision_;
}

std::vector<std::string> LagrangianFluid::describe() const {
  std::ostringstream m;
  const int N = size();
  m << "LPSPH: " << lat_.nx << " x " << lat_.ny << " = " << N << " moving particles (Eq. 37), "
    << verlet_.images_within_reach(im_, x_star_) << " images now, h = " << W_.h << " (" << prm_.h_over_dx
    << " (dx+dy)/2), " << neighbours_per_particle()
    << " neighbours per particle now; convection carried by the particle motion (no convection term); "
       "images, pairs, operators and systems rebuilt every step at the predicted positions x* = x^n + dt u^n";
  std::vector<std::string> lines{m.str()};
  std::ostringstream v;
  v << "LPSPH: pairs from a Verlet list (fluid/common/neighbours.hpp): candidates within 2h + skin, skin = "
    << verlet_.skin() << " (" << verlet_.skin() / W_.support() << " 2h), "
    << static_cast<double>(pairs_.size()) / N << " per particle now; built (cell list, new pattern) "
    << verlet_.builds() << " times, moved " << verlet_.updates() << " times";
  lines.push_back(v.str());
  std::ostringstream r;
  r << "LPSPH: reinitialisation onto the lattice (Eq. 61) ";
  if (prm_.lagrangian.reinit_every > 0)
    r << "every " << prm_.lagrangian.reinit_every << " steps (" << n_reinit_ << " so far)";
  else
    r << "never";
  r << "; breakdown when a kernel sum falls below " << prm_.lagrangian.min_kernel_sum << " (lowest so far "
    << S_low_ << ", now " << S_.minCoeff() << ")";
  lines.push_back(r.str());
  for (const auto& [name, sv] : {std::pair<const char*, const LinearSolver*>{"Crank-Nicolson", cn_.get()},
                                {"Poisson", poisson_.get()}}) {
    std::ostringstream s;
    s << "LPSPH: " << name << ": " << n_refactor_ << " new matrices";
    if (sv->info().nnz_factor == 0) {  // iterative: the matrices taken as they are
      s << ", conjugate gradients, " << sv->mean_iterations() << " iterations per solve so far";
      if (sv->preconditioner_factorisations() > 0)
        s << ", preconditioner factorised " << sv->preconditioner_factorisations() << " times (analysis kept in "
          << sv->preconditioner_analyses_kept() << ")";
      else if (sv->info().method.rfind("CG preconditioned", 0) == 0)
        s << ", no factorisation so far (the lattice's FFT solver preconditions)";
    } else {
      s << ", each refactorised, the symbolic analysis kept in "
        << (std::string(name) == "Poisson" ? n_reused_poisson_ : n_reused_cn_) << " (while the pattern stays)";
    }
    lines.push_back(s.str());
  }
  for (const auto& si : solver_info()) lines.push_back(si.describe());
  return lines;
}

std::vector<std::pair<std::string, double>> LagrangianFluid::figures() const {
  std::vector<std::pair<std::string, double>> f{
      {"images", verlet_.images_within_reach(im_, x_star_)},
      {"neighbours_per_particle", neighbours_per_particle()},
      {"kernel_sum_min", S_.minCoeff()},
      {"kernel_sum_lowest", S_low_},
      {"refactorised_steps", static_cast<double>(n_refactor_)},
      {"symbolic_reused_steps_crank_nicolson", static_cast<double>(n_reused_cn_)},
      {"symbolic_reused_steps_poisson", static_cast<double>(n_reused_poisson_)},
      {"reinitialisations", static_cast<double>(n_reinit_)},
      {"verlet_builds", static_cast<double>(verlet_.builds())}};
  if (cn_->mean_iterations() > 0) f.emplace_back("crank_nicolson_cg_iterations", cn_->mean_iterations());
  if (poisson_->mean_iterations() > 0) f.emplace_back("poisson_cg_iterations", poisson_->mean_iterations());
  for (const auto& [name, s] : {std::pair<const char*, const LinearSolver*>{"crank_nicolson", cn_.get()}, {"poisson", poisson_.get()}})
    if (s->preconditioner_factorisations() > 0)
      f.emplace_back(std::string(name) + "_preconditioner_factorisations", static_cast<double>(s->preconditioner_factorisations()));
  return f;
}

// LPSPH adds to the core's state the positions x^n and its counters.
void LagrangianFluid::extra_state(NamedArrays& st) const {
  Eigen::MatrixXd counters(1, 5);
  counters << S_low_, static_cast<double>(n_refactor_), static_cast<double>(n_reused_cn_),
      static_cast<double>(n_reused_poisson_), static_cast<double>(n_reinit_);
  st.emplace_back("x", x_);
  st.emplace_back("lagrangian_counters", counters);
}

void LagrangianFluid::restore_extra(const NamedArrays& st) {
  x_ = state_entry(st, "x", size(), 2);
  x_star_ = x_;
  rebuild(t_, true);  // the next step rebuilds at its own x* before using anything
  const Eigen::MatrixXd& c = state_entry(st, "lagrangian_counters", 1, 5);
  S_low_ = c(0, 0);
  n_refactor_ = static_cast<long>(c(0, 1));
  n_reused_cn_ = static_cast<long>(c(0, 2));
  n_reused_poisson_ = static_cast<long>(c(0, 3));
  n_reinit_ = static_cast<long>(c(0, 4));
}

}  // namespace sphib
