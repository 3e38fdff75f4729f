// The conservative pair (issue 12): the exact projection (Poisson operator G^T G = -D G, its
// null modes fixed by fluid/algebra/gauge.hpp) and divergence-free marker velocities (the curl of the
// interpolated stream function). Every tolerance is a measured value (Release build, stated
// beside the test) with a margin; round-off checks say so.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "coupling/interpolate.hpp"
#include "coupling/marker_update.hpp"
#include "coupling/simulation.hpp"
#include "fluid/algebra/gauge.hpp"
#include "fluid/eulerian/eulerian.hpp"
#include "membrane/geometry.hpp"
#include "membrane/force.hpp"
#include "membrane/shapes.hpp"

using namespace sphib;

namespace {

constexpr double kPi = 3.14159265358979323846;

FluidParams params(int n, bool periodic_x, bool periodic_y, Projection pr = Projection::Exact) {
  FluidParams p;
  p.domain.periodic_x = periodic_x;
  p.domain.periodic_y = periodic_y;
  p.nx = p.ny = n;
  p.h_over_dx = 1.2;
  p.rho = 1.0;
  p.mu = 1e-3;
  p.dt = 1e-3;
  p.convection = false;
  p.projection = pr;
  return p;
}

Mat2 random_field(int N, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Mat2 u(N, 2);
  for (int i = 0; i < N; ++i) { u(i, 0) = U(gen); u(i, 1) = U(gen); }
  return u;
}

// (-1)^{sx i_x + sy i_y} on the lattice
Vec mode(const Lattice& L, int sx, int sy) {
  Vec z(L.size());
  for (int iy = 0; iy < L.ny; ++iy)
    for (int ix = 0; ix < L.nx; ++ix) z[ix + L.nx * iy] = ((sx * ix + sy * iy) & 1) ? -1.0 : 1.0;
  return z;
}

struct DomainCase {
  bool px, py;
  const char* name;
};
const DomainCase kDomains[] = {{true, false, "channel"}, {false, false, "closed box"}, {true, true, "doubly periodic"}};

CellGrid lattice_grid(const Lattice& L) {
  const Domain& d = L.domain;
  CellGrid g(Eigen::Vector2d(d.x0, d.y0), Eigen::Vector2d(d.x1, d.y1), d.periodic_x, d.periodic_y,
             std::min(L.dx, L.dy));
  g.use_lattice(L);
  return g;
}

}  // namespace

// The null vectors the gauge names are annihilated by the gradient (even images: phi; odd images:
// a stream function) to round-off, and the alternating modes it leaves out are not: e.g. (-1)^{i_y}
// across a wall with even images. Measured max h |G z|: <= 1.4e-16 for the named modes; >= 0.111
// for the others. Tolerances 1e-12 and 0.05.
TEST(Gauge, NamedModesAreExactlyTheGradientsNullModes) {
  for (const DomainCase& c : kDomains) {
    const EulerianFluid f(params(16, c.px, c.py));
    const Lattice& L = f.lattice();
    const Operators& op = f.operators();
    for (NullSpace ns : {NullSpace::GradientScalar, NullSpace::GradientStream}) {
      const bool even = ns == NullSpace::GradientScalar;
      const SpMat& Gx = even ? op.grad_phix : op.grad_ux.A;
      const SpMat& Gy = even ? op.grad_phiy : op.grad_uy.A;
      const Gauge g(L, ns);
      int named = 0;
      for (int sy = 0; sy < 2; ++sy)
        for (int sx = 0; sx < 2; ++sx) {
          const Vec z = mode(L, sx, sy);
          const double gz = std::max((Gx * z).cwiseAbs().maxCoeff(), (Gy * z).cwiseAbs().maxCoeff()) * f.h();
          Vec zp = z;
          g.project(zp);
          const bool in_gauge = zp.norm() < 1e-12 * z.norm();
          named += in_gauge;
          if (in_gauge) EXPECT_LT(gz, 1e-12) << c.name << " even " << even << " mode " << sx << sy;
          else EXPECT_GT(gz, 0.05) << c.name << " even " << even << " mode " << sx << sy;
        }
      EXPECT_EQ(named, g.dimension()) << c.name;
    }
  }
}

