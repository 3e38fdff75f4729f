#include "kernels/spread.hpp"
#include "kernels/cubic_spline_lanes.hpp"

// Four-lane values (Lanes4) live only inside the inlined kernel of the AVX2 and default clones.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace sphib {

// Row by row: W at every point of a row, four lanes at a time (the padding lanes beyond 2h*), then
// added along the row. Compiled twice (AVX2 and SSE2, chosen at load time; no FMA, so both give the
// same bits). The points are distinct, so their order is immaterial to the bits.
[[gnu::target_clones("avx2", "default")]] void spread_rows(const LatticeRows& box, const CubicSpline& W, double fx,
                                                          double fy, double* __restrict Fx, double* __restrict Fy) {
  const int ncol = box.ncol, nlanes = (ncol + 3) / 4 * 4;
  const double support = 2.0 * W.h, beyond = 4.0 * support * support;  // the padding lanes: W = 0
  alignas(32) double cdx2[LatticeRows::kMaxCols + 4], w[LatticeRows::kMaxCols + 4];
  for (int c = 0; c < nlanes; ++c) cdx2[c] = c < ncol ? box.cdx[c] * box.cdx[c] : beyond;
  const bool contiguous = ncol > 0 && box.col[ncol - 1] - box.col[0] == ncol - 1;  // no periodic wrap
  for (int r = 0; r < box.nrow; ++r) {
    const double ry2 = box.ry[r] * box.ry[r];
    for (int c = 0; c < nlanes; c += 4) {
#if defined(__clang__)
      // clang refuses a 256-bit vector argument in the default clone (no AVX there, a different
      // ABI): two two-lane halves instead, each lane by the same expressions, so the same values.
      for (int half = c; half < c + 4; half += 2) {
        const Lanes2 wc = CubicSplineLanes<Lanes2>(W, Lanes2{cdx2[half], cdx2[half + 1]} + lanes2(ry2)).W();
        w[half] = wc[0];
        w[half + 1] = wc[1];
      }
#else
      Lanes4 d2;
      __builtin_memcpy(&d2, cdx2 + c, sizeof d2);
      const Lanes4 wc = CubicSplineLanes<Lanes4>(W, d2 + lanes(Lanes4{}, ry2)).W();  // W(x_i - X_k, h*)
      __builtin_memcpy(w + c, &wc, sizeof wc);
#endif
    }
    double* __restrict fxr = Fx + box.base[r];
    double* __restrict fyr = Fy + box.base[r];
    if (contiguous) {
      fxr += box.col[0];
      fyr += box.col[0];
      for (int c = 0; c < ncol; ++c) {
        fxr[c] += fx * w[c];  // Eq. (53)
        fyr[c] += fy * w[c];
      }
    } else {
      for (int c = 0; c < ncol; ++c) {
        fxr[box.col[c]] += fx * w[c];
        fyr[box.col[c]] += fy * w[c];
      }
    }
  }
}

void spread_rows_plain(const LatticeRows& box, const CubicSpline& W, double fx, double fy, double* Fx, double* Fy) {
  for (int r = 0; r < box.nrow; ++r)
    for (int c = 0; c < box.ncol; ++c) {
      const int i = box.base[r] + box.col[c];
      const double w = cubic_W(W, std::sqrt(box.cdx[c] * box.cdx[c] + box.ry[r] * box.ry[r]));  // W(x_i - X_k, h*)
      Fx[i] += fx * w;  // Eq. (53)
      Fy[i] += fy * w;
    }
}

// Two points at a time (SSE2), the kernel's branch-free two-lane form.
void spread_pairs(const MarkerPoints& nb, const CubicSpline& W, double fx, double fy, double* Fx, double* Fy) {
  for (int m = 0; m < nb.pairs; ++m) {
    const Lanes2 w = CubicSplineLanes<Lanes2>(W, Lanes2{nb.r2[2 * m], nb.r2[2 * m + 1]}).W();  // W(x_i - X_k, h*)
    const int i0 = nb.j[2 * m], i1 = nb.j[2 * m + 1];
    Fx[i0] += fx * w[0];  // Eq. (53)
    Fy[i0] += fy * w[0];
    Fx[i1] += fx * w[1];
    Fy[i1] += fy * w[1];
  }
}

void spread_pairs_plain(const MarkerPoints& nb, const CubicSpline& W, double fx, double fy, double* Fx, double* Fy) {
  for (int m = 0; m < 2 * nb.pairs; ++m) {
    const double w = cubic_W(W, std::sqrt(nb.r2[m]));  // W(x_i - X_k, h*)
    Fx[nb.j[m]] += fx * w;  // Eq. (53)
    Fy[nb.j[m]] += fy * w;
  }
}

}  // namespace sphib
