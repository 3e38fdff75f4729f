// Benchmark (not a test): the start-up planar Poiseuille sweep behind Figs. 4 and 7 and Table 1 of
// Noutcheuwa & Owens (2012), Section 5.1, with the EPSPH solver of fluid/projection.hpp.
//
// Problem (dimensionless, Section 4.1 / 5.1): domain [0,1]^2, periodic in x, no-slip walls at
// y = 0, 1; Re = 0.0125, i.e. rho = 1, mu = 1/Re, body force F = (8/Re, 0) so that u_max = 1;
// dt = 1.25e-6, t in [0, 0.0125] (10 000 steps), fluid at rest at t = 0. The paper's problem is
// unidirectional (u = u(y, t), v = 0), so (u.grad)u = 0 exactly and by default we solve the Stokes
// problem (convection off; --convection switches the AB2 convection term of Eq. 39 back on).
// Grid Nx = Ny in {16, 24, 32, 48, 64} x h/dx in {1.2, 1.525, 2.2, 2.75, 3, 4, 5}.
//
// For every run: rms velocity error of Eq. (69) at the final time against exact::poiseuille_u
// (Eq. 44; the exact v is 0), wall time of the constructor (one-off: neighbour search, assembly,
// factorisation) and of the time loop, the per-step breakdown into products / right-hand sides and
// triangular solves (Fluid::profile()), neighbours per particle, nnz and fill of the two
// factorisations, and the ratio of the paper's CPU time (Table 1) to ours.
//
//   poiseuille_sweep [--nx 16,24,...] [--h 1.2,1.525,...] [--steps N] [--out DIR]
//                    [--convection] [--pressure] [--solver KIND] [--verbose]
//
// Writes DIR/poiseuille_sweep.csv (one row per run) and DIR/poiseuille_sweep.md (tables), each
// rewritten atomically (.part then rename) after every run, so an interrupted sweep keeps its rows.
// The process re-executes itself once with OMP_NUM_THREADS=1 (and the BLAS equivalents) so that
// CHOLMOD/BLAS run single-threaded, as the paper's timings are for one 2.66 GHz core.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/common.hpp"
#include "io/atomic_file.hpp"
#include "fluid/exact.hpp"
#include "fluid/projection.hpp"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr double kRe = 0.0125;
constexpr double kDt = 1.25e-6;
constexpr long kPaperSteps = 10000;  // t in [0, 1.25e-2]
constexpr double kTargetSeconds = 30.0;  // target for the 64 x 64, h = 1.525 dx run

const std::vector<int> kAllNx = {16, 24, 32, 48, 64};
const std::vector<double> kAllH = {1.2, 1.525, 2.2, 2.75, 3.0, 4.0, 5.0};

// Table 1 of Noutcheuwa & Owens (2012), "Planar Poiseuille problem. CPU times (divided by 10^5) in
// seconds as a function of h and dx for calculations over the dimensionless time interval
// [0, 1.25e-2]. dt = 1.25e-6. EPSPH method." (2.66 GHz machine, 4 GB RAM).
// Rows h/dx = 1.20, 1.525, 2.20, 2.75, 3.00, 4.00, 5.00; columns dx = 1/16, 1/24, 1/32, 1/48, 1/64.
const double kTable1[7][5] = {
    {0.035022, 0.067669, 0.113006, 0.239269, 0.415746},  // h = 1.20 dx
    {0.046215, 0.089396, 0.147856, 0.311473, 0.540184},  // h = 1.525 dx
    {0.090997, 0.178537, 0.294559, 0.617233, 1.060960},  // h = 2.20 dx
    {0.147899, 0.287261, 0.472361, 0.982132, 1.677688},  // h = 2.75 dx
    {0.203369, 0.391393, 0.640025, 1.306324, 2.274285},  // h = 3.00 dx
    {0.333689, 0.645198, 1.042638, 2.120318, 3.552049},  // h = 4.00 dx
    {0.669753, 1.283128, 2.119406, 4.022646, 7.023340},  // h = 5.00 dx
};

