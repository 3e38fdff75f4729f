// Benchmark (not a test): where the EPSPH immersed-boundary step is stable (issue 6).
//
// A coarse, short version of the oscillating membrane (cases/membrane_oscillation.toml: the
// ellipse rx = 0.75, ry = 0.5, r0 = 0.5 in [-1.5, 1.5]^2; here 32 x 32 particles, Nb = 64, i.e.
// 1.91 markers per grid spacing as the 64 x 64 case with Nb = 128, h = 1.2 dx, h* = 1.4 h,
// T0 = 10, mu = 0.1, rho = 1, default dt = 1e-4) run to t = 0.5 but for no fewer than 500 and no
// more than 4000 steps. Every run is classified automatically:
//   unstable  the runner stopped it (sphib::RunError from run_scene: non-finite values, a particle
//             or a marker moving more than a lattice spacing in one step, a marker with no fluid
//             particle within 2h, a fixed point that does not converge), or the total energy
//             kinetic + elastic (diagnostics.csv, every step up to 100 rows) exceeded 10 times its
//             initial value;
//   stable    otherwise;
//   refused   the scene was refused at set-up (e.g. a kernel reaching the walls): no verdict.
//
//  G  classification grid: dt in {1e-5, 3.16e-5, 1e-4, 3.16e-4, 1e-3} (two decades around the
//     default) against each parameter in turn, the others at the default: T0 in 1..1e4, mu in
//     1e-3..10, markers per grid spacing 0.25..4 (membrane.nb), h/dx 1..5 (h* held at its default
//     value 0.1575 so that the support fits between membrane and walls), h*/h 0.5..2;
//  T  the largest stable dt for every (T0, mu) pair, T0 in {1, 10, ..., 1e4}, mu in {1e-3, ..., 10}:
//     bracketing by factors of 4 from the estimate of `sphib check` (app/check.cpp), then geometric
//     bisection until the bracket is within a factor 1.1; fitted to the two regimes of an explicit
//     membrane force,
//       viscous   dt ~ C_v mu dx / T0,   inertial   dt ~ C_i sqrt(rho dx^3 / T0),
//     as dt_max = max(C_i sqrt(rho dx^3/T0), C_v mu dx/T0), least squares in log dt over the
//     bracketed pairs; compared with `sphib check`'s max(0.3 sqrt(rho h*^3/T0), 10 mu h*/T0) and with
//     the classical estimates for an explicit (forward Euler) force (see classical() below);
//  X  the largest stable dt against Nx (24..64, Nb = 2 Nx), markers per grid spacing, h/dx and
//     h*/h at an inertial point (T0 = 1e3, mu = 1e-3) and a viscous point (T0 = 1e3, mu = 10):
//     which length (dx, h, h*, marker spacing) sets the limit.
//
//  E  as T with the bench's own loop instead of run_scene, without the runner's dx-per-step guards
//     (a particle or marker moving more than dx in a step): near the limit of T the runner stops
//     runs whose *physical* speed reaches dx/dt (a CFL guard, not a blow-up); here only non-finite
//     values, energy above the bound, a failing fixed point or a marker leaving the fluid count.
//  S  as E with convection off.
//
//   stability_map [--parts GTESX] [--out DIR] [--cases DIR] [--quick] [--residual] [--report-only]      (--help)
//
// --report-only runs nothing: it reads DIR/stability_runs.csv and DIR/stability_dtmax.csv back and
// rewrites them and DIR/stability_map.md (new columns, new text, same measurements).
//
// Writes DIR/stability_runs.csv (every run: parameters, verdict, reason), DIR/stability_dtmax.csv
// (one row per bisection), DIR/stability_map.md, each atomically after every run; plots:
// scripts/plot_bench.py. Run directories are scratch (DIR/scratch, removed). Single-threaded.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/common.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"
#include "membrane/geometry.hpp"

namespace fs = std::filesystem;

