#include "fluid/algebra/products.hpp"

#include "fluid/algebra/stencil_kernels.hpp"
#include "kernels/stencil_products.hpp"  // the block kernels

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <map>
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

namespace {
template <bool Add>
void image_terms(const SpMat& B, const std::vector<int>& rows, const double* c, double* y) {
  for (int i : rows) {
    double s = 0;
    for (SpMat::InnerIterator it(B, i); it; ++it) s += it.value() * c[it.col()];
    y[i] = Add ? y[i] + s : s;
  }
}
}  // namespace

void add_image_terms(const SpMat& B, const std::vector<int>& rows, const double* c, double* y) {
  image_terms<true>(B, rows, c, y);
}

void add_image_terms(const SpMat& B, const std::vector<int>& rows, const Mat2& c, Mat2& y) {
  image_terms<true>(B, rows, c.data(), y.data());
  image_terms<true>(B, rows, c.data() + c.rows(), y.data() + y.rows());
}

void set_image_terms(const SpMat& B, const std::vector<int>& rows, const Mat2& c, Mat2& y) {
  image_terms<false>(B, rows, c.data(), y.data());
  image_terms<false>(B, rows, c.data() + c.rows(), y.data() + y.rows());
}

int RowStencil::stencil_rows() const {
  int m = 0;
  for (const auto& b : blocks) m += b.count;
  return m;
}

