#pragma once
// The relaxing membrane of cases/membrane_relaxation.cpp (and its unit test): a membrane at rest on
// its reference circle of radius R released from r(theta) = R (1 + eps cos(n theta)), markers uniform
// in the arclength of that shape; the mode's amplitude a_n and its decay rate.
#include <cmath>
#include <complex>
#include <string>
#include <utility>
#include <vector>

#include "io/scene.hpp"
#include "membrane/polygon.hpp"
#include "membrane/shapes.hpp"

namespace sphib {

struct RelaxationParams {
  int mode = 3, nx = 64;
  double L = 4.0, R = 0.5, mu = 1.0, rho = 0.01, eps = 0.02, dt = 5e-4;
  std::string law = "skalak";
  double Es = 10.0, Eb = 0.1;
  double markers_per_dx = 2.0, h_star_over_h = 1.4;
  bool semi_implicit = true;
  MarkerInterpolation interpolation = MarkerInterpolation::Auto;
  /// The Stokes rate of the bending mode, n ((n^2 - 1) Eb / R^2 + Tbar) / (4 mu R), Tbar = 0 at rest
  /// (docs/membrane_validation.md, "Linear theory").
  double stokes_rate() const { return mode * (mode * mode - 1) * Eb / (R * R) / (4 * mu * R); }
};

/// The fluid at rest in [-L/2, L/2]^2 (periodic in x, walls y = +-L/2) and the released membrane; runs
/// to 3.5 / stokes_rate().
inline Scene relaxation_scene(const RelaxationParams& p) {
  Scene s;
  FluidParams& f = s.sim.fluid;
  f.domain = {-p.L / 2, p.L / 2, -p.L / 2, p.L / 2, /*periodic_x=*/true, /*periodic_y=*/false};
  f.nx = p.nx, f.ny = p.nx, f.rho = p.rho, f.mu = p.mu, f.dt = p.dt;
  s.sim.interpolation = p.interpolation;
  const double dx = p.L / p.nx;
  const int nb = static_cast<int>(std::lround(p.markers_per_dx * 2 * M_PI * p.R / dx));
  const int n = p.mode;
  const double R = p.R, eps = p.eps;
  const Mat2 X = from_polar([=](double th) { return R * (1 + eps * std::cos(n * th)); }, nb);
  Material mat;
  mat.law = p.law, mat.Es = p.Es, mat.Eb = p.Eb;
  MembraneSetup m{make_membrane(X, circle_reference(R), mat), p.h_star_over_h * f.h_over_dx * dx};
  m.semi_implicit = p.semi_implicit;
  s.sim.membranes.push_back(m);
  s.t_end = 3.5 / p.stokes_rate();
  s.diagnostics_every = std::max(1L, std::lround(s.t_end / p.dt / 400));
  return s;
}

/// int_Omega (z - c)^n dA over the polygon of the markers, by Green's theorem, int f dA =
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

/// The amplitude of mode n: a_n = |int (z - c)^n dA| / (pi R^{n+2}), z = x + i y about the area centroid
/// c, R = sqrt(A/pi); = eps for r = R (1 + eps cos(n (theta - theta0))) to first order (int over the
/// disc of r^{n+1} e^{i n theta} dr dtheta = pi eps R^{n+2}). n <= 6.
inline double mode_amplitude(const Mat2& X, int n) {
  const ShapeMoments e = ellipse_fit(X);
  const double R = std::sqrt(e.area / M_PI);
  return std::abs(area_moment(X, e.centroid, n)) / (M_PI * std::pow(R, n + 2));
}

/// The decay rate of a series (t, a): least squares of log a on t while a / a(0) lies in
/// [exp(-3), exp(-0.5)] (past the start, before the floor). NaN with fewer than 3 such points.
inline double decay_rate(const std::vector<std::pair<double, double>>& hist) {
  if (hist.empty()) return NAN;
  const double a0 = hist.front().second;
  double st = 0, sa = 0, stt = 0, sta = 0, c = 0;
  for (const auto& [t, a] : hist)
    if (a <= a0 * std::exp(-0.5) && a >= a0 * std::exp(-3.0)) {
      st += t, sa += std::log(a), stt += t * t, sta += t * std::log(a), ++c;
    }
  return c >= 3 ? -(c * sta - st * sa) / (c * stt - st * st) : NAN;
}

}  // namespace sphib