// One step from a random, divergent velocity: after the exact projection D u^{n+1} = 0 (D = -G^T)
// to solver precision on every domain kind and with every Poisson solver, and the Poisson residual
// is at round-off. Measured max |D u^1| / max |D u^0|: 2.7e-16 .. 5.1e-16 (the lattice solvers of
// fft_poisson.hpp on every domain, CHOLMOD with one, two or four pins); residuals <= 7.5e-14
// (CHOLMOD on the closed box). Tolerances 1e-11 and 1e-10 (round-off times the
// condition of G^T G near its null modes). The approximate projection leaves 0.57-0.58 of it
// (test_fluid.cpp).
TEST(ExactProjection, RandomFieldBecomesDivergenceFreeOnEveryDomain) {
  for (const DomainCase& c : kDomains)
    for (SolverKind k : {SolverKind::Auto, SolverKind::CholmodSimplicial}) {
      FluidParams p = params(16, c.px, c.py);
      p.poisson_solver = k;
      EulerianFluid f(p);
      f.set_velocity(random_field(f.size(), 7));
      const double d0 = f.max_abs_divergence();
      f.step(Mat2::Zero(f.size(), 2));
      EXPECT_LT(f.max_abs_divergence(), 1e-11 * d0) << c.name << " solver " << static_cast<int>(k);
      EXPECT_LT(f.poisson_residual(), 1e-10) << c.name;
    }
}

// The FFT solver of the singular G^T G (channel: null vectors 1 and (-1)^{i_x}, two singular
// wavenumber blocks) gives the velocity CHOLMOD with two pins gives. Measured max difference of
// u^1: 1.2e-14 (max |u| ~ 1). Tolerance 1e-12.
TEST(ExactProjection, FftAndCholmodAgreeOnTheChannel) {
  Mat2 u[2];
  for (int s = 0; s < 2; ++s) {
    FluidParams p = params(16, true, false);
    p.poisson_solver = s ? SolverKind::CholmodSimplicial : SolverKind::Fft;
    EulerianFluid f(p);
    f.set_velocity(random_field(f.size(), 3));
    f.step(Mat2::Zero(f.size(), 2));
    u[s] = f.u();
  }
  EXPECT_LT((u[0] - u[1]).cwiseAbs().maxCoeff(), 1e-12);
}

// A checkerboard phi produces no velocity (G of a sum of the four null modes: measured 5.3e-15,
// tolerance 1e-12), and neither phi nor the pressure (Eq. 35) after a step keeps any component along
// them (relative 1e-12: round-off). The pressure's smoothness near a membrane is checked in
// test_membrane_cases.cpp.
TEST(ExactProjection, CheckerboardPhiProducesNoVelocity) {
  EulerianFluid f(params(16, true, true));
  const Lattice& L = f.lattice();
  Vec phi = Vec::Zero(L.size());
  for (int sy = 0; sy < 2; ++sy)
    for (int sx = 0; sx < 2; ++sx) phi += (1.0 + sx + 2 * sy) * mode(L, sx, sy);
  const Vec gx = f.operators().grad_phix * phi, gy = f.operators().grad_phiy * phi;
  EXPECT_LT(std::max(gx.cwiseAbs().maxCoeff(), gy.cwiseAbs().maxCoeff()), 1e-12);
  // and the solved phi carries none of it
  f.set_velocity(random_field(f.size(), 5));
  f.step(Mat2::Zero(f.size(), 2));
  for (int sy = 0; sy < 2; ++sy)
    for (int sx = 0; sx < 2; ++sx) {
      EXPECT_LT(std::fabs(mode(L, sx, sy).dot(f.phi())) / L.size(), 1e-12 * f.phi().cwiseAbs().maxCoeff());
      EXPECT_LT(std::fabs(mode(L, sx, sy).dot(f.p())) / L.size(), 1e-12 * f.p().cwiseAbs().maxCoeff());
    }
}

