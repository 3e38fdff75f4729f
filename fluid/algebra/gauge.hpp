#pragma once
// The null space of the SPH gradient on the fixed lattice, and the gauge that fixes it.
//
// G f = sum_j V (f_i + f_j) (x_i - x_j) F_ij (Eq. 27) vanishes for a field whose value at every
// neighbour pair at +r and -r is the same: along each axis a mode is a constant or the alternating
// (-1)^i, and it must continue through the images. A periodic axis carries both (the alternating
// one when the number of particles is even); across a wall with even images (phi: f' = f) only the
// constant continues, across a wall with odd images (a stream function: f' = -f) only the
// alternating one (the half-spacing lattice reflects row 0 onto row -1). The null vectors are the
// products of one factor per axis, e.g. for G^T G with even images: a channel 1 and (-1)^{i_x}, a
// closed box 1, a doubly periodic box 1, (-1)^{i_x}, (-1)^{i_y}, (-1)^{i_x + i_y}; with odd images a
// channel (-1)^{i_y} and (-1)^{i_x + i_y}, a closed box (-1)^{i_x + i_y}; an axis with even images on
// one side and odd on the other (a stream function between an inflow and an outflow) carries
// neither mode, so the operator has no null vector. They are mutually
// orthogonal. The Morris Laplacian (Eq. 31) sees the alternating modes: its only null vector is 1.
//
// The gauge: right-hand sides are projected onto the orthogonal complement of the null space (the
// range of the symmetric operator); a direct factorisation pins f = 0 at one particle per null vector
// (in the 2 x 2 block at the lattice origin, on which the null vectors are independent); the
// solution is made orthogonal to the null space again. Only G f enters the velocity, so the null
// components are immaterial there; removing them keeps f free of grid-scale offsets.
#include <vector>

#include "fluid/common/lattice.hpp"
#include "kernels/parity_modes.hpp"

namespace sphib {

// Which null space an operator has: none, the constants (the Morris Laplacian of phi: none where a
// side's phi images are odd, an outflow's, by the boundary rule), or that of G^T G
// on phi (a scalar: the walls' Field::Scalar parities, even at no-slip walls) or on a stream function
// (Field::Stream, odd), the parities from the boundary rule (fluid/common/boundary_rule.hpp).
enum class NullSpace { None, Constants, GradientScalar, GradientStream };

class Gauge {
 public:
  Gauge() = default;
  Gauge(const Lattice& L, NullSpace ns);

  int dimension() const { return static_cast<int>(modes_.size()); }
  const std::vector<int>& pins() const { return pins_; }

  // f minus its components along the null vectors (exact: they are orthogonal).
  void project(Vec& f) const;
  // Rows and columns of the pins replaced by the identity (a symmetric, definite matrix for a direct
  // factorisation); A must hold its diagonal in its pattern. prune = false keeps A's pattern (the
  // zeros stay), so that a matrix pinned again every step keeps its symbolic analysis.
  SpMat pinned(const SpMat& A, bool prune = true) const;
  void pin_rhs(Vec& b) const;  // b = 0 at the pins

 private:
  struct Mode {
    int sx = 0, sy = 0;  // (-1)^{sx i_x + sy i_y}
  };
  std::vector<Mode> modes_;
  std::vector<int> pins_;
  int nx_ = 0, ny_ = 0;
  friend class VelocityModes;
};

// The velocity fields the divergence D = -G^T of the exact projection does not see and no curl of a
// stream function makes: per component the alternating modes that continue through its images
// (along a periodic axis 1 and (-1)^i; across a wall the normal component alternates, the
// tangential one is constant), the uniform flow of a doubly periodic box included, the uniform flux
// of a channel not (a stream function carries it in its wall values). The exact projection keeps
// them as they are.
class VelocityModes {
 public:
  VelocityModes() = default;
  explicit VelocityModes(const Lattice& L);
  // to += the components of `from` along the modes (column c of both for velocity component c)
  void add_components(const Mat2& from, Mat2& to) const;
  // What add_components(from, .) adds, as a table: to(i, c) += value[c][i_y & 1][i_x & 1] for the
  // components with has[c] (the same bits: the modes alternate with the parities only).
  using Addends = ParityModes;
  Addends addends(const Mat2& from) const;

 private:
  Gauge comp_[2];  // the modes of each component, as a gauge's mode list
};

}  // namespace sphib
