#pragma once
// The kernel sums of the divergence-free interpolation at one marker X (coupling/interpolate.hpp):
// over the particles j near X, with W_j = W(X - x_j) of Eq. (19) and d_j = X - x_j,
//   s = sum_j W_j,              sp = sum_j psi_j W_j,
//   g = sum_j grad W_j,         gp = sum_j psi_j grad W_j,        grad W_j = F_j d_j,
//   H = sum_j Hess W_j,         pH = sum_j psi_j Hess W_j,        Hess W_j = F_j I + G_j d_j d_j^T
// (F = (1/r) dW/dr, G = (1/r) dF/dr; the Hessians only when asked). The uniform volume cancels.
// The fast form takes the points two at a time (lanes); the plain form one at a time with the
// scalar kernel; tests/test_kernels.cpp checks they agree.
#include "kernels/cubic_spline.hpp"
#include "kernels/marker_points.hpp"

namespace sphib {

struct CurlSums {
  double s = 0, sp = 0, gx = 0, gy = 0, gpx = 0, gpy = 0;
  double hxx = 0, hxy = 0, hyy = 0, phxx = 0, phxy = 0, phyy = 0;
};

CurlSums curl_sums(const MarkerPoints& nb, const CubicSpline& W, const double* psi, bool hessian);
CurlSums curl_sums_plain(const MarkerPoints& nb, const CubicSpline& W, const double* psi, bool hessian);

}  // namespace sphib
