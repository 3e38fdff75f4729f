// The marker interpolations on a smooth flow: the error against the exact velocity and the ripple
// (the largest second difference along a line sampled every dx/30), for the SPH kernel's curl of the
// stream function (coupling.interpolation = "divergence_free"), its tensor cubic B-spline curl
// ("bspline"), the normalised SPH interpolation of the velocity (Eq. 63, "sph") and the curl by the
// spreading's kernel of radius h* ("spreading_kernel", at h*/dx = 1.68, 3.36, 6.72: its error against
// the exact velocity includes the kernel's smoothing, O((k h*)^2); its ripple is the lattice's).
//   build/marker_interpolation [--nx N] [--h-over-dx R]
// Doubly periodic box [-1.5, 1.5]^2, u = (sin(2 pi y/3), 0.3 cos(2 pi x/3)), h = 1.2 dx by default.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>

#include "coupling/interpolate.hpp"
#include "fluid/factory.hpp"
#include "fluid/core/solver.hpp"

using namespace sphib;

int main(int argc, char** argv) {
  int nx = 64;
  double h_over_dx = 1.2;
  CLI::App app{"marker interpolations: error and lattice-scale ripple on a smooth flow"};
  app.add_option("--nx", nx, "particles per side");
  app.add_option("--h-over-dx", h_over_dx, "kernel.h_over_dx");
  CLI11_PARSE(app, argc, argv);
  const double kPi = 3.14159265358979323846;
  FluidParams p;
  p.domain = {-1.5, 1.5, -1.5, 1.5, /*periodic_x=*/true, /*periodic_y=*/true};
  p.nx = p.ny = nx;
  p.h_over_dx = h_over_dx;
  auto fl = make_fluid(p);
  const Mat2& x = fl->x();
  Mat2 u(fl->size(), 2);
  auto exact = [&](double X, double Y) { return Eigen::Vector2d(std::sin(2 * kPi * Y / 3), 0.3 * std::cos(2 * kPi * X / 3)); };
  for (int i = 0; i < fl->size(); ++i) u.row(i) = exact(x(i, 0), x(i, 1)).transpose();
  fl->set_velocity(u);
  CellGrid grid(Eigen::Vector2d(-1.5, -1.5), Eigen::Vector2d(1.5, 1.5), true, true, fl->lattice().dx);
  grid.use_lattice(fl->lattice());
  const double dx = fl->lattice().dx, step = dx / 30;
  const int n = static_cast<int>(1.4 / step);
  Mat2 X(n, 2), U(n, 2);
  for (int k = 0; k < n; ++k) X.row(k) << -0.7 + k * step, 0.2 + 0.05 * std::sin(7.0 * k / n);
  const StreamFunction sf = fl->stream_function();
  std::printf("%d x %d, h = %g dx, %d points every dx/30 along a line\n", nx, nx, h_over_dx, n);
  std::printf("%-16s %12s %12s\n", "interpolation", "max error", "ripple");
  for (const char* name : {"divergence_free", "bspline", "sph", "h*/dx = 1.68", "h*/dx = 3.36", "h*/dx = 6.72"}) {
    const std::string s = name;
    if (s == "divergence_free") interpolate_curl(grid, fl->kernel(), *sf.psi, sf.mean, X, U);
    else if (s == "bspline") interpolate_curl_bspline(grid, dx, fl->lattice().dy, *sf.psi, sf.mean, X, U);
    else if (s == "sph") interpolate_velocity(grid, fl->kernel(), fl->volumes(), fl->u(), X, U);
    else interpolate_curl(grid, CubicSplineKernel(std::stod(s.substr(8)) * dx), *sf.psi, sf.mean, X, U);
    double err = 0, ripple = 0;
    for (int k = 0; k < n; ++k) err = std::max(err, (U.row(k).transpose() - exact(X(k, 0), X(k, 1))).norm());
    for (int k = 1; k + 1 < n; ++k) ripple = std::max(ripple, (U.row(k + 1) - 2 * U.row(k) + U.row(k - 1)).norm());
    std::printf("%-16s %12.3e %12.3e\n", name, err, ripple);
  }
}
