#pragma once
// A fluid's parameters, as a program sets them (public): the method, the domain and lattice, the
// fluid's properties, the step, the solvers, and each method's own options, every closed set of
// choices an enum. The scene file names the same choices in words (io/scene.cpp reads them through
// the tables below, so a word and its enum are written once).
#include <stdexcept>
#include <string>

#include "fluid/common/lattice.hpp"

namespace sphib {

// A refused set-up: the scene key to blame and what is wrong.
struct ParamProblem {
  std::string key, what;
};

// A choice's name in scene files and messages.
template <class E>
struct EnumName {
  E value;
  const char* name;
};
template <class E, std::size_t N>
const char* enum_name(E v, const EnumName<E> (&table)[N]) {
  for (const auto& e : table)
    if (e.value == v) return e.name;
  return "?";
}
// The choice a name names in `table`; throws std::invalid_argument listing the names otherwise.
template <class E, std::size_t N>
E enum_value(const std::string& name, const EnumName<E> (&table)[N]) {
  std::string all;
  for (const auto& e : table) {
    if (name == e.name) return e.value;
    all += (all.empty() ? "" : " | ") + std::string(e.name);
  }
  throw std::invalid_argument("\"" + name + "\" is not allowed (allowed: " + all + ")");
}

// eulerian: EPSPH, fixed particles (eulerian.hpp); lagrangian: LPSPH, moving particles
// (lagrangian.hpp); wcsph: weakly compressible SPH (wcsph.hpp); isph: incompressible SPH with a free
// surface (isph.hpp).
enum class FluidMethod { Eulerian, Lagrangian, Wcsph, Isph };
inline constexpr EnumName<FluidMethod> kFluidMethods[] = {{FluidMethod::Eulerian, "eulerian"},
                                                          {FluidMethod::Lagrangian, "lagrangian"},
                                                          {FluidMethod::Wcsph, "wcsph"},
                                                          {FluidMethod::Isph, "isph"}};
inline const char* to_string(FluidMethod m) { return enum_name(m, kFluidMethods); }

// Fft: the periodic-lattice Poisson solver of fluid/algebra/fft_poisson.hpp (EPSPH only; built there, not by
// factorize()). PcgCholmod, PcgFft: conjugate gradients for a matrix that changes every step (moving
// particles), preconditioned by a CHOLMOD factorisation of an earlier step's matrix or by the FFT
// solver of the fixed lattice (lagged_pcg in linear_solver.hpp; made by fluid/algebra/solver_policy.hpp).
enum class SolverKind { Auto, CholmodSupernodal, CholmodSimplicial, Umfpack, Pcg, Fft, PcgCholmod, PcgFft };

// LPSPH (Section 3.1): particles move with Eq. (37); neighbours, images, operators and
// factorisations are rebuilt every step.
struct LagrangianParams {
  int reinit_every = 0;          // > 0: put the particles back on the lattice every so many steps (Fig. 9 C-D)
  double min_kernel_sum = 0.5;   // breakdown: a particle whose sum_j V_j W_ij falls below this stops the run
};

// WCSPH's equation of state: Morris, p = c^2 rho; Tait, p = rho0 c^2 / gamma ((rho/rho0)^gamma - 1).
enum class Eos { Morris, Tait };
inline constexpr EnumName<Eos> kEos[] = {{Eos::Morris, "morris"}, {Eos::Tait, "tait"}};
inline const char* to_string(Eos v) { return enum_name(v, kEos); }
// WCSPH's walls: Morris fixed virtual particles, or the Lennard-Jones repulsion of Coelho et al. (Eq. 20).
enum class WcsphWalls { Virtual, LennardJones };
inline constexpr EnumName<WcsphWalls> kWcsphWalls[] = {{WcsphWalls::Virtual, "virtual"},
                                                       {WcsphWalls::LennardJones, "lennard_jones"}};
inline const char* to_string(WcsphWalls v) { return enum_name(v, kWcsphWalls); }
// WCSPH's time integration: leapfrog (V Eq. 22, summation density) or the predictor-corrector of
// Afanasiev et al. (A Eqs. 19-21, continuity density A Eqs. 2, 14).
enum class Integrator { Leapfrog, PredictorCorrector };
inline constexpr EnumName<Integrator> kIntegrators[] = {{Integrator::Leapfrog, "leapfrog"},
                                                        {Integrator::PredictorCorrector, "predictor_corrector"}};
inline const char* to_string(Integrator v) { return enum_name(v, kIntegrators); }
// The pressure of WCSPH's wall particles (loads.hpp, wall_particle_pressure): the equation of state at
// rest, A Eq. (30), or A Eq. (30) normalised with the hydrostatic term.
enum class WallPressure { Rest, Eq30, Extrapolated };
inline constexpr EnumName<WallPressure> kWallPressures[] = {
    {WallPressure::Rest, "rest"}, {WallPressure::Eq30, "eq30"}, {WallPressure::Extrapolated, "extrapolated"}};
inline const char* to_string(WallPressure v) { return enum_name(v, kWallPressures); }

// Weakly compressible SPH (Morris et al. 1997; Vukcevic et al. 2012; Coelho et al.).
struct WcsphParams {
  Eos eos = Eos::Morris;
  double c = 0.0;                // speed of sound (0: chosen from the expected velocity scale, see wcsph.hpp)
  double gamma = 7.0;            // Tait exponent
  double xsph = 0.0;             // XSPH epsilon (0: off)
  WcsphWalls walls = WcsphWalls::Virtual;
  double u_scale = 1.0;          // expected maximum speed, for c when c = 0
  // Classic SPH of Afanasiev et al. (2011) ["A"] (free surfaces; wcsph.hpp):
  Integrator integrator = Integrator::Leapfrog;
  double alpha = 0.0;                   // artificial viscosity of Monaghan (1992) (0: off)
  int smooth_every = 0;                 // density smoothing A Eq. (29) every so many steps (0: off)
  WallPressure wall_pressure = WallPressure::Rest;
  double delta = 0.0;  // delta-SPH density diffusion (Antuono et al. 2010, 2012; wcsph.hpp), 0: off (0.1: theirs)
};

// ISPH's viscous predictor: explicit (A Eq. 22) or Crank-Nicolson (Eq. 28 of the projection core).
enum class IsphViscous { Explicit, CrankNicolson };
inline constexpr EnumName<IsphViscous> kIsphViscous[] = {{IsphViscous::Explicit, "explicit"},
                                                         {IsphViscous::CrankNicolson, "crank_nicolson"}};
inline const char* to_string(IsphViscous v) { return enum_name(v, kIsphViscous); }
// ISPH's operators: isph.hpp's consistent scheme, or those of Afanasiev et al. as they were (with the
// Lennard-Jones push of the walls).
enum class IsphScheme { Consistent, Paper };
inline constexpr EnumName<IsphScheme> kIsphSchemes[] = {{IsphScheme::Consistent, "consistent"},
                                                        {IsphScheme::Paper, "paper"}};
inline const char* to_string(IsphScheme v) { return enum_name(v, kIsphSchemes); }
// Particle shifting after each step (shifting.hpp): Fickian (Lind et al. 2012, with the free-surface
// correction), Xu et al. (2009) or none (A Eq. 25 alone); Auto: Fickian with the consistent scheme,
// none with the paper's.
enum class Shifting { Auto, Fickian, Xu, None };
inline constexpr EnumName<Shifting> kShiftings[] = {
    {Shifting::Auto, "auto"}, {Shifting::Fickian, "fickian"}, {Shifting::Xu, "xu"}, {Shifting::None, "none"}};
inline const char* to_string(Shifting v) { return enum_name(v, kShiftings); }

// ISPH with a free surface (Afanasiev, Makarchuk & Popov 2011, Sections 3.4-3.6; isph.hpp).
struct IsphParams {
  IsphViscous viscous = IsphViscous::Explicit;
  // The Poisson CG (solver_policy.hpp, lagged_pcg): |r| <= poisson_rtol |b|, and a new preconditioner
  // factorisation after a solve that needed more than poisson_refresh iterations (isph.cpp, make_solvers).
  double poisson_rtol = 1e-8;
  int poisson_refresh = 8;
  IsphScheme scheme = IsphScheme::Consistent;
  Shifting shifting = Shifting::Auto;
  double shifting_A = 2.0;  // Fickian: D = A h |u| dt (Lind et al. Eq. 24)
};

// A dam break's gate (walls.hpp, append_gate; ISPH and WCSPH): a vertical plate of wall particles with its face on
// the line x = gate.x, the fluid on its low side, lifted at a constant speed from t = start. Off unless
// a scene has [gate].
struct GateParams {
  bool on = false;
  double x = 0;      // the plate's face, m
  double speed = 0;  // lift speed, m/s
  double start = 0;  // when the lift begins, s
  // How far the plate has risen at time t.
  double lift(double t) const { return on && t > start ? speed * (t - start) : 0.0; }
  // Its velocity at time t.
  double velocity(double t) const { return on && t > start ? speed : 0.0; }
};

// Where the fluid is at t = 0 (free surfaces: free_surface.hpp).
struct FluidRegion {
  enum class Shape { Domain, Block, Circle };
  enum class Arrangement { Lattice, Rings };
  Shape shape = Shape::Domain;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;            // Block
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // Circle
  double radius = 0;                                 // Circle
  // Lattice: the sites of Eq. (68) inside the region. Rings (circles): a particle at the centre and
  // rings k = 1..n of 6k particles at radius k dx, n = round(radius/dx - 1/2) (1 + 3n(n+1)
  // particles: A Table 3's 721 ... 7651 are n = 15 ... 50).
  Arrangement arrangement = Arrangement::Lattice;
};

// Free-surface detection: A Eq. (26) (Divergence; Lee et al. 2008), Dilts' algorithm (Dilts 2000) or
// none; Auto: the paper's choice for the method (A Section 3.5: Dilts for SPH, Eq. 26 for ISPH), none
// without a free surface (free_surface.hpp, detection_for).
enum class SurfaceDetection { Auto, None, Dilts, Divergence };
inline constexpr EnumName<SurfaceDetection> kSurfaceDetections[] = {{SurfaceDetection::Auto, "auto"},
                                                                    {SurfaceDetection::Dilts, "dilts"},
                                                                    {SurfaceDetection::Divergence, "divergence"},
                                                                    {SurfaceDetection::None, "none"}};
inline const char* to_string(SurfaceDetection v) { return enum_name(v, kSurfaceDetections); }

struct FreeSurfaceParams {
  FluidRegion fill;
  SurfaceDetection detection = SurfaceDetection::Auto;
  double beta = 0.75;         // A Eq. (26): free surface where div r < 2 beta (A's best: 0.75 with h/dx = 1.1)
  double dilts_radius = 1.0;  // Dilts: each particle's circle has radius dilts_radius h
};

// The Poisson operator of the projection (Eq. 32). Exact: D G, the divergence of the gradient the
// projection applies (Eq. 34), so that D u^{n+1} = 0 to solver precision; its grid-scale null
// modes are fixed by fluid/algebra/gauge.hpp. Approximate: the Morris Laplacian L of the paper (Eq. 31),
// which leaves D u^{n+1} = (dt/rho)(L - D G) phi, largest where the pressure jumps. Auto: exact for
// EPSPH, approximate for LPSPH (which has only that).
enum class Projection { Auto, Exact, Approximate };

struct FluidParams {
  FluidMethod method = FluidMethod::Eulerian;
  Domain domain;
  int nx = 32, ny = 32;
  double h_over_dx = 1.2;  // h = h_over_dx * (dx + dy) / 2
  double rho = 1.0, mu = 1.0;
  double dt = 1e-3;
  bool convection = true;  // false: Stokes flow, the convection operator is not even assembled
  Projection projection = Projection::Auto;
  SolverKind cn_solver = SolverKind::Auto, poisson_solver = SolverKind::Auto;
  // A viscosity contrast's Crank-Nicolson CG (fluid/eulerian/variable_viscosity.hpp): |r| <= viscosity_rtol |b|
  double viscosity_rtol = 1e-8;  // (docs/viscosity_contrast.md: its effect on results, against 1e-10)
  LagrangianParams lagrangian;
  WcsphParams wcsph;
  IsphParams isph;
  GateParams gate;
  // Free surfaces (free_surface.hpp; methods for which supports_free_surface holds): the fluid's
  // initial region and surface detection, and gravity, an acceleration the method applies itself
  // (it sets the hydrostatic initial state, A Eqs. 27-28).
  FreeSurfaceParams free_surface;
  Eigen::Vector2d gravity = Eigen::Vector2d::Zero();
};

}  // namespace sphib
