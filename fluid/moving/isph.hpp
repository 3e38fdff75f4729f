#pragma once
// Incompressible SPH with a free surface (ISPH) of Afanasiev, Makarchuk & Popov (2011) ["A"],
// Sections 3.3-3.6: the split step of Shao & Lo (A Eqs. 22-25) ON THE PROJECTION CORE
// (projection_core.hpp), which it shares with EPSPH and LPSPH. What ISPH adds:
//   - the particles: the fluid region of free_surface.hpp (a block, a circle or the tank), volume V
//     each, moving with A Eq. (25), x^{n+1} = x^n + dt u^{n+1};
//   - the walls: Morris virtual wall particles (A Section 3.6, walls.hpp), fixed, several rows deep,
//     as the core's "images" without parents (see below);
//   - gravity g, added to u* (A Eq. 22; the core's accel_);
//   - the viscous predictor of A Eq. (22), explicit (the core's explicit_viscous_), or the core's
//     Crank-Nicolson (isph.viscous);
//   - the free surface: the particles A Eq. (26) marks (div r_i < 2 beta, free_surface.hpp) are
//     Dirichlet rows p = 0 of the Poisson problem (A Section 3.5), eliminated symmetrically.
//
// One step (the core's step(): begin_step, predictor, project, end_step):
//   x* = x^n + dt u^n: the step's geometry there (as LPSPH, lagrangian.hpp: the projection then makes
//        u^{n+1} divergence-free where the particles go, x^{n+1} - x* = dt (u^{n+1} - u^n)); pairs
//        with particles and wall particles from a Verlet list (neighbours.hpp, fixed points), the
//        operators, both systems and A Eq. (26)'s sums in one pass (particle_operators.hpp);
//   surface: S = {i : div r_i < 2 beta}; the Poisson matrix -lap phi with rows AND columns of S zeroed
//        and 1 on their diagonal (ProjectionFluid::eliminate_dirichlet), b = 0 there;
//   u* = u^n + dt (g + nu lap u^n) + dt F / rho                          A Eq. (22) with Eq. (18)
//   -lap p = -(rho/dt) div u*, p = 0 on S                                A Eq. (24), Eqs. (17), (14)
//   u^{n+1} = u* - dt/rho grad p                                         A Eq. (23) with Eq. (13)
//   x^{n+1} = x^n + dt u^{n+1}                                           A Eq. (25)
// The Laplacian is Lee's A Eq. (17), which for a uniform density is the Morris Laplacian the core uses
// (2 V (p_i - p_j) F_ij); the viscous term is Morris's A Eq. (18), the same with nu; the divergence
// of u* is A Eq. (14)'s difference form sum_j V (u_j - u_i) . grad_i W (zero for a uniform flow also
// where the support is cut by the surface; the core's sum form is not); the gradient is A Eq. (13)'s
// sum form (which reads the missing neighbours beyond the surface as p = 0).
//
// Walls in the core's operators (operators.hpp: a neighbour j that is not a particle carries
// f_j = sign_j f_parent + c_j). A wall particle w seen from particle i carries a value of the PAIR:
// an affine function of f_i and of c_w, the wall particle's prescribed velocity (its wall's):
//   viscous term (A Eq. 18):  u_w = u_i - beta_iw (u_i - c_w), beta_iw = 1 + d_w / d_i   Morris et al.
//   divergence (A Eq. 14):    u_w = 2 c_w - u_i           the mirror rule of Eq. (42), pair by pair
//   pressure (A Eqs. 13, 17): p_w = p_i                   dp/dn = 0 (A Section 3.6), pair by pair
//                             (the consistent scheme's gradient: the extrapolated p_w, below)
// (particle_operators.hpp, PairRules). So the images are the wall particles (Images::parent -1), the
// offsets c are their velocities (velocity_offsets), and no wall pair enters the Poisson matrix: it is
// the symmetric graph Laplacian of the particle pairs, and stays symmetric after the symmetric
// elimination of the surface rows, so CHOLMOD and CG apply. (A embeds the Neumann condition by
// copying a fluid pressure into each wall particle, which breaks the symmetry, and uses PGMRES.)
// Why 2 c_w - u_i in the divergence and not c_w: the rows of the wall particles are no unknowns here,
// and with u_w = c_w only the half of the wall's flux jump that lies in the fluid's rows would enter
// (a still tank then sinks); with the mirror rule the whole jump does, which makes -lap p = -(rho/dt)
// div u* with dp/dn = 0 the discrete form of dp/dn = (rho/dt)(u* - u_w) . n at the wall.
//
// The consistent scheme (isph.scheme = "consistent", the default; "paper" keeps A's operators as they
// were): a fluid at rest on the lattice is an exact fixed point of the step, so a still tank stays
// still (to round-off) instead of growing a circulation. Three changes, each what the rest state needs,
// and a fourth that the rest state allows:
//   - the pressure gradient is A Eq. (13)'s sum form over M0 = -sum_j V x_ij^2 F_ij, the second moment
//     of a full support in the initial arrangement (1.0105 on the lattice at h = 1.3 dx): the sum form
//     of a linear p is M0 grad p, so the hydrostatic gradient is rho g exactly (with the wall
//     particles' hydrostatic part below and the renormalised gradient at surface particles);
//   - the Poisson rows of particles whose support is cut (beside the free surface) read the missing
//     neighbours as mirror images of the particle with p = -p_i, antisymmetric about the Dirichlet
//     rows p = 0: -lap p_i gains -4 V p_i (S_F - sum_j F_ij), S_F the full support's sum_j F_ij (an
//     SPD diagonal term). On the lattice the second row then has exactly the hydrostatic solution;
//     without it its Laplacian of a linear p is not zero and p below the surface rose 30 Pa over its
//     hydrostatic value (measured, still tank 40 x 20), which pushed the top row up;
//   - the Lennard-Jones push of the walls starts at 0.98 dx, inside the rest spacing (at dx its
//     one-sided spring grew round-off into a circulation);
//   - in the pressure gradient (only there: the Poisson matrix keeps the pair rule p_w = p_i) the wall
//     particles carry their pressure extrapolated from the fluid (Adami et al. 2012 Eq. 27, the
//     loads' and probes' rule): the gradient along a wall then reaches the first row in full, where
//     the pair rule gives it 0.77 of it (isph.cpp, wall_gradient). For a fluid at rest both are the
//     hydrostatic pressure.
//
// Particle shifting (shifting.hpp, isph.shifting; auto: fickian with the consistent scheme, none with
// the paper's): after x^{n+1} = x^n + dt u^{n+1}, x^{n+1} += dr and u^{n+1} += (dr . grad) u^{n+1} away
// from the surface, the shifts dr from the step's pairs at x* (Lind et al. 2012's Fickian shifting with
// its free-surface correction, or Xu et al. 2009's); no shift takes a particle closer to a wall than
// half a spacing.
//
// Beyond the paper (each measured, isph.cpp): negative pressures clipped to 0 with a free surface and
// u^{n+1} taken from the clipped p (clip_tension; as MPS); no particle within half a spacing of a
// wall (wall_contact: its normal velocity towards the wall cut); a Lennard-Jones push of the inner
// wall row on u* (wall_repulsion); at surface particles the renormalised gradient over their fluid
// neighbours instead of the sum form (surface_gradient).
//
// Linear systems: the solver policy of the moving particles (solver_policy.hpp, Refactor::EveryStep);
// auto: warm-started CG with a lagged preconditioner (a CHOLMOD factor; the FFT solver of the lattice
// for a full tank that starts on it), with a free surface and without (make_solvers says why).
// The Poisson matrix is singular only without a free surface (a tank full of fluid: the constants,
// fixed by the gauge as in LPSPH). A connected set of particles without a surface particle (a closed
// bubble of fluid cut off by walls) makes it singular: the solver then stops the run.
//
// Checkpoints: the core's state, x^n, and the Verlet list's (the positions of its last build, its
// skin and counters), so that a restart makes the same candidate pairs, operator patterns and
// symbolic analyses as the uninterrupted run; with a direct Poisson solver (the default) it then
// continues bit for bit.
//
// A gate (prm.gate, [gate] in a scene; walls.hpp, append_gate): a plate of wall particles appended to
// the tank's, of the same kind (Morris factors with the distance to its face, the mirror rule, the
// wall pressure, the Lennard-Jones push of its inner column, no particle within half a spacing of its
// face, A Eq. 26's mirror images across its face; no velocity in the pairs: walls.hpp), lifted at
// gate.speed from gate.start. While it moves the Verlet list is built every step with its new
// positions; once its lowest row is more than 2h above the highest particle it is removed and the
// walls are the tank's again.
//
// A particle that leaves the tank (through a wall or an open side) or gets a non-finite position
// stops the run naming it, the side and the time (keep_in_tank, boundary.hpp).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fluid/common/free_surface.hpp"
#include "fluid/moving/particle_operators.hpp"
#include "fluid/core/projection_core.hpp"
#include "fluid/moving/shifting.hpp"
#include "fluid/common/walls.hpp"

