#include "coupling/interpolate.hpp"

#include "coupling/neighbourhood.hpp"
#include "fluid/common/interpolation.hpp"
#include "kernels/curl_sums.hpp"

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

// The kernel sums at each marker by kernels/curl_sums.hpp; psi_h and its derivatives from them here.
void interpolate_curl(const CellGrid& grid, const CubicSplineKernel& W, const Vec& psi, const Eigen::Vector2d& U_mean,
                      const Mat2& X, Mat2& U, Jacobians* dU) {
  const double radius = W.support();
  Neighbourhood nb;
  if (dU) dU->resize(X.rows(), 4);
  for (int k = 0; k < X.rows(); ++k) {
    nb.gather(grid, X(k, 0), X(k, 1), radius);
    const CurlSums c = curl_sums(nb.points(), W.scale(), psi.data(), dU != nullptr);
    const double S = c.s;
    if (!(S > 0)) no_particle(k, X);
    const double ph = c.sp / S;  // psi_h(X)
    // grad psi_h = sum_j (psi_j - psi_h) grad W_j / sum_j W_j
    const double G0x = c.gx, G0y = c.gy;
    const double dpx = (c.gpx - ph * G0x) / S, dpy = (c.gpy - ph * G0y) / S;
    U(k, 0) = U_mean.x() + dpy;  // u = d psi/dy
    U(k, 1) = U_mean.y() - dpx;  // v = -d psi/dx
    if (!dU) continue;
    // d2 psi_h/dadb = (H1_ab - psi_h H0_ab - dpsi_b G0_a - dpsi_a G0_b) / S, H0 = sum_j Hess W_j, H1 = sum_j psi_j Hess W_j
    const double pxx = (c.phxx - ph * c.hxx - 2.0 * dpx * G0x) / S;
    const double pxy = (c.phxy - ph * c.hxy - dpy * G0x - dpx * G0y) / S;
    const double pyy = (c.phyy - ph * c.hyy - 2.0 * dpy * G0y) / S;
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
    double w0 = 0;  // sum_c B_x: the same in every row
    for (int c = 0; c < box.ncol; ++c) w0 += bx[c];
    double px = 0, py = 0, pxx = 0, pxy = 0, pyy = 0, sw = 0;
    for (int rr = 0; rr < box.nrow; ++rr) {
      double by, gy, hy;
      bspline3(box.ry[rr] / dy, by, gy, hy);
      gy /= dy;
      hy /= dy * dy;
      double s0 = 0, s1 = 0, s2 = 0;
      const double* prow = psi.data() + box.base[rr];
      for (int c = 0; c < box.ncol; ++c) {
        const double p = prow[box.col[c]];
        s0 += p * bx[c];
        s1 += p * gx[c];
        s2 += p * hx[c];
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