namespace {

using namespace sphib::bench;
using sphib::seconds_since;

constexpr double kL = 3.0;           // domain width
constexpr double kR0 = 0.5;          // rest radius: L0 = 2 pi r0
constexpr double kEnergyBound = 10;  // unstable: total energy above 10 x its initial value
constexpr double kDtCap = 1.0;       // the bisection does not look above this dt
constexpr double kDtFloor = 1e-7;

// The classical time-step limits of an explicit (forward Euler) membrane force, for a membrane of
// tension T0 between two fluids of density rho and viscosity mu on a grid of spacing dx:
//   inertial  dt < sqrt(rho dx^3 / (2 pi T0)): the capillary time-step constraint of Brackbill,
//             Kothe & Zemach (1992, J. Comput. Phys. 100:335), the period of the shortest capillary
//             wave the grid carries (omega^2 = T0 k^3 / (2 rho)); a tensioned membrane is a capillary
//             interface for normal perturbations;
//   viscous   dt < (8/pi) mu dx / T0: in Stokes flow a membrane mode of wavenumber k relaxes at the
//             rate T0 |k| / (4 mu) (the linear analysis behind Stockie & Wetton 1999, J. Comput. Phys.
//             154:41, and Hou & Shi 2008, J. Comput. Phys. 227:8968, where the explicit step is
//             limited by dt ~ mu h / T0); forward Euler needs dt T0 k / (4 mu) <= 2 at k = pi/dx.
// Our step takes the force explicitly at X^n but moves the markers by the trapezoidal fixed point
// (Eqs. 56-60), and spreads with h* > dx: the measured limits are expected to exceed these.
constexpr double kClassicalCi = 0.3989422804014327;  // 1/sqrt(2 pi)
// `sphib check`'s explicit bending limit, dt < max(kBendCi sqrt(rho h*^5/Eb), kBendCv mu h*^3/Eb): the
// constants part B measures (app/check.cpp quotes them).
constexpr double kBendCi = 0.07, kBendCv = 4.0;
constexpr double kClassicalCv = 2.5464790894703255;  // 8/pi

// The parameters of one run (the coarse membrane, changed from its defaults).
struct Params {
  double T0 = 10, mu = 0.1, rho = 1.0;
  int nx = 32;
  int nb = 64;
  double hdx = 1.2;
  double hsh = 1.4;        // h*/h (when h_star == 0)
  double h_star_abs = 0;   // > 0: h* fixed
  double dt = 1e-4;
  bool convection = true;  // false: Stokes (no AB2 convection: no convective CFL instability)
  std::string law = "hookean";  // membrane.law; T0 is its modulus (Es) for the other laws
  double Eb = 0;           // bending modulus (part B)
  int semi = -1;           // membrane.semi_implicit: -1 the scene's default (off for Hookean without bending), 0, 1
  bool residual = false;   // membrane.stiff_residual (with semi_implicit): the filter's residual G
  bool guard = true;       // true: run_scene and its checks; false: the bench's own loop without the
                           // dx-per-step guards (non-finite values, energy growth, fixed point, markers leaving)
  double dx() const { return kL / nx; }
  double h() const { return hdx * dx(); }
  double h_star() const { return h_star_abs > 0 ? h_star_abs : hsh * h(); }
  double markers_per_dx() const { return dx() / (2 * M_PI * kR0 / nb); }
  // `sphib check`'s estimate (app/check.cpp) for the default (conservative) pair
  double check_estimate() const {
    const double hs = h_star();
    return std::max(0.3 * std::sqrt(rho * hs * hs * hs / T0), 10.0 * mu * hs / T0);
  }
  // `sphib check`'s explicit bending limit (app/check.cpp), h* form; min with the tension's
  double bending_estimate() const {
    const double hs = h_star();
    return std::max(kBendCi * std::sqrt(rho * std::pow(hs, 5) / Eb), kBendCv * mu * hs * hs * hs / Eb);
  }
  double start_estimate() const { return Eb > 0 ? std::min(check_estimate(), bending_estimate()) : check_estimate(); }
  bool semi_implicit() const { return semi < 0 ? (Eb > 0 || law != "hookean") : semi == 1; }
  // the classical explicit estimate (see kClassicalCi, kClassicalCv)
  double classical() const {
    const double d = dx();
    return std::max(kClassicalCi * std::sqrt(rho * d * d * d / T0), kClassicalCv * mu * d / T0);
  }
  long steps() const { return std::clamp(std::lround(0.5 / dt), 500L, 4000L); }
  std::vector<std::string> sets() const {
    std::vector<std::string> s{"grid.nx=" + std::to_string(nx), "grid.ny=" + std::to_string(nx),
                               "membrane.nb=" + std::to_string(nb), "membrane.T0=" + num(T0), "fluid.mu=" + num(mu),
                               "kernel.h_over_dx=" + num(hdx), "time.dt=" + num(dt, 12),
                               "time.end=" + num(steps() * dt * (1 + 1e-9), 15),
                               "time.max_steps=" + std::to_string(steps()), "output.interval=0",
                               "output.diagnostics_every=" + std::to_string(std::max(1L, steps() / 100)),
                               "output.fields=[\"u\"]"};
    if (!convection) s.push_back("fluid.convection=false");
    if (law != "hookean") {  // Es for the other laws: T0 is the Hookean law's key
      s[3] = "membrane.Es=" + num(T0);
      s.push_back("membrane.law=" + law);
    }
    if (Eb > 0) s.push_back("membrane.Eb=" + num(Eb));
    if (Eb > 0 || law != "hookean" || semi >= 0) s.push_back(std::string("membrane.semi_implicit=") + (semi_implicit() ? "true" : "false"));
    if (residual && semi_implicit()) s.push_back("membrane.stiff_residual=true");
    if (h_star_abs > 0) s.push_back("membrane.h_star=" + num(h_star_abs, 12));
    else s.push_back("membrane.h_star_over_h=" + num(hsh));
    return s;
  }
};

struct Verdict {
  std::string part, axis;  // which study, which parameter is varied
  Params p;
  std::string verdict = "stable";  // stable | unstable | refused
  std::string reason;              // for unstable: non-finite | particle CFL | marker CFL | marker left fluid | fixed point | energy growth
  std::string message;
  long steps_done = 0;
  double t_done = 0, energy_ratio = NAN, area_error = NAN, cpu = 0;
  double max_speed = NAN;  // largest max |u| of the diagnostics rows (the last good state for an unstable run)
  double cfl() const { return max_speed * p.dt / p.dx(); }
  double u_fail = NAN;     // particle CFL failures: the max |u| the runner reported
  bool stable() const { return verdict == "stable"; }
};

std::string classify(const std::string& msg) {
  auto has = [&](const char* s) { return msg.find(s) != std::string::npos; };
  if (has("non-finite")) return "non-finite";
  if (has("moves a particle")) return "particle CFL";
  if (has("marker") && has("would move")) return "marker CFL";
  if (has("no fluid particle")) return "marker left fluid";
  if (has("did not converge")) return "fixed point";
  if (has("energy")) return "energy growth";  // the runner's own bound (kinetic + elastic > 10 x initial)
  return "other";
}

struct DtMax {
  std::string part, axis;
  Params p;       // dt unused
  double lo = NAN, hi = NAN;  // largest stable, smallest unstable dt found
  std::string reason;         // why the smallest unstable run failed
  double cfl_stable = NAN;    // max |u| dt / dx of the largest stable run
  double u_stable = NAN, u_fail = NAN;  // max |u| of the largest stable run; reported at the failure
  int runs = 0;
  double estimate() const { return std::isfinite(lo) && std::isfinite(hi) ? std::sqrt(lo * hi) : NAN; }
};

struct Options {
  std::string parts = "GTESX";
  fs::path out = "bench_out/stability_map";
  fs::path cases = "cases";
  bool quick = false, report_only = false;
  bool residual = false;  // part B: the semi-implicit runs with membrane.stiff_residual (axis "semi+G:..."), Eb and Es axes only
};

class Bench {
 public:
  explicit Bench(Options o) : o_(std::move(o)) { fs::create_directories(o_.out); }

  Verdict run(const std::string& part, const std::string& axis, const Params& p) {
    std::string key = p.guard ? "guard;" : "noguard;";
    for (const auto& s : p.sets()) key += s + ";";
    if (auto it = memo_.find(key); it != memo_.end()) {
      Verdict v = it->second;
      v.part = part;
      v.axis = axis;
      return v;
    }
    Verdict v;
    v.part = part;
    v.axis = axis;
    v.p = p;
    const fs::path dir = o_.out / "scratch";
    fs::remove_all(dir);
    const double c0 = cpu_seconds();
    sphib::Scene s;
    try {
      // the other laws take Es, not the Hookean T0 of the paper's scene: its copy with the law's keys
      const char* scene = p.law == "hookean" ? "membrane_oscillation.toml" : "membrane_laws.toml";
      s = sphib::load_scene((o_.cases / scene).string(), p.sets());
    } catch (const std::exception& e) {
      v.verdict = "refused";
      v.message = e.what();
    }
    if (v.verdict != "refused" && !p.guard) {
      direct(s, v);
    } else if (v.verdict != "refused") {
      sphib::RunOptions ro;
      ro.out_dir = dir.string();
      try {
        const nlohmann::json j = sphib::run_scene(s, ro);
        v.area_error = j.value("area_relative_error", NAN);
      } catch (const sphib::RunError& e) {
        v.verdict = "unstable";
        v.message = e.what();
        v.reason = classify(v.message);
        if (const auto k = v.message.find("max |u| = "); k != std::string::npos)
          v.u_fail = std::strtod(v.message.c_str() + k + 10, nullptr);
      } catch (const std::exception& e) {  // set-up refused (std::invalid_argument from the constructors)
        v.verdict = "refused";
        v.message = e.what();
      }
      // the energy: kinetic + elastic, against its initial value
      std::ifstream in(dir / "diagnostics.csv");
      std::string line;
      if (std::getline(in, line)) {
        std::vector<std::string> cols;
        std::stringstream ss(line);
        for (std::string c; std::getline(ss, c, ',');) cols.push_back(c);
        auto col = [&](const char* n) { return std::find(cols.begin(), cols.end(), n) - cols.begin(); };
        const long ik = col("kinetic_energy"), ie = col("m0_elastic_energy"), is = col("step"), it = col("t"),
                   iu = col("max_speed");
        double e0 = NAN, emax = 0;
        while (std::getline(in, line)) {
          std::vector<double> r;
          std::stringstream rs(line);
          for (std::string c; std::getline(rs, c, ',');) r.push_back(c.empty() ? NAN : std::strtod(c.c_str(), nullptr));
          if (static_cast<long>(r.size()) <= std::max({ik, ie, is, it, iu})) continue;
          v.max_speed = std::isfinite(v.max_speed) ? std::max(v.max_speed, r[iu]) : r[iu];
          const double e = r[ik] + r[ie];
          if (!std::isfinite(e0)) e0 = e;
          emax = std::isfinite(e) ? std::max(emax, e) : INFINITY;
          v.steps_done = static_cast<long>(r[is]);
          v.t_done = r[it];
        }
        if (e0 > 0) v.energy_ratio = emax / e0;
        if (v.verdict == "stable" && !(v.energy_ratio <= kEnergyBound)) {
          v.verdict = "unstable";
          v.reason = "energy growth";
          v.message = "total energy reached " + num(v.energy_ratio, 3) + " x its initial value";
        }
      }
    }
    v.cpu = cpu_seconds() - c0;
    fs::remove_all(dir);
    memo_[key] = v;
    return v;
  }

