#pragma once
// Spreading one marker's force onto the fluid particles around it, Eq. (53):
//   F_i += f_k ds W(x_i - X_k, h*)
// over a box of the fixed lattice (rows and columns around X_k) or over a list of gathered points.
// Each in its fast form (lanes, AVX2 or SSE2 chosen at load time) and its plain form (the sum as
// written, one point at a time, the scalar W of Eq. (19)); tests/test_kernels.cpp checks they agree.
#include "kernels/cubic_spline.hpp"
#include "kernels/marker_points.hpp"

namespace sphib {

// A marker's box on the fixed lattice: the points (row r, column c) at index base[r] + col[c], at
// offsets cdx[c] (x) and ry[r] (y) from the marker; at most kMaxCols columns.
struct LatticeRows {
  static constexpr int kMaxCols = 256;
  int ncol = 0, nrow = 0;
  const int* col;
  const double* cdx;
  const int* base;
  const double* ry;
};

// Fx[i] += fx W(x_i - X_k, h*), Fy[i] += fy W(...) for every point i of the box (Eq. 53); points
// beyond 2h* add +-0 (W = 0), which leaves F bit for bit as the sum over the points within 2h*.
void spread_rows(const LatticeRows& box, const CubicSpline& W, double fx, double fy, double* Fx, double* Fy);
void spread_rows_plain(const LatticeRows& box, const CubicSpline& W, double fx, double fy, double* Fx, double* Fy);

// The same over gathered points (any particles, two at a time: MarkerPoints)
void spread_pairs(const MarkerPoints& nb, const CubicSpline& W, double fx, double fy, double* Fx, double* Fy);
void spread_pairs_plain(const MarkerPoints& nb, const CubicSpline& W, double fx, double fy, double* Fx, double* Fy);

}  // namespace sphib
