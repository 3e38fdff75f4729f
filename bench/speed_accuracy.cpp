// Benchmark (not a test): the speed-accuracy trade of EPSPH (issue 6), error against cost over the
// numerical parameters, with the Pareto front marked.
//
//  P  start-up Poiseuille (cases/poiseuille.toml, Section 5.1: Re = 0.0125, t = 0.0125): rms error
//     of Eq. (69) against the exact series over Nx x h/dx x dt (a full grid; Stokes, as the case);
//  L  the same flow with LPSPH (method = "lagrangian", moving particles) over a smaller grid; its
//     runs join P's study, so the Pareto front is over both methods;
//  W  the Poiseuille flow of Vukcevic et al. (cases/wcsph_poiseuille.toml, SI units, to t = 1 s):
//     WCSPH (method = "wcsph") and EPSPH on the same scene, rms error / u_max over Ny and dt;
//  A  the oscillating membrane of Section 5.2.2 (cases/membrane_oscillation.toml: 64 x 64,
//     Nb = 128, h = 1.2 dx, h* = 1.4 h, dt = 1e-4, T0 = 10, mu = 0.1), to t = 2;
//  B  the same membrane with the Fig. 19 settings (T0 = 1, mu = 0.05, Nb = 360, dt = 0.1 dx,
//     h* = 0.0425 fixed), to t = 2.
//  For A and B: the enclosed-area error at t = 2 (summary `area_relative_error_at.2`) and the error
//  of rx(t) on [0, 2] against a fine reference run of the same physics (Nx = 128, dt = 2.5e-5;
//  Nb = 256 for A, 512 for B): m0_rx of each run's diagnostics.csv at its own sample times
//  against the reference's m0_rx (sampled every 0.005) interpolated linearly in t; max and rms.
//  Variations are one at a time around the default (Nx, Nb, h/dx, h*/h, dt) plus a few combined.
//
//   speed_accuracy [--parts PLWAB] [--out DIR] [--cases DIR] [--quick] [--reuse | --report-only]  (--help)
//
// Cost is the process CPU time of the run (set-up + loop + output; getrusage), which on this
// shared 2-core machine is steadier than wall time; both are written. Runs go to
// DIR/runs/<tag>/ (the HDF5 files are deleted after reading, except for the references). The two
// reference runs are reused when DIR/runs/ref_X/overrides.txt holds the same overrides and the
// run finished; --reuse reuses every such run (their times are then from when they ran);
// --report-only runs nothing: it rebuilds the CSV and the Markdown from the run directories
// (a run without one is listed as not run).
// Writes DIR/speed_accuracy.csv (one row per run) and DIR/speed_accuracy.md (tables, the Pareto
// fronts, "choosing a resolution"), each atomically after every run. Plots: scripts/plot_bench.py.
// Single-threaded.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/common.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"

namespace fs = std::filesystem;

namespace {

using namespace sphib::bench;
using sphib::seconds_since;

// ---- one run ----------------------------------------------------------------------------------

struct Run {
  std::string study;   // poiseuille | vukcevic | membrane_A | membrane_B
  std::string group;   // grid | lagrangian | base | reference | Nx | Nb | h/dx | h*/h | dt | combined | Nx, dt = 0.1 dx
  std::string label;   // what was varied, for the tables
  std::string tag;     // run directory name
  std::string scene;   // case file
  std::vector<std::string> sets;
  std::string method = "eulerian";
  int nx = 0, ny = 0, nb = 0;
  double dx = NAN, hdx = NAN, h = NAN, h_star = NAN, markers_per_dx = NAN, dt = NAN, t_end = NAN;
  long steps = 0;
  std::string status = "ok";
  bool reused = false;
  double wall = NAN, cpu = NAN, per_step = NAN;
  double rms = NAN;                           // P, W
  double area1 = NAN, area2 = NAN;            // A, B: relative area error at t = 1, 2
  double rx_max = NAN, rx_rms = NAN, rx_final = NAN;
  int rx_glitches = 0;  // diagnostics rows with rx <= 0 or NaN, left out (see read_rx)
  bool ok() const { return status == "ok"; }
};

struct Series {
  std::vector<double> t, rx;
  double at(double x) const {  // linear interpolation, clamped
    if (t.empty()) return NAN;
    if (x <= t.front()) return rx.front();
    if (x >= t.back()) return rx.back();
    const size_t k = std::upper_bound(t.begin(), t.end(), x) - t.begin();
    const double w = (x - t[k - 1]) / (t[k] - t[k - 1]);
    return (1 - w) * rx[k - 1] + w * rx[k];
  }
};

Series read_rx(const fs::path& csv) {
  std::ifstream in(csv);
  Series s;
  std::string line;
  if (!std::getline(in, line)) return s;
  std::vector<std::string> cols;
  {
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cols.push_back(c);
  }
  const long it = std::find(cols.begin(), cols.end(), "t") - cols.begin();
  const long irx = std::find(cols.begin(), cols.end(), "m0_rx") - cols.begin();
  if (it >= static_cast<long>(cols.size()) || irx >= static_cast<long>(cols.size())) return s;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string c;
    std::vector<double> v;
    while (std::getline(ss, c, ',')) v.push_back(c.empty() ? NAN : std::strtod(c.c_str(), nullptr));
    if (static_cast<long>(v.size()) <= std::max(it, irx)) continue;
    if (!s.t.empty() && v[it] <= s.t.back()) continue;
    s.t.push_back(v[it]);
    s.rx.push_back(v[irx]);
    // MembraneDiagnostics::half_axes can miss the crossings on one side when the line through the
    // centroid passes through a marker at the tip (rx = 0 for one row): such rows are kept here
    // and skipped (and counted) where they are compared.
  }
  return s;
}

struct Options {
  std::string parts = "PLWAB";
  fs::path out = "bench_out/speed_accuracy";
  fs::path cases = "cases";
  bool quick = false, reuse = false, report_only = false;
};

class Bench {
 public:
  explicit Bench(Options o) : o_(std::move(o)) { fs::create_directories(o_.out / "runs"); }

