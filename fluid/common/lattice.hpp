#pragma once
// Fixed particle lattice on a rectangle, Eq. (68), and the description of its four sides.
#include <array>
#include <string>

#include "fluid/common/types.hpp"

namespace sphib {

enum Side { Left = 0, Right = 1, Bottom = 2, Top = 3 };

// A rectangle [x0, x1] x [y0, y1]; along each axis either periodic or bounded by two sides, each a
// no-slip wall with its own prescribed velocity (a moving lid or Couette wall is one setting) or
// open: free space, no wall (free-surface methods only, fluid/common/free_surface.hpp; the rectangle is
// then the tank a particle may not leave).
struct Domain {
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  bool periodic_x = true, periodic_y = false;
  std::array<Eigen::Vector2d, 4> wall_velocity{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(),
                                               Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  std::array<bool, 4> open{false, false, false, false};  // by Side; never on a periodic axis
  double Lx() const { return x1 - x0; }
  double Ly() const { return y1 - y0; }
  bool is_periodic(Side s) const { return (s == Left || s == Right) ? periodic_x : periodic_y; }
  bool is_wall(Side s) const { return !is_periodic(s) && !open[s]; }
  bool any_open() const { return open[0] || open[1] || open[2] || open[3]; }
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
