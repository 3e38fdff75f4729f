#pragma once
// Exact solutions of the fluid benchmarks (series, summed until the terms fall below round-off).
#include <cmath>

namespace sphib::exact {

// Start-up planar Poiseuille flow, dimensionless (u / u_max, y / H, t u_max / H), Eq. (44) of
// Noutcheuwa & Owens. The sum starts at n = 0 (the paper prints n = 1): only then is u(y, 0) = 0,
// since 4 y (1 - y) = 32/pi^3 sum_{n>=0} sin((2n+1) pi y) / (2n+1)^3.
inline double poiseuille_u(double y, double t, double Re) {
  double s = 0.0;
  for (int n = 0; n < 100000; ++n) {
    const double k = 2.0 * n + 1.0;
    const double decay = std::exp(-k * k * M_PI * M_PI * t / Re);
    const double term = std::sin(k * M_PI * y) / (k * k * k) * decay;
    s += term;
    if (decay / (k * k * k) < 1e-17) break;
  }
  return -4.0 * y * (y - 1.0) - 32.0 / (M_PI * M_PI * M_PI) * s;
}

// Couette flow started from rest by the wall y = l moving at U (wall y = 0 at rest), kinematic
// viscosity nu: Eq. (23) of Vukcevic, Werner & Degiuli (after Morris et al. 1997).
inline double couette_u(double y, double t, double nu, double U, double l) {
  double s = 0.0;
  for (int n = 1; n < 200000; ++n) {
    const double decay = std::exp(-nu * n * n * M_PI * M_PI * t / (l * l));
    s += 2.0 * U / (n * M_PI) * ((n % 2) ? -1.0 : 1.0) * std::sin(n * M_PI * y / l) * decay;
    if (decay / n < 1e-17) break;
  }
  return U * y / l + s;
}

}  // namespace sphib::exact
