// The step of a capsule suspension against the same box without capsules (the scene of
// cases/suspension.hpp: 100 capsules x 64 markers, area fraction 0.3, sheared 256^2 box), paired in
// one process on one core (or `--threads`): both simulations are set up, then stepped alternately,
// `--block` steps of the empty box and `--block` of the suspension per round, each block timed by the
// process's CPU time on one thread, by the wall clock on more (CPU time would add the threads'
// times). Prints the ms per step of each (median over the rounds), the median (min-max) of the
// rounds' ratios, the load average before and after, and the suspension's coupling phases (their
// share of its step, from its profile's wall times).
//   build/suspension [--rounds R] [--block K] [--threads T] [--count C] [--nb NB] [--nx N] [--contact-strength S]
//                    [--interpolation bspline|divergence_free|spreading_kernel] [--newton true|false]
//                    [--linear-step S] [--marker-eps E] [--h-star R]
#include <algorithm>

#include "bench/common.hpp"
#include "cases/suspension.hpp"
#include "coupling/contact.hpp"
#include "coupling/simulation.hpp"
#include "coupling/spread.hpp"
#include "fluid/common/threads.hpp"

using namespace sphib;
using namespace sphib::bench;

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
}  // namespace

int main(int argc, char** argv) {
  SuspensionParams p;
  p.contact_strength = 0.1;
  int rounds = 7, block = 20, warm = 10, threads = 1;
  CLI::App app{"suspension step against the same box without capsules (one core or --threads, paired in one process)"};
  app.add_option("--rounds", rounds, "rounds of (empty, suspension) blocks");
  app.add_option("--threads", threads, "threads of both simulations (default 1; more: wall-clock timing)")
      ->check(CLI::Range(1, 256));
  app.add_option("--block", block, "steps per block");
  app.add_option("--warm-up", warm, "steps of each before the first round");
  add_suspension_options(app, p);
  return run_main(app, argc, argv, [&] {
    SuspensionParams e = p;
    e.empty = true;
    Simulation empty(suspension_scene(e).sim), susp(suspension_scene(p).sim);
    for (int s = 0; s < warm; ++s) empty.step(), susp.step();
    // one thread: CPU time (insensitive to the time the process waits for the core); more: wall time
    const Clock::time_point origin = Clock::now();
    auto now = [&] { return threads == 1 ? cpu_seconds() : seconds_since(origin); };
    const double load0 = load_average();
    std::vector<double> te, ts, ratio;
    for (int r = 0; r < rounds; ++r) {
      double t0 = now();
      for (int s = 0; s < block; ++s) empty.step();
      const double a = (now() - t0) / block;
      t0 = now();
      for (int s = 0; s < block; ++s) susp.step();
      const double b = (now() - t0) / block;
      te.push_back(a), ts.push_back(b), ratio.push_back(b / a);
      std::printf("round %d: empty %.3f ms/step, suspension %.3f ms/step, ratio %.3f\n", r + 1, 1e3 * a, 1e3 * b, b / a);
    }
    std::printf("%d capsules x %d markers, %d^2, %s, contact %s: %d thread(s) (%s time), %d rounds of %d steps\n",
                static_cast<int>(susp.membranes().size()), p.nb, p.nx, p.interpolation.c_str(),
                susp.contact() ? "on" : "off", thread_count(), threads == 1 ? "CPU" : "wall", rounds, block);
    std::printf("empty box %.3f ms/step, suspension %.3f ms/step (medians); suspension/empty %.3f (min %.3f, max %.3f); "
                "load average %.2f -> %.2f\n",
                1e3 * median(te), 1e3 * median(ts), median(ratio), *std::min_element(ratio.begin(), ratio.end()),
                *std::max_element(ratio.begin(), ratio.end()), load0, load_average());
    // the coupling's phases, as shares of the suspension's profiled step (wall times)
    const Profile& c = susp.profile();
    const double total = c.total() + susp.fluid().profiler().step_seconds();
    std::printf("suspension step (wall, profiled): fluid %.1f%%", 100 * susp.fluid().profiler().step_seconds() / total);
    for (size_t k = 0; k < c.names().size(); ++k) std::printf(", %s %.1f%%", c.names()[k].c_str(), 100 * c.seconds(k) / total);
    std::printf("\n");
    // The fluid's phases in both (wall ms per step of each phase over all steps, warm-up included;
    // "stream function" is the markers' psi, made on demand by the marker update, not part of step())
    const Profiler& pe = empty.fluid().profiler();
    const Profiler& ps = susp.fluid().profiler();
    const double ne = static_cast<double>(empty.fluid().steps()), ns = static_cast<double>(susp.fluid().steps());
    std::printf("fluid phases, empty / suspension (wall ms per step):");
    for (size_t k = 0; k < ps.names().size(); ++k) {
      double e = 0.0;
      for (size_t j = 0; j < pe.names().size(); ++j)
        if (pe.names()[j] == ps.names()[k]) e = pe.seconds(static_cast<int>(j)) / ne;
      std::printf(" %s %.3f / %.3f;", ps.names()[k].c_str(), 1e3 * e, 1e3 * ps.seconds(static_cast<int>(k)) / ns);
    }
    std::printf("\n");
    // The marker update's true residual: U^{n+1} interpolated again at X^{n+1} of every membrane
    double g_true = 0.0;
    for (const auto& m : susp.membranes()) {
      Mat2 Ut(m.m.nb(), 2);
      susp.marker_velocity(m.m.X, Ut);
      const double dt = susp.fluid().params().dt;
      g_true = std::max(g_true, (m.m.X - m.X_n - 0.5 * dt * (m.U_n + Ut)).rowwise().norm().maxCoeff());
    }
    double interpolations = 0.0;
    for (const auto& m : susp.membranes()) interpolations += static_cast<double>(m.interpolations) / m.updates;
    std::printf("marker update: %.3f interpolations per step, true residual of the last max |g(X^{n+1})| = %.2e "
                "(eps %.0e)\n", interpolations / std::max<size_t>(1, susp.membranes().size()), g_true, p.marker_eps);
    // The coupling's per-marker passes as one set of markers against one call per membrane, on the
    // suspension's last state: best of 20 timings each (CPU or wall, as the blocks), alternately.
    const auto& mem = susp.membranes();
    if (mem.empty()) return 0;
    const int n = static_cast<int>(mem.size()) * p.nb;
    Mat2 X(n, 2), P(n, 2), F = Mat2::Zero(susp.fluid().size(), 2), U(n, 2), Uk(p.nb, 2);
    Jacobians dU, dUk;
    for (size_t k = 0; k < mem.size(); ++k) {
      X.middleRows(k * p.nb, p.nb) = mem[k].m.X;
      P.middleRows(k * p.nb, p.nb) = mem[k].f * mem[k].m.ds();
    }
    CellGrid grid(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), true, false, 1.0 / p.nx);
    grid.use_lattice(susp.fluid().lattice());
    const CubicSplineKernel& W = mem[0].W_star;
    auto best = [&](auto&& kernel) {
      double t = 1e300;
      for (int r = 0; r < 20; ++r) {
        const double t0 = now();
        kernel();
        t = std::min(t, now() - t0);
      }
      return t;
    };
    double sp1 = 1e300, spk = 1e300, in1 = 1e300, ink = 1e300;
    for (int r = 0; r < 3; ++r) {
      spk = std::min(spk, best([&] { for (const auto& m : mem) spread_force(grid, W, m.m.X, m.f, m.m.ds(), F); }));
      sp1 = std::min(sp1, best([&] { spread_point_forces(grid, W, X, P, F); }));
      ink = std::min(ink, best([&] { for (const auto& m : mem) susp.marker_velocity(m.m.X, Uk, &dUk); }));
      in1 = std::min(in1, best([&] { susp.marker_velocity(X, U, &dU); }));
    }
    std::printf("one set against one call per membrane (best ms): spreading %.3f / %.3f, interpolation with "
                "gradient %.3f / %.3f\n", 1e3 * sp1, 1e3 * spk, 1e3 * in1, 1e3 * ink);
    // the markers' stream function the divergence-free interpolations need, once per step (its
    // right-hand side and solve: the fluid's floor of it, best wall time)
    std::printf("markers' stream function %.3f ms (best of 20)\n",
                1e3 * susp.fluid().profiler().stream_function_floor_seconds(20));
    if (susp.contact()) {  // the contact force alone, and the membranes' elastic forces alone
      ContactForce c(susp.contact()->params(), susp.fluid().params().domain);
      std::vector<int> start{0};
      std::vector<double> ds;
      for (const auto& m : mem) start.push_back(start.back() + m.m.nb()), ds.push_back(m.m.ds());
      Mat2 f = Mat2::Zero(n, 2);
      const double tc = best([&] { c.add(X, start, ds, f); });
      std::printf("contact force %.3f ms (%ld pairs within range)\n", 1e3 * tc, c.pairs());
    }
    return 0;
  }, &threads);
}