namespace sphib {

// What is wrong with an ISPH scene's keys (free_surface_problem's and ISPH's own), as (key, message).
std::optional<ParamProblem> isph_problem(const FluidParams& params);

class IsphFluid final : public ProjectionFluid {
 public:
  // The fluid region's particles, at rest; `profiler`: the run loop's (nullptr: its own).
  explicit IsphFluid(const FluidParams& params, Profiler* profiler = nullptr);

  const std::vector<char>* surface() const override { return detect_ ? &surface_ : nullptr; }
  // A Eq. (32) over the wall particles next to the fluid, with their pressure (see the header).
  WallForces wall_forces() const override;
  // Puts the particles at x (N x 2) and builds the geometry there (tests).
  void set_positions(const Mat2& x);
  const VirtualWalls& walls() const { return walls_; }
  const Vec& position_divergence() const { return div_r_; }  // A Eq. (26)'s sums at the last x*
  const Vec& wall_pressure_values() const { return p_w_; }   // the wall particles' (see the header)
  const SpMat& poisson_matrix() const { return A_phi_; }     // the last step's, surface rows eliminated
  const Vec& poisson_rhs() const { return b_phi_; }          // its right-hand side, -(rho/dt) div u*
  const Mat2& u_star() const { return u_star_; }
  // The step's pressure gradient (A Eq. 13 with the wall particles' part, over M0 in the consistent
  // scheme, the renormalised gradient at surface particles) of the particle pressures p at the
  // present positions; it takes p as the step's pressure and sets u^{n+1} from it (tests).
  const Mat2& pressure_gradient(const Vec& p);
  double viscous_bound() const;  // nu dt max_i |lap_ii| (the explicit predictor is stable below ~1)

