#pragma once
// The contract every fluid method meets, so that the coupling, the runner and the cases work
// with any of them: EPSPH (fixed particles, eulerian.hpp), LPSPH (moving particles,
// lagrangian.hpp) and ISPH (moving particles with a free surface, isph.hpp), all on the projection
// core (projection_core.hpp), and weakly compressible SPH (wcsph.hpp).
//
// A FluidSolver advances the velocity of N particles by one time step under an external force
// per unit volume, and shows their positions, volumes, velocity, pressure and its kernel.
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kernels/cubic_spline.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/common/params.hpp"
#include "fluid/common/profile.hpp"

namespace sphib {

// A discrete stream function of the velocity: u = U + (d psi/dy, -d psi/dx), with psi at the
// particles and U a uniform flow (nonzero only on doubly periodic domains, where a mean flow has no
// periodic stream function). See EulerianFluid::stream_function.
struct StreamFunction {
  const Vec* psi = nullptr;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
};

// Named arrays of doubles: a solver's state for checkpoints.
using NamedArrays = std::vector<std::pair<std::string, Eigen::MatrixXd>>;

// Refuses (std::invalid_argument naming the scene key) a value every method needs positive and
// finite: fluid.rho, fluid.mu, time.dt, kernel.h_over_dx; `positive_param` is the same test for one.
void positive_param(double v, const char* key);
void check_common_params(const FluidParams& p);

// The array `name` of a checkpointed state, which must be rows x cols (std::runtime_error otherwise).
const Eigen::MatrixXd& state_entry(const NamedArrays& state, const std::string& name, Eigen::Index rows,
                                   Eigen::Index cols);

// The contract. What every method has as data (parameters, lattice, kernel, positions, volumes,
// velocity, time, step count, particle mass) the base holds and shows through plain accessors; the
// method writes it. The physics is virtual: seven functions every method provides (step,
// set_velocity, p, phi, max_abs_divergence, state, restore) and four optional capabilities (the
// markers' stream function, a free surface, wall forces of its own, a variable viscosity) that a
// method without them leaves alone. Timing and reporting go to the Profiler (fluid/common/profile.hpp) the
// run loop hands over at construction.
class FluidSolver {
 public:
  virtual ~FluidSolver();
  FluidSolver(const FluidSolver&) = delete;
  FluidSolver& operator=(const FluidSolver&) = delete;

  // --- the physics every method provides ---------------------------------------------------------
  // One step from t_n to t_{n+1}; F is the external force per unit volume at the particles (N x 2).
  // A breakdown of the method (not a bug) throws std::runtime_error saying what and where.
  virtual void step(const Mat2& F) = 0;
  virtual void set_velocity(const Mat2& u0) = 0;  // initial condition
  virtual const Vec& p() const = 0;         // pressure (projection methods: p^{n-1/2}, zero mean)
  virtual const Vec& phi() const = 0;       // projection methods: phi^n; WCSPH: density rho
  virtual double max_abs_divergence() const = 0;  // max_i |(div u)_i|, Eq. (30)
  // Everything that determines the following steps (for checkpoints), and its restoration into a
  // solver built from the same parameters.
  virtual NamedArrays state() const = 0;
  virtual void restore(const NamedArrays& state) = 0;

  // --- optional capabilities -----------------------------------------------------------------------
  // The stream function of u^n, for marker velocities that are divergence-free between particles
  // (coupling/interpolate.hpp); a method with one sets has_stream_function_, the others return
  // psi = nullptr.
  virtual StreamFunction stream_function() const { return {}; }
  // Free surfaces (free_surface.hpp): the particles the last surface detection marked (1) or not
  // (0); nullptr for a method or scene without a free surface.
  virtual const std::vector<char>* surface() const { return nullptr; }
  // The pressure integral over each wall, int_Gamma p dGamma (loads.hpp; A Eqs. 31-32), NaN for a
  // side without a wall. Default: the Shepard interpolation of p() at the wall lines (methods with
  // image walls); methods with wall particles of their own pressure sum those (A Eq. 32).
  virtual WallForces wall_forces() const;
  // A viscosity that varies in space, mu_i = mu m_i (a viscosity contrast between the fluid inside
  // and outside membranes: coupling/viscosity_contrast.hpp): m at the particles at[0..n), the others
  // keeping theirs (every m is 1 at first), m > 0. Only methods that set variable_viscosity_
  // (EPSPH: fluid/eulerian/variable_viscosity.hpp); the others throw std::invalid_argument.
  virtual void set_viscosity(const int* at, const double* m, int n);

  // --- the data every method has (read only) -----------------------------------------------------
  const FluidParams& params() const { return prm_; }
  // the lattice of the domain (nx, ny, dx, dy); its sites are the particles unless they move or a
  // free surface fills only part of it
  const Lattice& lattice() const { return lat_; }
  const CubicSplineKernel& kernel() const { return W_; }
  bool particles_move() const { return moves_; }
  const Mat2& x() const { return moves_ ? x_ : lat_.x; }  // current particle positions, N x 2
  const Vec& volumes() const { return V_; }  // V_j = m_j / rho_j
  const Mat2& u() const { return u_; }       // u^n
  double time() const { return t_; }
  long steps() const { return n_; }
  double kinetic_energy() const;  // sum_i m |u_i|^2 / 2 (the same bits for any thread count)
  double max_speed() const;       // max_i |u_i| (the same bits for any thread count)
  static double max_abs(const Vec& d);  // max_i |d_i| (by the threads on a large lattice; exact)
  bool has_stream_function() const { return has_stream_function_; }
  bool supports_variable_viscosity() const { return variable_viscosity_; }
  // Its phases, set-up timings, report and floor (fluid/common/profile.hpp).
  Profiler& profiler() const { return *profiler_; }

  int size() const { return static_cast<int>(x().rows()); }
  double h() const { return W_.h; }
  double nu() const { return prm_.mu / prm_.rho; }
  // Changes with every change of the state (step, set_velocity, restore): callers that keep
  // quantities derived from u or x (the coupling's u^n(X^n)) check it before reusing them.
  long revision() const { return revision_; }

 protected:
  // The lattice of params.domain and the kernel of h = h_over_dx (dx + dy) / 2; `profiler` the run
  // loop's (nullptr: the method keeps one of its own).
  FluidSolver(const FluidParams& params, bool particles_move, Profiler* profiler);

  FluidParams prm_;
  Lattice lat_;
  CubicSplineKernel W_;
  Mat2 x_;  // positions of moving particles (fixed ones are the lattice's sites)
  Vec V_;
  Mat2 u_;
  double t_ = 0;
  long n_ = 0;
  double mass_ = 0;  // of every particle
  long revision_ = 0;
  bool has_stream_function_ = false, variable_viscosity_ = false;

 private:
  bool moves_;
  std::unique_ptr<Profiler> own_profiler_;
  Profiler* profiler_;
};

}  // namespace sphib
