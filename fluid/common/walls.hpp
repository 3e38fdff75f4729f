#pragma once
// Morris virtual wall particles (Morris, Fox & Zhu 1997), the solid walls of the moving-particle
// methods that keep the fluid's kernel support complete at a wall (WCSPH; ISPH, Afanasiev et al.
// Section 3.6): the lattice of Eq. (68) continued beyond each wall of the domain for
// ceil(2h / spacing) rows, corner blocks where two walls meet, fixed in place. Open sides
// (Domain::open) and periodic axes get none. Each particle carries its wall's prescribed velocity
// (corner blocks: the mean of the two walls').
#include <algorithm>
#include <optional>
#include <vector>

#include "fluid/common/lattice.hpp"
#include "fluid/common/params.hpp"

namespace sphib {

// The side code of a gate's particles (append_gate).
constexpr int kGateSide = -2;

struct VirtualWalls {
  Mat2 x, u;                 // positions and prescribed velocities, M x 2
  std::vector<int> side;     // the wall (Side) of a particle beyond one wall; -1 in a corner block; kGateSide
  std::vector<double> dist;  // distance to that wall's line (0 in corner blocks)
  std::vector<char> inner;   // the row next to the fluid (corner blocks: the corner particle next to both)
  int size() const { return static_cast<int>(side.size()); }
};

// The virtual particles of every wall of L.domain for a kernel of support `support` (= 2h), in the
// order of the extended lattice (rows from the bottom, left to right).
VirtualWalls make_virtual_walls(const Lattice& L, double support);

// What is wrong with the gate's keys (gate.*) for the scene's tank and fluid (none without a gate).
std::optional<ParamProblem> gate_problem(const FluidParams& p);

// A dam break's gate (GateParams): a plate of wall particles ceil(2h / dx) columns thick behind the
// line x = g.x (the fluid on its low side), on the lattice's rows from the floor to `top` + 2h, raised by
// g.lift(t); appended to w with side kGateSide, dist the distance behind the face, inner the column
// next to it. The face on a lattice line x0 + k dx continues the lattice, so that a column at rest
// against it is the rest state of a tank. The particles carry no velocity into the pairs (u = 0): the
// plate is moved from step to step, and the water fills the room under its lower edge by its own
// pressure. With the lift speed v in the pairs (the mirror rule of the divergence, the continuity
// equation) the lower edge of the plate, 2h thick (a numerical thickness, not the experiment's), would
// be a source of volume 2h v (docs/free_surfaces.md, "Dam break: the surge front").
void append_gate(const Lattice& L, double support, const GateParams& g, double top, double t, VirtualWalls& w);

// The gate at time t in w, whose first `tank` particles are the tank's: w cut back to those and the
// gate appended again at its lift of time t (append_gate), or left out for good (in = false) once
// its lower edge is more than one support above fluid_top, the highest particle. Returns whether w
// changed: not while `in` is false, nor while the gate, already placed, has not started to lift.
bool move_gate(const Lattice& L, double support, const GateParams& g, double top, double t, double fluid_top, int tank,
               bool& in, VirtualWalls& w);

// Morris et al. (1997): a virtual particle B at distance d_B beyond its wall, seen from a fluid
// particle A at distance d_A before it, carries u_B = u_w - (d_B/d_A)(u_A - u_w) in the viscous
// term, i.e. u_A - u_B = beta (u_A - u_w) with beta = min(beta_max, 1 + d_B/d_A). d_A is floored at
// half a spacing (the initial distance of the first fluid row): exact on the lattice, bounded for a
// particle closer to the wall. (x_A, y_A): the fluid particle.
inline double morris_wall_factor(const Lattice& L, int side, double d_B, double x_A, double y_A, double beta_max) {
  const Domain& d = L.domain;
  const double dA = side == Left ? x_A - d.x0 : side == Right ? d.x1 - x_A : side == Bottom ? y_A - d.y0 : d.y1 - y_A;
  const double dA_min = 0.5 * (side == Left || side == Right ? L.dx : L.dy);
  return std::min(beta_max, 1.0 + d_B / std::max(dA, dA_min));
}

}  // namespace sphib
