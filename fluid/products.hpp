#pragma once
// Sparse products of a time step, fused: operators assembled from one pair list share one
// sparsity pattern (operators.cpp keeps explicit zeros for that), so one pass over the pattern
// serves several operators and both velocity components. Results equal the separate Eigen
// products term by term (same summation order).
#include "fluid/types.hpp"

namespace sphib {

// Fused products over operators of one sparsity pattern: each reads the pattern once.
//   y = A x for both columns of x
void apply2(const SpMat& A, const Mat2& x, Mat2& y);
void apply2(const SpMat& A, const double* x, double* y);  // x, y: n x 2, column-major
//   dx = Gx u, dy = Gy u for both columns of u (the four derivatives of a velocity field)
void gradient2(const SpMat& Gx, const SpMat& Gy, const Mat2& u, Mat2& dx, Mat2& dy);
//   d = Gx u_x + Gy u_y (the divergence, Eq. 30)
void divergence(const SpMat& Gx, const SpMat& Gy, const Mat2& u, Vec& d);
//   g = (Gx f, Gy f) (a scalar's gradient, Eq. 27)
void gradient(const SpMat& Gx, const SpMat& Gy, const Vec& f, Mat2& g);
bool same_pattern(const SpMat& A, const SpMat& B);

}  // namespace sphib
