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

// The elliptic droplet of Afanasiev, Makarchuk & Popov (2011), Section 6.3 (Ovsyannikov 1967): an
// inviscid drop x^2/a^2 + a^2 y^2 <= 1 with u = (a'/a) x, v = -(a'/a) y (Eqs. 40-41), its semi-axis
// a(t) along x from Eq. (42), a' = c, c' = 2 c^2 / (a^5 + a), with a(0) = c(0) = 1 (Eq. 43), by the
// classical fourth-order Runge-Kutta method. advance_to takes equal steps of at most dt_max.
struct DropletAxis {
  double t = 0.0, a = 1.0, c = 1.0;
  void advance_to(double t_end, double dt_max = 1e-4) {
    if (!(t_end > t)) return;
    const int n = static_cast<int>(std::ceil((t_end - t) / dt_max));
    const double h = (t_end - t) / n;
    auto rate = [](double a_, double c_, double& da, double& dc) {
      da = c_;                                  // Eq. (42)
      dc = 2.0 * c_ * c_ / (std::pow(a_, 5) + a_);
    };
    for (int k = 0; k < n; ++k) {
      double a1, c1, a2, c2, a3, c3, a4, c4;
      rate(a, c, a1, c1);
      rate(a + 0.5 * h * a1, c + 0.5 * h * c1, a2, c2);
      rate(a + 0.5 * h * a2, c + 0.5 * h * c2, a3, c3);
      rate(a + h * a3, c + h * c3, a4, c4);
      a += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
      c += h / 6.0 * (c1 + 2.0 * c2 + 2.0 * c3 + c4);
    }
    t = t_end;
  }
};

}  // namespace sphib::exact
