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

void interpolate_curl(const CellGrid& grid, const CubicSplineKernel& W, const Vec& psi,
                      const Eigen::Vector2d& U_mean, const Mat2& X, Mat2& U) {
  const double radius = W.support();
  Neighbourhood nb;
  for (int k = 0; k < X.rows(); ++k) {
    // sums over the particles j near X_k, two at a time: W_j, psi_j W_j, grad W_j, psi_j grad W_j
    // (uniform V cancels)
    Lanes2 s{}, sp{}, gx{}, gy{}, gpx{}, gpy{};
    nb.gather(grid, X(k, 0), X(k, 1), radius);
    for (int i = 0; i < nb.pairs; ++i) {
      Lanes2 w, F;
      W.W_F2(nb.r2(i), w, F);  // W(X - x_j), (1/r) dW/dr
      const Lanes2 p{psi[nb.j0(i)], psi[nb.j1(i)]}, dx = nb.dx(i), dy = nb.dy(i);
      s += w;
      sp += p * w;
      const Lanes2 wx = F * dx, wy = F * dy;  // grad_X W(X - x_j) = F (X - x_j)
      gx += wx;
      gy += wy;
      gpx += p * wx;
      gpy += p * wy;
    }
    const double S = s[0] + s[1];
    if (!(S > 0)) no_particle(k, X);
    const double ph = (sp[0] + sp[1]) / S;  // psi_h(X)
    // grad psi_h = sum_j (psi_j - psi_h) grad W_j / sum_j W_j
    const double dpx = (gpx[0] + gpx[1] - ph * (gx[0] + gx[1])) / S;
    const double dpy = (gpy[0] + gpy[1] - ph * (gy[0] + gy[1])) / S;
    U(k, 0) = U_mean.x() + dpy;  // u = d psi/dy
    U(k, 1) = U_mean.y() - dpx;  // v = -d psi/dx
  }
}

}  // namespace sphib