// The exact projection is orthogonal: u* - u^{n+1} is orthogonal to every divergence-free field,
// i.e. to the curls C psi (C^T (u* - u^{n+1}) = 0), to the alternating velocity modes and, in a
// channel, to the uniform flux. (It is made through the least-squares stream function, whose curl
// plus those modes spans D u = 0: fluid/eulerian/exact_projection.cpp.) Measured max |C^T (u* - u)| / max |C^T u*|:
// channel 2.8e-14, closed box 8.0e-14, doubly periodic 3.2e-14; mode and flux components below
// 1.6e-16 of max |u*|. Tolerances 1e-11.
TEST(ExactProjection, IsOrthogonalToDivergenceFreeFields) {
  for (const DomainCase& c : kDomains) {
    EulerianFluid f(params(24, c.px, c.py));
    Mat2 u0 = random_field(f.size(), 11);
    u0.col(0).array() += 0.7;  // a mean flow
    f.set_velocity(u0);
    f.step(Mat2::Zero(f.size(), 2));
    Mat2 u_star;
    for (const auto& [name, a] : f.state())
      if (name == "u_star") u_star = a;
    const Mat2 w = u_star - f.u();
    const Operators& op = f.operators();
    auto ct = [&](const Mat2& u) -> Vec {  // C^T u = Gy^T u - Gx^T v (odd images)
      return op.grad_uy.A.transpose() * u.col(0) - op.grad_ux.A.transpose() * u.col(1);
    };
    const double ref = ct(u_star).cwiseAbs().maxCoeff();
    EXPECT_LT(ct(w).cwiseAbs().maxCoeff(), 1e-11 * ref) << c.name;
    const Lattice& L = f.lattice();
    const Domain& d = L.domain;
    for (int comp = 0; comp < 2; ++comp)
      for (int sy = 0; sy < 2; ++sy)
        for (int sx = 0; sx < 2; ++sx) {
          const bool in_x = d.periodic_x || sx == (comp == 0);  // normal component alternates across a wall
          const bool in_y = d.periodic_y || sy == (comp == 1);
          if (!in_x || !in_y) continue;
          const Vec z = mode(L, sx, sy);
          EXPECT_LT(std::fabs(z.dot(w.col(comp))) / L.size(), 1e-11 * u_star.cwiseAbs().maxCoeff())
              << c.name << " component " << comp << " mode " << sx << sy;
        }
  }
}