  // The bench's own loop (no run_scene): the runner's dx-per-step guards are off (markers may move
  // any distance, fluid speed is not checked), so only a genuine blow-up stops the run: a step
  // that throws (fixed point not converging, a marker with no fluid within 2h), non-finite
  // values, or energy above the bound. Checked after every step.
  static void direct(sphib::Scene& s, Verdict& v) {
    s.sim.markers.max_move = 1e300;
    std::unique_ptr<sphib::Simulation> sim;
    try {
      sim = std::make_unique<sphib::Simulation>(s.sim);
    } catch (const std::exception& e) {
      v.verdict = "refused";
      v.message = e.what();
      return;
    }
    const auto& m0 = sim->membranes()[0];
    sphib::MembraneForce E = m0.force;
    auto energy = [&]() {
      E.fit_energy(sim->membranes()[0].m.X);
      return sim->fluid().kinetic_energy() + E.energy().total();
    };
    const double e0 = energy();
    double emax = e0;
    v.max_speed = 0;
    const long n = v.p.steps();
    try {
      for (long k = 0; k < n; ++k) {
        sim->step();
        v.steps_done = k + 1;
        v.t_done = sim->time();
        const double e = energy();
        emax = std::isfinite(e) ? std::max(emax, e) : INFINITY;
        if (!std::isfinite(e) || !sim->membranes()[0].m.X.allFinite()) {
          v.verdict = "unstable";
          v.reason = "non-finite";
          v.message = "non-finite energy or markers at step " + std::to_string(k + 1);
          break;
        }
        v.max_speed = std::max(v.max_speed, sim->fluid().u().rowwise().norm().maxCoeff());
        if (e > kEnergyBound * e0) {
          v.verdict = "unstable";
          v.reason = "energy growth";
          v.message = "total energy reached " + num(e / e0, 3) + " x its initial value at step " + std::to_string(k + 1);
          break;
        }
      }
    } catch (const std::exception& e) {
      v.verdict = "unstable";
      v.message = e.what();
      v.reason = classify(v.message);
    }
    v.energy_ratio = e0 > 0 ? emax / e0 : NAN;
  }

  void record(const Verdict& v) {
    all_.push_back(v);
    std::printf("  %s %-9s %s T0 %-6s Eb %-6s semi %2d mu %-6s Nx %-3d nb %-4d h/dx %-5s h*/h %-6s dt %-9s %-8s %-17s steps %5ld E/E0 %-9s cpu %.1f s\n",
                v.part.c_str(), v.axis.c_str(), v.p.law.c_str(), num(v.p.T0, 4).c_str(), num(v.p.Eb, 4).c_str(), v.p.semi,
                num(v.p.mu, 4).c_str(), v.p.nx, v.p.nb,
                num(v.p.hdx, 4).c_str(), num(v.p.h_star() / v.p.h(), 3).c_str(), num(v.p.dt, 4).c_str(),
                v.verdict.c_str(), v.reason.c_str(), v.steps_done, sci(v.energy_ratio).c_str(), v.cpu);
    std::fflush(stdout);
  }

  // Largest stable dt with the other parameters of p: bracket by factors of 4 from the estimate,
  // then bisect geometrically to a factor 1.1. Assumes stability is monotone in dt (the grid G
  // checks that).
  DtMax bisect(const std::string& part, const std::string& axis, Params p) {
    DtMax d;
    d.part = part;
    d.axis = axis;
    d.p = p;
    auto probe = [&](double dt) {
      p.dt = dt;
      Verdict v = run(part, axis, p);
      record(v);
      ++d.runs;
      if (v.verdict == "refused") throw std::runtime_error("refused: " + v.message);
      if (!v.stable()) d.reason = v.reason;
      if (v.stable() && !(dt < d.lo)) { d.cfl_stable = v.cfl(); d.u_stable = v.max_speed; }
      return v.stable();
    };
    try {
      double g = std::clamp(p.start_estimate(), kDtFloor, kDtCap);
      if (probe(g)) {
        d.lo = g;
        for (double t = g * 4; ; t *= 4) {
          if (t > kDtCap) { d.hi = NAN; break; }  // stable up to the cap
          if (probe(t)) d.lo = t;
          else { d.hi = t; break; }
        }
      } else {
        d.hi = g;
        for (double t = g / 4; ; t /= 4) {
          if (t < kDtFloor) { d.lo = NAN; break; }
          if (!probe(t)) d.hi = t;
          else { d.lo = t; break; }
        }
      }
      std::string reason = d.reason;
      while (std::isfinite(d.lo) && std::isfinite(d.hi) && d.hi / d.lo > 1.1) {
        const double mid = std::sqrt(d.lo * d.hi);
        if (probe(mid)) d.lo = mid;
        else { d.hi = mid; reason = d.reason; }
      }
      // the reason of the smallest unstable dt
      if (std::isfinite(d.hi)) {
        Params q = d.p;
        q.dt = d.hi;
        const Verdict v = run(part, axis, q);
        d.reason = v.reason;
        d.u_fail = v.u_fail;
      }
    } catch (const std::exception& e) {
      d.reason = e.what();
    }
    dtmax_.push_back(d);
    std::printf("  => %s %s: largest stable dt in [%s, %s) (%s), check estimate %s\n", part.c_str(), axis.c_str(),
                sci(d.lo, 3).c_str(), sci(d.hi, 3).c_str(), d.reason.c_str(), sci(d.p.check_estimate(), 3).c_str());
    write();
    return d;
  }

  // ---- G ----
  void part_g() {
    std::printf("G: classification grid, dt x one parameter at a time (32 x 32, default T0 = 10, mu = 0.1)\n");
    // two decades around the default 1e-4, and on to 0.1 (at 32 x 32 the default T0, mu are stable far above it)
    const std::vector<double> dts = o_.quick ? std::vector<double>{1e-4, 1e-3}
                                             : std::vector<double>{1e-5, 3.16e-5, 1e-4, 3.16e-4, 1e-3, 3.16e-3, 1e-2,
                                                                   3.16e-2, 1e-1};
    const double hs_default = Params().h_star();
    struct Axis {
      std::string name;
      std::vector<double> values;
      std::function<void(Params&, double)> set;
    };
    std::vector<Axis> axes = {
        {"T0", {1, 10, 100, 1e3, 1e4}, [](Params& p, double v) { p.T0 = v; }},
        {"mu", {1e-3, 1e-2, 0.1, 1, 10}, [](Params& p, double v) { p.mu = v; }},
        {"markers/dx", {0.25, 0.5, 1, 2, 4},
         [](Params& p, double v) { p.nb = std::max(4, static_cast<int>(std::lround(v * 2 * M_PI * kR0 / p.dx()))); }},
        {"h/dx", {1, 1.5, 2, 3, 5}, [hs_default](Params& p, double v) { p.hdx = v; p.h_star_abs = hs_default; }},
        {"h*/h", {0.5, 0.7, 1, 1.4, 2}, [](Params& p, double v) { p.hsh = v; }},
    };
    if (o_.quick) axes.resize(1);
    for (const Axis& a : axes)
      for (double v : a.values)
        for (double dt : dts) {
          Params p;
          a.set(p, v);
          p.dt = dt;
          Verdict r = run("G", a.name, p);
          record(r);
          write();
        }
  }

  // ---- T ----
  void part_t(const std::string& part) {
    const bool stokes = part == "S", guard = part == "T";
    std::printf("%s: largest stable dt over (T0, mu) (32 x 32%s%s)\n", part.c_str(), stokes ? ", convection off" : "",
                guard ? ", the runner's checks" : ", no dx-per-step guards");
    const std::vector<double> T0s = o_.quick ? std::vector<double>{10, 1000} : std::vector<double>{1, 10, 100, 1e3, 1e4};
    const std::vector<double> mus = o_.quick ? std::vector<double>{0.1} : std::vector<double>{1e-3, 1e-2, 0.1, 1, 10};
    for (double T0 : T0s)
      for (double mu : mus) {
        Params p;
        p.T0 = T0;
        p.mu = mu;
        p.convection = !stokes;
        p.guard = guard;
        bisect(part, "T0,mu", p);
      }
  }

