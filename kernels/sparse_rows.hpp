#pragma once
// Three sparse products of one pattern in one pass over rows [i0, i1) (LPSPH's products ahead of
// the step, fluid/moving/lagrangian.cpp): with o, col the compressed rows (CSR) of the pattern and
// lap, cn, ph the values of the three operators,
//   out[0][i] = sum_p lap_p x4[4 c_p],     out[1][i] = sum_p lap_p x4[4 c_p + 1],
//   out[2][i] = sum_p cn_p  x4[4 c_p + 2], out[3][i] = sum_p cn_p  x4[4 c_p + 3],
//   out[4][i] = 0 + sum_p ph_p phi[c_p]
// (x4 holds four vectors interleaved: u, v and the two Crank-Nicolson starts), each sum term by term
// in the pattern's order, as Eigen's row-major product gives it. The fast form keeps the four
// velocity sums as the lanes of one vector; the plain form is the sums as written; they agree bit
// for bit (tests/test_kernels.cpp).
namespace sphib {

struct Rows3 {
  const int *o, *col;
  const double *lap, *cn, *ph, *x4, *phi;
};

void rows3(const Rows3& in, double* const* out, int i0, int i1);
void rows3_plain(const Rows3& in, double* const* out, int i0, int i1);

}  // namespace sphib