  // Loads the scene with the overrides and runs it into DIR/runs/<tag>; fills the common fields.
  nlohmann::json execute(Run& r, bool always_reuse = false) {
    const fs::path dir = o_.out / "runs" / r.tag;
    std::string joined;
    for (const auto& s : r.sets) joined += s + "\n";
    sphib::Scene s;
    try {
      s = sphib::load_scene((o_.cases / r.scene).string(), r.sets);
    } catch (const std::exception& e) {
      r.status = std::string("refused: ") + e.what();
      return nlohmann::json();
    }
    const auto& f = s.sim.fluid;
    r.method = to_string(s.method);
    r.nx = f.nx;
    r.ny = f.ny;
    r.hdx = f.h_over_dx;
    r.dt = f.dt;
    r.dx = f.domain.Lx() / (f.domain.periodic_x ? f.nx : f.nx - 1);
    const double dy = f.domain.Ly() / (f.domain.periodic_y ? f.ny : f.ny - 1);
    r.h = f.h_over_dx * 0.5 * (r.dx + dy);
    if (!s.membranes.empty()) {
      const auto& m = s.membranes[0];
      r.nb = m.nb;
      r.h_star = m.h_star > 0 ? m.h_star : m.h_star_over_h * r.h;
      r.markers_per_dx = r.dx / (2.0 * M_PI * m.r0 / m.nb);
    }
    nlohmann::json j;
    const bool may_reuse = always_reuse || o_.reuse || o_.report_only;
    if (may_reuse && fs::exists(dir / "summary.json") && fs::exists(dir / "overrides.txt")) {
      std::ifstream a(dir / "overrides.txt");
      std::stringstream b;
      b << a.rdbuf();
      std::ifstream js(dir / "summary.json");
      nlohmann::json old = nlohmann::json::parse(js, nullptr, false);
      const bool finished = !old.is_discarded() && old.value("stop_reason", "") == "end time";
      if (b.str() == joined && !old.is_discarded() && o_.report_only && !finished)
        r.status = "stopped: " + old.value("stop_reason", std::string("?"));  // a failed run, as it was recorded
      if (b.str() == joined && (finished || (o_.report_only && !old.is_discarded()))) {
        j = old;
        r.reused = true;
        r.wall = j.value("wall_seconds", NAN);
        r.cpu = NAN;
        if (fs::exists(dir / "bench_timing.json")) {
          std::ifstream tj(dir / "bench_timing.json");
          const nlohmann::json t = nlohmann::json::parse(tj, nullptr, false);
          if (!t.is_discarded()) {
            r.cpu = t.value("cpu_seconds", NAN);
            r.wall = t.value("wall_seconds", r.wall);
          }
        }
      }
    }
    if (!r.reused && o_.report_only) {
      if (r.ok()) r.status = "not run (--report-only: no finished run directory)";
      return nlohmann::json();
    }
    if (!r.reused) {
      fs::remove_all(dir);
      sphib::RunOptions ro;
      ro.out_dir = dir.string();
      const double c0 = cpu_seconds();
      const auto t0 = Clock::now();
      try {
        j = sphib::run_scene(s, ro);
      } catch (const std::exception& e) {
        r.status = e.what();
        if (r.status.size() > 160) r.status = r.status.substr(0, 160);
      }
      r.cpu = cpu_seconds() - c0;
      r.wall = seconds_since(t0);
      if (fs::exists(dir)) {
        sphib::write_file_atomic((dir / "overrides.txt").string(), joined);
        nlohmann::json t{{"cpu_seconds", r.cpu}, {"wall_seconds", r.wall}};
        sphib::write_file_atomic((dir / "bench_timing.json").string(), t.dump(1) + "\n");
      }
    }
    if (!j.is_null()) {
      r.steps = j.value("steps", 0L);
      r.t_end = j.value("time", NAN);
      r.per_step = j.value("seconds_per_step", NAN);
    }
    return j;
  }

  void drop_h5(const Run& r) {
    if (r.group == "reference") return;
    std::error_code ec;
    for (const char* f : {"output.h5", "output.xdmf", "checkpoint.h5"}) fs::remove(o_.out / "runs" / r.tag / f, ec);
  }

  void add(const Run& r) {
    runs_.push_back(r);
    std::printf("  %-10s %-14s %-28s cpu %8.2f s wall %8.2f s", r.study.c_str(), r.group.c_str(), r.label.c_str(),
                r.cpu, r.wall);
    if (!r.ok()) std::printf("  %s", r.status.substr(0, 90).c_str());
    if (std::isfinite(r.rms)) std::printf("  rms %.3e", r.rms);
    if (std::isfinite(r.area2)) std::printf("  area(t=2) %+.3e", r.area2);
    if (std::isfinite(r.rx_max)) std::printf("  rx max %.3e rms %.3e", r.rx_max, r.rx_rms);
    if (r.reused) std::printf("  (reused)");
    std::printf("\n");
    std::fflush(stdout);
    write();
  }

