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

#include "fluid/kernel.hpp"
#include "fluid/lattice.hpp"
#include "fluid/params.hpp"
#include "fluid/profile.hpp"

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

class FluidSolver {
 public:
  virtual ~FluidSolver() = default;

  // One step from t_n to t_{n+1}; F is the external force per unit volume at the particles (N x 2).
  // A breakdown of the method (not a bug) throws std::runtime_error saying what and where.
  virtual void step(const Mat2& F) = 0;
  virtual void set_velocity(const Mat2& u0) = 0;  // initial condition

  virtual const FluidParams& params() const = 0;
  virtual const Lattice& lattice() const = 0;  // the lattice of the domain (nx, ny, dx, dy); its sites are the particles unless a free surface fills only part of it
  virtual const CubicSplineKernel& kernel() const = 0;
  virtual bool particles_move() const = 0;
  virtual const Mat2& x() const = 0;        // current particle positions, N x 2
  virtual const Vec& volumes() const = 0;   // V_j = m_j / rho_j
  virtual const Mat2& u() const = 0;        // u^n
  virtual const Vec& p() const = 0;         // pressure (projection methods: p^{n-1/2}, zero mean)
  virtual const Vec& phi() const = 0;       // projection methods: phi^n; WCSPH: density rho
  virtual double time() const = 0;
  virtual long steps() const = 0;
  virtual double kinetic_energy() const = 0;      // sum_i m_i |u_i|^2 / 2
  virtual double max_abs_divergence() const = 0;  // max_i |(div u)_i|, Eq. (30)
  // The stream function of u^n, for marker velocities that are divergence-free between particles
  // (coupling/interpolate.hpp); methods without one return psi = nullptr.
  virtual StreamFunction stream_function() const { return {}; }
  virtual bool has_stream_function() const { return false; }

  // Run-log lines (particles, images, neighbours, each linear system's factorisation) and
  // figures for the summary (name, value).
  virtual std::vector<std::string> describe() const = 0;
  virtual std::vector<std::pair<std::string, double>> figures() const = 0;
  virtual Profile& profile() const = 0;
  // The wall time of its steps so far: profile()'s phases of step(), not those made on demand
  // (the pressure for output, the markers' stream function for the coupling).
  virtual double step_seconds() const { return profile().total(); }
  virtual double setup_seconds(const std::string& what) const = 0;
  // What the method keeps for the whole run (`sphib check`'s memory estimate): the non-zeros of
  // its operator matrices and of its factors (with the matrices it keeps), its neighbour pairs.
  // None for a method that rebuilds them every step.
  struct Footprint {
    long operator_nonzeros = 0, factor_nonzeros = 0, pairs = 0;
  };
  virtual std::optional<Footprint> footprint() const { return std::nullopt; }
  // The floor of a step: the bare kernels it cannot avoid, each timed alone on the current fields,
  // best of `reps` (0: the method measures none).
  virtual double floor_seconds(int /*reps*/ = 20) const { return 0.0; }
  // The markers' stream function's bare solve (stream_function()), timed alone the same way: part
  // of the coupling's floor (Simulation::coupling_floor_seconds); 0 without one.
  virtual double stream_function_floor_seconds(int /*reps*/ = 20) const { return 0.0; }

  // Free surfaces (free_surface.hpp): the particles the last surface detection marked (1) or not
  // (0); nullptr for a method or scene without a free surface.
  virtual const std::vector<char>* surface() const { return nullptr; }
  // The pressure integral over each wall, int_Gamma p dGamma (loads.hpp; A Eqs. 31-32), NaN for a
  // side without a wall. Default: the Shepard interpolation of p() at the wall lines (methods with
  // image walls); methods with wall particles of their own pressure sum those (A Eq. 32).
  virtual WallForces wall_forces() const;

  // A viscosity that varies in space, mu_i = mu m_i (a viscosity contrast between the fluid inside
  // and outside membranes: coupling/viscosity_contrast.hpp): m at the particles at[0..n), the others
  // keeping theirs (every m is 1 at first), m > 0. Only methods for which supports_variable_viscosity
  // holds (EPSPH: fluid/variable_viscosity.hpp); the others throw std::invalid_argument.
  virtual bool supports_variable_viscosity() const { return false; }
  virtual void set_viscosity(const int* at, const double* m, int n);

  // Everything that determines the following steps (for checkpoints), and its restoration into a
  // solver built from the same parameters: every method has both.
  virtual NamedArrays state() const = 0;
  virtual void restore(const NamedArrays& state) = 0;

  int size() const { return static_cast<int>(x().rows()); }
  double h() const { return kernel().h; }
  double nu() const { return params().mu / params().rho; }
  // Changes with every change of the state (step, set_velocity, restore): callers that keep
  // quantities derived from u or x (the coupling's u^n(X^n)) check it before reusing them.
  long revision() const { return revision_; }

 protected:
  long revision_ = 0;
};

}  // namespace sphib
