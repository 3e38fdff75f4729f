// Benchmark (not a test): EPSPH's time per step on every domain kind (issue 15), one core.
//
// Part R, the ratios at 64 x 64, in one process: five simulations are built, then stepped in turn,
// --block steps each, for --rounds rounds; each round gives every simulation's time per step and the
// ratios to its reference, and the medians over rounds are printed (pairing within a round cancels
// the machine's drift):
//   walled           cases/membrane_oscillation.toml as shipped (periodic x, walls in y; Nb 128): reference
//   doubly periodic  the same, domain.periodic_y = true
//   closed box       the same, domain.periodic_x = false
//   channel          cases/cavity_re100.toml with domain.periodic_x = true: the cavity's h, dt, viscosity,
//                    convection and moving lid, walls only in y (a shear-driven channel; observe.exact =
//                    none: the exact cavity observer needs a closed box): reference of
//   cavity           cases/cavity_re100.toml as shipped (walls on four sides, lid u = 1)
// The issue's targets: doubly periodic / walled <= 1.2, cavity / channel <= 1.5. Also per domain:
// the time per step of the three solves (Crank-Nicolson, the stream function of the exact projection,
// the markers' stream function), the method each system got, the coupling share (membrane force,
// spreading, marker update, over the steps' wall time), step / floor (the fluid's floor, as
// `sphib run` reports it; target on the walled job: <= 1.3, coupling <= 0.15), the coupling's own
// floor (Simulation::coupling_floor_seconds: its bare kernels timed alone) as a share of the fluid's
// and the coupling's floors together, and step / that whole floor.
//
// Part T, the transforms alone: FFTW's r2c + c2r FFT of 64 rows of 64 (the channel's x transform)
// against FFTW's own DCT-II + DCT-III and DST-II + DST-III (REDFT10/01, RODFT10/01) of the same rows,
// all FFTW_ESTIMATE, best of 20 repetitions of 200 calls: why fluid/algebra/fft_poisson.cpp computes the DCT
// and DST by the r2c FFT of reordered rows (RowDct) instead.
//
// Part N, scaling: the membrane job on each domain kind at Nx = Ny = --nx (Nb = 2 Nx), each in a fresh
// process (this program with --child): time per step (3 warm-up steps, then about --seconds of
// steps) and peak memory (VmHWM, and above the process's start); the exponents a of time per step and
// of memory ~ N^a by least squares over all sizes. Target: a ~ 1.0 on every domain kind.
//
//   domains [--parts RTN] [--rounds R] [--block B] [--nx LIST] [--seconds S] [--cases DIR] [--out DIR]
//
// Simulation::step only (no output, no run-time checks: the same for every domain). Wall times of a
// single-threaded process on a machine that may be shared: the load average is printed at the start
// and the end of each part; quote the ratios of part R, not its absolute times. Writes DIR/domains.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <fftw3.h>
#include <nlohmann/json.hpp>

#include "bench/common.hpp"
#include "coupling/simulation.hpp"
#include "io/atomic_file.hpp"
#include "io/scene.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using namespace sphib::bench;
using sphib::seconds_since;

struct Options {
  std::string parts = "RTN";
  int rounds = 15, block = 200;
  std::vector<int> nx{64, 128, 256, 512};
  double seconds = 1.5;
  fs::path cases = "cases";
  fs::path out = "bench_out/domains";
};

// A simulation of the benchmark: a name, its scene and --set overrides.
struct Setup {
  const char* name;
  const char* scene;
  std::vector<std::string> sets;
};
const Setup kMembrane[] = {{"walled", "membrane_oscillation.toml", {}},
                           {"doubly periodic", "membrane_oscillation.toml", {"domain.periodic_y=true"}},
                           {"closed box", "membrane_oscillation.toml", {"domain.periodic_x=false"}}};
const Setup kCavity[] = {{"channel (cavity scene, periodic x)", "cavity_re100.toml", {"domain.periodic_x=true", "observe.exact=none"}},
                         {"cavity", "cavity_re100.toml", {}}};

std::unique_ptr<sphib::Simulation> build(const Options& o, const Setup& s, const std::vector<std::string>& more = {}) {
  std::vector<std::string> sets = s.sets;
  sets.insert(sets.end(), more.begin(), more.end());
  const sphib::Scene sc = sphib::load_scene((o.cases / s.scene).string(), sets);
  return std::make_unique<sphib::Simulation>(sc.sim);
}

