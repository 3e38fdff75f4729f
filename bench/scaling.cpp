// Benchmark (not a test): how EPSPH's cost grows with the number of particles N (issue 6).
//
// Two cases, Nx = Ny from 32 to 512 (N = 1 024 to 262 144), one core:
//   poiseuille  cases/poiseuille.toml (h = 1.525 dx, Stokes, dt = 1.25e-6, mu = 80: the
//               Crank-Nicolson system is far from the identity, CHOLMOD under `auto`);
//   membrane    cases/membrane_oscillation.toml (h = 1.2 dx, convection on, dt = 1e-4,
//               Nb = 2 Nx markers: 1.9 per grid spacing as the 64 x 64 case; Crank-Nicolson by
//               warm-started Jacobi-PCG under `auto`).
// Every (case, Nx, solvers) runs in a fresh process (this program re-executed with --child), so
// that its peak memory is its own: VmHWM of /proc/self/status at the end, and ru_maxrss from
// wait4() in the parent. The child builds the Simulation (timed: neighbour search, assembly,
// analysis + factorisation from the fluid profiler's setup_seconds and solver_info()), takes 3 warm-up steps,
// then enough steps for about --seconds of loop (at least 5), and reports the time per step and per
// phase (Profile, warm-up subtracted).
//
// Part S compares, on the same matrices (the same scene and size, so the same operators), CHOLMOD
// supernodal against simplicial for both systems, Jacobi-PCG for Crank-Nicolson
// (solver.crank_nicolson = "pcg", Poisson by CHOLMOD simplicial), the FFT-in-x + banded-Cholesky
// solver of fluid/algebra/fft_poisson.hpp for both (`fft`, what `auto` picks on these channels), and Eigen's
// own SimplicialLDLT (AMD ordering) on both matrices rebuilt from the fluid's operators as
// fluid/eulerian/exact_projection.cpp builds them:
// factorisation time, factor size, memory and the time per solve (CHOLMOD and PCG: in the running
// step; Eigen: repeated solves of the same systems outside the step).
//
//   scaling [--parts NS] [--nx LIST] [--compare-nx LIST] [--cases poiseuille,membrane]
//           [--variants LIST] [--seconds S] [--out DIR] [--keep | --report-only]      (--help)
//
// --keep reads DIR/scaling.csv and DIR/solvers.csv back and runs only the rows they lack;
// --report-only reads them back and rewrites them and DIR/scaling.md without running anything.
//
// Fits time ~ N^a by least squares of log(time) against log N over the sizes from 64^2 up (the
// smallest sizes are dominated by fixed overheads). Writes DIR/scaling.csv, DIR/solvers.csv,
// DIR/scaling.md atomically after every child. Times are wall seconds of a single-threaded child
// on a 2-core machine shared with other jobs (CPU seconds of the loop are reported beside them).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <Eigen/SparseCholesky>

#include "bench/common.hpp"
#include "coupling/simulation.hpp"
#include "fluid/eulerian/eulerian.hpp"
#include "io/scene.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using namespace sphib::bench;
using sphib::seconds_since;

double jnum(const json& j, const char* k) { return j.contains(k) && j[k].is_number() ? j[k].get<double>() : NAN; }

std::vector<std::string> scene_sets(const std::string& c, int nx, const std::string& cn, const std::string& poisson) {
  // eigen_ldlt is this bench's, not a scene value: the simulation is built with `auto`
  std::vector<std::string> s{"grid.nx=" + std::to_string(nx), "grid.ny=" + std::to_string(nx),
                             "solver.crank_nicolson=" + (cn == "eigen_ldlt" ? std::string("auto") : cn),
                             "solver.poisson=" + (poisson == "eigen_ldlt" ? std::string("auto") : poisson)};
  if (c == "membrane") s.push_back("membrane.nb=" + std::to_string(2 * nx));
  return s;
}
std::string scene_file(const std::string& c) {
  return c == "poiseuille" ? "poiseuille.toml" : "membrane_oscillation.toml";
}

