#include "fluid/shifting.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fluid/particle_operators.hpp"

namespace sphib {

Shifting shifting_from_name(const std::string& name) {
  if (name == "none") return Shifting::None;
  if (name == "fickian") return Shifting::Fickian;
  if (name == "xu") return Shifting::Xu;
  throw std::invalid_argument("isph.shifting: \"" + name + "\" is not allowed (allowed: fickian | xu | none)");
}

void ParticleShifter::shifts(const PairList& P, int N, double V, double V_wall, const CubicSplineKernel& W, double reach,
                             double dp, const Mat2& u, double dt, const std::vector<char>* surface, Mat2& dr) {
  dr.setZero(N, 2);
  near_.clear();
  if (prm_.kind == Shifting::None) return;
  // grad C_i with the tensile term (Lind et al. Eq. 22): the Fickian shift and, for both kinds, the
  // surface normal.
  gradC_.setZero(N, 2);
  const double W_dp = W.W(dp);
  for (int i = 0; i < N; ++i)
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const double r = P.r[k];
      if (r >= reach) continue;
      const double Vj = P.j[k] < N ? V : V_wall;
      double w;
      const double F = KernelWF(W).F(r, &w), q = w / W_dp, q2 = q * q;
      const double f = Vj * (1.0 + prm_.R * q2 * q2) * F;  // grad_i W_ij = x_ij F_ij; (W_ij / W(dp))^4
      gradC_(i, 0) += f * P.rx[k];
      gradC_(i, 1) += f * P.ry[k];
    }
  if (prm_.kind == Shifting::Fickian) {
    for (int i = 0; i < N; ++i) {
      const double D = prm_.A * W.h * u.row(i).norm() * dt;  // Lind et al. Eq. (24)
      dr.row(i) = -D * gradC_.row(i);                        // Lind et al. Eq. (21)
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
      const double rbar = rsum / n, c = prm_.beta * rbar * rbar * umax * dt;
      dr(i, 0) = c * sx;
      dr(i, 1) = c * sy;
    }
  }
  if (surface) surface_tangential(P, N, W, reach, *surface, dr);
  const double cap = prm_.max_shift * W.h;
  for (int i = 0; i < N; ++i) {
    const double s = dr.row(i).norm();
    if (s > cap) dr.row(i) *= cap / s;
  }
}

// Lind et al. (2012) Section 3.3: at the surface and within the support of a surface particle only the
// shift along the surface (see the header).
void ParticleShifter::surface_tangential(const PairList& P, int N, const CubicSplineKernel& W, double reach,
                                         const std::vector<char>& surface, Mat2& dr) {
  near_.assign(N, 0);
  for (int i = 0; i < N; ++i) {
    if (surface[i]) { near_[i] = 1; continue; }
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k)
      if (P.j[k] < N && P.r[k] < reach && surface[P.j[k]]) { near_[i] = 1; break; }
  }
  normal_.setZero(N, 2);
  const double W0 = W.W(0.0);
  for (int i = 0; i < N; ++i) {
    if (!near_[i]) continue;
    normal_.row(i) = W0 * gradC_.row(i);
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const int j = P.j[k];
      if (j < N && P.r[k] < reach) normal_.row(i) += W.W(P.r[k]) * gradC_.row(j);
    }
  }
  for (int i = 0; i < N; ++i) {
    if (!near_[i]) continue;
    const double n = normal_.row(i).norm();
    if (n == 0) { dr.row(i).setZero(); continue; }
    const double nx = normal_(i, 0) / n, ny = normal_(i, 1) / n;  // s = (-ny, nx)
    const double ds = -ny * dr(i, 0) + nx * dr(i, 1);             // Lind et al. Eq. (27), alpha = 0
    dr(i, 0) = -ny * ds;
    dr(i, 1) = nx * ds;
  }
}

void ParticleShifter::carry_velocity(const PairList& P, int N, double V, const CubicSplineKernel& W, double reach,
                                     const Mat2& dr, Mat2& u) {
  du_.setZero(N, 2);
  const bool near = static_cast<int>(near_.size()) == N;  // the last shifts() had a free surface
  for (int i = 0; i < N; ++i) {
    if (dr(i, 0) == 0 && dr(i, 1) == 0) continue;
    if (near && near_[i]) continue;  // at and beside the surface: not carried (see the header)
    double gxx = 0, gxy = 0, gyx = 0, gyy = 0;  // g_ab = d u_a / d x_b
    for (int k = P.offset[i]; k < P.offset[i + 1]; ++k) {
      const int j = P.j[k];
      if (j >= N || P.r[k] >= reach) continue;
      const double f = V * W.F(P.r[k]), ax = f * P.rx[k], ay = f * P.ry[k];  // V grad_i W_ij
      const double dux = u(j, 0) - u(i, 0), duy = u(j, 1) - u(i, 1);
      gxx += dux * ax; gxy += dux * ay;
      gyx += duy * ax; gyy += duy * ay;
    }
    du_(i, 0) = gxx * dr(i, 0) + gxy * dr(i, 1);  // Xu et al. (2009) Eq. (37)
    du_(i, 1) = gyx * dr(i, 0) + gyy * dr(i, 1);
  }
  u += du_;
}

}  // namespace sphib
