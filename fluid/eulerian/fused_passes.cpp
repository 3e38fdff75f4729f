#include "fluid/eulerian/fused_passes.hpp"

#include "fluid/algebra/stencil_kernels.hpp"

namespace sphib {

namespace {

using stencil::kBlock;
using Cls = RowStencil::Class;
using Blk = RowStencil::Block;

}  // namespace

ImageRows::ImageRows(const RowStencil* st, int n, std::initializer_list<const SpMat*> Bs) {
  std::vector<char> row(n, 0);
  for (const SpMat* B : Bs)
    for (int i : nonempty_rows(*B)) row[i] = 1;
  if (!st) return;
  for (const Blk& k : st->blocks) {
    char any = 0;
    for (int t = 0; t < k.count; ++t) any |= row[k.begin + t * k.stride];
    block.push_back(any);
  }
}

// Each pass: the stencil's blocks by the kernel (kernels/fused_rows.hpp), the other rows by their
// sums from the compressed arrays and the kernel's row epilogue.

namespace {

// Eq. (28)'s pass with NW operators of the velocity pattern: lap (NW = 1), or lap, Gx, Gy (NW = 3).
template <int NW>
void predictor_pass(const PredictorRhs& p, const PredictorRows& r, const double* const* val) {
  const double* in[2] = {r.u, r.u + r.n};
  const RowStencil* st = p.st;
  stencil::pass<2, NW, false>(
      *p.lap, val, in, st,
      [&](const Cls& cl, const Blk& k, const double* const* w) {
        block_predictor(r, p.images->block[&k - st->blocks.data()] != 0, cl, k, w, in);
      },
      [&](const double (*acc)[kBlock], int i, int, int) {
        const double* sums[2 * NW];
        for (int a = 0; a < 2 * NW; ++a) sums[a] = acc[a];
        predictor_row(r, sums, i);
      });
}

}  // namespace

void predictor_rhs(const PredictorRhs& p) {
  PredictorRows r = p.rows;
  r.n = static_cast<int>(p.lap->rows());
  if (r.conv_old) {
    const double* val[3] = {p.lap->valuePtr(), p.gx->valuePtr(), p.gy->valuePtr()};
    predictor_pass<3>(p, r, val);
  } else {
    const double* val[1] = {p.lap->valuePtr()};
    predictor_pass<1>(p, r, val);
  }
}

void curl_transpose_rhs(const CurlTransposeRhs& p) {
  const int N = static_cast<int>(p.ty->rows());
  const double* val[2] = {p.ty->valuePtr(), p.tx->valuePtr()};
  const double* in[2] = {p.u, p.u + N};
  stencil::pass<2, 2, true>(
      *p.ty, val, in, p.st,
      [&](const Cls& cl, const Blk& k, const double* const* w) { block_curl_transpose(p.rows, cl, k, w, in); },
      [&](const double (*acc)[kBlock], int i, int, int) {
        const double* sums[2] = {acc[0], acc[1]};
        curl_transpose_row(p.rows, sums, i);
      });
}

void curl_velocity(const CurlVelocity& p) {
  CurlVelocityRows r = p.rows;
  r.n = static_cast<int>(p.gx->rows());
  const double* val[2] = {p.gx->valuePtr(), p.gy->valuePtr()};
  const double* in[1] = {p.psi};
  const RowStencil* st = p.st;
  stencil::pass<1, 2, false>(
      *p.gx, val, in, st,
      [&](const Cls& cl, const Blk& k, const double* const* w) {
        block_curl_velocity(r, p.images->block[&k - st->blocks.data()] != 0, cl, k, w, in);
      },
      [&](const double (*acc)[kBlock], int i, int, int) {
        const double* sums[2] = {acc[0], acc[1]};
        curl_velocity_row(r, sums, i);
      });
}

}  // namespace sphib