// Eigen's SimplicialLDLT (AMD ordering) on A: analysis, factorisation, the factor's size and the RSS it
// adds, then the time per solve of A X = B with k right-hand sides (repeated for about 0.3 s).
json eigen_ldlt(const std::string& system, const sphib::SpMat& A_rows, int k) {
  using ColMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  using LDLT = Eigen::SimplicialLDLT<ColMat, Eigen::Lower, Eigen::AMDOrdering<int>>;
  const ColMat A = A_rows;  // symmetric: the same matrix, column-major as Eigen's Cholesky wants it
  json x;
  x["system"] = system;
  x["method"] = "Eigen SimplicialLDLT (AMD)";
  x["n"] = A.rows();
  x["nnz_A"] = A.nonZeros();
  x["nnz_used"] = A.nonZeros();
  const long rss0 = status_kb("VmRSS");
  LDLT ldlt;
  auto t0 = Clock::now();
  ldlt.analyzePattern(A);
  x["analyse_s"] = seconds_since(t0);
  t0 = Clock::now();
  ldlt.factorize(A);
  x["factor_s"] = seconds_since(t0);
  if (ldlt.info() != Eigen::Success) throw std::runtime_error("Eigen SimplicialLDLT failed on " + system);
  // L is stored without its unit diagonal; CHOLMOD's nnz(L) counts the diagonal
  x["nnz_factor"] = static_cast<long>(ldlt.matrixL().nestedExpression().nonZeros()) + A.rows();
  x["factor_rss_kb"] = status_kb("VmRSS") - rss0;
  Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), k), X(A.rows(), k);
  X = ldlt.solve(B);  // first solve (allocations) not timed
  long reps = 0;
  t0 = Clock::now();
  do {
    X = ldlt.solve(B);
    ++reps;
  } while (seconds_since(t0) < 0.3 || reps < 5);
  x["solve_s"] = seconds_since(t0) / reps;
  x["solve_reps"] = reps;
  x["residual"] = (A * X - B).norm() / B.norm();
  return x;
}

// ---- the child: one case, one size, one pair of solvers; a JSON line on stdout ------------------
int child(const fs::path& cases, const std::string& c, int nx, const std::string& cn, const std::string& poisson,
          long steps) {
  json j;
  j["case"] = c;
  j["nx"] = nx;
  j["cn"] = cn;
  j["poisson"] = poisson;
  j["rss_start_kb"] = status_kb("VmRSS");
  try {
    const sphib::Scene s = sphib::load_scene((cases / scene_file(c)).string(), scene_sets(c, nx, cn, poisson));
    auto t0 = Clock::now();
    sphib::Simulation sim(s.sim);
    j["setup_s"] = seconds_since(t0);
    j["rss_after_setup_kb"] = status_kb("VmRSS");
    const auto* f = dynamic_cast<const sphib::EulerianFluid*>(&sim.fluid());
    if (!f) throw std::runtime_error("not an EPSPH fluid");
    j["n"] = f->size();
    j["images"] = f->images().size();
    j["pairs_per_particle"] = static_cast<double>(f->pairs().size()) / f->size();
    j["h_over_dx"] = f->params().h_over_dx;
    j["dt"] = f->params().dt;
    for (const char* k : {"neighbours", "assembly", "factorisation"}) j[std::string("setup_") + k + "_s"] = f->profiler().setup_seconds(k);
    if (cn == "eigen_ldlt") {
      // The two matrices as fluid/eulerian/exact_projection.cpp builds them: A_cn = I - (nu dt / 2) lap_u (Eq. 28);
      // Poisson -lap_phi with the gauge row and column of particle 0 replaced by the identity (Eq. 32).
      const sphib::Operators& op = f->operators();
      const int N = f->size();
      sphib::SpMat I(N, N);
      I.setIdentity();
      const sphib::SpMat A_cn = I - (0.5 * f->params().mu / f->params().rho * f->params().dt) * op.lap_u.A;
      sphib::SpMat A_p = -op.lap_phi;
      const int pin = 0;
      for (int c = 0; c < A_p.outerSize(); ++c)
        for (sphib::SpMat::InnerIterator it(A_p, c); it; ++it)
          if (it.row() == pin || it.col() == pin) it.valueRef() = (it.row() == it.col()) ? 1.0 : 0.0;
      A_p.prune(0.0);
      bool match = true;  // the same non-zero counts as the matrices the fluid factorised
      for (const auto& si : f->solver_info())
        match = match && si.nnz_A == (si.system == "Poisson" ? A_p.nonZeros() : A_cn.nonZeros());
      j["matrices_match"] = match;
      j["solvers"].push_back(eigen_ldlt("Crank-Nicolson", A_cn, 2));
      j["solvers"].push_back(eigen_ldlt("Poisson", A_p, 1));
      j["phases"]["solve Crank-Nicolson"] = j["solvers"][0]["solve_s"];
      j["phases"]["solve Poisson"] = j["solvers"][1]["solve_s"];
      j["factor_rss_kb"] = j["solvers"][0]["factor_rss_kb"].get<double>() + j["solvers"][1]["factor_rss_kb"].get<double>();
      j["residual_cn"] = j["solvers"][0]["residual"];
      j["residual_poisson"] = j["solvers"][1]["residual"];
      j["vmhwm_kb"] = status_kb("VmHWM");
      std::printf("%s\n", j.dump().c_str());
      std::fflush(stdout);
      return 0;
    }
    for (const auto& si : f->solver_info()) {
      json x;
      x["system"] = si.system;
      x["method"] = si.method;
      x["n"] = si.n;
      x["nnz_A"] = si.nnz_A;
      x["nnz_used"] = si.nnz_used;
      x["nnz_factor"] = si.nnz_factor;
      x["analyse_s"] = si.analyse_seconds;
      x["factor_s"] = si.factor_seconds;
      j["solvers"].push_back(x);
    }
    auto profile = [&]() {
      std::map<std::string, double> p;
      const sphib::Profile* profiles[] = {&sim.fluid().profiler(), &sim.profile()};
      for (const sphib::Profile* P : profiles)
        for (size_t k = 0; k < P->names().size(); ++k) p[P->names()[k]] += P->seconds(static_cast<int>(k));
      return p;
    };
    for (int k = 0; k < 3; ++k) sim.step();  // warm-up: the first AB2 step, first solves
    const auto p0 = profile();
    const double c0 = cpu_seconds();
    t0 = Clock::now();
    for (long k = 0; k < steps; ++k) sim.step();
    const double loop = seconds_since(t0);
    j["steps"] = steps;
    j["loop_s"] = loop;
    j["loop_cpu_s"] = cpu_seconds() - c0;
    j["per_step_s"] = loop / steps;
    for (const auto& [name, sec] : profile()) j["phases"][name] = (sec - (p0.count(name) ? p0.at(name) : 0.0)) / steps;
    j["cn_mean_iterations"] = f->cn_mean_iterations();
    j["ok"] = std::isfinite(f->kinetic_energy());
  } catch (const std::exception& e) {
    j["error"] = e.what();
  }
  j["vmhwm_kb"] = status_kb("VmHWM");
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
  return 0;
}

