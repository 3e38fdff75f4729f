#include "fluid/wcsph.hpp"

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
  positive_param(p.wcsph.gamma, "wcsph.gamma");
  positive_param(p.wcsph.u_scale, "wcsph.u_scale");
  const WcsphParams& w = p.wcsph;
  if (!(w.c >= 0) || !std::isfinite(w.c))
    throw std::invalid_argument("wcsph.c must be >= 0 and finite (got " + std::to_string(w.c) + ")");
  if (!(w.xsph >= 0 && w.xsph <= 1))
    throw std::invalid_argument("wcsph.xsph must be in [0, 1] (got " + std::to_string(w.xsph) + ")");
  if (w.eos != "morris" && w.eos != "tait")
    throw std::invalid_argument("wcsph.eos: \"" + w.eos + "\" is not allowed (allowed: morris | tait)");
  if (w.walls != "virtual" && w.walls != "lennard_jones")
    throw std::invalid_argument("wcsph.walls: \"" + w.walls + "\" is not allowed (allowed: virtual | lennard_jones)");
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
  // C Eq. (5): c^2 ~ U0^2 / delta; c = 10 U0 gives delta = |rho/rho0 - 1| ~ (U0/c)^2 ~ 1%.
  return p.wcsph.c > 0 ? p.wcsph.c : 10.0 * p.wcsph.u_scale;
}

double coelho_dt_limit(double h, double c, double nu) {
  return std::min(0.25 * h / c, 0.125 * h * h / nu);  // C Eq. (19), acoustic and viscous terms
}

static const FluidParams& checked(const FluidParams& p) {
  check_params(p);
  return p;
}

WcsphFluid::WcsphFluid(const FluidParams& params, const WcsphOptions& options)
    : prm_(checked(params)), opt_(options), lat_(make_lattice(params.domain, params.nx, params.ny)),
      W_(params.h_over_dx * 0.5 * (lat_.dx + lat_.dy)), walls_(make_virtual_walls(lat_, W_.support())),
      search_(prm_.domain, W_, lat_.size(), walls_.x) {
  eos_ = prm_.wcsph.eos == "tait" ? Eos::Tait : Eos::Morris;
  lj_ = prm_.wcsph.walls == "lennard_jones";
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

  const auto t0 = Clock::now();
  const int N = lat_.size();
  x_ = lat_.x;
  u_ = u_hat_ = a_ = Mat2::Zero(N, 2);
  rho_ = p_ = V_ = pr_ = Vec::Zero(N);
  find_neighbours();
  setup_.emplace_back("neighbours", seconds_since(t0));
  summation_density();
  xsph_velocity();
  check_density();

  k_drift_ = prof_.phase("drift (V Eq. 22)");
  k_neigh_ = prof_.phase("neighbours");
  k_rho_ = prof_.phase("summation density + EOS (V Eq. 11, 20)");
  k_force_ = prof_.phase("accelerations (C Eq. 17)");
  k_xsph_ = prof_.phase("XSPH (V Eq. 21)");
}

void WcsphFluid::find_neighbours() {
  x_eval_ = x_;
  search_.find(x_, pairs_);
  nbrs_last_ = search_.neighbours();
  nbrs_total_ += nbrs_last_;
}

void WcsphFluid::summation_density() {
  const int N = lat_.size();
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
  const int N = lat_.size();
  const ParticlePairs& P = pairs_;
  const double mu = prm_.mu, pr_wall = p_wall_ / (rho0_ * rho0_);
  a_ = F.array().colwise() / rho_.array();  // external force per unit volume / rho_i
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
      pr_j = pr_wall;
      rho_j = rho0_;
      du = u_(i, 0) - walls_.u(w, 0);
      dv = u_(i, 1) - walls_.u(w, 1);
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
    const double cp = -m_ * (pr_[i] + pr_j) * Fk;               // pressure, C Eq. (17) / V Eq. (12)
    const double cv = m_ * 2.0 * mu / (rho_[i] * rho_j) * Fk;   // Morris viscosity, C Eq. (17)
    const double fx = cp * rx + cv * du, fy = cp * ry + cv * dv;
    a_(i, 0) += fx;
    a_(i, 1) += fy;
    if (j < N) {  // the pair seen from j: x_ji = -x_ij, u_ji = -u_ij (equal masses)
      a_(j, 0) -= fx;
      a_(j, 1) -= fy;
    }
  }
}

