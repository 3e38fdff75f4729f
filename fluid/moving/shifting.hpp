#pragma once
// Particle shifting: a small displacement of each particle after its advection that keeps the
// particle distribution regular, for ISPH (isph.hpp; Afanasiev et al. advect the particles with
// u^{n+1} alone, A Eq. 25). The velocity is carried to the shifted position by its Taylor expansion
// (Xu et al. 2009, Eq. 37; Lind et al. 2012, Eq. 28): u_i <- u_i + (dr_i . grad) u_i, except at and
// beside the free surface: there the support is cut and the gradient one-sided, and carrying u with it
// fed the stretching of thin films along a wall (docs/method/choices.md, "ISPH: shifting beside the
// surface"). The caller cuts the shifts that a wall refuses before u is carried (isph.cpp, end_step),
// so that u is carried by the shift the particle makes.
//
//  - Fickian (Lind, Xu, Stansby & Rogers 2012, J. Comput. Phys. 231:1499-1523, Eqs. 21-24): the
//    particles diffuse down the gradient of their concentration C_i = sum_j V_j W_ij,
//      dr_i = -D grad C_i,  D = A h |u_i| dt  (A = 2, their choice in [1, 6]),
//      grad C_i = sum_j V_j (1 + R (W_ij / W(dp))^n) grad_i W_ij   (R = 0.2, n = 4: the tensile term
//    of Monaghan 2000, J. Comput. Phys. 159:290, that keeps pairs from clustering; dp the initial
//    spacing). The wall particles count in C: they complete a support cut by a wall, and a particle
//    closer to a wall than the lattice spacing is pushed off it.
//  - Xu (Xu, Stansby & Laurence 2009, J. Comput. Phys. 228:6703-6725, Eqs. 35-36): the simpler
//    repulsion dr_i = beta rbar_i^2 u_max dt sum_j x_ij / r_ij^3 (beta = 0.04, rbar_i the mean
//    distance to i's neighbours, u_max the largest speed), the same walls.
//  - Free surface (Lind et al. 2012, Section 3.3, Eqs. 26-27): at a free-surface particle, and at one
//    within the kernel's support of it, the support is cut by the surface and grad C points into
//    the fluid whatever the distribution; the shift keeps only its component along the surface,
//    dr_i <- (dr_i . s_i) s_i, s_i perpendicular to the surface normal n_i. n_i is the kernel-weighted
//    mean of the neighbours' grad C (so that the tangential part of a particle's own grad C, which the
//    disorder makes, survives: with n_i = grad C_i / |grad C_i| it would vanish).
//  - Each shift is bounded by max_shift h (a shift is a correction of the distribution, small
//    against the spacing; at most 0.1 h per step, the bound of King & Lind's ISPH code).
#include <string>
#include <vector>

#include "kernels/cubic_spline.hpp"
#include "fluid/common/neighbours.hpp"
#include "fluid/common/params.hpp"
#include "fluid/common/types.hpp"

namespace sphib {


struct ShiftingParams {
  Shifting kind = Shifting::Fickian;
  double A = 2.0;           // Fickian: D = A h |u_i| dt (Lind et al. Eq. 24)
  double R = 0.2;           // Fickian: tensile term R (W_ij / W(dp))^4 (Lind et al. Eq. 22, n = 4)
  double beta = 0.04;       // Xu: dr = beta rbar^2 u_max dt sum_j x_ij / r_ij^3 (Xu et al. Eq. 35)
  double max_shift = 0.1;   // |dr_i| <= max_shift h
};

// One pass over the pairs of N particles (i's neighbours in [P.offset[i], P.offset[i+1]), j >= N a
// fixed wall particle of volume V_wall; pairs at or beyond `reach` skipped; the particles' volume V, dp
// the initial spacing): grad C_i with the tensile term (Lind et al. Eq. 22, R), the kernel sum
// sum_j F_ij over every neighbour, and near_i = 1 for the particles at or beside the free surface
// (surface[i], or a surface particle within reach; all 0 without a surface).
struct ConcentrationSums {
  Mat2 grad_C;
  Vec sum_F;
  std::vector<char> near;
};
void concentration_sums(const PairList& P, int N, double V, double V_wall, const CubicSplineKernel& W, double reach,
                        double dp, double R, const std::vector<char>* surface, ConcentrationSums& out);

// The shifts dr of N particles from the sums of the step's pairs (concentration_sums), their
// velocities u, the time step and the surface flags (nullptr: no free surface).
class ParticleShifter {
 public:
  explicit ParticleShifter(const ShiftingParams& p) : prm_(p) {}
  const ShiftingParams& params() const { return prm_; }

  void shifts(const PairList& P, int N, const CubicSplineKernel& W, double reach, const ConcentrationSums& c,
              const Mat2& u, double dt, const std::vector<char>* surface, Mat2& dr);
  // u_i += (dr_i . grad) u_i away from the free surface (c.near_i = 0), grad u the difference-form
  // gradient by the operators gx = d/dx, gy = d/dy on the particle values (A Eq. 14's, the walls'
  // mirror rule included: isph.cpp's op_.grad_ux.A, grad_uy.A).
  void carry_velocity(const SpMat& gx, const SpMat& gy, const ConcentrationSums& c, const Mat2& dr, Mat2& u);

 private:
  void surface_tangential(const PairList& P, int N, const CubicSplineKernel& W, double reach,
                          const ConcentrationSums& c, Mat2& dr);

  ShiftingParams prm_;
  Mat2 gxu_, gyu_;
};

}  // namespace sphib
