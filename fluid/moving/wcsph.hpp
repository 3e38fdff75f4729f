#pragma once
// Weakly compressible SPH (WCSPH): the explicit baseline of Morris, Fox & Zhu (1997) as used by
// Vukcevic, Werner & Degiuli (2012) ["V"] and Coelho, Oliveira, Brasil & Maruzewski ["C"], so that
// users can see what the projection of EPSPH buys on the same scenes and diagnostics.
//
// Particles move. One step (V Eq. 22, drift-kick-drift leapfrog: positions at half steps,
// velocities at whole steps, ONE neighbour search and force evaluation per step):
//   x^{n+1/2} = x^n + dt/2 xsph(u^n)                                   V Eq. (22) 1st line, Eq. (21)
//   neighbours at x^{n+1/2}; rho_i = sum_j m W_ij (walls included)     V Eq. (11)
//   p_i = c^2 rho_i (Morris) or rho0 c^2/gamma ((rho_i/rho0)^gamma - 1) (Tait)   V Eq. (20), C Eqs. (3)-(4)
//   a_i = -sum_j m (p_i/rho_i^2 + p_j/rho_j^2) grad_i W_ij              C Eq. (17), V Eq. (12)
//         + sum_j m (mu_i + mu_j) / (rho_i rho_j) F_ij u_ij  + F_i / rho_i   (Morris viscosity, C Eq. 17)
//   u^{n+1} = u^n + dt a_i                                             V Eq. (22) 2nd line
//   x^{n+1} = x^{n+1/2} + dt/2 xsph(u^{n+1})                           V Eq. (22) 3rd line
// with F_ij = (1/r) dW/dr (kernels/cubic_spline.hpp) and xsph(u)_i = u_i - eps sum_j (m/rho_j) u_ij W_ij (V Eq. 21).
// The acceleration a^{n+1/2} is evaluated at x^{n+1/2} with the velocities u^n (the only ones at
// hand): second order for the pressure, first order in time for the viscous term.
// The XSPH sum of u^{n+1} uses the neighbours and densities of x^{n+1/2} (the only ones at hand);
// the next step's first half drift reuses it, so x^{n+3/2} = x^{n+1/2} + dt xsph(u^{n+1}).
// Consequently rho, p and the volumes shown after a step are those of x^{n+1/2}, half a step
// behind x(): their difference is O(dt |u| |grad rho|), far below the density variation itself.
//
// Masses: every particle carries m = rho0 / S with S = sum_j W(x_0 - x_j) over the infinite
// lattice of spacings dx, dy (Eq. 68), so that the summation density of the initial lattice is
// exactly rho0 (S dx dy - 1 is the kernel's quadrature error, reported by describe()).
//
// Walls (the domain's non-periodic sides): Morris virtual particles, i.e. the lattice of Eq. (68)
// continued beyond each wall for ceil(2h / spacing) rows (corner blocks included), fixed in place,
// with density rho0 and pressure p(rho0), carrying the wall's prescribed velocity (corner blocks:
// the mean of the two walls' velocities) in the viscous, XSPH and divergence sums. They give every
// fluid particle of the initial lattice a complete kernel support, so a fluid at rest is exactly at
// rest. In the viscous term they carry Morris's extrapolated velocity by default
// (WcsphOptions::morris_extrapolation): it continues a linear profile exactly, so V's Couette is
// exact at steady state; with the plain wall velocity V's Poiseuille errs by 8% instead of 0.2%.
// walls = "lennard_jones" adds the repulsive force of C Eq. (20) exerted by the innermost row of
// virtual particles (r0 = min(dx, dy), the initial fluid-wall particle distance, so it vanishes at
// rest; D = u_scale^2, "of the magnitude of the square of the maximum velocity"). C used it alone,
// with the continuity equation (C Eq. 18) for the density; with the summation density of V Eq. (11)
// a truncated kernel would read as a 28-36% density deficit in the first row (h = 1.3-2.2 dx), so
// the virtual rows stay.
//
// Speed of sound: wcsph.c, or when it is 0, c = 10 u_scale (the scaling of C Eq. 5: density
// variation ~ (u/c)^2 ~ 1%). The time step is the scene's; the constructor refuses a dt above the
// limit of C Eq. (19), min(0.25 h/c, 0.125 h^2/nu), and step() the force term 0.25 sqrt(h/|f|).
// The density variation max_i |rho_i/rho0 - 1| is monitored every step; above
// WcsphOptions::max_density_variation (10%; 25% with a free surface) the step throws
// std::runtime_error (a blow-up), and so
// does a particle that crosses a wall.
//
// Which EOS: with the symmetric pressure term a uniform pressure p0 does not cancel on a sheared or
// disordered particle set, so the Morris form (background pressure c^2 rho0) pushes sliding rows
// across each other once c is chosen for incompressibility; the Tait form has none. Measured:
// docs/validation/wcsph.md (bench/wcsph_comparison).
//
// Neighbours: a cell list over fluid and wall particles (cells at least 2h wide), rebuilt every
// step; each pair within 2h is found once (half stencil of cells) and every pair sum is
// accumulated on both particles (pair_search.hpp; the walls are walls.hpp's).
//
// Classic SPH with a free surface: Afanasiev, Makarchuk & Popov (2011) ["A"], Sections 3.4-3.7
// (wcsph_afanasiev.cpp), integrator = "predictor_corrector". The particles are the fluid region of
// free_surface.hpp (a block, a circle, the tank; sides may be open) with masses m = rho0 V (V the
// particle volume of the region's arrangement); the density follows the continuity equation,
// A Eqs. (2), (14), d rho_i/dt = sum_j m (u_i - u_j) . grad_i W_ij (walls with their velocity),
// from the hydrostatic density of A Eq. (28), rho* = rho0 (1 + rho0 |g| depth / B)^(1/gamma), with
// Tait's p = B ((rho/rho0)^gamma - 1), A Eq. (27), B = rho0 c^2 / gamma; wcsph.c = 0 with gravity
// takes A's B = 200 rho0 |g| H / gamma (c^2 = 200 |g| H, H the fluid's initial height). One step,
// A Eqs. (19)-(21), with ONE evaluation of the rates at r^n:
//   v^n = v^{n-1/2} + dt/2 a^{n-1},  rho^n = rho^{n-1/2} + dt/2 rhodot^{n-1}   A Eq. (19), predictor
//   neighbours at r^n; free-surface particles (Dilts or A Eq. 26) get p = 0, the others Tait's p
//   a^n = pressure + Morris viscosity (as above) + artificial viscosity + g + F/rho; rhodot^n
//   v^{n+1/2} = v^{n-1/2} + dt a^n,  rho^{n+1/2} = rho^{n-1/2} + dt rhodot^n      A Eq. (20), corrector
//   every wcsph.smooth_every steps rho^{n+1/2} <- sum_j m rho_j W_ij / sum_j m W_ij   A Eq. (29)
//   r^{n+1} = r^n + dt xsph(v^{n+1/2})                                          A Eq. (21)
// The first step kicks by dt/2 (v^{1/2} = v^0 + dt/2 a^0), the leapfrog's start. Its viscous
// stability is narrower than C Eq. (19)'s 0.125 h^2/nu, which the constructor still checks
// (docs/method/choices.md, "WCSPH: the viscous step"); the cases take half. After a step, u()
// is the next predictor v^{n+1}; p, rho and the volumes are those of the evaluation at r^n.
// delta-SPH (wcsph.delta > 0; Antuono, Colagrossi, Marrone & Molteni 2010, Comput. Phys. Commun.
// 181:532, Eq. 7 and Antuono, Colagrossi & Marrone 2012, Comput. Phys. Commun. 183:2570, Eqs. 5-6;
// Marrone et al. 2011, Comput. Methods Appl. Mech. Engrg. 200:1526, Eq. 3): a diffusion term in the
// continuity equation,
//   rhodot_i += delta h c sum_j V_j psi_ij . grad_i W_ij,
//   psi_ij = 2 (rho_j - rho_i) (x_j - x_i) / |x_j - x_i|^2 - (<grad rho>_i^L + <grad rho>_j^L),
// <grad rho>_i^L = L_i sum_j V_j (rho_j - rho_i) grad_i W_ij the renormalised density gradient, L_i the
// inverse of sum_j V_j (x_j - x_i) (x) grad_i W_ij, over the fluid particles only (the wall particles
// take no part: Antuono et al. 2012, Section 2). The second term makes the diffusion vanish on a
// linear density field, the hydrostatic one: without it the term of Molteni & Colagrossi (2009)
// pulls a column at rest (Antuono et al. 2012, Section 3). It damps the high-frequency pressure
// noise of the continuity density (what A Eq. 29's smoothing and the artificial viscosity were for).
// Artificial viscosity (Monaghan 1992, Annu. Rev. Astron. Astrophys. 30:543, Eq. 4.1 with beta = 0):
// Pi_ij = -alpha c h mu_ij / rho_ij, mu_ij = u_ij . x_ij / (r^2 + 0.01 h^2) when u_ij . x_ij < 0, added
// to the pressure term as -sum_j m Pi_ij grad_i W_ij (A: needed for stability in the dam break).
// Wall particles carry the pressure of wcsph.wall_pressure (loads.hpp: rest, A Eq. 30, or A Eq. 30
// normalised with a hydrostatic term) and the density of Tait's law at that pressure. With eq30 and
// extrapolated that pressure is at least Tait's at the wall particle's summation density over the
// wall particles and the fluid, sum_j m W_wj (walls.hpp's lattice: rho0 S dx dy ~ rho0 when the
// fluid sits on the lattice beside the wall, so a wetted wall gets nothing from it; more only when
// the fluid comes closer than the lattice spacing): a jet of free-surface particles (p = 0) carries
// no pressure of its own, and with A Eq. (30) alone it runs through the wall. (The continuity
// density of the dynamic boundary particles of Crespo et al. 2007, tried first, rises by the
// fluid's share of the kernel sum wherever a dry wall is wetted: a spurious 10x floor load.)
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kernels/cubic_spline.hpp"
#include "fluid/common/free_surface.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/common/loads.hpp"
#include "fluid/common/pair_search.hpp"
#include "fluid/common/profile.hpp"
#include "fluid/core/solver.hpp"
#include "fluid/common/walls.hpp"

