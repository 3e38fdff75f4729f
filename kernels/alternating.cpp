#include "kernels/alternating.hpp"

#include <cstddef>

namespace sphib {

// Four rows summed side by side: eight independent chains instead of two (a single chain waits on
// each add's latency), each chain the plain form's sum in its order.
void row_sums(const double* f, int nx, int iy, int m, double* e, double* o) {
  const int pairs = nx / 2;  // columns 2 p and 2 p + 1; an odd nx leaves the last column to e
  int l0 = 0;
  for (; l0 + 4 <= m; l0 += 4) {
    const double* r[4];
    double es[4] = {}, os[4] = {};
    for (int l = 0; l < 4; ++l) r[l] = f + static_cast<std::size_t>(nx) * (iy + l0 + l);
    for (int p = 0; p < pairs; ++p)
      for (int l = 0; l < 4; ++l) {
        es[l] += r[l][2 * p];
        os[l] += r[l][2 * p + 1];
      }
    for (int l = 0; l < 4; ++l) {
      if (nx % 2) es[l] += r[l][nx - 1];
      e[l0 + l] = es[l];
      o[l0 + l] = os[l];
    }
  }
  for (; l0 < m; ++l0) {
    const double* r = f + static_cast<std::size_t>(nx) * (iy + l0);
    double es = 0, os = 0;
    for (int p = 0; p < pairs; ++p) { es += r[2 * p]; os += r[2 * p + 1]; }
    if (nx % 2) es += r[nx - 1];
    e[l0] = es;
    o[l0] = os;
  }
}

void row_sums_plain(const double* f, int nx, int iy, int m, double* e, double* o) {
  for (int l = 0; l < m; ++l) {
    e[l] = o[l] = 0.0;
    for (int ix = 0; ix < nx; ++ix) (ix % 2 ? o[l] : e[l]) += f[static_cast<std::size_t>(nx) * (iy + l) + ix];
  }
}

// Two columns a step, compiled twice (AVX2 and SSE2, chosen at load time).
[[gnu::target_clones("avx2", "default")]] void add_alternating_row(double* r, int nx, double even, double odd) {
  int ix = 0;
  for (; ix + 1 < nx; ix += 2) { r[ix] += even; r[ix + 1] += odd; }
  if (ix < nx) r[ix] += even;
}

void add_alternating_row_plain(double* r, int nx, double even, double odd) {
  for (int ix = 0; ix < nx; ++ix) r[ix] += ix % 2 ? odd : even;
}

}  // namespace sphib
