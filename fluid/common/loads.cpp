#include "fluid/common/loads.hpp"

#include <cmath>

namespace sphib {

namespace {
WallForces no_walls() { return {NAN, NAN, NAN, NAN}; }
}  // namespace

WallForces wall_forces_from_particles(const Lattice& L, const VirtualWalls& w, const Vec& p_wall) {
  WallForces f = no_walls();
  for (int s = 0; s < 4; ++s)
    if (L.domain.is_wall(static_cast<Side>(s))) f[s] = 0.0;
  for (int k = 0; k < w.size(); ++k) {
    const int s = w.side[k];
    if (s < 0 || !w.inner[k]) continue;  // corner blocks and deeper rows
    const double ds = s == Left || s == Right ? L.dy : L.dx;
    f[s] += p_wall[k] * ds;  // A Eq. (32), midpoint rule of Eq. (31)
  }
  return f;
}

WallForces wall_forces_by_interpolation(const Domain& d, const Mat2& x, const Vec& V, const Vec& p,
                                        const CubicSplineKernel& W, double ds_x, double ds_y) {
  WallForces f = no_walls();
  const double reach = W.support();
  for (int s = 0; s < 4; ++s) {
    const Side side = static_cast<Side>(s);
    if (!d.is_wall(side)) continue;
    const bool vertical = side == Left || side == Right;  // the wall line x = const
    const double line = side == Left ? d.x0 : side == Right ? d.x1 : side == Bottom ? d.y0 : d.y1;
    const double a0 = vertical ? d.y0 : d.x0, ds = vertical ? ds_y : ds_x;
    const int n = std::max(1, static_cast<int>(std::lround((vertical ? d.Ly() : d.Lx()) / ds)));
    Vec num = Vec::Zero(n), den = Vec::Zero(n);
    for (int i = 0; i < x.rows(); ++i) {
      const double across = (vertical ? x(i, 0) : x(i, 1)) - line, along = vertical ? x(i, 1) : x(i, 0);
      if (std::fabs(across) >= reach) continue;
      const int k0 = std::max(0, static_cast<int>(std::floor((along - reach - a0) / ds - 0.5)));
      const int k1 = std::min(n - 1, static_cast<int>(std::ceil((along + reach - a0) / ds - 0.5)));
      for (int k = k0; k <= k1; ++k) {  // sample k at a0 + (k + 1/2) ds along the wall
        const double w = V[i] * W.W(std::hypot(across, along - (a0 + (k + 0.5) * ds)));
        num[k] += w * p[i];
        den[k] += w;
      }
    }
    double F = 0;
    for (int k = 0; k < n; ++k)
      if (den[k] > 0) F += num[k] / den[k] * ds;  // Shepard p at the sample, midpoint rule of Eq. (31)
    f[s] = F;
  }
  return f;
}

WallForces wall_shear_stress(const Lattice& L, const Mat2& u, double mu) {
  WallForces tau = no_walls();
  const Domain& d = L.domain;
  const int nx = L.nx, ny = L.ny;
  // sign * (9 u_1 - u_2 - 8 U_w) / (3 d): rows (or columns) 1 and 2 counted from the wall
  auto derivative = [](double u1, double u2, double Uw, double dn) { return (9.0 * u1 - u2 - 8.0 * Uw) / (3.0 * dn); };
  for (int s = 0; s < 4; ++s) {
    const Side side = static_cast<Side>(s);
    if (!d.is_wall(side)) continue;
    double sum = 0.0;
    if (side == Bottom || side == Top) {  // mu du/dy
      const int j1 = side == Bottom ? 0 : ny - 1, j2 = side == Bottom ? 1 : ny - 2;
      const double sign = side == Bottom ? 1.0 : -1.0, Uw = d.wall_velocity[s].x();
      for (int i = 0; i < nx; ++i) sum += sign * derivative(u(i + nx * j1, 0), u(i + nx * j2, 0), Uw, L.dy);
      tau[s] = mu * sum / nx;
    } else {  // mu dv/dx
      const int i1 = side == Left ? 0 : nx - 1, i2 = side == Left ? 1 : nx - 2;
      const double sign = side == Left ? 1.0 : -1.0, Vw = d.wall_velocity[s].y();
      for (int j = 0; j < ny; ++j) sum += sign * derivative(u(i1 + nx * j, 1), u(i2 + nx * j, 1), Vw, L.dx);
      tau[s] = mu * sum / ny;
    }
  }
  return tau;
}

void wall_particle_pressure(WallPressure kind, int N, const ParticlePairs& P, const Vec& V, const Vec& p,
                            const Vec& rho, const Eigen::Vector2d& g, Vec& p_wall, Vec& workspace) {
  if (kind == WallPressure::Rest) return;
  p_wall.setZero();
  Vec& sum_W = workspace;
  sum_W.setZero(p_wall.size());
  for (int k = 0; k < P.size(); ++k) {
    const int j = P.j[k] - N, i = P.i[k];
    if (j < 0) continue;  // fluid with fluid
    if (kind == WallPressure::Eq30) {
      p_wall[j] += V[i] * p[i] * P.W[k];  // A Eq. (30)
    } else {
      // Adami et al. (2012) Eq. (27), walls at rest: x_w - x_i = -(P.rx, P.ry)
      p_wall[j] += (p[i] - rho[i] * (g.x() * P.rx[k] + g.y() * P.ry[k])) * P.W[k];
      sum_W[j] += P.W[k];
    }
  }
  if (kind == WallPressure::Extrapolated)
    for (int j = 0; j < p_wall.size(); ++j) p_wall[j] = sum_W[j] > 0 ? p_wall[j] / sum_W[j] : 0.0;
}

}  // namespace sphib
