#pragma once
// The fluid particles within the kernel support of one marker, for the markers' spreading (Eq. 53)
// and interpolation (Eqs. 61-63): gathered first (CellGrid::gather_near: on the fixed lattice
// without a branch per point), then taken two at a time by the kernel's branch-free two-lane form
// (CubicSplineKernel::W_F2). A marker's 20-50 points fall on either side of q = 1 in no predictable
// order, which made the branches of a per-point loop its largest cost.
#include "fluid/common/kernel.hpp"
#include "fluid/common/neighbours.hpp"

namespace sphib {

class Neighbourhood {
 public:
  // The points within `radius` of (qx, qy), in CellGrid::for_each_near's order, padded to whole
  // pairs with a repeat of the first point at twice the radius (where the kernel is 0). Without
  // `offsets` only the indices and squared distances (dx and dy unset).
  void gather(const CellGrid& grid, double qx, double qy, double radius, bool offsets = true) {
    grid.gather_near(qx, qy, radius, p_, offsets);
    const int n = p_.n;
    pairs = (n + 1) / 2;
    if (n % 2) {
      p_.j[n] = n > 1 ? p_.j[0] : 0;
      p_.dx[n] = p_.dy[n] = 0.0;
      p_.r2[n] = 4.0 * radius * radius;
    }
  }
  int pairs = 0;  // the pairs gathered
  // pair i: particle indices, offsets q - x_j and squared distances
  int j0(int i) const { return p_.j[2 * i]; }
  int j1(int i) const { return p_.j[2 * i + 1]; }
  Lanes2 dx(int i) const { return Lanes2{p_.dx[2 * i], p_.dx[2 * i + 1]}; }
  Lanes2 dy(int i) const { return Lanes2{p_.dy[2 * i], p_.dy[2 * i + 1]}; }
  Lanes2 r2(int i) const { return Lanes2{p_.r2[2 * i], p_.r2[2 * i + 1]}; }

 private:
  NearPoints p_;
};

}  // namespace sphib
