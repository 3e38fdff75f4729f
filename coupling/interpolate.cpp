#include "coupling/interpolate.hpp"

#include "coupling/neighbourhood.hpp"
#include "fluid/common/interpolation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {
[[noreturn]] void no_particle(int k, const Mat2& X) {
  std::ostringstream m;
  m << " at (" << X(k, 0) << ", " << X(k, 1) << ") has no fluid particle within 2h";
  throw MarkerError("interpolation: marker ", k, m.str());
}
}  // namespace

// Eq. (63) (normalised) or Eq. (60), by fluid/common/interpolation.hpp
void interpolate_velocity(const CellGrid& grid, const CubicSplineKernel& W, double V, const Mat2& u,
                          const Mat2& X, Mat2& U, bool normalised) {
  interpolate_normalised<2>(grid, W, UniformVolume{V}, u, X, U, normalised, "interpolation: marker");
}

void interpolate_velocity(const CellGrid& grid, const CubicSplineKernel& W, const Vec& V, const Mat2& u,
                          const Mat2& X, Mat2& U, bool normalised) {
  interpolate_normalised<2>(grid, W, V, u, X, U, normalised, "interpolation: marker");
}

namespace {

// The kernel sums of the divergence-free interpolation at one marker, two lanes each: W_j, psi_j W_j,
// grad W_j, psi_j grad W_j and, for its gradient, the Hessians of W_j (F I + G d d^T, d = X - x_j)
// and psi_j times them. The uniform volume cancels.
struct CurlSums {
  Lanes2 s{}, sp{}, gx{}, gy{}, gpx{}, gpy{};
  Lanes2 hxx{}, hxy{}, hyy{}, phxx{}, phxy{}, phyy{};

  template <bool kHessian>
  void add(const Neighbourhood& nb, const CubicSplineKernel& W, const Vec& psi) {
    for (int i = 0; i < nb.pairs; ++i) {
      Lanes2 w, F, G;
      if constexpr (kHessian) W.W_F_G2(nb.r2(i), w, F, G);  // W(X - x_j), (1/r) dW/dr, (1/r) dF/dr
      else W.W_F2(nb.r2(i), w, F);
      const Lanes2 p{psi[nb.j0(i)], psi[nb.j1(i)]}, dx = nb.dx(i), dy = nb.dy(i);
      s += w;
      sp += p * w;
      const Lanes2 wx = F * dx, wy = F * dy;  // grad_X W(X - x_j) = F (X - x_j)
      gx += wx;
      gy += wy;
      gpx += p * wx;
      gpy += p * wy;
      if constexpr (kHessian) {  // Hess W(X - x_j) = F I + G d d^T
        const Lanes2 Gx = G * dx, Gy = G * dy, Hxx = F + Gx * dx, Hxy = Gx * dy, Hyy = F + Gy * dy;
        hxx += Hxx;
        hxy += Hxy;
        hyy += Hyy;
        phxx += p * Hxx;
        phxy += p * Hxy;
        phyy += p * Hyy;
      }
    }
  }
};

double sum(Lanes2 a) { return a[0] + a[1]; }

}  // namespace

// (Compiled twice, SSE2 and AVX2, chosen at load time: the same two-lane arithmetic, fewer register
// copies and spills with AVX's three-operand instructions; measured 1-2 us of the ~37 us marker
// update per step of the main job.)
[[gnu::target_clones("avx2", "default")]] void interpolate_curl(const CellGrid& grid, const CubicSplineKernel& W,
                                                              const Vec& psi, const Eigen::Vector2d& U_mean,
                                                              const Mat2& X, Mat2& U, Jacobians* dU) {
  const double radius = W.support();
  Neighbourhood nb;
  if (dU) dU->resize(X.rows(), 4);
  for (int k = 0; k < X.rows(); ++k) {
    nb.gather(grid, X(k, 0), X(k, 1), radius);
    CurlSums c;
    if (dU) c.add<true>(nb, W, psi);
    else c.add<false>(nb, W, psi);
    const double S = sum(c.s);
    if (!(S > 0)) no_particle(k, X);
    const double ph = sum(c.sp) / S;  // psi_h(X)
    // grad psi_h = sum_j (psi_j - psi_h) grad W_j / sum_j W_j
    const double G0x = sum(c.gx), G0y = sum(c.gy);
    const double dpx = (sum(c.gpx) - ph * G0x) / S, dpy = (sum(c.gpy) - ph * G0y) / S;
    U(k, 0) = U_mean.x() + dpy;  // u = d psi/dy
    U(k, 1) = U_mean.y() - dpx;  // v = -d psi/dx
    if (!dU) continue;
    // d2 psi_h/dadb = (H1_ab - psi_h H0_ab - dpsi_b G0_a - dpsi_a G0_b) / S, H0 = sum_j Hess W_j, H1 = sum_j psi_j Hess W_j
    const double pxx = (sum(c.phxx) - ph * sum(c.hxx) - 2.0 * dpx * G0x) / S;
    const double pxy = (sum(c.phxy) - ph * sum(c.hxy) - dpy * G0x - dpx * G0y) / S;
    const double pyy = (sum(c.phyy) - ph * sum(c.hyy) - 2.0 * dpy * G0y) / S;
    (*dU)(k, 0) = pxy;   // dUx/dx = d2 psi/dxdy
    (*dU)(k, 1) = pyy;   // dUx/dy
    (*dU)(k, 2) = -pxx;  // dUy/dx
    (*dU)(k, 3) = -pxy;  // dUy/dy
  }
}

}  // namespace sphib