  // ---- X ----
  void part_x() {
    std::printf("X: largest stable dt against Nx, markers per dx, h/dx, h*/h at an inertial and a viscous point,\n"
                "   with the runner's checks (convection on) and without guards (convection off: the elastic limit)\n");
    const double hs_default = Params().h_star();
    const std::vector<std::pair<double, double>> points =
        o_.quick ? std::vector<std::pair<double, double>>{{1e3, 1e-3}}
                 : std::vector<std::pair<double, double>>{{1e3, 1e-3}, {1e3, 10}};
    for (const std::string mode : {"runner", "elastic"})
      for (auto [T0, mu] : points) {
        Params base;
        base.T0 = T0;
        base.mu = mu;
        base.guard = mode == "runner";
        base.convection = mode == "runner";
        const std::string where = mode + "/" + (mu < 1 ? "inertial" : "viscous");
        for (int n : o_.quick ? std::vector<int>{24, 32} : std::vector<int>{24, 32, 48, 64}) {
          Params p = base;
          p.nx = n;
          p.nb = 2 * n;
          bisect("X", where + ":Nx", p);
        }
        if (o_.quick) continue;
        for (double m : {0.25, 0.5, 1.0, 1.91, 4.0}) {
          Params p = base;
          p.nb = std::max(4, static_cast<int>(std::lround(m * 2 * M_PI * kR0 / p.dx())));
          bisect("X", where + ":markers/dx", p);
        }
        for (double h : {1.0, 1.2, 1.5, 2.0, 3.0, 5.0}) {
          Params p = base;
          p.hdx = h;
          p.h_star_abs = hs_default;
          bisect("X", where + ":h/dx", p);
        }
        for (double r : {0.5, 0.7, 1.0, 1.4, 2.0}) {
          Params p = base;
          p.hsh = r;
          bisect("X", where + ":h*/h", p);
        }
      }
  }

  // ---- fits ----
  struct Fit {
    double Ci = NAN, Cv = NAN, rms_log = NAN;  // dt = max(Ci sqrt(rho L^3/T0), Cv mu L / T0)
    int n = 0;
  };
  // ---- B ----
  // Bending and the other laws, explicit against the stiff-force filter (semi_implicit), with the
  // runner's checks (convection on): the largest stable dt against Eb (Hookean T0 = 1, mu = 0.1 and
  // 10), against Es (Skalak, C = 1, no bending, mu = 0.1) and against markers per dx with bending
  // (Eb = 1, T0 = 1, mu = 0.1).
  std::string semi_axis() const { return o_.residual ? "semi+G" : "semi"; }
  void part_b() {
    std::printf("B: largest stable dt against Eb, Es (skalak) and markers/dx with bending, explicit and semi-implicit\n");
    const std::vector<int> semis{0, 1};
    // Eb = 0: the same membrane without bending, the tension's own limit (explicit only)
    const std::vector<double> Ebs = o_.quick ? std::vector<double>{0, 1} : std::vector<double>{0, 0.01, 0.1, 1, 10, 100};
    for (double mu : o_.quick ? std::vector<double>{0.1} : std::vector<double>{0.1, 10})
      for (int semi : semis)
        for (double Eb : Ebs) {
          if (semi && Eb == 0) continue;
          Params p;
          p.T0 = 1, p.mu = mu, p.Eb = Eb, p.semi = semi, p.residual = o_.residual;
          bisect("B", std::string(semi ? semi_axis() : "explicit") + ":Eb", p);
        }
    if (o_.quick) return;
    for (int semi : semis)
      for (double Es : {1.0, 10.0, 100.0, 1e3, 1e4}) {
        Params p;
        p.law = "skalak", p.T0 = Es, p.semi = semi, p.residual = o_.residual;
        bisect("B", std::string(semi ? semi_axis() : "explicit") + ":Es", p);
      }
    if (o_.residual) return;
    for (double Eb : {1.0, 10.0})
      for (int semi : semis)
        for (double m : {1.0, 1.5, 1.91, 3.0, 4.0}) {
          Params p;
          p.T0 = 1, p.Eb = Eb, p.semi = semi;
          p.nb = std::max(4, static_cast<int>(std::lround(m * 2 * M_PI * kR0 / p.dx())));
          bisect("B", std::string(semi ? "semi" : "explicit") + ":markers/dx", p);
        }
    // the explicit bending limit against the resolution (h* = 1.68 dx), inertial and viscous points
    for (auto [Eb, mu] : std::vector<std::pair<double, double>>{{1, 0.1}, {10, 10}})
      for (int n : {24, 48, 64}) {
        Params p;
        p.T0 = 1, p.Eb = Eb, p.mu = mu, p.semi = 0, p.nx = n, p.nb = 2 * n;
        bisect("B", "explicit:Nx", p);
      }
  }

  // The explicit bending limit dt = max(C_i sqrt(rho L^5/Eb), C_v mu L^3/Eb), least squares in log dt
  // over part B's explicit Eb bisections whose limit lies below half the tension's (T0 = 1) estimate
  // of the same run (bending-limited), L = h* (check's form) or dx.
  Fit fit_bending(bool use_hstar) const {
    std::vector<std::array<double, 3>> d;
    for (const DtMax& m : dtmax_)
      if (m.part == "B" && (m.axis == "explicit:Eb" || m.axis == "explicit:Nx") && std::isfinite(m.estimate()) &&
          bending_limited(m)) {
        const double L = use_hstar ? m.p.h_star() : m.p.dx();
        d.push_back({std::sqrt(m.p.rho * std::pow(L, 5) / m.p.Eb), m.p.mu * L * L * L / m.p.Eb, m.estimate()});
      }
    return fit_two(d);
  }
  // bending sets the limit: the membrane without bending is stable at 2x this dt, and the failure is not
  // the markers' own CFL (a faster flow, not an unstable force)
  bool bending_limited(const DtMax& m) const {
    for (const DtMax& t : dtmax_)  // part B's own Eb = 0 bisection of the same membrane
      if (t.part == "B" && t.p.Eb == 0 && t.p.law == m.p.law && t.p.T0 == m.p.T0 && t.p.mu == m.p.mu &&
          t.p.nb == m.p.nb && std::isfinite(t.lo))
        return m.estimate() < 0.5 * t.lo && m.reason != "marker CFL";
    for (const DtMax& t : dtmax_)
      if ((t.part == "T" || t.part == "E") && t.p.T0 == m.p.T0 && t.p.mu == m.p.mu && std::isfinite(t.lo))
        return m.estimate() < 0.5 * t.lo;
    return m.estimate() < 0.5 * m.p.check_estimate() && m.reason != "marker CFL";  // check's tension estimate
  }
  // least squares in log dt of dt = max(Ci a, Cv b) over rows (a, b, dt)
  static Fit fit_two(const std::vector<std::array<double, 3>>& d) {
    Fit f;
    f.n = static_cast<int>(d.size());
    if (d.size() < 2) return f;
    auto cost = [&](double li, double lv) {
      const double Ci = std::pow(10.0, li), Cv = std::pow(10.0, lv);
      double s = 0;
      for (const auto& r : d) {
        const double e = std::log(r[2] / std::max(Ci * r[0], Cv * r[1]));
        s += e * e;
      }
      return s;
    };
    double best = INFINITY, bi = 0, bv = 0;
    for (double li = -4; li <= 4; li += 0.05)
      for (double lv = -4; lv <= 5; lv += 0.05)
        if (const double c = cost(li, lv); c < best) { best = c; bi = li; bv = lv; }
    const double ci = bi, cv = bv;
    for (double li = ci - 0.1; li <= ci + 0.1; li += 0.002)
      for (double lv = cv - 0.1; lv <= cv + 0.1; lv += 0.002)
        if (const double c = cost(li, lv); c < best) { best = c; bi = li; bv = lv; }
    f.Ci = std::pow(10.0, bi);
    f.Cv = std::pow(10.0, bv);
    f.rms_log = std::sqrt(best / d.size());
    return f;
  }

