#pragma once
// A viscosity contrast: the fluid enclosed by membrane k has the viscosity lambda_k mu (mu the
// fluid's, outside every membrane), through the indicator I_k of each membrane's enclosed region
// at the fluid's particles:
//   mu(x_i) = mu m_i,   m_i = 1 + sum_k (lambda_k - 1) I_k(x_i),
// the viscosity the fluid's variable-viscosity step takes (fluid/eulerian/variable_viscosity.hpp).
//
// The indicator is the exact fraction of each particle's lattice cell (dx x dy about x_i, the cells
// of Eq. 68 tile the domain) that lies inside the polygon through the markers: sum_i I_i dx dy is the
// polygon's area to round-off, I is 0 and 1 a cell away from it, and a cell it cuts gets its exact
// fraction (a transition one cell wide). Computed by the signed-area accumulation of exact scan
// conversion: every edge, cut at the lattice lines into pieces inside one cell each, adds to its
// cell the area between the piece and the cell's left side and, to every cell left of it in its
// row, its height (signed: up or down); a sweep from the right along each row sums them (Green's
// theorem per cell, F = (x, 0): the area of a cell inside the curve is the integral of x dy over the
// boundary pieces inside it, plus the cell's width times the net height crossed to its right).
// Cost O(Nb + the cells of the membrane's bounding box); only the particles whose m changed go to
// the fluid, so its operator is updated only near the membranes (O(band)).
#include <vector>

#include "fluid/common/lattice.hpp"
#include "fluid/core/solver.hpp"
#include "fluid/common/types.hpp"

namespace sphib {

// The indicator of one closed polygon on the lattice: the particles whose cell it covers (I > 0),
// with their fractions. Cells within 1e-12 of full or empty are taken as full or empty.
struct CellFractions {
  std::vector<int> index;   // particle index (lattice order)
  std::vector<double> I;    // fraction of its cell inside the polygon, (0, 1]
  double area = 0.0;        // sum_i I_i dx dy
};

// Accumulation buffers, reused between calls.
struct CellFractionWork {
  std::vector<double> part, full;  // per cell of the bounding box: the partial areas, the full heights
};

// I of the polygon through X (nb x 2, either orientation) on lattice L. X may lie across a periodic
// side (unwrapped coordinates); throws std::runtime_error when its bounding box spans a whole period
// or leaves the domain across a wall.
void cell_fractions(const Lattice& L, const Mat2& X, CellFractions& out, CellFractionWork& work);

// The viscosity field of several membranes, each with its ratio lambda_k, brought to the fluid.
class ViscosityContrast {
 public:
  ViscosityContrast(const Lattice& L, std::vector<double> lambda);

  // m from the membranes' markers X[k] now; sends the particles whose m changed since the last call
  // to fluid.set_viscosity. Returns how many changed.
  int update(const std::vector<const Mat2*>& X, FluidSolver& fluid);

  const CellFractions& indicator(size_t k) const { return I_[k]; }
  const Vec& m() const { return m_; }
  double lambda(size_t k) const { return lambda_[k]; }

 private:
  Lattice L_;
  std::vector<double> lambda_;
  std::vector<CellFractions> I_;
  CellFractionWork work_;
  Vec m_, m_new_;                  // m at the particles (1 outside the support), and the new one
  std::vector<int> support_, support_new_;  // particles with some I_k > 0
  std::vector<char> in_new_;
  std::vector<int> at_;             // the changes sent to the fluid
  std::vector<double> val_;
};

}  // namespace sphib
