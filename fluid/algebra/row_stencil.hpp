#pragma once
// The classes of lattice rows that the fused products apply as stencils (products.hpp says how), and
// the row count from which they use the threads: shared by the products and their kernels
// (stencil_kernels.hpp).
#include <vector>

#include "kernels/stencil_block.hpp"

namespace sphib {

// Rows from which the products use the threads: below, a fork and join (~1-3 us) costs more than
// it saves (measured with bench/scaling: docs/performance/scaling.md).
constexpr int kParallelRows = 8192;

struct RowStencil {
  // A class of rows: translates of its reference row. Class 0 holds the most common row (the
  // interior); the others the rows near walls and periodic seams that repeat along them.
  using Class = StencilClass;
  // The work units of the products and their threads (at most 256 rows; stride 1 along a wall, the
  // lattice's row length along a seam).
  using Block = StencilBlock;
  std::vector<Class> classes;
  std::vector<Block> blocks;
  std::vector<int> rest;  // every other row, applied from the compressed arrays
  int stencil_rows() const;
};

}  // namespace sphib
