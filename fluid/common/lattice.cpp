#include "fluid/common/lattice.hpp"

#include <stdexcept>

namespace sphib {

const char* side_name(Side s) {
  static const char* names[4] = {"left", "right", "bottom", "top"};
  return names[s];
}

Lattice make_lattice(const Domain& d, int nx, int ny) {
  if (nx < 2 || ny < 2) throw std::invalid_argument("lattice: nx and ny must be at least 2");
  if (!(d.x1 > d.x0) || !(d.y1 > d.y0)) throw std::invalid_argument("lattice: empty domain");
  Lattice L;
  L.domain = d;
  L.nx = nx;
  L.ny = ny;
  L.dx = d.Lx() / nx;
  L.dy = d.Ly() / ny;
  L.volume = L.dx * L.dy;
  L.x.resize(nx * ny, 2);
  const double ox = d.periodic_x ? 0.0 : 0.5;  // Eq. (68): offset in spacings from the low side
  const double oy = d.periodic_y ? 0.0 : 0.5;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      L.x(i + nx * j, 0) = d.x0 + (i + ox) * L.dx;
      L.x(i + nx * j, 1) = d.y0 + (j + oy) * L.dy;
    }
  return L;
}

}  // namespace sphib
