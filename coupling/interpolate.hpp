#pragma once
// Fluid velocity -> marker velocity, two ways.
//
// SPH (the paper): normalised SPH interpolation, Eqs. (61)-(63),
//   U(X) = sum_j u_j W(X - x_j, h) V_j / sum_j W(X - x_j, h) V_j,
// exact for a constant field. (The unnormalised form, Eq. (60), is the adjoint of spreading.) Its
// divergence between particles is not zero, so a closed curve moving with it gains or loses area.
//
// Divergence-free: Eq. (63) applied to a stream function psi of the fluid velocity
// (FluidSolver::stream_function), then differentiated analytically,
//   psi_h(X) = sum_j psi_j W_j / sum_j W_j,          W_j = W(X - x_j, h)
//   U(X) = U_mean + (d psi_h/dy, -d psi_h/dx),  grad psi_h(X) = sum_j (psi_j - psi_h(X)) grad W_j / sum_j W_j.
// U is the curl of a C^2 function, so its divergence is exactly zero everywhere (in the spirit of the
// divergence-free immersed boundary method of Bao, Donev, Griffith, McQueen & Peskin, J. Comput.
// Phys. 347 (2017) 183), and a closed curve moving with it keeps its area up to the time
// integration. psi_h reproduces constants, so the gauge of psi does not matter; at a lattice point
// grad psi_h is (G psi)_i / sum_j V W_ij, the fluid's own gradient of psi (Eq. 27) over the kernel sum.
#include "coupling/marker_update.hpp"
#include "kernels/cubic_spline.hpp"
#include "fluid/common/neighbours.hpp"

namespace sphib {

// U (Nb x 2) at the points X from the particle field u (N x 2). Throws std::runtime_error if a
// point has no particle within 2h (a marker that left the fluid).
void interpolate_velocity(const CellGrid& grid, const CubicSplineKernel& W, double V, const Mat2& u,
                          const Mat2& X, Mat2& U, bool normalised = true);
// The same with per-particle volumes V_j = m_j / rho_j (moving particles, WCSPH).
void interpolate_velocity(const CellGrid& grid, const CubicSplineKernel& W, const Vec& V, const Mat2& u,
                          const Mat2& X, Mat2& U, bool normalised = true);

// The divergence-free marker velocity above, with the kernel W of any radius (the fluid's h, or the
// spreading's h*: coupling.interpolation = "spreading_kernel"; the lattice boxes gather up to
// CellGrid::LatticeBox::kMax columns), from psi at the particles of `grid` and the uniform
// flow U_mean; with dU non-null also its gradient dU/dX at X (from the Hessian of psi_h, exact for
// the interpolant: trace 0). Throws like interpolate_velocity for a point with no particle within 2h.
void interpolate_curl(const CellGrid& grid, const CubicSplineKernel& W, const Vec& psi,
                      const Eigen::Vector2d& U_mean, const Mat2& X, Mat2& U, Jacobians* dU = nullptr);

// The same curl with psi interpolated by tensor-product cubic B-splines of the lattice spacing,
//   psi_h(X) = sum_ij psi_ij B((X - x_i)/dx) B((Y - y_j)/dy),   U(X) = U_mean + (d psi_h/dy, -d psi_h/dx),
// B the cubic B-spline (support 2 spacings). On the uniform lattice sum_i B = 1 and sum_i x_i B = X
// exactly, so psi_h reproduces linear stream functions (uniform flows) and its derivatives carry no
// lattice-periodic ripple; the kernel form above reproduces only constants, and its gradient of a
// linear psi ripples at the lattice scale (measured: second differences along a line 120x those of
// Eq. 63), which bending stiffness turns into marker-scale growth. 16 lattice points per marker.
// `grid` must be in lattice mode (EPSPH); throws like interpolate_velocity when a point's 4 x 4
// stencil leaves the lattice (within two spacings of a wall).
void interpolate_curl_bspline(const CellGrid& grid, double dx, double dy, const Vec& psi, const Eigen::Vector2d& U_mean,
                              const Mat2& X, Mat2& U, Jacobians* dU = nullptr);

}  // namespace sphib
