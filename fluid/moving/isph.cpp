#include "fluid/moving/isph.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fluid/common/loads.hpp"
#include "fluid/algebra/solver_policy.hpp"

namespace sphib {

std::optional<ParamProblem> isph_problem(const FluidParams& p) {
  if (auto e = free_surface_problem(p.method, p.domain, p.free_surface, p.gravity)) return e;
  const FreeSurfaceParams& fs = p.free_surface;
  const bool free = has_free_surface(p.domain, fs);
  if (fs.detection == SurfaceDetection::Dilts)
    return ParamProblem{"free_surface.detection", "\"dilts\" is not available for isph (A Section 3.5: ISPH marks the "
                                                  "surface by Eq. 26, \"divergence\")"};
  if (free && fs.detection == SurfaceDetection::None)
    return ParamProblem{"free_surface.detection", "\"none\" leaves isph without the Dirichlet rows p = 0 of its free surface "
                                                  "(A Section 3.5): the Poisson problem would have no solution"};
  if (p.projection == Projection::Exact)
    return ParamProblem{"fluid.projection", "\"exact\" is available for method \"eulerian\" only (isph: \"approximate\", "
                                            "A Eq. 24 with Lee's Laplacian, Eq. 17)"};
  if (p.poisson_solver == SolverKind::Fft || p.cn_solver == SolverKind::Fft)
    return ParamProblem{p.poisson_solver == SolverKind::Fft ? "solver.poisson" : "solver.crank_nicolson",
                        "\"fft\" needs the fixed lattice (method \"eulerian\"); isph's particles move"};
  if (free && (p.poisson_solver == SolverKind::PcgFft || p.cn_solver == SolverKind::PcgFft))
    return ParamProblem{p.poisson_solver == SolverKind::PcgFft ? "solver.poisson" : "solver.crank_nicolson",
                        "\"pcg_fft\" does not apply to a partly filled tank (its preconditioner is the FFT solver of the "
                        "full lattice); use pcg_cholmod or a CHOLMOD factorisation"};
  if (!(p.isph.shifting_A > 0) || !std::isfinite(p.isph.shifting_A))
    return ParamProblem{"isph.shifting_A", "must be positive and finite (Lind et al. 2012: 1 to 6)"};
  if (auto e = gate_problem(p)) return e;
  if (p.isph.viscous == IsphViscous::Explicit && p.cn_solver != SolverKind::Auto)
    return ParamProblem{"solver.crank_nicolson", "does not apply with isph.viscous = \"explicit\" (A Eq. 22: no "
                                                 "Crank-Nicolson system)"};
  return std::nullopt;
}

namespace {

ParticleSet particles_of(const FluidParams& p) {
  if (const auto e = isph_problem(p)) throw std::invalid_argument(e->key + ": " + e->what);
  return fill_particles(make_lattice(p.domain, p.nx, p.ny), p.free_surface.fill);
}

ShiftingParams shifting_params(const IsphParams& p) {
  ShiftingParams s;
  s.kind = p.shifting != Shifting::Auto   ? p.shifting
           : p.scheme == IsphScheme::Paper ? Shifting::None
                                           : Shifting::Fickian;
  s.A = p.shifting_A;
  return s;
}

// The Verlet skin (neighbours.hpp), adaptive in [0.01, 0.3] of the support 2h, as LPSPH's
// (docs/method/choices.md, "LPSPH: the Verlet skin").
constexpr double kSkinMin = 0.01, kSkinMax = 0.3;

// f(i, a, s, side, dist) for every particle i (rows of x) and every wall of d: axis a (0: x, 1: y),
// s = 0 for the low wall and 1 for the high one, dist the particle's distance to that wall.
template <class F>
void for_each_wall_distance(const Domain& d, const Mat2& x, F&& f) {
  for (int i = 0; i < x.rows(); ++i)
    for (int a = 0; a < 2; ++a)
      for (int s = 0; s < 2; ++s) {
        const Side side = a == 0 ? (s == 0 ? Left : Right) : (s == 0 ? Bottom : Top);
        if (!d.is_wall(side)) continue;
        const double xi = x(i, a), lo = a == 0 ? d.x0 : d.y0, hi = a == 0 ? d.x1 : d.y1;
        f(i, a, s, side, s == 0 ? xi - lo : hi - xi);
      }
}

}  // namespace

IsphFluid::IsphFluid(const FluidParams& params, Profiler* profiler)
    : IsphFluid(params, particles_of(params), profiler) {}

IsphFluid::IsphFluid(const FluidParams& params, const ParticleSet& set, Profiler* profiler)
    : ProjectionFluid(params, true, profiler, static_cast<int>(set.x.rows()), set.volume), x_star_(set.x),
      walls_(make_virtual_walls(lat_, W_.support())),
      verlet_(prm_.domain, W_.support() * (1.0 - 1e-12), kSkinMin * W_.support(), kSkinMax * W_.support(), walls_.x),
      shifter_(shifting_params(params.isph)) {
  x_ = set.x;
  const FreeSurfaceParams& fs = prm_.free_surface;
  explicit_viscous_ = prm_.isph.viscous == IsphViscous::Explicit;
  accel_ = prm_.gravity;  // A Eq. (22)
  const SurfaceDetection how = detection_for(prm_.method, prm_.domain, fs);
  detect_ = how != SurfaceDetection::None;
  detector_ = SurfaceDetector(how, fs.beta, fs.dilts_radius * W_.h);
  surface_.assign(size(), 0);
  div_r_ = Vec::Zero(size());
  tank_walls_ = walls_.size();
  if (prm_.gate.on) {
    gate_top_ = x_.col(1).maxCoeff() + 0.5 * lat_.dy;
    gate_in_ = true;
    place_gate(0.0);
  }
  p_w_ = Vec::Zero(walls_.size());
  rho_ = Vec::Constant(size(), prm_.rho);
  // p at t = 0 (A Eq. 31's p(0); also the first warm start of an iterative Poisson solver): the
  // hydrostatic p0 = rho |g| (H - y) of A Section 3.7, zero at the top row of particles, where the
  // free surface's Dirichlet rows put it (half a spacing below the region's top).
  const Vec depth = hydrostatic_depth(x_, fs.fill, prm_.domain, prm_.gravity);
  phi_ = prm_.rho * prm_.gravity.norm() * (depth.array() - depth.minCoeff());
  // Without a free surface (a full tank) the Poisson operator has the constants as its null space.
  if (!has_free_surface(prm_.domain, fs)) gauge_ = Gauge(lat_, NullSpace::Constants);
  k_ = moving_phases("move particles (A Eq. 25)", "neighbours (Verlet list with the wall particles)",
                     "operators, systems, A Eq. (26) sums");
  k_surface_ = prof_.phase("free surface: Dirichlet rows (A Eq. 26)");
  if (shifter_.params().kind != Shifting::None) k_shift_ = prof_.phase("particle shifting");
  dr_ = Mat2::Zero(size(), 2);
  auto t0 = Profile::Clock::now();
  geometry(true);
  consistent_ = prm_.isph.scheme == IsphScheme::Consistent;
  if (consistent_) {  // the full support's sums, then the mirror rows they set
    reference_sums();
    assemble(false);
  }
  add_setup("neighbours", 0.0);
  add_setup("assembly", seconds_since(t0));
  t0 = Profile::Clock::now();
  make_solvers();
  add_setup("factorisation", seconds_since(t0));
  wall_pressure();
  prof_.set_reporter([this](FluidReport& r) {
    r.lines = describe();
    r.figures = figures();
  });
}

// Morris et al. (1997), A Section 3.6: the factor beta = 1 + d_w / d_i of every pair with a wall
// particle (walls.hpp; corner blocks carry their velocity, beta = 1).
void IsphFluid::morris_factors() {
  const int N = size();
  beta_.resize(pairs_.size());
  for (int i = 0; i < N; ++i)
    for (int k = pairs_.offset[i]; k < pairs_.offset[i + 1]; ++k) {
      const int w = pairs_.j[k] - N;
      if (w < 0) continue;
      const int side = walls_.side[w];
      if (side == kGateSide) {  // Morris's factor with the distance to the gate's face; 1 for a particle past it
        const double dA = prm_.gate.x - x_star_(i, 0);
        beta_[k] = dA > 0 ? 1.0 + walls_.dist[w] / std::max(dA, 0.5 * lat_.dx) : 1.0;
        continue;
      }
      beta_[k] = side < 0 ? 1.0 : morris_wall_factor(lat_, side, walls_.dist[w], x_star_(i, 0), x_star_(i, 1), INFINITY);
    }
}

void IsphFluid::geometry(bool force) {
  auto t0 = Profile::Clock::now();
  const bool built = verlet_.update(x_star_, im_, pairs_, force);
  prof_.add(k_.neighbours, seconds_since(t0));
  assemble(built);
}

// The pairs with a wall particle closer than 2h, as loads.hpp takes them.
void IsphFluid::find_wall_pairs() {
  const int N = size();
  ParticlePairs& P = wall_pairs_;
  for (auto* v : {&P.i, &P.j}) v->clear();
  for (auto* v : {&P.rx, &P.ry, &P.r, &P.W, &P.F}) v->clear();
  for (int i = 0; i < N; ++i)
    for (int k = pairs_.offset[i]; k < pairs_.offset[i + 1]; ++k)
      if (pairs_.j[k] >= N && pairs_.r[k] < verlet_.reach()) {
        double w = 0;
        P.i.push_back(i);
        P.j.push_back(pairs_.j[k]);
        P.rx.push_back(pairs_.rx[k]);
        P.ry.push_back(pairs_.ry[k]);
        P.r.push_back(pairs_.r[k]);
        P.F.push_back(KernelWF(W_).F(pairs_.r[k], &w));
        P.W.push_back(w);
      }
}

// The wall particles' pressure from the fluid's, A Eq. (30) normalised with the hydrostatic term of
// Adami et al. (loads.hpp, WallPressure::Extrapolated): exact for a fluid at rest, and a wall
// particle beside a surface particle (p = 0) still carries the pressure of the fluid below it.
void IsphFluid::wall_pressure() {
  wall_particle_pressure(WallPressure::Extrapolated, size(), wall_pairs_, V_, phi_, rho_, prm_.gravity, p_w_, work_);
}

void IsphFluid::project() {
  wall_repulsion();
  project_approximate();  // A Eqs. (23)-(24)
  clip_tension();
  wall_pressure();
  wall_gradient();
  surface_gradient();
  wall_contact();
}

// The wall particles' part of A Eq. (13) beyond 2 p_i (the operator's, p_w = p_i pair by pair: see
// the header), sum_w V (p_w - p_i) grad_i W_iw, and its part of Eq. (23). The paper's scheme:
// p_w - p_i = rho g . (x_w - x_i), dp/dn = 0 with the hydrostatic term (A Section 3.6). The consistent
// scheme: p_w the wall particle's pressure extrapolated from the fluid (wall_pressure, Adami et al.
// 2012 Eq. 27), which carries the fluid's pressure gradient along the wall; with the pair rule a
// particle of the first row feels only its fluid neighbours' part of it (0.77 on the lattice at
// h = 1.3 dx; the second row 0.99: test Isph.PressureGradientAlongTheFloorIsTheFluids). Both rules give
// the hydrostatic value for a fluid at rest, so the rest state is unchanged.
void IsphFluid::wall_gradient() {
  const int N = size();
  const double V = lat_.volume, k = prm_.dt / prm_.rho;
  const ParticlePairs& P = wall_pairs_;
  for (int q = 0; q < P.size(); ++q) {
    const int i = P.i[q];
    const double o = consistent_ ? p_w_[P.j[q] - N] - phi_[i]
                                 : -prm_.rho * (prm_.gravity.x() * P.rx[q] + prm_.gravity.y() * P.ry[q]);  // x_w - x_i = -(rx, ry)
    const double g = V * o * P.F[q];
    grad_phi_(i, 0) += g * P.rx[q];
    grad_phi_(i, 1) += g * P.ry[q];
    u_(i, 0) -= k * g * P.rx[q];
    u_(i, 1) -= k * g * P.ry[q];
  }
  if (consistent_) {  // the sum form over the lattice's second moment: exact for a linear p on the lattice
    grad_phi_ /= M0_;
    u_.noalias() = u_star_ - k * grad_phi_;
  }
}

const Mat2& IsphFluid::pressure_gradient(const Vec& p) {
  if (p.size() != size()) throw std::invalid_argument("ISPH: pressure_gradient: p has the wrong size");
  phi_ = p;
  gradient(op_.grad_phix, op_.grad_phiy, phi_, grad_phi_, phi_st_);
  u_.noalias() = u_star_ - (prm_.dt / prm_.rho) * grad_phi_;
  wall_pressure();
  wall_gradient();
  surface_gradient();
  return grad_phi_;
}

// Negative pressures set to zero, and u^{n+1} from the clipped p (as MPS, Koshizuka et al. 1998, A's
// reference for the wall conditions): without it a particle near the surface whose neighbours are
// nearly all surface particles gets p of either sign of ~1e6 Pa, alternating from step to step, and
// the dam break blows up (docs/method/choices.md, "ISPH: negative pressures clipped").
void IsphFluid::clip_tension() {
  if (gauge_.dimension() > 0) {
    // A full tank: p is defined up to a constant, and the gauge's zero mean makes it negative in part
    // of the tank, where the sum form's 2 p_i grad C_i pulls particles together (the tensile
    // instability: docs/method/choices.md, "ISPH: negative pressures clipped"). The consistent scheme takes the constant that makes
    // the smallest p zero (the gradient of a constant is zero on a full support).
    if (!consistent_) return;
    phi_.array() -= phi_.minCoeff();
    gradient(op_.grad_phix, op_.grad_phiy, phi_, grad_phi_, phi_st_);
    u_.noalias() = u_star_ - (prm_.dt / prm_.rho) * grad_phi_;
    return;
  }
  // Only the clipped particles' values change, so only their columns of the gradient: the particles'
  // entries of A Eq. (13)'s sum form are antisymmetric (G_ij = V x_ij F_ij = -G_ji, one volume), so
  // column j off the diagonal is minus row j; the diagonal G_jj (with the wall pairs) is row j's.
  const double k = prm_.dt / prm_.rho;
  for (int j = 0; j < size(); ++j) {
    if (!(phi_[j] < 0)) continue;
    const double d = -phi_[j];  // phi_j's change
    phi_[j] = 0.0;
    SpMat::InnerIterator gx(op_.grad_phix, j), gy(op_.grad_phiy, j);
    for (; gx; ++gx, ++gy) {
      const int i = static_cast<int>(gx.col());
      const double ax = (i == j ? gx.value() : -gx.value()) * d, ay = (i == j ? gy.value() : -gy.value()) * d;
      grad_phi_(i, 0) += ax;
      grad_phi_(i, 1) += ay;
      u_(i, 0) -= k * ax;
      u_(i, 1) -= k * ay;
    }
  }
}

// Lennard-Jones repulsion of the inner wall row on u* (Monaghan's wall particles, A Section 3.6, with
// Coelho et al.'s Eq. 20, D = 2 g H, r0 = dx): it keeps the particles next to a wall off it
// (docs/method/choices.md, "ISPH: wall repulsion and the surface gradient").
void IsphFluid::wall_repulsion() {
  const double D = 2.0 * prm_.gravity.norm() * fluid_height(prm_.free_surface.fill, prm_.domain, prm_.gravity);
  if (D == 0) return;
  // consistent: r0 just inside the spacing, so that a fluid at rest on the lattice (every wall pair at
  // r = dx or beyond) feels nothing; at r0 = dx the one-sided spring makes the rest state unstable
  // (docs/method/choices.md, "ISPH: wall repulsion and the surface gradient")
  const double r0 = std::min(lat_.dx, lat_.dy) * (consistent_ ? 0.98 : 1.0), dt = prm_.dt;
  const ParticlePairs& P = wall_pairs_;
  for (int q = 0; q < P.size(); ++q) {
    const int w = P.j[q] - size();
    if (!walls_.inner[w] || P.r[q] >= r0) continue;
    const double a = r0 / P.r[q], a4 = a * a * a * a;
    const double f = D * (a4 * a4 * a4 - a4) / (P.r[q] * P.r[q]);
    u_star_(P.i[q], 0) += dt * f * P.rx[q];
    u_star_(P.i[q], 1) += dt * f * P.ry[q];
  }
}

// At surface particles the sum form of A Eq. (13) reads the missing neighbours beyond the surface as
// p = 0, a force of order p_i / h on a particle next to the p = 0 row; there the gradient is the
// renormalised difference form over the fluid neighbours (Randles & Libersky), on the directions
// they span (docs/method/choices.md, "ISPH: wall repulsion and the surface gradient").
void IsphFluid::surface_gradient() {
  const int N = size();
  const double k = prm_.dt / prm_.rho, reach = verlet_.reach();
  for (int i : dirichlet_rows_) {
    double m00 = 0, m01 = 0, m11 = 0, gx = 0, gy = 0;
    for (int q = pairs_.offset[i]; q < pairs_.offset[i + 1]; ++q) {
      const double r = pairs_.r[q];
      const int j = pairs_.j[q];
      if (r >= reach || j >= N) continue;
      const double F = W_.F(r), rx = pairs_.rx[q], ry = pairs_.ry[q], dp = phi_[j] - phi_[i];
      m00 -= volume_ * rx * rx * F; m01 -= volume_ * rx * ry * F; m11 -= volume_ * ry * ry * F;
      gx += volume_ * dp * rx * F; gy += volume_ * dp * ry * F;
    }
    // M^+ g over the directions in which the neighbours span (eigenvalues above 0.1 of a full support's 1)
    const double tr = m00 + m11, det = m00 * m11 - m01 * m01, disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
    const double lam1 = 0.5 * tr + disc, lam2 = 0.5 * tr - disc;
    double G[2] = {0, 0};
    if (lam2 >= 0.1) {  // both directions: M^-1 g
      G[0] = (m11 * gx - m01 * gy) / det;
      G[1] = (m00 * gy - m01 * gx) / det;
    } else if (lam1 >= 0.1) {  // one direction: the eigenvector of lam1
      double ex = m01, ey = lam1 - m00;
      if (std::hypot(ex, ey) <= 1e-12 * lam1) { ex = m00 >= m11 ? 1 : 0; ey = 1 - ex; }
      const double n = std::hypot(ex, ey), c = (ex * gx + ey * gy) / (n * n * lam1);
      G[0] = c * ex;
      G[1] = c * ey;
    }
    u_(i, 0) = u_star_(i, 0) - k * G[0];
    u_(i, 1) = u_star_(i, 1) - k * G[1];
    grad_phi_(i, 0) = G[0];
    grad_phi_(i, 1) = G[1];
  }
}

// No particle comes closer than half a spacing to a wall: where u^{n+1} would take it there, the
// normal component of its velocity relative to the wall is cut to what reaches that distance (zero
// when it is already there); its share goes into grad p, which the loads read.
void IsphFluid::wall_contact() {
  const Domain& d = prm_.domain;
  const double k = prm_.dt / prm_.rho, dt = prm_.dt;
  const double gap[2] = {0.5 * lat_.dx, 0.5 * lat_.dy};
  for_each_wall_distance(d, x_, [&](int i, int a, int s, Side side, double dist) {
    const double uw = d.wall_velocity[side][a], into = s == 0 ? uw - u_(i, a) : u_(i, a) - uw;  // closing speed
    const double allowed = std::max(0.0, (dist - gap[a]) / dt);
    if (into <= allowed) return;
    const double un = s == 0 ? uw + allowed : uw - allowed;
    grad_phi_(i, a) += (u_(i, a) - un) / k;
    u_(i, a) = un;
  });
  if (!gate_in_) return;
  for (int i = 0; i < size(); ++i) {  // the gate's face, x = gate.x, above its lower edge
    const double dist = prm_.gate.x - x_(i, 0);
    if (!(dist > 0) || x_(i, 1) <= gate_bottom_) continue;
    const double allowed = std::max(0.0, (dist - gap[0]) / dt);
    if (u_(i, 0) <= allowed) continue;
    grad_phi_(i, 0) += (u_(i, 0) - allowed) / k;
    u_(i, 0) = allowed;
  }
}

// The consistent scheme's Poisson rows beside the free surface (see the header): a particle whose support
// the surface cuts reads the missing neighbours as mirror images of itself with p = -p_i (the surface
// the Dirichlet row p = 0 between), so -lap p_i gains -4 V p_i sum_missing F, sum_missing F = S_F -
// sum_present F (S_F the full support's, reference_sums) over the particles and the wall particles.
void IsphFluid::surface_mirror() {
  for (int i = 0; i < size(); ++i) {
    const double missing = S_F_ - csum_.sum_F[i];  // < 0 (F < 0): part of the support is empty
    if (!surface_[i] && missing < 0) A_phi_.valuePtr()[diag_[i]] -= 4.0 * volume_ * missing;
  }
}

// The sums of the mirror rows and of the shifts (shifting.hpp's ConcentrationSums) from what the
// assembly made, without a pass of their own over the pairs: grad C_i = sum_j V_j x_ij F_ij is the
// diagonal of the sum-form gradient G of A Eq. (13) less its wall pairs' second half (the rule
// p_w = p_i puts V_w x_iw F_iw there twice); sum_j F_ij = -A_phi,ii / (2 V) over the particles plus the
// wall pairs' F; the particles beside the surface: the surface and those with a Poisson entry to a
// surface particle (A_phi before the Dirichlet rows; the operators share one pattern,
// particle_operators.hpp). Lind et al.'s tensile term (R) is not in this grad C.
void IsphFluid::surface_sums() {
  const int N = size();
  if (op_.grad_phix.nonZeros() != A_phi_.nonZeros() || op_.grad_phiy.nonZeros() != A_phi_.nonZeros())
    throw std::logic_error("ISPH: the Poisson matrix and the gradient do not share their pattern");
  const int *outer = A_phi_.outerIndexPtr(), *col = A_phi_.innerIndexPtr();
  const double *a = A_phi_.valuePtr(), *gx = op_.grad_phix.valuePtr(), *gy = op_.grad_phiy.valuePtr();
  csum_.grad_C.resize(N, 2);
  csum_.sum_F.resize(N);
  csum_.near.assign(N, 0);
  diag_.resize(N);
  for (int i = 0; i < N; ++i) {
    const int d = static_cast<int>(std::lower_bound(col + outer[i], col + outer[i + 1], i) - col);  // columns sorted
    diag_[i] = d;
    csum_.grad_C(i, 0) = gx[d];  // sum_j V x_ij F_ij over the particles, the wall pairs twice (below)
    csum_.grad_C(i, 1) = gy[d];
    csum_.sum_F[i] = -a[d] / (2.0 * volume_);
  }
  const double Vw = lat_.volume;
  for (int q = 0; q < wall_pairs_.size(); ++q) {
    const int i = wall_pairs_.i[q];
    const double F = wall_pairs_.F[q];
    csum_.grad_C(i, 0) -= Vw * wall_pairs_.rx[q] * F;
    csum_.grad_C(i, 1) -= Vw * wall_pairs_.ry[q] * F;
    csum_.sum_F[i] += F;
  }
  for (int s : dirichlet_rows_) {  // A_phi is symmetric: a surface particle's row names its neighbours
    csum_.near[s] = 1;
    for (int k = outer[s]; k < outer[s + 1]; ++k)
      if (a[k] != 0) csum_.near[col[k]] = 1;
  }
}

// M0 = -sum_j V x_ij^2 F_ij and S_F = sum_j F_ij of a full support in the initial arrangement (the
// lattice: 1.0105 and its own value at h = 1.3 dx; rings alike): the median over the particles with
// no surface particle within their support, over their particle and wall-particle neighbours.
void IsphFluid::reference_sums() {
  const int N = size();
  const double reach = verlet_.reach();
  std::vector<double> m, f;
  for (int i = 0; i < N; ++i) {
    if (surface_[i]) continue;
    bool cut = false;
    double mi = 0, fi = 0;
    for (int q = pairs_.offset[i]; q < pairs_.offset[i + 1] && !cut; ++q) {
      const double r = pairs_.r[q];
      if (r >= reach) continue;
      const int j = pairs_.j[q];
      if (j < N && surface_[j]) cut = true;
      const double F = W_.F(r), V = j < N ? volume_ : lat_.volume;
      mi -= 0.5 * V * r * r * F;  // half the trace of -sum V x_ij (x) x_ij F
      fi += F;
    }
    if (cut) continue;
    m.push_back(mi);
    f.push_back(fi);
  }
  if (m.empty()) return;  // no particle with a full support: M0 = 1, S_F = 0 (no mirror rows)
  std::nth_element(m.begin(), m.begin() + m.size() / 2, m.end());
  std::nth_element(f.begin(), f.begin() + f.size() / 2, f.end());
  M0_ = m[m.size() / 2];
  S_F_ = f[f.size() / 2];
}

// A shift takes no particle closer to a wall than half a spacing (wall_contact's gap) nor closer than
// it already is: the wall-normal part of dr_ towards a wall is cut to what keeps that distance.
void IsphFluid::shift_off_walls() {
  const Domain& d = prm_.domain;
  const double gap[2] = {0.5 * lat_.dx, 0.5 * lat_.dy};
  for_each_wall_distance(d, x_, [&](int i, int a, int s, Side, double dist) {
    const double towards = s == 0 ? -dr_(i, a) : dr_(i, a);
    if (towards <= 0) return;
    const double allowed = std::max(0.0, dist - gap[a]);
    if (towards > allowed) dr_(i, a) = s == 0 ? -allowed : allowed;
  });
  if (!gate_in_) return;
  for (int i = 0; i < size(); ++i) {  // the gate's face
    const double dist = prm_.gate.x - x_(i, 0);
    if (!(dist > 0) || x_(i, 1) <= gate_bottom_ || dr_(i, 0) <= 0) continue;
    dr_(i, 0) = std::min(dr_(i, 0), std::max(0.0, dist - gap[0]));
  }
}

// The gate's particles at time t after the tank's (append_gate), or none once its lower edge is more
// than 2h above the highest particle (x*); the Verlet list then builds with them. Returns whether the
// wall particles changed (before gate.start they stay).
bool IsphFluid::place_gate(double t) {
  if (!move_gate(lat_, W_.support(), prm_.gate, gate_top_, t, x_star_.col(1).maxCoeff(), tank_walls_, gate_in_, walls_))
    return false;
  gate_bottom_ = gate_in_ ? prm_.domain.y0 + prm_.gate.lift(t) : -INFINITY;
  verlet_.set_fixed(walls_.x);
  p_w_.conservativeResize(walls_.size());
  if (walls_.size() > tank_walls_) p_w_.tail(walls_.size() - tank_walls_).setZero();
  return true;
}

// The operators, both systems and A Eq. (26)'s sums at the list's positions (one pass), then the free
// surface and the Poisson matrix's Dirichlet rows.
void IsphFluid::assemble(bool new_pattern) {
  auto t0 = Profile::Clock::now();
  new_pattern = new_pattern || pattern_stale_;
  morris_factors();
  find_wall_pairs();
  PairRules rules;
  rules.divergence_difference = true;  // A Eq. (14)
  rules.wall_beta = beta_.data();
  rules.V_fixed = lat_.volume;
  rules.position_divergence = div_r_.data();
  assembly_.assemble(pairs_, im_, size(), W_, volume_, verlet_.reach(), new_pattern, op_, {a_cn(), &A_cn_, &A_phi_},
                     nullptr, rules);
  if (new_pattern) operators_changed();
  else operator_values_changed();
  pattern_stale_ = false;
  prof_.add(k_.assembly, seconds_since(t0));
  ScopedTimer tm(prof_, k_surface_);
  if (detect_) {
    add_mirror_divergence();
    detector_.flag_divergence(div_r_, surface_);  // A Eq. (26)
  }
  dirichlet_rows_.clear();
  for (int i = 0; i < size(); ++i)
    if (surface_[i]) dirichlet_rows_.push_back(i);
  if (consistent_ || k_shift_ >= 0) surface_sums();
  if (consistent_ && detect_) surface_mirror();
  eliminate_dirichlet(A_phi_);  // A Section 3.5: p = 0 embedded in the matrix, symmetrically
}

// A Eq. (26)'s sum over the wall: the mirror images of the particle and its neighbours across each
// wall within 2h (and across both at a corner), as LPSPH's images (boundary.hpp) would give it. The
// wall particles themselves would complete the support of a surface particle next to a wall: those
// above the water line are there too (without them the top corner particles go unmarked as surface:
// docs/method/choices.md, "ISPH: the wall particles above the water").
void IsphFluid::add_mirror_divergence() {
  const Domain& d = prm_.domain;
  const int N = size();
  const double reach = verlet_.reach();
  for (int i = 0; i < N; ++i) {
    const double xi = x_star_(i, 0), yi = x_star_(i, 1);
    // the wall line within reach along each axis (NaN: none)
    double lx = d.is_wall(Left) && xi - d.x0 < reach ? d.x0 : d.is_wall(Right) && d.x1 - xi < reach ? d.x1 : NAN;
    const double ly = d.is_wall(Bottom) && yi - d.y0 < reach ? d.y0 : d.is_wall(Top) && d.y1 - yi < reach ? d.y1 : NAN;
    if (std::isnan(lx) && gate_in_ && yi > gate_bottom_ && xi < prm_.gate.x && prm_.gate.x - xi < reach) lx = prm_.gate.x;
    if (std::isnan(lx) && std::isnan(ly)) continue;
    auto add = [&](double rx, double ry) {  // an image at x_i - (rx, ry)
      const double r = std::hypot(rx, ry);
      if (r < reach) div_r_[i] -= volume_ * r * r * W_.F(r);  // -V (x_i - x_j') . grad_i W
    };
    for (int k = pairs_.offset[i] - 1; k < pairs_.offset[i + 1]; ++k) {
      if (k >= pairs_.offset[i] && pairs_.j[k] >= N) continue;  // particles only (k = offset - 1: i itself)
      const double rx = k < pairs_.offset[i] ? 0.0 : pairs_.rx[k], ry = k < pairs_.offset[i] ? 0.0 : pairs_.ry[k];
      const double mx = 2.0 * (xi - lx) - rx, my = 2.0 * (yi - ly) - ry;  // x_i minus the mirrored x_j
      if (!std::isnan(lx)) add(mx, ry);
      if (!std::isnan(ly)) add(rx, my);
      if (!std::isnan(lx) && !std::isnan(ly)) add(mx, my);  // the corner image
    }
  }
}

void IsphFluid::make_solvers() {
  // The FFT preconditioners of pcg_fft exist only for the lattice itself (a full tank at rest).
  const bool lattice = size() == lat_.size() && x_star_ == lat_.x;
  if (!explicit_viscous_)
    cn_ = crank_nicolson_solver(A_cn_, op_.lap_u.A, a_cn(), prm_.cn_solver, nullptr, Refactor::EveryStep,
                                lattice ? LatticeReference{&lat_, &A_cn_} : LatticeReference{});
  // auto: CG warm-started from the last p, preconditioned by a lagged factor (cheaper than a
  // factorisation every step: docs/method/choices.md, "ISPH: the Poisson solver"). A full tank's operator is singular (the constants): the gauge removes them
  // from the right-hand side and from every preconditioned residual, and the factor is of the matrix
  // pinned at one particle (NullSpaceHooks, linear_solver.hpp), so CG runs on the range of the
  // operator; at isph.poisson_rtol it converges there as with a free surface (docs/free_surfaces.md).
  const SolverKind kind = prm_.poisson_solver;
  // isph.poisson_rtol (default 1e-8, not the 1e-14 of LPSPH: ISPH's pressure is as accurate as its
  // O(h^2) Laplacian; docs/method/choices.md, "ISPH: the Poisson solver").
  LaggedPcgOptions cg;
  cg.rtol = prm_.isph.poisson_rtol;
  cg.refresh_iterations = prm_.isph.poisson_refresh;
  SystemSolver p = singular_solver("Poisson", Field::Scalar, A_phi_, gauge_, kind, nullptr, Refactor::EveryStep,
                                   lattice ? LatticeReference{&lat_, &A_phi_} : LatticeReference{}, cg);
  poisson_ = std::move(p.solver);
  poisson_unpinned_ = p.unpinned;
}

void IsphFluid::refactorise() {
  auto t0 = Profile::Clock::now();
  if (cn_) cn_->refactorize_in_place(A_cn_);
  prof_.add(k_.factor_cn, seconds_since(t0));
  t0 = Profile::Clock::now();
  if (poisson_unpinned_) poisson_->refactorize_in_place(A_phi_);
  else if (gauge_.dimension() > 0) poisson_->refactorize(gauge_.pinned(A_phi_, false));
  else poisson_->refactorize(A_phi_);
  prof_.add(k_.factor_poisson, seconds_since(t0));
}

void IsphFluid::begin_step() {
  // The step's geometry at x* = x^n + dt u^n (the header); a particle out of the tank throws here,
  // before anything has changed.
  x_star_ = x_ + prm_.dt * u_;
  keep_in_tank(prm_.domain, x_star_, t_ + prm_.dt, "ISPH", "the walls no longer hold the fluid (time.dt too large?)");
  geometry(place_gate(t_ + prm_.dt));  // a gate that moved: a build with its new particles
  refactorise();
}

void IsphFluid::viscous_rhs(const Mat2& F) {
  if (!explicit_viscous_) return ProjectionFluid::viscous_rhs(F);
  ScopedTimer tm(prof_, k_rhs_);
  // A Eq. (22) with Morris's Laplacian, Eq. (18): u* = u^n + dt (g + nu (lap u^n + B c^n)) + dt F^n / rho
  apply2(op_.lap_u.A, u_, u_star_, vel_st_);  // lap u^n, both components in one pass
  const double nu_dt = 2.0 * a_cn(), k = prm_.dt / prm_.rho;
  for (int c = 0; c < 2; ++c)
    for (int i = 0; i < size(); ++i) u_star_(i, c) = (u_star_(i, c) + lap_wall_(i, c)) * nu_dt + u_(i, c) + k * F(i, c);
  add_acceleration(u_star_);
}

void IsphFluid::end_step() {
  {
    ScopedTimer tm(prof_, k_.move);
    x_ += prm_.dt * u_;  // A Eq. (25): x^{n+1} = x^n + dt u^{n+1}
  }
  if (k_shift_ >= 0) {  // shifting.hpp: the shifts from the step's pairs at x*, u carried to the new place
    ScopedTimer tm(prof_, k_shift_);
    const double reach = verlet_.reach();
    shifter_.shifts(pairs_, size(), W_, reach, csum_, u_, prm_.dt, detect_ ? &surface_ : nullptr, dr_);
    shift_off_walls();  // before u is carried: by the shift the particle makes, not the one the wall refuses
    shifter_.carry_velocity(op_.grad_ux.A, op_.grad_uy.A, csum_, dr_, u_);
    x_ += dr_;
  }
  keep_in_tank(prm_.domain, x_, t_, "ISPH", "the walls no longer hold the fluid (time.dt too large?)");
}

void IsphFluid::velocity_offsets(const Mat2*, Mat2& c) const {
  c = walls_.u;  // each wall particle's prescribed velocity (the pair rules weigh it: particle_operators.hpp)
}

void IsphFluid::set_positions(const Mat2& x) {
  if (x.rows() != x_.rows()) throw std::invalid_argument("ISPH: positions have the wrong size");
  x_ = x;
  keep_in_tank(prm_.domain, x_, t_, "ISPH", "");
  x_star_ = x_;
  geometry(true);
  refactorise();
  ++revision_;
}

double IsphFluid::viscous_bound() const {
  return 2.0 * a_cn() * op_.lap_u.A.diagonal().cwiseAbs().maxCoeff();
}

WallForces IsphFluid::wall_forces() const { return wall_forces_from_particles(lat_, walls_, p_w_); }

std::vector<std::string> IsphFluid::describe() const {
  const int N = size();
  long within = 0;
  for (int k = 0; k < pairs_.size(); ++k) within += pairs_.r[k] < verlet_.reach();
  const long surface = std::count(surface_.begin(), surface_.end(), 1);
  std::ostringstream m;
  m << "ISPH (Afanasiev et al. 2011, Eqs. 22-25): " << N << " moving particles";
  if (N != lat_.size()) m << " (the fluid region in a " << lat_.nx << " x " << lat_.ny << " lattice)";
  m << ", " << walls_.size() << " Morris wall particles, h = " << W_.h << " (" << prm_.h_over_dx
    << " (dx+dy)/2), " << static_cast<double>(within) / N << " neighbours per particle now; viscous predictor "
    << (explicit_viscous_ ? "explicit (A Eq. 22)" : "Crank-Nicolson (Eq. 28)") << ", nu dt max|lap_ii| = "
    << viscous_bound() << "; gravity (" << prm_.gravity.x() << ", " << prm_.gravity.y() << ")";
  const Shifting sk = shifter_.params().kind;
  m << "; particle shifting "
    << (sk == Shifting::None      ? "none (A Eq. 25 alone)"
        : sk == Shifting::Fickian ? "Fickian (Lind et al. 2012, D = " + std::to_string(shifter_.params().A) + " h |u| dt)"
                                  : "Xu et al. (2009)");
  std::vector<std::string> lines{m.str()};
  std::ostringstream s;
  s << "ISPH: free surface ";
  if (detect_) s << "by A Eq. (26), beta = " << prm_.free_surface.beta << ": " << surface << " particles now (p = 0)";
  else s << "none (a full tank: the Poisson operator's constants fixed by the gauge)";
  lines.push_back(s.str());
  std::ostringstream v;
  v << "ISPH: pairs from a Verlet list with the wall particles as fixed points (fluid/common/neighbours.hpp), skin "
    << verlet_.skin() / W_.support() << " 2h; built " << verlet_.builds() << " times, moved " << verlet_.updates()
    << " times";
  lines.push_back(v.str());
  if (prm_.gate.on) {
    std::ostringstream g;
    g << "ISPH: a gate at x = " << prm_.gate.x << " lifted at " << prm_.gate.speed << " m/s from t = " << prm_.gate.start
      << " (walls.hpp, append_gate): " << (gate_in_ ? "in the tank, lower edge at y = " : "gone (2h above the fluid)");
    if (gate_in_) g << gate_bottom_;
    lines.push_back(g.str());
  }
  for (const auto& si : solver_info()) lines.push_back(si.describe());
  if (poisson_->mean_iterations() > 0) {
    std::ostringstream it;
    it << "ISPH: Poisson: " << poisson_->mean_iterations() << " CG iterations per solve, preconditioner factorised "
       << poisson_->preconditioner_factorisations() << " times";
    lines.push_back(it.str());
  }
  return lines;
}

std::vector<std::pair<std::string, double>> IsphFluid::figures() const {
  std::vector<std::pair<std::string, double>> f{
      {"surface_particles", static_cast<double>(std::count(surface_.begin(), surface_.end(), 1))},
      {"wall_particles", static_cast<double>(walls_.size())},
      {"verlet_builds", static_cast<double>(verlet_.builds())}};
  if (poisson_->mean_iterations() > 0) {
    f.emplace_back("poisson_cg_iterations", poisson_->mean_iterations());
    f.emplace_back("poisson_preconditioner_factorisations", static_cast<double>(poisson_->preconditioner_factorisations()));
  }
  if (cn_ && cn_->mean_iterations() > 0) f.emplace_back("crank_nicolson_cg_iterations", cn_->mean_iterations());
  return f;
}

// ISPH adds to the core's state x^n, the positions x* of the last step's geometry and the Verlet
// list's state (see the header).
void IsphFluid::extra_state(NamedArrays& st) const {
  const VerletList::State v = verlet_.state();
  Eigen::MatrixXd c(1, 4);
  c << v.skin, static_cast<double>(v.since_build), static_cast<double>(v.builds), static_cast<double>(v.updates);
  st.emplace_back("x", x_);
  st.emplace_back("x_star", x_star_);
  st.emplace_back("verlet_x_build", v.x_build);
  st.emplace_back("verlet", c);
}

void IsphFluid::restore_extra(const NamedArrays& st) {
  const int N = size();
  x_ = state_entry(st, "x", N, 2);
  x_star_ = state_entry(st, "x_star", N, 2);
  const Eigen::MatrixXd& c = state_entry(st, "verlet", 1, 4);
  VerletList::State v{state_entry(st, "verlet_x_build", N, 2), c(0, 0), static_cast<long>(c(0, 1)),
                      static_cast<long>(c(0, 2)), static_cast<long>(c(0, 3))};
  if (prm_.gate.on) {  // the gate at the checkpoint's time, before the list's build
    gate_in_ = true;
    place_gate(t_);
  }
  verlet_.restore(v, x_star_, im_, pairs_);
  pattern_stale_ = true;
  assemble(true);  // the last step's geometry again: surface(), p() and the loads as before the checkpoint
  refactorise();
  wall_pressure();
}

}  // namespace sphib