// Paper CPU time in seconds for the full 10 000 steps, or < 0 when (nx, h/dx) is not in Table 1.
double paper_seconds(int nx, double hdx) {
  int r = -1, c = -1;
  for (size_t k = 0; k < kAllH.size(); ++k)
    if (std::abs(kAllH[k] - hdx) < 1e-9) r = static_cast<int>(k);
  for (size_t k = 0; k < kAllNx.size(); ++k)
    if (kAllNx[k] == nx) c = static_cast<int>(k);
  return (r < 0 || c < 0) ? -1.0 : kTable1[r][c] * 1e5;
}

struct Options {
  std::vector<int> nx = kAllNx;
  std::vector<double> h = kAllH;
  long steps = kPaperSteps;
  std::string out = "bench_out";
  bool convection = false;
  bool pressure = false;  // recover p (Eq. 35) every step; the library does it lazily, on request
  bool verbose = false;
  sphib::SolverKind solver = sphib::SolverKind::Auto;  // for both systems
  std::string solver_name = "auto";
};

struct Phase {
  std::string name;
  double seconds;
};

struct Result {
  int nx = 0;
  double hdx = 0;
  std::string status = "ok";  // or the exception message
  double h = 0, dx = 0, t_end = 0;
  long steps = 0;
  int n = 0, n_images = 0;
  double nb_per_particle = 0;
  double rms = NAN, rms_u = NAN, rms_v = NAN, max_err = NAN, max_div = NAN;
  double t_neigh = 0, t_asm = 0, t_fact = 0, t_ctor = 0, t_loop = 0, t_products = 0, t_solves = 0;
  std::vector<Phase> phases;
  std::vector<sphib::SolverInfo> solvers;
  double total() const { return t_ctor + t_loop; }
  double per_step() const { return steps ? t_loop / steps : 0; }
  // our total extrapolated to the paper's 10 000 steps (set-up once, loop scaled)
  double total_10k() const { return t_ctor + (steps ? t_loop * kPaperSteps / steps : 0); }
  double paper_scaled() const {  // the paper's time for the same number of steps
    const double p = paper_seconds(nx, hdx);
    return p < 0 ? -1.0 : p * static_cast<double>(steps) / kPaperSteps;
  }
  double ratio() const {
    const double p = paper_scaled();
    return (p < 0 || total() <= 0) ? NAN : p / total();
  }
};

[[noreturn]] void usage(const char* prog, int code) {
  (code ? std::cerr : std::cout)
      << "usage: " << prog
      << " [--nx LIST] [--h LIST] [--steps N] [--out DIR] [--convection] [--pressure]\n"
         "       [--solver auto|supernodal|simplicial|umfpack|pcg] [--verbose]\n"
         "  --nx LIST      comma-separated Nx = Ny values (default 16,24,32,48,64)\n"
         "  --h LIST       comma-separated h/dx values (default 1.2,1.525,2.2,2.75,3,4,5)\n"
         "  --steps N      time steps (default 10000, t_end = 0.0125); fewer steps: the error is at\n"
         "                 t = N dt and the paper's time is scaled by N/10000\n"
         "  --out DIR      output directory (default bench_out)\n"
         "  --convection   keep the AB2 convection term (default: Stokes, the flow is unidirectional)\n"
         "  --pressure     recover the pressure (Eq. 35) after every step (default: never asked for;\n"
         "                 the library recovers it lazily)\n"
         "  --solver KIND  auto (default: the library's timed choice), supernodal, simplicial, umfpack\n"
         "                 or pcg, for both systems (pcg: Crank-Nicolson only, Poisson gets auto)\n"
         "  --verbose      print the per-phase breakdown and solver lines of every run\n";
  std::exit(code);
}

