#include "fluid/moving/shifting.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fluid/moving/particle_operators.hpp"
#include "fluid/algebra/products.hpp"

namespace sphib {

void concentration_sums(const PairList& P, int N, double V, double V_wall, const CubicSplineKernel& W, double reach,
                        double dp, double R, const std::vector<char>* surface, ConcentrationSums& out) {
  out.grad_C.setZero(N, 2);
  out.sum_F.setZero(N);
  out.near.assign(N, 0);
  const KernelWF K(W);
  const double W_dp = W.W(dp);
  for (int i = 0; i < N; ++i) {
    double gx = 0, gy = 0, sf = 0;
    bool near = surface && (*surface)[i];
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const double r = P.r[k];
      if (r >= reach) continue;
      const int j = P.j[k];
      double w;
      const double F = K.F(r, &w), q = w / W_dp, q2 = q * q;
      const double f = (j < N ? V : V_wall) * (1.0 + R * q2 * q2) * F;  // Lind et al. Eq. (22), n = 4
      gx += f * P.rx[k];  // grad_i W_ij = x_ij F_ij
      gy += f * P.ry[k];
      sf += F;
      if (surface && j < N && (*surface)[j]) near = true;
    }
    out.grad_C(i, 0) = gx;
    out.grad_C(i, 1) = gy;
    out.sum_F[i] = sf;
    out.near[i] = near;
  }
}

void ParticleShifter::shifts(const PairList& P, int N, const CubicSplineKernel& W, double reach,
                             const ConcentrationSums& c, const Mat2& u, double dt, const std::vector<char>* surface,
                             Mat2& dr) {
  dr.setZero(N, 2);
  if (prm_.kind == Shifting::None) return;
  if (prm_.kind == Shifting::Fickian) {
    for (int i = 0; i < N; ++i) {
      const double D = prm_.A * W.h * u.row(i).norm() * dt;  // Lind et al. Eq. (24)
      dr.row(i) = -D * c.grad_C.row(i);                      // Lind et al. Eq. (21)
    }
  } else {  // Xu et al. (2009) Eq. (35): beta rbar_i^2 u_max dt sum_j x_ij / r_ij^3
    const double umax = u.rowwise().norm().maxCoeff();
    for (int i = 0; i < N; ++i) {
      double sx = 0, sy = 0, rsum = 0;
      int n = 0;
      for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
        const double r = P.r[k];
        if (r >= reach || r <= 0) continue;
        const double r3 = r * r * r;
        sx += P.rx[k] / r3;
        sy += P.ry[k] / r3;
        rsum += r;
        ++n;
      }
      if (n == 0) continue;
      const double rbar = rsum / n, a = prm_.beta * rbar * rbar * umax * dt;
      dr(i, 0) = a * sx;
      dr(i, 1) = a * sy;
    }
  }
  if (surface) surface_tangential(P, N, W, reach, c, dr);
  const double cap = prm_.max_shift * W.h;
  for (int i = 0; i < N; ++i) {
    const double s = dr.row(i).norm();
    if (s > cap) dr.row(i) *= cap / s;
  }
}

// Lind et al. (2012) Section 3.3: at the surface and within the support of a surface particle only the
// shift along the surface (see the header).
void ParticleShifter::surface_tangential(const PairList& P, int N, const CubicSplineKernel& W, double reach,
                                         const ConcentrationSums& c, Mat2& dr) {
  const double W0 = W.W(0.0);
  for (int i = 0; i < N; ++i) {
    if (!c.near[i]) continue;
    double nx = W0 * c.grad_C(i, 0), ny = W0 * c.grad_C(i, 1);
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const int j = P.j[k];
      if (j >= N || P.r[k] >= reach) continue;
      const double w = W.W(P.r[k]);
      nx += w * c.grad_C(j, 0);
      ny += w * c.grad_C(j, 1);
    }
    const double n = std::hypot(nx, ny);
    if (n == 0) { dr.row(i).setZero(); continue; }
    nx /= n, ny /= n;                                  // s = (-ny, nx)
    const double ds = -ny * dr(i, 0) + nx * dr(i, 1);  // Lind et al. Eq. (27), alpha = 0
    dr(i, 0) = -ny * ds;
    dr(i, 1) = nx * ds;
  }
}

void ParticleShifter::carry_velocity(const SpMat& gx, const SpMat& gy, const ConcentrationSums& c, const Mat2& dr,
                                     Mat2& u) {
  const int N = static_cast<int>(u.rows());
  gxu_.resize(N, 2);
  gyu_.resize(N, 2);
  gradient2(gx, gy, u, gxu_, gyu_);  // d u_a / d x, d u_a / d y (products.hpp: one pass over the pattern)
  for (int i = 0; i < N; ++i) {
    if (c.near[i]) continue;  // at and beside the surface: not carried (see the header)
    u(i, 0) += gxu_(i, 0) * dr(i, 0) + gyu_(i, 0) * dr(i, 1);  // Xu et al. (2009) Eq. (37)
    u(i, 1) += gxu_(i, 1) * dr(i, 0) + gyu_(i, 1) * dr(i, 1);
  }
}

}  // namespace sphib