namespace {

using stencil::kBlock;

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

// (row i of the operators, which is row `at` of the lattice: a block's rows are numbered from 0)
std::uint64_t row_hash(const std::vector<const SpMat*>& ops, int i, int at) {
  const SpMat& A = *ops[0];
  const int *o = A.outerIndexPtr(), *c = A.innerIndexPtr();
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over offsets and coefficient bits
  auto mix = [&](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  for (int k = o[i]; k < o[i + 1]; ++k) {
    mix(static_cast<std::uint64_t>(static_cast<std::int64_t>(c[k] - at)));
    for (const SpMat* B : ops) {
      std::uint64_t bits;
      std::memcpy(&bits, B->valuePtr() + k, sizeof bits);
      mix(bits);
    }
  }
  return h;
}

// The rows of one class (ascending) as blocks: runs of rows a constant stride apart (1 along a
// wall, the lattice's row length along a seam), at most kBlock rows each.
void add_blocks(int cls, const std::vector<int>& rows, std::vector<RowStencil::Block>& blocks) {
  const int n = static_cast<int>(rows.size());
  for (int k = 0; k < n;) {
    const int stride = k + 1 < n ? rows[k + 1] - rows[k] : 1;
    int m = 1;
    while (k + m < n && m < kBlock && rows[k + m] - rows[k + m - 1] == stride) ++m;
    blocks.push_back({cls, rows[k], m, m > 1 ? stride : 1});
    k += m;
  }
}

using Cls = RowStencil::Class;
using Blk = RowStencil::Block;
using stencil::store_sum;

// One product through stencil::pass: `kernel` for the blocks, the same store for the other rows
// (Diag: the divergence's sum).
template <int NI, int NW, bool Diag, class Kernel>
void product(const SpMat& A, const double* const* val, const double* const* in, double* const* out,
             const RowStencil* st, Kernel kernel) {
  stencil::pass<NI, NW, Diag>(
      A, val, in, st, [&](const Cls& cl, const Blk& k, const double* const* w) { kernel(cl, k, w, in, out); },
      [&](const double (*acc)[kBlock], int b, int m, int stride) {
        if (Diag) store_sum(acc, out, b, m, stride);
        else stencil::store<NI * NW>(acc, out, b, m, stride);
      });
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
  // Rows grouped by their hash (offsets and coefficients; collisions are caught by same_row below),
  // the most common first.
  std::vector<std::uint64_t> h(n);
  std::unordered_map<std::uint64_t, int> count;
  for (int i = 0; i < n; ++i) ++count[h[i] = row_hash(ops, i, i)];
  std::uint64_t best = 0;
  int most = 0;
  for (int i = 0; i < n; ++i)
    if (count[h[i]] > most) { most = count[h[i]]; best = h[i]; }
  if (most < std::max(2, n / 4)) {  // not a lattice operator worth a stencil: every row plain
    for (int i = 0; i < n; ++i) st.rest.push_back(i);
    return st;
  }
  std::unordered_map<std::uint64_t, int> cls;  // hash -> class
  std::vector<std::vector<int>> members;
  std::vector<char> plain(n, 1);
  auto class_of = [&](int i) {
    auto [it, fresh] = cls.emplace(h[i], static_cast<int>(st.classes.size()));
    if (fresh) {
      RowStencil::Class c;
      c.ref = i;
      for (int k = A.outerIndexPtr()[i]; k < A.outerIndexPtr()[i + 1]; ++k) c.offset.push_back(A.innerIndexPtr()[k] - i);
      st.classes.push_back(std::move(c));
      members.emplace_back();
    }
    return it->second;
  };
  for (int i = 0; i < n; ++i)
    if (h[i] == best) { class_of(i); break; }  // class 0: the most common row
  for (int i = 0; i < n; ++i) {
    if (count[h[i]] < kMinClassRows) continue;
    const int k = class_of(i);
    if (same_row(ops, i, st.classes[k].ref)) { members[k].push_back(i); plain[i] = 0; }
  }
  for (int k = 0; k < static_cast<int>(members.size()); ++k) {
    if (static_cast<int>(members[k].size()) < kMinClassRows)
      for (int i : members[k]) plain[i] = 1;
    else
      add_blocks(k, members[k], st.blocks);
  }
  std::sort(st.blocks.begin(), st.blocks.end(), [](const Blk& a, const Blk& b) { return a.begin < b.begin; });
  for (int i = 0; i < n; ++i)
    if (plain[i]) st.rest.push_back(i);
  return st;
}

namespace {

// find_row_stencil over OperatorRows in one pass over the rows, where the two passes below take two:
// each row is compared as it passes with the first row of its hash (the reference row of its class,
// should the hash turn out to be a class's), and the rows that may be kept are copied as they pass
// (every reference row; a row unlike its hash's first; the rows of a hash until it has
// kMinClassRows of them). At the end the classes are numbered as the passes number them (the most
// common hash first, then by first row), so the stencil and the kept rows are theirs. false (the
// caller then takes the passes) where the passes would need their third: no stencil, or a class with
// fewer than kMinClassRows rows like its reference row.
bool find_row_stencil_in_one_pass(const OperatorRows& rows, int n, std::vector<SpMat>& kept, RowStencil& st) {
  struct Copy {  // a row: its column offsets (column - row) and its values in every operator
    std::vector<int> offset;
    std::vector<std::vector<double>> val;
  };
  struct Hash {
    int count = 0, first = -1;
    Copy ref;                  // the first row
    std::vector<int> members;  // the rows like it, ascending
  };
  std::unordered_map<std::uint64_t, Hash> table;
  std::map<int, Copy> held;  // rows that may be kept (plain), by row
  int nops = 0;
  long cols = 0;
  const auto copy = [](const std::vector<const SpMat*>& ops, int q, int i) {
    const int *o = ops[0]->outerIndexPtr(), *c = ops[0]->innerIndexPtr();
    Copy r;
    for (int e = o[q]; e < o[q + 1]; ++e) r.offset.push_back(c[e] - i);
    for (const SpMat* B : ops) r.val.emplace_back(B->valuePtr() + o[q], B->valuePtr() + o[q + 1]);
    return r;
  };
  rows([&](const std::vector<const SpMat*>& ops, int r0) {
    nops = static_cast<int>(ops.size());
    cols = ops[0]->cols();
    for (const SpMat* B : ops)
      if (!same_pattern(*ops[0], *B)) throw std::logic_error("find_row_stencil: the operators do not share one pattern");
    const int *o = ops[0]->outerIndexPtr(), *c = ops[0]->innerIndexPtr();
    for (int q = 0; q < ops[0]->rows(); ++q) {
      const int i = r0 + q;
      Hash& e = table[row_hash(ops, q, i)];
      ++e.count;
      if (e.first < 0) {
        e.first = i;
        e.ref = copy(ops, q, i);
      }
      // as the passes' comparison with the class's reference row
      const int n_i = o[q + 1] - o[q];
      bool same = n_i == static_cast<int>(e.ref.offset.size());
      for (int k = 0; same && k < n_i; ++k) same = c[o[q] + k] - i == e.ref.offset[k];
      for (int b = 0; same && b < nops; ++b)
        same = std::memcmp(ops[b]->valuePtr() + o[q], e.ref.val[b].data(), sizeof(double) * n_i) == 0;
      if (!same) {
        held[i] = copy(ops, q, i);  // plain whatever the hash's count
        continue;
      }
      e.members.push_back(i);
      if (e.count < kMinClassRows) {
        if (i != e.first) held[i] = copy(ops, q, i);  // plain should the hash stay rare
      } else if (e.count == kMinClassRows) {
        for (int j : e.members)  // a class's rows from now on (its reference row is e.ref)
          if (j != e.first) held.erase(j);
      }
    }
  });
  // the most common hash (the first row's on ties), and the classes in the passes' order
  const Hash* best = nullptr;
  for (const auto& [h, e] : table)
    if (!best || e.count > best->count || (e.count == best->count && e.first < best->first)) best = &e;
  if (!best || best->count < std::max(2, n / 4) || best->count < kMinClassRows) return false;
  std::vector<const Hash*> cls{best};
  for (const auto& [h, e] : table)
    if (&e != best && e.count >= kMinClassRows) cls.push_back(&e);
  std::sort(cls.begin() + 1, cls.end(), [](const Hash* a, const Hash* b) { return a->first < b->first; });
  std::vector<char> plain(n, 1);
  std::map<int, const Copy*> keep;  // the kept rows: the reference rows and the plain rows
  st.classes.resize(cls.size());
  for (size_t k = 0; k < cls.size(); ++k) {
    if (static_cast<int>(cls[k]->members.size()) < kMinClassRows) return false;  // (the passes' third)
    st.classes[k].ref = cls[k]->first;
    st.classes[k].offset = cls[k]->ref.offset;
    for (int i : cls[k]->members) plain[i] = 0;
    add_blocks(static_cast<int>(k), cls[k]->members, st.blocks);
    keep[cls[k]->first] = &cls[k]->ref;
  }
  std::sort(st.blocks.begin(), st.blocks.end(), [](const Blk& a, const Blk& b) { return a.begin < b.begin; });
  std::unordered_map<int, const Copy*> first;  // a rare hash's first row: its reference copy
  for (const auto& [h, e] : table)
    if (e.count < kMinClassRows) first[e.first] = &e.ref;
  for (int i = 0; i < n; ++i)
    if (plain[i]) {
      st.rest.push_back(i);
      const auto it = held.find(i);
      const auto f = first.find(i);
      if (it != held.end()) keep[i] = &it->second;
      else if (f != first.end()) keep[i] = f->second;
      else throw std::logic_error("find_row_stencil: a plain row was not kept");
    }
  kept.assign(nops, SpMat());
  long nnz = 0;
  for (const auto& [i, r] : keep) nnz += static_cast<long>(r->offset.size());
  for (int b = 0; b < nops; ++b) {
    SpMat& R = kept[b];
    R.resize(n, cols);
    R.reserve(static_cast<Eigen::Index>(nnz));
    auto it = keep.begin();
    for (int i = 0; i < n; ++i) {
      R.startVec(i);
      if (it == keep.end() || it->first != i) continue;
      const Copy& r = *it->second;
      for (size_t k = 0; k < r.offset.size(); ++k) R.insertBack(i, i + r.offset[k]) = r.val[b][k];  // zeros kept
      ++it;
    }
    R.finalize();
  }
  return true;
}

}  // namespace

RowStencil find_row_stencil(const OperatorRows& rows, int n, std::vector<SpMat>& kept) {
  {
    RowStencil st;
    if (find_row_stencil_in_one_pass(rows, n, kept, st)) return st;
  }
  // find_row_stencil above, pass by pass: the hashes; the classes (each reference row copied as it
  // passes, the rows compared with it); the kept rows.
  RowStencil st;
  std::vector<std::uint64_t> h(n);
  int nops = 0;
  long cols = 0;
  rows([&](const std::vector<const SpMat*>& ops, int r0) {
    nops = static_cast<int>(ops.size());
    cols = ops[0]->cols();
    for (const SpMat* B : ops)
      if (!same_pattern(*ops[0], *B)) throw std::logic_error("find_row_stencil: the operators do not share one pattern");
    for (int q = 0; q < ops[0]->rows(); ++q) h[r0 + q] = row_hash(ops, q, r0 + q);
  });
  std::unordered_map<std::uint64_t, int> count;
  for (int i = 0; i < n; ++i) ++count[h[i]];
  std::uint64_t best = 0;
  int most = 0;
  for (int i = 0; i < n; ++i)
    if (count[h[i]] > most) { most = count[h[i]]; best = h[i]; }
  std::vector<char> plain(n, 1);
  // the kept rows (stencil_rows_only's: the classes' reference rows and the plain ones), collected
  // as they pass (in order) and compressed at the end
  std::vector<int> len(n, 0), col;
  std::vector<std::vector<double>> val;
  const auto collect = [&](const std::vector<const SpMat*>& ops, int q, int i) {
    const int *o = ops[0]->outerIndexPtr(), *c = ops[0]->innerIndexPtr();
    val.resize(ops.size());
    len[i] = o[q + 1] - o[q];
    col.insert(col.end(), c + o[q], c + o[q + 1]);
    for (size_t b = 0; b < ops.size(); ++b) val[b].insert(val[b].end(), ops[b]->valuePtr() + o[q], ops[b]->valuePtr() + o[q + 1]);
  };
  bool collected = false;  // the second pass collected them (no class fell below kMinClassRows)
  if (n > 0 && most >= std::max(2, n / 4)) {
    // the classes in find_row_stencil's order: the most common row's first, then by first row
    std::unordered_map<std::uint64_t, int> cls;
    std::vector<int> ref;
    for (int i = 0; i < n; ++i)
      if (h[i] == best) { cls.emplace(best, 0); ref.push_back(i); break; }
    for (int i = 0; i < n; ++i)
      if (count[h[i]] >= kMinClassRows && cls.emplace(h[i], static_cast<int>(ref.size())).second) ref.push_back(i);
    struct Ref {
      std::vector<int> offset;
      std::vector<std::vector<double>> val;  // per operator
    };
    std::vector<Ref> rd(ref.size());
    std::vector<std::vector<int>> members(ref.size());
    st.classes.resize(ref.size());
    rows([&](const std::vector<const SpMat*>& ops, int r0) {
      const int *o = ops[0]->outerIndexPtr(), *c = ops[0]->innerIndexPtr();
      for (int q = 0; q < ops[0]->rows(); ++q) {
        const int i = r0 + q;
        const bool first = cls.count(h[i]) && ref[cls[h[i]]] == i;  // (class 0 is made whatever its count)
        if (!first && count[h[i]] < kMinClassRows) {
          collect(ops, q, i);  // plain
          continue;
        }
        const int k = cls[h[i]];
        Ref& r = rd[k];
        if (first) {
          for (int e = o[q]; e < o[q + 1]; ++e) r.offset.push_back(c[e] - i);
          for (const SpMat* B : ops) r.val.emplace_back(B->valuePtr() + o[q], B->valuePtr() + o[q + 1]);
          st.classes[k].ref = i;
          st.classes[k].offset = r.offset;
          collect(ops, q, i);  // a reference row
          if (count[h[i]] < kMinClassRows) continue;
        }
        const int n_i = o[q + 1] - o[q];
        bool same = n_i == static_cast<int>(r.offset.size());
        for (int e = 0; same && e < n_i; ++e) same = c[o[q] + e] - i == r.offset[e];
        for (int b = 0; same && b < nops; ++b)
          same = std::memcmp(ops[b]->valuePtr() + o[q], r.val[b].data(), sizeof(double) * n_i) == 0;
        if (same) { members[k].push_back(i); plain[i] = 0; }
        else collect(ops, q, i);  // plain
      }
    });
    collected = true;
    for (int k = 0; k < static_cast<int>(members.size()); ++k) {
      if (static_cast<int>(members[k].size()) < kMinClassRows) {
        for (int i : members[k]) plain[i] = 1;
        collected = false;  // rows of a class not collected are plain after all
      } else {
        add_blocks(k, members[k], st.blocks);
      }
    }
    std::sort(st.blocks.begin(), st.blocks.end(), [](const Blk& a, const Blk& b) { return a.begin < b.begin; });
  }
  for (int i = 0; i < n; ++i)
    if (plain[i]) st.rest.push_back(i);
  if (!collected) {  // a third pass for them
    std::vector<char> keep(plain.begin(), plain.end());
    for (const auto& c : st.classes) keep[c.ref] = 1;
    std::fill(len.begin(), len.end(), 0);
    col.clear();
    val.assign(nops, {});
    rows([&](const std::vector<const SpMat*>& ops, int r0) {
      for (int q = 0; q < ops[0]->rows(); ++q)
        if (keep[r0 + q]) collect(ops, q, r0 + q);
    });
  }
  val.resize(nops);
  kept.assign(nops, SpMat());
  for (int b = 0; b < nops; ++b) {
    SpMat& R = kept[b];
    R.resize(n, cols);
    R.reserve(static_cast<Eigen::Index>(col.size()));
    long e = 0;
    for (int i = 0; i < n; ++i) {
      R.startVec(i);
      for (int k = 0; k < len[i]; ++k, ++e) R.insertBack(i, col[e]) = val[b][e];  // zeros kept
    }
    R.finalize();
    std::vector<double>().swap(val[b]);
  }
  return st;
}

std::vector<int> column_counts(const SpMat& G) {
  std::vector<int> n(G.cols(), 0);
  for (Eigen::Index k = 0; k < G.nonZeros(); ++k) ++n[G.innerIndexPtr()[k]];
  return n;
}

std::vector<int> reach_of(const SpMat& B) {
  std::vector<int> from(B.innerIndexPtr(), B.innerIndexPtr() + B.nonZeros());
  std::sort(from.begin(), from.end());
  from.erase(std::unique(from.begin(), from.end()), from.end());
  return from;
}

std::vector<int> reach_of(const SpMat& B, std::vector<char>& mark) {
  std::vector<int> from;
  const int* c = B.innerIndexPtr();
  for (Eigen::Index k = 0; k < B.nonZeros(); ++k)
    if (!mark[c[k]]) {
      mark[c[k]] = 1;
      from.push_back(c[k]);
    }
  for (int j : from) mark[j] = 0;
  std::sort(from.begin(), from.end());
  return from;
}

SpMat transposed_rows(const SpMat& G, const std::vector<int>& cols, int c0, int m) {
  return transposed_rows(G, {}, cols, c0, m, false);
}

SpMat transposed_rows(const SpMat& R, const std::vector<int>& at, const std::vector<int>& cols, int c0, int m,
                      bool local) {
  const int *o = R.outerIndexPtr(), *c = R.innerIndexPtr();
  // R's rows to read: those `at` names (all of them), or, R being G itself (`at` empty), the rows
  // with an entry in columns c0 .. c0 + m - 1: by the pattern's symmetry, the columns of G's rows
  // c0 .. c0 + m - 1
  std::vector<int> from;
  if (at.empty()) from = reach_of(SpMat(R.middleRows(c0, m)));
  const int nfrom = at.empty() ? static_cast<int>(from.size()) : static_cast<int>(at.size());
  auto row_of = [&](int q) { return at.empty() ? from[q] : q; };   // R's row
  auto name_of = [&](int q) { return at.empty() ? from[q] : (local ? q : at[q]); };  // its column in T
  SpMat T(m, local ? static_cast<Eigen::Index>(at.size()) : R.cols());
  long nnz = 0;
  for (int q = 0; q < m; ++q) nnz += cols[c0 + q];
  std::vector<int> start(m + 1, 0);
  for (int q = 0; q < nfrom; ++q) {
    const int k = row_of(q);
    for (int e = o[k]; e < o[k + 1]; ++e)
      if (c[e] >= c0 && c[e] < c0 + m) ++start[c[e] - c0 + 1];
  }
  for (int q = 0; q < m; ++q) {
    if (start[q + 1] != cols[c0 + q])
      throw std::logic_error("transposed_rows: the operator's pattern is not symmetric (column " +
                             std::to_string(c0 + q) + ")");
    start[q + 1] += start[q];
  }
  T.reserve(nnz);
  std::vector<int> idx(nnz);
  std::vector<double> v(nnz);
  std::vector<int> next(start.begin(), start.end() - 1);
  for (int q = 0; q < nfrom; ++q) {  // ascending rows of G: each row of the transpose in column order, as the whole's
    const int k = row_of(q);
    for (int e = o[k]; e < o[k + 1]; ++e)
      if (c[e] >= c0 && c[e] < c0 + m) {
        const int a = next[c[e] - c0]++;
        idx[a] = name_of(q);
        v[a] = R.valuePtr()[e];
      }
  }
  for (int q = 0; q < m; ++q) {
    T.startVec(q);
    for (int e = start[q]; e < start[q + 1]; ++e) T.insertBack(q, idx[e]) = v[e];
  }
  T.finalize();
  return T;
}

StencilRows::StencilRows(const RowStencil& st, int n) : st_(st), cls_(n, -1) {
  for (const auto& b : st.blocks)
    for (int k = 0; k < b.count; ++k) cls_[b.begin + k * b.stride] = b.cls;
  for (const auto& c : st.classes) cls_[c.ref] = -1;  // kept
}

template <class Row>
SpMat StencilRows::gather(const SpMat& A, int m, Row row) const {
  const int* o = A.outerIndexPtr();
  long nnz = 0;
  for (int q = 0; q < m; ++q) {
    const int i = row(q), k = cls_[i];
    const int src = k < 0 ? i : st_.classes[k].ref;
    nnz += o[src + 1] - o[src];
  }
  SpMat B(m, A.cols());
  B.reserve(nnz);
  for (int q = 0; q < m; ++q) {
    const int i = row(q), k = cls_[i];
    B.startVec(q);
    if (k < 0) {
      for (int e = o[i]; e < o[i + 1]; ++e) B.insertBack(q, A.innerIndexPtr()[e]) = A.valuePtr()[e];
    } else {
      const RowStencil::Class& c = st_.classes[k];
      for (int e = o[c.ref], t = 0; e < o[c.ref + 1]; ++e, ++t) B.insertBack(q, i + c.offset[t]) = A.valuePtr()[e];
    }
  }
  B.finalize();
  return B;
}

SpMat StencilRows::rows(const SpMat& A, int r0, int m) const {
  return gather(A, m, [r0](int q) { return r0 + q; });
}

SpMat StencilRows::rows(const SpMat& A, const std::vector<int>& at) const {
  return gather(A, static_cast<int>(at.size()), [&at](int q) { return at[q]; });
}

std::vector<int> StencilRows::column_counts(const SpMat& A) const {
  std::vector<int> n(A.cols(), 0);
  const int* o = A.outerIndexPtr();
  for (int i = 0; i < static_cast<int>(cls_.size()); ++i) {
    const int k = cls_[i];
    if (k < 0) {
      for (int e = o[i]; e < o[i + 1]; ++e) ++n[A.innerIndexPtr()[e]];
    } else {
      for (int t : st_.classes[k].offset) ++n[i + t];
    }
  }
  return n;
}

void apply2(const SpMat& A, const Mat2& x, Mat2& y, const RowStencil* st) { apply2(A, x.data(), y.data(), st); }

void apply2(const SpMat& A, const double* x, double* y, const RowStencil* st) {
  const int n = static_cast<int>(A.rows());
  const double* val[1] = {A.valuePtr()};
  const double* in[2] = {x, x + n};
  double* out[2] = {y, y + n};
  product<2, 1, false>(A, val, in, out, st, block_apply2);
}

void apply1(const SpMat& A, const double* x, double* y, const RowStencil* st) {
  const double* val[1] = {A.valuePtr()};
  const double* in[1] = {x};
  double* out[1] = {y};
  product<1, 1, false>(A, val, in, out, st, block_apply1);
}

SpMat stencil_rows_only(const SpMat& A, const RowStencil& st) {
  const int n = static_cast<int>(A.rows());
  std::vector<char> keep(n, st.classes.empty() ? 1 : 0);  // no classes: every row is plain
  for (const auto& c : st.classes) keep[c.ref] = 1;
  for (int i : st.rest) keep[i] = 1;
  const int* o = A.outerIndexPtr();
  long nnz = 0;
  for (int i = 0; i < n; ++i)
    if (keep[i]) nnz += o[i + 1] - o[i];
  SpMat R(A.rows(), A.cols());
  R.reserve(nnz);
  for (int i = 0; i < n; ++i) {
    R.startVec(i);
    if (keep[i])
      for (int k = o[i]; k < o[i + 1]; ++k) R.insertBack(i, A.innerIndexPtr()[k]) = A.valuePtr()[k];  // zeros kept
  }
  R.finalize();
  return R;
}

void keep_stencil_rows(SpMat& A, const RowStencil& st) {
  SpMat R = stencil_rows_only(A, st);
  A.swap(R);
}

void release(SpMat& A) {
  SpMat empty;
  A.swap(empty);
}

void negate(SpMat& A) {
  double* v = A.valuePtr();
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k) v[k] = -v[k];
}

SpMat rows_of_sum_of_products(const SpMat& A1, const SpMat& B1, double s2, const SpMat& A2, const SpMat& B2,
                              int r0, int m) {
  const SpMat a2 = s2 * A2.middleRows(r0, m);
  return SpMat(SpMat(SpMat(A1.middleRows(r0, m)) * B1) + SpMat(a2 * B2));
}

void SumOfProductRows::row(const SpMat& A, const SpMat& B, double s, bool scaled, int i, std::vector<int>& c,
                           std::vector<double>& p) {
  // as Eigen's conservative product of row-major matrices: for each entry (k, y) of A's row, in
  // order, each entry (j, x) of B's row k, in order: the first x y of column j assigned, the next added
  if (tag_ == std::numeric_limits<int>::max()) {  // (the running count starts again)
    std::fill(stamp_.begin(), stamp_.end(), -1);
    tag_ = 0;
  }
  const int tag = tag_++;
  const int *oa = A.outerIndexPtr(), *ca = A.innerIndexPtr(), *ob = B.outerIndexPtr(), *cb = B.innerIndexPtr();
  const double *va = A.valuePtr(), *vb = B.valuePtr();
  c.clear();
  for (int e = oa[i]; e < oa[i + 1]; ++e) {
    const double y = scaled ? s * va[e] : va[e];  // (Eigen's s2 * A2, entry by entry)
    const int k = ca[e];
    for (int f = ob[k]; f < ob[k + 1]; ++f) {
      const int j = cb[f];
      const double x = vb[f];
      if (stamp_[j] != tag) {
        stamp_[j] = tag;
        v_[j] = x * y;
        c.push_back(j);
      } else {
        v_[j] += x * y;
      }
    }
  }
  std::sort(c.begin(), c.end());
  p.resize(c.size());
  for (size_t q = 0; q < c.size(); ++q) p[q] = v_[c[q]];
}

const SpMat& SumOfProductRows::operator()(const SpMat& A1, const SpMat& B1, double s2, const SpMat& A2,
                                         const SpMat& B2) {
  const int m = static_cast<int>(A1.rows());
  SpMat& R = out_;
  R.resize(m, B1.cols());  // (keeps the room of the last block's entries)
  R.reserve(static_cast<Eigen::Index>(A1.nonZeros() + A2.nonZeros()) * 4);
  for (int i = 0; i < m; ++i) {
    row(A1, B1, 1.0, false, i, c1_, p1_);
    row(A2, B2, s2, true, i, c2_, p2_);
    R.startVec(i);
    // the sum as Eigen's: both, p1 + p2; one alone, p1 + 0 or 0 + p2 (the same bits but for a -0)
    size_t a = 0, b = 0;
    while (a < c1_.size() || b < c2_.size()) {
      if (b == c2_.size() || (a < c1_.size() && c1_[a] < c2_[b])) {
        R.insertBack(i, c1_[a]) = p1_[a] + 0.0;
        ++a;
      } else if (a == c1_.size() || c2_[b] < c1_[a]) {
        R.insertBack(i, c2_[b]) = 0.0 + p2_[b];
        ++b;
      } else {
        R.insertBack(i, c1_[a]) = p1_[a] + p2_[b];
        ++a;
        ++b;
      }
    }
  }
  R.finalize();
  return R;
}

SpMat sum_of_products(const SpMat& A1, const SpMat& B1, double s2, const SpMat& A2, const SpMat& B2, int block) {
  const int n = static_cast<int>(A1.rows());
  if (block <= 0) block = product_block(n);
  auto rows = [&](int r0, int m) { return rows_of_sum_of_products(A1, B1, s2, A2, B2, r0, m); };
  SpMat R(A1.rows(), B1.cols());
  {  // room for n rows as long as the longest of the middle block's (on a lattice the interior rows
     // are the longest: walls and seams only fold columns onto others)
    const int r0 = std::max(0, std::min(n / 2, n - block)), m = std::min(block, n - r0);
    const SpMat P = rows(r0, m);
    long longest = 0;
    for (int i = 0; i < m; ++i) longest = std::max<long>(longest, P.outerIndexPtr()[i + 1] - P.outerIndexPtr()[i]);
    R.reserve(longest * n);
  }
  for (int r0 = 0; r0 < n; r0 += block) {
    const int m = std::min(block, n - r0);
    const SpMat P = rows(r0, m);
    auto& data = R.data();  // grow by half at least, should a block not fit (insertBack grows by one)
    if (data.size() + P.nonZeros() > data.allocatedSize()) data.reserve(std::max<long>(P.nonZeros(), data.size() / 2));
    for (int i = 0; i < m; ++i) {
      R.startVec(r0 + i);
      for (int k = P.outerIndexPtr()[i]; k < P.outerIndexPtr()[i + 1]; ++k)
        R.insertBack(r0 + i, P.innerIndexPtr()[k]) = P.valuePtr()[k];
    }
  }
  R.finalize();
  return R;
}

void gradient2(const SpMat& Gx, const SpMat& Gy, const Mat2& u, Mat2& dx, Mat2& dy, const RowStencil* st) {
  const int n = static_cast<int>(Gx.rows());
  const double* val[2] = {Gx.valuePtr(), Gy.valuePtr()};
  const double* in[2] = {u.data(), u.data() + u.rows()};
  double* out[4] = {dx.data(), dx.data() + n, dy.data(), dy.data() + n};  // d/dx of u, v; d/dy of u, v
  product<2, 2, false>(Gx, val, in, out, st, block_gradient2);
}

void divergence(const SpMat& Gx, const SpMat& Gy, const Mat2& u, Vec& d, const RowStencil* st) {
  const double* val[2] = {Gx.valuePtr(), Gy.valuePtr()};
  const double* in[2] = {u.data(), u.data() + u.rows()};
  double* out[1] = {d.data()};
  product<2, 2, true>(Gx, val, in, out, st, block_divergence);  // d = Gx u_x + Gy u_y
}

void gradient(const SpMat& Gx, const SpMat& Gy, const Vec& f, Mat2& g, const RowStencil* st) {
  const int n = static_cast<int>(Gx.rows());
  const double* val[2] = {Gx.valuePtr(), Gy.valuePtr()};
  const double* in[1] = {f.data()};
  double* out[2] = {g.data(), g.data() + n};
  product<1, 2, false>(Gx, val, in, out, st, block_gradient);
}

void gradient_rows(const SpMat& Gx, const SpMat& Gy, const Vec& f, Mat2& g, const std::vector<int>& rows) {
  const int n = static_cast<int>(Gx.rows());
  const double* val[2] = {Gx.valuePtr(), Gy.valuePtr()};
  const double* in[1] = {f.data()};
  double* out[2] = {g.data(), g.data() + n};
  for (int i : rows) {  // as product's plain rows
    double acc[2][kBlock];
    stencil::accumulate_row<1, 2, false>(Gx.outerIndexPtr(), Gx.innerIndexPtr(), val, in, acc, i);
    stencil::store<2>(acc, out, i, 1, 1);
  }
}

}  // namespace sphib