// ---- the parent -----------------------------------------------------------------------------------
struct Options {
  std::string parts = "NS";
  std::vector<int> nx{32, 64, 128, 256, 512};
  std::vector<int> compare_nx{32, 64, 128, 256};
  std::vector<std::string> cases{"poiseuille", "membrane"};
  std::vector<std::string> variants{"cholmod_supernodal", "cholmod_simplicial", "pcg", "eigen_ldlt", "fft"};
  bool keep = false, report_only = false;
  double seconds = 3.0;
  fs::path out = "bench_out/scaling";
  fs::path cases_dir = "cases";
};

// Runs one child; returns its JSON with the parent's wall time and wait4's ru_maxrss added.
json spawn(const Options& o, const std::string& c, int nx, const std::string& cn, const std::string& poisson, long steps) {
  const ChildRun r = run_self({"/proc/self/exe", "--child", c, std::to_string(nx), cn, poisson, std::to_string(steps),
                               "--cases-dir", o.cases_dir.string()});
  json j;
  const std::string last = last_json_line(r.out);  // the child's last line is its JSON
  if (!last.empty()) j = json::parse(last, nullptr, false);
  if (j.is_discarded() || j.is_null()) {
    j = json::object();
    j["case"] = c;
    j["nx"] = nx;
    j["cn"] = cn;
    j["poisson"] = poisson;
    j["error"] = "child failed (status " + std::to_string(r.status) + ")";
  }
  j["child_wall_s"] = r.wall_s;
  j["ru_maxrss_kb"] = r.maxrss_kb;
  return j;
}

struct Bench {
  Options o;
  std::vector<json> scale, compare;

  static double phase_sum(const json& j, const std::string& prefix) {
    double s = 0;
    if (j.contains("phases"))
      for (auto it = j["phases"].begin(); it != j["phases"].end(); ++it)
        if (it.key().rfind(prefix, 0) == 0) s += it.value().get<double>();
    return s;
  }
  static const json* solver(const json& j, const std::string& system) {
    if (j.contains("solvers"))
      for (const auto& s : j["solvers"])
        if (s["system"] == system) return &s;
    return nullptr;
  }
  static double sv(const json& j, const std::string& system, const char* key) {
    const json* s = solver(j, system);
    return s && s->contains(key) ? (*s)[key].get<double>() : NAN;
  }

  long steps_for(const std::string& c, int nx) const {
    // a guess from the last measured size of this case: time per step ~ N^1.1
    double per = 1e-3 * std::pow(nx / 64.0, 2.2) * (c == "membrane" ? 1.0 : 1.2);
    for (const json& j : scale)
      if (j["case"] == c && j.contains("per_step_s"))
        per = j["per_step_s"].get<double>() * std::pow(static_cast<double>(nx) / j["nx"].get<int>(), 2.2);
    return std::clamp(std::lround(o.seconds / per), 5L, 3000L);
  }

