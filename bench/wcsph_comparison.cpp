// Benchmark (not a test): weakly compressible SPH (fluid/moving/wcsph.hpp) against EPSPH
// (fluid/eulerian/eulerian.hpp) on the problems of Vukcevic, Werner & Degiuli (2012) ["V"] and
// Coelho, Oliveira, Brasil & Maruzewski ["C"] (issue 8):
//
//  A  the constructed Stokes solution of C Section 4 (Eqs. 23-24) in the unit square, both methods:
//     the mean square deviation of C Eq. (27) against h/dx for 900 and 1600 particles, beside the
//     paper's Tables 1 and 2;
//  B  start-up Poiseuille and Couette with V's parameters (WCSPH): velocity profiles at several
//     times against V Eqs. (19) and (23), the rms error over time, and the choice of c, EOS and
//     wall velocity;
//  C  error against wall time, EPSPH and WCSPH, on Poiseuille, Couette, the constructed solution
//     and the lid-driven cavity at Re = 100 (Ghia et al.), every run through the scene runner.
//
//   wcsph_comparison [--parts ABC] [--out DIR] [--cases DIR] [--quick]      (--help)
//
// Every run is a scene of cases/ loaded with load_scene(path, overrides) and run by run_scene
// (io/run.hpp), the constructed solution with its force field and observers attached in C++ (a
// scene file cannot express a force field). Writes DIR/wcsph_comparison.csv (one row per run),
// DIR/wcsph_profiles.csv (part B) and DIR/wcsph_comparison.md (tables), and prints the tables.
// Runs are single-threaded and report wall and CPU seconds: on a shared machine CPU time is the
// fairer clock.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "bench/common.hpp"
#include "fluid/common/exact.hpp"
#include "fluid/moving/wcsph.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"

namespace fs = std::filesystem;
using namespace sphib;

namespace {

// ---- The constructed Stokes solution, C Section 4 ------------------------------------------------
//
// C Eqs. (23)-(24): u1 = x^2 (1-x)^2 (2y - 6y^2 + 4y^3), u2 = -y^2 (1-y)^2 (2x - 6x^2 + 4x^3).
// With phi(s) = s^2 (1-s)^2:  phi' = 2s - 6s^2 + 4s^3 = 2s(1-s)(1-2s),  phi'' = 2 - 12s + 12s^2,
// phi''' = -12 + 24s, the field is u = (phi(x) phi'(y), -phi(y) phi'(x)): the curl of the stream
// function psi = phi(x) phi(y), so div u = phi'(x) phi'(y) - phi'(y) phi'(x) = 0, and u = 0 on the
// four walls (phi = phi' = 0 at s = 0, 1). Its Laplacian, term by term:
//   lap u1 = phi''(x) phi'(y) + phi(x) phi'''(y)
//   lap u2 = -(phi'(x) phi''(y) + phi'''(x) phi(y))
// With a constant pressure, Stokes' equation C Eq. (21), F = grad P / rho - nu lap u, gives the body
// force per unit mass F = -nu lap u; per unit volume (the FluidSolver contract) rho F.
// (C Eqs. 25-26 are -lap u with nu = 1 but garbled: the x1^4, x1^3 and x1^2 coefficients of F1
// agree with -lap u1 above, the x1 and x1^0 coefficients carry stray constants -2 and +1.)
// U = max |u| = phi(1/2) max phi' = (1/16)(sqrt(3)/9) = sqrt(3)/144, at (1/2, (3 -+ sqrt 3)/6).
double ph(double s) { return s * s * (1 - s) * (1 - s); }
double ph1(double s) { return 2 * s - 6 * s * s + 4 * s * s * s; }
double ph2(double s) { return 2 - 12 * s + 12 * s * s; }
double ph3(double s) { return -12 + 24 * s; }
const double kU = std::sqrt(3.0) / 144.0;

Eigen::Vector2d stokes_u(double x, double y) { return {ph(x) * ph1(y), -ph(y) * ph1(x)}; }
Eigen::Vector2d stokes_lap_u(double x, double y) {
  return {ph2(x) * ph1(y) + ph(x) * ph3(y), -(ph1(x) * ph2(y) + ph3(x) * ph(y))};
}

// Largest |lap u (analytic) - lap u (5-point finite differences)| / max |lap u| on a grid: the
// derivation above, checked.
double check_laplacian() {
  const double d = 1e-4;
  double err = 0, scale = 0;
  for (int i = 1; i < 20; ++i)
    for (int j = 1; j < 20; ++j) {
      const double x = i / 20.0, y = j / 20.0;
      const Eigen::Vector2d fd = (stokes_u(x + d, y) + stokes_u(x - d, y) + stokes_u(x, y + d) +
                                  stokes_u(x, y - d) - 4 * stokes_u(x, y)) / (d * d);
      err = std::max(err, (fd - stokes_lap_u(x, y)).cwiseAbs().maxCoeff());
      scale = std::max(scale, stokes_lap_u(x, y).cwiseAbs().maxCoeff());
    }
  return err / scale;
}

// C Eq. (27) and friends over the particles.
struct Deviation {
  double msd_u = 0;    // (1/n) sum (u_sph - u_a)^2, u component: C Eq. (27) literally
  double msd_uv = 0;   // the same over both components
  double max_u = 0;    // max |u_sph - u_a|, u component ("maximum deviation")
};
Deviation stokes_deviation(const FluidSolver& f) {
  Deviation d;
  const int n = f.size();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d ue = stokes_u(f.x()(i, 0), f.x()(i, 1));
    const double du = f.u()(i, 0) - ue.x(), dv = f.u()(i, 1) - ue.y();
    d.msd_u += du * du;
    d.msd_uv += du * du + dv * dv;
    d.max_u = std::max(d.max_u, std::fabs(du));
  }
  d.msd_u /= n;
  d.msd_uv /= n;
  return d;
}

