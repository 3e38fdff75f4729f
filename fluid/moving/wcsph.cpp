#include "fluid/moving/wcsph.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fluid/common/boundary.hpp"

namespace sphib {

// wcsph_afanasiev.cpp: the parameters of A's classic SPH, and the particle count of a scene.
void check_afanasiev_params(const FluidParams& p);
int particle_count(const FluidParams& p, const Lattice& L);

namespace {
using Clock = std::chrono::steady_clock;

void check_params(const FluidParams& p) {
  check_common_params(p);
  positive_param(p.wcsph.gamma, "wcsph.gamma");
  positive_param(p.wcsph.u_scale, "wcsph.u_scale");
  const WcsphParams& w = p.wcsph;
  if (!(w.c >= 0) || !std::isfinite(w.c))
    throw std::invalid_argument("wcsph.c must be >= 0 and finite (got " + std::to_string(w.c) + ")");
  if (!(w.xsph >= 0 && w.xsph <= 1))
    throw std::invalid_argument("wcsph.xsph must be in [0, 1] (got " + std::to_string(w.xsph) + ")");
  check_afanasiev_params(p);
}

// S = sum_j W(x_0 - x_j) over the infinite lattice of spacings dx, dy (x_0 included).
double kernel_sum_on_lattice(const CubicSplineKernel& W, double dx, double dy) {
  const int Rx = static_cast<int>(std::ceil(W.support() / dx)) + 1;
  const int Ry = static_cast<int>(std::ceil(W.support() / dy)) + 1;
  double S = 0;
  for (int b = -Ry; b <= Ry; ++b)
    for (int a = -Rx; a <= Rx; ++a) S += W.W(std::hypot(a * dx, b * dy));
  return S;
}
}  // namespace

double wcsph_sound_speed(const FluidParams& p) {
  if (p.wcsph.c > 0) return p.wcsph.c;
  // A Eq. (27): B = rho0 c^2 / gamma = 200 rho0 |g| H / gamma, H the fluid's initial height
  const double H = fluid_height(p.free_surface.fill, p.domain, p.gravity);
  if (H > 0) return std::sqrt(200.0 * p.gravity.norm() * H);
  // C Eq. (5): c^2 ~ U0^2 / delta; c = 10 U0 gives delta = |rho/rho0 - 1| ~ (U0/c)^2 ~ 1%.
  return 10.0 * p.wcsph.u_scale;
}

double coelho_dt_limit(double h, double c, double nu) {
  return std::min(0.25 * h / c, 0.125 * h * h / nu);  // C Eq. (19), acoustic and viscous terms
}

static const FluidParams& checked(const FluidParams& p) {
  check_params(p);
  return p;
}

WcsphFluid::WcsphFluid(const FluidParams& params, const WcsphOptions& options, Profiler* profiler)
    : FluidSolver(checked(params), true, profiler), opt_(options), walls_(make_virtual_walls(lat_, W_.support())),
      search_(prm_.domain, W_, particle_count(params, lat_), walls_.x), prof_(FluidSolver::profiler()) {
  eos_ = prm_.wcsph.eos;
  lj_ = prm_.wcsph.walls == WcsphWalls::LennardJones;
  c_ = wcsph_sound_speed(prm_);
  dt_limit_ = coelho_dt_limit(W_.h, c_, nu());
  if (prm_.dt > dt_limit_) {
    std::ostringstream m;
    m << "time.dt = " << prm_.dt << " exceeds the WCSPH stability limit " << dt_limit_
      << " of Coelho et al. Eq. (19): min(0.25 h/c = " << 0.25 * W_.h / c_ << ", 0.125 h^2/nu = "
      << 0.125 * W_.h * W_.h / nu() << ") with h = " << W_.h << ", c = " << c_ << ", nu = " << nu();
    throw std::invalid_argument(m.str());
  }
  rho0_ = prm_.rho;
  S_ = kernel_sum_on_lattice(W_, lat_.dx, lat_.dy);
  m_ = rho0_ / S_;  // the initial lattice has summation density rho0 exactly
  p_wall_ = eos_pressure(eos_, rho0_, rho0_, c_, prm_.wcsph.gamma);
  lj_D_ = opt_.lj_D > 0 ? opt_.lj_D : prm_.wcsph.u_scale * prm_.wcsph.u_scale;
  lj_r0_ = std::min(lat_.dx, lat_.dy);
  dvar_limit_ = has_free_surface(prm_.domain, prm_.free_surface) ? opt_.max_density_variation_free_surface
                                                                  : opt_.max_density_variation;
  const int M = walls_.size();
  p_w_.setConstant(M, p_wall_);
  pr_w_.setConstant(M, p_wall_ / (rho0_ * rho0_));
  rho_w_.setConstant(M, rho0_);

  const auto t0 = Clock::now();
  pc_ = prm_.wcsph.integrator == Integrator::PredictorCorrector;
  if (pc_) {
    init_afanasiev();  // A's particles, masses, hydrostatic density; the evaluation at t = 0
    prof_.add_setup("neighbours", seconds_since(t0));
  } else {
    N_ = lat_.size();
    x_ = lat_.x;
    u_ = u_hat_ = a_ = Mat2::Zero(N_, 2);
    rho_ = p_ = V_ = pr_ = Vec::Zero(N_);
    find_neighbours();
    prof_.add_setup("neighbours", seconds_since(t0));
    summation_density();
    xsph_velocity(u_);
  }
  check_density();

  k_drift_ = prof_.phase("drift (V Eq. 22)");
  k_neigh_ = prof_.phase("neighbours");
  k_rho_ = prof_.phase("summation density + EOS (V Eq. 11, 20)");
  k_force_ = prof_.phase("accelerations (C Eq. 17)");
  k_xsph_ = prof_.phase("XSPH (V Eq. 21)");
  if (surface_on_) k_surface_ = prof_.phase("free surface (Dilts / A Eq. 26)");
  mass_ = m_;
  prof_.set_reporter([this](FluidReport& r) {
    r.lines = describe();
    r.figures = figures();
  });
}

void WcsphFluid::find_neighbours() {
  place_gate(t_);  // a gate (none: nothing)
  x_eval_ = x_;
  search_.find(x_, pairs_);
  nbrs_last_ = search_.neighbours();
  nbrs_total_ += nbrs_last_;
}

void WcsphFluid::summation_density() {
  const int N = N_;
  const double gamma = prm_.wcsph.gamma;
  rho_.setConstant(W_.W(0.0));  // the particle itself
  const ParticlePairs& P = pairs_;
  for (int k = 0; k < P.size(); ++k) {
    rho_[P.i[k]] += P.W[k];
    if (P.j[k] < N) rho_[P.j[k]] += P.W[k];
  }
  for (int i = 0; i < N; ++i) {
    rho_[i] *= m_;                                            // V Eq. (11): rho_i = sum_j m_j W_ij
    p_[i] = eos_pressure(eos_, rho_[i], rho0_, c_, gamma);    // V Eq. (20) / C Eq. (3)
    pr_[i] = p_[i] / (rho_[i] * rho_[i]);                     // p_i / rho_i^2 of C Eq. (17)
    V_[i] = m_ / rho_[i];
  }
}

void WcsphFluid::accelerations(const Mat2& F) {
  const int N = N_;
  const ParticlePairs& P = pairs_;
  const double mu = prm_.mu;
  // Monaghan (1992) artificial viscosity, alpha c h; A's continuity equation
  const double av = prm_.wcsph.alpha * c_ * W_.h, eta2 = 0.01 * W_.h * W_.h;
  const bool continuity = pc_;
  const double dhc = prm_.wcsph.delta * W_.h * c_;  // delta-SPH: delta h c
  if (continuity && dhc > 0) density_gradient();
  a_ = F.array().colwise() / rho_.array();  // external force per unit volume / rho_i
  if (prm_.gravity.norm() != 0) a_.rowwise() += prm_.gravity.transpose();  // A Eq. (22)'s g
  if (continuity) drho_.setZero(N);
  for (int k = 0; k < P.size(); ++k) {
    const int i = P.i[k], j = P.j[k];
    const double rx = P.rx[k], ry = P.ry[k], Fk = P.F[k];  // grad_i W_ij = (x_i - x_j) F_ij
    double pr_j, rho_j, du, dv;
    if (j < N) {
      pr_j = pr_[j];
      rho_j = rho_[j];
      du = u_(i, 0) - u_(j, 0);
      dv = u_(i, 1) - u_(j, 1);
    } else {
      const int w = j - N;
      pr_j = pr_w_[w];
      rho_j = rho_w_[w];
      du = u_(i, 0) - walls_.u(w, 0);
      dv = u_(i, 1) - walls_.u(w, 1);
    }
    double Pi = 0;  // Monaghan (1992): Pi_ij for approaching particles (u_ij . x_ij < 0)
    if (continuity || av > 0) {
      const double ux = du * rx + dv * ry;                         // u_ij . x_ij, the wall's own velocity
      if (continuity) {
        drho_[i] += m_ * ux * Fk;                                  // A Eqs. (2), (14): m u_ij . grad_i W_ij
        if (j < N) drho_[j] += m_ * ux * Fk;                       // the same from j
        if (j < N && dhc > 0) {
          // delta-SPH (see the header): psi_ij . grad_i W_ij = -2 (rho_j - rho_i) F_ij
          //   - (<grad rho>_i^L + <grad rho>_j^L) . x_ij F_ij; seen from j (psi_ji = psi_ij,
          //   grad_j W_ji = -grad_i W_ij) its negative: the diffusion conserves mass
          const double d = (-2.0 * (rho_[j] - rho_[i]) - ((grad_rho_(i, 0) + grad_rho_(j, 0)) * rx +
                                                           (grad_rho_(i, 1) + grad_rho_(j, 1)) * ry)) * Fk * dhc;
          drho_[i] += V_[j] * d;
          drho_[j] -= V_[i] * d;
        }
      }
      if (av > 0 && ux < 0) Pi = -av * (ux / (P.r[k] * P.r[k] + eta2)) / (0.5 * (rho_[i] + rho_j));
    }
    if (j >= N) {
      const int w = j - N;
      if (opt_.morris_extrapolation && walls_.side[w] >= 0) {
        // Morris et al. (1997): u_B = u_w - (d_B/d_A)(u_A - u_w)  =>  u_AB = beta (u_A - u_w)
        const double beta = morris_wall_factor(lat_, walls_.side[w], walls_.dist[w], x_(i, 0), x_(i, 1), opt_.beta_max);
        du *= beta;
        dv *= beta;
      }
      if (lj_ && walls_.inner[w] && P.r[k] < lj_r0_) {
        // C Eq. (20): D [(r0/r)^12 - (r0/r)^4] x_ab / r^2, repulsive for r < r0
        const double q = lj_r0_ / P.r[k], q4 = q * q * q * q;
        const double f = lj_D_ * (q4 * q4 * q4 - q4) / (P.r[k] * P.r[k]);
        a_(i, 0) += f * rx;
        a_(i, 1) += f * ry;
      }
    }
    const double cp = Pi == 0 ? -m_ * (pr_[i] + pr_j) * Fk          // pressure, C Eq. (17) / V Eq. (12) / A Eq. (13)
                              : -m_ * (pr_[i] + pr_j + Pi) * Fk;    // + Monaghan (1992)
    const double cv = m_ * 2.0 * mu / (rho_[i] * rho_j) * Fk;   // Morris viscosity, C Eq. (17), A Eq. (18)
    const double fx = cp * rx + cv * du, fy = cp * ry + cv * dv;
    a_(i, 0) += fx;
    a_(i, 1) += fy;
    if (j < N) {  // the pair seen from j: x_ji = -x_ij, u_ji = -u_ij (equal masses)
      a_(j, 0) -= fx;
      a_(j, 1) -= fy;
    }
  }
}

// delta-SPH's <grad rho>_i^L = L_i sum_j V_j (rho_j - rho_i) grad_i W_ij over the fluid pairs (Antuono et
// al. 2012, Eq. 6), L_i = (sum_j V_j (x_j - x_i) (x) grad_i W_ij)^-1; where the neighbours span one
// direction only (a thin jet, a lone pair), the gradient along it; none: 0.
void WcsphFluid::density_gradient() {
  const int N = N_;
  const ParticlePairs& P = pairs_;
  Mat2& g = grad_rho_;
  g.setZero(N, 2);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(N, 3);  // m00, m01, m11
  for (int k = 0; k < P.size(); ++k) {
    const int i = P.i[k], j = P.j[k];
    if (j >= N) continue;
    const double rx = P.rx[k], ry = P.ry[k], F = P.F[k], dr = rho_[j] - rho_[i];
    // from i: V_j (x_j - x_i) (x) x_ij F = -V_j x_ij (x) x_ij F; V_j (rho_j - rho_i) x_ij F; from j alike
    const double xx = -rx * rx * F, xy = -rx * ry * F, yy = -ry * ry * F;
    M(i, 0) += V_[j] * xx; M(i, 1) += V_[j] * xy; M(i, 2) += V_[j] * yy;
    M(j, 0) += V_[i] * xx; M(j, 1) += V_[i] * xy; M(j, 2) += V_[i] * yy;
    g(i, 0) += V_[j] * dr * rx * F; g(i, 1) += V_[j] * dr * ry * F;
    g(j, 0) += V_[i] * dr * rx * F; g(j, 1) += V_[i] * dr * ry * F;  // (rho_i - rho_j)(x_j - x_i) F
  }
  for (int i = 0; i < N; ++i) {
    const double m00 = M(i, 0), m01 = M(i, 1), m11 = M(i, 2), gx = g(i, 0), gy = g(i, 1);
    const double tr = m00 + m11, det = m00 * m11 - m01 * m01, disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
    const double lam1 = 0.5 * tr + disc, lam2 = 0.5 * tr - disc;
    if (lam2 >= 0.1) {
      g(i, 0) = (m11 * gx - m01 * gy) / det;
      g(i, 1) = (m00 * gy - m01 * gx) / det;
    } else if (lam1 >= 0.1) {
      double ex = m01, ey = lam1 - m00;
      if (std::hypot(ex, ey) <= 1e-12 * lam1) { ex = m00 >= m11 ? 1 : 0; ey = 1 - ex; }
      const double n = std::hypot(ex, ey), c = (ex * gx + ey * gy) / (n * n * lam1);
      g(i, 0) = c * ex;
      g(i, 1) = c * ey;
    } else {
      g(i, 0) = g(i, 1) = 0;
    }
  }
}

void WcsphFluid::xsph_velocity(const Mat2& u) {
  const double eps = prm_.wcsph.xsph;
  if (eps == 0) { u_hat_ = u; return; }
  const int N = N_;
  const ParticlePairs& P = pairs_;
  const double V_wall = m_ / rho0_;
  Mat2& s = a_;  // workspace: the XSPH sums (a_ is spent once u^{n+1} is known)
  s.setZero();
  for (int k = 0; k < P.size(); ++k) {
    const int i = P.i[k], j = P.j[k];
    const double w = P.W[k];
    if (j < N) {
      const double dx = (u(i, 0) - u(j, 0)) * w, dy = (u(i, 1) - u(j, 1)) * w;  // u_ij W_ij
      s(i, 0) += V_[j] * dx;  // (m_j / rho_j) u_ij W_ij
      s(i, 1) += V_[j] * dy;
      s(j, 0) -= V_[i] * dx;  // (m_i / rho_i) u_ji W_ji
      s(j, 1) -= V_[i] * dy;
    } else {
      s(i, 0) += V_wall * (u(i, 0) - walls_.u(j - N, 0)) * w;  // wall particles: V = m / rho0
      s(i, 1) += V_wall * (u(i, 1) - walls_.u(j - N, 1)) * w;
    }
  }
  u_hat_ = u - eps * s;  // V Eq. (21)
}

void WcsphFluid::drift(double tau) {
  x_ += tau * u_hat_;
  keep_in_tank(prm_.domain, x_, t_ + tau, "WCSPH",
               "the walls no longer hold the fluid (c too low for this flow, or time.dt too large)");
}

void WcsphFluid::check_density() {
  const int N = N_;
  int worst = 0;
  double dv = 0;
  for (int i = 0; i < N; ++i) {
    const double e = std::fabs(rho_[i] / rho0_ - 1.0);
    if (e > dv || !std::isfinite(e)) { dv = e; worst = i; }
  }
  dvar_ = dv;
  if (dv > dvar_max_) { dvar_max_ = dv; t_dvar_max_ = t_; }
  if (!(dv <= dvar_limit_)) {
    std::ostringstream m;
    m << "WCSPH: density variation |rho/rho0 - 1| = " << dv << " at particle " << worst << " (" << x_(worst, 0)
      << ", " << x_(worst, 1) << ") exceeds " << dvar_limit_ << " at t = " << t_
      << ": a blow-up (speed of sound c = " << c_ << " too low for this flow, or time.dt too large)";
    throw std::runtime_error(m.str());
  }
}

void WcsphFluid::set_velocity(const Mat2& u0) {
  ++revision_;
  if (u0.rows() != u_.rows() || u0.cols() != 2) throw std::invalid_argument("fluid: initial velocity has the wrong size");
  u_ = u0;
  if (pc_) v_half_ = u0;  // A: v^{-1/2} = v^0, the first step kicks by dt/2
  xsph_velocity(u_);  // with the neighbours of the current positions
}

void WcsphFluid::step(const Mat2& F) {
  ++revision_;
  const double dt = prm_.dt;
  if (F.rows() != u_.rows()) throw std::invalid_argument("WCSPH: force field has the wrong size");
  // C Eq. (19), force term: dt <= 0.25 sqrt(h / |f|), f = F / rho0 (+ g) the external acceleration
  const double fmax = prm_.gravity.norm() == 0 ? F.rowwise().norm().maxCoeff() / rho0_
                                                : ((F / rho0_).rowwise() + prm_.gravity.transpose()).rowwise().norm().maxCoeff();
  if (fmax > 0 && dt > 0.25 * std::sqrt(W_.h / fmax)) {
    std::ostringstream m;
    m << "time.dt = " << dt << " exceeds the force limit 0.25 sqrt(h/|f|) = " << 0.25 * std::sqrt(W_.h / fmax)
      << " of Coelho et al. Eq. (19) (|f| = max |F|/rho = " << fmax << ")";
    throw std::invalid_argument(m.str());
  }
  if (pc_) return step_afanasiev(F);
  {
    ScopedTimer tm(prof_, k_drift_);
    drift(0.5 * dt);  // V Eq. (22): x^{n+1/2} = x^n + dt/2 v^n (XSPH velocity, V Eq. 21)
  }
  {
    ScopedTimer tm(prof_, k_neigh_);
    find_neighbours();  // at x^{n+1/2}
  }
  {
    ScopedTimer tm(prof_, k_rho_);
    summation_density();  // V Eq. (11) and the EOS, V Eq. (20) / C Eq. (3)
  }
  {
    ScopedTimer tm(prof_, k_force_);
    accelerations(F);  // a^{n+1/2}: C Eq. (17) + F / rho (+ C Eq. 20)
    u_ += dt * a_;     // V Eq. (22): v^{n+1} = v^n + dt a^{n+1/2}
  }
  {
    ScopedTimer tm(prof_, k_xsph_);
    xsph_velocity(u_);  // V Eq. (21) of v^{n+1}, neighbours of x^{n+1/2}
  }
  {
    ScopedTimer tm(prof_, k_drift_);
    drift(0.5 * dt);  // V Eq. (22): x^{n+1} = x^{n+1/2} + dt/2 v^{n+1}
  }
  t_ += dt;
  ++n_;
  check_density();
}

double WcsphFluid::max_abs_divergence() const {
  // (div u)_i = sum_j (m/rho_j) (u_i + u_j) . (x_i - x_j) F_ij  (Eq. 30 form), walls carry u_w
  const int N = N_;
  const double V_wall = m_ / rho0_;
  const ParticlePairs& P = pairs_;
  Vec d = Vec::Zero(N);
  for (int k = 0; k < P.size(); ++k) {
    const int i = P.i[k], j = P.j[k];
    const double uj = j < N ? u_(j, 0) : walls_.u(j - N, 0), vj = j < N ? u_(j, 1) : walls_.u(j - N, 1);
    const double t = ((u_(i, 0) + uj) * P.rx[k] + (u_(i, 1) + vj) * P.ry[k]) * P.F[k];
    d[i] += (j < N ? V_[j] : V_wall) * t;
    if (j < N) d[j] -= V_[i] * t;  // x_ji = -x_ij
  }
  return d.cwiseAbs().maxCoeff();
}

std::vector<std::string> WcsphFluid::describe() const {
  const WcsphParams& w = prm_.wcsph;
  std::vector<std::string> lines;
  {
    std::ostringstream m;
    m << "WCSPH (Morris et al. 1997; Vukcevic et al. 2012; Coelho et al."
      << (pc_ ? "; Afanasiev et al. 2011" : "") << "): ";
    if (size() == lat_.size()) m << lat_.nx << " x " << lat_.ny << " = ";
    m << size() << " moving particles";
    if (size() != lat_.size()) m << " (the fluid region in a " << lat_.nx << " x " << lat_.ny << " lattice)";
    m << ", " << walls_.size() << " fixed virtual wall particles"
      << (opt_.morris_extrapolation ? " (Morris extrapolated velocity)" : " (wall velocity)")
      << (lj_ ? " + Lennard-Jones repulsion (C Eq. 20)" : "") << ", h = " << W_.h << " (" << prm_.h_over_dx
      << " (dx+dy)/2), " << static_cast<double>(nbrs_total_) / ((n_ + 1.0) * size())
      << " neighbours per particle (mean over the run)";
    lines.push_back(m.str());
  }
  if (prm_.gate.on) {
    std::ostringstream m;
    m << "a gate at x = " << prm_.gate.x << " lifted at " << prm_.gate.speed << " m/s from t = " << prm_.gate.start
      << " (walls.hpp, append_gate): " << (gate_in_ ? "in the tank" : "gone (2h above the fluid)");
    lines.push_back(m.str());
  }
  {
    std::ostringstream m;
    m << "EOS ";
    if (eos_ == Eos::Morris) m << "p = c^2 rho (Morris, V Eq. 20; background pressure c^2 rho0 = " << p_wall_ << ")";
    else m << "Tait (C Eq. 3, A Eq. 27), gamma = " << w.gamma;
    m << ", c = " << c_;
    if (w.c > 0) m << " (wcsph.c)";
    else if (pc_ && prm_.gravity.norm() > 0) m << " (wcsph.c = 0: B = 200 rho0 g H / gamma, A Eq. 27)";
    else m << " (wcsph.c = 0: 10 u_scale, C Eq. 5 scaling for ~1% density variation)";
    m << ", rho0 = " << rho0_;
    if (pc_) m << ", m = rho0 V = " << m_ << " (continuity density, A Eqs. 2, 14)";
    else m << ", m = rho0 / sum_j W_ij = " << m_ << " (lattice kernel sum S dx dy = " << lattice_kernel_sum() << ")";
    lines.push_back(m.str());
  }
  {
    std::ostringstream m;
    if (pc_) m << "predictor-corrector A Eqs. (19)-(21), artificial viscosity alpha = " << w.alpha
               << " (Monaghan 1992), density smoothing A Eq. (29) every " << w.smooth_every << " steps, wall pressure "
               << to_string(w.wall_pressure) << ", XSPH eps = " << w.xsph;
    else m << "leapfrog V Eq. (22) (drift-kick-drift), XSPH eps = " << w.xsph;
    m << ", dt = " << prm_.dt << " (C Eq. 19 limit " << dt_limit_ << ": 0.25 h/c = " << 0.25 * W_.h / c_
      << ", 0.125 h^2/nu = " << 0.125 * W_.h * W_.h / nu() << ")";
    lines.push_back(m.str());
  }
  if (surface_on_) {
    std::ostringstream m;
    m << "free surface: " << (detector_.method() == SurfaceDetection::Dilts ? "Dilts (2000), circles of radius " : "A Eq. (26), beta = ")
      << (detector_.method() == SurfaceDetection::Dilts ? prm_.free_surface.dilts_radius : prm_.free_surface.beta)
      << (detector_.method() == SurfaceDetection::Dilts ? " h" : "") << "; gravity (" << prm_.gravity.x() << ", "
      << prm_.gravity.y() << "); open sides:";
    for (int s = 0; s < 4; ++s)
      if (prm_.domain.is_open(static_cast<Side>(s))) m << " " << side_name(static_cast<Side>(s));
    lines.push_back(m.str());
  }
  {
    std::ostringstream m;
    m << "density variation max |rho/rho0 - 1| = " << dvar_max_ << " (at t = " << t_dvar_max_ << "), now "
      << dvar_ << " (papers aim below 0.03; blow-up above " << dvar_limit_ << ")";
    lines.push_back(m.str());
  }
  return lines;
}

std::vector<std::pair<std::string, double>> WcsphFluid::figures() const {
  std::vector<std::pair<std::string, double>> f{{"max_density_variation", dvar_max_},
          {"density_variation", dvar_},
          {"sound_speed", c_},
          {"dt_limit_coelho", dt_limit_},
          {"wall_particles", static_cast<double>(walls_.size())},
          {"neighbours_per_particle", static_cast<double>(nbrs_last_) / size()},
          {"lattice_kernel_sum", lattice_kernel_sum()}};
  if (surface_on_) f.emplace_back("surface_particles", static_cast<double>(std::count(surface_.begin(), surface_.end(), 1)));
  return f;
}

NamedArrays WcsphFluid::state() const {
  if (pc_) return state_afanasiev();
  return {{"x", x_}, {"x_eval", x_eval_}, {"u", u_}, {"u_hat", u_hat_}, {"clock", clock()}};
}

void WcsphFluid::restore(const NamedArrays& state) {
  ++revision_;
  if (pc_) return restore_afanasiev(state);
  const int N = size();
  x_ = state_entry(state, "x_eval", N, 2);
  find_neighbours();  // the neighbours and densities of the last evaluation, exactly
  summation_density();
  x_ = state_entry(state, "x", N, 2);
  u_ = state_entry(state, "u", N, 2);
  u_hat_ = state_entry(state, "u_hat", N, 2);
  restore_clock(state);
}

Eigen::MatrixXd WcsphFluid::clock() const {
  Eigen::MatrixXd c(1, pc_ ? 6 : 5);
  c.leftCols(5) << t_, static_cast<double>(n_), dvar_, dvar_max_, t_dvar_max_;
  if (pc_) c(0, 5) = started_ ? 1.0 : 0.0;
  return c;
}

void WcsphFluid::restore_clock(const NamedArrays& state) {
  const Eigen::MatrixXd& c = state_entry(state, "clock", 1, pc_ ? 6 : 5);
  t_ = c(0, 0);
  n_ = static_cast<long>(c(0, 1));
  dvar_ = c(0, 2);
  dvar_max_ = c(0, 3);
  t_dvar_max_ = c(0, 4);
  if (pc_) started_ = c(0, 5) != 0;
}

WallForces WcsphFluid::wall_forces() const {
  if (wall_pressure_ == WallPressure::Rest) return FluidSolver::wall_forces();  // by interpolation
  return wall_forces_from_particles(lat_, walls_, p_w_);                        // A Eq. (32)
}

}  // namespace sphib
