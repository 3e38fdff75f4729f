#pragma once
// Neighbour pairs of moving particles (WCSPH, ISPH): a cell list over N moving particles and M fixed
// points (Morris virtual wall particles, fluid/common/walls.hpp), rebuilt at every call. Cells are at least
// 2h wide; along a non-periodic axis the box grows by two supports on each side, so the wall rows
// (one support and a spacing deep) fit. Each pair within 2h is found once, by a half stencil of
// cells, with the kernel's W_ij and F_ij = (1/r) dW/dr, so that a pair sum is accumulated on both
// particles in one pass.
#include <vector>

#include "kernels/cubic_spline.hpp"
#include "fluid/common/lattice.hpp"

namespace sphib {

// Pairs closer than 2h, each once: i a moving particle; j a moving particle (j < N: the pair counts
// for both) or the fixed point j - N (counts for i only); x_i - x_j (minimum image), r, W_ij and
// F_ij = (1/r) dW/dr of the cubic spline (kernels/cubic_spline.hpp).
struct ParticlePairs {
  std::vector<int> i, j;
  std::vector<double> rx, ry, r, W, F;
  int size() const { return static_cast<int>(i.size()); }
};

class PairSearch {
 public:
  // N moving particles and the fixed points `fixed` (M x 2) in the domain `d`; 2h below half a
  // periodic length (std::invalid_argument otherwise, naming the axis).
  PairSearch(const Domain& d, const CubicSplineKernel& W, int N, const Mat2& fixed);

  // The pairs of the particles at x (N x 2) with each other and with the fixed points. A particle
  // outside the box is binned into the edge cell (the methods stop a particle leaving the tank).
  void find(const Mat2& x, ParticlePairs& P);
  long neighbours() const { return nbrs_; }  // neighbours summed over the moving particles, last search

 private:
  Domain d_;
  CubicSplineKernel W_;
  int N_;
  Eigen::Vector2d lo_, cell_;
  int nc_[2] = {1, 1};
  Mat2 all_;  // moving particles, then the fixed points
  std::vector<int> cell_start_, cell_items_, cell_of_, moving_;  // moving_: moving particles per cell
  std::vector<double> cell_x_, cell_y_;  // positions in cell order
  long nbrs_ = 0;
};

}  // namespace sphib