// C Tables 1 (1600 particles) and 2 (900): h/dx, eps, maximum deviation.
struct PaperRow {
  int n;
  double hdx, eps, maxdev;
};
const PaperRow kPaper[] = {{40, 1.1, 0.03430, 0.0630}, {40, 1.2, 0.03100, 0.0567}, {40, 1.5, 0.00380, 0.0115},
                           {40, 1.6, 0.00048, 0.0110}, {40, 1.7, 0.00590, 0.0130}, {40, 2.0, 0.07210, 0.1518},
                           {30, 1.2, 0.0045, 0.0157},  {30, 1.3, 0.0011, 0.0144},  {30, 1.6, 0.1078, 0.2249},
                           {30, 2.7, 10.517, 21.509}};
const PaperRow* paper_row(int n, double hdx) {
  for (const auto& r : kPaper)
    if (r.n == n && std::fabs(r.hdx - hdx) < 1e-9) return &r;
  return nullptr;
}

// ---- Runs ---------------------------------------------------------------------------------------

struct Options {
  std::string parts = "ABC";
  fs::path out = "bench_out/wcsph";
  fs::path cases = fs::path(__FILE__).parent_path().parent_path() / "cases";  // the source tree's
  bool quick = false;
};

struct Run {
  std::string part, problem, method, error_name;
  int nx = 0, ny = 0;
  double hdx = 0, dt = 0, t_end = 0;
  long steps = 0;
  double error = NAN, error2 = NAN, error3 = NAN;  // the problem's error measures (see error_name)
  double wall = 0, cpu = 0, dvar = NAN;
  std::string note;
};

std::string num(double v, int prec = 3) { return std::isnan(v) ? "-" : bench::num(v, prec); }
using bench::cpu_seconds;

class Bench {
 public:
  explicit Bench(Options o) : o_(std::move(o)), cases_(o_.cases) {
    fs::create_directories(o_.out);
  }