  std::string bending_md() const {
    std::ostringstream m;
    std::vector<const DtMax*> b;
    for (const DtMax& d : dtmax_)
      if (d.part == "B") b.push_back(&d);
    if (b.empty()) return "";
    const Params def;
    m << "## B: bending, the Skalak law and markers per dx, explicit against semi-implicit\n\n"
         "run_scene's verdict (convection on), " << def.nx << " x " << def.nx << ", h* = " << num(def.h_star(), 4)
      << ". Eb axis: Hookean T0 = 1 with bending Eb (reference: the circle r0 = 0.5, so the released ellipse is "
         "bent too), mu = 0.1 and 10; Es axis: law skalak (C = 1) without bending, mu = 0.1; markers/dx axis: "
         "T0 = 1, Eb = 1 and 10, mu = 0.1; Nx axis: Nx = 24, 48, 64 (Nb = 2 Nx, h* = 1.68 dx), Eb = 1 with mu = 0.1 "
         "and Eb = 10 with mu = 10, explicit. `explicit`: membrane.semi_implicit = false; `semi`: the stiff-force filter; "
         "`semi+G`: with its residual (membrane.stiff_residual, `--residual`). "
         "`bending estimate` = max(" << kBendCi << " sqrt(rho h*^5/Eb), " << kBendCv << " mu h*^3/Eb), `sphib check`'s "
         "explicit bending limit; `bending-limited`: the limit is below half that of the same membrane without bending (Eb = 0 row) "
         "and the failure is not the markers' CFL (a faster flow, not an unstable force); the fit uses those rows.\n\n"
         "| axis | law | T0 or Es | Eb | mu | Nx | markers/dx | stable dt | unstable dt | failure | bending estimate | "
         "measured / estimate | bending-limited | semi / explicit | runs |\n"
         "|---|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---|---:|---:|\n";
    for (const DtMax* d : b) {
      const bool semi = d->axis.rfind("semi", 0) == 0;
      double ratio = NAN;  // the same point explicit
      if (semi)
        for (const DtMax* e : b)
          if (e->axis == "explicit" + d->axis.substr(d->axis.find(':')) && e->p.T0 == d->p.T0 && e->p.Eb == d->p.Eb &&
              e->p.mu == d->p.mu && e->p.nb == d->p.nb && e->p.nx == d->p.nx && e->p.law == d->p.law)
            ratio = (std::isfinite(d->hi) ? d->estimate() : d->lo) / e->estimate();
      m << "| " << d->axis << " | " << d->p.law << " | " << num(d->p.T0) << " | " << num(d->p.Eb) << " | "
        << num(d->p.mu) << " | " << d->p.nx << " | " << fix(d->p.markers_per_dx(), 2) << " | " << sci(d->lo) << " | "
        << (std::isfinite(d->hi) ? sci(d->hi) : "> " + num(kDtCap)) << " | " << d->reason << " | "
        << (d->p.Eb > 0 ? sci(d->p.bending_estimate()) : "") << " | "
        << (d->p.Eb > 0 ? fix(d->estimate() / d->p.bending_estimate(), 2) : "") << " | "
        << (d->p.Eb > 0 && !semi ? (bending_limited(*d) ? "yes" : "no") : "") << " | "
        << (semi ? (std::isfinite(d->hi) ? "" : ">= ") + fix(ratio, 1) : "") << " | " << d->runs << " |\n";
    }
    const Fit fh = fit_bending(true), fd = fit_bending(false);
    m << "\n### Fitted explicit bending limit\n\n";
    if (fh.n >= 2)
      m << "Over " << fh.n << " bending-limited explicit pairs, least squares in log dt: with h* as the length "
        << "(check's form) **C_i = " << fix(fh.Ci, 3) << "**, **C_v = " << fix(fh.Cv, 3) << "** (rms misfit a factor "
        << fix(std::exp(fh.rms_log), 2) << "); with dx: C_i = " << fix(fd.Ci, 3) << ", C_v = " << fix(fd.Cv, 3)
        << ". The classical explicit estimates for a bending mode k ~ pi/dx: inertial omega^2 = Eb k^5/(2 rho) "
           "(added mass 2 rho/k), viscous rate Eb k^3/(4 mu).\n\n";
    else
      m << "Fewer than two bending-limited explicit pairs: no fit.\n\n";
    return m.str();
  }

  // least squares in log dt over the bracketed (T0, mu) pairs, with L = dx (use_hstar false) or h*
  // The (T0, mu) pair of `part` with the same parameters, if bisected.
  const DtMax* find_pair(const std::string& part, const Params& p) const {
    for (const DtMax& d : dtmax_)
      if (d.part == part && d.p.T0 == p.T0 && d.p.mu == p.mu) return &d;
    return nullptr;
  }
  // Why a limit of T or E lies well below (a factor 1.3) another part's limit for the same pair:
  // T below E: the runner's dx-per-step guard stops runs the bench's loop finds bounded; E (or T)
  // below S: the explicit convection, not the membrane force, sets it. Empty: neither.
  std::string other_limit(const DtMax& d) const {
    if (d.part == "S" || d.part == "X" || !std::isfinite(d.estimate())) return "";
    if (d.part == "T")
      if (const DtMax* e = find_pair("E", d.p); e && std::isfinite(e->estimate()) && d.estimate() < e->estimate() / 1.3)
        return "runner's guard (no-guard limit " + sci(e->estimate()) + ")";
    if (const DtMax* s = find_pair("S", d.p); s && std::isfinite(s->estimate()) && d.estimate() < s->estimate() / 1.3)
      return "convection (Stokes limit " + sci(s->estimate()) + ")";
    return "";
  }
  bool convection_limited(const DtMax& d) const { return !other_limit(d).empty(); }
  Fit fit_tmu(const std::string& part, bool use_hstar, bool skip_convective = true) const {
    std::vector<std::array<double, 3>> d;  // sqrt(rho L^3/T0), mu L/T0, measured dt_max
    for (const DtMax& m : dtmax_)
      if (m.part == part && std::isfinite(m.estimate()) && !(skip_convective && convection_limited(m))) {
        const double L = use_hstar ? m.p.h_star() : m.p.dx();
        d.push_back({std::sqrt(m.p.rho * L * L * L / m.p.T0), m.p.mu * L / m.p.T0, m.estimate()});
      }
    return fit_two(d);
  }