template <class T>
std::vector<T> parse_list(const std::string& s, const char* what) {
  std::vector<T> v;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    size_t pos = 0;
    T x{};
    try {
      if constexpr (std::is_same_v<T, int>) x = std::stoi(item, &pos);
      else x = std::stod(item, &pos);
    } catch (const std::exception&) {
      pos = 0;
    }
    if (pos != item.size()) throw std::invalid_argument(std::string("bad value '") + item + "' in " + what);
    v.push_back(x);
  }
  if (v.empty()) throw std::invalid_argument(std::string("empty list for ") + what);
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i], val;
    bool has_val = false;
    if (const auto eq = a.find('='); a.rfind("--", 0) == 0 && eq != std::string::npos) {
      val = a.substr(eq + 1);
      a = a.substr(0, eq);
      has_val = true;
    }
    auto value = [&]() -> std::string {
      if (has_val) return val;
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--help" || a == "-h") usage(argv[0], 0);
    else if (a == "--nx") o.nx = parse_list<int>(value(), "--nx");
    else if (a == "--h") o.h = parse_list<double>(value(), "--h");
    else if (a == "--steps") {
      const auto s = parse_list<int>(value(), "--steps");
      if (s.size() != 1 || s[0] < 1) throw std::invalid_argument("--steps needs one positive integer");
      o.steps = s[0];
    } else if (a == "--out") o.out = value();
    else if (a == "--convection") o.convection = true;
    else if (a == "--pressure") o.pressure = true;
    else if (a == "--verbose" || a == "-v") o.verbose = true;
    else if (a == "--solver") {
      o.solver_name = value();
      if (o.solver_name == "auto") o.solver = sphib::SolverKind::Auto;
      else if (o.solver_name == "supernodal") o.solver = sphib::SolverKind::CholmodSupernodal;
      else if (o.solver_name == "simplicial") o.solver = sphib::SolverKind::CholmodSimplicial;
      else if (o.solver_name == "umfpack") o.solver = sphib::SolverKind::Umfpack;
      else if (o.solver_name == "pcg") o.solver = sphib::SolverKind::Pcg;
      else throw std::invalid_argument("--solver must be auto, supernodal, simplicial, umfpack or pcg");
    }
    else throw std::invalid_argument("unknown option " + a);
  }
  for (int n : o.nx)
    if (n < 2) throw std::invalid_argument("--nx values must be at least 2");
  for (double h : o.h)
    if (!(h > 0)) throw std::invalid_argument("--h values must be positive");
  return o;
}

Result run_one(int nx, double hdx, const Options& o) {
  Result r;
  r.nx = nx;
  r.hdx = hdx;
  r.steps = o.steps;
  sphib::FluidParams prm;
  prm.domain = sphib::Domain{0.0, 1.0, 0.0, 1.0, true, false};
  prm.nx = prm.ny = nx;
  prm.h_over_dx = hdx;
  prm.rho = 1.0;
  prm.mu = 1.0 / kRe;
  prm.dt = kDt;
  prm.convection = o.convection;
  prm.cn_solver = o.solver;
  // Jacobi-PCG is offered for the diagonally dominant Crank-Nicolson system only
  prm.poisson_solver = o.solver == sphib::SolverKind::Pcg ? sphib::SolverKind::Auto : o.solver;
  try {
    auto t0 = Clock::now();
    sphib::Fluid fluid(prm);
    r.t_ctor = since(t0);
    const int N = fluid.size();
    r.n = N;
    r.h = fluid.h();
    r.dx = fluid.lattice().dx;
    r.n_images = fluid.images().size();
    r.nb_per_particle = static_cast<double>(fluid.pairs().size()) / N;
    r.t_neigh = fluid.setup_seconds("neighbours");
    r.t_asm = fluid.setup_seconds("assembly");
    r.t_fact = fluid.setup_seconds("factorisation");
    r.solvers = fluid.solver_info();

    sphib::Mat2 F = sphib::Mat2::Zero(N, 2);
    F.col(0).setConstant(8.0 / kRe);  // dp/dx = -8 mu u_max / H^2, dimensionless 8/Re
    t0 = Clock::now();
    fluid.set_velocity(sphib::Mat2::Zero(N, 2));
    double p_sink = 0;
    for (long s = 0; s < o.steps; ++s) {
      fluid.step(F);
      if (o.pressure) p_sink += fluid.p()[0];
    }
    r.t_loop = since(t0);
    if (!std::isfinite(p_sink)) r.status = "non-finite pressure";

    for (size_t k = 0; k < fluid.profile().names().size(); ++k) {
      const std::string& name = fluid.profile().names()[k];
      const double sec = fluid.profile().seconds(static_cast<int>(k));
      r.phases.push_back({name, sec});
      (name.rfind("solve", 0) == 0 ? r.t_solves : r.t_products) += sec;
    }

    // Eq. (69) at t = steps dt
    r.t_end = o.steps * kDt;
    double su = 0, sv = 0, mx = 0;
    for (int i = 0; i < N; ++i) {
      const double ue = sphib::exact::poiseuille_u(fluid.lattice().x(i, 1), r.t_end, kRe);
      const double du = ue - fluid.u()(i, 0), dv = 0.0 - fluid.u()(i, 1);
      su += du * du;
      sv += dv * dv;
      mx = std::max(mx, std::sqrt(du * du + dv * dv));
    }
    r.rms = std::sqrt((su + sv) / N);
    r.rms_u = std::sqrt(su / N);
    r.rms_v = std::sqrt(sv / N);
    r.max_err = mx;
    r.max_div = fluid.max_abs_divergence();
    if (std::abs(fluid.time() - r.t_end) > 1e-12) r.status = "time mismatch";
    if (!std::isfinite(r.rms)) r.status = "non-finite velocity";
  } catch (const std::exception& e) {
    r.status = e.what();
  }
  return r;
}