  // Loads cases/<file> with the overrides, lets `attach` add C++ parts, runs it, returns the summary.
  nlohmann::json run(const std::string& file, const std::vector<std::string>& sets, const std::string& tag,
                     const std::function<void(Scene&)>& attach, Run& r) {
    Scene s = load_scene((cases_ / file).string(), sets);
    if (attach) attach(s);
    r.method = to_string(s.method);
    r.nx = s.sim.fluid.nx;
    r.ny = s.sim.fluid.ny;
    r.hdx = s.sim.fluid.h_over_dx;
    r.dt = s.sim.fluid.dt;
    RunOptions ro;
    ro.out_dir = (o_.out / "runs" / tag).string();
    fs::remove_all(ro.out_dir);
    const double c0 = cpu_seconds();
    nlohmann::json j;
    try {
      j = run_scene(s, ro);
    } catch (const std::exception& e) {
      r.note = e.what();
      std::cerr << "  " << tag << ": " << e.what() << "\n";
      r.cpu = cpu_seconds() - c0;
      return nlohmann::json();
    }
    r.cpu = cpu_seconds() - c0;
    r.t_end = j["time"].get<double>();
    r.steps = j["steps"].get<long>();
    r.wall = j["wall_seconds"].get<double>();
    if (j.contains("max_density_variation")) r.dvar = j["max_density_variation"].get<double>();
    return j;
  }

  void add(const Run& r) {
    runs_.push_back(r);
    std::printf("  %-2s %-12s %-8s %3dx%-3d h/dx %-5s dt %-9s steps %-6ld %s = %-9s wall %7.2f s cpu %7.2f s%s%s\n",
                r.part.c_str(), r.problem.c_str(), r.method.c_str(), r.nx, r.ny, num(r.hdx).c_str(), num(r.dt).c_str(),
                r.steps, r.error_name.c_str(), num(r.error).c_str(), r.wall, r.cpu,
                std::isnan(r.dvar) ? "" : (" drho " + num(r.dvar, 2)).c_str(), r.note.empty() ? "" : (" [" + r.note.substr(0, 80) + "]").c_str());
    std::fflush(stdout);
    write();
  }

  // ---- A: the constructed Stokes solution ----
  Run stokes(const std::string& method, int n, double hdx, const std::string& part) {
    Run r;
    r.part = part;
    r.problem = "stokes";
    r.error_name = "msd_u/U^2";
    const bool wc = method == "wcsph";
    const std::string file = wc ? "stokes_constructed_wcsph.toml" : "stokes_constructed_epsph.toml";
    std::vector<std::string> sets{"grid.nx=" + std::to_string(n), "grid.ny=" + std::to_string(n),
                                  "kernel.h_over_dx=" + num(hdx, 6)};
    if (wc) {
      // dt: 0.9 of C Eq. (19) (the viscous term: c = 120 leaves the acoustic one far above)
      const Scene s = load_scene((cases_ / file).string(), sets);
      const double h = hdx / n, nu = s.sim.fluid.mu / s.sim.fluid.rho;
      std::ostringstream d;
      d << std::setprecision(6) << 0.9 * coelho_dt_limit(h, s.sim.fluid.wcsph.c, nu);
      sets.push_back("time.dt=" + d.str());
    }
    auto attach = [](Scene& s) {
      const double rho = s.sim.fluid.rho, nu = s.sim.fluid.mu / rho;
      s.sim.body_force_field = [rho, nu](double x, double y, double) -> Eigen::Vector2d {
        return -rho * nu * stokes_lap_u(x, y);  // rho F, F = -nu lap u
      };
      s.observers.push_back({"msd_u", [](const Simulation& sim) { return stokes_deviation(sim.fluid()).msd_u; }});
      s.observers.push_back({"msd_uv", [](const Simulation& sim) { return stokes_deviation(sim.fluid()).msd_uv; }});
      s.observers.push_back({"max_dev_u", [](const Simulation& sim) { return stokes_deviation(sim.fluid()).max_u; }});
    };
    const nlohmann::json j = run(file, sets, method + "_stokes_" + std::to_string(n) + "_h" + num(hdx), attach, r);
    if (!j.is_null()) {
      r.error = j["msd_u"].get<double>() / (kU * kU);
      r.error2 = j["max_dev_u"].get<double>() / kU;
      r.error3 = std::sqrt(j["msd_uv"].get<double>()) / kU;
    }
    return r;
  }