 private:
  // Its report to the profiler: the run-log lines and the figures.
  std::vector<std::string> describe() const;
  std::vector<std::pair<std::string, double>> figures() const;
  void begin_step() override;
  void viscous_rhs(const Mat2& F) override;  // explicit: u* of A Eq. (22); else the core's Eq. (28)
  void project() override;  // the core's, then the wall particles' pressure and its part of the gradient
  void end_step() override;
  void velocity_offsets(const Mat2* grad_phi, Mat2& c) const override;  // the wall particles' velocities
  void extra_state(NamedArrays& st) const override;
  void restore_extra(const NamedArrays& st) override;
  IsphFluid(const FluidParams& params, const ParticleSet& set, Profiler* profiler);
  void geometry(bool force);     // at x_star_: the Verlet list's update, then assemble()
  void assemble(bool new_pattern);  // Morris factors, operators, systems, surface, Dirichlet rows
  void morris_factors();         // beta_ of every pair with a wall particle
  void add_mirror_divergence();  // A Eq. (26)'s sums: the wall's part
  void clip_tension();           // p = max(p, 0) and u^{n+1} from it (see isph.cpp)
  void surface_gradient();       // the renormalised gradient at surface particles (isph.cpp)
  void wall_contact();           // no particle within half a spacing of a wall (see the header)
  void wall_repulsion();         // Lennard-Jones force of the inner wall row on u* (isph.cpp)
  void shift_off_walls();        // the shifts dr_ keep wall_contact's gap
  void surface_mirror();         // consistent: the Poisson rows beside the surface (isph.cpp)
  void surface_sums();           // csum_ from the assembly's operators (isph.cpp)
  void reference_sums();         // consistent: M0_, S_F_ of a full support at t = 0
  void find_wall_pairs();        // wall_pairs_ from pairs_
  void wall_pressure();          // p_w_ from phi_ (A Eq. 30 normalised, with the hydrostatic term)
  void wall_gradient();          // the wall particles' part of the pressure gradient and of u^{n+1}
  void make_solvers();
  void refactorise();            // the solvers take the step's matrices
  bool place_gate(double t);     // the gate's particles at time t (or none once it has left); whether they changed

  Mat2 x_star_;  // the step's predicted positions (x^n: the base's x_)
  VirtualWalls walls_;
  VerletList verlet_;
  ParticleOperators assembly_;
  bool pattern_stale_ = true;  // the next assembly makes the patterns (after a restore)
  SpMat A_cn_, A_phi_;
  std::vector<double> beta_;  // per pair: Morris's factor (pairs with a wall particle)
  ParticlePairs wall_pairs_;  // the pairs with a wall particle closer than 2h (j - N: the wall particle)
  Vec p_w_, rho_, work_;      // the wall particles' pressure; rho at the particles; workspace
  Vec div_r_;                 // A Eq. (26)'s sums
  SurfaceDetector detector_{SurfaceDetection::None, 0.75, 1.0};
  bool detect_ = false;
  std::vector<char> surface_;
  ParticleShifter shifter_;   // after A Eq. (25) (shifting.hpp; isph.shifting)
  Mat2 dr_;                   // the last step's shifts
  ConcentrationSums csum_;    // grad C, sum F and the particles beside the surface at the step's x*
  std::vector<int> diag_;     // the diagonal's place in A_phi_'s values, row by row
  bool consistent_ = false;   // isph.scheme = "consistent" (see the header)
  double M0_ = 1, S_F_ = 0;   // consistent: a full support's -sum V x^2 F and sum F (reference_sums)
  int tank_walls_ = 0;        // walls_'s first tank_walls_ particles are the tank's, the rest the gate's
  bool gate_in_ = false;      // the gate's particles are in walls_
  double gate_top_ = 0;       // the fluid's initial top (the gate reaches 2h above it)
  double gate_bottom_ = -INFINITY;  // the gate's lower edge at the step's t^{n+1} (-inf: no gate)
  MovingPhases k_;
  int k_surface_, k_shift_ = -1;
};

}  // namespace sphib
