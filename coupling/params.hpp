#pragma once
// An immersed-boundary simulation's parameters, as a program sets them (public): the fluid
// (fluid/common/params.hpp), the membranes and how each is coupled, the marker update, the contact force.
#include <functional>
#include <vector>

#include "fluid/common/params.hpp"
#include "membrane/membrane.hpp"

namespace sphib {

struct MembraneSetup {
  Membrane membrane;      // markers, reference state, material (law, moduli)
  double h_star = 0.05;   // spreading kernel's smoothing length h* (support 2h*)
  bool fixed = false;     // markers held in place (Section 5.2.1)
  bool semi_implicit = false;  // the stiff-force filter (coupling/stiff_force.hpp)
  // lambda = mu_in / mu of the fluid it encloses (a viscosity contrast: coupling/viscosity_contrast.hpp;
  // method "eulerian" only); 1: the same fluid inside and out
  double viscosity_ratio = 1.0;
  // the stiff-force filter predicts U^{n+1} with its model's measured residual (accurate steady
  // states at large steps; less stable on stiff stretching: coupling/stiff_force.hpp)
  bool stiff_residual = false;
};

// How markers get their velocity from the fluid (coupling/interpolate.hpp): divergence-free (the curl
// of the stream function interpolated by the SPH kernel, or by tensor cubic B-splines on the
// lattice: a closed membrane keeps its area) or the paper's normalised SPH interpolation, Eq. (63).
// SpreadingKernel: the divergence-free curl with the SPH kernel of the membranes' spreading radius h*
// (their MembraneSetup::h_star, which the free membranes must share) in place of the fluid's h: the
// interpolation as wide as the spreading (Eq. 53) at any h*, for studies that hold h* fixed.
// Auto: where the fluid method has a stream function (EPSPH), divergence-free, by B-splines when a
// membrane has bending (the kernel's curl carries a lattice-scale ripple that bending amplifies);
// SPH otherwise.
enum class MarkerInterpolation { Auto, DivergenceFree, BSpline, Sph, SpreadingKernel };

// The marker update, Eqs. (56)-(60) (coupling/marker_update.hpp says how).
struct MarkerUpdateParams {
  double eps = 1e-12;  // tolerance on max_k |g_k| (a length)
  int max_iter = 50;
  double max_move = 0;  // > 0: a marker moving farther in one step is a blow-up (the Simulation sets dx)
  bool extrapolate = true;  // predictor: AB2 extrapolation when U^{n-1} is known, else Eq. (58)
  bool linearise = true;    // linearised acceptance when the interpolation gives dU/dX (above)
  // The largest |g| the linearised acceptance takes, as a fraction of max_move (above: 1e-6 keeps
  // the neglected quadratic terms ~1e-6 of the linear ones whatever the flow).
  double linear_step = 1e-6;
  // true: the linearised step is a Newton step (I - dt/2 dU/dX)^{-1} g, not the fixed-point step g: its
  // linear residual is zero, so the acceptance needs only the step below linear_step (the neglected
  // term dt/4 |grad grad U| |step|^2); coupling/marker_update.hpp.
  bool newton = false;
  // true: every free membrane's U^{n+1} loses the least normal velocity that would change the area its
  // spline curve encloses over the trapezoidal step (membrane/geometry.hpp, AreaKeeper): each step then
  // keeps that area to the update's residual (coupling/marker_update.hpp). false: the velocities as
  // interpolated.
  bool keep_area = false;
};

// What one marker update did (per membrane: MembraneState::last).
struct MarkerUpdateResult {
  int iterations = 0;
  double residual = 0;      // max_k |g_k| at the accepted iterate (linearised: its first-order value, 0 after a Newton step)
  bool linearised = false;  // a marker was accepted by the linearised residual (its U^{n+1}(X^{n+1}) linearised)
  int interpolations = 0;   // marker velocity interpolations a marker went through (the most of any)
};

// dU/dX at each marker: dUx/dx, dUx/dy, dUy/dx, dUy/dy.
using Jacobians = Eigen::Matrix<double, Eigen::Dynamic, 4>;

// The short-range repulsion between membranes and off the walls (coupling/contact.hpp: the Morse
// potential's repulsive branch of Liu & Liu 2006, Fedosov et al. 2011).
struct ContactParams {
  double strength = 0.0;  // De (0: no contact force)
  double range = 0.0;     // r0: the force is zero at and beyond it
  double beta = 0.0;      // the potential's steepness (1/length); 0: 2/range
  bool walls = true;      // markers are pushed off the walls too
  bool on() const { return strength > 0.0; }
};

struct SimulationParams {
  FluidParams fluid;
  Eigen::Vector2d body_force = Eigen::Vector2d::Zero();  // per unit volume, constant in space and time
  // Optional body force field F(x, y, t) per unit volume; replaces body_force when set.
  std::function<Eigen::Vector2d(double, double, double)> body_force_field;
  // Optional initial velocity u0(x, y) (default: at rest).
  std::function<Eigen::Vector2d(double, double)> initial_velocity;
  std::vector<MembraneSetup> membranes;
  MarkerUpdateParams markers;
  MarkerInterpolation interpolation = MarkerInterpolation::Auto;
  // The short-range repulsion between membranes and off the walls (coupling/contact.hpp); off by
  // default (strength 0), and then no part of the step.
  ContactParams contact;
};

}  // namespace sphib