  void part_a() {
    std::printf("A: constructed Stokes solution (C Eqs. 23-24), F = -nu lap u; derivation checked by finite "
                "differences: max |lap u - FD| / max |lap u| = %.1e\n", check_laplacian());
    std::vector<std::pair<int, std::vector<double>>> grid{{40, {1.1, 1.2, 1.3, 1.5, 1.6, 1.7, 2.0}},
                                                          {30, {1.2, 1.3, 1.5, 1.6, 2.0, 2.7}}};
    if (o_.quick) grid = {{30, {1.3, 1.6}}};
    for (const auto& [n, hs] : grid)
      for (double hdx : hs)
        for (const char* m : {"wcsph", "eulerian"}) add(stokes(m, n, hdx, "A"));
  }

  // ---- B: Vukcevic's Poiseuille and Couette, profiles and choices ----
  void part_b() {
    std::printf("B: Vukcevic et al. Poiseuille and Couette (WCSPH): profiles, rms error over time, choices\n");
    for (const char* problem : {"poiseuille", "couette"}) {
      const bool couette = std::string(problem) == "couette";
      const std::string file = std::string("wcsph_") + problem + ".toml";
      Scene s = load_scene((cases_ / file).string());
      const FluidParams& fp = s.sim.fluid;
      const double l = fp.domain.Ly(), nu = fp.mu / fp.rho;
      const double U = couette ? fp.domain.wall_velocity[Top].x() : s.sim.body_force.x() / fp.rho * l * l / (8 * nu);
      auto exact_u = [&](double y, double t) {
        return couette ? exact::couette_u(y, t, nu, U, l) : U * exact::poiseuille_u(y / l, t * U / l, U * l / nu);
      };
      WcsphFluid f(fp);
      Mat2 F = Mat2::Zero(f.size(), 2);
      F.col(0).setConstant(s.sim.body_force.x());
      F.col(1).setConstant(s.sim.body_force.y());
      const std::vector<double> times{0.0225, 0.045, 0.1125, 0.225, 0.45, 1.0};
      const int ny = fp.ny;
      for (double T : times) {
        while (f.time() < T - 0.5 * fp.dt) f.step(F);
        // row means of u (particles keep their rows in these unidirectional flows)
        std::vector<double> sum(ny, 0.0);
        std::vector<int> cnt(ny, 0);
        double e = 0;
        for (int i = 0; i < f.size(); ++i) {
          const int row = std::min(ny - 1, std::max(0, static_cast<int>(std::floor(f.x()(i, 1) / f.lattice().dy))));
          sum[row] += f.u()(i, 0);
          ++cnt[row];
          e += std::pow(f.u()(i, 0) - exact_u(f.x()(i, 1), f.time()), 2) + std::pow(f.u()(i, 1), 2);
        }
        for (int row = 0; row < ny; ++row) {
          const double y = (row + 0.5) * f.lattice().dy;
          const double us = cnt[row] ? sum[row] / cnt[row] / U : NAN, ue = exact_u(y, f.time()) / U;
          profiles_ << problem << "," << f.time() << "," << y / l << "," << us << "," << ue << "\n";
          for (double yq : {0.1, 0.25, 0.5, 0.75, 0.9})  // the rows nearest these y / l, for the tables
            if (std::fabs(y / l - yq) <= 0.5 * f.lattice().dy / l) profile_pts_.push_back({problem, f.time(), y / l, us, ue});
        }
        rms_time_.push_back({problem, f.time(), std::sqrt(e / f.size()) / U});
      }
      // Choices: the paper's c against C Eq. (5) with delta = 1%, Morris and Tait EOS, Morris's
      // extrapolated wall velocity or the plain wall velocity (WcsphOptions, C++ only).
      const double L = l, F0 = couette ? 0.0 : s.sim.body_force.x() / fp.rho, delta = 0.01;
      const double c_eq5 = std::sqrt(std::max({U * U / delta, nu * U / (L * delta), F0 * L / delta}));
      struct Choice {
        std::string eos;
        double c;
        bool extrapolate;
        std::string label;
      };
      std::vector<Choice> choices{{"morris", fp.wcsph.c, true, "paper c, Morris EOS"},
                                  {"morris", fp.wcsph.c, false, "paper c, Morris EOS, plain wall velocity"},
                                  {"tait", fp.wcsph.c, true, "paper c, Tait EOS"},
                                  {"morris", c_eq5, true, "C Eq. 5 c, Morris EOS"},
                                  {"tait", c_eq5, true, "C Eq. 5 c, Tait EOS"},
                                  {"morris", 10 * U, true, "c = 10 U, Morris EOS"}};
      if (o_.quick) choices.resize(2);
      for (const Choice& ch : choices) {
        FluidParams p = fp;
        p.wcsph.eos = enum_value(ch.eos, kEos);
        p.wcsph.c = ch.c;
        WcsphOptions wo;
        wo.morris_extrapolation = ch.extrapolate;
        Run r;
        r.part = "B";
        r.problem = problem;
        r.method = "wcsph";
        r.error_name = "rms/U";
        r.nx = p.nx;
        r.ny = p.ny;
        r.hdx = p.h_over_dx;
        r.dt = p.dt;
        r.note = ch.label + ", c = " + num(ch.c);
        const auto t0 = bench::Clock::now();
        const double c0 = cpu_seconds();
        try {
          WcsphFluid g(p, wo);
          while (g.time() < 1.0 - 0.5 * p.dt) g.step(F);
          double e = 0;
          for (int i = 0; i < g.size(); ++i)
            e += std::pow(g.u()(i, 0) - exact_u(g.x()(i, 1), g.time()), 2) + std::pow(g.u()(i, 1), 2);
          r.error = std::sqrt(e / g.size()) / U;
          r.steps = g.steps();
          r.t_end = g.time();
          r.dvar = g.max_density_variation();
        } catch (const std::exception& e) {
          r.note += std::string(": ") + e.what();
        }
        r.wall = seconds_since(t0);
        r.cpu = cpu_seconds() - c0;
        add(r);
      }
    }
    write_text(o_.out / "wcsph_profiles.csv", "problem,t,y_over_l,u_sph_over_U,u_exact_over_U\n" + profiles_.str());
  }

