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
#include "fluid/algebra/row_stencil.hpp"
#include "fluid/common/types.hpp"
#include "kernels/stencil_rows.hpp"  // the rows' inner loops

namespace sphib::stencil {

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
