#pragma once
// The fixed lattice's sparse products on one block of stencil rows (fluid/algebra/products.hpp
// orchestrates them: blocks, threads, the rows that are no stencil): the SPH operators of
// Eqs. (27)-(34) assembled as matrices A and applied as y_i = sum_j A_ij x_j, over a block of rows
// of one class (offsets cl.offset, coefficient sets w[j] of its reference row):
//   apply2:     out[c] = A in[c], c < 2              (A: w[0]; two columns)
//   apply1:     out[0] = A in[0]
//   gradient2:  out[j 2 + c] = D_j in[c], j, c < 2   (D_0, D_1: w[0], w[1]; the four derivatives)
//   divergence: out[0] = D_0 in[0] + D_1 in[1]
//   gradient:   out[j] = D_j in[0], j < 2
// Each in its fast form (four rows in the lanes of a vector, AVX2 or SSE2 chosen at load time) and
// its plain form (each row's sum as written); the same terms in the same order, so they agree bit
// for bit (tests/test_kernels.cpp).
#include "kernels/stencil_block.hpp"

namespace sphib {

void block_apply2(const StencilClass& cl, const StencilBlock& k, const double* const* w, const double* const* in,
                  double* const* out);
void block_apply1(const StencilClass& cl, const StencilBlock& k, const double* const* w, const double* const* in,
                  double* const* out);
void block_gradient2(const StencilClass& cl, const StencilBlock& k, const double* const* w, const double* const* in,
                     double* const* out);
void block_divergence(const StencilClass& cl, const StencilBlock& k, const double* const* w, const double* const* in,
                      double* const* out);
void block_gradient(const StencilClass& cl, const StencilBlock& k, const double* const* w, const double* const* in,
                    double* const* out);

void block_apply2_plain(const StencilClass& cl, const StencilBlock& k, const double* const* w,
                        const double* const* in, double* const* out);
void block_apply1_plain(const StencilClass& cl, const StencilBlock& k, const double* const* w,
                        const double* const* in, double* const* out);
void block_gradient2_plain(const StencilClass& cl, const StencilBlock& k, const double* const* w,
                           const double* const* in, double* const* out);
void block_divergence_plain(const StencilClass& cl, const StencilBlock& k, const double* const* w,
                            const double* const* in, double* const* out);
void block_gradient_plain(const StencilClass& cl, const StencilBlock& k, const double* const* w,
                          const double* const* in, double* const* out);

}  // namespace sphib
