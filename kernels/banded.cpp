#include "kernels/banded.hpp"

#include <algorithm>
#include <cstddef>
#include <type_traits>

#pragma GCC diagnostic ignored "-Wpsabi"  // (Pair4 lives only inside the inlined rows: no call passes one)

namespace sphib {

namespace {

// One row of a substitution over the n values of h's row i (every wavenumber, real and imaginary
// parts alike): h_i = (h_i - l_1 h_{i -+ 1} - ... - l_D h_{i -+ D}) / L(i, i), the terms subtracted
// one by one in the order of d, then the product by 1 / L(i, i): the arithmetic of a loop over d of
// whole-row updates, each value kept in a register instead of the row stored after every d.
template <int D>
[[gnu::always_inline]] inline void substitute_row(double* __restrict hi, const double* const* hj, const double* const* l,
                                                  const double* __restrict r, int n) {
  const double* __restrict h1 = hj[0];
  const double* __restrict h2 = hj[D > 1 ? 1 : 0];
  const double* __restrict h3 = hj[D > 2 ? 2 : 0];
  const double* __restrict h4 = hj[D > 3 ? 3 : 0];
  const double* __restrict l1 = l[0];
  const double* __restrict l2 = l[D > 1 ? 1 : 0];
  const double* __restrict l3 = l[D > 2 ? 2 : 0];
  const double* __restrict l4 = l[D > 3 ? 3 : 0];
  for (int m = 0; m < n; ++m) {
    double a = hi[m];
    if (D > 0) a -= l1[m] * h1[m];
    if (D > 1) a -= l2[m] * h2[m];
    if (D > 2) a -= l3[m] * h3[m];
    if (D > 3) a -= l4[m] * h4[m];
    hi[m] = a * r[m];
  }
}

typedef double Pair4 __attribute__((vector_size(32)));
typedef double Pair4u __attribute__((vector_size(32), aligned(8), may_alias));
// (f[0], f[0], f[1], f[1]): two wavenumbers' factor for their real and imaginary parts
[[gnu::always_inline]] inline Pair4 twice(const double* f) { return Pair4{f[0], f[0], f[1], f[1]}; }
[[gnu::always_inline]] inline Pair4 load_pair4(const double* p) { return *reinterpret_cast<const Pair4u*>(p); }

// substitute_row for complex rows, (re, im) of wavenumber k at 2k and 2k + 1, whose factors are
// the same for both parts and stored once per wavenumber (k): two wavenumbers at a time, each
// value by substitute_row's expressions (the same bits), the factors read once instead of twice.
template <int D>
[[gnu::always_inline]] inline void substitute_row_pairs(double* __restrict hi, const double* const* hj,
                                                        const double* const* l, const double* __restrict r,
                                                        int nk) {
  int k = 0;
  for (; k + 2 <= nk; k += 2) {
    const int m = 2 * k;
    Pair4 a = load_pair4(hi + m);
    if (D > 0) a = a - twice(l[0] + k) * load_pair4(hj[0] + m);
    if (D > 1) a = a - twice(l[1] + k) * load_pair4(hj[1] + m);
    if (D > 2) a = a - twice(l[2] + k) * load_pair4(hj[2] + m);
    if (D > 3) a = a - twice(l[3] + k) * load_pair4(hj[3] + m);
    *reinterpret_cast<Pair4u*>(hi + m) = a * twice(r + k);
  }
  for (; k < nk; ++k)
    for (int m = 2 * k; m < 2 * k + 2; ++m) {
      double a = hi[m];
      for (int d = 0; d < D; ++d) a -= l[d][k] * hj[d][m];
      hi[m] = a * r[k];
    }
}

// Rows reaching at most 4 neighbours by substitute_row(_pairs), each value in a register; rows
// reaching more (wide kernels) by the loop over d of whole-row updates (the same arithmetic).
// Compiled twice (AVX2 and SSE2, chosen at load time; no FMA).
}  // namespace

[[gnu::target_clones("avx2", "default")]] void substitute_bands(double* h, const BandedFactors& f, int k0, int k1) {
  const int ny = f.ny, w = f.w, ldab = f.ldab, nk_all = f.nk;
  const bool pairs = f.pairs;
  const double *lrow = f.lrow, *lcol = f.lcol, *rdiag = f.rdiag;
  const int stride = pairs ? 2 * nk_all : nk_all;  // a row of h
  const int nk = k1 - k0, n = pairs ? 2 * nk : nk;  // with pairs, value m of a row has factor m / 2
  h += pairs ? 2 * k0 : k0;
  rdiag += k0;
  lrow += k0;
  lcol += k0;
  auto row = [&](int i, int dir, const double* f, int dmax) __attribute__((always_inline)) {
    double* hi = h + static_cast<std::size_t>(i) * stride;
    const double* r = rdiag + static_cast<std::size_t>(i) * nk_all;
    auto hd = [&](int d) { return h + static_cast<std::size_t>(i + dir * d) * stride; };      // h_{i -+ d}
    auto ld = [&](int d) { return f + (static_cast<std::size_t>(i) * ldab + d) * nk_all; };  // l_d
    if (dmax > 4 && pairs) {  // whole-row updates, two wavenumbers (four values) at a time
      const int k2 = nk / 2 * 2;
      for (int d = 1; d <= dmax; ++d) {
        const double *hj = hd(d), *l = ld(d);
        for (int k = 0; k < k2; k += 2)
          *reinterpret_cast<Pair4u*>(hi + 2 * k) = load_pair4(hi + 2 * k) - twice(l + k) * load_pair4(hj + 2 * k);
        for (int m = 2 * k2; m < n; ++m) hi[m] -= l[m >> 1] * hj[m];
      }
      for (int k = 0; k < k2; k += 2) *reinterpret_cast<Pair4u*>(hi + 2 * k) = load_pair4(hi + 2 * k) * twice(r + k);
      for (int m = 2 * k2; m < n; ++m) hi[m] *= r[m >> 1];
      return;
    }
    if (dmax > 4) {
      for (int d = 1; d <= dmax; ++d) {
        const double *hj = hd(d), *l = ld(d);
        for (int m = 0; m < n; ++m) hi[m] -= l[m] * hj[m];
      }
      for (int m = 0; m < n; ++m) hi[m] *= r[m];
      return;
    }
    const double* hj[4] = {hi, hi, hi, hi};
    const double* l[4] = {r, r, r, r};
    for (int d = 1; d <= dmax; ++d) {
      hj[d - 1] = hd(d);
      l[d - 1] = ld(d);
    }
    auto depth = [&](auto D) __attribute__((always_inline)) {  // D: dmax as a constant
      if (pairs) substitute_row_pairs<decltype(D)::value>(hi, hj, l, r, nk);
      else substitute_row<decltype(D)::value>(hi, hj, l, r, n);
    };
    switch (dmax) {
      case 0: depth(std::integral_constant<int, 0>{}); break;
      case 1: depth(std::integral_constant<int, 1>{}); break;
      case 2: depth(std::integral_constant<int, 2>{}); break;
      case 3: depth(std::integral_constant<int, 3>{}); break;
      default: depth(std::integral_constant<int, 4>{});
    }
  };
  for (int i = 0; i < ny; ++i) row(i, -1, lrow, std::min(w, i));                // L y = b
  for (int i = ny - 1; i >= 0; --i) row(i, +1, lcol, std::min(w, ny - 1 - i));  // L' x = y
}

void substitute_bands_plain(double* h, const BandedFactors& f, int k0, int k1) {
  const int n = f.pairs ? 2 * f.nk : f.nk;  // values per row of h
  auto H = [&](int i, int m) -> double& { return h[static_cast<std::size_t>(i) * n + m]; };
  auto L = [&](const double* band, int i, int d, int k) { return band[(static_cast<std::size_t>(i) * f.ldab + d) * f.nk + k]; };
  for (int k = k0; k < k1; ++k)
    for (int part = 0; part < (f.pairs ? 2 : 1); ++part) {
      const int m = f.pairs ? 2 * k + part : k;
      for (int i = 0; i < f.ny; ++i) {  // L y = b: y_i = (b_i - sum_d L(i, i - d) y_{i - d}) / L(i, i)
        double a = H(i, m);
        for (int d = 1; d <= std::min(f.w, i); ++d) a -= L(f.lrow, i, d, k) * H(i - d, m);
        H(i, m) = a * f.rdiag[static_cast<std::size_t>(i) * f.nk + k];
      }
      for (int i = f.ny - 1; i >= 0; --i) {  // L' x = y: x_i = (y_i - sum_d L(i + d, i) x_{i + d}) / L(i, i)
        double a = H(i, m);
        for (int d = 1; d <= std::min(f.w, f.ny - 1 - i); ++d) a -= L(f.lcol, i, d, k) * H(i + d, m);
        H(i, m) = a * f.rdiag[static_cast<std::size_t>(i) * f.nk + k];
      }
    }
}

}  // namespace sphib