// ---------------------------------------------------------------- output

std::string fmt(double v, int prec = 3, bool sci = false) {
  if (!std::isfinite(v)) return "";
  std::ostringstream s;
  s << (sci ? std::scientific : std::fixed) << std::setprecision(prec) << v;
  return s.str();
}

std::string csv_quote(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string md_escape(std::string s) {
  for (size_t p = 0; (p = s.find('|', p)) != std::string::npos; p += 2) s.replace(p, 1, "\\|");
  return s;
}

void write_atomic(const std::filesystem::path& path, const std::string& text) {
  sphib::write_file_atomic(path.string(), text);  // io/atomic_file.hpp: .part, fsync, rename
}

std::string hdx_str(double h) {
  std::ostringstream s;
  s << h;
  return s.str();
}

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("model name", 0) == 0) {
      const auto c = line.find(':');
      if (c != std::string::npos) return line.substr(c + 2);
    }
  return "unknown";
}

// SolverInfo::fill() = nnz(factor) / nnz(A), A's both triangles (NaN here for the factor-free PCG).
double fill(const sphib::SolverInfo& s) { return s.nnz_factor > 0 ? s.fill() : NAN; }
// A Cholesky factor L is one triangle: for CHOLMOD also compare it with the stored lower triangle,
// (nnz(A) + n) / 2 (full diagonal), so that "fill < 1" cannot happen.
double fill_vs_stored(const sphib::SolverInfo& s) {
  if (s.nnz_factor <= 0) return NAN;
  if (s.method.rfind("CHOLMOD", 0) != 0) return s.fill();
  return s.nnz_factor / (0.5 * (static_cast<double>(s.nnz_A) + s.n));
}