  void print(const json& j) {
    std::printf("  %-10s Nx %4d  cn %-18s poisson %-18s", j.value("case", "").c_str(), j.value("nx", 0),
                j.value("cn", "").c_str(), j.value("poisson", "").c_str());
    if (j.contains("error")) {
      std::printf(" FAILED: %s\n", j["error"].get<std::string>().c_str());
    } else {
      std::printf(" set-up %7.3f s (nb %.3f asm %.3f fact %.3f)  %9.3f ms/step (%ld steps)  peak %7.1f MB\n",
                  jnum(j, "setup_s"), jnum(j, "setup_neighbours_s"), jnum(j, "setup_assembly_s"),
                  jnum(j, "setup_factorisation_s"), 1e3 * jnum(j, "per_step_s"), j.value("steps", 0L),
                  jnum(j, "vmhwm_kb") / 1024.0);
    }
    std::fflush(stdout);
  }

  static bool has(const std::vector<json>& v, const std::string& c, int nx, const std::string& cn) {
    for (const json& j : v)
      if (j.value("case", "") == c && j.value("nx", 0) == nx && j.value("cn", "") == cn && !j.contains("error")) return true;
    return false;
  }

  void part_n() {
    std::printf("N: time per step, set-up and peak memory against N (solvers auto)\n");
    for (const std::string& c : o.cases)
      for (int nx : o.nx) {
        if (o.keep && has(scale, c, nx, "auto")) continue;
        json j = spawn(o, c, nx, "auto", "auto", steps_for(c, nx));
        print(j);
        put(scale, j);
        write();
      }
  }

  void part_s() {
    std::printf("S: CHOLMOD supernodal vs simplicial, Jacobi-PCG for Crank-Nicolson, the FFT solver and Eigen's SimplicialLDLT, "
                "on the same matrices\n");
    for (const std::string& c : o.cases)
      for (int nx : o.compare_nx)
        for (const std::string& cn : o.variants) {
          // pcg: Crank-Nicolson only; its Poisson system by CHOLMOD as before the FFT solver existed
          const std::string p = cn == "pcg" ? "cholmod_simplicial" : cn;
          if (o.keep && has(compare, c, nx, cn)) continue;
          json j = spawn(o, c, nx, cn, p, std::max(5L, steps_for(c, nx) / 2));
          print(j);
          put(compare, j);
          write();
        }
  }

  // part S's rows in a stable order: case, Nx, variant (rows added by --keep come last otherwise)
  std::vector<json> sorted_compare() const {
    static const std::vector<std::string> order{"cholmod_supernodal", "cholmod_simplicial", "pcg", "eigen_ldlt", "fft"};
    auto rank = [&](const json& j) {
      const auto c = std::find(o.cases.begin(), o.cases.end(), j.value("case", ""));
      const auto v = std::find(order.begin(), order.end(), j.value("cn", ""));
      return std::make_tuple(c - o.cases.begin(), j.value("nx", 0), v - order.begin());
    };
    std::vector<json> v = compare;
    std::stable_sort(v.begin(), v.end(), [&](const json& a, const json& b) { return rank(a) < rank(b); });
    return v;
  }

  // --keep, --report-only: the rows of DIR/scaling.csv and DIR/solvers.csv back as the children's JSON
  // (the fields the tables use).
  static std::vector<json> load_csv(const fs::path& f) {
    std::vector<json> out;
    for (sphib::bench::CsvRow& r : sphib::bench::read_csv_rows(f.string())) {
      auto d = [&](const std::string& k) { return r[k].empty() ? NAN : std::strtod(r[k].c_str(), nullptr); };
      json j;
      j["case"] = r["case"];
      j["nx"] = std::atoi(r["nx"].c_str());
      j["cn"] = r["cn"];
      j["poisson"] = r["poisson"];
      if (!r["error"].empty()) {
        j["error"] = r["error"];
        out.push_back(j);
        continue;
      }
      for (const char* k : {"n", "steps", "pairs_per_particle", "setup_s", "setup_neighbours_s", "setup_assembly_s",
                            "setup_factorisation_s", "per_step_s", "loop_s", "loop_cpu_s", "cn_mean_iterations",
                            "rss_start_kb", "rss_after_setup_kb", "vmhwm_kb", "ru_maxrss_kb", "child_wall_s",
                            "factor_rss_kb", "residual_cn", "residual_poisson"})
        if (std::isfinite(d(k))) j[k] = d(k);
      if (!r["matrices_match"].empty()) j["matrices_match"] = r["matrices_match"] == "1";
      j["phases"]["solve Crank-Nicolson"] = d("cn_solve_per_step_s");
      j["phases"]["solve Poisson"] = d("poisson_solve_per_step_s");
      if (std::isfinite(d("membrane_per_step_s"))) j["phases"]["membrane (all)"] = d("membrane_per_step_s");
      for (const auto& [sys, pre] : {std::pair<std::string, std::string>{"Crank-Nicolson", "cn_"}, {"Poisson", "poisson_"}}) {
        if (r[pre + "method"].empty()) continue;
        json x;
        x["system"] = sys;
        x["method"] = r[pre + "method"];
        for (const char* k : {"nnz_A", "nnz_factor", "analyse_s", "factor_s"})
          if (std::isfinite(d(pre + k))) x[k] = d(pre + k);
        j["solvers"].push_back(x);
      }
      out.push_back(j);
    }
    return out;
  }
  void load() {
    scale = load_csv(o.out / "scaling.csv");
    compare = load_csv(o.out / "solvers.csv");
    std::printf("read %zu rows of scaling.csv and %zu of solvers.csv from %s\n", scale.size(), compare.size(),
                o.out.c_str());
  }
  // a new row replaces a failed one of the same case, size and variant
  static void put(std::vector<json>& v, const json& j) {
    for (json& x : v)
      if (x.value("case", "") == j.value("case", "") && x.value("nx", 0) == j.value("nx", 0) &&
          x.value("cn", "") == j.value("cn", "")) {
        x = j;
        return;
      }
    v.push_back(j);
  }

