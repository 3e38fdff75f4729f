#pragma once
// Neighbour search with a cell grid (periodic axes wrap by the minimum-image convention).
// EPSPH builds the particle pair list once; markers query the same kind of grid each step in O(Nb).
#include <cmath>
#include <vector>

#include "fluid/lattice.hpp"
#include "fluid/types.hpp"

namespace sphib {

class CellGrid {
 public:
  // Points in the box [lo, hi]; along a periodic axis the box is exactly one period and points wrap.
  // Points outside the box along a bounded axis go to the edge cells.
  CellGrid(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, bool periodic_x, bool periodic_y,
           double min_cell_size);

  void build(const Mat2& points);  // allocates only when the point count grows

  // Calls f(j, dx, dy, r) for every point j with r = |q - x_j| < radius (minimum image),
  // where (dx, dy) = q - x_j. Requires radius <= the cell size.
  template <class F>
  void for_each_near(double qx, double qy, double radius, F&& f) const {
    const int cx = cell_of(qx, 0), cy = cell_of(qy, 1);
    const double r2max = radius * radius;
    int xs[3], ys[3];
    const int nxs = stencil(cx, 0, xs), nys = stencil(cy, 1, ys);
    for (int b = 0; b < nys; ++b)
      for (int a = 0; a < nxs; ++a) {
        const int c = xs[a] + nc_[0] * ys[b];
        for (int k = start_[c]; k < start_[c + 1]; ++k) {
          const int j = items_[k];
          double dx = qx - (*pts_)(j, 0), dy = qy - (*pts_)(j, 1);
          if (periodic_[0]) dx -= period_[0] * std::round(dx / period_[0]);
          if (periodic_[1]) dy -= period_[1] * std::round(dy / period_[1]);
          const double r2 = dx * dx + dy * dy;
          if (r2 < r2max) f(j, dx, dy, std::sqrt(r2));
        }
      }
  }

  double cell_size(int axis) const { return h_[axis]; }

 private:
  int cell_of(double c, int axis) const {
    int k = static_cast<int>(std::floor((c - lo_[axis]) / h_[axis]));
    if (periodic_[axis]) { k %= nc_[axis]; if (k < 0) k += nc_[axis]; }
    else k = k < 0 ? 0 : (k >= nc_[axis] ? nc_[axis] - 1 : k);
    return k;
  }
  // The (up to) three distinct neighbouring cell indices along an axis.
  int stencil(int c, int axis, int* out) const {
    int n = 0;
    for (int d = -1; d <= 1; ++d) {
      int k = c + d;
      if (periodic_[axis]) { k %= nc_[axis]; if (k < 0) k += nc_[axis]; }
      else if (k < 0 || k >= nc_[axis]) continue;
      bool seen = false;
      for (int m = 0; m < n; ++m) seen |= (out[m] == k);
      if (!seen) out[n++] = k;
    }
    return n;
  }

  Eigen::Vector2d lo_, period_;
  bool periodic_[2];
  int nc_[2];
  double h_[2];
  const Mat2* pts_ = nullptr;
  std::vector<int> start_, items_, cell_;
};

// The fixed pair list of EPSPH: for each particle i, every other point j (particle, or image
// numbered N + k) closer than 2h, with x_i - x_j by minimum image and F_ij = (1/r) dW/dr.
struct PairList {
  std::vector<int> offset;  // pairs of particle i: [offset[i], offset[i+1])
  std::vector<int> j;
  std::vector<double> rx, ry, r;
  int size() const { return static_cast<int>(j.size()); }
};

// Throws std::invalid_argument if 2h is not below half a periodic period (minimum image would fail).
PairList find_pairs(const Lattice& lattice, const Mat2& image_x, double support);

}  // namespace sphib