std::string make_csv(const std::vector<Result>& rs, const Options& opt) {
  std::ostringstream o;
  o << std::setprecision(10);
  o << "nx,ny,h_over_dx,h,dx,n_particles,n_images,steps,t_end,convection,pressure,status,"
       "rms_error,rms_error_u,rms_error_v,max_error,max_abs_div,"
       "setup_neighbours_s,setup_assembly_s,setup_factorisation_s,setup_total_s,loop_s,per_step_s,"
       "products_s,solves_s,products_per_step_s,solves_per_step_s,total_s,total_s_at_10000_steps,"
       "neighbours_per_particle,"
       "cn_method,cn_nnz_A,cn_nnz_factor,cn_fill,cn_fill_vs_stored,"
       "poisson_method,poisson_nnz_A,poisson_nnz_factor,poisson_fill,poisson_fill_vs_stored,"
       "paper_table1_s,paper_s_scaled_to_steps,paper_over_ours\n";
  for (const Result& r : rs) {
    const bool ok = r.status == "ok";
    auto num = [&](double v) { return std::isfinite(v) ? (std::ostringstream() << std::setprecision(10) << v).str() : std::string(); };
    o << r.nx << ',' << r.nx << ',' << r.hdx << ',' << num(r.h) << ',' << num(r.dx) << ',' << r.n << ','
      << r.n_images << ',' << r.steps << ',' << num(r.steps * kDt) << ',' << opt.convection << ','
      << opt.pressure << ',' << csv_quote(r.status) << ',' << num(r.rms) << ',' << num(r.rms_u) << ','
      << num(r.rms_v) << ',' << num(r.max_err) << ',' << num(r.max_div) << ',';
    if (ok) {
      o << num(r.t_neigh) << ',' << num(r.t_asm) << ',' << num(r.t_fact) << ',' << num(r.t_ctor) << ','
        << num(r.t_loop) << ',' << num(r.per_step()) << ',' << num(r.t_products) << ',' << num(r.t_solves) << ','
        << num(r.t_products / r.steps) << ',' << num(r.t_solves / r.steps) << ',' << num(r.total()) << ','
        << num(r.total_10k()) << ',' << num(r.nb_per_particle) << ',';
    } else {
      o << ",,,,,,,,,,,,,";
    }
    for (int k = 0; k < 2; ++k) {
      if (ok && k < static_cast<int>(r.solvers.size())) {
        const auto& s = r.solvers[k];
        o << csv_quote(s.method) << ',' << s.nnz_A << ',' << s.nnz_factor << ',' << num(fill(s)) << ','
          << num(fill_vs_stored(s)) << ',';
      } else {
        o << ",,,,,";
      }
    }
    const double p = paper_seconds(r.nx, r.hdx);
    o << (p < 0 ? std::string() : num(p)) << ',' << (ok && p >= 0 ? num(r.paper_scaled()) : std::string()) << ','
      << (ok ? num(r.ratio()) : std::string()) << '\n';
  }
  return o.str();
}

const Result* find(const std::vector<Result>& rs, int nx, double h) {
  for (const Result& r : rs)
    if (r.nx == nx && std::abs(r.hdx - h) < 1e-12 && r.status == "ok") return &r;
  return nullptr;
}