namespace sphib {

// Choices of the C++ API only (not in scenes).
struct WcsphOptions {
  // Morris et al. (1997): a virtual particle B seen from fluid particle A carries
  // u_B = u_w - (d_B/d_A)(u_A - u_w) in the viscous term, i.e. u_AB = beta (u_A - u_w) with
  // beta = min(beta_max, 1 + d_B/d_A) (d: distances to the wall line, d_A floored at half a
  // spacing); corner blocks keep u_w. false: every virtual particle carries u_w.
  bool morris_extrapolation = true;
  double beta_max = INFINITY;  // Morris et al. cap beta at 1.5
  double max_density_variation = 0.10;  // blow-up threshold of |rho/rho0 - 1|
  // the same with a free surface, where a jet hitting a wall at speed u compresses the fluid by
  // (1 + gamma u / c)^(1/gamma) - 1 (the water hammer p = rho0 c u of A Eq. 27): 8% at u = c/4
  double max_density_variation_free_surface = 0.25;
  double lj_D = 0.0;                    // C Eq. (20) strength D (0: u_scale^2)
};

// Equation of state: V Eq. (20) / C Eq. (4) "morris" p = c^2 rho, or C Eq. (3) "tait".
inline double eos_pressure(Eos eos, double rho, double rho0, double c, double gamma) {
  if (eos == Eos::Morris) return c * c * rho;                                         // C Eq. (4)
  return rho0 * c * c / gamma * (std::pow(rho / rho0, gamma) - 1.0);                  // C Eq. (3)
}

// What is wrong with the free-surface and classic-SPH keys of a WCSPH scene (A: predictor-corrector,
// Tait), including free_surface_problem's, as (key, message); nothing if all is well.
std::optional<ParamProblem> wcsph_free_surface_problem(const FluidParams& params);

// The speed of sound the solver uses for these parameters (see the header comment).
double wcsph_sound_speed(const FluidParams& params);

// C Eq. (19) without the force term: min(0.25 h / c, 0.125 h^2 / nu).
double coelho_dt_limit(double h, double c, double nu);

class WcsphFluid final : public FluidSolver {
 public:
  // `profiler`: the run loop's (nullptr: its own).
  explicit WcsphFluid(const FluidParams& params, const WcsphOptions& options = {}, Profiler* profiler = nullptr);