  std::string markdown() const {
    std::ostringstream m;
    m << "# Scaling of EPSPH with the number of particles (issue 6)\n\nGenerated by `bench/scaling`. One core "
         "(single-threaded CHOLMOD/BLAS), a fresh process per row; wall times on a 2-core machine shared with "
         "other jobs (expect ±20-50%; the loop's CPU time is in the CSV). Peak memory = VmHWM of the child "
         "(the process before building anything: " << (scale.empty() ? std::string("–") : fix(jnum(scale[0], "rss_start_kb") / 1024.0, 1))
      << " MB). `auto` picks the FFT-in-x solver (fluid/algebra/fft_poisson.hpp) on these channels; where CHOLMOD is "
         "picked instead, its factorisation time includes a discarded simplicial factorisation (`factorize`, "
         "fluid/algebra/linear_solver.cpp, factorises simplicial to learn nnz(L) and, above 8e5, again supernodal); part S "
         "below times each kind alone. The FFT solver's nnz(L) is its banded factors' storage.\n\n";
    for (const std::string& c : o.cases) m << size_md(c);
    if (!compare.empty()) m << solvers_md();
    return m.str();
  }

  // Part N of one case: a row per size, then the exponents.
  std::string size_md(const std::string& c) const {
    std::ostringstream m;
    std::vector<const json*> rs;
    for (const json& j : scale)
      if (j["case"] == c && !j.contains("error")) rs.push_back(&j);
    if (rs.empty()) return "";
    m << "## " << c << " (" << (c == "poiseuille" ? "cases/poiseuille.toml, h = 1.525 dx, Stokes" : "cases/membrane_oscillation.toml, h = 1.2 dx, Nb = 2 Nx")
      << "), solvers auto\n\n"
      << "| Nx | N | pairs/particle | steps | ms/step | µs/step/particle | solves ms/step | membrane ms/step | "
         "neighbours s | assembly s | factorisation s | CN: method, nnz(L) | Poisson: method, nnz(L) | peak MB | "
         "peak − start MB | ru_maxrss MB |\n"
      << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---:|---:|---:|\n";
    for (const json* j : rs) {
      const double N = jnum(*j, "n"), per = jnum(*j, "per_step_s");
      const double memb = phase_sum(*j, "membrane") + phase_sum(*j, "spread") + phase_sum(*j, "interpolat") +
                          phase_sum(*j, "marker");
      auto meth = [&](const std::string& sys) {
        const json* s = solver(*j, sys);
        if (!s) return std::string();
        std::string mth = (*s)["method"].get<std::string>();
        mth = mth.substr(0, mth.find(" ("));
        return mth + ", " + ((*s)["nnz_factor"].get<long>() > 0 ? sci((*s)["nnz_factor"].get<double>()) : "–");
      };
      m << "| " << (*j)["nx"].get<int>() << " | " << static_cast<long>(N) << " | " << fix(jnum(*j, "pairs_per_particle"), 1)
        << " | " << (*j)["steps"].get<long>() << " | " << fix(1e3 * per, 3) << " | " << fix(1e6 * per / N, 3) << " | "
        << fix(1e3 * phase_sum(*j, "solve"), 3) << " | " << fix(1e3 * memb, 3) << " | "
        << fix(jnum(*j, "setup_neighbours_s"), 3) << " | " << fix(jnum(*j, "setup_assembly_s"), 3) << " | "
        << fix(jnum(*j, "setup_factorisation_s"), 3) << " | " << meth("Crank-Nicolson") << " | " << meth("Poisson")
        << " | " << fix(jnum(*j, "vmhwm_kb") / 1024, 1) << " | "
        << fix((jnum(*j, "vmhwm_kb") - jnum(*j, "rss_start_kb")) / 1024, 1) << " | "
        << fix(jnum(*j, "ru_maxrss_kb") / 1024, 1) << " |\n";
    }
    // exponents over Nx >= 64
    auto fit = [&](const std::function<double(const json&)>& y) {
      std::vector<std::pair<double, double>> pts;
      for (const json* j : rs)
        if ((*j)["nx"].get<int>() >= 64) pts.emplace_back(jnum(*j, "n"), y(*j));
      return power_law_exponent(pts);
    };
    m << "\nObserved exponents a in y ~ N^a (least squares over Nx ≥ 64):\n\n"
      << "- time per step: **" << fix(fit([](const json& j) { return jnum(j, "per_step_s"); }), 2) << "**"
      << "; solves: " << fix(fit([](const json& j) { return phase_sum(j, "solve"); }), 2)
      << "; everything but the solves: "
      << fix(fit([](const json& j) { return jnum(j, "per_step_s") - phase_sum(j, "solve"); }), 2) << "\n"
      << "- set-up: neighbours " << fix(fit([](const json& j) { return jnum(j, "setup_neighbours_s"); }), 2)
      << ", assembly " << fix(fit([](const json& j) { return jnum(j, "setup_assembly_s"); }), 2)
      << ", analysis + factorisation " << fix(fit([](const json& j) { return jnum(j, "setup_factorisation_s"); }), 2)
      << ", total " << fix(fit([](const json& j) { return jnum(j, "setup_s"); }), 2) << "\n"
      << "- factor non-zeros: Crank-Nicolson "
      << fix(fit([](const json& j) { return sv(j, "Crank-Nicolson", "nnz_factor"); }), 2) << ", Poisson "
      << fix(fit([](const json& j) { return sv(j, "Poisson", "nnz_factor"); }), 2) << "\n"
      << "- peak memory above the start: "
      << fix(fit([](const json& j) { return jnum(j, "vmhwm_kb") - jnum(j, "rss_start_kb"); }), 2) << "\n\n";
    return m.str();
  }

