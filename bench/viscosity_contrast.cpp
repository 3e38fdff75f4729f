// The viscosity contrast's numerics, printed (docs/viscosity_contrast.md quotes them):
//  1. the indicator of a circle polygon: its integral against the polygon's, the spline's and the
//     circle's areas, and the width of its transition (cells cut per lattice spacing of perimeter);
//  2. layered Couette flow against its exact profile, max error and order in h, lambda 0.1 ... 10,
//     the interface on a lattice line or through a row of cells (bench/viscosity_contrast.hpp);
//  3. a circular interface against an exact two-fluid Stokes flow (the central-force form of m > 1
//     and, for comparison, the gradient form), max error and order in h;
//  4. the discrete div(m (grad u + grad u^T)) on manufactured fields: error and order in h;
//  5. the step's error in time on the manufactured unsteady Stokes flow: order in dt;
//  6. the stability of the explicit cross term of lambda < 1 against nu (1 - lambda) dt / dx^2.
//   build/viscosity_contrast [--max-n 128] [--tables 1,2,3,4,5,6]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <vector>
#include <cmath>
#include <cstdio>

#include "bench/viscosity_contrast.hpp"
#include "coupling/viscosity_contrast.hpp"
#include "membrane/geometry.hpp"
#include "membrane/polygon.hpp"
#include "membrane/shapes.hpp"

using namespace sphib;
using namespace sphib::bench::viscosity;