std::string make_md(const std::vector<Result>& rs, const Options& o) {
  std::ostringstream m;
  const double t_end = o.steps * kDt;
  m << "# Start-up planar Poiseuille sweep (EPSPH), Noutcheuwa & Owens (2012) Section 5.1\n\n"
    << "Re = 0.0125 (rho = 1, mu = 1/Re = 80, F = 8/Re = 640 in x, u_max = 1), domain [0,1]^2 periodic in x, "
    << "no-slip walls at y = 0, 1, dt = 1.25e-6, " << o.steps << " steps, errors at t = " << fmt(t_end, 6, true)
    << ".\n\n"
    << (o.convection ? "Convection ON (AB2, Eq. 39).\n\n"
                     : "Convection OFF (Stokes): the paper's problem is unidirectional, u = u(y, t), v = 0, so "
                       "(u.grad)u = 0 exactly.\n\n")
    << "Pressure recovery (Eq. 35) every step: " << (o.pressure ? "on" : "off (lazy, never asked for)")
    << ". Linear solvers: " << o.solver_name << ". Single-threaded ("
    << "OMP_NUM_THREADS=1), CPU: " << cpu_model() << ".\n\n";
  if (o.steps != kPaperSteps)
    m << "**Shortened run**: " << o.steps << " of 10 000 steps; the errors are at t = " << fmt(t_end, 6, true)
      << " (not 1.25e-2, flow not yet developed) and the paper's Table 1 times are scaled by " << o.steps
      << "/10000 for the ratio (our set-up is not scaled).\n\n";

  auto header = [&](const std::string& corner, const std::vector<std::string>& cols) {
    m << "| " << corner << " |";
    for (const auto& c : cols) m << ' ' << c << " |";
    m << "\n|---|";
    for (size_t k = 0; k < cols.size(); ++k) m << "---:|";
    m << '\n';
  };
  std::vector<std::string> nxcols;
  for (int n : o.nx) nxcols.push_back("Nx = " + std::to_string(n));

  m << "## rms velocity error, Eq. (69) (data of Figs. 4 and 7)\n\n";
  header("h/dx", nxcols);
  for (double h : o.h) {
    m << "| " << hdx_str(h) << " |";
    for (int n : o.nx) {
      const Result* r = find(rs, n, h);
      m << ' ' << (r ? fmt(r->rms, 3, true) : "–") << " |";
    }
    m << '\n';
  }

  if (o.nx.size() > 1) {
    m << "\n## Observed order in Nx, log(e1/e2)/log(N2/N1) (Fig. 4; 2 = quadratic)\n\n";
    std::vector<std::string> cols;
    for (size_t k = 0; k + 1 < o.nx.size(); ++k)
      cols.push_back(std::to_string(o.nx[k]) + "→" + std::to_string(o.nx[k + 1]));
    header("h/dx", cols);
    for (double h : o.h) {
      m << "| " << hdx_str(h) << " |";
      for (size_t k = 0; k + 1 < o.nx.size(); ++k) {
        const Result *a = find(rs, o.nx[k], h), *b = find(rs, o.nx[k + 1], h);
        std::string c = "–";
        if (a && b && a->rms > 0 && b->rms > 0)
          c = fmt(std::log(a->rms / b->rms) / std::log(static_cast<double>(o.nx[k + 1]) / o.nx[k]), 2);
        m << ' ' << c << " |";
      }
      m << '\n';
    }
  }
  if (o.h.size() > 1) {
    m << "\n## Slope of log(error) vs log(h) at fixed dx between successive h (Fig. 7; +2 smoothing-, "
         "-4 discretisation-dominated)\n\n";
    std::vector<std::string> cols;
    for (size_t k = 0; k + 1 < o.h.size(); ++k) cols.push_back(hdx_str(o.h[k]) + "→" + hdx_str(o.h[k + 1]));
    header("Nx", cols);
    for (int n : o.nx) {
      m << "| " << n << " |";
      for (size_t k = 0; k + 1 < o.h.size(); ++k) {
        const Result *a = find(rs, n, o.h[k]), *b = find(rs, n, o.h[k + 1]);
        std::string c = "–";
        if (a && b && a->rms > 0 && b->rms > 0) c = fmt(std::log(b->rms / a->rms) / std::log(o.h[k + 1] / o.h[k]), 2);
        m << ' ' << c << " |";
      }
      m << '\n';
    }
  }

  m << "\n## Least-squares fit of Eq. (74), e = A alpha^2 dx^2 + B alpha^-4 (alpha = h/dx), per dx\n\n"
    << "alpha_opt = (2B / (A dx^2))^(1/6), Eq. (75); the paper fits dx = 1/16 and finds alpha_opt = 1.43.\n\n";
  header("Nx", {"points", "A", "B", "alpha_opt"});
  for (int n : o.nx) {
    // normal equations of the 2-parameter linear least-squares problem
    double s11 = 0, s12 = 0, s22 = 0, b1 = 0, b2 = 0;
    int pts = 0;
    const double dx = 1.0 / n;
    for (double h : o.h)
      if (const Result* r = find(rs, n, h)) {
        const double f1 = h * h * dx * dx, f2 = std::pow(h, -4.0);
        s11 += f1 * f1; s12 += f1 * f2; s22 += f2 * f2; b1 += f1 * r->rms; b2 += f2 * r->rms;
        ++pts;
      }
    const double det = s11 * s22 - s12 * s12;
    m << "| " << n << " | " << pts << " |";
    if (pts >= 2 && std::abs(det) > 0) {
      const double A = (b1 * s22 - b2 * s12) / det, B = (s11 * b2 - s12 * b1) / det;
      m << ' ' << fmt(A, 3, true) << " | " << fmt(B, 3, true) << " | "
        << (A > 0 && B > 0 ? fmt(std::pow(2 * B / (A * dx * dx), 1.0 / 6.0), 3) : "–") << " |\n";
    } else {
      m << " – | – | – |\n";
    }
  }

  m << "\n## Total time, set-up + " << o.steps << " steps, seconds (cf. Table 1)\n\n";
  header("h/dx", nxcols);
  for (double h : o.h) {
    m << "| " << hdx_str(h) << " |";
    for (int n : o.nx) {
      const Result* r = find(rs, n, h);
      m << ' ' << (r ? fmt(r->total(), 3) : "–") << " |";
    }
    m << '\n';
  }
  m << "\n## Paper Table 1 time (value x 1e5 s" << (o.steps != kPaperSteps ? ", scaled to our step count" : "")
    << ") / our total time\n\n";
  header("h/dx", nxcols);
  for (double h : o.h) {
    m << "| " << hdx_str(h) << " |";
    for (int n : o.nx) {
      const Result* r = find(rs, n, h);
      m << ' ' << (r && std::isfinite(r->ratio()) ? fmt(r->ratio(), 0) : "–") << " |";
    }
    m << '\n';
  }

  m << "\n## Per run\n\n"
    << "| Nx | h/dx | status | nb/particle | neighbours s | assembly s | factorisation s | loop s | "
       "us/step | products us/step | solves us/step | total s | Crank-Nicolson: method, nnz(A), nnz(factor), "
       "fill (vs stored triangle) | Poisson: same | paper s | paper/ours |\n"
    << "|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---:|---:|\n";
  for (const Result& r : rs) {
    const bool ok = r.status == "ok";
    m << "| " << r.nx << " | " << hdx_str(r.hdx) << " | " << md_escape(r.status) << " | ";
    if (ok) {
      m << fmt(r.nb_per_particle, 1) << " | " << fmt(r.t_neigh, 4) << " | " << fmt(r.t_asm, 4) << " | "
        << fmt(r.t_fact, 4) << " | " << fmt(r.t_loop, 3) << " | " << fmt(1e6 * r.per_step(), 1) << " | "
        << fmt(1e6 * r.t_products / r.steps, 1) << " | " << fmt(1e6 * r.t_solves / r.steps, 1) << " | "
        << fmt(r.total(), 3) << " | ";
      for (int k = 0; k < 2; ++k) {
        if (k < static_cast<int>(r.solvers.size())) {
          const auto& s = r.solvers[k];
          m << s.method << ", " << s.nnz_A << ", " << s.nnz_factor << ", " << fmt(fill(s), 2) << " ("
            << fmt(fill_vs_stored(s), 2) << ")";
        }
        m << " | ";
      }
      const double p = r.paper_scaled();
      m << (p >= 0 ? fmt(p, 0) : "–") << " | " << (std::isfinite(r.ratio()) ? fmt(r.ratio(), 0) : "–") << " |\n";
    } else {
      m << "| | | | | | | | | | | | |\n";
    }
  }

  if (const Result* r = find(rs, 64, 1.525)) {
    m << "\n## 64 x 64, h = 1.525 dx\n\nTotal " << fmt(r->total(), 2) << " s for " << r->steps << " steps";
    if (r->steps != kPaperSteps) m << " (extrapolated to 10 000 steps: " << fmt(r->total_10k(), 2) << " s)";
    m << "; target " << fmt(kTargetSeconds, 0) << " s; paper 54 018 s. rms error " << fmt(r->rms, 3, true)
      << ".\n";
  }
  return m.str();
}

