#pragma once
// Sparse products of a time step, fused: operators assembled from one pair list share one
// sparsity pattern (operators.cpp keeps explicit zeros for that), so one pass over the pattern
// serves several operators and both velocity components. Results equal the separate Eigen
// products term by term (same summation order).
//
// On the fixed lattice most rows of an operator are translates of one another: away from walls
// and periodic seams row i has the columns i + o_s and, bit for bit, the coefficients of a
// reference row; along a wall (or a seam) the rows at one distance from it are translates of one
// another too. A RowStencil lists those classes of rows; the products then apply them as stencils
// (the coefficients of the class's reference row, no column indices, loads that vectorise) and only
// the remaining rows (corners) from the compressed arrays. The summation order of every row is
// unchanged, so the results are bitwise those of the plain products.
#include <array>
#include <initializer_list>
#include <functional>
#include <vector>

#include "fluid/algebra/row_stencil.hpp"
#include "fluid/common/types.hpp"

namespace sphib {

// The rows that are translates of one another in every operator of `ops` (one pattern, checked),
// grouped by class. Operators whose most common row is shared by fewer than a quarter of the rows
// get no stencil; classes of fewer than kMinClassRows rows stay with the compressed rows.
constexpr int kMinClassRows = 4;
RowStencil find_row_stencil(std::initializer_list<const SpMat*> ops);

// Operators of one pattern given as their rows: rows(f) calls f(ops, r0) with rows r0 .. r0 + m - 1
// of every operator (ops[q]: m x cols, compressed), consecutive blocks, every row once, in order;
// it is called once, or up to four times (below), and must give the same rows each time.
using OperatorRows = std::function<void(const std::function<void(const std::vector<const SpMat*>& ops, int r0)>&)>;
// find_row_stencil of the n-row operators given by `rows`, and kept[q] = stencil_rows_only of
// operator q, without any operator ever whole (EPSPH's compact storage: the transposes of the
// velocity gradients): the same stencil and the same kept rows, bit for bit. One pass over the rows
// (each compared as it passes with the first row of its hash, the rows that may be kept copied);
// should a class fall below kMinClassRows (hash collisions) or no stencil apply, then two or three
// more (the hashes; the classes and the kept rows; the kept rows again).
RowStencil find_row_stencil(const OperatorRows& rows, int n, std::vector<SpMat>& kept);

// Rows c0 .. c0 + m - 1 of G^T (an m x G.rows() matrix), the same bits and order as those rows of
// the whole transpose, read from the rows of G that the columns' own rows reach: G's pattern must be
// symmetric (the lattice operators' is: a pair and its mirror), which is checked against G's column
// counts `cols` (column_counts(G)); std::logic_error if not.
std::vector<int> column_counts(const SpMat& G);
SpMat transposed_rows(const SpMat& G, const std::vector<int>& cols, int c0, int m);
// The same from R, the rows `at` (ascending) of G (R's row q is G's row at[q]), which must hold the
// rows of G that G's columns c0 .. c0 + m - 1 reach (reach_of below); `local`: the columns numbered
// as R's rows (q for G's row at[q]: an m x at.size() matrix for products with R).
SpMat transposed_rows(const SpMat& R, const std::vector<int>& at, const std::vector<int>& cols, int c0, int m,
                      bool local);
// The columns of the rows of B, ascending, each once (of G's rows c0 .. c0 + m - 1: by the
// pattern's symmetry, the rows that reach the columns c0 .. c0 + m - 1)
std::vector<int> reach_of(const SpMat& B);
// The same with `mark` (B.cols() zeros, left zero) for the columns seen: only the distinct columns
// sorted, not every entry (the setup's blocks read it for every block of rows)
std::vector<int> reach_of(const SpMat& B, std::vector<char>& mark);

// An operator kept compact by a stencil (stencil_rows_only over `st`), its rows whole again: a row
// of a class is its reference row translated (the same coefficient bits, the columns shifted), the
// other rows are the kept ones. `st` must outlive it.
class StencilRows {
 public:
  StencilRows(const RowStencil& st, int n);
  SpMat rows(const SpMat& A, int r0, int m) const;               // rows r0 .. r0 + m - 1 (m x cols)
  SpMat rows(const SpMat& A, const std::vector<int>& at) const;  // rows at[q], ascending or not
  std::vector<int> column_counts(const SpMat& A) const;          // of the whole operator

