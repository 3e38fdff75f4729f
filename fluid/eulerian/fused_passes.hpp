#pragma once
// The passes of EPSPH's step fused with the products they follow (fluid/algebra/products.hpp): one pass
// over a sparsity pattern computes the operators' sums for a block of rows and, while those rows
// are in L1, the row-local arithmetic that consumes them, instead of writing the sums to N-sized
// arrays and reading them back in further passes. The blocks' kernels and their plain forms are in
// kernels/fused_rows.hpp; here: the operators, the blocks and the threads. Each row's arithmetic is
// the unfused code's, in the same order, so the results are bitwise those of the separate products
// and loops (tests/test_fused_passes.cpp compares them).
//
// Image terms (B c with the wall offsets c) touch only rows near walls: the callers keep them in
// N x 2 arrays that are zero elsewhere, and the passes read them only in the blocks that hold such
// rows (elsewhere they add the literal zero those arrays hold, which keeps the bits).
#include <vector>

#include "fluid/algebra/operators.hpp"
#include "fluid/algebra/products.hpp"
#include "kernels/fused_rows.hpp"

namespace sphib {

// Which stencil blocks and rows have image terms in any of the image operators `Bs`.
struct ImageRows {
  ImageRows() = default;
  ImageRows(const RowStencil* st, int n, std::initializer_list<const SpMat*> Bs);
  std::vector<char> block;  // by RowStencil::blocks index
};

// Eqs. (28), (39)-(41): the right-hand side of the Crank-Nicolson predictor with the AB2 convection
// (kernels/fused_rows.hpp, PredictorRows, says row by row what it computes) from lap u^n, Gx u^n,
// Gy u^n (one pattern, one stencil: find_row_stencil({lap, Gx, Gy})) in one pass. rows.n is set here.
struct PredictorRhs {
  const SpMat *lap, *gx, *gy;
  const RowStencil* st;
  const ImageRows* images;
  PredictorRows rows;
};
void predictor_rhs(const PredictorRhs& p);

// The exact projection's right-hand sides (exact_projection.hpp; kernels/fused_rows.hpp,
// CurlTransposeRows) in one pass over the pattern of the transposed gradients (Gy^T, -Gx^T) applied
// to u (N x 2).
struct CurlTransposeRhs {
  const SpMat *ty, *tx;
  const RowStencil* st;
  const double* u;
  CurlTransposeRows rows;
};
void curl_transpose_rhs(const CurlTransposeRhs& p);

// The exact projection's velocity (exact_projection.hpp; kernels/fused_rows.hpp, CurlVelocityRows)
// in one pass over the velocity pattern (Gx, Gy) applied to psi; by1, bx1 are read in the blocks
// with image terms only (`images`: those of Gx, Gy). rows.n is set here.
struct CurlVelocity {
  const SpMat *gx, *gy;
  const RowStencil* st;
  const ImageRows* images;
  const double* psi;
  CurlVelocityRows rows;
};
void curl_velocity(const CurlVelocity& p);

}  // namespace sphib