namespace {

double order(double coarse, double fine, double ratio = 2.0) { return std::log(coarse / fine) / std::log(ratio); }

void indicator_table() {
  std::printf("1. Indicator of a circle polygon (r = 0.3, centre (0.137, -0.061), nb = 2 per dx) on [-1, 1] x [-0.5, 0.5]\n");
  std::printf("%6s %5s %14s %14s %14s %10s %12s\n", "nx", "nb", "sum I dA - Ap", "Ap/As - 1", "As/(pi r2) - 1",
              "cut cells", "per perim/dx");
  for (int nx : {64, 128, 256}) {
    const Domain d{-1.0, 1.0, -0.5, 0.5, true, false};
    const Lattice L = make_lattice(d, nx, nx / 2);
    const int nb = static_cast<int>(std::lround(2 * kPi * 0.3 / (0.5 * L.dx)));
    const Mat2 X = circle(nb, 0.137, -0.061, 0.3);
    CellFractions f;
    CellFractionWork w;
    cell_fractions(L, X, f, w);
    MembraneDiagnostics D(nb, 2 * kPi * 0.3);
    D.fit(X);
    const double Ap = signed_area(X), As = D.area();
    int cut = 0;
    for (double I : f.I) cut += I < 1.0;
    std::printf("%6d %5d %14.3e %14.3e %14.3e %10d %12.3f\n", nx, nb, f.area - Ap, Ap / As - 1, As / (kPi * 0.09) - 1, cut,
                cut / (2 * kPi * 0.3 / L.dx));
  }
}

void two_layer_table(int max_n) {
  std::printf("\n2. Layered Couette flow (U = 1, interface at y = round(0.4 n)/n + offset dx): max |u - u_exact|, order\n");
  for (double lambda : {0.1, 0.2, 5.0, 10.0})
    for (double offset : {0.0, 0.3, 0.5}) {
      std::printf("lambda %-4g offset %.1f:", lambda, offset);
      double prev = 0;
      for (int n = 16; n <= max_n; n *= 2) {
        const double e = two_layer_error(n, lambda, std::round(0.4 * n) / n + offset / n);
        std::printf("  n %3d %.3e", n, e);
        if (prev > 0) std::printf(" (%.2f)", order(prev, e));
        prev = e;
      }
      std::printf("\n");
    }
}

void circle_table(int max_n) {
  std::printf("\n3. A circular interface (R = 0.4, exact two-fluid Stokes flow with continuous traction):\n"
              "   max |u - u_exact| / max |u_exact| at steady state, order; central: the stress form of m > 1\n");
  for (double lambda : {1.0, 0.2, 5.0, 10.0})
    for (bool central : {true, false}) {
      if (lambda <= 1 && !central) continue;  // the same scheme
      std::printf("lambda %-4g %s:", lambda, lambda <= 1 ? "        " : central ? "central " : "gradient");
      double prev = 0;
      for (int n = 32; n <= max_n; n *= 2) {
        long steps = 0;
        const double e = circle_error(n, lambda, central, &steps);
        std::printf("  n %3d %.3e [%ld steps]", n, e, steps);
        if (prev > 0) std::printf(" (%.2f)", order(prev, e));
        prev = e;
        std::fflush(stdout);
      }
      std::printf("\n");
    }
}

void operator_table(int max_n) {
  std::printf("\n4. Manufactured field: max |discrete - exact| / max |exact| of div(m (grad u + grad u^T)) (variable)\n"
              "   and of the constant-viscosity Laplacian of the same u (constant), order in h\n");
  for (const Manufactured* mf : {&kAbove, &kBelow})
  for (double hr : {1.2, 2.0}) {
    double pv = 0, pc = 0;
    for (int n = 32; n <= max_n; n *= 2) {
      const OperatorError e = operator_error(*mf, n, hr);
      std::printf("m = %.1f + %.1f sin cos, h/dx %.1f n %3d: variable %.3e", mf->m0, mf->m1, hr, n, e.variable);
      if (pv > 0) std::printf(" (%.2f)", order(pv, e.variable));
      std::printf("  constant %.3e", e.constant);
      if (pc > 0) std::printf(" (%.2f)", order(pc, e.constant));
      std::printf("\n");
      pv = e.variable, pc = e.constant;
    }
  }
}

void time_table() {
  std::printf("\n5. Unsteady manufactured Stokes flow, n = 16, t = 0.5: max |u - u(dt/64)|, order in dt\n");
  for (const Manufactured* mf : {&kAbove, &kBelow}) {
  std::printf("m = %.1f + %.1f sin cos\n", mf->m0, mf->m1);
  const Mat2 ref = unsteady_run(*mf, 16, 0.05 / 64, 0.5);
  double prev = 0;
  for (int c = 0; c < 5; ++c) {
    const double dt = 0.05 / (1 << c), e = (unsteady_run(*mf, 16, dt, 0.5) - ref).cwiseAbs().maxCoeff();
    std::printf("dt %.5f: %.3e", dt, e);
    if (prev > 0) std::printf(" (%.2f)", order(prev, e));
    std::printf("\n");
    prev = e;
  }
  }
}

void stability_table() {
  std::printf("\n6. The explicit cross term of lambda < 1: a circle (r = 0.3) in the periodic unit box, n = 32,\n"
              "   dt from nu (1 - lambda) dt / dx^2: the step that passes max |u| = 1e3, or 'stable' after 1000 steps\n");
  for (double lambda : {0.01, 0.1, 0.5}) {
    std::printf("lambda %-4g:", lambda);
    for (double number : {0.4, 0.5, 0.6, 0.7}) {
      const long s = explicit_cross_blowup(lambda, number);
      if (s < 0) std::printf("  %.1f stable", number);
      else std::printf("  %.1f blows up at step %ld", number, s);
      std::fflush(stdout);
    }
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  int max_n = 128;
  std::vector<int> tables{1, 2, 3, 4, 5, 6};
  CLI::App app{"viscosity contrast: indicator, layered Couette, circular interface, manufactured operator and step, "
               "stability"};
  app.add_option("--max-n", max_n, "largest resolution of the convergence tables");
  app.add_option("--tables", tables, "which tables (comma-separated; table 3 takes the longest)")->delimiter(',');
  CLI11_PARSE(app, argc, argv);
  auto want = [&](int t) { return std::find(tables.begin(), tables.end(), t) != tables.end(); };
  if (want(1)) indicator_table();
  if (want(2)) two_layer_table(max_n);
  if (want(3)) circle_table(max_n);
  if (want(4)) operator_table(max_n);
  if (want(5)) time_table();
  if (want(6)) stability_table();
}