  // ---- P, L: start-up Poiseuille over Nx x h/dx x dt, EPSPH (P) and LPSPH (L) in one study ----
  void part_p() {
    std::printf("P: start-up Poiseuille (cases/poiseuille.toml), rms error at t = 0.0125\n");
    if (o_.quick) return poiseuille_grid("P", "eulerian", {16, 32}, {1.525, 3}, {1.25e-5, 1.25e-4});
    poiseuille_grid("P", "eulerian", {16, 24, 32, 48, 64}, {1.2, 1.525, 2.2, 3},
                    {1.25e-6, 6.25e-6, 3.125e-5, 1.5625e-4, 1.25e-3});
  }
  void part_l() {
    std::printf("L: start-up Poiseuille with LPSPH (method = lagrangian), rms error at t = 0.0125\n");
    if (o_.quick) return poiseuille_grid("L", "lagrangian", {16}, {1.525}, {1.5625e-4});
    poiseuille_grid("L", "lagrangian", {16, 24, 32, 48}, {1.525, 2.2}, {3.125e-5, 1.5625e-4, 1.25e-3});
  }
  void poiseuille_grid(const std::string& part, const std::string& method, const std::vector<int>& nxs,
                       const std::vector<double>& hs, const std::vector<double>& dts) {
    const bool lagrangian = method == "lagrangian";
    for (double dt : dts)
      for (double h : hs)
        for (int nx : nxs) {
          Run r;
          r.study = "poiseuille";
          r.group = lagrangian ? "lagrangian" : "grid";
          r.scene = "poiseuille.toml";
          r.label = std::string(lagrangian ? "LPSPH " : "") + "Nx " + std::to_string(nx) + " h/dx " + num(h) + " dt " + num(dt);
          r.tag = part + "_nx" + std::to_string(nx) + "_h" + num(h) + "_dt" + num(dt);
          r.sets = {"grid.nx=" + std::to_string(nx), "grid.ny=" + std::to_string(nx), "kernel.h_over_dx=" + num(h),
                    "time.dt=" + num(dt), "output.interval=0"};
          if (lagrangian) r.sets.insert(r.sets.begin(), "method=lagrangian");
          const nlohmann::json j = execute(r);
          if (!j.is_null() && r.ok()) r.rms = j.value("rms_error", NAN);
          drop_h5(r);
          add(r);
        }
  }

  // ---- W: Vukcevic Poiseuille, WCSPH and EPSPH ----
  void part_w() {
    std::printf("W: Poiseuille of Vukcevic et al. (cases/wcsph_poiseuille.toml, t = 1 s), WCSPH and EPSPH\n");
    const double l = 1e-3, nu = 1e-6, U = 2.5e-5;
    const std::vector<int> nys = o_.quick ? std::vector<int>{21} : std::vector<int>{21, 31, 41, 61};
    for (const char* method : {"wcsph", "eulerian"})
      for (int ny : nys) {
        const int nx = (ny + 1) / 2;
        const double h = 2.2 * l / ny;
        const double limit = 0.125 * h * h / nu;  // Coelho Eq. (19), viscous (the binding one here)
        const std::vector<double> dts = std::string(method) == "wcsph" ? std::vector<double>{0.9 * limit, 0.3 * limit}
                                                                       : std::vector<double>{2e-2, 2e-3};
        for (double dt : dts) {
          Run r;
          r.study = "vukcevic";
          r.group = method;
          r.scene = "wcsph_poiseuille.toml";
          r.label = std::string(method) + " " + std::to_string(nx) + "x" + std::to_string(ny) + " dt " + num(dt, 3);
          r.tag = std::string("W_") + method + "_ny" + std::to_string(ny) + "_dt" + num(dt, 3);
          r.sets = {"method=" + std::string(method), "grid.nx=" + std::to_string(nx), "grid.ny=" + std::to_string(ny),
                    "domain.x=[0.0, " + num(nx * l / ny, 17) + "]", "time.dt=" + num(dt, 6), "output.interval=0"};
          const nlohmann::json j = execute(r);
          if (!j.is_null() && r.ok()) r.rms = j.value("rms_error", NAN) / U;
          drop_h5(r);
          add(r);
        }
      }
  }

  // ---- A, B: the oscillating membrane ----
  struct Variation {
    std::string group, label;
    std::vector<std::string> sets;
  };

  // The membrane study A or B: a reference run, then every variation against it.
  void membrane(const std::string& name) {
    const bool A = name == "A";
    std::printf("%s: oscillating membrane, %s, to t = 2\n", name.c_str(),
                A ? "the 64 x 64 case of Section 5.2.2 (T0 = 10, mu = 0.1, Nb = 128, dt = 1e-4, h* = 1.4 h)"
                  : "Fig. 19 settings (T0 = 1, mu = 0.05, Nb = 360, dt = 0.1 dx, h* = 0.0425)");
    const std::vector<std::string> physics =
        A ? std::vector<std::string>{} : std::vector<std::string>{"membrane.T0=1", "fluid.mu=0.05"};
    const Series reference = membrane_reference(name, physics);
    const std::map<std::string, std::string> def = membrane_defaults(name == "A");
    int k = 0;
    for (const Variation& v : membrane_variations(name == "A")) {
      Run r;
      r.study = "membrane_" + name;
      r.group = v.group;
      r.label = v.label;
      r.scene = "membrane_oscillation.toml";
      std::map<std::string, std::string> kv = def;
      for (const auto& s : v.sets) kv[s.substr(0, s.find('='))] = s.substr(s.find('=') + 1);
      const double dt = std::strtod(kv["time.dt"].c_str(), nullptr);
      r.sets = physics;
      for (const auto& [key, val] : kv) r.sets.push_back(key + "=" + val);
      r.sets.push_back("time.end=2");
      r.sets.push_back("output.interval=0");
      r.sets.push_back("output.diagnostics_every=" + std::to_string(std::max(1L, std::lround(0.01 / dt))));
      std::ostringstream tag;
      tag << name << "_" << std::setw(2) << std::setfill('0') << k++;
      r.tag = tag.str();
      const nlohmann::json j = execute(r);
      if (!j.is_null() && r.ok()) {
        if (j.contains("area_relative_error_at")) {
          r.area1 = j["area_relative_error_at"].value("1", NAN);
          r.area2 = j["area_relative_error_at"].value("2", NAN);
        }
        r.rx_final = j.value("rx", NAN);
        if (!reference.t.empty()) compare_rx(r, reference);
      }
      drop_h5(r);
      add(r);
    }
  }

  // rx(t) of run r against the reference's, interpolated linearly in t: max and rms deviation.
  void compare_rx(Run& r, const Series& reference) const {
    const Series s = read_rx(o_.out / "runs" / r.tag / "diagnostics.csv");
    double mx = 0, sq = 0;
    int n = 0;
    for (size_t i = 0; i < s.t.size(); ++i) {
      if (s.t[i] > reference.t.back() + 1e-9) break;
      if (!(s.rx[i] > 0)) {  // a half-chord glitch of the diagnostics, not the membrane
        ++r.rx_glitches;
        continue;
      }
      const double d = s.rx[i] - reference.at(s.t[i]);
      mx = std::max(mx, std::fabs(d));
      sq += d * d;
      ++n;
    }
    if (n > 0) {
      r.rx_max = mx;
      r.rx_rms = std::sqrt(sq / n);
    }
  }

