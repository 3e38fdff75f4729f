#pragma once
// The immersed-boundary simulation: a Fluid, its Membranes and the coupling between them.
// One IB step (see step()): force from the spline of X^n -> spread with h* -> PMIII -> markers.
#include <functional>
#include <vector>

#include <memory>
#include <optional>

#include "coupling/params.hpp"
#include "fluid/core/solver.hpp"
#include "membrane/force.hpp"

namespace sphib {

class AreaKeeper;         // membrane/geometry.hpp
class CellGrid;           // fluid/common/neighbours.hpp
class ContactForce;       // coupling/contact.hpp
class StiffForceFilter;   // coupling/stiff_force.hpp
class ViscosityContrast;  // coupling/viscosity_contrast.hpp

struct MembraneState {
  MembraneState(const MembraneSetup& s);
  MembraneState(MembraneState&&) noexcept;
  MembraneState& operator=(MembraneState&&) noexcept;
  ~MembraneState();
  Membrane m;
  double h_star;
  bool fixed;
  CubicSplineKernel W_star;
  MembraneForce force;   // f, T and the energy by the membrane's law (membrane/force.hpp)
  std::unique_ptr<StiffForceFilter> filter;  // semi_implicit: f~, the force spread (stiff_force.hpp)
  Mat2 f_tilde;
  Mat2 f, U_n, U, X_n;  // force density, u^n(X^n), u^{n+1}(X^{n+1}), workspace
  Mat2 U_prev;          // u^{n-1}(X^{n-1}): the marker predictor's extrapolation
  bool U_n_known = false, U_prev_known = false;
  long U_revision = -1;  // U = u(X) of the fluid at this revision, at the current markers (-1: not known)
  Vec T;                // tension at the markers
  std::unique_ptr<AreaKeeper> keeper;  // the area constraint (MarkerUpdateParams::keep_area), or null
  MarkerUpdateResult last;
  long iterations = 0, updates = 0;  // fixed-point iterations (Eq. 59) and marker updates so far
  long interpolations = 0;           // marker velocity interpolations in those updates
};

class Simulation {
 public:
  explicit Simulation(const SimulationParams& params);
  ~Simulation();

  void step();  // one IB time step, t_n -> t_{n+1}

  FluidSolver& fluid() { return *fluid_; }
  const FluidSolver& fluid() const { return *fluid_; }
  const std::vector<MembraneState>& membranes() const { return mem_; }
  const Mat2& force() const { return F_; }  // F^n of the last step (body + membranes), N x 2
  void set_markers(size_t k, const Mat2& X);  // restart: markers of membrane k (same Nb)
  // Restart: U^n(X^n) of the step that made the checkpoint's markers, the next step's U^{n-1}
  // (the marker predictor's history; without it the first step uses Eq. 58), and U_next, the
  // U^{n+1}(X^{n+1}) that step left (next_marker_velocity), the next step's U^n(X^n) (without it,
  // interpolated: a linearised one differs in the last bits).
  void set_marker_history(size_t k, const Mat2& U_n, const Mat2* U_next = nullptr);
  // U^{n+1}(X^{n+1}) of membrane k as the last marker update left it for the next step, or nullptr.
  const Mat2* next_marker_velocity(size_t k) const;
  // Restart: the stiff-force filter's history of membrane k (StiffForceFilter::state; empty when it
  // has none or the membrane is not semi-implicit) and its restoration.
  Eigen::MatrixXd stiff_filter_state(size_t k) const;
  void set_stiff_filter_state(size_t k, const Eigen::MatrixXd& s);
  // f and T of every membrane at its current markers (Eqs. 47-50), with the contact force added to f
  // when it is on, as membranes()[k].f and .T show them at all times: the constructor, set_markers
  // and the end of step() call it, and step() spreads the f it left (f^n at X^n).
  void update_membrane_forces();
  // The contact force (coupling/contact.hpp) of the last update_membrane_forces(), or nullptr when off.
  const ContactForce* contact() const { return contact_.get(); }
  double time() const { return fluid_->time(); }
  long steps() const { return fluid_->steps(); }
  Profile& profile() { return prof_; }  // coupling phases; the fluid's are in fluid_profiler()
  // The fluid method's phases, set-up timings, report and floor (fluid/common/profile.hpp): the
  // simulation owns it and hands it to the method it makes.
  const Profiler& fluid_profiler() const { return fluid_prof_; }
  // The viscosity contrast of the membranes (their indicators and m), or nullptr when every
  // viscosity_ratio is 1.
  const ViscosityContrast* viscosity_contrast() const { return contrast_.get(); }
  MarkerInterpolation interpolation() const { return interp_; }  // as resolved (never Auto)
  // The smoothing length of the marker interpolation in use: h (SPH kernel), the lattice spacing
  // (B-splines) or the free membranes' h* (the spreading kernel).
  double interpolation_length() const;
  // The marker velocity of the fluid's current state at the points X, by the interpolation in use;
  // with dU non-null also its gradient at X where the interpolation has one (returns whether it has).
  bool marker_velocity(const Mat2& X, Mat2& U, Jacobians* dU = nullptr) const;
  // The coupling's floor: the bare kernels one step of it cannot avoid, each timed alone on the
  // current state, best of `reps` (as Profiler::floor_seconds for the fluid): the membrane
  // forces, the stiff-force filter (semi-implicit membranes), one spreading, the markers' stream
  // function solve (divergence-free interpolations) and
  // one marker-velocity interpolation (with its gradient where the marker update linearises) per
  // free membrane. 0 without membranes.
  double coupling_floor_seconds(int reps = 20) const;

