#include "fluid/products.hpp"

#include <algorithm>

namespace sphib {

bool same_pattern(const SpMat& A, const SpMat& B) {
  if (A.rows() != B.rows() || A.nonZeros() != B.nonZeros() || !A.isCompressed() || !B.isCompressed()) return false;
  return std::equal(A.outerIndexPtr(), A.outerIndexPtr() + A.rows() + 1, B.outerIndexPtr()) &&
         std::equal(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros(), B.innerIndexPtr());
}

void apply2(const SpMat& A, const Mat2& x, Mat2& y) { apply2(A, x.data(), y.data()); }

void apply2(const SpMat& A, const double* x, double* y) {
  const int n = static_cast<int>(A.rows());
  const int* o = A.outerIndexPtr();
  const int* c = A.innerIndexPtr();
  const double* a = A.valuePtr();
  const double *x0 = x, *x1 = x + n;
  double *y0 = y, *y1 = y + n;
  for (int i = 0; i < n; ++i) {
    double s0 = 0, s1 = 0;
    for (int k = o[i]; k < o[i + 1]; ++k) {
      s0 += a[k] * x0[c[k]];
      s1 += a[k] * x1[c[k]];
    }
    y0[i] = s0;
    y1[i] = s1;
  }
}

void gradient2(const SpMat& Gx, const SpMat& Gy, const Mat2& u, Mat2& dx, Mat2& dy) {
  const int n = static_cast<int>(Gx.rows());
  const int* o = Gx.outerIndexPtr();
  const int* c = Gx.innerIndexPtr();
  const double *gx = Gx.valuePtr(), *gy = Gy.valuePtr();
  const double *u0 = u.data(), *u1 = u.data() + u.rows();
  for (int i = 0; i < n; ++i) {
    double a0 = 0, a1 = 0, b0 = 0, b1 = 0;
    for (int k = o[i]; k < o[i + 1]; ++k) {
      const double v0 = u0[c[k]], v1 = u1[c[k]];
      a0 += gx[k] * v0;  // d/dx of u
      a1 += gx[k] * v1;  // d/dx of v
      b0 += gy[k] * v0;  // d/dy of u
      b1 += gy[k] * v1;  // d/dy of v
    }
    dx(i, 0) = a0;
    dx(i, 1) = a1;
    dy(i, 0) = b0;
    dy(i, 1) = b1;
  }
}

void divergence(const SpMat& Gx, const SpMat& Gy, const Mat2& u, Vec& d) {
  const int n = static_cast<int>(Gx.rows());
  const int* o = Gx.outerIndexPtr();
  const int* c = Gx.innerIndexPtr();
  const double *gx = Gx.valuePtr(), *gy = Gy.valuePtr();
  const double *u0 = u.data(), *u1 = u.data() + u.rows();
  for (int i = 0; i < n; ++i) {
    double sx = 0, sy = 0;
    for (int k = o[i]; k < o[i + 1]; ++k) {
      sx += gx[k] * u0[c[k]];
      sy += gy[k] * u1[c[k]];
    }
    d[i] = sx + sy;
  }
}

void gradient(const SpMat& Gx, const SpMat& Gy, const Vec& f, Mat2& g) {
  const int n = static_cast<int>(Gx.rows());
  const int* o = Gx.outerIndexPtr();
  const int* c = Gx.innerIndexPtr();
  const double *gx = Gx.valuePtr(), *gy = Gy.valuePtr();
  for (int i = 0; i < n; ++i) {
    double sx = 0, sy = 0;
    for (int k = o[i]; k < o[i + 1]; ++k) {
      sx += gx[k] * f[c[k]];
      sy += gy[k] * f[c[k]];
    }
    g(i, 0) = sx;
    g(i, 1) = sy;
  }
}

}  // namespace sphib