void print_run(const Result& r, bool verbose) {
  std::printf("Nx=%3d h/dx=%-5s ", r.nx, hdx_str(r.hdx).c_str());
  if (r.status != "ok") {
    std::printf("FAILED: %s\n", r.status.c_str());
    std::fflush(stdout);
    return;
  }
  std::printf(
      "rms=%.4e  nb/p=%5.1f  setup %.3f s (nb %.3f asm %.3f fact %.3f)  loop %.3f s = %.1f us/step "
      "(products %.1f, solves %.1f)  total %.3f s",
      r.rms, r.nb_per_particle, r.t_ctor, r.t_neigh, r.t_asm, r.t_fact, r.t_loop, 1e6 * r.per_step(),
      1e6 * r.t_products / r.steps, 1e6 * r.t_solves / r.steps, r.total());
  if (std::isfinite(r.ratio())) std::printf("  paper/ours %.0f", r.ratio());
  std::printf("\n");
  if (verbose) {
    for (const auto& s : r.solvers) std::printf("    %s\n", s.describe().c_str());
    std::printf("    per step:");
    for (const auto& p : r.phases) std::printf("  %s %.2f us", p.name.c_str(), 1e6 * p.seconds / r.steps);
    std::printf("\n    rms u %.4e  rms v %.4e  max |e| %.4e  max |div u| %.3e\n", r.rms_u, r.rms_v, r.max_err,
                r.max_div);
  }
  std::fflush(stdout);
}