 private:
  // The named parts of step():
  void external_force(double t);   // F = the body force at t
  void marker_velocities_now();    // U^n(X^n) of every free membrane
  void stiff_forces();             // f~ of the semi-implicit membranes (coupling/stiff_force.hpp)
  void spread_membrane_forces();   // F += S f (Eq. 53), f~ where semi-implicit
  void move_markers();             // the trapezoidal fixed point (Eqs. 56-60)
  void elastic_forces();           // f, T by each membrane's law (Eqs. 47-50)
  void contact_forces();           // f += the contact force (coupling/contact.hpp)
  void viscosity_now();            // mu^n from the indicators of X^n (a viscosity contrast)

  SimulationParams prm_;
  Profiler fluid_prof_;  // (before fluid_: outlives it)
  std::unique_ptr<FluidSolver> fluid_;
  std::vector<MembraneState> mem_;
  std::unique_ptr<CellGrid> grid_;  // lattice-spaced cells over the fixed particles: marker neighbourhoods in O(Nb)
  MarkerInterpolation interp_ = MarkerInterpolation::Sph;
  std::optional<CubicSplineKernel> W_interp_;  // SpreadingKernel: the free membranes' kernel of radius h*
  Mat2 F_body_, F_;
  std::unique_ptr<ContactForce> contact_;  // nullptr: off
  // The passes over markers take many membranes as one set, their markers concatenated (membrane
  // members[i]'s rows [start[i], start[i+1])): one call over all of them.
  struct MarkerSet {
    std::vector<int> members, start;
    Mat2 X, P;  // markers; point forces f ds (spreading) or contact force densities
  };
  MarkerSet all_;              // every membrane (contact, spreading)
  std::vector<double> ds_;     // every membrane's rest spacing
  std::vector<std::pair<int, int>> spread_runs_;  // runs [a, b) of membranes with the same h*: one pass each
  struct FreeSet;  // free membranes with the same predictor (the marker update; simulation.cpp)
  std::unique_ptr<FreeSet> free_;
  void spread_run(int a, int b, Mat2& F);  // F += the spreading of membranes [a, b) (one h*), Eq. (53)
  void advance_set(FreeSet& set, bool extrapolate);  // the marker update of a set (Eqs. 56-60)
  std::unique_ptr<ViscosityContrast> contrast_;  // when some viscosity_ratio differs from 1
  std::vector<const Mat2*> X_now_;                // its markers
  Profile prof_;
  int k_force_, k_spread_, k_interp_, k_markers_, k_stiff_ = -1, k_contact_ = -1, k_visc_ = -1;
};

}  // namespace sphib
