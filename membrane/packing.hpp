#pragma once
// Random placement of equal disks in a rectangle without overlap, for the initial state of a
// suspension of capsules: random sequential addition (Feder 1980; Widom 1966), each disk's centre
// drawn uniformly where it keeps a clearance from the disks already placed and from the box's
// bounded sides, until `count` are placed. Reproducible: the same seed gives the same centres on
// every platform (the 64-bit Mersenne twister of <random>, whose sequence the standard fixes, turned
// into doubles by its top 53 bits rather than by a std:: distribution, whose algorithm it does not).
// In 2-D this placement jams near an area fraction of 0.547; a dense request fails there.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace sphib {

struct DiskPacking {
  int count = 0;           // disks to place
  double radius = 0.0;     // their radius
  double x0 = 0.0, x1 = 1.0, y0 = 0.0, y1 = 1.0;  // the box
  bool periodic_x = true, periodic_y = false;      // a periodic side wraps (minimum image); a bounded one is a wall
  double gap = 0.0;        // least distance between two disks' edges
  double wall_gap = 0.0;   // least distance between a disk's edge and a bounded side
  std::uint64_t seed = 1;
  long max_attempts = 0;   // draws before giving up (0: 10000 count)
};

/// The centres (count x 2). Throws std::invalid_argument for a count < 0, a radius <= 0, a box that
/// cannot hold one disk, or when max_attempts draws placed fewer than count (too dense: the message
/// names the area fraction asked for and the count placed).
Eigen::MatrixX2d random_disks(const DiskPacking& p);

/// The least distance between the edges of two of the disks (minimum image along periodic axes):
/// <= 0 where two overlap; +infinity for fewer than two.
double least_disk_gap(const Eigen::MatrixX2d& centres, const DiskPacking& p);

}  // namespace sphib