  // Part S: the solvers on the same matrices, then their exponents.
  std::string solvers_md() const {
    std::ostringstream m;
    const std::vector<json> cmp = sorted_compare();
    m << "## Linear solvers on the same matrices\n\n"
         "Per solve = one call per step (Crank-Nicolson: both velocity components at once; Poisson: one). "
         "`pcg` = warm-started Jacobi-PCG for Crank-Nicolson with Poisson by CHOLMOD simplicial. `fft` = the "
         "FFT-in-x + banded-Cholesky solver for both. `eigen_ldlt` = Eigen's SimplicialLDLT with AMD "
         "ordering on the two matrices rebuilt from the fluid's operators as fluid/eulerian/exact_projection.cpp builds them "
         "(the same non-zero counts: checked, `matrices_match` in the CSV); its time per solve is from repeated "
         "solves of the same systems outside the step (the others' from the running step), its nnz(L) counts "
         "L's unit diagonal as CHOLMOD's counts the diagonal, and its memory is the RSS the two factors add "
         "(its process also holds the `auto` solvers of the simulation it takes the operators from), so it "
         "has no ms/step or peak.\n\n"
         "| case | Nx | variant | CN method | CN analyse+factor s | CN nnz(L) | CN ms/solve | PCG iterations | "
         "Poisson method | Poisson analyse+factor s | Poisson nnz(L) | Poisson ms/solve | ms/step | peak MB |\n"
         "|---|---:|---|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|\n";
    for (const json& j : cmp) {
      m << "| " << j["case"].get<std::string>() << " | " << j["nx"].get<int>() << " | " << j["cn"].get<std::string>()
        << " | ";
      if (j.contains("error")) {
        m << "failed: " << j["error"].get<std::string>().substr(0, 80) << " | | | | | | | | | | |\n";
        continue;
      }
      auto meth = [&](const std::string& sys) {
        const json* s = solver(j, sys);
        if (!s) return std::string();
        const std::string mth = (*s)["method"].get<std::string>();
        return mth.substr(0, mth.find(" ("));
      };
      auto nnz = [&](const std::string& sys) {
        const double v = sv(j, sys, "nnz_factor");
        return v > 0 ? sci(v) : std::string("–");
      };
      m << meth("Crank-Nicolson") << " | "
        << fix(sv(j, "Crank-Nicolson", "analyse_s") + sv(j, "Crank-Nicolson", "factor_s"), 3) << " | "
        << nnz("Crank-Nicolson") << " | " << fix(1e3 * phase_sum(j, "solve Crank"), 3) << " | "
        << (j["cn"] == "pcg" ? fix(jnum(j, "cn_mean_iterations"), 1) : std::string("–")) << " | " << meth("Poisson")
        << " | " << fix(sv(j, "Poisson", "analyse_s") + sv(j, "Poisson", "factor_s"), 3) << " | " << nnz("Poisson")
        << " | " << fix(1e3 * phase_sum(j, "solve Poisson"), 3) << " | " << fix(1e3 * jnum(j, "per_step_s"), 3)
        << " | "
        << (j["cn"] == "eigen_ldlt" ? "+" + fix(jnum(j, "factor_rss_kb") / 1024, 1) + " (factors)"
                                    : fix(jnum(j, "vmhwm_kb") / 1024, 1))
        << " |\n";
    }
    m << "\nObserved exponents a in time ~ N^a per variant (least squares over Nx ≥ 64):\n\n"
         "| case | variant | CN per solve | Poisson per solve | CN analyse+factor | Poisson analyse+factor | "
         "nnz(L) Poisson | peak memory |\n|---|---|---:|---:|---:|---:|---:|---:|\n";
    for (const std::string& c : o.cases)
      for (const std::string v : {"cholmod_supernodal", "cholmod_simplicial", "pcg", "eigen_ldlt", "fft"}) {
        std::vector<const json*> rs;
        for (const json& j : cmp)
          if (j["case"] == c && j["cn"] == v && !j.contains("error") && j["nx"].get<int>() >= 64) rs.push_back(&j);
        if (rs.size() < 2) continue;
        auto fit = [&](const std::function<double(const json&)>& y) {
          std::vector<std::pair<double, double>> pts;
          for (const json* j : rs) pts.emplace_back(jnum(*j, "n"), y(*j));
          return fix(power_law_exponent(pts), 2);
        };
        m << "| " << c << " | " << v << " | " << fit([](const json& j) { return phase_sum(j, "solve Crank"); })
          << " | " << fit([](const json& j) { return phase_sum(j, "solve Poisson"); }) << " | "
          << fit([](const json& j) { return sv(j, "Crank-Nicolson", "analyse_s") + sv(j, "Crank-Nicolson", "factor_s"); })
          << " | " << fit([](const json& j) { return sv(j, "Poisson", "analyse_s") + sv(j, "Poisson", "factor_s"); })
          << " | " << fit([](const json& j) { return sv(j, "Poisson", "nnz_factor"); }) << " | "
          << (v == "eigen_ldlt" ? fit([](const json& j) { return jnum(j, "factor_rss_kb"); }) + " (factors)"
                                : fit([](const json& j) { return jnum(j, "vmhwm_kb") - jnum(j, "rss_start_kb"); }))
          << " |\n";
      }
    m << "\n";
    return m.str();
  }

