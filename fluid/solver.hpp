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

#include "fluid/free_surface.hpp"
#include "fluid/kernel.hpp"
#include "fluid/lattice.hpp"
#include "fluid/loads.hpp"
#include "fluid/linear_solver.hpp"
#include "fluid/profile.hpp"

namespace sphib {

// LPSPH (Section 3.1): particles move with Eq. (37); neighbours, images, operators and
// factorisations are rebuilt every step.
struct LagrangianParams {
  int reinit_every = 0;          // > 0: put the particles back on the lattice every so many steps (Fig. 9 C-D)
  double min_kernel_sum = 0.5;   // breakdown: a particle whose sum_j V_j W_ij falls below this stops the run
};

// Weakly compressible SPH (Morris et al. 1997; Vukcevic et al. 2012; Coelho et al.).
struct WcsphParams {
  std::string eos = "morris";    // morris: p = c^2 rho; tait: p = rho0 c^2 / gamma ((rho/rho0)^gamma - 1)
  double c = 0.0;                // speed of sound (0: chosen from the expected velocity scale, see wcsph.hpp)
  double gamma = 7.0;            // Tait exponent
  double xsph = 0.0;             // XSPH epsilon (0: off)
  std::string walls = "virtual"; // virtual (Morris fixed wall particles) | lennard_jones (Coelho Eq. 20)
  double u_scale = 1.0;          // expected maximum speed, for c when c = 0
  // Classic SPH of Afanasiev et al. (2011) ["A"] (free surfaces; wcsph.hpp):
  std::string integrator = "leapfrog";  // leapfrog (V Eq. 22, summation density) | predictor_corrector (A Eqs. 19-21, continuity density A Eqs. 2, 14)
  double alpha = 0.0;                   // artificial viscosity of Monaghan (1992) (0: off)
  int smooth_every = 0;                 // density smoothing A Eq. (29) every so many steps (0: off)
  std::string wall_pressure = "rest";   // rest (p(rho0)) | eq30 (A Eq. 30) | extrapolated (A Eq. 30 normalised + hydrostatic term)
  double delta = 0.0;  // delta-SPH density diffusion (Antuono et al. 2010, 2012; wcsph.hpp), 0: off (0.1: theirs)
};

// ISPH with a free surface (Afanasiev, Makarchuk & Popov 2011, Sections 3.4-3.6; isph.hpp).
struct IsphParams {
  std::string viscous = "explicit";  // explicit (A Eq. 22) | crank_nicolson (Eq. 28 of the projection core)
  // The Poisson CG (solver_policy.hpp, lagged_pcg): |r| <= poisson_rtol |b|, and a new preconditioner
  // factorisation after a solve that needed more than poisson_refresh iterations (isph.cpp, make_solvers).
  double poisson_rtol = 1e-8;
  int poisson_refresh = 8;
  // consistent (the default) | paper: the operators of isph.hpp's consistent scheme, or those of
  // Afanasiev et al. as they were (with the Lennard-Jones push of the walls).
  std::string scheme = "consistent";
  // Particle shifting after each step (shifting.hpp): fickian (Lind et al. 2012, with the free-surface
  // correction), xu (Xu et al. 2009) or none (A Eq. 25 alone); auto: fickian with the consistent
  // scheme, none with the paper's.
  std::string shifting = "auto";
  double shifting_A = 2.0;  // Fickian: D = A h |u| dt (Lind et al. Eq. 24)
};

// The Poisson operator of the projection (Eq. 32). Exact: D G, the divergence of the gradient the
// projection applies (Eq. 34), so that D u^{n+1} = 0 to solver precision; its grid-scale null
// modes are fixed by fluid/gauge.hpp. Approximate: the Morris Laplacian L of the paper (Eq. 31),
// which leaves D u^{n+1} = (dt/rho)(L - D G) phi, largest where the pressure jumps. Auto: exact for
// EPSPH, approximate for LPSPH (which has only that).
enum class Projection { Auto, Exact, Approximate };

struct FluidParams {
  std::string method = "eulerian";  // eulerian (EPSPH) | lagrangian (LPSPH) | wcsph | isph
  Domain domain;
  int nx = 32, ny = 32;
  double h_over_dx = 1.2;  // h = h_over_dx * (dx + dy) / 2
  double rho = 1.0, mu = 1.0;
  double dt = 1e-3;
  bool convection = true;  // false: Stokes flow, the convection operator is not even assembled
  Projection projection = Projection::Auto;
  SolverKind cn_solver = SolverKind::Auto, poisson_solver = SolverKind::Auto;
  LagrangianParams lagrangian;
  WcsphParams wcsph;
  IsphParams isph;
  // Free surfaces (free_surface.hpp; methods for which supports_free_surface holds): the fluid's
  // initial region and surface detection, and gravity, an acceleration the method applies itself
  // (it sets the hydrostatic initial state, A Eqs. 27-28).
  FreeSurfaceParams free_surface;
  Eigen::Vector2d gravity = Eigen::Vector2d::Zero();
};

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
