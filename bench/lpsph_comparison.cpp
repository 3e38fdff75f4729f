// Benchmark (not a test): LPSPH (moving particles, fluid/moving/lagrangian.hpp) against EPSPH (fixed
// particles, fluid/eulerian/eulerian.hpp), issue 5, after Sections 3.1, 5.1 and 5.2 of Noutcheuwa & Owens
// (2012). Three parts, each printed, with a CSV and a section of DIR/lpsph_comparison.md:
//
// poiseuille  Start-up planar Poiseuille (Section 5.1, Tables 1-2): Re = 0.0125 (rho = 1,
//             mu = 1/Re, F = 8/Re, u_max = 1; bench/poiseuille.hpp), 10 000 steps (--steps to
//             shorten), Nx = Ny in --nx (24, 32, 48, 64) x h/dx in --h (1.525).
//             Both methods with the same settings and solvers (auto); rms error (Eq. 69) at the
//             final time and CPU time of the process (set-up + loop: the machine is shared, CPU
//             time is what a run costs); the time ratio LPSPH/EPSPH next to the paper's (Table 2
//             / Table 1: 2.77 to 5.25); an LPSPH step phase by phase (ms) beside EPSPH's step;
//             the solvers LPSPH chose, their CG iterations per solve and preconditioner
//             factorisations, and the Verlet list's builds. The load average before and after.
//             With fewer steps, totals are also extrapolated to 10 000 steps (set-up once, loop
//             scaled).
// fig9        Fixed membrane in equilibrium (Section 5.2.1, Fig. 9): T0 = 3, mu = 0.25,
//             Nb = 360, dt = 0.1 dx, 2h = 2.25 (dx + dy), h* = 0.5 h, Nx = Ny in --fig9-nx; the
//             mean absolute pressure error (Eq. 80, free constant chosen optimally as the runner
//             does) against time for LPSPH, LPSPH reinitialised every --fig9-reinit steps, EPSPH.
//             Scene: cases/membrane_equilibrium_lagrangian.toml.
// fig18       Oscillating membrane with LPSPH at 64 x 64 (Section 5.2.2, Fig. 18), scene
//             cases/membrane_oscillation_lagrangian.toml, to --fig18-end: the lowest kernel sum and
//             the half-axes against time next to EPSPH's, and when (whether) the breakdown
//             diagnostic stops the run, with what it says.
//
//   lpsph_comparison [--parts poiseuille,fig9,fig18] [--nx LIST] [--h LIST] [--steps N]
//                    [--fig9-nx LIST] [--fig9-end T] [--fig9-reinit N] [--fig18-end T] [--out DIR]
//
// Single-threaded, as the paper's timings are for one core.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "bench/common.hpp"
#include "bench/poiseuille.hpp"
#include "coupling/simulation.hpp"
#include "fluid/factory.hpp"
#include "fluid/moving/lagrangian.hpp"
#include "io/scene.hpp"
#include "membrane/geometry.hpp"