  // ---- C: error against wall time ----
  Run unidirectional(const std::string& problem, const std::string& method, int ny) {
    Run r;
    r.part = "C";
    r.problem = problem;
    r.error_name = "rms/U";
    const int nx = (ny + 1) / 2;
    const double l = 1e-3, nu = 1e-6, h = 2.2 * l / ny;
    std::ostringstream x1, dt;
    x1 << std::setprecision(17) << nx * l / ny;
    // WCSPH: 0.9 of the C Eq. (19) limit (viscous here); EPSPH: Crank-Nicolson at dt = 2 ms.
    dt << std::setprecision(6) << (method == "wcsph" ? 0.9 * 0.125 * h * h / nu : 2e-3);
    const std::vector<std::string> sets{"method=" + method, "grid.nx=" + std::to_string(nx),
                                        "grid.ny=" + std::to_string(ny), "domain.x=[0.0, " + x1.str() + "]",
                                        "time.dt=" + dt.str(), "output.interval=0"};
    const nlohmann::json j =
        run("wcsph_" + problem + ".toml", sets, method + "_" + problem + "_" + std::to_string(ny), nullptr, r);
    if (!j.is_null()) r.error = j["rms_error"].get<double>() / 2.5e-5;  // u_max = U = 2.5e-5 m/s
    return r;
  }