  std::string markdown() const {
    std::ostringstream m;
    const Params def;
    m << "# Stability map of the EPSPH immersed-boundary step (issue 6)\n\n"
      << "Generated by `bench/stability_map`. The oscillating membrane (`cases/membrane_oscillation.toml`) on a "
         "coarse lattice: " << def.nx << " x " << def.nx << " (dx = " << num(def.dx(), 4) << "), Nb = " << def.nb
      << " (" << fix(def.markers_per_dx(), 2) << " markers per grid spacing), h = 1.2 dx, h* = 1.4 h = "
      << num(def.h_star(), 4) << ", rho = 1; defaults T0 = 10, mu = 0.1, dt = 1e-4. Each run goes to t = 0.5 "
         "with at least 500 and at most 4000 steps. **Unstable**: stopped by the runner (RunError: non-finite "
         "values, a particle or marker moving more than dx in a step, a marker with no fluid within 2h, a "
         "fixed point not converging) or total energy (kinetic + elastic) above "
      << kEnergyBound << " x its initial value. **Refused**: the scene was refused at set-up.\n\n"
      << "## Classical estimate\n\n"
         "For an explicit (forward Euler) membrane force the classical limits are, with the grid spacing dx, the "
         "tension T0, density rho and viscosity mu on both sides:\n\n"
         "- inertial: dt < sqrt(rho dx^3 / (2 pi T0)), the capillary time-step constraint of Brackbill, Kothe & "
         "Zemach (1992, J. Comput. Phys. 100:335-354): the period of the shortest capillary wave the grid carries "
         "(omega^2 = T0 k^3 / (2 rho)); for normal perturbations a tensioned membrane is a capillary interface;\n"
         "- viscous: dt < (8/pi) mu dx / T0: in Stokes flow a membrane mode of wavenumber k relaxes at the rate "
         "T0 k / (4 mu), the stiffness analysed for the immersed boundary method by Stockie & Wetton (1999, J. "
         "Comput. Phys. 154:41-64) and Hou & Shi (2008, J. Comput. Phys. 227:8968-8991), who find the explicit "
         "step limited by dt ~ mu h / T0; forward Euler is stable for dt T0 k / (4 mu) <= 2, here at k = pi/dx "
         "(the constant 8/pi is this bench's, from that rate).\n\n"
         "`classical` below = max of the two (C_i = 1/sqrt(2 pi) = " << fix(kClassicalCi, 3) << ", C_v = 8/pi = "
      << fix(kClassicalCv, 3) << " in the form of the fit). Our step takes the membrane force explicitly at X^n, "
         "as the classical analysis assumes, but moves the markers by the semi-implicit trapezoidal rule solved by "
         "fixed point (Eqs. 56-60: u^n at X^n and u^{n+1} at X^{n+1}, not forward Euler), with viscosity by "
         "Crank-Nicolson, and spreads the force with its own kernel of radius h* = " << fix(def.h_star() / def.dx(), 2)
      << " dx, which damps the shortest modes; limits above the classical ones are therefore expected, and the "
         "tables say by how much.\n\n";
    m << grid_md() << dtmax_md("T") << dtmax_md("E") << dtmax_md("S") << resolution_md() << bending_md();
    return m.str();
  }

  // G: the verdicts, dt against one parameter at a time.
  std::string grid_md() const {
    std::ostringstream m;
    const Params def;
    std::map<std::string, std::vector<const Verdict*>> g;
    std::vector<std::string> order;
    for (const Verdict& v : all_)
      if (v.part == "G") {
        if (!g.count(v.axis)) order.push_back(v.axis);
        g[v.axis].push_back(&v);
      }
    if (g.empty()) return "";
    {
      m << "## G: classification, dt against one parameter at a time\n\n"
           "S = stable, U = unstable (reason: N non-finite, P particle CFL, M marker CFL, L marker left the "
           "fluid, F fixed point, E energy growth), R = refused. One parameter varies per table, the others at the "
           "defaults; on the h/dx axis h* stays at its default " << num(def.h_star(), 4) << " (so that the spreading "
           "support fits between membrane and walls), so h*/h falls as h/dx rises; markers per grid spacing are "
           "rounded to whole markers (Nb = round(m 2 pi r0 / dx)).\n\n";
      for (const std::string& a : order) {
        std::vector<double> vals, dts;
        auto value = [&](const Verdict& v) {
          if (a == "T0") return v.p.T0;
          if (a == "mu") return v.p.mu;
          if (a == "markers/dx") return v.p.markers_per_dx();
          if (a == "h/dx") return v.p.hdx;
          return v.p.h_star() / v.p.h();
        };
        for (const Verdict* v : g[a]) {
          if (std::find(vals.begin(), vals.end(), value(*v)) == vals.end()) vals.push_back(value(*v));
          if (std::find(dts.begin(), dts.end(), v->p.dt) == dts.end()) dts.push_back(v->p.dt);
        }
        m << "| " << a << " \\ dt |";
        for (double dt : dts) m << " " << num(dt, 3) << " |";
        m << "\n|---|";
        for (size_t k = 0; k < dts.size(); ++k) m << "---|";
        m << "\n";
        for (double x : vals) {
          m << "| " << num(x, 3) << " |";
          for (double dt : dts) {
            std::string c = " ";
            for (const Verdict* v : g[a])
              if (value(*v) == x && v->p.dt == dt) {
                if (v->verdict == "stable") c = "S";
                else if (v->verdict == "refused") c = "R";
                else {
                  const std::map<std::string, std::string> code{{"non-finite", "N"}, {"particle CFL", "P"},
                                                                {"marker CFL", "M"}, {"marker left fluid", "L"},
                                                                {"fixed point", "F"}, {"energy growth", "E"}};
                  c = "U" + (code.count(v->reason) ? code.at(v->reason) : std::string("?"));
                }
              }
            m << " " << c << " |";
          }
          m << "\n";
        }
        m << "\n";
      }
    }
    return m.str();
  }

