#pragma once
// The passes of EPSPH's step fused with the products they follow (fluid/algebra/products.hpp): one pass
// over a sparsity pattern computes the operators' sums for a block of rows and, while those rows
// are in L1, the row-local arithmetic that consumes them, instead of writing the sums to N-sized
// arrays and reading them back in further passes. Each row's arithmetic is the unfused code's, in
// the same order, so the results are bitwise those of the separate products and loops
// (tests/test_fused_passes.cpp compares them).
//
// Image terms (B c with the wall offsets c) touch only rows near walls: the callers keep them in
// N x 2 arrays that are zero elsewhere, and the passes read them only in the blocks that hold such
// rows (elsewhere they add the literal zero those arrays hold, which keeps the bits).
#include <vector>

#include "fluid/algebra/gauge.hpp"
#include "fluid/algebra/operators.hpp"
#include "fluid/algebra/products.hpp"

namespace sphib {

// Which stencil blocks and rows have image terms in any of the image operators `Bs`.
struct ImageRows {
  ImageRows() = default;
  ImageRows(const RowStencil* st, int n, std::initializer_list<const SpMat*> Bs);
  std::vector<char> block;  // by RowStencil::blocks index
};

// Eqs. (28), (39)-(41): the right-hand side of the Crank-Nicolson predictor with the AB2 convection,
// from lap u^n, Gx u^n, Gy u^n (one pattern, one stencil: find_row_stencil({lap, Gx, Gy})) in one
// pass. All fields N x 2, column-major. Row by row, component c:
//   n_c      = (Gx u_c + cwx_c) u + (Gy u_c + cwy_c) v            (Eqs. 40-41; cwx, cwy = B c^n)
//   conv_c   = 3/2 n_c - 1/2 (first ? n_c : conv_old_c);  conv_old_c = n_c   (Eq. 39, AB2)
//   rhs_c    = ((lap u_c + bc_c) + lw_c) a + u_c + k F_c - kc conv_c          (Eq. 28)
// with bc = B c* of the Laplacian (this step's images) and lw = B c^n. Without convection
// (conv_old == nullptr) only the Laplacian is applied and conv_c is read from `conv`.
struct PredictorRhs {
  const SpMat *lap, *gx, *gy;
  const RowStencil* st;
  const ImageRows* images;
  const double *u, *F, *bc, *lw, *cwx, *cwy;
  double a, k, kc;
  bool first;
  double* conv_old;    // N^{n-1} in, N^n out (nullptr: Stokes flow)
  const double* conv;  // Stokes flow: the convection term to subtract (zero)
  double* rhs;
};
void predictor_rhs(const PredictorRhs& p);

// The exact projection's right-hand sides (exact_projection.hpp) in one pass over the pattern of
// the transposed gradients (Gy^T, -Gx^T): row by row
//   cu    = Gy^T u - Gx^T v                       (C^T u*)
//   b_psi = cu - Q flux  (Q != 0), else cu        (the normal equations' right-hand side)
//   b_m   = (cu + Q mflux) scale                  (the markers' psi_m; when b_m is given)
struct CurlTransposeRhs {
  const SpMat *ty, *tx;
  const RowStencil* st;
  const double* u;  // N x 2
  double Q, scale;
  const double *flux, *mflux;
  double *cu, *b_psi, *b_m;
};
void curl_transpose_rhs(const CurlTransposeRhs& p);

// The exact projection's velocity (exact_projection.hpp) in one pass over the velocity pattern:
// row by row, from the curl of psi (Gx psi, Gy psi) and the flux Q,
//   u^{n+1}   = (Gy psi + Q by1, -(Gx psi + Q bx1))  (+ u*'s alternating modes: `modes`, by the
//               parity class par[i] = 2 (i_y & 1) + (i_x & 1))
//   grad phi  = r (u* - u^{n+1})                     (Eq. 34 read backwards, r = rho/dt)
// by1, bx1 are read in the blocks with image terms only (`images`: those of Gx, Gy).
struct CurlVelocity {
  const SpMat *gx, *gy;
  const RowStencil* st;
  const ImageRows* images;
  const double* psi;
  double Q, r;
  const double *by1, *bx1, *u_star;
  const unsigned char* par;
  int nx;  // the lattice's row length
  VelocityModes::Addends modes;
  double *u, *grad_phi;  // N x 2
};
void curl_velocity(const CurlVelocity& p);

}  // namespace sphib