// The markers' stream function psi_m (-lap psi_m = C^T u / m: Morris Laplacian with odd images, m the
// lattice normalisation of G) has a discrete curl that approximates u at second order in h, like
// Eq. (63) at the lattice points: a smooth divergence-free field (a Taylor-Green cell plus a uniform
// flow on a doubly periodic box; a Poiseuille profile plus a cell in a channel), max |(Gy psi_m,
// -Gx psi_m) + U - u| / max |u| over particles farther than 2h from walls. Measured, nx = 32, 64:
//   h = 1.2 dx: periodic 1.94e-2, 4.89e-3; channel 1.90e-2, 4.97e-3   (Eq. 63: 1.33e-2, 3.33e-3)
//   h = 2 dx:   periodic 5.48e-2, 1.40e-2; channel 5.36e-2, 1.37e-2   (Eq. 63: 3.67e-2, 9.33e-3)
// (without the 1/m, h = 1.2 dx saturated at 0.8%). Tolerances 1.2x measured at nx = 64, order > 1.8.
TEST(StreamFunction, MarkersStreamFunctionApproximatesTheVelocity) {
  struct Row { DomainCase c; double h, e64; };
  for (const Row& r : {Row{kDomains[2], 1.2, 4.89e-3}, Row{kDomains[0], 1.2, 4.97e-3}, Row{kDomains[2], 2.0, 1.40e-2},
                       Row{kDomains[0], 2.0, 1.37e-2}}) {
    const DomainCase& c = r.c;
    double e[2];
    for (int k = 0; k < 2; ++k) {
      FluidParams pp = params(32 << k, c.px, c.py);
      pp.h_over_dx = r.h;
      EulerianFluid f(pp);
      const Lattice& L = f.lattice();
      Mat2 u(L.size(), 2);
      for (int i = 0; i < L.size(); ++i) {
        const double x = 2 * kPi * L.x(i, 0), y = 2 * kPi * L.x(i, 1), Y = L.x(i, 1);
        if (c.py) {  // psi = sin x sin y / (2 pi) + 0.3 Y
          u(i, 0) = std::sin(x) * std::cos(y) + 0.3;
          u(i, 1) = -std::cos(x) * std::sin(y);
        } else {  // psi = sin(x) sin^2(pi Y) / (2 pi) + Y^2/2 - Y^3/3: no-slip walls at Y = 0, 1
          const double s = std::sin(kPi * Y);
          u(i, 0) = 0.5 * std::sin(x) * std::sin(y) + Y - Y * Y;
          u(i, 1) = -std::cos(x) * s * s;
        }
      }
      f.set_velocity(u);
      const StreamFunction sf = f.stream_function();
      const Vec up = f.operators().grad_uy.A * *sf.psi, vp = -(f.operators().grad_ux.A * *sf.psi);
      const double reach = 2.0 * f.h();
      double res = 0;
      for (int i = 0; i < L.size(); ++i) {
        const double y = L.x(i, 1);
        if (!c.py && (y < reach || 1.0 - y < reach)) continue;
        res = std::max(res, std::hypot(sf.mean.x() + up[i] - u(i, 0), sf.mean.y() + vp[i] - u(i, 1)));
      }
      e[k] = res / u.cwiseAbs().maxCoeff();
    }
    EXPECT_LT(e[1], 1.2 * r.e64) << c.name << " h " << r.h;
    EXPECT_GT(std::log2(e[0] / e[1]), 1.8) << c.name << " h " << r.h;
  }
}

