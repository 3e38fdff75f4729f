#include "kernels/stencil_products.hpp"

#include "kernels/stencil_rows.hpp"

namespace sphib {

using stencil::kBlock;

// Compiled twice (SSE2 and AVX2, chosen at load time; no FMA, so both give the same bits). Each
// accumulates a block and stores it.
[[gnu::target_clones("avx2", "default")]] void block_apply2(const StencilClass& cl, const StencilBlock& k,
                                                           const double* const* w, const double* const* in,
                                                           double* const* out) {
  double acc[2][kBlock];
  stencil::accumulate_block<2, 1, false>(cl, k, w, in, acc);
  stencil::store<2>(acc, out, k.begin, k.count, k.stride);
}
[[gnu::target_clones("avx2", "default")]] void block_apply1(const StencilClass& cl, const StencilBlock& k,
                                                           const double* const* w, const double* const* in,
                                                           double* const* out) {
  double acc[1][kBlock];
  stencil::accumulate_block<1, 1, false>(cl, k, w, in, acc);
  stencil::store<1>(acc, out, k.begin, k.count, k.stride);
}
[[gnu::target_clones("avx2", "default")]] void block_gradient2(const StencilClass& cl, const StencilBlock& k,
                                                              const double* const* w, const double* const* in,
                                                              double* const* out) {
  double acc[4][kBlock];
  stencil::accumulate_block<2, 2, false>(cl, k, w, in, acc);
  stencil::store<4>(acc, out, k.begin, k.count, k.stride);
}
[[gnu::target_clones("avx2", "default")]] void block_divergence(const StencilClass& cl, const StencilBlock& k,
                                                               const double* const* w, const double* const* in,
                                                               double* const* out) {
  double acc[2][kBlock];
  stencil::accumulate_block<2, 2, true>(cl, k, w, in, acc);
  stencil::store_sum(acc, out, k.begin, k.count, k.stride);
}
[[gnu::target_clones("avx2", "default")]] void block_gradient(const StencilClass& cl, const StencilBlock& k,
                                                             const double* const* w, const double* const* in,
                                                             double* const* out) {
  double acc[2][kBlock];
  stencil::accumulate_block<1, 2, false>(cl, k, w, in, acc);
  stencil::store<2>(acc, out, k.begin, k.count, k.stride);
}

namespace {

// y_row = sum_s w_j[s] x_c[row + off_s] for every row of the block: operator j on input c
double row_sum(const StencilClass& cl, const double* w, const double* x, int row) {
  double y = 0.0;
  for (size_t s = 0; s < cl.offset.size(); ++s) y += w[s] * x[row + cl.offset[s]];
  return y;
}
template <class F>
void each_row(const StencilBlock& k, F&& f) {
  for (int t = 0; t < k.count; ++t) f(k.begin + t * k.stride);
}

}  // namespace

void block_apply2_plain(const StencilClass& cl, const StencilBlock& k, const double* const* w,
                        const double* const* in, double* const* out) {
  each_row(k, [&](int i) {
    out[0][i] = row_sum(cl, w[0], in[0], i);
    out[1][i] = row_sum(cl, w[0], in[1], i);
  });
}
void block_apply1_plain(const StencilClass& cl, const StencilBlock& k, const double* const* w,
                        const double* const* in, double* const* out) {
  each_row(k, [&](int i) { out[0][i] = row_sum(cl, w[0], in[0], i); });
}
void block_gradient2_plain(const StencilClass& cl, const StencilBlock& k, const double* const* w,
                           const double* const* in, double* const* out) {
  each_row(k, [&](int i) {
    for (int j = 0; j < 2; ++j)
      for (int c = 0; c < 2; ++c) out[j * 2 + c][i] = row_sum(cl, w[j], in[c], i);
  });
}
void block_divergence_plain(const StencilClass& cl, const StencilBlock& k, const double* const* w,
                            const double* const* in, double* const* out) {
  each_row(k, [&](int i) { out[0][i] = row_sum(cl, w[0], in[0], i) + row_sum(cl, w[1], in[1], i); });
}
void block_gradient_plain(const StencilClass& cl, const StencilBlock& k, const double* const* w,
                          const double* const* in, double* const* out) {
  each_row(k, [&](int i) {
    out[0][i] = row_sum(cl, w[0], in[0], i);
    out[1][i] = row_sum(cl, w[1], in[0], i);
  });
}

}  // namespace sphib
