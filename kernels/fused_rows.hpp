#pragma once
// EPSPH's fused passes on one block of stencil rows (fluid/eulerian/fused_passes.hpp orchestrates
// them: the operators, the blocks, the threads, the rows that are no stencil): the sums of the
// operators of one sparsity pattern (kernels/stencil_rows.hpp) and, while those rows are in L1, the
// row-local arithmetic that consumes them. Each pass in its fast form (the sums four rows at a
// time in the lanes of a vector, AVX2 or SSE2 chosen at load time) and its plain form (each row's
// sums and arithmetic as written, one row at a time); the same terms in the same order, so they
// agree bit for bit (tests/test_kernels.cpp).
//
// All fields are N x 2, column-major (column c of f at f + c N). Image terms (B c, with the wall
// offsets c) are nonzero only in rows near walls: `images` says whether a block holds such rows;
// where it does not, the fast forms add the literal zero the image arrays hold there instead of
// reading them.
#include "kernels/parity_modes.hpp"
#include "kernels/stencil_block.hpp"

namespace sphib {

// Eqs. (28), (39)-(41): the right-hand side of the Crank-Nicolson predictor with the AB2 convection.
// Operators w[0] = lap, w[1] = d/dx, w[2] = d/dy (one pattern) applied to in = (u, v). Row by row,
// component c:
//   n_c    = (Gx u_c + cwx_c) u + (Gy u_c + cwy_c) v                     (Eqs. 40-41; cwx, cwy = B c^n)
//   conv_c = 3/2 n_c - 1/2 (first ? n_c : conv_old_c);  conv_old_c = n_c  (Eq. 39, AB2)
//   rhs_c  = ((lap u_c + bc_c) + lw_c) a + u_c + k F_c - kc conv_c        (Eq. 28)
// with bc = B c* of the Laplacian (this step's images) and lw = B c^n. Without convection
// (conv_old == nullptr) only w[0] is applied and conv_c is read from `conv`.
struct PredictorRows {
  int n = 0;  // N
  const double *u = nullptr, *F = nullptr, *bc = nullptr, *lw = nullptr, *cwx = nullptr, *cwy = nullptr;
  double a = 0, k = 0, kc = 0;
  bool first = false;
  double* conv_old = nullptr;    // N^{n-1} in, N^n out (nullptr: Stokes flow)
  const double* conv = nullptr;  // Stokes flow: the convection term to subtract
  double* rhs = nullptr;
};
void block_predictor(const PredictorRows& p, bool images, const StencilClass& cl, const StencilBlock& k,
                     const double* const* w, const double* const* in);
// Row i outside the stencil, from its sums: *sums[j 2 + c] = operator j applied to column c.
void predictor_row(const PredictorRows& p, const double* const* sums, int i);
void block_predictor_plain(const PredictorRows& p, const StencilClass& cl, const StencilBlock& k,
                           const double* const* w, const double* const* in);

// The exact projection's right-hand sides (fluid/eulerian/exact_projection.hpp), with C psi =
// (Gy psi, -Gx psi) the curl of a stream function, G the SPH gradient of Eq. (27): the discrete
// vorticity C^T u* = Gy^T u - Gx^T v (w[0] = Gy^T on in[0] = u, w[1] = -Gx^T on in[1] = v), then
// row by row
//   cu    = Gy^T u - Gx^T v
//   b_psi = cu - Q flux  (Q != 0), else cu    (the stream function's normal equations)
//   b_m   = (cu + Q mflux) scale              (the markers' psi_m; when b_m is given)
struct CurlTransposeRows {
  double Q = 0, scale = 0;
  const double *flux = nullptr, *mflux = nullptr;
  double *cu = nullptr, *b_psi = nullptr, *b_m = nullptr;
};
void block_curl_transpose(const CurlTransposeRows& p, const StencilClass& cl, const StencilBlock& k,
                          const double* const* w, const double* const* in);
void curl_transpose_row(const CurlTransposeRows& p, const double* const* sums, int i);  // *sums: Gy^T u, -Gx^T v
void block_curl_transpose_plain(const CurlTransposeRows& p, const StencilClass& cl, const StencilBlock& k,
                                const double* const* w, const double* const* in);

// The exact projection's velocity from the stream function: w[0] = Gx, w[1] = Gy (Eq. 27) on
// in[0] = psi, then row by row the curl C psi = (Gy psi, -Gx psi) plus the flux and the modes
//   u^{n+1}  = (Gy psi + Q by1, -(Gx psi + Q bx1)) + u*'s alternating modes
//   grad phi = r (u* - u^{n+1})                      (Eq. 34 read backwards, r = rho/dt)
// by1, bx1: the image terms of the flux's stream function (read where `images`).
struct CurlVelocityRows {
  int n = 0;   // N
  int nx = 0;  // the lattice's row length
  double Q = 0, r = 0;
  const double *by1 = nullptr, *bx1 = nullptr, *u_star = nullptr;
  const unsigned char* par = nullptr;
  ParityModes modes;
  double *u = nullptr, *grad_phi = nullptr;
};
void block_curl_velocity(const CurlVelocityRows& p, bool images, const StencilClass& cl, const StencilBlock& k,
                         const double* const* w, const double* const* in);
void curl_velocity_row(const CurlVelocityRows& p, const double* const* sums, int i);  // *sums: Gx psi, Gy psi
void block_curl_velocity_plain(const CurlVelocityRows& p, const StencilClass& cl, const StencilBlock& k,
                               const double* const* w, const double* const* in);

}  // namespace sphib