  Run cavity(const std::string& method, int n) {
    Run r;
    r.part = "C";
    r.problem = "cavity100";
    r.error_name = "rms dev Ghia";
    std::vector<std::string> sets{"grid.nx=" + std::to_string(n), "grid.ny=" + std::to_string(n), "output.interval=0"};
    std::string file = "cavity_re100.toml";
    if (method == "wcsph") {
      file = "wcsph_cavity_re100.toml";
      const FluidParams fp = load_scene((cases_ / file).string(), sets).sim.fluid;
      std::ostringstream dt;  // 0.9 of the C Eq. (19) limit
      dt << std::setprecision(6) << 0.9 * coelho_dt_limit(fp.h_over_dx / n, wcsph_sound_speed(fp), fp.mu / fp.rho);
      sets.push_back("time.dt=" + dt.str());
    }
    const nlohmann::json j = run(file, sets, method + "_cavity100_" + std::to_string(n), nullptr, r);
    if (!j.is_null()) {
      r.error = j["rms_deviation"].get<double>();
      r.error2 = j["max_deviation"].get<double>();
      r.error3 = j["kinetic_energy"].get<double>();
    }
    return r;
  }

  void part_c() {
    std::printf("C: error against wall time, EPSPH and WCSPH\n");
    const std::vector<int> nys = o_.quick ? std::vector<int>{21} : std::vector<int>{21, 41, 61};
    for (const char* problem : {"poiseuille", "couette"})
      for (int ny : nys)
        for (const char* m : {"wcsph", "eulerian"}) add(unidirectional(problem, m, ny));
    for (int n : o_.quick ? std::vector<int>{20} : std::vector<int>{20, 30, 40})
      for (const char* m : {"wcsph", "eulerian"}) add(stokes(m, n, 1.6, "C"));
    for (int n : o_.quick ? std::vector<int>{24} : std::vector<int>{32, 48})
      for (const char* m : {"wcsph", "eulerian"}) add(cavity(m, n));
  }

  void write() {
    std::ostringstream c;
    c << "part,problem,method,nx,ny,h_over_dx,dt,t_end,steps,error_name,error,error2,error3,wall_seconds,"
         "cpu_seconds,max_density_variation,note\n";
    for (const Run& r : runs_) {
      std::string note = r.note;
      for (char& ch : note)
        if (ch == ',' || ch == '\n') ch = ';';
      c << r.part << "," << r.problem << "," << r.method << "," << r.nx << "," << r.ny << "," << r.hdx << "," << r.dt
        << "," << r.t_end << "," << r.steps << "," << r.error_name << "," << r.error << "," << r.error2 << ","
        << r.error3 << "," << r.wall << "," << r.cpu << "," << r.dvar << "," << note << "\n";
    }
    write_text(o_.out / "wcsph_comparison.csv", c.str());
    write_text(o_.out / "wcsph_comparison.md", markdown());
  }