void WcsphFluid::xsph_velocity() {
  const double eps = prm_.wcsph.xsph;
  if (eps == 0) { u_hat_ = u_; return; }
  const int N = lat_.size();
  const ParticlePairs& P = pairs_;
  const double V_wall = m_ / rho0_;
  Mat2& s = a_;  // workspace: the XSPH sums (a_ is spent once u^{n+1} is known)
  s.setZero();
  for (int k = 0; k < P.size(); ++k) {
    const int i = P.i[k], j = P.j[k];
    const double w = P.W[k];
    if (j < N) {
      const double dx = (u_(i, 0) - u_(j, 0)) * w, dy = (u_(i, 1) - u_(j, 1)) * w;  // u_ij W_ij
      s(i, 0) += V_[j] * dx;  // (m_j / rho_j) u_ij W_ij
      s(i, 1) += V_[j] * dy;
      s(j, 0) -= V_[i] * dx;  // (m_i / rho_i) u_ji W_ji
      s(j, 1) -= V_[i] * dy;
    } else {
      s(i, 0) += V_wall * (u_(i, 0) - walls_.u(j - N, 0)) * w;
      s(i, 1) += V_wall * (u_(i, 1) - walls_.u(j - N, 1)) * w;
    }
  }
  u_hat_ = u_ - eps * s;  // V Eq. (21)
}

void WcsphFluid::drift(double tau) {
  const Domain& d = prm_.domain;
  x_ += tau * u_hat_;
  for (int i = 0; i < x_.rows(); ++i) {
    for (int a = 0; a < 2; ++a) {
      const bool periodic = a == 0 ? d.periodic_x : d.periodic_y;
      const double lo = a == 0 ? d.x0 : d.y0, hi = a == 0 ? d.x1 : d.y1;
      double& c = x_(i, a);
      if (periodic) {
        c -= (hi - lo) * std::floor((c - lo) / (hi - lo));  // periodic wrap into [lo, hi)
        if (c >= hi) c = lo;  // -tiny + period rounds to hi
      } else if (!(c > lo && c < hi)) {
        std::ostringstream m;
        m << "WCSPH: particle " << i << " crossed the wall " << (a == 0 ? "x = " : "y = ") << (c <= lo ? lo : hi)
          << " (now at " << x_(i, 0) << ", " << x_(i, 1) << ") at t = " << t_ + tau
          << ": the walls no longer hold the fluid (c too low for this flow, or time.dt too large)";
        throw std::runtime_error(m.str());
      }
    }
  }
}

void WcsphFluid::check_density() {
  const int N = lat_.size();
  int worst = 0;
  double dv = 0;
  for (int i = 0; i < N; ++i) {
    const double e = std::fabs(rho_[i] / rho0_ - 1.0);
    if (e > dv || !std::isfinite(e)) { dv = e; worst = i; }
  }
  dvar_ = dv;
  if (dv > dvar_max_) { dvar_max_ = dv; t_dvar_max_ = t_; }
  if (!(dv <= opt_.max_density_variation)) {
    std::ostringstream m;
    m << "WCSPH: density variation |rho/rho0 - 1| = " << dv << " at particle " << worst << " (" << x_(worst, 0)
      << ", " << x_(worst, 1) << ") exceeds " << opt_.max_density_variation << " at t = " << t_
      << ": a blow-up (speed of sound c = " << c_ << " too low for this flow, or time.dt too large)";
    throw std::runtime_error(m.str());
  }
}

void WcsphFluid::set_velocity(const Mat2& u0) {
  ++revision_;
  if (u0.rows() != u_.rows() || u0.cols() != 2) throw std::invalid_argument("fluid: initial velocity has the wrong size");
  u_ = u0;
  xsph_velocity();  // with the neighbours of the current positions
}

void WcsphFluid::step(const Mat2& F) {
  ++revision_;
  const double dt = prm_.dt;
  if (F.rows() != u_.rows()) throw std::invalid_argument("WCSPH: force field has the wrong size");
  // C Eq. (19), force term: dt <= 0.25 sqrt(h / |f|), f = F / rho0 the external acceleration
  const double fmax = F.rowwise().norm().maxCoeff() / rho0_;
  if (fmax > 0 && dt > 0.25 * std::sqrt(W_.h / fmax)) {
    std::ostringstream m;
    m << "time.dt = " << dt << " exceeds the force limit 0.25 sqrt(h/|f|) = " << 0.25 * std::sqrt(W_.h / fmax)
      << " of Coelho et al. Eq. (19) (|f| = max |F|/rho = " << fmax << ")";
    throw std::invalid_argument(m.str());
  }
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
    xsph_velocity();  // V Eq. (21) of v^{n+1}, neighbours of x^{n+1/2}
  }
  {
    ScopedTimer tm(prof_, k_drift_);
    drift(0.5 * dt);  // V Eq. (22): x^{n+1} = x^{n+1/2} + dt/2 v^{n+1}
  }
  t_ += dt;
  ++n_;
  check_density();
}

