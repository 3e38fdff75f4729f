#include "fluid/eulerian/eulerian.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "fluid/algebra/solver_policy.hpp"

namespace sphib {

EulerianFluid::EulerianFluid(const FluidParams& params, Profiler* profiler) : ProjectionFluid(params, false, profiler) {
  visc_prm_.rtol = prm_.viscosity_rtol;
  if (prm_.projection == Projection::Auto)  // exact where the domain has a stream function (boundary.hpp)
    prm_.projection = stream_function_refusal(prm_.domain).empty() ? Projection::Exact : Projection::Approximate;
  const int N = lat_.size();

  // Neighbours: images and the pair list, once (the compact storage: the pairs a block of rows at a
  // time, as the assembly reads them; the whole list never exists).
  auto lattice_solver = [](SolverKind k) { return k == SolverKind::Auto || k == SolverKind::Fft; };
  compact_ = exact() && lattice_solver(prm_.cn_solver) && lattice_solver(prm_.poisson_solver);
  auto t0 = Profile::Clock::now();
  im_ = make_images(lat_, W_.support());
  std::unique_ptr<LatticePairs> blocks;
  if (compact_) {
    blocks = std::make_unique<LatticePairs>(lat_, im_.x, W_.support());
    pairs_count_ = blocks->count();
  } else {
    pairs_ = find_pairs(lat_, im_.x, W_.support());
    pairs_count_ = pairs_.size();
  }
  add_setup("neighbours", seconds_since(t0));

  // Operators, once (Eqs. 27-34), and the rows of their patterns that are lattice translates. The
  // convection gradient is the divergence's, so Stokes flow assembles nothing more.
  // Compact storage (exact projection, lattice solvers): every product of a step goes through the
  // stencils, so each operator keeps only its stencil's rows (stencil_rows_only), and what only the
  // setup reads is freed as soon as it has been read. The setup never holds the operators whole
  // together, nor the pair list (its blocks are searched as the assembly reads them): the phi
  // operators are assembled first and read (the Morris Laplacian by its solver, the phi gradients by
  // the exact projection's divergence D = -G^T), then the velocity operators; the Morris Laplacian
  // of odd images (lap_u.A) is reduced to its stencil's rows once the Crank-Nicolson and the
  // markers' solvers are made, before G^T G is computed from the velocity gradients. The lattice
  // solvers read their matrices' rows a block at a time (-lap, I - a lap, G^T G: none is made
  // whole), and the velocity gradients' transposes are read a block at a time, never whole.
  const double m = !exact() ? 0.0
                   : compact_ ? ExactProjection::gradient_normalisation(*blocks, W_)
                              : ExactProjection::gradient_normalisation(lat_, pairs_, W_);
  double factorisation = 0;
  ExactProjection::Divergence div;
  t0 = Profile::Clock::now();
  gauge_ = Gauge(lat_, NullSpace::Constants);
  if (compact_) {
    // Each set of operators by blocks of rows, never whole: the pairs of a block searched, its rows
    // assembled (operator_rows), read once by find_row_stencil (the classes and the kept rows; more
    // passes only should a class fall short); the velocity operators' image parts B whole (rows near
    // the walls only) from the first pass. Where a reader needs the whole rows again (the lattice solvers' models and row
    // checks, the transposes), StencilRows makes them from the kept ones, a block at a time.
    std::vector<Triplet> tB[3];
    const auto rows_of = [&](OperatorSet set, bool images) -> OperatorRows {
      return [&, set, images](const std::function<void(const std::vector<const SpMat*>&, int)>& f) mutable {
        PairList P;
        for (int r0 = 0; r0 < N; r0 += kAssemblyRows) {
          blocks->rows(r0, std::min(N, r0 + kAssemblyRows), P);
          const Operators b = operator_rows(P, r0, lat_, im_, W_, set);
          if (set == OperatorSet::LapPhi) {
            f({&b.lap_phi}, r0);
          } else if (set == OperatorSet::GradPhi) {
            f({&b.grad_phix, &b.grad_phiy}, r0);
          } else {
            const ImageOp* ops[3] = {&b.lap_u, &b.grad_ux, &b.grad_uy};
            for (int q = 0; images && q < 3; ++q)
              for (int i = 0; i < ops[q]->B.outerSize(); ++i)
                for (SpMat::InnerIterator it(ops[q]->B, i); it; ++it) tB[q].emplace_back(r0 + i, it.col(), it.value());
            f({&b.lap_u.A, &b.grad_ux.A, &b.grad_uy.A}, r0);
          }
        }
        images = false;  // (the first pass's only)
      };
    };
    std::vector<SpMat> kept;
    // the Morris Laplacian of phi, and its solver (for phi~ and the pressure of Eq. 35)
    lap_phi_st_lattice_ = find_row_stencil(rows_of(OperatorSet::LapPhi, false), N, kept);
    op_.lap_phi.swap(kept[0]);
    lap_phi_st_ = &lap_phi_st_lattice_;
    {
      const auto t1 = Profile::Clock::now();
      const StencilRows sr(lap_phi_st_lattice_, N);
      SystemSolver s = lattice_singular_solver(
          phi_system(), Field::Scalar, negated_rows([&](int r0, int k) { return sr.rows(op_.lap_phi, r0, k); }, N), N, gauge_,
          prm_.poisson_solver, lat_);
      if (s.solver) {
        poisson_ = std::move(s.solver);
        poisson_unpinned_ = s.unpinned;
      } else {  // the Laplacian whole again for the other solvers
        SpMat lap = sr.rows(op_.lap_phi, 0, N);
        op_.lap_phi.swap(lap);
        make_phi_solver();
        op_.lap_phi.swap(lap);
      }
      factorisation += seconds_since(t1);
    }
    // the phi gradients, read only by the exact projection's divergence D = -G^T (then freed)
    phi_st_lattice_ = find_row_stencil(rows_of(OperatorSet::GradPhi, false), N, kept);
    div = ExactProjection::divergence_by_blocks(kept[0], kept[1], phi_st_lattice_);
    kept.clear();
    // the velocity operators
    vel_st_lattice_ = find_row_stencil(rows_of(OperatorSet::Velocity, true), N, kept);
    blocks.reset();
    op_.lap_u.A.swap(kept[0]);
    op_.grad_ux.A.swap(kept[1]);
    op_.grad_uy.A.swap(kept[2]);
    ImageOp* whole[3] = {&op_.lap_u, &op_.grad_ux, &op_.grad_uy};
    for (int q = 0; q < 3; ++q) {
      whole[q]->B.resize(N, im_.size());
      whole[q]->B.setFromTriplets(tB[q].begin(), tB[q].end());
    }
  } else {
    Operators built = build_operators(pairs_, lat_, im_, W_);
    op_.swap(built);  // (not an assignment: that would copy)
    phi_st_lattice_ = find_row_stencil({&op_.grad_phix, &op_.grad_phiy});
    vel_st_lattice_ = find_row_stencil({&op_.lap_u.A, &op_.grad_ux.A, &op_.grad_uy.A});
  }
  operators_changed(&vel_st_lattice_, &phi_st_lattice_);
  conv_wall_x_ = conv_wall_y_ = Mat2::Zero(N, 2);  // the wall values' terms, once
  add_image_terms(op_.grad_ux.B, gx_b_rows_, c_wall_, conv_wall_x_);
  add_image_terms(op_.grad_uy.B, gy_b_rows_, c_wall_, conv_wall_y_);
  vel_images_ = ImageRows(vel_st_, N, {&op_.lap_u.B, &op_.grad_ux.B, &op_.grad_uy.B});
  lap_star_ = conv_old_ = Mat2::Zero(N, 2);
  add_setup("assembly", seconds_since(t0) - factorisation);

  // Factorisations, once (fluid/algebra/solver_policy.hpp). The approximate projection's Poisson operator is
  // the Morris Laplacian (Eqs. 31-32, the constants its null space); the exact projection solves the
  // stream function's normal equations (exact_projection.hpp) and the Morris Laplacian only when phi
  // is asked for (phi()); the compact storage made that one above, while the Morris Laplacian existed.
  t0 = Profile::Clock::now();
  if (im_.split()) {
    make_split_crank_nicolson();
  } else if (compact_) {  // the matrix I - a lap never made, lap made whole again only should that solver not apply
    const StencilRows sr(vel_st_lattice_, N);
    cn_ = lattice_crank_nicolson_solver(crank_nicolson_rows([&](int r0, int k) { return sr.rows(op_.lap_u.A, r0, k); },
                                                            N, a_cn()),
                                        N, prm_.cn_solver, lat_);
    if (!cn_) {
      SpMat lap = sr.rows(op_.lap_u.A, 0, N);
      op_.lap_u.A.swap(lap);
      cn_ = crank_nicolson_solver(crank_nicolson_matrix(), op_.lap_u.A, a_cn(), prm_.cn_solver, &lat_, Refactor::Once);
      op_.lap_u.A.swap(lap);
    }
  } else {
    cn_ = crank_nicolson_solver(crank_nicolson_matrix(), op_.lap_u.A, a_cn(), prm_.cn_solver, &lat_, Refactor::Once);
  }
  if (compact_) {
    streams_ = std::make_unique<ExactProjection>(lat_, im_, op_, m, vel_st_, prm_.poisson_solver, true, true, &div);
    streams_->make_solvers();
  } else if (exact()) {
    streams_ = std::make_unique<ExactProjection>(lat_, im_, op_, m, vel_st_, prm_.poisson_solver, true);
  } else {
    make_phi_solver();
  }
  add_setup("factorisation", seconds_since(t0) + factorisation);
  k_psi_ = prof_.on_demand_phase("stream function");
  convective_ = prm_.convection;
  // the markers' stream function: constant along walls, prescribed through an inflow; none where the
  // domain's sides give it no values (the markers then interpolate by SPH, coupling/interpolate.hpp)
  has_stream_function_ = stream_function_refusal(prm_.domain).empty();
  variable_viscosity_ = true;
  prof_.set_reporter([this](FluidReport& r) { report(r); });
  prof_.set_floor([this](FloorTimer& t) { floor_kernels(t); });
  prof_.set_stream_function_floor([this](FloorTimer& t) { stream_function_floor_kernels(t); });
}

void EulerianFluid::make_split_crank_nicolson() {
  // Each component's Laplacian with its own image parities (component_matrix, boundary.hpp), its
  // Crank-Nicolson matrix I - a lap (Eq. 28) and solver; the FFT solver's x transform from the
  // component's parity at the x walls (the x component is their normal one).
  const int N = size();
  const SpMat lap = compact_ ? StencilRows(vel_st_lattice_, N).rows(op_.lap_u.A, 0, N) : op_.lap_u.A;
  std::unique_ptr<LinearSolver> s[2];
  for (int a = 0; a < 2; ++a) {
    const SpMat la = component_matrix(lap, op_.lap_u.B, im_, a);
    s[a] = crank_nicolson_solver(crank_nicolson_matrix(la), la, a_cn(), prm_.cn_solver, &lat_, Refactor::Once, {},
                                 a == 0 ? Field::VelocityNormal : Field::VelocityTangential);
    s[a]->annotate(a == 0 ? "; the x component's (its own image parities)" : "; the y component's (its own image parities)",
                   0.0);
  }
  cn_ = std::move(s[0]);
  cn_v_ = std::move(s[1]);
}

void EulerianFluid::pairs_current() const {
  if (pairs_.offset.empty()) pairs_ = find_pairs(lat_, im_.x, W_.support());  // freed by the compact storage
}

const Operators& EulerianFluid::operators() const {
  if (compact_) {  // the whole matrices again (their values are the assembly's: the same bits)
    pairs_current();
    Operators whole = build_operators(pairs_, lat_, im_, W_);
    op_.swap(whole);
    compact_ = false;
  }
  return op_;
}

std::string EulerianFluid::phi_system() const {
  return exact() ? "Poisson (Morris Laplacian: phi and p of the exact projection)" : "Poisson";
}

void EulerianFluid::make_phi_solver() const {
  SpMat minus_lap = op_.lap_phi;  // -lap (negated in place: an assigned -A grows its own storage)
  negate(minus_lap);
  auto s = singular_solver(phi_system(), Field::Scalar, minus_lap, gauge_, prm_.poisson_solver, &lat_, Refactor::Once);
  poisson_ = std::move(s.solver);
  poisson_unpinned_ = s.unpinned;
}

void EulerianFluid::viscous_rhs(const Mat2& F) {
  ScopedTimer tm(prof_, k_rhs_);
  // Eq. (28) as in the core, with, when the flow is convective, Eqs. (40)-(41): (u.grad)u_i =
  // u_i (d/dx)u + v_i (d/dy)u with images of u^n (wall values), and Eq. (39): AB2, 3/2 N^n -
  // 1/2 N^{n-1} (first step: Euler, N^{-1} = N^0); conv_old_ keeps N^n. One pass over the velocity
  // pattern for lap u^n and the four derivatives and the row-local arithmetic.
  set_image_terms(op_.lap_u.B, lap_b_rows_, c_star_, lap_star_);  // B c*: the wall rows only
  PredictorRhs p;
  p.lap = &op_.lap_u.A;
  p.gx = &op_.grad_ux.A;
  p.gy = &op_.grad_uy.A;
  p.st = vel_st_;
  p.images = &vel_images_;
  p.rows.u = u_.data();
  p.rows.F = F.data();
  p.rows.bc = lap_star_.data();
  p.rows.lw = lap_wall_.data();
  p.rows.cwx = conv_wall_x_.data();
  p.rows.cwy = conv_wall_y_.data();
  if (im_.split()) {  // the images of u^n with each component's parity (boundary.hpp, add_split_images)
    split_c_.setZero(im_.size(), 2);
    add_split_images(im_, u_, split_c_);
    split_lw_ = lap_wall_;
    split_cwx_ = conv_wall_x_;
    split_cwy_ = conv_wall_y_;
    add_image_terms(op_.lap_u.B, lap_b_rows_, split_c_, split_lw_);
    add_image_terms(op_.grad_ux.B, gx_b_rows_, split_c_, split_cwx_);
    add_image_terms(op_.grad_uy.B, gy_b_rows_, split_c_, split_cwy_);
    p.rows.lw = split_lw_.data();
    p.rows.cwx = split_cwx_.data();
    p.rows.cwy = split_cwy_.data();
  }
  p.rows.a = a_cn();
  p.rows.k = prm_.dt / prm_.rho;
  p.rows.kc = convective_ ? prm_.dt : 0.0;
  p.rows.first = first_;
  p.rows.conv_old = convective_ ? conv_old_.data() : nullptr;
  p.rows.conv = conv_.data();
  p.rows.rhs = rhs_.data();
  predictor_rhs(p);
  // A variable viscosity: its difference from the constant operator and its cross term, in the rows
  // where the viscosity is not uniformly mu (fluid/eulerian/variable_viscosity.hpp).
  if (visc_ && visc_->active())
    visc_->add_rhs(u_, c_wall_, c_star_, grad_phi_, prm_.dt / prm_.rho, prm_.dt * nu(), first_, rhs_);
}

void EulerianFluid::set_viscosity(const int* at, const double* m, int n) {
  if (!visc_) {
    bool uniform = true;
    for (int q = 0; q < n && uniform; ++q) uniform = m[q] == 1.0;
    if (uniform) return;  // nothing differs from the constant-viscosity step
    if (im_.split())
      throw std::invalid_argument("domain.free_slip: a variable viscosity (membrane.viscosity_ratio) is not available "
                                  "with a free-slip side (its operator rows carry one velocity parity)");
    VariableViscosityParams vp = visc_prm_;
    vp.a = a_cn();
    operators();  // the whole matrices and the pair list (compact storage: assembled again)
    pairs_current();
    visc_ = std::make_unique<VariableViscosity>(pairs_, im_, size(), volume_, W_, crank_nicolson_matrix(), *cn_, vp);
    k_visc_ = prof_.phase("variable viscosity (operator rows)");
  }
  ScopedTimer tm(prof_, k_visc_);
  visc_->set(at, m, n);
}

void EulerianFluid::project() {
  if (!exact()) return project_approximate();
  {
    ScopedTimer tm(prof_, k_div_);
    streams_->rhs(u_star_, revision_);
  }
  {
    ScopedTimer tm(prof_, k_solve_poisson_);
    streams_->solve();
  }
  ScopedTimer tm(prof_, k_project_);
  streams_->velocity(u_star_, prm_.dt / prm_.rho, u_, grad_phi_);
  phi_step_ = -1;
}

const Vec& EulerianFluid::phi() const {
  if (exact() && phi_step_ != n_) {
    // The projection's own phi (G^T G phi = -(rho/dt) D u*) is determined up to the components G
    // hardly sees, which G^T G's tiny eigenvalues near its null modes amplify: measured, a fixed
    // membrane at h = 2.25 dx gives a pressure jump of 9.7 instead of 1. Its velocity is immune (it
    // sees only G phi), but phi and p are taken as the smooth phi~ with the same D G phi:
    //   -lap phi~ = G^T (G phi) = -D (G phi),   lap the Morris Laplacian of Eq. (31),
    // i.e. the approximate projection's phi for the same u* (jump 1.0000 at 70 x 70, Section 5.2.1).
    if (!poisson_) make_phi_solver();
    Vec& b = b_phi_;  // the step's workspace, free between steps
    streams_->divergence(grad_phi_, b);  // D G phi = -G^T G phi, G phi = rho/dt (u* - u^{n+1})
    b *= -1.0;
    gauge_.project(b);
    if (!poisson_unpinned_) gauge_.pin_rhs(b);
    poisson_->solve(b.data(), phi_.data(), 1);
    phi_.array() -= phi_.mean();
    phi_step_ = n_;
  }
  return phi_;
}

double EulerianFluid::max_abs_divergence() const {
  if (!exact()) return ProjectionFluid::max_abs_divergence();
  Vec d(size());
  streams_->velocity_divergence(u_, d);  // the divergence the projection makes zero
  return max_abs(d);
}

StreamFunction EulerianFluid::stream_function() const {
  ScopedTimer tm(prof_, k_psi_);
  if (!streams_) {
    pairs_current();
    streams_ = std::make_unique<ExactProjection>(lat_, im_, op_, ExactProjection::gradient_normalisation(lat_, pairs_, W_),
                                                 vel_st_, prm_.poisson_solver, false);
  }
  return streams_->markers(u_, revision_);
}

double EulerianFluid::poisson_residual() const {
  // ||A x - b|| / ||b|| with the unpinned operator and the right-hand side of the last step:
  // the stream function's normal equations (exact projection) or Eq. (32)
  if (exact()) return streams_->normal_equations_residual(u_star_);
  Vec b = (-prm_.rho / prm_.dt) * div_;
  gauge_.project(b);
  Vec r = -(operators().lap_phi * phi_);
  r -= b;
  const double nb = b.norm();
  return nb > 0 ? r.norm() / nb : r.norm();
}

std::vector<SolverInfo> EulerianFluid::solver_info() const {
  std::vector<SolverInfo> v{cn_->info()};
  if (cn_v_) v.push_back(cn_v_->info());
  if (visc_) v.push_back(visc_->solver().info());
  if (streams_ && exact()) v.push_back(streams_->psi_solver().info());
  if (poisson_) v.push_back(poisson_->info());
  if (streams_ && !exact() && streams_->has_psi_solver()) v.push_back(streams_->psi_solver().info());
  return v;
}

void EulerianFluid::report(FluidReport& r) const {
  std::ostringstream m;
  m << "EPSPH: " << lat_.nx << " x " << lat_.ny << " = " << size() << " fixed particles, " << im_.size()
    << " images, h = " << W_.h << " (" << prm_.h_over_dx << " (dx+dy)/2), "
    << static_cast<double>(pairs_count_) / size() << " neighbours per particle, convection "
    << (prm_.convection ? "on" : "off (Stokes)") << ", "
    << (exact() ? "exact projection (Poisson operator D G)" : "approximate projection (Poisson operator: Morris Laplacian)")
    << "; products: " << vel_st_lattice_.stencil_rows() << " velocity and " << phi_st_lattice_.stencil_rows()
    << " phi rows of " << size() << " applied as a lattice stencil";
  if (exact()) m << " (D = -G^T: " << streams_->divergence_stencil_rows() << " rows)";
  r.lines = {m.str()};
  for (const auto& si : solver_info()) r.lines.push_back(si.describe());

  r.figures = {{"images", im_.size()}, {"neighbours_per_particle", static_cast<double>(pairs_count_) / size()}};
  if (cn_->mean_iterations() > 0) r.figures.emplace_back("crank_nicolson_cg_iterations", cn_->mean_iterations());
  if (visc_) r.figures.emplace_back("variable_viscosity_cg_iterations", visc_->solver().mean_iterations());

  auto nnz = [](const SpMat& A) { return static_cast<long>(A.nonZeros()); };
  Footprint f;
  f.operator_nonzeros = nnz(op_.lap_u.A) + nnz(op_.lap_u.B) + nnz(op_.grad_ux.A) + nnz(op_.grad_ux.B) +
                        nnz(op_.grad_uy.A) + nnz(op_.grad_uy.B) + nnz(op_.lap_phi) + nnz(op_.grad_phix) +
                        nnz(op_.grad_phiy);
  for (const auto& si : solver_info()) {
    f.factor_nonzeros += si.nnz_factor ? si.nnz_factor : si.nnz_used;  // an iterative solver keeps A itself
    if (si.system == "Poisson") f.factor_nonzeros += si.nnz_A;         // kept for the residual check
  }
  f.pairs = static_cast<long>(pairs_.size());  // (none kept by the compact storage)
  r.footprint = f;
}

void EulerianFluid::floor_kernels(FloorTimer& t) const {
  Mat2 a = u_, b = u_, c = u_, x = u_star_;
  Vec d(size()), f = phi_;
  if (prm_.convection) t.kernel([&] { gradient2(op_.grad_ux.A, op_.grad_uy.A, u_, a, b, vel_st_); });
  t.kernel([&] { apply2(op_.lap_u.A, u_, c, vel_st_); });
  t.kernel([&] {
    x = u_star_;  // the same warm start a step gives an iterative solver
    cn_->solve(rhs_.data(), x.data(), 2);
  });
  if (exact()) return t.add(streams_->floor_seconds(u_star_, a, t.reps()));
  t.kernel([&] { divergence(op_.grad_ux.A, op_.grad_uy.A, u_star_, d, vel_st_); });
  t.kernel([&] { poisson_->solve(b_phi_.data(), f.data(), 1); });
  t.kernel([&] { gradient(op_.grad_phix, op_.grad_phiy, phi_, a, phi_st_); });
}

void EulerianFluid::stream_function_floor_kernels(FloorTimer& t) const {
  stream_function();  // its right-hand side and solver, as a step makes them
  t.add(streams_->markers_floor_seconds(t.reps()));
}

// EPSPH adds to the core's state the convection N^n kept for AB2 (Eq. 39) and, with the exact
// projection, C^T u* and its flux (the markers' stream function of u^{n+1}).
void EulerianFluid::extra_state(NamedArrays& st) const {
  st.emplace_back("conv_old", conv_old_);
  if (visc_) visc_->save(st);
  if (exact()) streams_->save(st);
}

void EulerianFluid::restore_extra(const NamedArrays& st) {
  conv_old_ = state_entry(st, "conv_old", size(), 2);
  bool has_visc = false;
  for (const auto& e : st) has_visc |= e.first == "viscous_cross_old";
  if (has_visc != static_cast<bool>(visc_))
    throw std::runtime_error(visc_ ? "checkpoint: no variable viscosity's state, but this scene has one"
                                   : "checkpoint: a variable viscosity's state, but this scene has none");
  if (visc_) visc_->load(st);
  phi_step_ = n_;
  if (exact()) streams_->load(st, revision_);
}

}  // namespace sphib