// Re-executes the program once with single-threaded OpenMP/BLAS (libgomp reads OMP_NUM_THREADS at
// load time, so setting it from main is too late for the running process).
void ensure_single_thread(char** argv) { sphib::bench::ensure_single_thread("poiseuille_sweep", argv); }

}  // namespace

int main(int argc, char** argv) {
  Options o;
  try {
    o = parse(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "poiseuille_sweep: " << e.what() << "\n";
    usage(argv[0], 2);
  }
  ensure_single_thread(argv);

  namespace fs = std::filesystem;
  const fs::path dir(o.out);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    std::cerr << "poiseuille_sweep: cannot create " << dir << ": " << ec.message() << "\n";
    return 1;
  }

  std::printf("Start-up planar Poiseuille (Noutcheuwa & Owens 2012, Sec. 5.1): Re = %g, dt = %g, %ld steps, "
              "t_end = %g%s\n",
              kRe, kDt, o.steps, o.steps * kDt, o.steps == kPaperSteps ? "" : " (shortened: not the paper's 0.0125)");
  std::printf("%s; pressure recovery %s; solvers %s; single-threaded; %zu runs\n",
              o.convection ? "convection ON (AB2)"
                           : "convection OFF (Stokes: the flow is unidirectional, (u.grad)u = 0 exactly)",
              o.pressure ? "every step" : "off (lazy, never asked for)", o.solver_name.c_str(),
              o.nx.size() * o.h.size());
  if (o.steps != kPaperSteps)
    std::printf("paper Table 1 times are scaled by %ld/10000 for the paper/ours ratio (our set-up is not scaled)\n",
                o.steps);

  std::vector<Result> rs;
  const auto t_all = Clock::now();
  for (double h : o.h)
    for (int n : o.nx) {
      rs.push_back(run_one(n, h, o));
      print_run(rs.back(), o.verbose);
      try {
        write_atomic(dir / "poiseuille_sweep.csv", make_csv(rs, o));
        write_atomic(dir / "poiseuille_sweep.md", make_md(rs, o));
      } catch (const std::exception& e) {
        std::cerr << "poiseuille_sweep: " << e.what() << "\n";
        return 1;
      }
    }
  double est = 0;
  for (const Result& r : rs)
    if (r.status == "ok") est += r.total_10k();
  std::printf("sweep wall time %.1f s", since(t_all));
  if (o.steps != kPaperSteps) std::printf("; these runs at the paper's 10000 steps: about %.0f s", est);
  std::printf("\n");

  std::printf("\n%s", make_md(rs, o).c_str());
  if (const Result* r = find(rs, 64, 1.525)) {
    std::printf("\n64 x 64, h = 1.525 dx: total %.2f s", r->total());
    if (r->steps != kPaperSteps) std::printf(" for %ld steps, extrapolated to 10000 steps %.2f s", r->steps, r->total_10k());
    std::printf(" (target %.0f s: %s; paper 54 018 s)\n", kTargetSeconds,
                r->total_10k() <= kTargetSeconds ? "met" : "MISSED");
  }
  std::printf("wrote %s and %s\n", (dir / "poiseuille_sweep.csv").c_str(), (dir / "poiseuille_sweep.md").c_str());
  int failed = 0;
  for (const Result& r : rs) failed += r.status != "ok";
  if (failed) std::printf("%d run(s) failed (see status column)\n", failed);
  return 0;
}