  void step(const Mat2& F) override;  // F: force per unit volume at the particles; a_i gets F_i / rho_i
  void set_velocity(const Mat2& u0) override;

  // x(): x^n; volumes(): m / rho_i (at x^{n-1/2}, see above); u(): u^n
  const Vec& p() const override { return p_; }            // EOS pressure (absolute for Morris)
  const Vec& phi() const override { return rho_; }        // density rho_i
  double max_abs_divergence() const override;  // Eq. (30) form with m/rho_j, over the last neighbours
  // Checkpoints: x^n, u^n, the XSPH velocity, the positions of the last evaluation (x^{n-1/2}:
  // its neighbours and densities are rebuilt from them exactly), t_n, n and the density monitor.
  NamedArrays state() const override;
  void restore(const NamedArrays& state) override;

  // WCSPH specifics
  double sound_speed() const { return c_; }
  double rho0() const { return rho0_; }
  double mass() const { return m_; }
  double density_variation() const { return dvar_; }          // max_i |rho_i/rho0 - 1| of the last step
  double max_density_variation() const { return dvar_max_; }  // the same, maximum over the run
  const Mat2& wall_x() const { return walls_.x; }             // virtual particles, M x 2
  const Vec& wall_p() const { return p_w_; }                  // their pressure (wcsph.wall_pressure)
  double lattice_kernel_sum() const { return S_ * lat_.dx * lat_.dy; }  // S dx dy (1 for an exact quadrature)
  const std::vector<char>* surface() const override { return surface_on_ ? &surface_ : nullptr; }
  WallForces wall_forces() const override;  // A Eq. (32) over the wall particles, or by interpolation (rest)

