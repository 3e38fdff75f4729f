#pragma once
// The gauge's two passes over a lattice field f (nx by ny, row-major; fluid/algebra/gauge.hpp): the
// sums of each row's even and odd columns (the projections on the alternating modes
// (-1)^{sx i_x + sy i_y} are made of them) and the addition of a value alternating along a row.
// Each in its fast form and its plain form (the sum as written); tests/test_kernels.cpp checks they
// agree, bit for bit (the same sums in the same order).
namespace sphib {

// e[l] = sum_p f(2p, iy + l), o[l] = sum_p f(2p + 1, iy + l) for l < m (an odd nx's last column in e)
void row_sums(const double* f, int nx, int iy, int m, double* e, double* o);
void row_sums_plain(const double* f, int nx, int iy, int m, double* e, double* o);

// r[ix] += even at even ix, odd at odd ix (one row of nx values)
void add_alternating_row(double* r, int nx, double even, double odd);
void add_alternating_row_plain(double* r, int nx, double even, double odd);

}  // namespace sphib