  // T, E, S: the largest stable dt over (T0, mu), its fit and the comparison with the estimates.
  std::string dtmax_md(const std::string& part) const {
    std::ostringstream m;
    const Params def;
    std::vector<const DtMax*> t;
    for (const DtMax& d : dtmax_)
      if (d.part == part) t.push_back(&d);
    const Fit fd = fit_tmu(part, false), fh = fit_tmu(part, true);
    if (t.empty()) return "";
    {
      m << "## " << part << ": largest stable dt over (T0, mu)"
        << (part == "T"   ? ", run_scene's verdict (convection on)"
            : part == "E" ? ", no dx-per-step guards (the bench's loop: blow-up = non-finite, energy > 10 E0, fixed "
                            "point failing, marker leaving the fluid), convection on"
                          : ", no dx-per-step guards, convection off (Stokes: only the elastic limit is left)")
        << "\n\n"
           "Bracket [largest stable, smallest unstable) from a bisection to a factor 1.1; `check` = "
           "max(0.3 sqrt(rho h*^3/T0), 10 mu h*/T0) of `sphib check`; fit = max(C_i sqrt(rho dx^3/T0), C_v mu dx/T0) "
           "with the constants below; regime = the larger term of the fit, or, where the limit lies more than a "
           "factor 1.3 below that of another part for the same pair, `runner's guard` (T below E: run_scene's "
           "dx-per-step check stops runs that stay bounded without it) or `convection` (below S: the explicit "
           "convection sets the limit). The map depends on T0 and mu only through mu/sqrt(rho T0 dx) (with rho "
           "and the geometry fixed, (T0, mu) -> (l^2 T0, l mu) rescales time by 1/l), hence the repeated "
           "brackets. `classical` = max(sqrt(rho dx^3/(2 pi T0)), (8/pi) mu dx/T0), the explicit-force estimate "
           "(section *Classical estimate* above).\n\n"
           "| T0 | mu | stable dt | unstable dt | failure at the limit | check estimate | measured / check | "
           "classical | measured / classical | "
           "fit | measured / fit | regime | max\\|u\\| dt/dx at the stable dt | max\\|u\\| stable / at failure | runs |\n"
           "|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---|---:|---|---:|\n";
      for (const DtMax* d : t) {
        const double dx = d->p.dx(), inert = fd.Ci * std::sqrt(d->p.rho * dx * dx * dx / d->p.T0),
                     visc = fd.Cv * d->p.mu * dx / d->p.T0, model = std::max(inert, visc);
        m << "| " << num(d->p.T0) << " | " << num(d->p.mu) << " | " << sci(d->lo) << " | "
          << (std::isfinite(d->hi) ? sci(d->hi) : "> " + num(kDtCap)) << " | " << d->reason << " | "
          << sci(d->p.check_estimate()) << " | " << fix(d->estimate() / d->p.check_estimate(), 2) << " | "
          << sci(d->p.classical()) << " | " << fix(d->estimate() / d->p.classical(), 1) << " | "
          << sci(model) << " | " << fix(d->estimate() / model, 2) << " | "
          << (convection_limited(*d) ? other_limit(*d)
              : std::isfinite(model) ? (inert >= visc ? "inertial" : "viscous") : "")
          << " | " << fix(d->cfl_stable, 3)
          << " | " << sci(d->u_stable) << " / " << sci(d->u_fail) << " | " << d->runs << " |\n";
      }
      m << "\n### Fitted constants\n\n";
      if (fd.n >= 2) {
        const Fit fa = fit_tmu(part, false, false);
        m << "Over " << fd.n << " bracketed pairs (dt_max = geometric mean of the bracket"
          << (fa.n != fd.n ? ", pairs limited by the runner's guard or by convection left out" : "") << "), least squares in log dt:\n\n"
          << "- with dx = " << num(def.dx(), 4) << ": **C_i = " << fix(fd.Ci, 3) << "**, **C_v = " << fix(fd.Cv, 3)
          << "**; rms misfit a factor " << fix(std::exp(fd.rms_log), 2);
        if (fa.n != fd.n)
          m << " (all " << fa.n << " pairs: C_i = " << fix(fa.Ci, 3) << ", C_v = " << fix(fa.Cv, 3) << ", misfit a factor "
            << fix(std::exp(fa.rms_log), 2) << ")";
        m << ";\n"
          << "- the same with h* = " << num(def.h_star(), 4) << " as the length (check's form): C_i = " << fix(fh.Ci, 3)
          << ", C_v = " << fix(fh.Cv, 3) << " (check uses 0.3 and 10);\n"
          << "- crossover at mu / sqrt(rho T0 dx) = C_i/C_v = " << fix(fd.Ci / fd.Cv, 3)
          << ", i.e. viscosity mu* = (C_i/C_v) sqrt(rho dx T0): viscous above, inertial below: ";
        for (double T0 : {1.0, 10.0, 100.0, 1e3, 1e4})
          m << "T0 = " << num(T0) << ": " << sci(fd.Ci / fd.Cv * std::sqrt(def.rho * def.dx() * T0)) << (T0 < 1e4 ? "; " : ".\n");
        double lo = INFINITY, hi = 0;
        for (const DtMax* d : t)
          if (std::isfinite(d->estimate()) && !convection_limited(*d)) {
            lo = std::min(lo, d->estimate() / d->p.check_estimate());
            hi = std::max(hi, d->estimate() / d->p.check_estimate());
          }
        m << "- measured / `sphib check` estimate: " << fix(lo, 2) << " to " << fix(hi, 2)
          << (fa.n != fd.n ? " (those pairs left out)" : "") << ";\n";
        double clo = INFINITY, chi = 0, cap_lo = INFINITY, cap_hi = 0;
        int ncap = 0;
        for (const DtMax* d : t) {
          if (std::isfinite(d->estimate()) && !convection_limited(*d)) {
            clo = std::min(clo, d->estimate() / d->p.classical());
            chi = std::max(chi, d->estimate() / d->p.classical());
          }
          if (std::isfinite(d->lo) && !std::isfinite(d->hi)) {
            ++ncap;
            cap_lo = std::min(cap_lo, d->p.classical());
            cap_hi = std::max(cap_hi, d->p.classical());
          }
        }
        m << "- against the classical explicit estimate: measured / classical = " << fix(clo, 1) << " to " << fix(chi, 1)
          << (fa.n != fd.n ? " (the same pairs)" : "");
        if (ncap) m << "; the " << ncap << " pairs stable up to the cap dt = " << num(kDtCap) << " are not bracketed "
                    << "(classical estimate there " << sci(cap_lo) << " to " << sci(cap_hi) << ")";
        m << "; fitted over classical constants: C_i / (1/sqrt(2 pi)) = " << fix(fd.Ci / kClassicalCi, 1)
          << ", C_v / (8/pi) = " << fix(fd.Cv / kClassicalCv, 1) << ".\n";
      }
      m << "\n";
    }
    return m.str();
  }

  // X: the largest stable dt against the resolution parameters, and its exponents.
  std::string resolution_md() const {
    std::ostringstream m;
    std::vector<const DtMax*> x;
    for (const DtMax& d : dtmax_)
      if (d.part == "X") x.push_back(&d);
    if (x.empty()) return "";
    {
      m << "## X: largest stable dt against resolution parameters (T0 = 1e3; inertial: mu = 1e-3, viscous: "
           "mu = 10; runner: run_scene's verdict, convection on; elastic: the bench's loop without dx-per-step "
           "guards, convection off)\n\n"
           "| point : axis | Nx | Nb | markers/dx | h/dx | h*/h | h* | stable dt | unstable dt | failure | "
           "check estimate | measured / check | max\\|u\\| dt/dx at the stable dt | max\\|u\\| stable / at failure |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---|\n";
      for (const DtMax* d : x)
        m << "| " << d->axis << " | " << d->p.nx << " | " << d->p.nb << " | " << fix(d->p.markers_per_dx(), 2) << " | "
          << num(d->p.hdx, 3) << " | " << fix(d->p.h_star() / d->p.h(), 2) << " | " << num(d->p.h_star(), 4) << " | "
          << sci(d->lo) << " | " << (std::isfinite(d->hi) ? sci(d->hi) : "> " + num(kDtCap)) << " | " << d->reason
          << " | " << sci(d->p.check_estimate()) << " | " << fix(d->estimate() / d->p.check_estimate(), 2) << " | "
          << fix(d->cfl_stable, 3) << " | " << sci(d->u_stable) << " / " << sci(d->u_fail) << " |\n";
      // exponents against dx (Nx axis), h* (h*/h axis), h (h/dx axis at fixed h*)
      m << "\nObserved exponents (least squares of log dt_max):\n\n";
      for (const std::string where : {"runner/inertial", "runner/viscous", "elastic/inertial", "elastic/viscous"})
        for (const auto& [axis, what] : std::vector<std::pair<std::string, std::string>>{
                 {"Nx", "dx (h, h*, marker spacing in proportion)"}, {"h*/h", "h* (dx, h fixed)"},
                 {"h/dx", "h (dx, h* fixed)"}, {"markers/dx", "marker spacing ds (dx, h, h* fixed)"}}) {
          // all points, and those with h* >= 0.8 h (a spreading kernel much narrower than the fluid's
          // destabilises on its own, see the table)
          for (const bool wide : {false, true}) {
            std::vector<std::pair<double, double>> pts;
            int all = 0;
            for (const DtMax* d : x) {
              if (d->axis != where + ":" + axis || !std::isfinite(d->estimate())) continue;
              ++all;
              if (wide && d->p.h_star() < 0.8 * d->p.h()) continue;
              double len = d->p.dx();
              if (axis == "h*/h") len = d->p.h_star();
              if (axis == "h/dx") len = d->p.h();
              if (axis == "markers/dx") len = 2 * M_PI * kR0 / d->p.nb;
              pts.emplace_back(len, d->estimate());
            }
            const int n = static_cast<int>(pts.size());
            if (wide && n == all) continue;  // nothing left out
            if (n >= 2)
              m << "- " << where << ", dt_max ~ " << what << "^a: a = " << fix(power_law_exponent(pts), 2) << " ("
                << n << " points" << (wide ? ", h* >= 0.8 h only" : "") << ")\n";
          }
        }
      m << "\n";
    }
    return m.str();
  }

