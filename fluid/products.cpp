#include "fluid/products.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <unordered_map>

namespace sphib {

bool same_pattern(const SpMat& A, const SpMat& B) {
  if (A.rows() != B.rows() || A.nonZeros() != B.nonZeros() || !A.isCompressed() || !B.isCompressed()) return false;
  return std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.rows() + 1, B.outerIndexPtr()) &&
         std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(), B.innerIndexPtr());
}

std::vector<int> nonempty_rows(const SpMat& B) {
  std::vector<int> rows;
  for (int i = 0; i < B.outerSize(); ++i)
    if (B.outerIndexPtr()[i + 1] > B.outerIndexPtr()[i] || (!B.isCompressed() && B.innerNonZeroPtr()[i] > 0))
      rows.push_back(i);
  return rows;
}

void add_image_terms(const SpMat& B, const std::vector<int>& rows, const double* c, double* y) {
  for (int i : rows) {
    double s = 0;
    for (SpMat::InnerIterator it(B, i); it; ++it) s += it.value() * c[it.col()];
    y[i] += s;
  }
}

void add_image_terms(const SpMat& B, const std::vector<int>& rows, const Mat2& c, Mat2& y) {
  add_image_terms(B, rows, c.data(), y.data());
  add_image_terms(B, rows, c.data() + c.rows(), y.data() + y.rows());
}

int RowStencil::stencil_rows() const {
  int m = 0;
  for (const auto& b : blocks) m += b[1] - b[0];
  return m;
}

