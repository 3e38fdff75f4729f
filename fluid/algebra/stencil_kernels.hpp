#pragma once
// The machinery behind fluid/algebra/products.hpp and fluid/eulerian/fused_passes.hpp (not a public header): one
// pass over a sparsity pattern that sums, for every row, NW operators of that pattern applied to NI
// inputs into accumulators, and hands them, a block of rows at a time, to an epilogue that makes
// the outputs (a copy, a sum, or a fused pass's row-local arithmetic).
//
// Every row's sums are the sequential sums of its terms in the compressed row's order, whether the
// row is applied as a stencil (RowStencil) or from the compressed arrays: the results do not
// depend on the path, the vector width (the SSE2 and AVX2 clones of the callers; no FMA) or the
// thread count.
#include <algorithm>
#include <cstring>

#include "fluid/algebra/row_stencil.hpp"
#include "fluid/common/types.hpp"

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

// Every row once: the stencil's blocks by block(blk), plain rows by row(i). With OpenMP and at
// least kParallelRows rows, blocks and rows are shared among the threads.
template <class Row, class Blk>
void for_rows(int n, const RowStencil* st, Row&& row, Blk&& block) {
  const bool par = n >= kParallelRows;
  (void)par;
  if (!st || st->classes.empty()) {
#pragma omp parallel for schedule(static) if (par)
    for (int i = 0; i < n; ++i) row(i);
    return;
  }
  const int nb = static_cast<int>(st->blocks.size()), nr = static_cast<int>(st->rest.size());
#pragma omp parallel if (par)
  {
#pragma omp for schedule(static) nowait
    for (int k = 0; k < nb; ++k) block(st->blocks[k]);
#pragma omp for schedule(static)
    for (int k = 0; k < nr; ++k) row(st->rest[k]);
  }
}

// Operator j's coefficients in a class's reference row: w[j] = val[j] + o[ref].
template <int NW>
inline void class_weights(const RowStencil::Class& cl, const int* o, const double* const* val, const double** w) {
  for (int j = 0; j < NW; ++j) w[j] = val[j] + o[cl.ref];
}

// accumulate() over one block of the stencil (its class's offsets; contiguous or strided rows).
template <int NI, int NW, bool Diag>
[[gnu::always_inline]] inline void accumulate_block(const RowStencil::Class& cl, const RowStencil::Block& k,
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

// One pass of NW operators of one pattern (A's; values val[j]) over NI inputs: every stencil block
// by block(cl, k, w) (a clone that accumulates and finishes its rows), every other row by
// accumulate_row and finish(acc, i, 1, 1) (finish(acc, b, m, stride): the epilogue of rows
// b + t stride, t < m).
template <int NI, int NW, bool Diag, class Block, class Finish>
void pass(const SpMat& A, const double* const* val, const double* const* in, const RowStencil* st, Block&& block,
          Finish&& finish) {
  const int* o = A.outerIndexPtr();
  const int* c = A.innerIndexPtr();
  auto row = [&](int i) {
    double acc[Diag ? NI : NI * NW][kBlock];
    accumulate_row<NI, NW, Diag>(o, c, val, in, acc, i);
    finish(static_cast<const double(*)[kBlock]>(acc), i, 1, 1);
  };
  for_rows(static_cast<int>(A.rows()), st, row, [&](const RowStencil::Block& k) {
    const double* w[NW];
    class_weights<NW>(st->classes[k.cls], o, val, w);
    block(st->classes[k.cls], k, static_cast<const double* const*>(w));
  });
}

}  // namespace sphib::stencil