  void write() const {
    std::ostringstream c;
    c << "case,nx,n,cn,poisson,steps,pairs_per_particle,setup_s,setup_neighbours_s,setup_assembly_s,"
         "setup_factorisation_s,per_step_s,loop_s,loop_cpu_s,solves_per_step_s,cn_solve_per_step_s,"
         "poisson_solve_per_step_s,membrane_per_step_s,cn_method,cn_nnz_A,cn_nnz_factor,cn_analyse_s,cn_factor_s,"
         "poisson_method,poisson_nnz_A,poisson_nnz_factor,poisson_analyse_s,poisson_factor_s,cn_mean_iterations,"
         "rss_start_kb,rss_after_setup_kb,vmhwm_kb,ru_maxrss_kb,child_wall_s,factor_rss_kb,residual_cn,"
         "residual_poisson,matrices_match,error\n";
    auto row = [&](std::ostringstream& o, const json& j) {
      auto method = [&](const std::string& sys) {
        const json* s = solver(j, sys);
        std::string mth = s ? (*s)["method"].get<std::string>() : "";
        for (char& ch : mth)
          if (ch == ',') ch = ';';
        return mth;
      };
      const double memb = phase_sum(j, "membrane") + phase_sum(j, "spread") + phase_sum(j, "interpolat") +
                          phase_sum(j, "marker");
      o << j.value("case", "") << ',' << j.value("nx", 0) << ',' << csv_num(jnum(j, "n")) << ',' << j.value("cn", "")
        << ',' << j.value("poisson", "") << ',' << csv_num(jnum(j, "steps")) << ','
        << csv_num(jnum(j, "pairs_per_particle")) << ',' << csv_num(jnum(j, "setup_s")) << ','
        << csv_num(jnum(j, "setup_neighbours_s")) << ',' << csv_num(jnum(j, "setup_assembly_s")) << ','
        << csv_num(jnum(j, "setup_factorisation_s")) << ',' << csv_num(jnum(j, "per_step_s")) << ','
        << csv_num(jnum(j, "loop_s")) << ',' << csv_num(jnum(j, "loop_cpu_s")) << ','
        << csv_num(phase_sum(j, "solve")) << ',' << csv_num(phase_sum(j, "solve Crank")) << ','
        << csv_num(phase_sum(j, "solve Poisson")) << ',' << csv_num(memb) << ',' << method("Crank-Nicolson") << ','
        << csv_num(sv(j, "Crank-Nicolson", "nnz_A")) << ',' << csv_num(sv(j, "Crank-Nicolson", "nnz_factor")) << ','
        << csv_num(sv(j, "Crank-Nicolson", "analyse_s")) << ',' << csv_num(sv(j, "Crank-Nicolson", "factor_s")) << ','
        << method("Poisson") << ',' << csv_num(sv(j, "Poisson", "nnz_A")) << ','
        << csv_num(sv(j, "Poisson", "nnz_factor")) << ',' << csv_num(sv(j, "Poisson", "analyse_s")) << ','
        << csv_num(sv(j, "Poisson", "factor_s")) << ',' << csv_num(jnum(j, "cn_mean_iterations")) << ','
        << csv_num(jnum(j, "rss_start_kb")) << ',' << csv_num(jnum(j, "rss_after_setup_kb")) << ','
        << csv_num(jnum(j, "vmhwm_kb")) << ',' << csv_num(jnum(j, "ru_maxrss_kb")) << ','
        << csv_num(jnum(j, "child_wall_s")) << ',' << csv_num(jnum(j, "factor_rss_kb")) << ','
        << csv_num(jnum(j, "residual_cn")) << ',' << csv_num(jnum(j, "residual_poisson")) << ','
        << (j.contains("matrices_match") ? (j["matrices_match"].get<bool>() ? "1" : "0") : "") << ',';
      std::string e = j.value("error", "");
      for (char& ch : e)
        if (ch == ',' || ch == '\n') ch = ';';
      o << e << '\n';
    };
    std::ostringstream s = std::ostringstream(c.str(), std::ios::ate);
    for (const json& j : scale) row(c, j);
    for (const json& j : sorted_compare()) row(s, j);
    sphib::write_file_atomic((o.out / "scaling.csv").string(), c.str());
    sphib::write_file_atomic((o.out / "solvers.csv").string(), s.str());
    sphib::write_file_atomic((o.out / "scaling.md").string(), markdown());
  }
};

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Scaling of EPSPH with N: time per step, set-up and memory (N); linear solvers on the same matrices (S)",
               "scaling"};
  add_parts(app, o.parts, "NS", "N time per step / set-up / memory against N, S solver comparison");
  app.add_option("--nx", o.nx, "sizes for N")->delimiter(',')->check(CLI::Range(2, 1 << 16))->capture_default_str();
  app.add_option("--compare-nx", o.compare_nx, "sizes for S")->delimiter(',')->check(CLI::Range(2, 1 << 16))->capture_default_str();
  app.add_option("--cases", o.cases, "cases")->delimiter(',')->check(CLI::IsMember({"poiseuille", "membrane"}))->capture_default_str();
  app.add_option("--variants", o.variants, "solvers for S")->delimiter(',')
      ->check(CLI::IsMember({"cholmod_supernodal", "cholmod_simplicial", "pcg", "eigen_ldlt", "fft"}))->capture_default_str();
  app.add_option("--seconds", o.seconds, "loop time to aim for per run")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--out", o.out, "output directory")->capture_default_str();
  app.add_option("--cases-dir", o.cases_dir, "scene directory")->capture_default_str();
  auto* keep = app.add_flag("--keep", o.keep, "read DIR's CSV files back and run only the rows they lack (or that failed)");
  app.add_flag("--report-only", o.report_only, "read DIR's CSV files back, rewrite them and scaling.md; run nothing")->excludes(keep);
  std::vector<std::string> child_args;  // the parent's call of one child: case nx cn poisson steps
  app.add_option("--child", child_args)->expected(5)->group("");
  if (argc > 1 && std::string(argv[1]) == "--child") {  // a child: no re-execution, its JSON line on stdout
    CLI11_PARSE(app, argc, argv);
    return child(o.cases_dir, child_args[0], std::stoi(child_args[1]), child_args[2], child_args[3], std::stol(child_args[4]));
  }
  return run_main(app, argc, argv, [&] {
    create_out_dir(o.out.string());
    Bench b{o, {}, {}};
    const auto t0 = Clock::now();
    if (o.keep || o.report_only) b.load();
    if (o.report_only) {
      b.write();
      std::printf("rewrote %s/scaling.csv, solvers.csv, scaling.md\n", o.out.c_str());
      return 0;
    }
    if (wants(o.parts, 'N')) b.part_n();
    if (wants(o.parts, 'S')) b.part_s();
    b.write();
    std::printf("\n%s\ntotal %.0f s wall; wrote %s/scaling.csv, solvers.csv, scaling.md\n", b.markdown().c_str(),
                seconds_since(t0), o.out.c_str());
    return 0;
  });
}