// The divergence-free interpolant is the curl of a C^2 function: its divergence by central
// differences (step e) at random points tends to zero with e (the truncation error of the
// differences), while that of Eq. (63) stays. Smooth periodic psi, nx = 32, h = 1.2 dx, 200 points,
// max |div U| / max |U|; measured: curl 1.74e-5 (e = 2.5e-4 h), 1.43e-6 (e = 1e-4 h); Eq. (63) of the
// sampled curl 0.0910 at both. Tolerances: curl below 1.5x measured at 1e-4 h and falling > 4x
// from 2.5e-4 h; Eq. (63) > 0.05. At lattice points U = (G psi)/(sum_j V W_ij): measured
// agreement 5.3e-15, tolerance 1e-12.
TEST(StreamFunction, InterpolatedCurlIsDivergenceFree) {
  const EulerianFluid f(params(32, true, true));
  const Lattice& L = f.lattice();
  const CubicSplineKernel& W = f.kernel();
  const CellGrid grid = lattice_grid(L);
  Vec psi(L.size());
  Mat2 u(L.size(), 2);
  for (int i = 0; i < L.size(); ++i) {
    const double x = 2 * kPi * L.x(i, 0), y = 2 * kPi * L.x(i, 1);
    psi[i] = std::sin(x) * std::sin(y) + 0.3 * std::cos(2 * x + y);
    u(i, 0) = 2 * kPi * (std::sin(x) * std::cos(y) - 0.3 * std::sin(2 * x + y));   // d psi/dy
    u(i, 1) = -2 * kPi * (std::cos(x) * std::sin(y) - 0.6 * std::sin(2 * x + y));  // -d psi/dx
  }
  const Eigen::Vector2d U0(0.2, -0.1);
  double div_curl[2], div_sph[2];
  for (int c = 0; c < 2; ++c) {
    const double e = (c ? 1e-4 : 2.5e-4) * W.h;
    std::mt19937 gen(1);
    std::uniform_real_distribution<double> R(0.0, 1.0);
    double dc = 0, ds = 0, umax = 0;
    for (int k = 0; k < 200; ++k) {
      const double x = R(gen), y = R(gen);
      Mat2 X(4, 2), U(4, 2), S(4, 2);
      X << x + e, y, x - e, y, x, y + e, x, y - e;
      interpolate_curl(grid, W, psi, U0, X, U);
      interpolate_velocity(grid, W, L.volume, u, X, S);
      dc = std::max(dc, std::fabs((U(0, 0) - U(1, 0) + U(2, 1) - U(3, 1)) / (2 * e)));
      ds = std::max(ds, std::fabs((S(0, 0) - S(1, 0) + S(2, 1) - S(3, 1)) / (2 * e)));
      umax = std::max(umax, U.cwiseAbs().maxCoeff());
    }
    div_curl[c] = dc / umax;
    div_sph[c] = ds / umax;
  }
  EXPECT_LT(div_curl[1], 1.5 * 1.43e-6);
  EXPECT_GT(div_curl[0] / div_curl[1], 4.0);
  EXPECT_GT(div_sph[0], 0.05);
  EXPECT_GT(div_sph[1], 0.05);
  // at the lattice points: the fluid's own gradient of psi over the kernel sum
  Mat2 U(L.size(), 2);
  interpolate_curl(grid, W, psi, U0, L.x, U);
  const Vec gx = f.operators().grad_phix * psi, gy = f.operators().grad_phiy * psi;
  double S = W.W(0.0);
  for (int k = f.pairs().offset[0]; k < f.pairs().offset[1]; ++k) S += W.W(f.pairs().r[k]);
  S *= L.volume;
  double d = 0;
  for (int i = 0; i < L.size(); ++i)
    d = std::max(d, std::max(std::fabs(U(i, 0) - U0.x() - gy[i] / S), std::fabs(U(i, 1) - U0.y() + gx[i] / S)));
  EXPECT_LT(d, 1e-12);
}

