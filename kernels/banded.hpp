#pragma once
// The banded Cholesky substitutions of the lattice Poisson solver (fluid/algebra/fft_poisson.cpp),
// every wavenumber at once: after the transform along x, each wavenumber k has a banded system
// B_k x = b along y, factored B_k = L_k L_k' (half-bandwidth w), solved in place in h by
//   L y = b:   y_i = (b_i - sum_{d=1..min(w, i)} L_k(i, i - d) y_{i-d}) / L_k(i, i)
//   L' x = y:  x_i = (y_i - sum_{d=1..min(w, ny-1-i)} L_k(i + d, i) x_{i+d}) / L_k(i, i)
// (the division as the product by the stored 1 / L_k(i, i)). The fast form runs along whole rows
// of h (all wavenumbers side by side, lanes); the plain form one wavenumber at a time, as written.
// The same terms in the same order: they agree bit for bit (tests/test_kernels.cpp).
namespace sphib {

// h: row i at h + i n, n = 2 nk values with pairs ((re, im) of each wavenumber, one factor for
// both), else n = nk. Factors wavenumber-fastest: lrow[(i ldab + d) nk + k] = L_k(i, i - d),
// lcol[(i ldab + d) nk + k] = L_k(i + d, i), rdiag[i nk + k] = 1 / L_k(i, i).
struct BandedFactors {
  int ny, w, ldab, nk;
  bool pairs;
  const double *lrow, *lcol, *rdiag;
};

// Only the wavenumbers k0 <= k < k1 (k0 even): each wavenumber's values are computed alone, so
// disjoint ranges may run on different threads and give the bits of the whole range.
void substitute_bands(double* h, const BandedFactors& f, int k0, int k1);
void substitute_bands_plain(double* h, const BandedFactors& f, int k0, int k1);

}  // namespace sphib