namespace sphib {

namespace {
// The cubic B-spline with unit knot spacing, its first and second derivatives: support |t| < 2,
// sum_i B(t - i) = 1 and sum_i i B(t - i) = t (it reproduces linear functions on the lattice).
inline void bspline3(double t, double& b, double& d1, double& d2) {
  const double a = std::fabs(t), s = t < 0 ? -1.0 : 1.0;
  if (a < 1.0) {
    b = 2.0 / 3.0 - a * a + 0.5 * a * a * a;
    d1 = s * (-2.0 * a + 1.5 * a * a);
    d2 = -2.0 + 3.0 * a;
  } else if (a < 2.0) {
    const double r = 2.0 - a;
    b = r * r * r / 6.0;
    d1 = -s * 0.5 * r * r;
    d2 = r;
  } else {
    b = d1 = d2 = 0.0;
  }
}
}  // namespace

void interpolate_curl_bspline(const CellGrid& grid, double dx, double dy, const Vec& psi, const Eigen::Vector2d& U_mean,
                              const Mat2& X, Mat2& U, Jacobians* dU) {
  if (!grid.lattice_mode()) throw std::invalid_argument("interpolate_curl_bspline: needs the fixed lattice (EPSPH)");
  if (dU) dU->resize(X.rows(), 4);
  CellGrid::LatticeBox box;
  const double r = 2.0 * std::max(dx, dy);
  for (int k = 0; k < X.rows(); ++k) {
    grid.lattice_box(X(k, 0), X(k, 1), r, box);
    double bx[CellGrid::LatticeBox::kMax], gx[CellGrid::LatticeBox::kMax], hx[CellGrid::LatticeBox::kMax];
    for (int c = 0; c < box.ncol; ++c) {
      bspline3(box.cdx[c] / dx, bx[c], gx[c], hx[c]);
      gx[c] /= dx;
      hx[c] /= dx * dx;
    }
    double px = 0, py = 0, pxx = 0, pxy = 0, pyy = 0, sw = 0;
    for (int rr = 0; rr < box.nrow; ++rr) {
      double by, gy, hy;
      bspline3(box.ry[rr] / dy, by, gy, hy);
      gy /= dy;
      hy /= dy * dy;
      double s0 = 0, s1 = 0, s2 = 0, w0 = 0;
      for (int c = 0; c < box.ncol; ++c) {
        const double p = psi[box.base[rr] + box.col[c]];
        s0 += p * bx[c];
        s1 += p * gx[c];
        s2 += p * hx[c];
        w0 += bx[c];
      }
      sw += w0 * by;
      px += s1 * by;   // d psi_h/dx: d/dX of B((X - x_i)/dx) = B'/dx
      py += s0 * gy;
      pxx += s2 * by;
      pxy += s1 * gy;
      pyy += s0 * hy;
    }
    if (!(std::fabs(sw - 1.0) < 1e-9)) {  // the stencil left the lattice (a wall)
      std::ostringstream m;
      m << " at (" << X(k, 0) << ", " << X(k, 1)
        << ") is within two lattice spacings of a wall (its B-spline stencil leaves the lattice)";
      throw MarkerError("interpolation: marker ", k, m.str());
    }
    U(k, 0) = U_mean.x() + py;
    U(k, 1) = U_mean.y() - px;
    if (!dU) continue;
    (*dU)(k, 0) = pxy;
    (*dU)(k, 1) = pyy;
    (*dU)(k, 2) = -pxx;
    (*dU)(k, 3) = -pxy;
  }
}

}  // namespace sphib
