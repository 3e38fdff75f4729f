#pragma once
// What a field's alternating (grid-scale) modes add to a lattice row, by its parity class.

namespace sphib {

// Row i of component c gets value[c][i_y & 1][i_x & 1] where has[c] (the parity class of row i:
// par[i] = 2 (i_y & 1) + (i_x & 1)).
struct ParityModes {
  bool has[2] = {false, false};
  double value[2][2][2] = {};
};

}  // namespace sphib
