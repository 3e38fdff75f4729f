#pragma once
// The fluid particles within the kernel support of one marker, for the markers' spreading (Eq. 53)
// and interpolation (Eqs. 61-63): gathered first (CellGrid::gather_near: on the fixed lattice
// without a branch per point), then handed to the markers' kernels (kernels/spread.hpp,
// kernels/curl_sums.hpp) (MarkerPoints), which take them two at a time.
#include "fluid/common/neighbours.hpp"
#include "kernels/marker_points.hpp"

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
  // the points: particle indices, offsets q - x_j and squared distances (valid until the next gather)
  MarkerPoints points() const { return {pairs, p_.j.data(), p_.dx.data(), p_.dy.data(), p_.r2.data()}; }

 private:
  NearPoints p_;
};

}  // namespace sphib
