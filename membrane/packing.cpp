#include "membrane/packing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {

// Uniform in [0, 1): the generator's top 53 bits (the same doubles on every platform).
double uniform01(std::mt19937_64& g) { return static_cast<double>(g() >> 11) * 0x1.0p-53; }

// Distance between centres a and b, by minimum image along the periodic axes.
double centre_distance(const DiskPacking& p, double ax, double ay, double bx, double by) {
  double dx = ax - bx, dy = ay - by;
  const double Lx = p.x1 - p.x0, Ly = p.y1 - p.y0;
  if (p.periodic_x) dx -= Lx * std::round(dx / Lx);
  if (p.periodic_y) dy -= Ly * std::round(dy / Ly);
  return std::sqrt(dx * dx + dy * dy);
}

}  // namespace

Eigen::MatrixX2d random_disks(const DiskPacking& p) {
  if (p.count < 0) throw std::invalid_argument("random_disks: count = " + std::to_string(p.count) + " must be >= 0");
  if (!(p.radius > 0) || !std::isfinite(p.radius))
    throw std::invalid_argument("random_disks: radius must be positive and finite");
  if (!(p.gap >= 0) || !(p.wall_gap >= 0)) throw std::invalid_argument("random_disks: the gaps must be >= 0");
  // The centres' range: a bounded side keeps radius + wall_gap off; a periodic one none.
  const double mx = p.periodic_x ? 0.0 : p.radius + p.wall_gap, my = p.periodic_y ? 0.0 : p.radius + p.wall_gap;
  const double cx0 = p.x0 + mx, cx1 = p.x1 - mx, cy0 = p.y0 + my, cy1 = p.y1 - my;
  const double Lx = p.x1 - p.x0, Ly = p.y1 - p.y0;
  // A disk and its own periodic image must not meet either (and minimum image needs 2 r + gap < L / 2
  // to find the nearest copy of the others).
  if (!(cx1 > cx0) || !(cy1 > cy0) || (p.periodic_x && 2 * (2 * p.radius + p.gap) > Lx) ||
      (p.periodic_y && 2 * (2 * p.radius + p.gap) > Ly))
    throw std::invalid_argument("random_disks: the box cannot hold a disk of radius " + std::to_string(p.radius));
  const long attempts = p.max_attempts > 0 ? p.max_attempts : 10000L * std::max(p.count, 1);
  const double min_d = 2.0 * p.radius + p.gap;
  std::mt19937_64 g(p.seed);
  Eigen::MatrixX2d c(p.count, 2);
  int placed = 0;
  for (long a = 0; a < attempts && placed < p.count; ++a) {
    const double x = cx0 + (cx1 - cx0) * uniform01(g), y = cy0 + (cy1 - cy0) * uniform01(g);
    bool free = true;
    for (int k = 0; k < placed && free; ++k) free = centre_distance(p, x, y, c(k, 0), c(k, 1)) >= min_d;
    if (!free) continue;
    c(placed, 0) = x;
    c(placed, 1) = y;
    ++placed;
  }
  if (placed < p.count) {
    std::ostringstream m;
    m << "random_disks: placed " << placed << " of " << p.count << " disks in " << attempts
      << " draws (area fraction asked for " << p.count * M_PI * p.radius * p.radius / (Lx * Ly)
      << "; random sequential addition jams near 0.547, less with gaps)";
    throw std::invalid_argument(m.str());
  }
  return c;
}

double least_disk_gap(const Eigen::MatrixX2d& c, const DiskPacking& p) {
  double least = std::numeric_limits<double>::infinity();
  for (int k = 0; k < c.rows(); ++k)
    for (int l = k + 1; l < c.rows(); ++l)
      least = std::min(least, centre_distance(p, c(k, 0), c(k, 1), c(l, 0), c(l, 1)) - 2.0 * p.radius);
  return least;
}

}  // namespace sphib
