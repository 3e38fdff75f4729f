// Classic SPH with a free surface: Afanasiev, Makarchuk & Popov (2011) ["A"], Sections 3.4-3.7, on
// the WCSPH solver (wcsph.hpp: the header comment lists the step). The rates themselves (A Eqs. 13,
// 14, 18, the artificial viscosity of Monaghan 1992) are WcsphFluid::accelerations.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fluid/moving/wcsph.hpp"

namespace sphib {

std::optional<ParamProblem> wcsph_free_surface_problem(const FluidParams& p) {
  if (auto e = free_surface_problem(p.method, p.domain, p.free_surface, p.gravity)) return e;
  const WcsphParams& w = p.wcsph;
  if (!(w.alpha >= 0) || !std::isfinite(w.alpha)) return ParamProblem{"wcsph.alpha", "must be >= 0 and finite"};
  if (w.smooth_every < 0) return ParamProblem{"wcsph.smooth_every", "must be >= 0"};
  if (!(w.delta >= 0) || !std::isfinite(w.delta)) return ParamProblem{"wcsph.delta", "must be >= 0 and finite"};
  if (w.delta > 0 && w.integrator != Integrator::PredictorCorrector)
    return ParamProblem{"wcsph.delta", "needs wcsph.integrator = \"predictor_corrector\" (a diffusion term of the continuity "
                                       "equation; the leapfrog's density is the summation density)"};
  if (p.gate.on && w.integrator != Integrator::PredictorCorrector)
    return ParamProblem{"gate", "needs wcsph.integrator = \"predictor_corrector\" (A's walls with a free surface)"};
  if (auto e = gate_problem(p)) return e;
  const bool free = has_free_surface(p.domain, p.free_surface), gravity = p.gravity.norm() != 0;
  if (!gravity && !free) return std::nullopt;
  const std::string what = free ? "a free surface" : "gravity";
  if (w.integrator != Integrator::PredictorCorrector)
    return ParamProblem{"wcsph.integrator", what + " needs \"predictor_corrector\" (A Eqs. 19-21 with the continuity "
                                                  "equation; the summation density of the leapfrog reads a free surface as a density deficit)"};
  if (w.eos != Eos::Tait) return ParamProblem{"wcsph.eos", what + " needs \"tait\" (A Eq. 27: p = 0 at the rest density)"};
  if (w.walls != WcsphWalls::Virtual) return ParamProblem{"wcsph.walls", what + " needs \"virtual\""};
  return std::nullopt;
}

void check_afanasiev_params(const FluidParams& p) {
  if (const auto e = wcsph_free_surface_problem(p)) throw std::invalid_argument(e->key + ": " + e->what);
}

int particle_count(const FluidParams& p, const Lattice& L) {
  if (p.wcsph.integrator != Integrator::PredictorCorrector) return L.size();
  return static_cast<int>(fill_particles(L, p.free_surface.fill).x.rows());
}

void WcsphFluid::init_afanasiev() {
  const FreeSurfaceParams& fs = prm_.free_surface;
  const ParticleSet set = fill_particles(lat_, fs.fill);
  N_ = static_cast<int>(set.x.rows());
  x_ = set.x;
  m_ = rho0_ * set.volume;  // the continuity equation carries the density: m = rho0 V
  B_ = rho0_ * c_ * c_ / prm_.wcsph.gamma;  // A Eq. (27): B = rho0 c^2 / gamma
  wall_pressure_ = prm_.wcsph.wall_pressure;
  const SurfaceDetection how = detection_for(prm_.method, prm_.domain, fs);
  surface_on_ = how != SurfaceDetection::None;
  detector_ = SurfaceDetector(how, fs.beta, fs.dilts_radius * W_.h);
  u_ = u_hat_ = a_ = v_half_ = Mat2::Zero(N_, 2);
  p_ = pr_ = drho_ = Vec::Zero(N_);
  surface_.assign(N_, 0);
  // A Eq. (28): rho* = rho0 (1 + rho0 |g| depth / B)^(1/gamma), p(rho*) = rho0 |g| depth
  const Vec depth = hydrostatic_depth(x_, fs.fill, prm_.domain, prm_.gravity);
  rho_next_.resize(N_);
  for (int i = 0; i < N_; ++i)
    rho_next_[i] = rho0_ * std::pow(1.0 + rho0_ * prm_.gravity.norm() * depth[i] / B_, 1.0 / prm_.wcsph.gamma);
  rho_half_ = rho_ = rho_next_;
  V_ = m_ / rho_.array();
  wall_self_density();
  tank_walls_ = walls_.size();
  if (prm_.gate.on) {
    gate_top_ = x_.col(1).maxCoeff() + 0.5 * lat_.dy;
    gate_in_ = true;
  }
  find_neighbours();  // the gate placed there; the state at t = 0: surface, pressures (the loads' p(0))
  if (surface_on_) detector_.detect(N_, pairs_, V_, m_ / rho0_, surface_);
  pressures();
  xsph_velocity(u_);
}

// The wall particles among themselves: m (W(0) + sum_w' W_ww').
void WcsphFluid::wall_self_density() {
  PairSearch among(prm_.domain, W_, walls_.size(), Mat2(0, 2));
  ParticlePairs P;
  among.find(walls_.x, P);
  rho_ww_.setConstant(walls_.size(), m_ * W_.W(0.0));
  for (int k = 0; k < P.size(); ++k) {
    rho_ww_[P.i[k]] += m_ * P.W[k];
    rho_ww_[P.j[k]] += m_ * P.W[k];
  }
}

// A gate (isph.hpp describes it; walls.hpp, append_gate): its particles at time t after the tank's, or
// none once its lower edge is more than 2h above the highest particle; the pair search and the wall
// particles' self-density then take the new walls. Returns whether the walls changed.
bool WcsphFluid::place_gate(double t) {
  const int M0 = walls_.size();
  if (!move_gate(lat_, W_.support(), prm_.gate, gate_top_, t, x_.col(1).maxCoeff(), tank_walls_, gate_in_, walls_))
    return false;
  const int M = walls_.size();
  search_ = PairSearch(prm_.domain, W_, N_, walls_.x);
  wall_self_density();
  for (Vec* v : {&p_w_, &pr_w_, &rho_w_}) v->conservativeResize(M);
  for (int w = M0; w < M; ++w) {  // new wall particles: the rest values (pressures() sets them)
    p_w_[w] = p_wall_;
    pr_w_[w] = p_wall_ / (rho0_ * rho0_);
    rho_w_[w] = rho0_;
  }
  return true;
}

void WcsphFluid::pressures() {
  const double gamma = prm_.wcsph.gamma;
  for (int i = 0; i < N_; ++i) {
    V_[i] = m_ / rho_[i];
    p_[i] = surface_[i] ? 0.0 : eos_pressure(eos_, rho_[i], rho0_, c_, gamma);  // A Eq. (27); p = 0 on the surface (A Section 3.5)
    pr_[i] = p_[i] / (rho_[i] * rho_[i]);
  }
  if (wall_pressure_ == WallPressure::Rest) return;
  wall_particle_pressure(wall_pressure_, N_, pairs_, V_, p_, rho_, prm_.gravity, p_w_, work_w_);  // A Eq. (30)
  Vec& rho_sum = work_w_;  // the wall particles' summation density: themselves, then the fluid
  rho_sum = rho_ww_;
  for (int k = 0; k < pairs_.size(); ++k)
    if (pairs_.j[k] >= N_) rho_sum[pairs_.j[k] - N_] += m_ * pairs_.W[k];
  for (int w = 0; w < walls_.size(); ++w) {
    // no penetration: at least Tait's pressure at that density; no tension (a wall cannot pull the
    // fluid, e.g. beside the free surface)
    p_w_[w] = std::max({p_w_[w], eos_pressure(eos_, std::max(rho_sum[w], rho0_), rho0_, c_, gamma), 0.0});
    // the density of Tait's law at the wall pressure (A Eq. 27 inverted)
    rho_w_[w] = rho0_ * std::pow(std::max(1.0 + p_w_[w] / B_, 1e-6), 1.0 / gamma);
    pr_w_[w] = p_w_[w] / (rho_w_[w] * rho_w_[w]);
  }
}

void WcsphFluid::smooth_density(Vec& rho) const {
  // A Eq. (29), equal masses: rho_i <- sum_j rho_j W_ij / sum_j W_ij (the particle itself and the
  // wall particles included)
  const ParticlePairs& P = pairs_;
  const double W0 = W_.W(0.0);
  Vec num = W0 * rho, den = Vec::Constant(N_, W0);
  for (int k = 0; k < P.size(); ++k) {
    const int i = P.i[k], j = P.j[k];
    const double w = P.W[k];
    num[i] += w * (j < N_ ? rho[j] : rho_w_[j - N_]);
    den[i] += w;
    if (j < N_) {
      num[j] += w * rho[i];
      den[j] += w;
    }
  }
  rho = num.cwiseQuotient(den);
}

void WcsphFluid::step_afanasiev(const Mat2& F) {
  const double dt = prm_.dt;
  rho_ = rho_next_;  // A Eq. (19): v^n (u_) and rho^n, predicted at the end of the last step
  V_ = m_ / rho_.array();
  {
    ScopedTimer tm(prof_, k_neigh_);
    find_neighbours();  // at r^n
  }
  if (surface_on_) {
    ScopedTimer tm(prof_, k_surface_);
    detector_.detect(N_, pairs_, V_, m_ / rho0_, surface_);  // Dilts or A Eq. (26)
    // p = 0 on the surface (A Section 3.5) is rho = rho0 by A Eq. (27): the continuity equation's
    // density of a particle with a truncated support means nothing there (a free surface stretched
    // along itself compresses it without bound)
    for (int i = 0; i < N_; ++i)
      if (surface_[i]) rho_[i] = rho_half_[i] = rho0_;
  }
  {
    ScopedTimer tm(prof_, k_rho_);
    pressures();  // A Eq. (27), p = 0 on the surface, wall particles (A Eq. 30)
  }
  {
    ScopedTimer tm(prof_, k_force_);
    accelerations(F);  // a^n, rhodot^n: A Eqs. (13), (14), (18), g, Monaghan (1992)
    const double kick = started_ ? dt : 0.5 * dt;  // the first step: v^{1/2} = v^0 + dt/2 a^0
    v_half_ += kick * a_;        // A Eq. (20): v^{n+1/2} = v^{n-1/2} + dt a^n
    rho_half_ += kick * drho_;   // A Eq. (20): rho^{n+1/2} = rho^{n-1/2} + dt rhodot^n
    started_ = true;
    if (prm_.wcsph.smooth_every > 0 && (n_ + 1) % prm_.wcsph.smooth_every == 0) smooth_density(rho_half_);  // A Eq. (29)
    u_ = v_half_ + 0.5 * dt * a_;          // A Eq. (19) of the next step: v^{n+1}
    rho_next_ = rho_half_ + 0.5 * dt * drho_;  // and rho^{n+1}
  }
  {
    ScopedTimer tm(prof_, k_xsph_);
    xsph_velocity(v_half_);  // V Eq. (21) of v^{n+1/2} (eps = 0: v^{n+1/2} itself)
  }
  {
    ScopedTimer tm(prof_, k_drift_);
    drift(dt);  // A Eq. (21): r^{n+1} = r^n + dt v^{n+1/2}
  }
  t_ += dt;
  ++n_;
  check_density();
}

NamedArrays WcsphFluid::state_afanasiev() const {
  return {{"x", x_},          {"x_eval", x_eval_},       {"rho_eval", rho_},   {"u", u_},
          {"v_half", v_half_}, {"rho_half", rho_half_}, {"rho_next", rho_next_},
          {"clock", clock()}};
}

void WcsphFluid::restore_afanasiev(const NamedArrays& state) {
  const int N = N_;
  if (prm_.gate.on) {  // the gate of the last evaluation, at t - dt
    restore_clock(state);
    gate_in_ = true;
    place_gate(t_ - prm_.dt);
  }
  x_ = state_entry(state, "x_eval", N, 2);  // the last evaluation again: surface, pressures, volumes
  rho_ = state_entry(state, "rho_eval", N, 1);
  V_ = m_ / rho_.array();
  find_neighbours();
  if (surface_on_) detector_.detect(N_, pairs_, V_, m_ / rho0_, surface_);
  pressures();
  x_ = state_entry(state, "x", N, 2);
  u_ = state_entry(state, "u", N, 2);
  v_half_ = state_entry(state, "v_half", N, 2);
  rho_half_ = state_entry(state, "rho_half", N, 1);
  rho_next_ = state_entry(state, "rho_next", N, 1);
  restore_clock(state);
}

}  // namespace sphib