  static constexpr double kL = 3.0;  // the domain's width
  static constexpr int kNx0 = 64;    // the default resolution
  static double default_dt(bool A) { return A ? 1e-4 : 0.1 * kL / kNx0; }

  // The fine reference run of the same physics; its rx(t) without glitch rows (see read_rx).
  Series membrane_reference(const std::string& name, const std::vector<std::string>& physics) {
    // the reference: the exact override list the run directory records
    const bool A = name == "A";
    std::vector<std::string> ref = physics;
    if (!A) ref.push_back("membrane.h_star=0.0425");
    if (o_.quick)  // a cheap stand-in, for smoke tests only
      ref.insert(ref.end(), {"grid.nx=48", "grid.ny=48", "time.dt=0.001", "time.end=2", "output.interval=0"});
    else
      ref.insert(ref.end(), {"grid.nx=128", "grid.ny=128", A ? "membrane.nb=256" : "membrane.nb=512",
                             "time.dt=2.5e-05", "time.end=2", "output.interval=0", "output.diagnostics_every=200"});
    Run rr;
    rr.study = "membrane_" + name;
    rr.group = "reference";
    rr.label = o_.quick ? "Nx 48 dt 1e-3 (quick)" : A ? "Nx 128 Nb 256 dt 2.5e-5" : "Nx 128 Nb 512 dt 2.5e-5";
    rr.tag = "ref_" + name;
    rr.scene = "membrane_oscillation.toml";
    rr.sets = ref;
    std::printf("  reference run %s (%s)...\n", rr.tag.c_str(), rr.label.c_str());
    std::fflush(stdout);
    const nlohmann::json jr = execute(rr, true);
    Series reference;
    if (!jr.is_null() && rr.ok()) {
      reference = read_rx(o_.out / "runs" / rr.tag / "diagnostics.csv");
      for (size_t i = 0; i < reference.t.size();)  // glitch rows out of the reference (see read_rx)
        if (!(reference.rx[i] > 0)) {
          reference.t.erase(reference.t.begin() + i);
          reference.rx.erase(reference.rx.begin() + i);
          ++rr.rx_glitches;
        } else {
          ++i;
        }
      if (jr.contains("area_relative_error_at")) {
        rr.area1 = jr["area_relative_error_at"].value("1", NAN);
        rr.area2 = jr["area_relative_error_at"].value("2", NAN);
      }
      rr.rx_final = jr.value("rx", NAN);
    }
    add(rr);
    if (reference.t.empty()) std::printf("  no reference: rx errors are not computed\n");
    return reference;
  }

  // The default values (applied after the physics); each variation overrides some of them.
  static std::map<std::string, std::string> membrane_defaults(bool A) {
    const double dt0 = default_dt(A);
    const int nb0 = A ? 128 : 360;
    std::map<std::string, std::string> def{{"grid.nx", "64"}, {"grid.ny", "64"}, {"membrane.nb", std::to_string(nb0)},
                                           {"kernel.h_over_dx", "1.2"}, {"time.dt", num(dt0)}};
    if (A) def["membrane.h_star_over_h"] = "1.4";
    else def["membrane.h_star"] = "0.0425";

    return def;
  }