  void write() const {
    std::ostringstream c;
    c << "part,axis,T0,mu,nx,dx,nb,markers_per_dx,h_over_dx,h,h_star,h_star_over_h,dt,steps,verdict,reason,"
         "steps_done,t_done,energy_ratio,max_speed,cfl,area_error,cpu_s,check_estimate,message,law,Eb,semi_implicit\n";
    for (const Verdict& v : all_)
      c << v.part << ',' << csv_text(v.axis) << ',' << num(v.p.T0) << ',' << num(v.p.mu) << ',' << v.p.nx << ','
        << csv_num(v.p.dx()) << ',' << v.p.nb << ',' << csv_num(v.p.markers_per_dx()) << ',' << num(v.p.hdx) << ','
        << csv_num(v.p.h()) << ',' << csv_num(v.p.h_star()) << ',' << csv_num(v.p.h_star() / v.p.h()) << ','
        << csv_num(v.p.dt) << ',' << v.p.steps() << ',' << v.verdict << ',' << v.reason << ',' << v.steps_done << ','
        << csv_num(v.t_done) << ',' << csv_num(v.energy_ratio) << ',' << csv_num(v.max_speed) << ','
        << csv_num(v.cfl()) << ',' << csv_num(v.area_error) << ','
        << csv_num(v.cpu) << ',' << csv_num(v.p.check_estimate()) << ',' << csv_text(v.message.substr(0, 200)) << ','
        << v.p.law << ',' << num(v.p.Eb) << ',' << v.p.semi << '\n';
    sphib::write_file_atomic((o_.out / "stability_runs.csv").string(), c.str());
    std::ostringstream d;
    std::map<std::string, Fit> fits;
    for (const char* part : {"T", "E", "S"}) fits[part] = fit_tmu(part, false);
    d << "part,axis,T0,mu,nx,dx,nb,markers_per_dx,h_over_dx,h,h_star,h_star_over_h,dt_stable,dt_unstable,dt_max,"
         "reason,runs,cfl_at_stable,u_stable,u_fail,check_estimate,fit_inertial,fit_viscous,fit_Ci,fit_Cv,"
         "classical_estimate,law,Eb,semi_implicit\n";
    for (const DtMax& m : dtmax_) {
      const double dx = m.p.dx();
      const Fit f = fits.count(m.part) ? fits[m.part] : fits["T"];
      d << m.part << ',' << csv_text(m.axis) << ',' << num(m.p.T0) << ',' << num(m.p.mu) << ',' << m.p.nx << ','
        << csv_num(dx) << ',' << m.p.nb << ',' << csv_num(m.p.markers_per_dx()) << ',' << num(m.p.hdx) << ','
        << csv_num(m.p.h()) << ',' << csv_num(m.p.h_star()) << ',' << csv_num(m.p.h_star() / m.p.h()) << ','
        << csv_num(m.lo) << ',' << csv_num(m.hi) << ',' << csv_num(m.estimate()) << ',' << csv_text(m.reason) << ','
        << m.runs << ',' << csv_num(m.cfl_stable) << ',' << csv_num(m.u_stable) << ',' << csv_num(m.u_fail) << ',' << csv_num(m.p.check_estimate()) << ','
        << csv_num(f.Ci * std::sqrt(m.p.rho * dx * dx * dx / m.p.T0)) << ',' << csv_num(f.Cv * m.p.mu * dx / m.p.T0)
        << ',' << csv_num(f.Ci) << ',' << csv_num(f.Cv) << ',' << csv_num(m.p.classical()) << ',' << m.p.law << ','
        << num(m.p.Eb) << ',' << m.p.semi << '\n';
    }
    sphib::write_file_atomic((o_.out / "stability_dtmax.csv").string(), d.str());
    sphib::write_file_atomic((o_.out / "stability_map.md").string(), markdown());
  }

  // --report-only: the measurements back from the two CSV files (Params from the recorded values;
  // h* is taken as recorded, which gives the same h*, h*/h and estimates).
  void load() {
    auto read = [](const fs::path& f) {
      if (!std::ifstream(f)) throw std::runtime_error("--report-only: cannot read " + f.string());
      return sphib::bench::read_csv_rows(f.string());
    };
    auto d = [](const std::map<std::string, std::string>& r, const char* k) {
      const auto it = r.find(k);
      return it == r.end() || it->second.empty() ? NAN : std::strtod(it->second.c_str(), nullptr);
    };
    auto params = [&](const std::map<std::string, std::string>& r) {
      Params p;
      p.T0 = d(r, "T0");
      p.mu = d(r, "mu");
      p.nx = static_cast<int>(d(r, "nx"));
      p.nb = static_cast<int>(d(r, "nb"));
      p.hdx = d(r, "h_over_dx");
      p.h_star_abs = d(r, "h_star");
      if (r.count("law") && !r.at("law").empty()) p.law = r.at("law");  // (files before part B: Hookean, no bending)
      if (const double Eb = d(r, "Eb"); std::isfinite(Eb)) p.Eb = Eb;
      if (const double s = d(r, "semi_implicit"); std::isfinite(s)) p.semi = static_cast<int>(s);
      const std::string part = r.at("part"), axis = r.at("axis");
      p.residual = axis.rfind("semi+G", 0) == 0;
      p.convection = !(part == "S" || axis.rfind("elastic/", 0) == 0);
      p.guard = part == "G" || part == "T" || axis.rfind("runner/", 0) == 0;
      return p;
    };
    auto axis = [](std::string a) {  // csv_text wrote "T0,mu" as "T0;mu"
      for (char& c : a)
        if (c == ';') c = ',';
      return a;
    };
    for (const auto& r : read(o_.out / "stability_runs.csv")) {
      Verdict v;
      v.part = r.at("part");
      v.axis = axis(r.at("axis"));
      v.p = params(r);
      v.p.dt = d(r, "dt");
      v.verdict = r.at("verdict");
      v.reason = r.at("reason");
      v.message = r.at("message");
      v.steps_done = static_cast<long>(d(r, "steps_done"));
      v.t_done = d(r, "t_done");
      v.energy_ratio = d(r, "energy_ratio");
      v.max_speed = d(r, "max_speed");
      v.area_error = d(r, "area_error");
      v.cpu = d(r, "cpu_s");
      all_.push_back(v);
    }
    for (const auto& r : read(o_.out / "stability_dtmax.csv")) {
      DtMax m;
      m.part = r.at("part");
      m.axis = axis(r.at("axis"));
      m.p = params(r);
      m.lo = d(r, "dt_stable");
      m.hi = d(r, "dt_unstable");
      m.reason = r.at("reason");
      m.runs = static_cast<int>(d(r, "runs"));
      m.cfl_stable = d(r, "cfl_at_stable");
      m.u_stable = d(r, "u_stable");
      m.u_fail = d(r, "u_fail");
      dtmax_.push_back(m);
    }
    std::printf("read %zu runs and %zu bisections from %s\n", all_.size(), dtmax_.size(), o_.out.c_str());
  }

  void run_all() {
    const auto t0 = Clock::now();
    if (o_.report_only) {
      load();
      write();
      std::printf("rewrote %s/stability_runs.csv, stability_dtmax.csv, stability_map.md\n", o_.out.c_str());
      return;
    }
    if (o_.parts.find('G') != std::string::npos) part_g();
    if (o_.parts.find('T') != std::string::npos) part_t("T");
    if (o_.parts.find('E') != std::string::npos) part_t("E");
    if (o_.parts.find('S') != std::string::npos) part_t("S");
    if (o_.parts.find('X') != std::string::npos) part_x();
    if (o_.parts.find('B') != std::string::npos) part_b();
    write();
    std::printf("\n%s\n%zu runs, total %.0f s wall\n", markdown().c_str(), memo_.size(), seconds_since(t0));
  }

 private:
  Options o_;
  std::map<std::string, Verdict> memo_;
  std::vector<Verdict> all_;
  std::vector<DtMax> dtmax_;
};

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Where the EPSPH immersed-boundary step is stable", "stability_map"};
  add_scene_options(app, o, "GTESXB",
                    "G classification grid (dt x one parameter), T largest stable dt over (T0, mu), E as T without the "
                    "runner's dx-per-step guards (the bench's loop), S as E with convection off, X largest stable dt "
                    "against Nx, markers/dx, h/dx, h*/h, B bending (Eb), the Skalak law (Es) and markers/dx with bending, "
                    "explicit and semi-implicit");
  app.add_flag("--residual", o.residual,
               "part B: the semi-implicit runs with membrane.stiff_residual = true (axes semi+G:Eb, semi+G:Es only)");
  app.add_flag("--report-only", o.report_only, "run nothing: read DIR's two CSV files back, rewrite them and the Markdown");
  return run_main(app, argc, argv, [&] {
    Bench(o).run_all();
    return 0;
  });
}
