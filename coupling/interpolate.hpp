#pragma once
// Fluid velocity -> marker velocity by normalised SPH interpolation, Eqs. (61)-(63):
//   U(X) = sum_j u_j W(X - x_j, h) V_j / sum_j W(X - x_j, h) V_j,
// exact for a constant field. (The unnormalised form, Eq. (60), is the adjoint of spreading.)
#include "fluid/kernel.hpp"
#include "fluid/neighbours.hpp"

namespace sphib {

// U (Nb x 2) at the points X from the particle field u (N x 2). Throws std::runtime_error if a
// point has no particle within 2h (a marker that left the fluid).
void interpolate_velocity(const CellGrid& grid, const CubicSplineKernel& W, double V, const Mat2& u,
                          const Mat2& X, Mat2& U, bool normalised = true);
// The same with per-particle volumes V_j = m_j / rho_j (moving particles, WCSPH).
void interpolate_velocity(const CellGrid& grid, const CubicSplineKernel& W, const Vec& V, const Mat2& u,
                          const Mat2& X, Mat2& U, bool normalised = true);

}  // namespace sphib
