#pragma once
// A short-range repulsion between the markers of different membranes, and between markers and the
// walls, so that capsules moving in a suspension do not overlap. The immersed boundary alone keeps
// two membranes apart only as far as the flow between them is resolved: closer than the kernels'
// support (~2h*) both move with nearly the same interpolated velocity, and nothing stops them
// crossing.
//
// The model is the repulsive branch of the Morse potential, as used between the membranes of red
// blood cells by Liu & Liu (2006, J. Comput. Phys. 220, 139) and Fedosov, Pan, Caswell, Gompper &
// Karniadakis (2011, PNAS 108, 11772), cut at its minimum r0 so that it only repels:
//   U(r) = De [exp(2 beta (r0 - r)) - 2 exp(beta (r0 - r)) + 1]   for r < r0, 0 beyond,
//   phi(r) = -dU/dr = 2 beta De [exp(2 beta (r0 - r)) - exp(beta (r0 - r))]  (> 0, repulsive),
// which is 0 with its value at r = r0 (the force is continuous), grows as r falls, and is finite
// at r = 0. It acts between the membranes' line elements: elements ds_a at X_i and ds_b at X_j of
// two different membranes push each other apart with the force phi(r_ij) ds_a ds_b along
// X_i - X_j, so the force density (per unit label, as the membrane force f) on marker i is
//   f_i += sum_j phi(r_ij) (X_i - X_j)/r_ij ds_b,
// and on j the same pair gives -phi ds_a: every pair is equal and opposite, the total force is zero
// and momentum is conserved. Being per element, the force does not depend on the number of markers
// (a sum over ds_b approximates the integral over the other membrane). De is an energy per unit
// length of each membrane (force per unit depth in 2-D units).
//
// A wall pushes a marker at distance d from it along the wall's inward normal with the force
// density r0 phi(d): as much as a flat membrane along the wall line would if all its elements within
// r0 pushed straight (an upper bound of that membrane's push; monotone in d, where the integral over
// the line's elements falls back to 0 at d = 0). The wall takes the reaction, as it takes the
// flow's shear: this part changes the momentum of the fluid and membranes, as any wall does.
//
// The pairs closer than r0 are found with a cell list over the markers (cells of at least r0,
// counting sort every evaluation, half stencil): O(markers), not O(markers^2).
#include <limits>
#include <memory>
#include <vector>

#include "coupling/params.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/common/types.hpp"

namespace sphib {

// The Morse repulsion phi(r) above (0 for r >= r0).
double morse_repulsion(const ContactParams& p, double r);

class MarkerCells;  // the cell list (contact.cpp)

class ContactForce {
 public:
  // Throws std::invalid_argument (naming the parameter) for a negative or non-finite strength, a
  // range not positive, a negative beta, or a range of a third of a periodic period or more.
  ContactForce(const ContactParams& p, const Domain& d);
  ~ContactForce();
  ContactForce(const ContactForce&) = delete;
  ContactForce& operator=(const ContactForce&) = delete;

  // Adds the contact force densities to f, for the markers X (all membranes concatenated: membrane
  // k's rows [start[k], start[k+1])) of rest spacings ds[k]. X and f have start.back() rows.
  void add(const Mat2& X, const std::vector<int>& start, const std::vector<double>& ds, Mat2& f);

  // Of the last add(): the least distance between markers of different membranes among the pairs
  // closer than the range (+infinity when none), and the pairs within range.
  double least_distance() const { return least_; }
  double least_distance_so_far() const { return least_so_far_; }  // the same over every add() so far
  long pairs() const { return pairs_; }
  const ContactParams& params() const { return p_; }

 private:
  ContactParams p_;
  Domain d_;
  std::unique_ptr<MarkerCells> cells_;
  double least_ = std::numeric_limits<double>::infinity(), least_so_far_ = least_;
  long pairs_ = 0;
};

// The least distance between markers of different membranes (minimum image along periodic axes)
// that are closer than `radius`, +infinity when no two are; by a cell list, O(markers). The same
// layout of X as ContactForce::add. For diagnostics (the gap between capsules).
double least_marker_distance(const Mat2& X, const std::vector<int>& start, const Domain& d, double radius);

}  // namespace sphib