double WcsphFluid::kinetic_energy() const { return 0.5 * m_ * u_.squaredNorm(); }

double WcsphFluid::max_abs_divergence() const {
  // (div u)_i = sum_j (m/rho_j) (u_i + u_j) . (x_i - x_j) F_ij  (Eq. 30 form), walls carry u_w
  const int N = lat_.size();
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
    m << "WCSPH (Morris et al. 1997; Vukcevic et al. 2012; Coelho et al.): " << lat_.nx << " x " << lat_.ny << " = "
      << size() << " moving particles, " << walls_.size() << " fixed virtual wall particles"
      << (opt_.morris_extrapolation ? " (Morris extrapolated velocity)" : " (wall velocity)")
      << (lj_ ? " + Lennard-Jones repulsion (C Eq. 20)" : "") << ", h = " << W_.h << " (" << prm_.h_over_dx
      << " (dx+dy)/2), " << static_cast<double>(nbrs_total_) / ((n_ + 1.0) * size())
      << " neighbours per particle (mean over the run)";
    lines.push_back(m.str());
  }
  {
    std::ostringstream m;
    m << "EOS ";
    if (eos_ == Eos::Morris) m << "p = c^2 rho (Morris, V Eq. 20; background pressure c^2 rho0 = " << p_wall_ << ")";
    else m << "Tait (C Eq. 3), gamma = " << w.gamma;
    m << ", c = " << c_
      << (w.c > 0 ? " (wcsph.c)" : " (wcsph.c = 0: 10 u_scale, C Eq. 5 scaling for ~1% density variation)")
      << ", rho0 = " << rho0_ << ", m = rho0 / sum_j W_ij = " << m_ << " (lattice kernel sum S dx dy = "
      << lattice_kernel_sum() << ")";
    lines.push_back(m.str());
  }
  {
    std::ostringstream m;
    m << "leapfrog V Eq. (22) (drift-kick-drift), XSPH eps = " << w.xsph << ", dt = " << prm_.dt
      << " (C Eq. 19 limit " << dt_limit_ << ": 0.25 h/c = " << 0.25 * W_.h / c_
      << ", 0.125 h^2/nu = " << 0.125 * W_.h * W_.h / nu() << ")";
    lines.push_back(m.str());
  }
  {
    std::ostringstream m;
    m << "density variation max |rho/rho0 - 1| = " << dvar_max_ << " (at t = " << t_dvar_max_ << "), now "
      << dvar_ << " (papers aim below 0.03; blow-up above " << opt_.max_density_variation << ")";
    lines.push_back(m.str());
  }
  return lines;
}

std::vector<std::pair<std::string, double>> WcsphFluid::figures() const {
  return {{"max_density_variation", dvar_max_},
          {"density_variation", dvar_},
          {"sound_speed", c_},
          {"dt_limit_coelho", dt_limit_},
          {"wall_particles", static_cast<double>(walls_.size())},
          {"neighbours_per_particle", static_cast<double>(nbrs_last_) / size()},
          {"lattice_kernel_sum", lattice_kernel_sum()}};
}

NamedArrays WcsphFluid::state() const {
  Eigen::MatrixXd clock(1, 5);
  clock << t_, static_cast<double>(n_), dvar_, dvar_max_, t_dvar_max_;
  return {{"x", x_}, {"x_eval", x_eval_}, {"u", u_}, {"u_hat", u_hat_}, {"clock", clock}};
}

void WcsphFluid::restore(const NamedArrays& state) {
  ++revision_;
  const int N = size();
  x_ = state_entry(state, "x_eval", N, 2);
  find_neighbours();  // the neighbours and densities of the last evaluation, exactly
  summation_density();
  x_ = state_entry(state, "x", N, 2);
  u_ = state_entry(state, "u", N, 2);
  u_hat_ = state_entry(state, "u_hat", N, 2);
  const Eigen::MatrixXd& clock = state_entry(state, "clock", 1, 5);
  t_ = clock(0, 0);
  n_ = static_cast<long>(clock(0, 1));
  dvar_ = clock(0, 2);
  dvar_max_ = clock(0, 3);
  t_dvar_max_ = clock(0, 4);
}

double WcsphFluid::setup_seconds(const std::string& what) const {
  for (const auto& [k, s] : setup_)
    if (k == what) return s;
  return 0.0;
}

}  // namespace sphib
