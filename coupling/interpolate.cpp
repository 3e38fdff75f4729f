#include "coupling/interpolate.hpp"

#include "coupling/neighbourhood.hpp"
#include "fluid/interpolation.hpp"

#include <sstream>
#include <stdexcept>

namespace sphib {

namespace {
[[noreturn]] void no_particle(int k, const Mat2& X) {
  std::ostringstream m;
  m << "interpolation: marker " << k << " at (" << X(k, 0) << ", " << X(k, 1) << ") has no fluid particle within 2h";
  throw std::runtime_error(m.str());
}
}  // namespace

// Eq. (63) (normalised) or Eq. (60), by fluid/interpolation.hpp
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