// A manufactured discretely divergence-free flow: psi a smooth cell plus grid-scale noise (the
// content a flow past a membrane has: its velocity kinks there), u = (Gy psi, -Gx psi), so D u = 0
// as after the exact projection. A circle (Nb = 512) moved for t = 0.25 by the trapezoidal fixed
// point (Eqs. 56-60): with the curl interpolant the area error is time-step error only (and a
// marker-spacing part, below 1e-7 at this Nb), falling about 4x per halving of dt; with Eq. (63) it
// tends to the interpolant's own divergence, a floor independent of dt.
// Measured relative area change, dt = 0.005, 0.0025, 0.00125:
//   curl -4.84e-6, -1.50e-6, -6.69e-7;  Eq. (63) -4.298e-5, -4.130e-5, -4.088e-5.
// Tolerances: curl below 1.5x measured at the smallest dt and falling > 2x per halving; Eq. (63)
// above 3e-5 with halvings changing it by < 5%.
TEST(StreamFunction, ManufacturedDivergenceFreeFlowKeepsTheArea) {
  const EulerianFluid f(params(32, true, true));
  const Lattice& L = f.lattice();
  const CubicSplineKernel& W = f.kernel();
  const CellGrid grid = lattice_grid(L);
  std::mt19937 gen(9);
  std::uniform_real_distribution<double> R(-1.0, 1.0);
  Vec psi(L.size());
  for (int i = 0; i < L.size(); ++i)
    psi[i] = 0.1 * std::sin(2 * kPi * L.x(i, 0)) * std::sin(2 * kPi * L.x(i, 1)) + 1e-2 * R(gen);
  Mat2 u(L.size(), 2);
  u.col(0) = f.operators().grad_phiy * psi;
  u.col(1) = -(f.operators().grad_phix * psi);
  auto run = [&](bool curl, double dt) {
    const int nb = 512;
    Membrane m = make_membrane(circle(nb, 0.4, 0.45, 0.2), 0.2, 1.0);
    MembraneDiagnostics D(nb, m.L0());
    const double a0 = D.measure(m.X).area;
    MarkerVelocity vel = [&](const Mat2& X, Mat2& U, Jacobians*) {
      if (curl) interpolate_curl(grid, W, psi, Eigen::Vector2d::Zero(), X, U);
      else interpolate_velocity(grid, W, L.volume, u, X, U);
      return false;
    };
    Mat2 Un(nb, 2), U(nb, 2), Xn = m.X;
    MarkerUpdateParams mp;
    MarkerWork work;
    for (int s = 0; s < static_cast<int>(std::lround(0.25 / dt)); ++s) {
      vel(m.X, Un, nullptr);
      advance_markers(vel, Un, nullptr, dt, mp, s, m.X, Xn, U, work);
    }
    return std::fabs(D.measure(m.X).area / a0 - 1.0);
  };
  double c[3], e[3];
  for (int k = 0; k < 3; ++k) {
    c[k] = run(true, 0.005 / (1 << k));
    e[k] = run(false, 0.005 / (1 << k));
  }
  EXPECT_LT(c[2], 1.5 * 6.69e-7);
  EXPECT_GT(c[0] / c[1], 2.0);
  EXPECT_GT(c[1] / c[2], 2.0);
  for (int k = 0; k < 3; ++k) EXPECT_GT(e[k], 3e-5);
  EXPECT_LT(std::fabs(e[1] / e[2] - 1.0), 0.05);
  EXPECT_LT(std::fabs(e[0] / e[1] - 1.0), 0.05);
}

// A free membrane in equilibrium (Section 5.2.1 at Nx = 40, dt = 0.1 dx, convection on) keeps its
// area over 267 steps (t = 2) with the conservative pair; the paper's pair loses 5%.
// Measured area error at t = 2: exact + divergence-free -4.1e-7; approximate + SPH -5.3e-2.
// Tolerances 2e-6 (5x measured: the marker-spacing part, see the README) and > 1e-2.
TEST(StreamFunction, FreeMembraneAtRestKeepsItsArea) {
  for (bool conservative : {true, false}) {
    SimulationParams sp;
    sp.fluid.domain.x0 = sp.fluid.domain.y0 = -1.5;
    sp.fluid.domain.x1 = sp.fluid.domain.y1 = 1.5;
    sp.fluid.nx = sp.fluid.ny = 40;
    sp.fluid.rho = 1.0;
    sp.fluid.mu = 0.1;
    sp.fluid.dt = 0.1 * 3.0 / 40;
    sp.fluid.projection = conservative ? Projection::Exact : Projection::Approximate;
    sp.interpolation = conservative ? MarkerInterpolation::DivergenceFree : MarkerInterpolation::Sph;
    MembraneSetup ms;
    ms.membrane = make_membrane(circle(140, 0.0, 0.0, 0.6), 0.5, 3.0);
    ms.h_star = 1.4 * 1.2 * 3.0 / 40;
    sp.membranes.push_back(ms);
    Simulation sim(sp);
    MembraneDiagnostics D(140, ms.membrane.L0());
    const double a0 = D.measure(ms.membrane.X).area;
    while (sim.time() < 2.0 - 1e-9) sim.step();
    const double e = D.measure(sim.membranes()[0].m.X).area / a0 - 1.0;
    if (conservative) EXPECT_LT(std::fabs(e), 2e-6) << e;
    else EXPECT_GT(std::fabs(e), 1e-2) << e;
  }
}
