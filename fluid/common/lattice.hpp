#pragma once
// Fixed particle lattice on a rectangle, Eq. (68), and the description of its four sides.
#include <array>
#include <string>

#include "fluid/common/boundary_rule.hpp"
#include "fluid/common/types.hpp"

namespace sphib {

enum Side { Left = 0, Right = 1, Bottom = 2, Top = 3 };

// A rectangle [x0, x1] x [y0, y1]; along each axis either periodic or bounded by two sides, each of
// the kind `bounded[side]` (fluid/common/boundary_rule.hpp: the one rule of what a kind implies): a
// no-slip wall with its own prescribed velocity (a moving lid or Couette wall is one setting) or
// open: free space, no wall (free-surface methods only, fluid/common/free_surface.hpp; the rectangle is
// then the tank a particle may not leave).
struct Domain {
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  bool periodic_x = true, periodic_y = false;
  std::array<Eigen::Vector2d, 4> wall_velocity{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(),
                                               Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  // by Side, the kind of a side on a bounded axis (a periodic axis's sides are periodic whatever
  // this holds): SideKind::NoSlip, Open, Inflow (velocity wall_velocity[side] shaped by
  // inflow_profile) or Outflow
  std::array<SideKind, 4> bounded{SideKind::NoSlip, SideKind::NoSlip, SideKind::NoSlip, SideKind::NoSlip};
  InflowProfile inflow_profile = InflowProfile::None;
  double Lx() const { return x1 - x0; }
  double Ly() const { return y1 - y0; }
  bool is_periodic(Side s) const { return (s == Left || s == Right) ? periodic_x : periodic_y; }
  SideKind kind(Side s) const { return is_periodic(s) ? SideKind::Periodic : bounded[s]; }
  bool is_wall(Side s) const { return is_wall_kind(kind(s)); }
  bool is_open(Side s) const { return kind(s) == SideKind::Open; }
  bool any_open() const { return is_open(Left) || is_open(Right) || is_open(Bottom) || is_open(Top); }
  bool any_through() const {  // an inflow or outflow side
    return is_through_kind(kind(Left)) || is_through_kind(kind(Right)) || is_through_kind(kind(Bottom)) ||
           is_through_kind(kind(Top));
  }
  // The image parity of field f across side s (boundary_rule.hpp; 0 on a periodic or open side).
  int parity(Side s, Field f) const { return image_parity(kind(s), f); }
};

// "left", "right", "bottom", "top".
const char* side_name(Side s);

// A figure per wall, by Side (the wall loads of loads.hpp, FluidSolver::wall_forces): NaN for a side
// without a wall.
using WallForces = std::array<double, 4>;

struct Lattice {
  Domain domain;
  int nx = 0, ny = 0;
  double dx = 0, dy = 0;
  Mat2 x;           // particle positions, N x 2, index i + nx * j
  double volume = 0;  // V = m / rho = dx dy, the same for every particle

  int size() const { return nx * ny; }
};

// Eq. (68): along a periodic axis x_i = a + i dx; along a walled axis particles sit half a spacing
// off each wall, y_j = a + (j + 1/2) dy, so that mirror images continue the lattice across the wall.
Lattice make_lattice(const Domain& domain, int nx, int ny);

}  // namespace sphib