 private:
  // Its report to the profiler: the run-log lines and the figures.
  std::vector<std::string> describe() const;
  std::vector<std::pair<std::string, double>> figures() const;
  void find_neighbours();     // pair lists at x_
  void summation_density();   // V Eq. (11), then the EOS
  void accelerations(const Mat2& F);  // a_ (and drho_ with the continuity equation)
  void xsph_velocity(const Mat2& u);  // V Eq. (21): u_hat_ from u
  void drift(double tau);     // x += tau u_hat, periodic wrap, walls checked
  void check_density();
  // Classic SPH with a free surface (wcsph_afanasiev.cpp)
  void init_afanasiev();                   // particles, masses, hydrostatic density (A Eq. 28)
  void evaluate(const Mat2& F);            // at x_ with u_, rho_: neighbours, surface, pressures, rates
  void pressures();                        // A Eq. (27), p = 0 on the free surface, wall particles
  void smooth_density(Vec& rho) const;     // A Eq. (29)
  void density_gradient();                 // delta-SPH: <grad rho>^L into grad_rho_
  void step_afanasiev(const Mat2& F);      // A Eqs. (19)-(21)
  NamedArrays state_afanasiev() const;
  Eigen::MatrixXd clock() const;                   // t, n, the density monitor (and A's first-step flag)
  void restore_clock(const NamedArrays& state);
  void restore_afanasiev(const NamedArrays& state);
  void wall_self_density();                // rho_ww_ of the wall particles
  bool place_gate(double t);               // the gate at time t (isph.hpp: the same rule); whether the walls changed

  WcsphOptions opt_;
  Eos eos_ = Eos::Morris;
  double c_ = 0, rho0_ = 0, m_ = 0, S_ = 0, p_wall_ = 0, dt_limit_ = 0, lj_D_ = 0, lj_r0_ = 0;
  bool lj_ = false;
  bool pc_ = false;          // the predictor-corrector of A with the continuity equation
  bool surface_on_ = false;  // a free surface is detected
  double dvar_limit_ = 0.1;  // the blow-up threshold in use
  int N_ = 0;                // particles
  double B_ = 0;             // Tait's B = rho0 c^2 / gamma
  WallPressure wall_pressure_ = WallPressure::Rest;

  VirtualWalls walls_;   // fixed Morris virtual particles (fluid/common/walls.hpp)
  PairSearch search_;    // cell list over the particles and the wall particles (fluid/common/pair_search.hpp)
  ParticlePairs pairs_;  // pairs closer than 2h at x_eval_, each once; j >= N: the wall particle j - N
  long nbrs_last_ = 0, nbrs_total_ = 0;  // neighbours summed over the fluid particles: last search, all

  Mat2 x_eval_, u_hat_, a_;  // x_eval_: positions of the last neighbour search (x^{n-1/2})
  Vec rho_, p_, pr_;  // pr_ = p / rho^2
  // walls: pressure, p/rho^2 and density of each wall particle (rest: p(rho0), rho0); A's walls:
  // the summation density of the wall particles among themselves, m (W(0) + sum_w' W_ww')
  Vec p_w_, pr_w_, rho_w_, work_w_, rho_ww_;
  // A's predictor-corrector: v^{n-1/2}, rho^{n-1/2}, rhodot, the next predicted density
  Mat2 v_half_;
  Vec rho_half_, drho_, rho_next_;
  Mat2 grad_rho_;  // delta-SPH: the renormalised density gradient of the evaluation
  bool started_ = false;
  SurfaceDetector detector_{SurfaceDetection::None, 0.75, 1.0};
  std::vector<char> surface_;
  double dvar_ = 0, dvar_max_ = 0, t_dvar_max_ = 0;
  int tank_walls_ = 0;     // walls_'s first tank_walls_ particles are the tank's, the rest a gate's
  bool gate_in_ = false;   // a gate's particles are in walls_ (prm.gate; walls.hpp, append_gate)
  double gate_top_ = 0;    // the fluid's initial top
  Profiler& prof_;  // profiler(): the run loop's
  int k_drift_, k_neigh_, k_rho_, k_force_, k_xsph_, k_surface_ = -1;
};

}  // namespace sphib