 private:
  template <class Row>
  SpMat gather(const SpMat& A, int m, Row row) const;
  const RowStencil& st_;
  std::vector<int> cls_;  // each row's class, -1 for a kept row
};

// Fused products over operators of one sparsity pattern: each reads the pattern once. `st`, when
// given, must come from find_row_stencil over these operators (or a superset of them). With
// OpenMP and at least kParallelRows rows, the rows are shared among the threads (OMP_NUM_THREADS);
// every row is computed by one thread in its own order, so the bits do not depend on the count.
//   y = A x for both columns of x
void apply2(const SpMat& A, const Mat2& x, Mat2& y, const RowStencil* st = nullptr);
void apply2(const SpMat& A, const double* x, double* y, const RowStencil* st = nullptr);  // n x 2, column-major
//   dx = Gx u, dy = Gy u for both columns of u (the four derivatives of a velocity field)
void gradient2(const SpMat& Gx, const SpMat& Gy, const Mat2& u, Mat2& dx, Mat2& dy, const RowStencil* st = nullptr);
//   d = Gx u_x + Gy u_y (the divergence, Eq. 30)
void divergence(const SpMat& Gx, const SpMat& Gy, const Mat2& u, Vec& d, const RowStencil* st = nullptr);
//   g = (Gx f, Gy f) (a scalar's gradient, Eq. 27)
void gradient(const SpMat& Gx, const SpMat& Gy, const Vec& f, Mat2& g, const RowStencil* st = nullptr);
//   the same in the rows `rows` of g only (the other rows untouched), the same bits as gradient()
void gradient_rows(const SpMat& Gx, const SpMat& Gy, const Vec& f, Mat2& g, const std::vector<int>& rows);
//   y = A x for one column (the pressure's Laplacian, Eq. 35)
void apply1(const SpMat& A, const double* x, double* y, const RowStencil* st = nullptr);
bool same_pattern(const SpMat& A, const SpMat& B);

// A with only the rows the products above read when given `st` (find_row_stencil over A and its
// partners): its classes' reference rows and its `rest` rows, every other row empty. The products
// with `st` then give the same bits as with A, from about (classes + rest) rows of storage instead
// of N (EPSPH's compact storage, eulerian.hpp); any other use of the result sees empty rows.
SpMat stencil_rows_only(const SpMat& A, const RowStencil& st);
// A = stencil_rows_only(A, st), A's whole storage released (an assignment would keep its capacity)
void keep_stencil_rows(SpMat& A, const RowStencil& st);
// A's storage released (A 0 x 0)
void release(SpMat& A);

// A1 B1 + s2 A2 B2 (s2 = +1 or -1, exact), computed `block` rows at a time: bit for bit the
// entries of the whole products and their sum (each row of a product is summed alone, in the order
// of its row of A1 or A2), without the two whole products held at once.
SpMat sum_of_products(const SpMat& A1, const SpMat& B1, double s2, const SpMat& A2, const SpMat& B2,
                      int block = 0);  // 0: product_block(rows)
// Its rows r0 .. r0 + m - 1 alone (an m-row matrix), and the default block of an n-row product
SpMat rows_of_sum_of_products(const SpMat& A1, const SpMat& B1, double s2, const SpMat& A2, const SpMat& B2,
                              int r0, int m);
inline int product_block(int n) { return n / 64 > 1024 ? n / 64 : 1024; }
// rows_of_sum_of_products(A1, B1, s2, A2, B2, 0, A1.rows()) bit for bit (the same products, summed
// in the same order, the rows sorted by column, the entries of one product alone added to 0.0 as
// Eigen's sum does), from per-column scratch kept from one block to the next: no work or storage in
// proportion to B's columns per block, where Eigen's product allocates and clears three arrays of
// B's column count and converts the result's storage order twice (the setup's G^T G by blocks).
class SumOfProductRows {
 public:
  explicit SumOfProductRows(long cols) : stamp_(cols, -1), v_(cols) {}
  // the rows, valid until the next call (their storage is reused)
  const SpMat& operator()(const SpMat& A1, const SpMat& B1, double s2, const SpMat& A2, const SpMat& B2);

 private:
  // row i of s A B into (c, p), ascending columns; s = 1 reads A's values as they are
  void row(const SpMat& A, const SpMat& B, double s, bool scaled, int i, std::vector<int>& c, std::vector<double>& p);
  std::vector<int> stamp_;  // the row (a running count) whose product last touched the column
  std::vector<double> v_;
  int tag_ = 0;
  SpMat out_;
  std::vector<int> c1_, c2_;
  std::vector<double> p1_, p2_;
};
// A = -A in place, exactly (no new storage: an assignment of -A would grow its own)
void negate(SpMat& A);

// Image terms: an image operator B (N x M) has entries only in the rows near walls. y += B c
// over those rows (`rows` = nonempty_rows(B)); c is M x 2 (both columns) or one column.
std::vector<int> nonempty_rows(const SpMat& B);
void add_image_terms(const SpMat& B, const std::vector<int>& rows, const Mat2& c, Mat2& y);
void add_image_terms(const SpMat& B, const std::vector<int>& rows, const double* c, double* y);
// y = B c over those rows, the same sums (the other rows of y untouched: zero in the fused passes)
void set_image_terms(const SpMat& B, const std::vector<int>& rows, const Mat2& c, Mat2& y);

}  // namespace sphib
