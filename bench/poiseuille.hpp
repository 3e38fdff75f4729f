#pragma once
// The start-up planar Poiseuille problem of Noutcheuwa & Owens (2012), Section 5.1, as the
// benchmarks poiseuille_sweep and lpsph_comparison run it, with the paper's CPU times.
//
// Dimensionless: domain [0,1]^2, periodic in x, no-slip walls at y = 0, 1; Re = 0.0125, i.e.
// rho = 1, mu = 1/Re, body force F = (8/Re, 0) so that u_max = 1; dt = 1.25e-6, t in [0, 0.0125]
// (10 000 steps), fluid at rest at t = 0. The flow is unidirectional (u = u(y, t), v = 0), so
// (u.grad)u = 0 exactly: Stokes flow unless convection is asked for.
#include <cmath>
#include <vector>

#include "fluid/common/exact.hpp"
#include "fluid/core/solver.hpp"

namespace sphib::bench::poiseuille {

constexpr double kRe = 0.0125;
constexpr double kDt = 1.25e-6;
constexpr long kPaperSteps = 10000;  // t in [0, 1.25e-2]

// Tables 1 (EPSPH) and 2 (LPSPH) of the paper: "CPU times (divided by 10^5) in seconds as a
// function of h and dx for calculations over the dimensionless time interval [0, 1.25e-2].
// dt = 1.25e-6" (2.66 GHz, one core, 4 GB RAM), for dx = 1/Nx, Nx in kPaperNx; Table 2 has no
// h = 5 dx, Nx = 64 (-1).
const std::vector<int> kPaperNx = {16, 24, 32, 48, 64};
struct PaperTimes {
  double hdx, epsph[5], lpsph[5];
};
constexpr PaperTimes kPaperTimes[] = {
    {1.2, {0.035022, 0.067669, 0.113006, 0.239269, 0.415746}, {0.099005, 0.187561, 0.319504, 0.714037, 1.323536}},
    {1.525, {0.046215, 0.089396, 0.147856, 0.311473, 0.540184}, {0.127923, 0.252388, 0.424687, 0.948320, 1.760337}},
    {2.2, {0.090997, 0.178537, 0.294559, 0.617233, 1.060960}, {0.274136, 0.538272, 0.908807, 2.010848, 3.731087}},
    {2.75, {0.147899, 0.287261, 0.472361, 0.982132, 1.677688}, {0.475463, 0.930296, 1.573539, 3.561883, 6.672354}},
    {3.0, {0.203369, 0.391393, 0.640025, 1.306324, 2.274285}, {0.571796, 1.116098, 1.891615, 4.573303, 10.035217}},
    {4.0, {0.333689, 0.645198, 1.042638, 2.120318, 3.552049}, {1.197621, 2.303141, 3.975691, 9.391495, 18.396347}},
    {5.0, {0.669753, 1.283128, 2.119406, 4.022646, 7.023340}, {2.277747, 5.864076, 10.2052380, 21.126515, -1.0}}};
const std::vector<double> kPaperH = {1.2, 1.525, 2.2, 2.75, 3.0, 4.0, 5.0};

// The paper's CPU seconds for the 10 000 steps of EPSPH (Table 1) or LPSPH (Table 2), NaN when
// (nx, h/dx) is not tabulated.
inline double paper_seconds(bool lagrangian, int nx, double hdx) {
  for (const PaperTimes& row : kPaperTimes)
    for (size_t c = 0; c < kPaperNx.size(); ++c)
      if (std::abs(row.hdx - hdx) < 1e-9 && kPaperNx[c] == nx) {
        const double t = lagrangian ? row.lpsph[c] : row.epsph[c];
        return t > 0 ? t * 1e5 : NAN;
      }
  return NAN;
}

// The fluid's parameters for Nx = Ny = nx and h = hdx dx.
inline FluidParams params(const std::string& method, int nx, double hdx, bool convection = false) {
  FluidParams p;
  p.method = enum_value(method, kFluidMethods);
  p.domain = Domain{0.0, 1.0, 0.0, 1.0, true, false};
  p.nx = p.ny = nx;
  p.h_over_dx = hdx;
  p.rho = 1.0;
  p.mu = 1.0 / kRe;
  p.dt = kDt;
  p.convection = convection;
  return p;
}

// The body force at every particle: dp/dx = -8 mu u_max / H^2, dimensionless 8/Re.
inline Mat2 body_force(int n) {
  Mat2 F = Mat2::Zero(n, 2);
  F.col(0).setConstant(8.0 / kRe);
  return F;
}

// Eq. (69) at the particles, against the exact series of Eq. (44) (exact v = 0): the rms of
// |u_ex - u| and of each component, and the largest |u_ex - u|.
struct Error {
  double rms = NAN, rms_u = NAN, rms_v = NAN, max = NAN;
};
inline Error error(const FluidSolver& f) {
  double su = 0, sv = 0, mx = 0;
  const int N = f.size();
  for (int i = 0; i < N; ++i) {
    const double du = exact::poiseuille_u(f.x()(i, 1), f.time(), kRe) - f.u()(i, 0), dv = -f.u()(i, 1);
    su += du * du;
    sv += dv * dv;
    mx = std::max(mx, std::sqrt(du * du + dv * dv));
  }
  return {std::sqrt((su + sv) / N), std::sqrt(su / N), std::sqrt(sv / N), mx};
}

}  // namespace sphib::bench::poiseuille