  // One at a time around the default, plus combinations.
  std::vector<Variation> membrane_variations(bool A) const {
    const double L = kL, dt0 = default_dt(A);
    const int nx0 = kNx0;
    std::vector<Variation> vs;
    vs.push_back({"base", "default", {}});
    auto nx_sets = [](int n) { return std::vector<std::string>{"grid.nx=" + std::to_string(n), "grid.ny=" + std::to_string(n)}; };
    auto cat = [](std::vector<std::string> a, const std::vector<std::string>& b) {
      a.insert(a.end(), b.begin(), b.end());
      return a;
    };
    const double h0 = 1.2 * L / nx0;  // default h
    if (o_.quick) {
      vs.push_back({"Nx", "Nx 32", nx_sets(32)});
      vs.push_back({"dt", "dt x4", {"time.dt=" + num(4 * dt0)}});
    } else if (A) {
      for (int n : {32, 48, 96, 128}) vs.push_back({"Nx", "Nx " + std::to_string(n), nx_sets(n)});
      for (int nb : {64, 96, 192, 256}) vs.push_back({"Nb", "Nb " + std::to_string(nb), {"membrane.nb=" + std::to_string(nb)}});
      for (double h : {1.0, 1.525, 2.0, 2.5}) vs.push_back({"h/dx", "h/dx " + num(h), {"kernel.h_over_dx=" + num(h)}});
      for (double r : {0.7, 1.0, 2.0, 2.8}) vs.push_back({"h*/h", "h*/h " + num(r), {"membrane.h_star_over_h=" + num(r)}});
      for (double dt : {2.5e-5, 5e-5, 2e-4, 5e-4, 1e-3, 2e-3, 4e-3}) vs.push_back({"dt", "dt " + num(dt), {"time.dt=" + num(dt)}});
      vs.push_back({"combined", "Nx 32 Nb 64 dt 1e-3", cat(nx_sets(32), {"membrane.nb=64", "time.dt=0.001"})});
      vs.push_back({"combined", "Nx 48 Nb 96 dt 5e-4", cat(nx_sets(48), {"membrane.nb=96", "time.dt=0.0005"})});
      vs.push_back({"combined", "Nx 48 Nb 96 dt 1e-3", cat(nx_sets(48), {"membrane.nb=96", "time.dt=0.001"})});
      vs.push_back({"combined", "Nx 64 dt 1e-3 h/dx 1.525", {"time.dt=0.001", "kernel.h_over_dx=1.525"}});
      vs.push_back({"combined", "Nx 96 Nb 192 dt 5e-4", cat(nx_sets(96), {"membrane.nb=192", "time.dt=0.0005"})});
      vs.push_back({"combined", "Nx 96 Nb 192 dt 1e-3", cat(nx_sets(96), {"membrane.nb=192", "time.dt=0.001"})});
      vs.push_back({"combined", "Nx 128 Nb 256 dt 5e-4", cat(nx_sets(128), {"membrane.nb=256", "time.dt=0.0005"})});
      vs.push_back({"combined", "Nx 128 Nb 256 dt 1e-4", cat(nx_sets(128), {"membrane.nb=256"})});
      // second round, after the first showed area loss ~ 3 dt/dx, Nb without effect above 1 per dx, and
      // h = dx the most accurate for rx (appended: the tags of the first round stay)
      vs.push_back({"combined", "Nx 64 h/dx 1 dt 5e-5", {"kernel.h_over_dx=1", "time.dt=5e-05"}});
      vs.push_back({"combined", "Nx 64 h/dx 1 dt 2e-4", {"kernel.h_over_dx=1", "time.dt=0.0002"}});
      vs.push_back({"combined", "Nx 64 h/dx 1 h*/h 2", {"kernel.h_over_dx=1", "membrane.h_star_over_h=2"}});
      vs.push_back({"combined", "Nx 64 h*/h 2 dt 2e-4", {"membrane.h_star_over_h=2", "time.dt=0.0002"}});
      vs.push_back({"combined", "Nx 96 h/dx 1 dt 1e-4", cat(nx_sets(96), {"kernel.h_over_dx=1"})});
      vs.push_back({"combined", "Nx 96 dt 5e-5", cat(nx_sets(96), {"time.dt=5e-05"})});
      vs.push_back({"combined", "Nx 48 Nb 64 h/dx 1 dt 2.5e-4", cat(nx_sets(48), {"membrane.nb=64", "kernel.h_over_dx=1", "time.dt=0.00025"})});
    } else {
      for (int n : {32, 40, 48, 80, 96, 120, 128, 160, 192})  // Fig. 19: dt = 0.1 dx
        vs.push_back({"Nx, dt = 0.1 dx", "Nx " + std::to_string(n), cat(nx_sets(n), {"time.dt=" + num(0.1 * L / n)})});
      for (int n : {32, 96, 128}) vs.push_back({"Nx", "Nx " + std::to_string(n) + " (dt fixed)", nx_sets(n)});
      for (int nb : {90, 180, 720}) vs.push_back({"Nb", "Nb " + std::to_string(nb), {"membrane.nb=" + std::to_string(nb)}});
      for (double h : {1.0, 1.525, 2.0}) vs.push_back({"h/dx", "h/dx " + num(h), {"kernel.h_over_dx=" + num(h)}});
      for (double r : {0.5, 1.0, 1.4, 2.0})
        vs.push_back({"h*/h", "h*/h " + num(r), {"membrane.h_star=" + num(r * h0)}});
      for (double f : {0.0125, 0.025, 0.05, 0.2, 0.4})
        vs.push_back({"dt", "dt " + num(f) + " dx", {"time.dt=" + num(f * L / nx0)}});
      vs.push_back({"combined", "Nx 96 Nb 540 dt 0.1 dx", cat(nx_sets(96), {"membrane.nb=540", "time.dt=" + num(0.1 * L / 96)})});
      vs.push_back({"combined", "Nx 128 dt 0.025 dx", cat(nx_sets(128), {"time.dt=" + num(0.025 * L / 128)})});
      vs.push_back({"combined", "Nx 128 Nb 720 dt 0.05 dx", cat(nx_sets(128), {"membrane.nb=720", "time.dt=" + num(0.05 * L / 128)})});
      vs.push_back({"combined", "Nx 160 dt 0.05 dx", cat(nx_sets(160), {"time.dt=" + num(0.05 * L / 160)})});
      vs.push_back({"combined", "Nx 96 dt 0.025 dx", cat(nx_sets(96), {"time.dt=" + num(0.025 * L / 96)})});
      vs.push_back({"combined", "Nx 64 dt 0.025 dx h*/h 1.4", {"time.dt=" + num(0.025 * L / 64), "membrane.h_star=" + num(1.4 * h0)}});
      // second round (appended)
      vs.push_back({"combined", "Nx 64 dt 0.025 dx h*/h 2", {"time.dt=" + num(0.025 * L / 64), "membrane.h_star=" + num(2 * h0)}});
      vs.push_back({"combined", "Nx 64 dt 0.0125 dx h*/h 2", {"time.dt=" + num(0.0125 * L / 64), "membrane.h_star=" + num(2 * h0)}});
      vs.push_back({"combined", "Nx 64 dt 0.0125 dx h*/h 1.4", {"time.dt=" + num(0.0125 * L / 64), "membrane.h_star=" + num(1.4 * h0)}});
      vs.push_back({"combined", "Nx 96 dt 0.025 dx h*/h 1.4", cat(nx_sets(96), {"time.dt=" + num(0.025 * L / 96), "membrane.h_star=" + num(1.4 * 1.2 * L / 96)})});
      vs.push_back({"combined", "Nx 64 h/dx 1 dt 0.025 dx h*/h 1.7", {"kernel.h_over_dx=1", "time.dt=" + num(0.025 * L / 64), "membrane.h_star=" + num(1.4 * h0)}});
    }
    return vs;
  }

  // ---- output ----
  // Pareto front over the runs of one study: no other run is both cheaper and more accurate.
  static std::vector<bool> pareto(const std::vector<const Run*>& rs, const std::function<double(const Run&)>& err) {
    std::vector<bool> front(rs.size(), false);
    for (size_t i = 0; i < rs.size(); ++i) {
      const double ei = err(*rs[i]), ci = rs[i]->cpu;
      if (!std::isfinite(ei) || !std::isfinite(ci) || !rs[i]->ok()) continue;
      bool dominated = false;
      for (size_t k = 0; k < rs.size() && !dominated; ++k) {
        if (k == i || !rs[k]->ok()) continue;
        const double ek = err(*rs[k]), ck = rs[k]->cpu;
        if (!std::isfinite(ek) || !std::isfinite(ck)) continue;
        // equal errors within 1% count as equal (the dt-independent Poiseuille errors differ in the 4th digit)
        dominated = (ck < ci && ek <= 1.01 * ei) || (ck <= ci && ek < ei / 1.01);
      }
      front[i] = !dominated;
    }
    return front;
  }

