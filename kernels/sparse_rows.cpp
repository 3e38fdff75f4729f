#include "kernels/sparse_rows.hpp"

#include "kernels/lanes.hpp"

#pragma GCC diagnostic ignored "-Wpsabi"  // Lanes4 only inside rows3 (no call passes one)

namespace sphib {

// Compiled twice (AVX2 and SSE2, chosen at load time; no FMA: each lane's arithmetic is its scalar
// sum's, term by term).
[[gnu::target_clones("avx2", "default")]] void rows3(const Rows3& in, double* const* out, int i0, int i1) {
  using U4 = double __attribute__((vector_size(32), aligned(8), may_alias));
  for (int i = i0; i < i1; ++i) {
    Lanes4 s{0.0, 0.0, 0.0, 0.0};
    double t = 0.0;
    for (int p = in.o[i]; p < in.o[i + 1]; ++p) {
      const int c = in.col[p];
      const double a = in.lap[p], b = in.cn[p];
      s = s + Lanes4{a, a, b, b} * *reinterpret_cast<const U4*>(in.x4 + 4 * c);
      t += in.ph[p] * in.phi[c];
    }
    for (int m = 0; m < 4; ++m) out[m][i] = s[m];
    out[4][i] = 0.0 + t;
  }
}

void rows3_plain(const Rows3& in, double* const* out, int i0, int i1) {
  for (int i = i0; i < i1; ++i) {
    double u = 0, v = 0, cu = 0, cv = 0, t = 0;
    for (int p = in.o[i]; p < in.o[i + 1]; ++p) {
      const int c = in.col[p];
      u += in.lap[p] * in.x4[4 * c];
      v += in.lap[p] * in.x4[4 * c + 1];
      cu += in.cn[p] * in.x4[4 * c + 2];
      cv += in.cn[p] * in.x4[4 * c + 3];
      t += in.ph[p] * in.phi[c];
    }
    out[0][i] = u;
    out[1][i] = v;
    out[2][i] = cu;
    out[3][i] = cv;
    out[4][i] = 0.0 + t;
  }
}

}  // namespace sphib
