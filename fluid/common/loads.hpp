#pragma once
// Hydrodynamic loads (Afanasiev, Makarchuk & Popov 2011 ["A"], Section 4) and the pressure of wall
// particles (A Eq. 30).
//
// The load on a wall Gamma is P_s = int_Gamma [p(T) - p(0)] dGamma (A Eq. 31), a force per unit
// depth (N/m in SI units). A methods reports the pressure integral F(T) = int_Gamma p(T) dGamma of
// each wall (FluidSolver::wall_forces); observe/loads.cpp writes F and P_s = F(T) - F(0).
//  - Methods with Morris wall particles carrying a pressure (WCSPH with wcsph.wall_pressure eq30 or
//    extrapolated; ISPH): A Eq. (32), P_s ~ sum_{j in P_b} p_j(T) - p_j(0), read as the midpoint rule
//    of Eq. (31): P_b the wall particles of the row next to the fluid (half a spacing beyond the
//    wall line), each weighted by its spacing ds along the wall (A writes the sum without ds; with
//    it the load is a force and does not depend on the resolution).
//  - Methods whose walls are image particles (EPSPH, LPSPH; WCSPH with wall particles at rest): the
//    wall pressure is that of the fluid at the wall line, the Shepard interpolation
//    sum_j V_j p_j W / sum_j V_j W of the particles within 2h at points ds apart along the wall.
//    The images mirror their parents' pressure (Neumann, boundary.hpp), so at the wall line they
//    add the same sum again and drop out of the ratio.
#include <array>

#include "kernels/cubic_spline.hpp"
#include "fluid/common/lattice.hpp"
#include "fluid/common/pair_search.hpp"
#include "fluid/common/params.hpp"
#include "fluid/common/walls.hpp"

namespace sphib {

// A Eq. (32) over the wall particles next to the fluid, p_wall their pressures.
WallForces wall_forces_from_particles(const Lattice& L, const VirtualWalls& w, const Vec& p_wall);

// The Shepard interpolation of p at the wall lines (N particles at x with volumes V), ds apart.
WallForces wall_forces_by_interpolation(const Domain& d, const Mat2& x, const Vec& V, const Vec& p,
                                        const CubicSplineKernel& W, double ds_x, double ds_y);

// The fluid's shear stress at each wall, the mean along it of mu du_t/dy on the bottom and top walls
// and mu dv/dx on the left and right ones (sigma_xy at the wall line; NaN for a side without a wall),
// from the fixed lattice L (particles half a spacing off a wall, Eq. 68) and its velocity u (N x 2, in
// L's order): the derivative at the wall of the quadratic through the wall's velocity at the wall
// line and the first two rows, du/dn(0) = (9 u_1 - u_2 - 8 U_w) / (3 d) (second order; exact for the
// linear profile of Couette flow), with n pointing into the fluid from the bottom and left walls and
// out of it at the top and right ones (so both walls of a sheared box give the same sign).
WallForces wall_shear_stress(const Lattice& L, const Mat2& u, double mu);

// The pressure of the wall particles, from their fluid neighbours (pairs i < N fluid, j >= N the
// wall particle j - N; V, p, rho of the fluid particles):
//  - Rest: the equation of state at the rest density (Morris et al. 1997), set by the method;
//  - Eq30: A Eq. (30), p_w = sum_j V_j p_j W_wj;
//  - Extrapolated: A Eq. (30) normalised, with the hydrostatic term of Adami, Hu & Adams (2012,
//    Eq. 27) for walls at rest, p_w = sum_j (p_j + rho_j g . (x_w - x_j)) W_wj / sum_j W_wj, which
//    holds a fluid at rest exactly where A Eq. (30) gives about a third of the pressure at the wall.
// A wall particle with no fluid neighbour gets p_w = 0.
void wall_particle_pressure(WallPressure kind, int N, const ParticlePairs& P, const Vec& V, const Vec& p,
                            const Vec& rho, const Eigen::Vector2d& g, Vec& p_wall, Vec& workspace);

}  // namespace sphib