namespace {

// Row i as a translate: its column offsets and the bits of its coefficients in every operator.
bool same_row(const std::vector<const SpMat*>& ops, int i, int ref) {
  const SpMat& A = *ops[0];
  const int *o = A.outerIndexPtr(), *c = A.innerIndexPtr();
  const int len = o[i + 1] - o[i];
  if (len != o[ref + 1] - o[ref]) return false;
  for (int k = 0; k < len; ++k)
    if (c[o[i] + k] - i != c[o[ref] + k] - ref) return false;
  for (const SpMat* B : ops)
    if (std::memcmp(B->valuePtr() + o[i], B->valuePtr() + o[ref], sizeof(double) * len) != 0) return false;
  return true;
}

std::uint64_t row_hash(const std::vector<const SpMat*>& ops, int i) {
  const SpMat& A = *ops[0];
  const int *o = A.outerIndexPtr(), *c = A.innerIndexPtr();
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over offsets and coefficient bits
  auto mix = [&](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  for (int k = o[i]; k < o[i + 1]; ++k) {
    mix(static_cast<std::uint64_t>(static_cast<std::int64_t>(c[k] - i)));
    for (const SpMat* B : ops) {
      std::uint64_t bits;
      std::memcpy(&bits, B->valuePtr() + k, sizeof bits);
      mix(bits);
    }
  }
  return h;
}

constexpr int kBlock = 256;  // rows per stencil block (RowStencil::blocks): the accumulators stay in L1

// Every row once: plain rows by `row(i)`, the stencil's blocks by `block(begin, end)`.
template <class Row, class Block>
void for_rows(int n, const RowStencil* st, Row&& row, Block&& block) {
  const bool par = n >= kParallelRows;
  (void)par;
  if (!st || st->ref < 0) {
#pragma omp parallel for schedule(static) if (par)
    for (int i = 0; i < n; ++i) row(i);
    return;
  }
  const int nb = static_cast<int>(st->blocks.size()), nr = static_cast<int>(st->rest.size());
#pragma omp parallel if (par)
  {
#pragma omp for schedule(static) nowait
    for (int k = 0; k < nb; ++k) block(st->blocks[k][0], st->blocks[k][1]);
#pragma omp for schedule(static)
    for (int k = 0; k < nr; ++k) row(st->rest[k]);
  }
}

// A block [b, e) of stencil rows: out_{jc} = sum_s w_j[s] in_c[t + o_s] for the NW coefficient sets
// j and NI inputs c (Diag: only j = c; Sum: the single output is the sum of those). Four terms per
// pass over the accumulators, added in the rows' own order: the same bits as the row-by-row loop.
template <int NI, int NW, bool Diag, bool Sum>
[[gnu::always_inline]] inline void stencil_block(const RowStencil& st, const double* const* w, const double* const* in,
                                                 double* const* out, int b, int e) {
  constexpr int NA = Diag ? NI : NI * NW;
  const int m = e - b, S = static_cast<int>(st.offset.size());
  const int* off = st.offset.data();
  double acc[NA][kBlock];
  for (int a = 0; a < NA; ++a)
    for (int t = 0; t < m; ++t) acc[a][t] = 0.0;
  int s = 0;
  for (; s + 4 <= S; s += 4) {
    for (int c = 0; c < NI; ++c) {
      const double* p = in[c] + b;
      const double *p0 = p + off[s], *p1 = p + off[s + 1], *p2 = p + off[s + 2], *p3 = p + off[s + 3];
      for (int j = 0; j < NW; ++j) {
        if (Diag && j != c) continue;
        const double *wj = w[j] + s;
        const double c0 = wj[0], c1 = wj[1], c2 = wj[2], c3 = wj[3];
        double* A = acc[Diag ? c : j * NI + c];
        for (int t = 0; t < m; ++t) A[t] = A[t] + c0 * p0[t] + c1 * p1[t] + c2 * p2[t] + c3 * p3[t];
      }
    }
  }
  for (; s < S; ++s)
    for (int c = 0; c < NI; ++c) {
      const double* p0 = in[c] + b + off[s];
      for (int j = 0; j < NW; ++j) {
        if (Diag && j != c) continue;
        const double c0 = w[j][s];
        double* A = acc[Diag ? c : j * NI + c];
        for (int t = 0; t < m; ++t) A[t] += c0 * p0[t];
      }
    }
  if (Sum) {
    for (int t = 0; t < m; ++t) out[0][b + t] = acc[0][t] + acc[1][t];
  } else {
    for (int a = 0; a < NA; ++a) std::copy(acc[a], acc[a] + m, out[a] + b);
  }
}

// The kernels, compiled twice (SSE2 and AVX2, chosen at load time; no FMA, so both give the same
// bits): y = A x for two columns; the four derivatives; the divergence; a scalar's gradient.
[[gnu::target_clones("avx2", "default")]] void block_apply2(const RowStencil& st, const double* const* w,
                                                           const double* const* in, double* const* out, int b, int e) {
  stencil_block<2, 1, false, false>(st, w, in, out, b, e);
}
[[gnu::target_clones("avx2", "default")]] void block_gradient2(const RowStencil& st, const double* const* w,
                                                              const double* const* in, double* const* out, int b, int e) {
  stencil_block<2, 2, false, false>(st, w, in, out, b, e);
}
[[gnu::target_clones("avx2", "default")]] void block_divergence(const RowStencil& st, const double* const* w,
                                                               const double* const* in, double* const* out, int b, int e) {
  stencil_block<2, 2, true, true>(st, w, in, out, b, e);
}
[[gnu::target_clones("avx2", "default")]] void block_gradient(const RowStencil& st, const double* const* w,
                                                             const double* const* in, double* const* out, int b, int e) {
  stencil_block<1, 2, false, false>(st, w, in, out, b, e);
}

}  // namespace

RowStencil find_row_stencil(std::initializer_list<const SpMat*> list) {
  const std::vector<const SpMat*> ops(list);
  RowStencil st;
  if (ops.empty()) return st;
  const SpMat& A = *ops[0];
  for (const SpMat* B : ops)
    if (!same_pattern(A, *B)) throw std::logic_error("find_row_stencil: the operators do not share one pattern");
  const int n = static_cast<int>(A.rows());
  // The most common row (offsets and coefficients); hash collisions are caught by same_row below.
  std::vector<std::uint64_t> h(n);
  std::unordered_map<std::uint64_t, int> count;
  for (int i = 0; i < n; ++i) ++count[h[i] = row_hash(ops, i)];
  std::uint64_t best = 0;
  int most = 0;
  for (int i = 0; i < n; ++i)
    if (count[h[i]] > most) { most = count[h[i]]; best = h[i]; }
  if (most < std::max(2, n / 4)) {  // not a lattice operator worth a stencil: every row plain
    for (int i = 0; i < n; ++i) st.rest.push_back(i);
    return st;
  }
  for (int i = 0; i < n; ++i)
    if (h[i] == best) { st.ref = i; break; }
  const int* o = A.outerIndexPtr();
  for (int k = o[st.ref]; k < o[st.ref + 1]; ++k) st.offset.push_back(A.innerIndexPtr()[k] - st.ref);
  for (int i = 0; i < n; ++i) {
    if (h[i] == best && same_row(ops, i, st.ref)) {
      auto& b = st.blocks;  // extend the last block while it is contiguous and short enough
      if (!b.empty() && b.back()[1] == i && b.back()[1] - b.back()[0] < kBlock) ++b.back()[1];
      else b.push_back({i, i + 1});
    } else {
      st.rest.push_back(i);
    }
  }
  return st;
}

void apply2(const SpMat& A, const Mat2& x, Mat2& y, const RowStencil* st) { apply2(A, x.data(), y.data(), st); }

void apply2(const SpMat& A, const double* x, double* y, const RowStencil* st) {
  const int n = static_cast<int>(A.rows());
  const int* o = A.outerIndexPtr();
  const int* c = A.innerIndexPtr();
  const double* a = A.valuePtr();
  const double *x0 = x, *x1 = x + n;
  double *y0 = y, *y1 = y + n;
  auto row = [&](int i) {
    double s0 = 0, s1 = 0;
    for (int k = o[i]; k < o[i + 1]; ++k) {
      s0 += a[k] * x0[c[k]];
      s1 += a[k] * x1[c[k]];
    }
    y0[i] = s0;
    y1[i] = s1;
  };
  const double* w[1] = {st ? a + o[std::max(st->ref, 0)] : nullptr};
  const double* in[2] = {x0, x1};
  double* out[2] = {y0, y1};
  for_rows(n, st, row, [&](int b, int e) { block_apply2(*st, w, in, out, b, e); });
}

void gradient2(const SpMat& Gx, const SpMat& Gy, const Mat2& u, Mat2& dx, Mat2& dy, const RowStencil* st) {
  const int n = static_cast<int>(Gx.rows());
  const int* o = Gx.outerIndexPtr();
  const int* c = Gx.innerIndexPtr();
  const double *gx = Gx.valuePtr(), *gy = Gy.valuePtr();
  const double *u0 = u.data(), *u1 = u.data() + u.rows();
  double *dx0 = dx.data(), *dx1 = dx.data() + n, *dy0 = dy.data(), *dy1 = dy.data() + n;
  auto row = [&](int i) {
    double a0 = 0, a1 = 0, b0 = 0, b1 = 0;
    for (int k = o[i]; k < o[i + 1]; ++k) {
      const double v0 = u0[c[k]], v1 = u1[c[k]];
      a0 += gx[k] * v0;  // d/dx of u
      a1 += gx[k] * v1;  // d/dx of v
      b0 += gy[k] * v0;  // d/dy of u
      b1 += gy[k] * v1;  // d/dy of v
    }
    dx0[i] = a0;
    dx1[i] = a1;
    dy0[i] = b0;
    dy1[i] = b1;
  };
  const int r = st ? std::max(st->ref, 0) : 0;
  const double* w[2] = {gx + o[r], gy + o[r]};
  const double* in[2] = {u0, u1};
  double* out[4] = {dx0, dx1, dy0, dy1};
  for_rows(n, st, row, [&](int b, int e) { block_gradient2(*st, w, in, out, b, e); });
}

void divergence(const SpMat& Gx, const SpMat& Gy, const Mat2& u, Vec& d, const RowStencil* st) {
  const int n = static_cast<int>(Gx.rows());
  const int* o = Gx.outerIndexPtr();
  const int* c = Gx.innerIndexPtr();
  const double *gx = Gx.valuePtr(), *gy = Gy.valuePtr();
  const double *u0 = u.data(), *u1 = u.data() + u.rows();
  double* dd = d.data();
  auto row = [&](int i) {
    double sx = 0, sy = 0;
    for (int k = o[i]; k < o[i + 1]; ++k) {
      sx += gx[k] * u0[c[k]];
      sy += gy[k] * u1[c[k]];
    }
    dd[i] = sx + sy;
  };
  const int r = st ? std::max(st->ref, 0) : 0;
  const double* w[2] = {gx + o[r], gy + o[r]};
  const double* in[2] = {u0, u1};
  double* out[1] = {dd};
  for_rows(n, st, row, [&](int b, int e) { block_divergence(*st, w, in, out, b, e); });
}

void gradient(const SpMat& Gx, const SpMat& Gy, const Vec& f, Mat2& g, const RowStencil* st) {
  const int n = static_cast<int>(Gx.rows());
  const int* o = Gx.outerIndexPtr();
  const int* c = Gx.innerIndexPtr();
  const double *gx = Gx.valuePtr(), *gy = Gy.valuePtr();
  const double* ff = f.data();
  double *g0 = g.data(), *g1 = g.data() + n;
  auto row = [&](int i) {
    double sx = 0, sy = 0;
    for (int k = o[i]; k < o[i + 1]; ++k) {
      sx += gx[k] * ff[c[k]];
      sy += gy[k] * ff[c[k]];
    }
    g0[i] = sx;
    g1[i] = sy;
  };
  const int r = st ? std::max(st->ref, 0) : 0;
  const double* w[2] = {gx + o[r], gy + o[r]};
  const double* in[1] = {ff};
  double* out[2] = {g0, g1};
  for_rows(n, st, row, [&](int b, int e) { block_gradient(*st, w, in, out, b, e); });
}

}  // namespace sphib
