#pragma once
// Membrane force -> fluid force field, Eq. (53):  F_i = sum_k f_k W(x_i - X_k, h*) ds,
// with f_k the force density per unit rest arclength and ds = L0 / Nb the rest marker spacing.
// The kernel radius h* is the membrane's own, independent of the fluid's h.
#include "kernels/cubic_spline.hpp"
#include "fluid/common/neighbours.hpp"

namespace sphib {

// Adds the spread force of one membrane into F (N x 2). grid holds the fluid particles and has
// cells of at least 2 h*. Cost O(Nb * particles per kernel support).
void spread_force(const CellGrid& grid, const CubicSplineKernel& W_star, const Mat2& X, const Mat2& f,
                  double ds, Mat2& F);

// The same for point forces P_k = f_k ds at the markers X (any number of membranes sharing h*, their
// markers concatenated: one pass over all of them). Bit for bit the sum of spread_force over the
// membranes in the same order, with P = f ds.
void spread_point_forces(const CellGrid& grid, const CubicSplineKernel& W_star, const Mat2& X, const Mat2& P, Mat2& F);

}  // namespace sphib