  std::vector<const Run*> study(const std::string& s, bool with_reference = false) const {
    std::vector<const Run*> v;
    for (const Run& r : runs_)
      if (r.study == s && (with_reference || r.group != "reference")) v.push_back(&r);
    return v;
  }

  static double area_err(const Run& r) { return std::fabs(r.area2); }
  static double rx_err(const Run& r) { return r.rx_max; }
  static double rms_err(const Run& r) { return r.rms; }

  void write() {
    std::ostringstream c;
    c << "study,group,label,tag,method,nx,ny,nb,markers_per_dx,dx,h_over_dx,h,h_star,h_star_over_h,dt,steps,t_end,"
         "status,reused,cpu_s,wall_s,s_per_step,rms_error,area_err_t1,area_err_t2,rx_max_err,rx_rms_err,rx_final,"
         "pareto_rms,pareto_area,pareto_rx,rx_glitch_rows\n";
    std::map<const Run*, std::array<bool, 3>> flags;
    for (const std::string s : {"poiseuille", "vukcevic", "membrane_A", "membrane_B"}) {
      const auto rs = study(s);
      const auto p0 = pareto(rs, rms_err), p1 = pareto(rs, area_err), p2 = pareto(rs, rx_err);
      for (size_t i = 0; i < rs.size(); ++i) flags[rs[i]] = {p0[i], p1[i], p2[i]};
    }
    for (const Run& r : runs_) {
      const auto f = flags.count(&r) ? flags[&r] : std::array<bool, 3>{false, false, false};
      c << r.study << ',' << csv_text(r.group) << ',' << csv_text(r.label) << ',' << r.tag << ',' << r.method << ','
        << r.nx << ',' << r.ny << ',' << r.nb << ',' << csv_num(r.markers_per_dx) << ',' << csv_num(r.dx) << ','
        << csv_num(r.hdx) << ',' << csv_num(r.h) << ',' << csv_num(r.h_star) << ',' << csv_num(r.h_star / r.h) << ','
        << csv_num(r.dt) << ',' << r.steps << ',' << csv_num(r.t_end) << ',' << csv_text(r.status) << ',' << r.reused
        << ',' << csv_num(r.cpu) << ',' << csv_num(r.wall) << ',' << csv_num(r.per_step) << ',' << csv_num(r.rms)
        << ',' << csv_num(r.area1) << ',' << csv_num(r.area2) << ',' << csv_num(r.rx_max) << ',' << csv_num(r.rx_rms)
        << ',' << csv_num(r.rx_final) << ',' << f[0] << ',' << f[1] << ',' << f[2] << ',' << r.rx_glitches << '\n';
    }
    sphib::write_file_atomic((o_.out / "speed_accuracy.csv").string(), c.str());
    sphib::write_file_atomic((o_.out / "speed_accuracy.md").string(), markdown());
  }

  std::string markdown() {
    std::ostringstream m;
    m << "# Speed-accuracy trade (issue 6)\n\nGenerated by `bench/speed_accuracy` (single-threaded). Cost = CPU "
         "seconds of the run (set-up, loop and output; the machine has 2 cores shared with other jobs, so wall "
         "times vary by tens of per cent; CPU time less; both are in the tables and the CSV). Reused runs keep "
         "the times measured when they ran. Pareto front (★): no other run of the study is both cheaper and more "
         "accurate (errors within 1% count as equal).\n\n";
    if (const auto rs = study("poiseuille"); !rs.empty()) m << poiseuille_md(rs);
    if (const auto rs = study("vukcevic"); !rs.empty()) m << vukcevic_md(rs);
    for (const std::string name : {"A", "B"})
      if (const auto rs = study("membrane_" + name, true); !rs.empty()) m << membrane_md(name, rs);
    return m.str();
  }

