#pragma once
// The units of work of the stencil kernels (kernels/stencil_rows.hpp): classes of rows that are
// translates of one reference row, and blocks of rows of one class.
#include <vector>

namespace sphib {

// A class of rows: translates of its reference row (the same column offsets j - i and, in every
// operator, the same coefficient bits).
struct StencilClass {
  int ref = -1;             // the reference row
  std::vector<int> offset;  // its column offsets j - ref, in the row's own (column) order
};
// Rows begin + k stride, k < count, all of one class (at most stencil::kBlock rows).
struct StencilBlock {
  int cls, begin, count, stride;
};

}  // namespace sphib