// Seconds in the phases of `P` whose names start with `prefix`, so far.
double phase_seconds(const sphib::Profile& P, const std::string& prefix) {
  double s = 0;
  for (size_t k = 0; k < P.names().size(); ++k)
    if (P.names()[k].rfind(prefix, 0) == 0) s += P.seconds(static_cast<int>(k));
  return s;
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The method of each system, from the fluid's run-log lines ("system: method, n = ..."), each name
// and method up to its first " (" or ":".
std::string methods(const sphib::FluidSolver& f) {
  std::string m;
  for (const std::string& line : f.profiler().report().lines) {
    size_t colon = std::string::npos, n = line.find(", n = ");
    int depth = 0;
    for (size_t k = 0; k + 1 < line.size() && colon == std::string::npos; ++k) {  // the first ": " outside (...)
      if (line[k] == '(') ++depth;
      if (line[k] == ')') --depth;
      if (depth == 0 && line[k] == ':' && line[k + 1] == ' ') colon = k;
    }
    if (colon == std::string::npos || n == std::string::npos || n < colon) continue;
    const std::string system = line.substr(0, colon), method = line.substr(colon + 2, n - colon - 2);
    m += (m.empty() ? "" : "; ") + system.substr(0, system.find(" (")) + ": " +
         method.substr(0, std::min(method.find(" ("), method.find(":")));
  }
  return m;
}

// ---- Part R ------------------------------------------------------------------------------------
std::string part_r(const Options& o) {
  std::vector<Setup> setups(std::begin(kMembrane), std::end(kMembrane));
  setups.insert(setups.end(), std::begin(kCavity), std::end(kCavity));
  const double load0 = load_average();
  std::printf("R: %d rounds of %d steps per simulation, 64 x 64, load average %.2f\n", o.rounds, o.block, load0);
  std::vector<std::unique_ptr<sphib::Simulation>> sims;
  for (const Setup& s : setups) {
    sims.push_back(build(o, s));
    for (int k = 0; k < 20; ++k) sims.back()->step();  // warm-up: first AB2 step, first solves
  }
  const size_t n = sims.size();
  std::vector<std::vector<double>> per(n), cpu(n);  // wall and CPU time per step, per round
  std::vector<double> solve_cn(n), solve_psi(n), psi_m(n), coupling(n), wall(n, 0.0);
  for (size_t s = 0; s < n; ++s) {
    coupling[s] = -sims[s]->profile().total();  // the membranes and their coupling (Simulation's phases)
    const sphib::Profile& P = sims[s]->fluid().profiler();
    solve_cn[s] = -phase_seconds(P, "solve Crank");
    solve_psi[s] = -phase_seconds(P, "solve Poisson");
    psi_m[s] = -phase_seconds(P, "stream function");
  }
  for (int r = 0; r < o.rounds; ++r)
    for (size_t s = 0; s < n; ++s) {
      const auto t0 = Clock::now();
      const double c0 = cpu_seconds();
      for (int k = 0; k < o.block; ++k) sims[s]->step();
      wall[s] += seconds_since(t0);
      per[s].push_back(seconds_since(t0) / o.block);
      cpu[s].push_back((cpu_seconds() - c0) / o.block);
    }
  const double steps = static_cast<double>(o.rounds) * o.block;
  for (size_t s = 0; s < n; ++s) {
    const sphib::Profile& P = sims[s]->fluid().profiler();
    solve_cn[s] = (solve_cn[s] + phase_seconds(P, "solve Crank")) / steps;
    solve_psi[s] = (solve_psi[s] + phase_seconds(P, "solve Poisson")) / steps;
    psi_m[s] = (psi_m[s] + phase_seconds(P, "stream function")) / steps;
    coupling[s] = (coupling[s] + sims[s]->profile().total()) / wall[s];
  }
  std::vector<double> floor(n), cfloor(n);  // the fluid step's and the coupling's floors: bare kernels, best of 20 each
  for (size_t s = 0; s < n; ++s) {
    floor[s] = sims[s]->fluid().profiler().floor_seconds();
    cfloor[s] = sims[s]->coupling_floor_seconds();
  }
  const double load1 = load_average();
  std::ostringstream m;
  m << "## R: time per step at 64 x 64, paired\n\n" << o.rounds << " rounds of " << o.block
    << " steps per simulation, one process, one thread; load average " << fix(load0, 2) << " at the start, "
    << fix(load1, 2) << " at the end (" << cpu_model() << ").\n\n"
    << "| simulation | ms/step (median) | ratio to its reference (median, min–max over rounds) | CPU ms/step | CPU ratio | "
       "CN solve µs/step | stream-function solve µs/step | markers' ψ_m µs/step | coupling share | step / floor | "
       "coupling floor µs/step | its share of the whole floor | step / whole floor | methods |\n"
    << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  auto ratio = [&](const std::vector<std::vector<double>>& t, size_t a, size_t b) {
    std::vector<double> q;
    for (int r = 0; r < o.rounds; ++r) q.push_back(t[a][r] / t[b][r]);
    return fix(median(q), 3) + " (" + fix(*std::min_element(q.begin(), q.end()), 2) + "–" +
           fix(*std::max_element(q.begin(), q.end()), 2) + ")";
  };
  for (size_t s = 0; s < n; ++s) {
    const size_t ref = s < 3 ? 0 : 3;
    m << "| " << setups[s].name << " | " << fix(1e3 * median(per[s]), 3) << " | "
      << (s == ref ? "reference" : ratio(per, s, ref)) << " | " << fix(1e3 * median(cpu[s]), 3) << " | "
      << (s == ref ? "reference" : ratio(cpu, s, ref)) << " | " << fix(1e6 * solve_cn[s], 1) << " | "
      << fix(1e6 * solve_psi[s], 1) << " | " << fix(1e6 * psi_m[s], 1) << " | "
      << (sims[s]->membranes().empty() ? std::string("–") : fix(coupling[s], 3)) << " | " << fix(median(per[s]) / floor[s], 2)
      << " | " << fix(1e6 * cfloor[s], 1) << " | " << fix(cfloor[s] / (floor[s] + cfloor[s]), 3) << " | "
      << fix(median(per[s]) / (floor[s] + cfloor[s]), 2) << " | " << md_text(methods(sims[s]->fluid())) << " |\n";
  }
  m << "\nCoupling share: the membranes' force, spreading and marker update (ψ_m included) over the wall time of the "
       "steps. Step / floor: the median wall time per step over the fluid step's floor (its bare solves and "
       "products timed alone, best of 20: `floor_seconds_per_step` of `sphib run`). Coupling floor: the "
       "membranes' force, one spreading, the markers' ψ_m solve and one marker interpolation with its gradient, "
       "each timed alone, best of 20 (`coupling_floor_seconds_per_step`); its share of the fluid's and its own "
       "floors together is the least coupling share a step at its floor could have; step / whole floor: the "
       "median time per step over both floors. Targets (issue 15): doubly periodic / walled ≤ 1.2; cavity / "
       "channel ≤ 1.5; on the main job (walled) step / floor ≤ 1.3 and coupling ≤ 0.15.\n\n";
  std::printf("%s", m.str().c_str());
  return m.str();
}

// ---- Part T ------------------------------------------------------------------------------------
std::string part_t() {
  const int n = 64, rows = 64, N = n * rows, nk = n / 2 + 1;
  double* in = fftw_alloc_real(N);
  double* out = fftw_alloc_real(N);
  double* hat = fftw_alloc_real(2 * nk * rows);
  auto* c = reinterpret_cast<fftw_complex*>(hat);
  const int dims[1] = {n};
  const unsigned inv = FFTW_ESTIMATE | FFTW_DESTROY_INPUT;
  auto r2r = [&](fftw_r2r_kind k, double* i, double* o, unsigned f) {
    return fftw_plan_many_r2r(1, dims, rows, i, nullptr, 1, n, o, nullptr, 1, n, &k, f);
  };
  // forward and inverse of the three kinds, timed in turn (200 calls each) 20 times; best of each
  const fftw_plan plans[3][2] = {
      {fftw_plan_many_dft_r2c(1, dims, rows, in, nullptr, 1, n, c, nullptr, 1, nk, FFTW_ESTIMATE),
       fftw_plan_many_dft_c2r(1, dims, rows, c, nullptr, 1, nk, out, nullptr, 1, n, inv)},
      {r2r(FFTW_REDFT10, in, hat, FFTW_ESTIMATE), r2r(FFTW_REDFT01, hat, out, inv)},
      {r2r(FFTW_RODFT10, in, hat, FFTW_ESTIMATE), r2r(FFTW_RODFT01, hat, out, inv)}};
  double best[3] = {1e300, 1e300, 1e300};
  for (int rep = 0; rep < 20; ++rep)
    for (int t = 0; t < 3; ++t) {
      const auto t0 = Clock::now();
      for (int k = 0; k < 200; ++k) {
        for (int i = 0; i < N; ++i) in[i] = 1.0 / (1 + i);
        if (t == 0) {
          fftw_execute_dft_r2c(plans[t][0], in, c);
          fftw_execute_dft_c2r(plans[t][1], c, out);
        } else {
          fftw_execute_r2r(plans[t][0], in, hat);
          fftw_execute_r2r(plans[t][1], hat, out);
        }
      }
      best[t] = std::min(best[t], 1e6 * seconds_since(t0) / 200);
    }
  for (auto& p : plans)
    for (fftw_plan q : p) fftw_destroy_plan(q);
  fftw_free(in);
  fftw_free(out);
  fftw_free(hat);
  std::ostringstream m;
  m << "## T: FFTW's transforms of 64 rows of 64, forward and inverse (FFTW_ESTIMATE; 20 rounds of 200 calls "
       "of each in turn, best round)\n\n"
    << "| transform | µs (with the input's refill) | ratio to r2c + c2r |\n|---|---:|---:|\n"
    << "| r2c + c2r FFT | " << fix(best[0], 2) << " | 1 |\n"
    << "| REDFT10 + REDFT01 (DCT-II, DCT-III) | " << fix(best[1], 2) << " | " << fix(best[1] / best[0], 2) << " |\n"
    << "| RODFT10 + RODFT01 (DST-II, DST-III) | " << fix(best[2], 2) << " | " << fix(best[2] / best[0], 2) << " |\n\n"
    << "(load average " << fix(load_average(), 2) << ")\n\n";
  std::printf("%s", m.str().c_str());
  return m.str();
}

// ---- Part N ------------------------------------------------------------------------------------
// The child: one domain kind at one size; its JSON line on stdout.
int child(const Options& o, int kind, int nx, long steps) {
  json j;
  j["kind"] = kind;
  j["nx"] = nx;
  j["rss_start_kb"] = status_kb("VmRSS");
  try {
    auto sim = build(o, kMembrane[kind], {"grid.nx=" + std::to_string(nx), "grid.ny=" + std::to_string(nx),
                                          "membrane.nb=" + std::to_string(2 * nx)});
    for (int k = 0; k < 3; ++k) sim->step();
    const auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    for (long k = 0; k < steps; ++k) sim->step();
    j["per_step_s"] = seconds_since(t0) / steps;
    j["cpu_per_step_s"] = (cpu_seconds() - c0) / steps;
    j["steps"] = steps;
    j["methods"] = methods(sim->fluid());
  } catch (const std::exception& e) {
    j["error"] = e.what();
  }
  j["vmhwm_kb"] = status_kb("VmHWM");
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

std::string part_n(const Options& o) {
  const double load0 = load_average();
  std::printf("N: the membrane job on each domain kind, Nx = Ny, Nb = 2 Nx, a process per run; load average %.2f\n", load0);
  std::ostringstream m;
  m << "## N: scaling with N = Nx²\n\n| domain | Nx | steps | ms/step | CPU ms/step | µs/step/particle | peak MB | "
       "peak − start MB |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  std::ostringstream fits;
  for (int kind = 0; kind < 3; ++kind) {
    std::vector<std::pair<double, double>> t, tc, mem;
    double per = 3e-4;  // a guess for 64 x 64, then the last size's time scaled by N^1.1
    int last = 64;
    for (int nx : o.nx) {
      per *= std::pow(static_cast<double>(nx) / last, 2.2);
      last = nx;
      const long steps = std::clamp(std::lround(o.seconds / per), 5L, 5000L);
      const ChildRun r = run_self({"/proc/self/exe", "--child", std::to_string(kind), std::to_string(nx),
                                   std::to_string(steps), "--cases", o.cases.string()});
      const std::string line = last_json_line(r.out);
      const json j = line.empty() ? json() : json::parse(line, nullptr, false);
      if (j.is_discarded() || j.is_null() || j.contains("error")) {
        const std::string e = j.is_object() && j.contains("error") ? j["error"].get<std::string>() : "child failed";
        std::printf("  %-16s Nx %4d FAILED: %s\n", kMembrane[kind].name, nx, e.c_str());
        m << "| " << kMembrane[kind].name << " | " << nx << " | failed: " << md_text(e) << " | | | | | |\n";
        continue;
      }
      per = j["per_step_s"].get<double>();
      const double N = static_cast<double>(nx) * nx, peak = j["vmhwm_kb"].get<double>() / 1024.0,
                   above = peak - j["rss_start_kb"].get<double>() / 1024.0;
      const double cpu = j["cpu_per_step_s"].get<double>();
      t.emplace_back(N, per);
      tc.emplace_back(N, cpu);
      mem.emplace_back(N, above);
      std::printf("  %-16s Nx %4d %9.3f ms/step (%ld steps)  peak %8.1f MB  %s\n", kMembrane[kind].name, nx, 1e3 * per,
                  j["steps"].get<long>(), peak, j["methods"].get<std::string>().c_str());
      std::fflush(stdout);
      m << "| " << kMembrane[kind].name << " | " << nx << " | " << j["steps"].get<long>() << " | " << fix(1e3 * per, 3)
        << " | " << fix(1e3 * cpu, 3) << " | " << fix(1e6 * per / N, 3) << " | " << fix(peak, 1) << " | " << fix(above, 1) << " |\n";
    }
    fits << "| " << kMembrane[kind].name << " | " << fix(power_law_exponent(t), 2) << " | " << fix(power_law_exponent(tc), 2) << " | "
         << fix(power_law_exponent(mem), 2) << " |\n";
  }
  m << "\nExponents a in y ~ N^a (least squares over Nx = ";
  for (size_t k = 0; k < o.nx.size(); ++k) m << (k ? ", " : "") << o.nx[k];
  m << "; load average " << fix(load0, 2) << " at the start, " << fix(load_average(), 2) << " at the end):\n\n"
    << "| domain | time per step | CPU time per step | peak memory above the start |\n|---|---:|---:|---:|\n" << fits.str() << "\n";
  std::printf("%s", m.str().c_str());
  return m.str();
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Time per step on every domain kind: paired ratios at 64 x 64 (R), the x transforms alone (T), scaling with N (N)",
               "domains"};
  add_parts(app, o.parts, "RTN", "R ratios at 64 x 64, T transforms alone, N scaling with N");
  app.add_option("--rounds", o.rounds, "rounds of part R")->check(CLI::Range(1, 10000))->capture_default_str();
  app.add_option("--block", o.block, "steps per simulation and round (R)")->check(CLI::Range(1, 1000000))->capture_default_str();
  app.add_option("--nx", o.nx, "sizes for N")->delimiter(',')->check(CLI::Range(16, 1 << 14))->capture_default_str();
  app.add_option("--seconds", o.seconds, "loop time to aim for per run (N)")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--cases", o.cases, "scene directory")->capture_default_str();
  app.add_option("--out", o.out, "output directory")->capture_default_str();
  std::vector<std::string> child_args;  // one child of part N: kind nx steps
  app.add_option("--child", child_args)->expected(3)->group("");
  if (argc > 1 && std::string(argv[1]) == "--child") {  // a child: no re-execution, its JSON line on stdout
    CLI11_PARSE(app, argc, argv);
    return child(o, std::stoi(child_args[0]), std::stoi(child_args[1]), std::stol(child_args[2]));
  }
  return run_main(app, argc, argv, [&] {
    const auto t0 = Clock::now();
    std::string md = "# EPSPH on every domain kind (issue 15)\n\nGenerated by `bench/domains`.\n\n";
    if (wants(o.parts, 'R')) md += part_r(o);
    if (wants(o.parts, 'T')) md += part_t();
    if (wants(o.parts, 'N')) md += part_n(o);
    create_out_dir(o.out.string());
    sphib::write_file_atomic((o.out / "domains.md").string(), md);
    std::printf("total %.0f s wall; wrote %s\n", seconds_since(t0), (o.out / "domains.md").c_str());
    return 0;
  });
}
