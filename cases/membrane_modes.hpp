#pragma once
// The amplitude of a membrane's shape mode n (cases/membrane_relaxation.cpp and its unit test):
// a_n = |int (z - c)^n dA| / (pi R^{n+2}), z = x + i y about the area centroid c, R = sqrt(A/pi): for
// r(theta) = R (1 + eps cos(n (theta - theta0))) it is eps to first order (int over the disc of
// r^{n+1} e^{i n theta} dr dtheta = pi eps R^{n+2}).
#include <cmath>
#include <complex>

#include "membrane/polygon.hpp"

namespace sphib {

/// int_Omega (z - c)^n dA over the polygon of the markers X, by Green's theorem, int f dA =
/// (1/2i) closed-int conj(z) f(z) dz for holomorphic f, exact on each straight edge (Gauss-Legendre
/// 4 points: the integrand is a polynomial of degree n + 1 <= 7 in the edge's parameter).
inline std::complex<double> area_moment(const Mat2& X, const Eigen::Vector2d& c, int n) {
  using cplx = std::complex<double>;
  static const double gx[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  static const double gw[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  const int nb = static_cast<int>(X.rows());
  cplx sum = 0.0;
  for (int k = 0; k < nb; ++k) {
    const cplx a(X(k, 0) - c.x(), X(k, 1) - c.y()), b(X((k + 1) % nb, 0) - c.x(), X((k + 1) % nb, 1) - c.y());
    for (int q = 0; q < 4; ++q) {
      const cplx z = a + 0.5 * (1.0 + gx[q]) * (b - a);
      sum += 0.5 * gw[q] * std::conj(z) * std::pow(z, n) * (b - a);
    }
  }
  return sum / cplx(0.0, 2.0);
}

/// a_n of the markers X (n <= 6).
inline double mode_amplitude(const Mat2& X, int n) {
  const ShapeMoments e = ellipse_fit(X);
  const double R = std::sqrt(e.area / M_PI);
  return std::abs(area_moment(X, e.centroid, n)) / (M_PI * std::pow(R, n + 2));
}

}  // namespace sphib
