#pragma once
// Rows of sparse operators applied as stencils, the inner loops of the fused products
// (fluid/algebra/products.hpp, fluid/eulerian/fused_passes.hpp): NW operators of one sparsity
// pattern applied to NI inputs, for a block of rows that are translates of one reference row
// (a class: the same column offsets and coefficients),
//   acc[j NI + c][t] = sum_s w_j[s] in_c[row_t + off_s]     (Diag: only j = c, in acc[c]),
// every sum the sequential sum of its terms in the row's own order, whether four rows at a time
// (lanes) or one, so the results depend neither on the path nor on the vector width (the SSE2 and
// AVX2 clones of the callers; no FMA). The caller owns the threads and the blocks.
#include <algorithm>

#include "kernels/stencil_block.hpp"

namespace sphib::stencil {

constexpr int kBlock = 256;  // rows per stencil block (RowStencil::Block): the accumulators stay in L1

// The vector type is only ever used inside always_inline functions: no call passes one, so the
// ABI note GCC gives for it in the SSE2 clones does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

// Four doubles (GCC's vector extension): AVX2 registers in the AVX2 clones, two SSE2 registers in
// the others; +, * lane by lane (no FMA), so every lane's arithmetic is the scalar one.
typedef double v4d __attribute__((vector_size(32)));
typedef double v4d_unaligned __attribute__((vector_size(32), aligned(8), may_alias));  // loads and stores

// p[0], p[st], p[2 st], p[3 st] (contiguous when !Strided)
template <bool Strided>
[[gnu::always_inline]] inline v4d load4(const double* p, int st) {
  if (Strided) return v4d{p[0], p[st], p[2 * st], p[3 * st]};
  return *reinterpret_cast<const v4d_unaligned*>(p);
}

// acc[a][t .. t + 4V) for the rows b + t stride, ... of one class (offsets `off`, S of them;
// coefficient sets w[j] from its reference row): acc[j NI + c] = sum_s w_j[s] in_c[row + off_s]
// (Diag: only j = c, in acc[c]). The sums stay in registers, each added term by term in the row's
// own order.
template <int NI, int NW, bool Diag, bool Strided, int V>
[[gnu::always_inline]] inline void accumulate_vectors(const int* off, int S, const double* const* w,
                                                      const double* const* in, double (*acc)[kBlock], int b,
                                                      int t, int st) {
  constexpr int NA = Diag ? NI : NI * NW;
  v4d A[NA][V];
  for (int a = 0; a < NA; ++a)
    for (int v = 0; v < V; ++v) A[a][v] = v4d{0.0, 0.0, 0.0, 0.0};
  const int row = b + t * st;
  for (int s = 0; s < S; ++s) {
    v4d x[NI][V];
    for (int c = 0; c < NI; ++c)
      for (int v = 0; v < V; ++v) x[c][v] = load4<Strided>(in[c] + row + 4 * v * st + off[s], st);
    for (int j = 0; j < NW; ++j) {
      const double cw = w[j][s];
      const v4d wv = {cw, cw, cw, cw};
      for (int c = 0; c < NI; ++c) {
        if (Diag && j != c) continue;
        for (int v = 0; v < V; ++v) A[Diag ? c : j * NI + c][v] = A[Diag ? c : j * NI + c][v] + wv * x[c][v];
      }
    }
  }
  for (int a = 0; a < NA; ++a)
    for (int v = 0; v < V; ++v) *reinterpret_cast<v4d_unaligned*>(&acc[a][t + 4 * v]) = A[a][v];
}

// acc[a][t] for the rows b + t stride, t < m, of one class: 8 accumulator registers at a time
// (4V rows), then 4 rows at a time, the last m mod 4 rows one by one in the same order.
template <int NI, int NW, bool Diag, bool Strided>
[[gnu::always_inline]] inline void accumulate(const int* off, int S, const double* const* w, const double* const* in,
                                              double (*acc)[kBlock], int b, int m, int stride) {
  constexpr int NA = Diag ? NI : NI * NW;
  constexpr int V = NA >= 8 ? 1 : 8 / NA;
  const int st = Strided ? stride : 1;
  int t = 0;
  for (; t + 4 * V <= m; t += 4 * V) accumulate_vectors<NI, NW, Diag, Strided, V>(off, S, w, in, acc, b, t, st);
  if (V > 1)
    for (; t + 4 <= m; t += 4) accumulate_vectors<NI, NW, Diag, Strided, 1>(off, S, w, in, acc, b, t, st);
  for (; t < m; ++t) {
    double A[NA] = {};
    const int row = b + t * st;
    for (int s = 0; s < S; ++s)
      for (int c = 0; c < NI; ++c) {
        const double x = in[c][row + off[s]];
        for (int j = 0; j < NW; ++j) {
          if (Diag && j != c) continue;
          A[Diag ? c : j * NI + c] += w[j][s] * x;
        }
      }
    for (int a = 0; a < NA; ++a) acc[a][t] = A[a];
  }
}

// The same for one row i from the compressed arrays (o, col: the pattern; val[j]: operator j's
// values), into acc[a][0].
template <int NI, int NW, bool Diag>
[[gnu::always_inline]] inline void accumulate_row(const int* o, const int* col, const double* const* val,
                                                  const double* const* in, double (*acc)[kBlock], int i) {
  constexpr int NA = Diag ? NI : NI * NW;
  double s[NA];
  for (int a = 0; a < NA; ++a) s[a] = 0.0;
  for (int k = o[i]; k < o[i + 1]; ++k)
    for (int c = 0; c < NI; ++c) {
      const double x = in[c][col[k]];
      for (int j = 0; j < NW; ++j) {
        if (Diag && j != c) continue;
        s[Diag ? c : j * NI + c] += val[j][k] * x;
      }
    }
  for (int a = 0; a < NA; ++a) acc[a][0] = s[a];
}

// accumulate() over one block of the stencil (its class's offsets; contiguous or strided rows).
template <int NI, int NW, bool Diag>
[[gnu::always_inline]] inline void accumulate_block(const StencilClass& cl, const StencilBlock& k,
                                                    const double* const* w, const double* const* in,
                                                    double (*acc)[kBlock]) {
  const int S = static_cast<int>(cl.offset.size());
  if (k.stride == 1) accumulate<NI, NW, Diag, false>(cl.offset.data(), S, w, in, acc, k.begin, k.count, 1);
  else accumulate<NI, NW, Diag, true>(cl.offset.data(), S, w, in, acc, k.begin, k.count, k.stride);
}

// out[a][row t of the block] = acc[a][t], a < NA
template <int NA>
[[gnu::always_inline]] inline void store(const double (*acc)[kBlock], double* const* out, int b, int m, int stride) {
  for (int a = 0; a < NA; ++a) {
    if (stride == 1) std::copy(acc[a], acc[a] + m, out[a] + b);
    else
      for (int t = 0; t < m; ++t) out[a][b + t * stride] = acc[a][t];
  }
}

// out[0][row t of the block] = acc[0][t] + acc[1][t] (the divergence's two terms)
[[gnu::always_inline]] inline void store_sum(const double (*acc)[kBlock], double* const* out, int b, int m, int st) {
  for (int t = 0; t < m; ++t) out[0][b + t * st] = acc[0][t] + acc[1][t];
}

}  // namespace sphib::stencil