namespace {

namespace fs = std::filesystem;
using namespace sphib::bench;
using namespace sphib::bench::poiseuille;
using sphib::seconds_since;

// The scene files: cases/ of the source tree this file was compiled from (CMake passes absolute
// source paths), or SPHIB_CASES if set.
fs::path cases_dir() {
  if (const char* c = std::getenv("SPHIB_CASES")) return c;
  return fs::path(__FILE__).parent_path().parent_path() / "cases";
}

// The load average (1, 5, 15 minutes) of the machine.
std::string load_average() {
  std::ifstream f("/proc/loadavg");
  double a = NAN, b = NAN, c = NAN;
  f >> a >> b >> c;
  return fix(a, 2) + ", " + fix(b, 2) + ", " + fix(c, 2);
}

// The paper's LPSPH/EPSPH time ratio for (nx, h/dx), NaN when not tabulated.
double paper_ratio(int nx, double hdx) { return paper_seconds(true, nx, hdx) / paper_seconds(false, nx, hdx); }

struct Options {
  std::vector<std::string> parts{"poiseuille", "fig9", "fig18"};
  std::vector<int> nx{24, 32, 48, 64};
  std::vector<double> h{1.525};
  long steps = kPaperSteps;
  std::vector<int> fig9_nx{40, 80};
  double fig9_end = 3.0;
  int fig9_reinit = 10;
  double fig18_end = 1.2;
  std::string out = "bench_out/lpsph";
  bool wants(const std::string& part) const { return std::find(parts.begin(), parts.end(), part) != parts.end(); }
};

// ---------------------------------------------------------------- Poiseuille (Tables 1-2)

struct PoiseuilleRun {
  std::string status = "ok";
  double rms = NAN, t_setup = 0, t_loop = 0, cpu_setup = 0, cpu_loop = 0;
  long steps = 0;
  // LPSPH only: its profile (ms per step by phase), the neighbours, the solvers' work
  std::vector<std::pair<std::string, double>> phases;
  double nb = 0, s_low = NAN, it_cn = 0, it_poisson = 0;
  long builds = 0, factor_cn = 0, factor_poisson = 0;
  std::string method_cn, method_poisson;
  double total() const { return cpu_setup + cpu_loop; }  // CPU seconds: the machine is shared
  double total_10k() const { return cpu_setup + (steps ? cpu_loop * kPaperSteps / steps : 0.0); }
  double phase(const std::string& prefix) const {
    double t = 0;
    for (const auto& [n, v] : phases)
      if (n.rfind(prefix, 0) == 0) t += v;
    return t;
  }
};

// The solver's short name for the tables: what preconditions its CG, or its method.
std::string solver_name(const sphib::SolverInfo& si) {
  const std::string& m = si.method;
  if (m.rfind("CG preconditioned by FFT", 0) == 0) return "pcg_fft";
  if (m.rfind("CG preconditioned by a lagged", 0) == 0) return "pcg_cholmod";
  if (m.rfind("Jacobi-PCG", 0) == 0) return "Jacobi-PCG";
  return m.substr(0, m.find(" ("));
}

void lpsph_figures(const sphib::LagrangianFluid& l, PoiseuilleRun& r) {
  const sphib::Profile& P = l.profiler();
  for (size_t k = 0; k < P.names().size(); ++k) {
    const double s = P.seconds(static_cast<int>(k));
    if (s > 0) r.phases.emplace_back(P.names()[k], 1e3 * s / r.steps);
  }
  r.nb = l.neighbours_per_particle();
  r.builds = l.verlet().builds();
  r.s_low = l.lowest_kernel_sum();
  const auto info = l.solver_info();
  r.method_cn = solver_name(info[0]);
  r.method_poisson = solver_name(info[1]);
  for (const auto& [name, v] : l.profiler().report().figures) {
    if (name == "crank_nicolson_cg_iterations") r.it_cn = v;
    if (name == "poisson_cg_iterations") r.it_poisson = v;
    if (name == "crank_nicolson_preconditioner_factorisations") r.factor_cn = static_cast<long>(v);
    if (name == "poisson_preconditioner_factorisations") r.factor_poisson = static_cast<long>(v);
  }
}

PoiseuilleRun poiseuille_run(const std::string& method, int nx, double hdx, long steps) {
  PoiseuilleRun r;
  r.steps = steps;
  try {
    auto t0 = Clock::now();
    double c0 = cpu_seconds();
    auto f = sphib::make_fluid(params(method, nx, hdx));  // Stokes: LPSPH has no convection term
    r.t_setup = seconds_since(t0);
    r.cpu_setup = cpu_seconds() - c0;
    const sphib::Mat2 F = body_force(f->size());
    t0 = Clock::now();
    c0 = cpu_seconds();
    for (long s = 0; s < steps; ++s) f->step(F);
    r.t_loop = seconds_since(t0);
    r.cpu_loop = cpu_seconds() - c0;
    r.rms = error(*f).rms;  // Eq. (69) at the particles' positions
    if (!std::isfinite(r.rms)) r.status = "non-finite velocity";
    if (auto* l = dynamic_cast<sphib::LagrangianFluid*>(f.get())) lpsph_figures(*l, r);
  } catch (const std::exception& e) {
    r.status = e.what();
  }
  return r;
}

struct PoiseuillePair {
  int nx;
  double hdx;
  PoiseuilleRun e, l;
  double ratio() const { return l.total() / e.total(); }
  double ratio_10k() const { return l.total_10k() / e.total_10k(); }
  double ratio_loop() const { return l.cpu_loop / e.cpu_loop; }
};

std::string poiseuille_csv(const std::vector<PoiseuillePair>& rs) {
  std::ostringstream o;
  o << "nx,h_over_dx,steps,t_end,eps_status,eps_rms,eps_setup_cpu_s,eps_loop_cpu_s,eps_loop_wall_s,lps_status,lps_rms,"
       "lps_setup_cpu_s,lps_loop_cpu_s,lps_loop_wall_s,lps_neighbours_ms,lps_operators_ms,lps_new_matrices_ms,"
       "lps_solve_cn_ms,lps_solve_poisson_ms,lps_neighbours_per_particle,lps_list_builds,lps_cn_solver,lps_cn_iterations,"
       "lps_cn_factorisations,lps_poisson_solver,lps_poisson_iterations,lps_poisson_factorisations,lps_lowest_kernel_sum,"
       "ratio_total,ratio_loop,ratio_total_10k,paper_ratio\n";
  for (const auto& r : rs) {
    const PoiseuilleRun& l = r.l;
    o << r.nx << ',' << r.hdx << ',' << r.e.steps << ',' << csv_num(r.e.steps * kDt) << ",\"" << r.e.status << "\","
      << csv_num(r.e.rms) << ',' << csv_num(r.e.cpu_setup) << ',' << csv_num(r.e.cpu_loop) << ',' << csv_num(r.e.t_loop)
      << ",\"" << l.status << "\"," << csv_num(l.rms) << ',' << csv_num(l.cpu_setup) << ',' << csv_num(l.cpu_loop) << ','
      << csv_num(l.t_loop) << ',' << csv_num(l.phase("neighbours")) << ',' << csv_num(l.phase("operators")) << ','
      << csv_num(l.phase("new matrix")) << ',' << csv_num(l.phase("solve Crank")) << ',' << csv_num(l.phase("solve Poisson"))
      << ',' << csv_num(l.nb) << ',' << l.builds << ",\"" << l.method_cn << "\"," << csv_num(l.it_cn) << ',' << l.factor_cn
      << ",\"" << l.method_poisson << "\"," << csv_num(l.it_poisson) << ',' << l.factor_poisson << ',' << csv_num(l.s_low)
      << ',' << csv_num(r.ratio()) << ',' << csv_num(r.ratio_loop()) << ',' << csv_num(r.ratio_10k()) << ','
      << csv_num(paper_ratio(r.nx, r.hdx)) << '\n';
  }
  return o.str();
}

// The LPSPH step, phase by phase (ms per step, the profile of fluid/moving/lagrangian.hpp), one column per run.
std::string breakdown_md(const std::vector<PoiseuillePair>& rs) {
  std::vector<std::string> names;
  for (const auto& r : rs)
    for (const auto& [n, v] : r.l.phases)
      if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
  std::ostringstream m;
  m << "### An LPSPH step, ms (CPU of the loop by phase; EPSPH's whole step below)\n\n| phase |";
  for (const auto& r : rs) m << " Nx = " << r.nx << ", h = " << r.hdx << " dx |";
  m << "\n|---|";
  for (size_t k = 0; k < rs.size(); ++k) m << "---:|";
  m << '\n';
  for (const auto& n : names) {
    m << "| " << n << " |";
    for (const auto& r : rs) m << ' ' << fix(r.l.phase(n), 3) << " |";
    m << '\n';
  }
  m << "| **LPSPH step** |";
  for (const auto& r : rs) m << " **" << fix(r.l.steps ? 1e3 * r.l.cpu_loop / r.l.steps : NAN, 3) << "** |";
  m << "\n| EPSPH step |";
  for (const auto& r : rs) m << ' ' << fix(r.e.steps ? 1e3 * r.e.cpu_loop / r.e.steps : NAN, 3) << " |";
  m << "\n\n";
  return m.str();
}

std::string poiseuille_md(const std::vector<PoiseuillePair>& rs, const Options& o) {
  std::ostringstream m;
  m << "## Start-up Poiseuille, EPSPH against LPSPH (Section 5.1, Tables 1-2)\n\n"
    << "Re = 0.0125, dt = 1.25e-6, " << o.steps << " steps (t = " << sci(o.steps * kDt, 6)
    << "), the same solvers (auto) for both; one core; times are CPU seconds of the process (the machine is "
       "shared), set-up + loop.";
  if (o.steps != kPaperSteps)
    m << " **Shortened**: the errors are at t = " << sci(o.steps * kDt, 6)
      << ", not the developed flow of t = 0.0125; the 10 000-step totals are extrapolated (set-up once, loop "
         "scaled).";
  m << "\n\n";
  auto table = [&](const std::string& title, auto cell) {
    m << "### " << title << "\n\n| h/dx |";
    for (int n : o.nx) m << " Nx = " << n << " |";
    m << "\n|---|";
    for (size_t k = 0; k < o.nx.size(); ++k) m << "---:|";
    m << '\n';
    for (double h : o.h) {
      m << "| " << h << " |";
      for (int n : o.nx) {
        const PoiseuillePair* p = nullptr;
        for (const auto& r : rs)
          if (r.nx == n && std::abs(r.hdx - h) < 1e-12) p = &r;
        m << ' ' << (p ? cell(*p) : std::string("–")) << " |";
      }
      m << '\n';
    }
    m << '\n';
  };
  auto ok = [](const PoiseuillePair& p) { return p.e.status == "ok" && p.l.status == "ok"; };
  table("rms error (Eq. 69), EPSPH / LPSPH", [&](const PoiseuillePair& p) {
    return ok(p) ? sci(p.e.rms, 3) + " / " + sci(p.l.rms, 3) : std::string("failed");
  });
  table("CPU time, set-up + loop, s: EPSPH / LPSPH", [&](const PoiseuillePair& p) {
    return ok(p) ? fix(p.e.total(), 2) + " / " + fix(p.l.total(), 2) : std::string("failed");
  });
  table("Time ratio LPSPH / EPSPH: ours over these steps (loop only) [paper, Table 2 / Table 1]",
        [&](const PoiseuillePair& p) {
          return ok(p) ? fix(p.ratio(), 1) + " (" + fix(p.ratio_loop(), 1) + ") [" + fix(paper_ratio(p.nx, p.hdx), 2) + "]"
                       : std::string("failed");
        });
  if (o.steps != kPaperSteps)
    table("Time ratio LPSPH / EPSPH extrapolated to 10 000 steps", [&](const PoiseuillePair& p) {
      return ok(p) ? fix(p.ratio_10k(), 1) : std::string("failed");
    });
  table("LPSPH solvers: Crank-Nicolson / Poisson, CG iterations per solve [preconditioner factorisations]",
        [&](const PoiseuillePair& p) {
          if (!ok(p)) return std::string("failed");
          return p.l.method_cn + " " + fix(p.l.it_cn, 2) + " [" + std::to_string(p.l.factor_cn) + "] / " +
                 p.l.method_poisson + " " + fix(p.l.it_poisson, 2) + " [" + std::to_string(p.l.factor_poisson) + "]";
        });
  table("LPSPH neighbours within 2h per particle; Verlet list builds in the run", [&](const PoiseuillePair& p) {
    return ok(p) ? fix(p.l.nb, 1) + "; " + std::to_string(p.l.builds) : std::string("failed");
  });
  std::vector<PoiseuillePair> done;
  for (const auto& r : rs)
    if (ok(r)) done.push_back(r);
  if (!done.empty()) m << breakdown_md(done);
  double lo = INFINITY, hi = 0;
  for (const auto& r : done) { lo = std::min(lo, r.ratio_10k()); hi = std::max(hi, r.ratio_10k()); }
  if (std::isfinite(lo))
    m << "Our LPSPH/EPSPH time ratio (" << (o.steps == kPaperSteps ? "10 000 steps" : "extrapolated to 10 000 steps")
      << "): " << fix(lo, 1) << " to " << fix(hi, 1)
      << "; the paper's text says 2.83 to 5.25, its Tables 2/1 give 2.77 to 5.25.\n\n";
  for (const auto& r : rs) {
    if (r.e.status != "ok") m << "- EPSPH Nx = " << r.nx << ", h/dx = " << r.hdx << ": " << r.e.status << "\n";
    if (r.l.status != "ok") m << "- LPSPH Nx = " << r.nx << ", h/dx = " << r.hdx << ": " << r.l.status << "\n";
  }
  return m.str();
}

// ---------------------------------------------------------------- Fig. 9

struct Fig9Run {
  int nx;
  std::string variant;  // LPSPH, LPSPH reinit N, EPSPH
  std::vector<double> t, p_mad, jump;
  std::string stop = "end time";
  double seconds = 0, s_low = NAN;
  long builds = 0, steps = 0;  // LPSPH: Verlet list builds in the run's steps
};

// Eq. (80) with the free constant chosen optimally (the median), as io/run.cpp's
// measure_equilibrium: p_ex = [p] inside r < re, 0 outside, about the membrane's centre (0, 0).
double pressure_mad(const sphib::FluidSolver& f, double re, double jump_exact, double* jump) {
  const int N = f.size();
  const sphib::Vec& p = f.p();
  std::vector<double> shifted(N);
  double pin = 0, pout = 0;
  int nin = 0, nout = 0;
  for (int i = 0; i < N; ++i) {
    const double r = std::hypot(f.x()(i, 0), f.x()(i, 1));
    shifted[i] = p[i] - (r < re ? jump_exact : 0.0);
    if (r < 0.3) { pin += p[i]; ++nin; }                                   // well inside
    if (r > 0.9 && std::abs(f.x()(i, 1)) < 1.0) { pout += p[i]; ++nout; }  // well outside, off the walls
  }
  std::vector<double> sorted(shifted);
  std::nth_element(sorted.begin(), sorted.begin() + N / 2, sorted.end());
  const double c = sorted[N / 2];
  double mad = 0;
  for (double s : shifted) mad += std::abs(s - c);
  *jump = (nin && nout) ? pin / nin - pout / nout : NAN;
  return mad / N;
}

Fig9Run fig9_run(int nx, const std::string& method, int reinit, const Options& o) {
  Fig9Run r;
  r.nx = nx;
  r.variant = method == "eulerian" ? "EPSPH" : (reinit ? "LPSPH reinit " + std::to_string(reinit) : "LPSPH");
  const double dx = 3.0 / nx, dt = 0.1 * dx;
  const fs::path scene = cases_dir() / "membrane_equilibrium_lagrangian.toml";
  const std::vector<std::string> sets{"method=" + method, "grid.nx=" + std::to_string(nx), "grid.ny=" + std::to_string(nx),
                                      "time.dt=" + num(dt), "lagrangian.reinit_every=" + std::to_string(reinit)};
  sphib::Scene s = sphib::load_scene(scene.string(), sets);
  const double re = s.membranes[0].radius, jump_exact = s.membranes[0].Es / re * (re / s.membranes[0].r0 - 1.0);
  const auto t0 = Clock::now();
  sphib::Simulation sim(s.sim);
  const long n = std::lround(o.fig9_end / dt);
  const long every = std::max<long>(1, n / 60);
  try {
    for (long k = 1; k <= n; ++k) {
      sim.step();
      if (k % every == 0 || k == 1 || k == n) {
        double jump;
        r.t.push_back(sim.time());
        r.p_mad.push_back(pressure_mad(sim.fluid(), re, jump_exact, &jump));
        r.jump.push_back(jump);
      }
    }
  } catch (const std::exception& e) {
    r.stop = e.what();
  }
  r.seconds = seconds_since(t0);
  if (auto* l = dynamic_cast<const sphib::LagrangianFluid*>(&sim.fluid())) {
    r.s_low = l->lowest_kernel_sum();
    r.builds = l->verlet().builds();
    r.steps = l->steps();
  }
  return r;
}

std::string fig9_csv(const std::vector<Fig9Run>& rs) {
  std::ostringstream o;
  o << "nx,variant,t,pressure_mad_error,pressure_jump\n";
  for (const auto& r : rs)
    for (size_t k = 0; k < r.t.size(); ++k)
      o << r.nx << ",\"" << r.variant << "\"," << csv_num(r.t[k]) << ',' << csv_num(r.p_mad[k]) << ',' << csv_num(r.jump[k]) << '\n';
  return o.str();
}

// The value of a series at the sample closest to time T (NaN if it ended before).
double at(const Fig9Run& r, double T, const std::vector<double>& v) {
  if (r.t.empty() || r.t.back() < T - 1e-9) return NAN;
  size_t best = 0;
  for (size_t k = 0; k < r.t.size(); ++k)
    if (std::abs(r.t[k] - T) < std::abs(r.t[best] - T)) best = k;
  return v[best];
}

std::string fig9_md(const std::vector<Fig9Run>& rs, const Options& o) {
  std::ostringstream m;
  m << "## Fixed membrane in equilibrium: pressure error against time (Section 5.2.1, Fig. 9)\n\n"
    << "T0 = 3, mu = 0.25, Nb = 360, dt = 0.1 dx, 2h = 2.25 (dx + dy), h* = 0.5 h, fluid at rest at t = 0, "
       "membrane fixed at re = 0.6; exact [p] = 1, u = 0. Mean absolute pressure error (Eq. 80, the free "
       "constant chosen optimally), and the jump (mean p for r < 0.3 minus mean p for r > 0.9 off the walls) in "
       "brackets. LPSPH reinitialised every "
    << o.fig9_reinit << " steps (the paper does not give its interval).\n\n| t |";
  for (const auto& r : rs) m << " Nx = " << r.nx << " " << r.variant << " |";
  m << "\n|---|";
  for (size_t k = 0; k < rs.size(); ++k) m << "---:|";
  m << '\n';
  std::vector<double> times{0.0};
  for (int k = 1; k <= 10; ++k) times.push_back(o.fig9_end * k / 10.0);
  for (double T : times) {
    m << "| " << fix(T, 2) << " |";
    for (const auto& r : rs) {
      const double e = T == 0.0 ? (r.p_mad.empty() ? NAN : r.p_mad.front()) : at(r, T, r.p_mad);
      const double j = T == 0.0 ? (r.jump.empty() ? NAN : r.jump.front()) : at(r, T, r.jump);
      m << ' ' << fix(e, 4) << " (" << fix(j, 3) << ") |";
    }
    m << '\n';
  }
  m << "\n(t = 0 row: after the first step.)\n\n";
  for (const auto& r : rs) {
    m << "- Nx = " << r.nx << ", " << r.variant << ": " << fix(r.seconds, 1) << " s";
    if (std::isfinite(r.s_low))
      m << ", lowest kernel sum " << fix(r.s_low, 3) << ", Verlet list built " << r.builds << " times in " << r.steps
        << " steps";
    m << "; stopped: " << r.stop << "\n";
  }
  return m.str() + "\n";
}

// ---------------------------------------------------------------- Fig. 18

struct Fig18Sample {
  double t, s_min, rx, ry, rx_e, ry_e;  // LPSPH: lowest kernel sum now, half-axes; EPSPH half-axes
};

struct Fig18Run {
  std::string stop = "end time";
  double t_stop = NAN, seconds = 0, seconds_e = 0, s_low = NAN;
  long steps = 0, builds = 0;
  std::vector<Fig18Sample> samples;
};

// LPSPH and EPSPH side by side through the Simulation (the runner's path, without its output), so
// that the kernel sums can be sampled; the breakdown stops the LPSPH run with its diagnostic.
Fig18Run fig18_run(const Options& o) {
  Fig18Run r;
  const fs::path scene = cases_dir() / "membrane_oscillation_lagrangian.toml";
  sphib::Scene s = sphib::load_scene(scene.string(), {"time.end=" + num(o.fig18_end)});
  sphib::Scene se = sphib::load_scene(scene.string(), {"time.end=" + num(o.fig18_end), "method=eulerian"});
  sphib::Simulation sim(s.sim), sim_e(se.sim);
  const auto* l = dynamic_cast<const sphib::LagrangianFluid*>(&sim.fluid());
  sphib::MembraneDiagnostics D(sim.membranes()[0].m.nb(), sim.membranes()[0].m.L0());
  const long n = std::lround(s.t_end / s.sim.fluid.dt), every = 250;
  bool broken = false;
  const auto t_start = Clock::now();
  for (long k = 1; k <= n; ++k) {
    if (!broken) {
      const auto t0 = Clock::now();
      try {
        sim.step();
      } catch (const std::exception& e) {
        broken = true;
        r.stop = e.what();
      }
      r.seconds += seconds_since(t0);
    }
    const auto t0 = Clock::now();
    sim_e.step();
    r.seconds_e += seconds_since(t0);
    if (k % every == 0 || k == n) {
      const sphib::MembraneShape a = D.measure(sim.membranes()[0].m.X);
      const sphib::MembraneShape b = D.measure(sim_e.membranes()[0].m.X);
      r.samples.push_back({sim_e.time(), broken ? NAN : l->kernel_sums().minCoeff(), broken ? NAN : a.rx,
                           broken ? NAN : a.ry, b.rx, b.ry});
      if (k % (10 * every) == 0)
        std::printf("  t = %.3f  LPSPH: min kernel sum %.4f rx %.4f ry %.4f | EPSPH rx %.4f ry %.4f  (%.0f s)\n",
                    sim_e.time(), r.samples.back().s_min, r.samples.back().rx, r.samples.back().ry, b.rx, b.ry,
                    seconds_since(t_start));
      std::fflush(stdout);
    }
  }
  r.t_stop = sim.time();
  r.steps = sim.steps();
  r.s_low = l->lowest_kernel_sum();
  r.builds = l->verlet().builds();
  return r;
}

std::string fig18_csv(const Fig18Run& r) {
  std::ostringstream o;
  o << "t,lpsph_min_kernel_sum,lpsph_rx,lpsph_ry,epsph_rx,epsph_ry\n";
  for (const auto& x : r.samples)
    o << csv_num(x.t) << ',' << csv_num(x.s_min) << ',' << csv_num(x.rx) << ',' << csv_num(x.ry) << ',' << csv_num(x.rx_e) << ','
      << csv_num(x.ry_e) << '\n';
  return o.str();
}

std::string fig18_md(const Fig18Run& r, const Options& o) {
  std::ostringstream m;
  m << "## Oscillating membrane with LPSPH at 64 x 64 (Section 5.2.2, Fig. 18)\n\n"
    << "T0 = 10, mu = 0.1, Nb = 128, dt = 1e-4, 2h = 1.2 (dx + dy), h* = 1.4 h "
       "(cases/membrane_oscillation_lagrangian.toml), to t = "
    << o.fig18_end << "; breakdown threshold: a kernel sum below "
    << "0.5 (lagrangian.min_kernel_sum). The paper shows the particles driven away from the membrane at "
       "t = 0.200-0.285 and, later, complete breakdown.\n\n"
    << "| t | LPSPH min kernel sum | LPSPH rx | LPSPH ry | EPSPH rx | EPSPH ry |\n|---:|---:|---:|---:|---:|---:|\n";
  for (size_t k = 0; k < r.samples.size(); ++k) {
    const auto& x = r.samples[k];
    if (k % 2 && k + 1 != r.samples.size()) continue;  // every 0.05
    m << "| " << fix(x.t, 3) << " | " << fix(x.s_min, 4) << " | " << fix(x.rx, 4) << " | " << fix(x.ry, 4) << " | "
      << fix(x.rx_e, 4) << " | " << fix(x.ry_e, 4) << " |\n";
  }
  m << "\n- LPSPH stopped: " << r.stop << " (after " << r.steps << " steps, t = " << fix(r.t_stop, 4)
    << "); lowest kernel sum " << fix(r.s_low, 4) << "; Verlet list built " << r.builds << " times; "
    << fix(r.seconds, 1) << " s (EPSPH " << fix(r.seconds_e, 1)
    << " s, ratio " << fix(r.seconds / r.seconds_e, 1) << ")\n\n";
  return m.str();
}

int compare(const Options& o) {
  const fs::path dir = create_out_dir(o.out);
  std::string md_poiseuille, md_fig9, md_fig18;
  auto write_md = [&]() {
    sphib::write_file_atomic((dir / "lpsph_comparison.md").string(),
                 "# LPSPH against EPSPH (Noutcheuwa & Owens 2012, Sections 3.1, 5.1, 5.2)\n\n" + md_poiseuille +
                     md_fig9 + md_fig18);
  };

  if (o.wants("poiseuille")) {
    const std::string load0 = load_average();
    std::printf("== Start-up Poiseuille: %zu x %zu runs per method, %ld steps; %s, load average %s\n", o.nx.size(),
                o.h.size(), o.steps, cpu_model().c_str(), load0.c_str());
    std::vector<PoiseuillePair> rs;
    for (double h : o.h)
      for (int n : o.nx) {
        PoiseuillePair p{n, h, poiseuille_run("eulerian", n, h, o.steps), poiseuille_run("lagrangian", n, h, o.steps)};
        std::printf("Nx=%3d h/dx=%-5g EPSPH rms %.4e cpu %7.2f s | LPSPH rms %.4e cpu %8.2f s (CN %s %.2f it, Poisson %s "
                    "%.2f it, %ld list builds) | ratio %.1f (loop %.1f, 10k %.1f; paper %.2f)%s%s\n",
                    n, h, p.e.rms, p.e.total(), p.l.rms, p.l.total(), p.l.method_cn.c_str(), p.l.it_cn,
                    p.l.method_poisson.c_str(), p.l.it_poisson, p.l.builds, p.ratio(), p.ratio_loop(), p.ratio_10k(),
                    paper_ratio(n, h), p.e.status == "ok" ? "" : (" EPSPH: " + p.e.status).c_str(),
                    p.l.status == "ok" ? "" : (" LPSPH: " + p.l.status).c_str());
        std::fflush(stdout);
        rs.push_back(p);
        sphib::write_file_atomic((dir / "lpsph_poiseuille.csv").string(), poiseuille_csv(rs));
        md_poiseuille = poiseuille_md(rs, o) + "Machine: " + cpu_model() + "; load average (1, 5, 15 min) " + load0 +
                        " before, " + load_average() + " after.\n\n";
        write_md();
      }
    std::printf("\n%s", md_poiseuille.c_str());
  }

  if (o.wants("fig9")) {
    std::printf("== Fig. 9: fixed membrane in equilibrium, Nx in {");
    for (int n : o.fig9_nx) std::printf(" %d", n);
    std::printf(" }, t in [0, %g]\n", o.fig9_end);
    std::vector<Fig9Run> rs;
    for (int n : o.fig9_nx)
      for (auto [method, reinit] : {std::pair{"lagrangian", 0}, std::pair{"lagrangian", o.fig9_reinit}, std::pair{"eulerian", 0}}) {
        rs.push_back(fig9_run(n, method, reinit, o));
        const Fig9Run& r = rs.back();
        std::printf("Nx=%d %-16s %.1f s, error at t = %g: %.4f; stopped: %s\n", n, r.variant.c_str(), r.seconds,
                    r.t.empty() ? 0.0 : r.t.back(), r.p_mad.empty() ? NAN : r.p_mad.back(), r.stop.c_str());
        std::fflush(stdout);
        sphib::write_file_atomic((dir / "lpsph_fig9.csv").string(), fig9_csv(rs));
        md_fig9 = fig9_md(rs, o);
        write_md();
      }
    std::printf("\n%s", md_fig9.c_str());
  }

  if (o.wants("fig18")) {
    std::printf("== Fig. 18: oscillating membrane, LPSPH, 64 x 64, to t = %g\n", o.fig18_end);
    const Fig18Run r = fig18_run(o);
    sphib::write_file_atomic((dir / "lpsph_fig18.csv").string(), fig18_csv(r));
    md_fig18 = fig18_md(r, o);
    write_md();
    std::printf("\n%s", md_fig18.c_str());
  }
  std::printf("wrote %s\n", (dir / "lpsph_comparison.md").c_str());
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"LPSPH against EPSPH: Poiseuille (Tables 1-2), Figs. 9 and 18", "lpsph_comparison"};
  app.add_option("--parts", o.parts, "which comparisons")->delimiter(',')
      ->check(CLI::IsMember({"poiseuille", "fig9", "fig18"}))->capture_default_str();
  app.add_option("--nx", o.nx, "Poiseuille Nx = Ny")->delimiter(',')->check(CLI::Range(2, 1 << 16))->capture_default_str();
  app.add_option("--h", o.h, "Poiseuille h/dx")->delimiter(',')->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--steps", o.steps, "Poiseuille steps (10000: t = 0.0125)")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--fig9-nx", o.fig9_nx, "Fig. 9 resolutions")->delimiter(',')->check(CLI::Range(2, 1 << 16))->capture_default_str();
  app.add_option("--fig9-end", o.fig9_end, "Fig. 9 end time")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--fig9-reinit", o.fig9_reinit, "reinitialisation interval in steps")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--fig18-end", o.fig18_end, "Fig. 18 end time (LPSPH stops at its breakdown, README: LPSPH)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--out", o.out, "output directory")->capture_default_str();
  return run_main(app, argc, argv, [&] { return compare(o); });
}
