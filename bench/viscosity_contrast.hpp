#pragma once
// The exact and manufactured problems of the variable-viscosity step (fluid/eulerian/variable_viscosity.hpp),
// as bench/viscosity_contrast prints them and tests/test_viscosity_contrast.cpp holds them:
//  - two layers of viscosity lambda mu and mu in a Couette channel, the exact piecewise-linear
//    profile, the discrete steady state found in one step;
//  - a manufactured divergence-free field with a smooth m(x, y) on the doubly periodic unit box, the
//    exact div(m (grad u + grad u^T)), the operator's error and the step's error in time.
#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "coupling/viscosity_contrast.hpp"
#include "fluid/eulerian/eulerian.hpp"
#include "membrane/shapes.hpp"

namespace sphib::bench::viscosity {

constexpr double kPi = 3.14159265358979323846;

// Two layers in the channel [0, 1] x [0, 1], periodic in x, walls at y = 0 (at rest) and y = 1
// (velocity U = 1), mu = 1: viscosity lambda below y = yi, 1 above. The shear stress tau is uniform:
//   u = tau y / lambda (y < yi),  u = tau yi / lambda + tau (y - yi) (y > yi),  tau = 1 / (yi / lambda + 1 - yi).
inline double two_layer_u(double y, double yi, double lambda) {
  const double tau = 1.0 / (yi / lambda + 1.0 - yi);
  return y < yi ? tau * y / lambda : tau * yi / lambda + tau * (y - yi);
}

// max |u_s - u| over the particles (both components), u_s the scheme's steady state on n x n
// particles with m = 1 + (lambda - 1) I, I the lower layer's cell fractions. The steady state in one
// step: Crank-Nicolson from u^0 = 0 with a = nu dt / 2 -> oo gives u^1 = 2 u_s - u^0 + O(1/a) (the
// amplification (1 - a z)/(1 + a z) -> -1; here a = 1e10); the cross term vanishes (grad m is along
// y, u along x), and so does the pressure.
inline double two_layer_error(int n, double lambda, double yi, double h_over_dx = 1.2) {
  FluidParams p;
  p.domain = {0.0, 1.0, 0.0, 1.0, true, false};
  p.domain.wall_velocity[Top] = {1.0, 0.0};
  p.nx = n, p.ny = n, p.h_over_dx = h_over_dx;
  p.convection = false;
  p.dt = 2e10;
  EulerianFluid f(p);
  const Lattice& L = f.lattice();
  std::vector<int> at(f.size());
  std::vector<double> m(f.size());
  for (int i = 0; i < f.size(); ++i) {
    const double lo = L.x(i, 1) - 0.5 * L.dy;
    at[i] = i;
    m[i] = 1.0 + (lambda - 1.0) * std::clamp((yi - lo) / L.dy, 0.0, 1.0);
  }
  f.set_viscosity(at.data(), m.data(), f.size());
  f.step(Mat2::Zero(f.size(), 2));
  double e = 0;
  for (int i = 0; i < f.size(); ++i) {
    e = std::max(e, std::abs(0.5 * f.u()(i, 0) - two_layer_u(L.x(i, 1), yi, lambda)));
    e = std::max(e, std::abs(0.5 * f.u()(i, 1)));
  }
  return e;
}

// The manufactured field: u = (psi_y, -psi_x), psi = sin(kx) sin(2ky) / k, k = 2 pi, and
// m = m0 + m1 sin(kx) cos(ky); its exact viscous term (mu = 1)
//   div(m (grad u + grad u^T)) = m lap u + (grad u + grad u^T) grad m.
// The variable part's two forms are tested apart: m >= 1 everywhere (the central-force form) and
// m < 1 everywhere (the Morris form and the explicit cross term).
struct Manufactured {
  static constexpr double k = 2 * kPi;
  double m0 = 1.6, m1 = 0.5;
  double m(double x, double y) const { return m0 + m1 * std::sin(k * x) * std::cos(k * y); }
  static Eigen::Vector2d u(double x, double y) {
    return {2 * std::sin(k * x) * std::cos(2 * k * y), -std::cos(k * x) * std::sin(2 * k * y)};
  }
  static Eigen::Vector2d lap_u(double x, double y) {
    return {-10 * k * k * std::sin(k * x) * std::cos(2 * k * y), 5 * k * k * std::cos(k * x) * std::sin(2 * k * y)};
  }
  Eigen::Vector2d viscous(double x, double y) const {
    const double sx = std::sin(k * x), cx = std::cos(k * x), s2 = std::sin(2 * k * y), c2 = std::cos(2 * k * y);
    const double ux = 2 * k * cx * c2, uy = -4 * k * sx * s2, vx = k * sx * s2, vy = -2 * k * cx * c2;
    const double mx = m1 * k * cx * std::cos(k * y), my = -m1 * k * sx * std::sin(k * y);
    const double sxx = 2 * ux, sxy = uy + vx, syy = 2 * vy;
    const Eigen::Vector2d lap = lap_u(x, y);
    return {m(x, y) * lap[0] + sxx * mx + sxy * my, m(x, y) * lap[1] + sxy * mx + syy * my};
  }
};
constexpr Manufactured kAbove{1.6, 0.5}, kBelow{0.6, 0.3};  // m in [1.1, 2.1] and [0.3, 0.9]

inline FluidParams periodic_box(int n, double h_over_dx = 1.2) {
  FluidParams p;
  p.domain = {0.0, 1.0, 0.0, 1.0, true, true};
  p.nx = n, p.ny = n, p.h_over_dx = h_over_dx;
  p.convection = false;
  return p;
}

inline void set_manufactured_m(EulerianFluid& f, const Manufactured& mf) {
  std::vector<int> at(f.size());
  std::vector<double> m(f.size());
  for (int i = 0; i < f.size(); ++i) at[i] = i, m[i] = mf.m(f.x()(i, 0), f.x()(i, 1));
  f.set_viscosity(at.data(), m.data(), f.size());
}

// The discrete div(m (grad u + grad u^T)) of the manufactured u (L u + VariableViscosity's
// added_viscous_term) against its exact value, and the
// constant-viscosity Laplacian of u against lap u: max errors over max |exact viscous term|.
struct OperatorError {
  double variable = 0, constant = 0, scale = 0;
};
inline OperatorError operator_error(const Manufactured& mf, int n, double h_over_dx) {
  EulerianFluid f(periodic_box(n, h_over_dx));
  set_manufactured_m(f, mf);
  Mat2 u(f.size(), 2), V;
  for (int i = 0; i < f.size(); ++i) u.row(i) = Manufactured::u(f.x()(i, 0), f.x()(i, 1)).transpose();
  f.variable_viscosity()->added_viscous_term(u, Mat2(0, 2), V);  // what m adds to L u
  const Mat2 L1 = f.operators().lap_u.A * u;                        // L u (no images: doubly periodic)
  V += L1;
  OperatorError e;
  for (int i = 0; i < f.size(); ++i) {
    const double x = f.x()(i, 0), y = f.x()(i, 1);
    const Eigen::Vector2d ex = mf.viscous(x, y), lap = Manufactured::lap_u(x, y);
    e.variable = std::max(e.variable, (V.row(i) - ex.transpose()).cwiseAbs().maxCoeff());
    e.constant = std::max(e.constant, (L1.row(i) - lap.transpose()).cwiseAbs().maxCoeff());
    e.scale = std::max(e.scale, ex.cwiseAbs().maxCoeff());
  }
  e.variable /= e.scale;
  e.constant /= e.scale;
  return e;
}

// Stokes flow u = U(x) cos t on a manufactured field, mu = 0.01 (forcing rho U' - mu div(m sigma(U))
// cos t, taken at t_n + dt/2), on n x n particles to t = t_end: u at the end.
inline Mat2 unsteady_run(const Manufactured& mf, int n, double dt, double t_end) {
  FluidParams p = periodic_box(n);
  p.dt = dt;
  p.mu = 0.01;
  EulerianFluid f(p);
  set_manufactured_m(f, mf);
  const int N = f.size();
  Mat2 U(N, 2), V(N, 2), F(N, 2);
  for (int i = 0; i < N; ++i) {
    U.row(i) = Manufactured::u(f.x()(i, 0), f.x()(i, 1)).transpose();
    V.row(i) = mf.viscous(f.x()(i, 0), f.x()(i, 1)).transpose();
  }
  f.set_velocity(U);
  const long steps = std::lround(t_end / dt);
  for (long s = 0; s < steps; ++s) {
    const double t = (s + 0.5) * dt;
    F = -std::sin(t) * U - (p.mu * std::cos(t)) * V;  // rho = 1
    f.step(F);
  }
  return f.u();
}

// A circular interface, exact: Stokes flow in the doubly periodic box [-1, 1]^2, viscosity lambda
// (mu = 1) inside r < R, 1 outside, stream function psi = f(r) sin 2 theta (u = (psi_y, -psi_x):
// u_r = 2 f / r cos 2 theta, u_theta = -f' sin 2 theta), f_in = a1 r^2 + a2 r^4 + a3 r^6 inside,
// f_out = s^3 (b0 + b1 s + b2 s^2), s = R2 - r, outside (zero beyond R2 < 1), with
//   f, f' continuous at R (the velocity), f'(R) = f(R)/R (the normal viscous stress 4 mu (f'/r -
//   f/r^2) cos 2 theta zero on both sides: no pressure jump), lambda (f_in'' + c) = f_out'' + c,
//   c = -f'/R + 4 f/R^2 (the shear stress -mu (f'' - f'/r + 4 f/r^2) sin 2 theta continuous).
// The body force that makes it steady with p = 0: F = -mu lap u in each region, lap u the same
// form with psi -> lap psi = h(r) sin 2 theta, h = f'' + f'/r - 4 f/r^2. Continuous traction and
// velocity, no interface force: the solution of the two-fluid problem, which the viscosity contrast
// (cell fractions of the circle, m = 1 + (lambda - 1) I) approaches at first order in h.
struct CircleInterface {
  double R = 0.4, R2 = 0.9, A = 0.05, lambda = 5.0;
  double a1 = 0, a2 = 0, a3 = 0, b[3] = {0, 0, 0};
  explicit CircleInterface(double lambda_) : lambda(lambda_) {
    a3 = 0.5 * A / std::pow(R, 6);  // a shear stress at the interface that depends on lambda
    a2 = (-A - 4 * a3 * std::pow(R, 6)) / (2 * std::pow(R, 4));
    a1 = (A - a3 * std::pow(R, 6) - a2 * std::pow(R, 4)) / (R * R);
    const double fin2 = 2 * a1 + 12 * a2 * R * R + 30 * a3 * std::pow(R, 4), c = 3 * A / (R * R);
    const double fout2 = lambda * (fin2 + c) - c, S = R2 - R;
    Eigen::Matrix3d M;  // g(S) = A, g'(S) = -A/R, g''(S) = fout2 for g = b0 s^3 + b1 s^4 + b2 s^5
    M << std::pow(S, 3), std::pow(S, 4), std::pow(S, 5), 3 * S * S, 4 * std::pow(S, 3), 5 * std::pow(S, 4), 6 * S,
        12 * S * S, 20 * std::pow(S, 3);
    const Eigen::Vector3d x = M.lu().solve(Eigen::Vector3d(A, -A / R, fout2));
    b[0] = x[0], b[1] = x[1], b[2] = x[2];
  }
  // f and its first three derivatives at r
  void f(double r, double d[4]) const {
    if (r < R) {
      d[0] = a1 * r * r + a2 * std::pow(r, 4) + a3 * std::pow(r, 6);
      d[1] = 2 * a1 * r + 4 * a2 * std::pow(r, 3) + 6 * a3 * std::pow(r, 5);
      d[2] = 2 * a1 + 12 * a2 * r * r + 30 * a3 * std::pow(r, 4);
      d[3] = 24 * a2 * r + 120 * a3 * std::pow(r, 3);
    } else if (r < R2) {
      const double s = R2 - r;
      d[0] = b[0] * std::pow(s, 3) + b[1] * std::pow(s, 4) + b[2] * std::pow(s, 5);
      d[1] = -(3 * b[0] * s * s + 4 * b[1] * std::pow(s, 3) + 5 * b[2] * std::pow(s, 4));
      d[2] = 6 * b[0] * s + 12 * b[1] * s * s + 20 * b[2] * std::pow(s, 3);
      d[3] = -(6 * b[0] + 24 * b[1] * s + 60 * b[2] * s * s);
    } else {
      d[0] = d[1] = d[2] = d[3] = 0;
    }
  }
  // the field (v_r, v_theta) = scale (2 q cos 2 theta, -dq sin 2 theta) in Cartesian components
  static Eigen::Vector2d cartesian(double x, double y, double q, double dq, double scale = 1.0) {
    const double r = std::hypot(x, y), c = r > 0 ? x / r : 1, s = r > 0 ? y / r : 0;
    const double c2 = c * c - s * s, s2 = 2 * s * c;
    const double vr = 2 * q * c2 * scale, vt = -dq * s2 * scale;
    return {vr * c - vt * s, vr * s + vt * c};
  }
  Eigen::Vector2d u(double x, double y) const {
    const double r = std::hypot(x, y);
    double d[4];
    f(r, d);
    return cartesian(x, y, r > 0 ? d[0] / r : 0.0, d[1]);
  }
  Eigen::Vector2d force(double x, double y) const {  // -mu lap u
    const double r = std::hypot(x, y);
    if (r == 0) return {0, 0};
    double d[4];
    f(r, d);
    const double h = d[2] + d[1] / r - 4 * d[0] / (r * r);
    const double dh = d[3] + d[2] / r - d[1] / (r * r) - 4 * d[1] / (r * r) + 8 * d[0] / (r * r * r);
    return cartesian(x, y, h / r, dh, -(r < R ? lambda : 1.0));
  }
};

// The circle's steady flow on n x n particles: max |u - u_exact| / max |u_exact|, the particles'
// m from the cell fractions of the circle (polygon of 8 n vertices). Time-stepped from the exact
// flow (dt = dx^2 / 4: the explicit cross term of m < 1 stays stable, and so does the gradient
// form's for m > 1 up to lambda = 9) until a step changes u by less than 1e-9 max |u| (the slowest
// mode, nu (pi/2)^2 ~ 2.5, then carries 1e-9 / (2.5 dt) ~ 1e-4 of max |u| at n = 64: far below the
// errors measured); NaN when it blows up.
inline double circle_error(int n, double lambda, bool central = true, long* steps_out = nullptr) {
  const CircleInterface c(lambda);
  FluidParams p;
  p.domain = {-1.0, 1.0, -1.0, 1.0, true, true};
  p.nx = p.ny = n;
  p.convection = false;
  p.dt = 0.25 * std::pow(2.0 / n, 2);
  EulerianFluid f(p);
  VariableViscosityParams vp;
  vp.central = central;
  f.set_variable_viscosity_params(vp);
  CellFractions I;
  CellFractionWork w;
  cell_fractions(f.lattice(), circle(8 * n, 0.0, 0.0, c.R), I, w);
  std::vector<double> m(I.I.size());
  for (size_t q = 0; q < m.size(); ++q) m[q] = 1.0 + (lambda - 1.0) * I.I[q];
  f.set_viscosity(I.index.data(), m.data(), static_cast<int>(m.size()));
  const int N = f.size();
  Mat2 U(N, 2), F(N, 2), prev;
  for (int i = 0; i < N; ++i) {
    U.row(i) = c.u(f.x()(i, 0), f.x()(i, 1)).transpose();
    F.row(i) = c.force(f.x()(i, 0), f.x()(i, 1)).transpose();
  }
  const double umax = U.cwiseAbs().maxCoeff();
  f.set_velocity(U);
  long s = 0;
  for (; s < 100000; ++s) {
    prev = f.u();
    f.step(F);
    const double du = (f.u() - prev).cwiseAbs().maxCoeff();
    if (!(du < umax)) return std::nan("");  // (unstable)
    if (du < 1e-9 * umax) break;
  }
  if (steps_out) *steps_out = s + 1;  // (100000: not converged)
  return (f.u() - U).cwiseAbs().maxCoeff() / umax;
}

// The explicit cross term of m < 1 (fluid/eulerian/variable_viscosity.hpp): a circle of radius 0.3 with
// viscosity lambda < 1 in the doubly periodic unit box, n = 32, mu = 1, dt such that
// nu (1 - lambda) dt / dx^2 = number, from the manufactured flow plus 1e-3 noise, no forcing: the
// step at which max |u| passes 1e3 (a blow-up), or -1 when 1000 steps stay below it.
inline long explicit_cross_blowup(double lambda, double number) {
  FluidParams p = periodic_box(32);
  p.dt = number / (1.0 - lambda) / (32.0 * 32.0);
  EulerianFluid f(p);
  CellFractions I;
  CellFractionWork w;
  cell_fractions(f.lattice(), circle(256, 0.5, 0.5, 0.3), I, w);
  std::vector<double> m(I.I.size());
  for (size_t q = 0; q < m.size(); ++q) m[q] = 1.0 + (lambda - 1.0) * I.I[q];
  f.set_viscosity(I.index.data(), m.data(), static_cast<int>(m.size()));
  const int N = f.size();
  Mat2 U(N, 2);
  for (int i = 0; i < N; ++i) U.row(i) = Manufactured::u(f.x()(i, 0), f.x()(i, 1)).transpose();
  std::srand(1);
  U += 1e-3 * Mat2::Random(N, 2);
  f.set_velocity(U);
  const Mat2 F = Mat2::Zero(N, 2);
  for (long s = 0; s < 1000; ++s) {
    f.step(F);
    if (!(f.u().cwiseAbs().maxCoeff() < 1e3)) return s + 1;
  }
  return -1;
}

}  // namespace sphib::bench::viscosity