  // P (and L): the Pareto front, every EPSPH run, LPSPH beside EPSPH.
  std::string poiseuille_md(const std::vector<const Run*>& rs) const {
    std::ostringstream m;
    const auto pf = pareto(rs, rms_err);
    const bool has_l = std::any_of(rs.begin(), rs.end(), [](const Run* r) { return r->group == "lagrangian"; });
    m << "## P: start-up Poiseuille, rms error (Eq. 69) at t = 0.0125 against CPU time\n\n"
         "`cases/poiseuille.toml` (Re = 0.0125, Stokes), full grid Nx x h/dx x dt with EPSPH"
      << (has_l ? "; part L adds LPSPH (`method = lagrangian`) on a smaller grid, and the front is over both methods"
                : "")
      << ".\n\n";
    std::vector<size_t> idx(rs.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    m << "### Pareto front\n\n| method | Nx | h/dx | dt | steps | rms error | CPU s | wall s |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|\n";
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return rs[a]->cpu < rs[b]->cpu; });
    for (size_t i : idx)
      if (pf[i])
        m << "| " << (rs[i]->group == "lagrangian" ? "LPSPH" : "EPSPH") << " | " << rs[i]->nx << " | "
          << num(rs[i]->hdx) << " | " << num(rs[i]->dt, 4) << " | " << rs[i]->steps << " | " << sci(rs[i]->rms)
          << " | " << fix(rs[i]->cpu) << " | " << fix(rs[i]->wall) << " |\n";
    m << "\n### All EPSPH runs: rms error (CPU s)\n\n";
    std::vector<double> dts, hs;
    std::vector<int> nxs;
    for (const Run* r : rs) {
      if (r->group != "grid") continue;
      if (std::find(dts.begin(), dts.end(), r->dt) == dts.end()) dts.push_back(r->dt);
      if (std::find(hs.begin(), hs.end(), r->hdx) == hs.end()) hs.push_back(r->hdx);
      if (std::find(nxs.begin(), nxs.end(), r->nx) == nxs.end()) nxs.push_back(r->nx);
    }
    m << "| dt | h/dx |";
    for (int n : nxs) m << " Nx = " << n << " |";
    m << "\n|---:|---:|";
    for (size_t k = 0; k < nxs.size(); ++k) m << "---:|";
    m << "\n";
    for (double dt : dts)
      for (double h : hs) {
        m << "| " << num(dt, 4) << " | " << num(h) << " |";
        for (int n : nxs) {
          std::string cell = " ";
          for (size_t i = 0; i < rs.size(); ++i)
            if (rs[i]->group == "grid" && rs[i]->dt == dt && rs[i]->hdx == h && rs[i]->nx == n)
              cell = rs[i]->ok() ? sci(rs[i]->rms) + " (" + fix(rs[i]->cpu, rs[i]->cpu < 1 ? 2 : 1) + ")" +
                                       (pf[i] ? " ★" : "")
                                 : "failed";
          m << ' ' << cell << " |";
        }
        m << "\n";
      }
    m << "\n";
    if (has_l) {
      m << "### LPSPH (part L) against EPSPH at the same Nx, h/dx and dt\n\n"
           "| Nx | h/dx | dt | steps | LPSPH rms error | LPSPH CPU s | EPSPH rms error | EPSPH CPU s | "
           "LPSPH / EPSPH CPU | Pareto | status |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n";
      for (size_t i = 0; i < rs.size(); ++i) {
        const Run& l = *rs[i];
        if (l.group != "lagrangian") continue;
        const Run* e = nullptr;
        for (const Run* r : rs)
          if (r->group == "grid" && r->nx == l.nx && r->hdx == l.hdx && r->dt == l.dt) e = r;
        m << "| " << l.nx << " | " << num(l.hdx) << " | " << num(l.dt, 4) << " | " << l.steps << " | " << sci(l.rms)
          << " | " << fix(l.cpu) << " | " << (e ? sci(e->rms) : "–") << " | " << (e ? fix(e->cpu) : "–") << " | "
          << (e && e->cpu > 0 ? fix(l.cpu / e->cpu, 1) : "–") << " | " << (pf[i] ? "★" : "") << " | "
          << md_text(l.ok() ? "" : l.status) << " |\n";
      }
      m << "\n";
    }
    return m.str();
  }

  // W: WCSPH and EPSPH on Vukcevic's Poiseuille flow.
  std::string vukcevic_md(const std::vector<const Run*>& rs) const {
    std::ostringstream m;
    const auto pf = pareto(rs, rms_err);
    m << "## W: Poiseuille of Vukcevic et al. (t = 1 s), WCSPH and EPSPH, rms error / u_max\n\n"
         "`cases/wcsph_poiseuille.toml` (h = 2.2 dy); WCSPH at 0.9 and 0.3 of Coelho's viscous limit "
         "0.125 h^2/nu, EPSPH (`method = eulerian`, same scene) at dt = 2e-2 and 2e-3 s.\n\n"
         "| method | Nx x Ny | dt (s) | steps | rms error / U | CPU s | wall s | Pareto | status |\n"
         "|---|---|---:|---:|---:|---:|---:|---|---|\n";
    for (size_t i = 0; i < rs.size(); ++i) {
      const Run& r = *rs[i];
      m << "| " << r.method << " | " << r.nx << " x " << r.ny << " | " << sci(r.dt) << " | " << r.steps << " | "
        << sci(r.rms) << " | " << fix(r.cpu) << " | " << fix(r.wall) << " | " << (pf[i] ? "★" : "") << " | "
        << md_text(r.ok() ? "" : r.status) << " |\n";
    }
    m << "\n";
    return m.str();
  }

  // A or B: every variation with its area and rx errors, the fronts, the choice.
  std::string membrane_md(const std::string& name, const std::vector<const Run*>& rs) const {
    std::ostringstream m;
    const auto nr = study("membrane_" + name);
    const auto pa = pareto(nr, area_err), px = pareto(nr, rx_err);
    std::map<const Run*, std::pair<bool, bool>> pf;
    for (size_t i = 0; i < nr.size(); ++i) pf[nr[i]] = {pa[i], px[i]};
    m << "## " << name << ": oscillating membrane, "
      << (name == "A" ? "Section 5.2.2 (64 x 64, Nb = 128, h = 1.2 dx, h* = 1.4 h, dt = 1e-4, T0 = 10, mu = 0.1)"
                      : "Fig. 19 settings (64 x 64, Nb = 360, h = 1.2 dx, h* = 0.0425, dt = 0.1 dx, T0 = 1, mu = 0.05)")
      << ", t in [0, 2]\n\n"
      << "Area error: relative error of the enclosed area at t = 2. rx error: max (and rms) over the run's "
         "diagnostics times in [0, 2] of |rx(t) - rx_ref(t)|, rx_ref from the reference run (first row) "
         "interpolated linearly. ★a / ★x: on the Pareto front of area / rx error against CPU time.\n\n"
      << "| group | setting | Nx | Nb | markers/dx | h/dx | h*/h | dt | steps | CPU s | wall s | ms/step | area err t=1 | "
         "area err t=2 | rx max err | rx rms err | Pareto | status |\n"
      << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n";
    for (const Run* r : rs) {
      std::string p;
      if (pf.count(r)) p = std::string(pf[r].first ? "★a " : "") + (pf[r].second ? "★x" : "");
      m << "| " << r->group << " | " << r->label << " | " << r->nx << " | " << r->nb << " | "
        << fix(r->markers_per_dx, 2) << " | " << num(r->hdx, 4) << " | " << fix(r->h_star / r->h, 3) << " | "
        << num(r->dt, 4) << " | " << r->steps << " | " << fix(r->cpu, 1) << " | " << fix(r->wall, 1) << " | "
        << fix(1e3 * r->per_step, 3) << " | " << pct(r->area1, 3) << " | " << pct(r->area2, 3) << " | "
        << sci(r->rx_max) << " | " << sci(r->rx_rms) << " | " << p << " | "
        << md_text(r->ok() ? std::string(r->reused ? "reused" : "") +
                                 (r->rx_glitches ? " " + std::to_string(r->rx_glitches) + " rx glitch row(s) skipped" : "")
                           : r->status)
        << " |\n";
    }
    m << "\n" << reference_check(rs) << choosing(name) << "\n";
    return m.str();
  }

  // How far the reference itself is from converged in dt: the run with the reference's Nx, h/dx and
  // h* (Nb aside: the Nb rows show no effect above one marker per dx) and the smallest larger dt.
  static std::string reference_check(const std::vector<const Run*>& rs) {
    const Run* ref = nullptr;
    for (const Run* r : rs)
      if (r->group == "reference" && r->ok()) ref = r;
    if (!ref) return "";
    const Run* near = nullptr;
    for (const Run* r : rs)
      if (r != ref && r->ok() && r->nx == ref->nx && std::fabs(r->hdx - ref->hdx) < 1e-9 &&
          std::fabs(r->h_star - ref->h_star) < 1e-9 * ref->h_star && r->dt > ref->dt && std::isfinite(r->rx_max) &&
          (!near || r->dt < near->dt))
        near = r;
    std::ostringstream m;
    m << "**The reference's own error.** ";
    if (!near) {
      m << "No run shares the reference's Nx, h/dx and h*, so its own error is not estimated here.\n\n";
      return m.str();
    }
    const double est = near->rx_max * ref->dt / (near->dt - ref->dt);
    m << "`" << near->label << "` has the reference's Nx, h/dx and h* (Nb " << near->nb << ", dt " << num(near->dt, 4)
      << " against " << num(ref->dt, 4) << "): it differs from the reference by " << sci(near->rx_max)
      << " in rx (max) and its area error at t = 2 is " << pct(near->area2, 3) << " against the reference's "
      << pct(ref->area2, 3) << ". If that difference is first order in dt, the reference's own dt error in rx is "
      << "about " << sci(est) << " (" << sci(near->rx_max) << " x dt_ref / (dt - dt_ref)): rx errors near or below "
      << "that are not resolved by this reference, and its error in Nx is not measured. rx is sampled at each run's "
      << "diagnostics times (every max(1, round(0.01/dt)) steps).\n\n";
    return m.str();
  }

  // Cheapest run meeting each error budget (area at t = 2; rx max error on [0, 2]).
  std::string choosing(const std::string& name) const {
    const auto rs = study("membrane_" + name);
    std::ostringstream m;
    m << "### Choosing a resolution (" << name << "): the cheapest run found within an error budget\n\n"
      << "| budget | cheapest setting | Nx | Nb | h/dx | h*/h | dt | CPU s | area err t=2 | rx max err |\n"
      << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    // The cheapest finished run within the budget.
    auto row = [&](const std::string& what, const std::function<bool(const Run&)>& within) {
      const Run* best = nullptr;
      for (const Run* r : rs)
        if (r->ok() && within(*r) && std::isfinite(r->cpu) && (!best || r->cpu < best->cpu)) best = r;
      m << "| " << what << " | ";
      if (!best) {
        m << "none of these runs | | | | | | | | |\n";
        return;
      }
      m << best->label << " | " << best->nx << " | " << best->nb << " | " << num(best->hdx, 4) << " | "
        << fix(best->h_star / best->h, 2) << " | " << num(best->dt, 4) << " | " << fix(best->cpu, 1) << " | "
        << pct(best->area2, 2) << " | " << sci(best->rx_max) << " |\n";
    };
    for (double b : {0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001})
      row("area ≤ " + pct(b, 1), [&](const Run& r) { return area_err(r) <= b; });
    for (double b : {0.05, 0.02, 0.01, 0.005, 0.002, 0.001})
      row("rx ≤ " + num(b), [&](const Run& r) { return rx_err(r) <= b; });
    // both budgets at once
    const std::vector<std::pair<double, double>> both{{0.05, 0.03}, {0.05, 0.02}, {0.02, 0.01}, {0.01, 0.01},
                                                      {0.01, 0.005}, {0.005, 0.005}, {0.005, 0.0025}, {0.002, 0.005}};
    for (auto [ba, bx] : both)
      row("area ≤ " + pct(ba, 1) + " and rx ≤ " + num(bx),
          [&, ba = ba, bx = bx](const Run& r) { return area_err(r) <= ba && r.rx_max <= bx; });
    return m.str();
  }

  void run() {
    const auto t0 = Clock::now();
    if (o_.parts.find('P') != std::string::npos) part_p();
    if (o_.parts.find('L') != std::string::npos) part_l();
    if (o_.parts.find('W') != std::string::npos) part_w();
    if (o_.parts.find('A') != std::string::npos) membrane("A");
    if (o_.parts.find('B') != std::string::npos) membrane("B");
    write();
    std::printf("\n%s\ntotal %.0f s wall; wrote %s and %s\n", markdown().c_str(), seconds_since(t0),
                (o_.out / "speed_accuracy.csv").c_str(), (o_.out / "speed_accuracy.md").c_str());
  }

 private:
  std::vector<Run> runs_;
  Options o_;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The speed-accuracy trade of EPSPH: error against CPU time with the Pareto fronts", "speed_accuracy"};
  Options o;
  add_scene_options(app, o, "PLWAB",
                    "P start-up Poiseuille (EPSPH), L the same with LPSPH, W Vukcevic Poiseuille (WCSPH and EPSPH), "
                    "A oscillating membrane (Section 5.2.2), B the same with the Fig. 19 settings");
  auto* reuse = app.add_flag("--reuse", o.reuse, "reuse every finished run directory with the same overrides "
                                                 "(default: the references only)");
  app.add_flag("--report-only", o.report_only, "run nothing: rebuild the CSV and Markdown of the chosen parts from "
                                               "the run directories")->excludes(reuse);
  return run_main(app, argc, argv, [&] {
    Bench(o).run();
    return 0;
  });
}
