#include "coupling/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <sstream>
#include <stdexcept>

#include "coupling/contact.hpp"
#include "coupling/interpolate.hpp"
#include "coupling/marker_update.hpp"
#include "coupling/spread.hpp"
#include "coupling/stiff_force.hpp"
#include "coupling/viscosity_contrast.hpp"
#include "fluid/factory.hpp"
#include "fluid/common/neighbours.hpp"
#include "fluid/common/threads.hpp"
#include "fluid/algebra/row_stencil.hpp"  // kParallelRows
#include "membrane/geometry.hpp"  // AreaKeeper

namespace sphib {

namespace {

// A membrane must lie inside the domain and keep its spreading support 2h* and the fluid's
// interpolation support 2h off every wall.
void check_membrane(const Domain& d, const MembraneSetup& s, double h, int index) {
  std::ostringstream m;
  m << "membrane " << index << ": ";
  if (!(s.h_star > 0)) { m << "h_star must be positive (got " << s.h_star << ")"; throw std::invalid_argument(m.str()); }
  if (s.membrane.nb() < 4) { m << "needs at least 4 markers (got " << s.membrane.nb() << ")"; throw std::invalid_argument(m.str()); }
  if (!s.membrane.X.allFinite()) { m << "marker positions are not finite"; throw std::invalid_argument(m.str()); }
  if (!(s.viscosity_ratio > 0) || !std::isfinite(s.viscosity_ratio)) {
    m << "viscosity_ratio must be positive and finite (got " << s.viscosity_ratio << ")";
    throw std::invalid_argument(m.str());
  }
  const double reach = std::max(2.0 * s.h_star, 2.0 * h);
  const double xmin = s.membrane.X.col(0).minCoeff(), xmax = s.membrane.X.col(0).maxCoeff();
  const double ymin = s.membrane.X.col(1).minCoeff(), ymax = s.membrane.X.col(1).maxCoeff();
  auto refuse = [&](const char* side, double gap) {
    m << "lies within " << gap << " of the " << side << " (needs at least max(2h*, 2h) = " << reach << ")";
    throw std::invalid_argument(m.str());
  };
  if (!d.periodic_x) {
    if (xmin - d.x0 < reach) refuse("wall x = x0", xmin - d.x0);
    if (d.x1 - xmax < reach) refuse("wall x = x1", d.x1 - xmax);
  }
  if (!d.periodic_y) {
    if (ymin - d.y0 < reach) refuse("wall y = y0", ymin - d.y0);
    if (d.y1 - ymax < reach) refuse("wall y = y1", d.y1 - ymax);
  }
}

}  // namespace

MembraneState::MembraneState(const MembraneSetup& s)
    : m(s.membrane), h_star(s.h_star), fixed(s.fixed), W_star(s.h_star), force(s.membrane),
      f(Mat2::Zero(s.membrane.nb(), 2)), U_n(f), U(f), X_n(s.membrane.X), T(Vec::Zero(s.membrane.nb())) {
  if (s.semi_implicit && !s.fixed) {
    filter = std::make_unique<StiffForceFilter>(s.membrane.nb(), s.stiff_residual);
    f_tilde = f;
  }
}

MembraneState::MembraneState(MembraneState&&) noexcept = default;
MembraneState& MembraneState::operator=(MembraneState&&) noexcept = default;
MembraneState::~MembraneState() = default;

struct Simulation::FreeSet : MarkerSet {
  Mat2 X_n, U, U_n, U_prev;
  MarkerWork work;
};

Simulation::~Simulation() = default;

Simulation::Simulation(const SimulationParams& params)
    : prm_(params), fluid_(make_fluid(params.fluid, &fluid_prof_)),
      grid_(std::make_unique<CellGrid>(
          Eigen::Vector2d(params.fluid.domain.x0, params.fluid.domain.y0),
          Eigen::Vector2d(params.fluid.domain.x1, params.fluid.domain.y1), params.fluid.domain.periodic_x,
          params.fluid.domain.periodic_y, std::min(fluid_->lattice().dx, fluid_->lattice().dy))),
      free_(std::make_unique<FreeSet>()) {
  const int N = fluid_->size();
  for (size_t k = 0; k < prm_.membranes.size(); ++k) {
    check_membrane(prm_.fluid.domain, prm_.membranes[k], fluid_->h(), static_cast<int>(k));
    mem_.emplace_back(prm_.membranes[k]);
  }
  if (prm_.markers.keep_area)
    for (auto& s : mem_)
      if (!s.fixed) s.keeper = std::make_unique<AreaKeeper>(s.m.nb());
  if (prm_.markers.max_move <= 0)  // a marker moving more than a lattice spacing in a step is a blow-up
    prm_.markers.max_move = std::min(fluid_->lattice().dx, fluid_->lattice().dy);
  interp_ = prm_.interpolation;
  if (interp_ == MarkerInterpolation::Auto) {
    // B-splines where the kernel curl's lattice-scale ripple matters: bending (it feeds the curvature)
    // and the laws other than Hookean (the neo-Hookean ring lost 4e-5 of its area by t = 10 with the
    // kernel curl, 1e-6 with B-splines: docs/membrane_validation.md).
    bool smooth = false;
    for (const auto& s : prm_.membranes) smooth |= s.membrane.mat.Eb > 0 || s.membrane.mat.law != "hookean";
    interp_ = !fluid_->has_stream_function() ? MarkerInterpolation::Sph
              : smooth                       ? MarkerInterpolation::BSpline
                                             : MarkerInterpolation::DivergenceFree;
  }
  if (interp_ != MarkerInterpolation::Sph && !fluid_->has_stream_function())
    throw std::invalid_argument(std::string("coupling.interpolation = \"") +
                                (interp_ == MarkerInterpolation::BSpline           ? "bspline"
                                 : interp_ == MarkerInterpolation::SpreadingKernel ? "spreading_kernel"
                                                                                   : "divergence_free") +
                                "\" needs a stream function of the fluid, which method \"" + to_string(prm_.fluid.method) +
                                "\" does not provide (use \"sph\")");
  if (interp_ == MarkerInterpolation::SpreadingKernel) {  // one kernel for the free markers: one h*
    const MembraneState* first = nullptr;
    for (const auto& s : mem_) {
      if (s.fixed) continue;
      if (first && s.h_star != first->h_star) {
        std::ostringstream e;
        e << "coupling.interpolation = \"spreading_kernel\" interpolates every free membrane with one kernel: membrane "
          << &s - mem_.data() << " has h_star = " << s.h_star << ", membrane " << first - mem_.data() << " h_star = "
          << first->h_star << " (give the free membranes one membrane.h_star)";
        throw std::invalid_argument(e.str());
      }
      if (!first) first = &s;
    }
    if (first) W_interp_.emplace(first->h_star);
  }
  if (!mem_.empty()) {  // no membranes, no coupling
    if (fluid_->particles_move()) grid_->build(fluid_->x());
    else grid_->use_lattice(fluid_->lattice());  // EPSPH: index arithmetic on the fixed lattice
    bool free = false;
    for (const auto& s : mem_) free |= !s.fixed;
    if (free && interp_ != MarkerInterpolation::Sph) fluid_->stream_function();  // its set-up, now
  }
  // A viscosity contrast: the fluid's variable viscosity, from the indicators of the markers
  bool contrast = false;
  for (const auto& s : prm_.membranes) contrast |= s.viscosity_ratio != 1.0;
  if (contrast) {
    if (!fluid_->supports_variable_viscosity())
      throw std::invalid_argument("membrane.viscosity_ratio != 1 (a viscosity contrast) needs method \"eulerian\"; method \"" +
                                  std::string(to_string(prm_.fluid.method)) + "\" has one viscosity everywhere");
    std::vector<double> lambda;
    for (const auto& s : prm_.membranes) lambda.push_back(s.viscosity_ratio);
    // A ratio below 1 takes its cross term explicitly (fluid/eulerian/variable_viscosity.hpp): measured stable
    // for nu (1 - lambda) dt / dx^2 <= 0.5 across a sharp interface (a circle at lambda = 0.01, 0.1 in
    // a periodic box blows up at 0.6; lambda = 0.5 is stable at 0.7)
    const double lo = *std::min_element(lambda.begin(), lambda.end()), dx = std::min(fluid_->lattice().dx, fluid_->lattice().dy);
    const double number = fluid_->nu() * (1.0 - lo) * prm_.fluid.dt / (dx * dx);
    if (number > 0.5) {
      std::ostringstream e;
      e << "membrane.viscosity_ratio = " << lo << " < 1 takes the less viscous inside's cross term explicitly, stable for "
        << "nu (1 - viscosity_ratio) time.dt / dx^2 <= 0.5: here " << number << " (nu = " << fluid_->nu()
        << ", dx = " << dx << "); lower time.dt to " << 0.5 * dx * dx / (fluid_->nu() * (1.0 - lo)) << " or below";
      throw std::invalid_argument(e.str());
    }
    contrast_ = std::make_unique<ViscosityContrast>(fluid_->lattice(), lambda);
    k_visc_ = prof_.phase("viscosity contrast (indicator)");
    viscosity_now();  // m^0: the fluid's variable-viscosity state exists before a restart restores it
  }
  if (prm_.initial_velocity) {
    const Mat2& x = fluid_->x();
    Mat2 u0(N, 2);
    for (int i = 0; i < N; ++i) u0.row(i) = prm_.initial_velocity(x(i, 0), x(i, 1)).transpose();
    fluid_->set_velocity(u0);
  }
  F_ = Mat2::Zero(N, 2);
  if (prm_.body_force_field) {
    F_body_ = F_;
  } else {  // a uniform body force fills F_ (external_force)
    F_.col(0).setConstant(prm_.body_force.x());
    F_.col(1).setConstant(prm_.body_force.y());
  }
  k_force_ = prof_.phase("membrane force (Eqs. 47-50)");
  k_spread_ = prof_.phase("spreading (Eq. 53)");
  k_interp_ = prof_.phase("interpolation u^n(X^n) (Eq. 63)");
  k_markers_ = prof_.phase("marker update (Eqs. 56-60)");
  for (const auto& s : mem_)
    if (s.filter) k_stiff_ = prof_.phase("stiff-force filter (coupling/stiff_force.hpp)");
  all_.start.assign(1, 0);
  for (size_t k = 0; k < mem_.size(); ++k) {
    all_.members.push_back(static_cast<int>(k));
    all_.start.push_back(all_.start.back() + mem_[k].m.nb());
    ds_.push_back(mem_[k].m.ds());
    if (k == 0 || mem_[k].h_star != mem_[k - 1].h_star) spread_runs_.push_back({static_cast<int>(k), static_cast<int>(k)});
    spread_runs_.back().second = static_cast<int>(k) + 1;
  }
  if (prm_.contact.on() && !mem_.empty()) {
    contact_ = std::make_unique<ContactForce>(prm_.contact, prm_.fluid.domain);
    k_contact_ = prof_.phase("contact force (coupling/contact.hpp)");
  }
  update_membrane_forces();  // f and T at t = 0 (a stretched membrane starts under tension)
}

void Simulation::set_markers(size_t k, const Mat2& X) {
  if (k >= mem_.size() || X.rows() != mem_[k].m.X.rows())
    throw std::invalid_argument("membrane " + std::to_string(k) + ": markers do not match the scene");
  mem_[k].m.X = X;
  mem_[k].U_revision = -1;
  mem_[k].U_n_known = mem_[k].U_prev_known = false;  // a jump: no history for the predictor
  if (contact_) update_membrane_forces();  // the contact of every membrane changes with these markers
  else mem_[k].force.compute(mem_[k].m.X, mem_[k].f, mem_[k].T);
}

Eigen::MatrixXd Simulation::stiff_filter_state(size_t k) const {
  return mem_.at(k).filter ? mem_[k].filter->state() : Eigen::MatrixXd();
}

void Simulation::set_stiff_filter_state(size_t k, const Eigen::MatrixXd& s) {
  if (mem_.at(k).filter) {
    mem_[k].filter->set_state(s);
  } else if (s.size() > 0) {
    throw std::invalid_argument("membrane " + std::to_string(k) + " has a stiff-force filter state but is not semi-implicit");
  }
}

void Simulation::set_marker_history(size_t k, const Mat2& U_n, const Mat2* U_next) {
  if (k >= mem_.size() || U_n.rows() != mem_[k].m.X.rows() || (U_next && U_next->rows() != U_n.rows()))
    throw std::invalid_argument("membrane " + std::to_string(k) + ": marker velocities do not match the scene");
  mem_[k].U_n = U_n;
  mem_[k].U_n_known = true;
  if (U_next) {
    mem_[k].U = *U_next;
    mem_[k].U_revision = fluid_->revision();
  }
}

const Mat2* Simulation::next_marker_velocity(size_t k) const {
  return k < mem_.size() && mem_[k].U_revision == fluid_->revision() ? &mem_[k].U : nullptr;
}

void Simulation::update_membrane_forces() {
  elastic_forces();
  if (contact_) contact_forces();
}

// Each membrane's force is its own (its splines and workspace in its MembraneForce): from
// kParallelMembraneMarkers markers in two or more membranes the threads share the membranes out, the
// same bits for any thread count.
constexpr int kParallelMembraneMarkers = 512;

void Simulation::elastic_forces() {
  const int M = static_cast<int>(mem_.size());
  const bool par = M >= 2 && all_.start.back() >= kParallelMembraneMarkers;
  (void)par;
  std::exception_ptr fault;  // the first membrane's refusal in membrane order, as the serial loop
  int faulted = M;
#pragma omp parallel for schedule(static) if (par)
  for (int k = 0; k < M; ++k) {
    try {
      mem_[k].force.compute(mem_[k].m.X, mem_[k].f, mem_[k].T);  // Eqs. (47)-(50)
    } catch (...) {
#pragma omp critical(sphib_elastic_fault)
      if (k < faulted) faulted = k, fault = std::current_exception();
    }
  }
  if (fault) std::rethrow_exception(fault);
}

void Simulation::contact_forces() {
  all_.X.resize(all_.start.back(), 2);
  for (size_t k = 0; k < mem_.size(); ++k) all_.X.middleRows(all_.start[k], mem_[k].m.nb()) = mem_[k].m.X;
  all_.P.setZero(all_.start.back(), 2);
  contact_->add(all_.X, all_.start, ds_, all_.P);
  for (size_t k = 0; k < mem_.size(); ++k) mem_[k].f += all_.P.middleRows(all_.start[k], mem_[k].m.nb());
}

namespace {

// Markers per block of the interpolation by the threads (by_marker_blocks): enough work per block to
// outweigh a fork and join many times over.
constexpr int kMarkerBlock = 256;

// interp(X, U, dU) over the rows of X, from 2 kMarkerBlock markers by the threads in fixed blocks of
// kMarkerBlock rows (each marker's velocity is its own sum: the same bits as one call, for any thread
// count). A failing marker (MarkerError) is reported as one call reports it: the first in X,
// numbered in X. On one thread: one call over X (no copies of the blocks).
template <class Interp>
void by_marker_blocks(const Mat2& X, Mat2& U, Jacobians* dU, Interp&& interp) {
  const int n = static_cast<int>(X.rows());
  if (n < 2 * kMarkerBlock) return interp(X, U, dU);
  U.resize(n, 2);
  if (thread_count() == 1) return interp(X, U, dU);
  if (dU) dU->resize(n, 4);
  const int blocks = (n + kMarkerBlock - 1) / kMarkerBlock;
  std::vector<std::exception_ptr> fault(blocks);
#pragma omp parallel for schedule(static)
  for (int b = 0; b < blocks; ++b) {
    const int at = b * kMarkerBlock, m = std::min(n, at + kMarkerBlock) - at;
    try {
      const Mat2 Xb = X.middleRows(at, m);
      Mat2 Ub(m, 2);
      Jacobians dUb;
      interp(Xb, Ub, dU ? &dUb : nullptr);
      U.middleRows(at, m) = Ub;
      if (dU) dU->middleRows(at, m) = dUb;
    } catch (const MarkerError& e) {
      fault[b] = std::make_exception_ptr(MarkerError(e.head, at + e.marker, e.tail));
    } catch (...) {
      fault[b] = std::current_exception();
    }
  }
  for (const auto& f : fault)
    if (f) std::rethrow_exception(f);
}

}  // namespace

bool Simulation::marker_velocity(const Mat2& X, Mat2& U, Jacobians* dU) const {
  const FluidSolver& fluid = *fluid_;
  if (interp_ == MarkerInterpolation::DivergenceFree) {
    const StreamFunction sf = fluid.stream_function();  // once per fluid state, then cached
    by_marker_blocks(X, U, dU, [&](const Mat2& Xb, Mat2& Ub, Jacobians* dUb) {
      interpolate_curl(*grid_, fluid.kernel(), *sf.psi, sf.mean, Xb, Ub, dUb);
    });
    return dU != nullptr;
  }
  if (interp_ == MarkerInterpolation::SpreadingKernel) {  // Eq. (63) on psi with W(r, h*), the kernel of Eq. (53), then its curl
    const StreamFunction sf = fluid.stream_function();
    by_marker_blocks(X, U, dU, [&](const Mat2& Xb, Mat2& Ub, Jacobians* dUb) {
      interpolate_curl(*grid_, *W_interp_, *sf.psi, sf.mean, Xb, Ub, dUb);
    });
    return dU != nullptr;
  }
  if (interp_ == MarkerInterpolation::BSpline) {
    const StreamFunction sf = fluid.stream_function();
    by_marker_blocks(X, U, dU, [&](const Mat2& Xb, Mat2& Ub, Jacobians* dUb) {
      interpolate_curl_bspline(*grid_, fluid.lattice().dx, fluid.lattice().dy, *sf.psi, sf.mean, Xb, Ub, dUb);
    });
    return dU != nullptr;
  }
  interpolate_velocity(*grid_, fluid.kernel(), fluid.volumes(), fluid.u(), X, U);  // Eq. (63)
  return false;
}

double Simulation::coupling_floor_seconds(int reps) const {
  if (mem_.empty()) return 0.0;
  std::vector<MembraneForce> force;  // copies: the states' splines stay as they are
  for (const auto& s : mem_) force.push_back(s.force);
  Mat2 f, F = F_, U;
  Vec T;
  Jacobians dU;
  double total = best_of(reps, [&] {
    for (size_t k = 0; k < mem_.size(); ++k) force[k].compute(mem_[k].m.X, f, T);  // Eqs. (47)-(50)
  });
  if (contact_) {
    Mat2 fc;
    total += best_of(reps, [&] {
      fc.setZero(all_.X.rows(), 2);
      contact_->add(all_.X, all_.start, ds_, fc);
    });
  }
  if (k_stiff_ >= 0) {
    Mat2 ft;
    const FluidParams& p = fluid_->params();
    total += best_of(reps, [&] {
      for (const auto& s : mem_)
        if (s.filter)
          s.filter->apply(s.force, s.f, s.U_n, {p.rho, p.mu, p.dt, s.h_star, interpolation_length()}, ft, false);
    });
  }
  // one spreading, as step() makes it: one pass over each run of membranes sharing h*
  Simulation& self = const_cast<Simulation&>(*this);  // (its workspace; the state stays as it is)
  total += best_of(reps, [&] {
    for (const auto& [a, b] : spread_runs_) self.spread_run(a, b, F);  // Eq. (53)
  });
  Mat2 X(free_->start.empty() ? 0 : free_->start.back(), 2);
  for (size_t i = 0; i < free_->members.size(); ++i)
    X.middleRows(free_->start[i], free_->start[i + 1] - free_->start[i]) = mem_[free_->members[i]].m.X;
  if (X.rows() == 0) return total;
  if (interp_ != MarkerInterpolation::Sph) total += fluid_prof_.stream_function_floor_seconds(reps);
  U.resize(X.rows(), 2);
  total += best_of(reps, [&] { marker_velocity(X, U, prm_.markers.linearise ? &dU : nullptr); });  // one call
  return total;
}

// One IB time step, t_n -> t_{n+1} (ARCHITECTURE.md, "One IB time step"):
//   F^n = body force + S f^n;  PMIII: u^n -> u^{n+1};  X^{n+1} by the trapezoidal rule;  f^{n+1}.
void Simulation::step() {
  external_force(time());      // F^n: the body force at t_n
  marker_velocities_now();     // U^n(X^n), the explicit half of the trapezoidal rule (Eq. 59)
  if (contrast_) viscosity_now();  // mu^n = mu (1 + (lambda - 1) I(X^n)) (coupling/viscosity_contrast.hpp)
  stiff_forces();              // semi-implicit membranes: f~ ~ f^{n+1}, linearised (stiff_force.hpp)
  spread_membrane_forces();    // F^n += sum_k f_k^n W(x_i - X_k^n, h*) ds (Eq. 53)
  fluid_->step(F_);            // PMIII with prefactored systems: u^n -> u*, u^{n+1} (Eqs. 28-35)
  move_markers();              // X^{n+1} = X^n + dt/2 (U^n(X^n) + U^{n+1}(X^{n+1})) (Eqs. 56-60)
  {
    ScopedTimer t(prof_, k_force_);
    elastic_forces();          // f^{n+1}, T^{n+1} (Eqs. 47-50): the next step's, and what output sees
  }
  if (!contact_) return;
  ScopedTimer t(prof_, k_contact_);
  contact_forces();            // f^{n+1} += the repulsion between membranes and off walls (contact.hpp)
}

void Simulation::external_force(double t) {
  if (prm_.body_force_field) {
    const Mat2& x = fluid_->x();
    for (int i = 0; i < x.rows(); ++i) F_body_.row(i) = prm_.body_force_field(x(i, 0), x(i, 1), t).transpose();
    F_ = F_body_;
  } else {  // uniform: filled, not copied (half the memory traffic), by the threads on a large lattice
    const int N = static_cast<int>(F_.rows());
    const double fx = prm_.body_force.x(), fy = prm_.body_force.y();
    double *F0 = F_.col(0).data(), *F1 = F_.col(1).data();
#pragma omp parallel for schedule(static) if (N >= kParallelRows)
    for (int i = 0; i < N; ++i) {
      F0[i] = fx;
      F1[i] = fy;
    }
  }
  if (fluid_->particles_move() && !mem_.empty()) grid_->build(fluid_->x());  // LPSPH, WCSPH: O(N)
}

double Simulation::interpolation_length() const {
  if (interp_ == MarkerInterpolation::BSpline) return std::min(fluid_->lattice().dx, fluid_->lattice().dy);
  if (W_interp_) return W_interp_->h;
  return fluid_->h();
}

void Simulation::stiff_forces() {
  if (k_stiff_ < 0) return;
  ScopedTimer t(prof_, k_stiff_);
  const FluidParams& p = fluid_->params();
  for (auto& s : mem_)
    if (s.filter) s.filter->apply(s.force, s.f, s.U_n, {p.rho, p.mu, p.dt, s.h_star, interpolation_length()}, s.f_tilde);
}

void Simulation::spread_membrane_forces() {
  ScopedTimer t(prof_, k_spread_);
  for (const auto& [a, b] : spread_runs_) spread_run(a, b, F_);  // Eq. (53), f~ where semi-implicit
}

void Simulation::spread_run(int a, int b, Mat2& F) {
  if (b - a == 1) {  // one membrane: its own arrays
    const MembraneState& s = mem_[a];
    spread_force(*grid_, s.W_star, s.m.X, s.filter ? s.f_tilde : s.f, s.m.ds(), F);
    return;
  }
  const int r0 = all_.start[a], rows = all_.start[b] - r0;
  all_.X.resize(rows, 2);
  all_.P.resize(rows, 2);
  for (int k = a; k < b; ++k) {  // the run's markers and point forces f_k ds, concatenated
    const MembraneState& s = mem_[k];
    const Mat2& f = s.filter ? s.f_tilde : s.f;
    const int o = all_.start[k] - r0, n = s.m.nb();
    const double ds = ds_[k];
    all_.X.middleRows(o, n) = s.m.X;
    for (int i = 0; i < n; ++i) {
      all_.P(o + i, 0) = f(i, 0) * ds;
      all_.P(o + i, 1) = f(i, 1) * ds;
    }
  }
  spread_point_forces(*grid_, mem_[a].W_star, all_.X, all_.P, F);
}

void Simulation::marker_velocities_now() {
  ScopedTimer t(prof_, k_interp_);
  for (auto& s : mem_) {
    if (s.fixed) continue;
    if (s.U_n_known) {  // last step's U^n becomes U^{n-1}
      s.U_prev = s.U_n;
      s.U_prev_known = true;
    }
    s.U_n_known = true;
    if (s.U_revision == fluid_->revision()) {
      s.U_n = s.U;  // the last marker update's u^n at X^n
      continue;
    }
    try {
      marker_velocity(s.m.X, s.U_n);
    } catch (const std::runtime_error& e) {  // name the membrane: a scene may hold several
      throw std::runtime_error("membrane " + std::to_string(&s - mem_.data()) + ": " + e.what());
    }
  }
}

void Simulation::viscosity_now() {
  ScopedTimer t(prof_, k_visc_);
  X_now_.clear();
  for (const auto& s : mem_) X_now_.push_back(&s.m.X);
  contrast_->update(X_now_, *fluid_);
}

void Simulation::move_markers() {
  ScopedTimer t(prof_, k_markers_);
  if (fluid_->particles_move() && !mem_.empty()) grid_->build(fluid_->x());  // the particles of u^{n+1}
  // The free membranes in one set, or two when some start their predictor afresh (Eq. 58: the first
  // step, a restart without the history) and others extrapolate.
  for (bool extrapolate : {true, false}) {
    free_->members.clear();
    free_->start.assign(1, 0);
    for (size_t k = 0; k < mem_.size(); ++k) {
      const MembraneState& s = mem_[k];
      if (s.fixed || (s.U_prev_known && prm_.markers.extrapolate) != extrapolate) continue;
      free_->members.push_back(static_cast<int>(k));
      free_->start.push_back(free_->start.back() + s.m.nb());
    }
    if (!free_->members.empty()) advance_set(*free_, extrapolate);
  }
}

void Simulation::advance_set(FreeSet& set, bool extrapolate) {
  const int n = set.start.back(), M = static_cast<int>(set.members.size());
  set.X.resize(n, 2);
  set.U_n.resize(n, 2);
  set.U_prev.resize(n, 2);
  set.U.resize(n, 2);
  for (int i = 0; i < M; ++i) {
    MembraneState& s = mem_[set.members[i]];
    const int o = set.start[i], nb = s.m.nb();
    set.X.middleRows(o, nb) = s.m.X;
    set.U_n.middleRows(o, nb) = s.U_n;
    if (extrapolate) set.U_prev.middleRows(o, nb) = s.U_prev;
    s.U_revision = -1;
  }
  const MarkerVelocity U_new = [this](const Mat2& X, Mat2& U, Jacobians* dU) { return marker_velocity(X, U, dU); };
  const MarkerConstraint keep = [&](int g, Eigen::Ref<const Mat2> Xn, Eigen::Ref<const Mat2> Un,
                                    Eigen::Ref<const Mat2> X, Eigen::Ref<Mat2> U) {
    mem_[set.members[g]].keeper->keep(Xn, Un, X, U);
  };
  try {
    advance_markers(U_new, set.U_n, extrapolate ? &set.U_prev : nullptr, fluid_->params().dt, prm_.markers,
                    fluid_->steps(), set.X, set.X_n, set.U, set.work, &set.start,
                    prm_.markers.keep_area ? &keep : nullptr);
  } catch (const MarkerError& e) {  // name the membrane and its marker
    const int i = static_cast<int>(std::upper_bound(set.start.begin(), set.start.end(), e.marker) - set.start.begin()) - 1;
    throw std::runtime_error("membrane " + std::to_string(set.members[i]) + ": " + e.head +
                             std::to_string(e.marker - set.start[i]) + e.tail);
  } catch (const std::runtime_error& e) {  // (the SPH interpolation's, fluid/common/interpolation.hpp: markers numbered across the set)
    throw std::runtime_error((M == 1 ? "membrane " + std::to_string(set.members[0]) : std::string("membranes")) + ": " + e.what());
  }
  for (int i = 0; i < M; ++i) {
    MembraneState& s = mem_[set.members[i]];
    const int o = set.start[i], nb = s.m.nb();
    s.m.X = set.X.middleRows(o, nb);
    s.X_n = set.X_n.middleRows(o, nb);
    s.U = set.U.middleRows(o, nb);
    s.last = set.work.results[i];
    s.U_revision = fluid_->revision();  // converged: U = u^{n+1}(X^{n+1}) (to O(|g|^2) if linearised), the next U^n(X^n)
    s.iterations += s.last.iterations;
    s.interpolations += s.last.interpolations;
    ++s.updates;
  }
}

}  // namespace sphib