  std::string markdown() const {
    std::ostringstream m;
    m << "# WCSPH against EPSPH (issue 8)\n\nGenerated by `bench/wcsph_comparison` (single-threaded; wall and "
         "CPU seconds of the whole run, set-up included).\n\n";
    // A
    m << "## A. Constructed Stokes solution (Coelho et al. Eqs. 23-24, Re = 1e-6)\n\n"
      << "msd = C Eq. (27), (1/n) sum (u_sph - u_a)^2 over the u component, here divided by U^2 "
         "(U = max |u| = sqrt(3)/144 = 0.01203); max dev = max |u_sph - u_a| / U. The paper's eps and "
         "maximum deviation are printed as given: their ratio (about 0.5) cannot be a mean square "
         "against a maximum of the same quantity, so their normalisation is unknown.\n\n"
      << "| particles | h/dx | WCSPH msd/U^2 | WCSPH max dev/U | EPSPH msd/U^2 | EPSPH max dev/U | paper eps | "
         "paper max dev |\n|---|---|---|---|---|---|---|---|\n";
    std::map<std::pair<int, double>, std::pair<const Run*, const Run*>> rows;
    for (const Run& r : runs_)
      if (r.part == "A") {
        auto& e = rows[{-r.nx, r.hdx}];
        (r.method == "wcsph" ? e.first : e.second) = &r;
      }
    for (const auto& [k, e] : rows) {
      const PaperRow* p = paper_row(-k.first, k.second);
      m << "| " << k.first * k.first << " | " << k.second << " | " << (e.first ? num(e.first->error) : "-") << " | "
        << (e.first ? num(e.first->error2) : "-") << " | " << (e.second ? num(e.second->error) : "-") << " | "
        << (e.second ? num(e.second->error2) : "-") << " | " << (p ? num(p->eps) : "-") << " | "
        << (p ? num(p->maxdev) : "-") << " |\n";
    }
    // B
    m << "\n## B. Vukcevic et al. Poiseuille and Couette (WCSPH, 41 x 21 particles, h = 2.2 dy, XSPH 0.3)\n\n"
      << "rms |u - u_exact| / U over the particles at the profile times (profiles in wcsph_profiles.csv):\n\n"
      << "| problem | t (s) | rms / U |\n|---|---|---|\n";
    for (const auto& q : rms_time_) m << "| " << q.problem << " | " << num(q.t) << " | " << num(q.e) << " |\n";
    m << "\nVelocity profiles u / U (row means; SPH / exact) at the rows nearest y / l = 0.1, 0.25, 0.5, 0.75, 0.9:\n\n"
      << "| problem | t (s) | y/l | u_SPH / U | u_exact / U |\n|---|---|---|---|---|\n";
    for (const auto& q : profile_pts_)
      m << "| " << q.problem << " | " << num(q.t) << " | " << num(q.y, 3) << " | " << num(q.us, 4) << " | "
        << num(q.ue, 4) << " |\n";
    m << "\nChoices (t = 1 s):\n\n| problem | choice | rms / U | max drho/rho0 | steps | CPU s |\n|---|---|---|---|---|---|\n";
    for (const Run& r : runs_)
      if (r.part == "B")
        m << "| " << r.problem << " | " << r.note << " | " << num(r.error) << " | " << num(r.dvar, 2) << " | "
          << r.steps << " | " << num(r.cpu) << " |\n";
    // C
    m << "\n## C. Error against wall time\n\n| problem | method | particles | dt | steps | error | value | wall s | "
         "CPU s | max drho/rho0 | note |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Run& r : runs_)
      if (r.part == "C")
        m << "| " << r.problem << " | " << r.method << " | " << r.nx << "x" << r.ny << " | " << num(r.dt) << " | "
          << r.steps << " | " << r.error_name << " | " << num(r.error) << " | " << num(r.wall) << " | " << num(r.cpu)
          << " | " << num(r.dvar, 2) << " | " << r.note.substr(0, 120) << " |\n";
    return m.str();
  }

  static void write_text(const fs::path& p, const std::string& s) { write_file_atomic(p.string(), s); }

 private:
  struct RmsAt {
    std::string problem;
    double t, e;
  };
  struct ProfilePoint {
    std::string problem;
    double t, y, us, ue;
  };
  std::vector<ProfilePoint> profile_pts_;
  Options o_;
  fs::path cases_;
  std::vector<Run> runs_;
  std::ostringstream profiles_;
  std::vector<RmsAt> rms_time_;
};

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Weakly compressible SPH against EPSPH (Vukcevic et al.; Coelho et al.)", "wcsph_comparison"};
  bench::add_scene_options(app, o, "ABC",
                           "A constructed Stokes flow, B Vukcevic Poiseuille/Couette, C error against time");
  return bench::run_main(app, argc, argv, [&] {
    Bench b(o);
    const auto t0 = bench::Clock::now();
    if (bench::wants(o.parts, 'A')) b.part_a();
    if (bench::wants(o.parts, 'B')) b.part_b();
    if (bench::wants(o.parts, 'C')) b.part_c();
    b.write();
    std::printf("\n%s\nwritten to %s (%.0f s)\n", b.markdown().c_str(), o.out.c_str(), seconds_since(t0));
    return 0;
  });
}
