// Benchmark (not a test): the start-up planar Poiseuille sweep behind Figs. 4 and 7 and Table 1 of
// Noutcheuwa & Owens (2012), Section 5.1, with the EPSPH solver of fluid/eulerian/eulerian.hpp.
//
// The problem is bench/poiseuille.hpp's (Stokes by default; --convection switches the AB2
// convection term of Eq. 39 back on), over Nx = Ny in {16, 24, 32, 48, 64} x h/dx in
// {1.2, 1.525, 2.2, 2.75, 3, 4, 5}.
//
// For every run: rms velocity error of Eq. (69) at the final time against exact::poiseuille_u
// (Eq. 44; the exact v is 0), wall time of the constructor (one-off: neighbour search, assembly,
// factorisation) and of the time loop, the per-step breakdown into products / right-hand sides and
// triangular solves (the fluid's profiler()), neighbours per particle, nnz and fill of the two
// factorisations, and the ratio of the paper's CPU time (Table 1) to ours.
//
//   poiseuille_sweep [--nx 16,24,...] [--h 1.2,1.525,...] [--steps N] [--out DIR]
//                    [--convection] [--pressure] [--solver KIND] [--verbose]      (--help)
//
// Writes DIR/poiseuille_sweep.csv (one row per run) and DIR/poiseuille_sweep.md (tables), each
// rewritten atomically after every run, so an interrupted sweep keeps its rows. Single-threaded,
// as the paper's timings are for one 2.66 GHz core.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "bench/common.hpp"
#include "bench/poiseuille.hpp"
#include "fluid/eulerian/eulerian.hpp"

namespace {

using namespace sphib::bench;
using namespace sphib::bench::poiseuille;
using sphib::seconds_since;

constexpr double kTargetSeconds = 30.0;  // target for the 64 x 64, h = 1.525 dx run

struct Options {
  std::vector<int> nx = kPaperNx;
  std::vector<double> h = kPaperH;
  long steps = kPaperSteps;
  std::string out = "bench_out";
  bool convection = false;
  bool pressure = false;  // recover p (Eq. 35) every step; the library does it lazily, on request
  bool verbose = false;
  std::string solver = "auto";  // for both systems
};

sphib::SolverKind solver_kind(const std::string& name) {
  if (name == "supernodal") return sphib::SolverKind::CholmodSupernodal;
  if (name == "simplicial") return sphib::SolverKind::CholmodSimplicial;
  if (name == "umfpack") return sphib::SolverKind::Umfpack;
  if (name == "pcg") return sphib::SolverKind::Pcg;
  return sphib::SolverKind::Auto;
}

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
  Error err;
  double max_div = NAN;
  double t_neigh = 0, t_asm = 0, t_fact = 0, t_ctor = 0, t_loop = 0, t_products = 0, t_solves = 0;
  std::vector<Phase> phases;
  std::vector<sphib::SolverInfo> solvers;
  bool ok() const { return status == "ok"; }
  double total() const { return t_ctor + t_loop; }
  double per_step() const { return steps ? t_loop / steps : 0; }
  // our total extrapolated to the paper's 10 000 steps (set-up once, loop scaled)
  double total_10k() const { return t_ctor + (steps ? t_loop * kPaperSteps / steps : 0); }
  double paper_scaled() const {  // the paper's time for the same number of steps
    return paper_seconds(false, nx, hdx) * static_cast<double>(steps) / kPaperSteps;
  }
  double ratio() const { return total() > 0 ? paper_scaled() / total() : NAN; }
};

Result run_one(int nx, double hdx, const Options& o) {
  Result r;
  r.nx = nx;
  r.hdx = hdx;
  r.steps = o.steps;
  sphib::FluidParams prm = params("eulerian", nx, hdx, o.convection);
  prm.cn_solver = solver_kind(o.solver);
  // Jacobi-PCG is offered for the diagonally dominant Crank-Nicolson system only
  prm.poisson_solver = prm.cn_solver == sphib::SolverKind::Pcg ? sphib::SolverKind::Auto : prm.cn_solver;
  try {
    auto t0 = Clock::now();
    sphib::EulerianFluid fluid(prm);
    r.t_ctor = seconds_since(t0);
    r.n = fluid.size();
    r.h = fluid.h();
    r.dx = fluid.lattice().dx;
    r.n_images = fluid.images().size();
    r.nb_per_particle = static_cast<double>(fluid.pairs().size()) / r.n;
    r.t_neigh = fluid.profiler().setup_seconds("neighbours");
    r.t_asm = fluid.profiler().setup_seconds("assembly");
    r.t_fact = fluid.profiler().setup_seconds("factorisation");
    r.solvers = fluid.solver_info();
    const sphib::Mat2 F = body_force(r.n);
    t0 = Clock::now();
    fluid.set_velocity(sphib::Mat2::Zero(r.n, 2));
    double p_sink = 0;
    for (long s = 0; s < o.steps; ++s) {
      fluid.step(F);
      if (o.pressure) p_sink += fluid.p()[0];
    }
    r.t_loop = seconds_since(t0);
    if (!std::isfinite(p_sink)) r.status = "non-finite pressure";
    const sphib::Profile& P = fluid.profiler();
    for (size_t k = 0; k < P.names().size(); ++k) {
      r.phases.push_back({P.names()[k], P.seconds(static_cast<int>(k))});
      (P.names()[k].rfind("solve", 0) == 0 ? r.t_solves : r.t_products) += r.phases.back().seconds;
    }
    r.t_end = o.steps * kDt;
    r.err = error(fluid);  // Eq. (69) at t = steps dt
    r.max_div = fluid.max_abs_divergence();
    if (std::abs(fluid.time() - r.t_end) > 1e-12) r.status = "time mismatch";
    if (!std::isfinite(r.err.rms)) r.status = "non-finite velocity";
  } catch (const std::exception& e) {
    r.status = e.what();
  }
  return r;
}

// ---------------------------------------------------------------- output

std::string csv_quote(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
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
  o << "nx,ny,h_over_dx,h,dx,n_particles,n_images,steps,t_end,convection,pressure,status,"
       "rms_error,rms_error_u,rms_error_v,max_error,max_abs_div,"
       "setup_neighbours_s,setup_assembly_s,setup_factorisation_s,setup_total_s,loop_s,per_step_s,"
       "products_s,solves_s,products_per_step_s,solves_per_step_s,total_s,total_s_at_10000_steps,"
       "neighbours_per_particle,"
       "cn_method,cn_nnz_A,cn_nnz_factor,cn_fill,cn_fill_vs_stored,"
       "poisson_method,poisson_nnz_A,poisson_nnz_factor,poisson_fill,poisson_fill_vs_stored,"
       "paper_table1_s,paper_s_scaled_to_steps,paper_over_ours\n";
  for (const Result& r : rs) {
    o << r.nx << ',' << r.nx << ',' << num(r.hdx) << ',' << csv_num(r.h) << ',' << csv_num(r.dx) << ',' << r.n << ','
      << r.n_images << ',' << r.steps << ',' << csv_num(r.steps * kDt) << ',' << opt.convection << ','
      << opt.pressure << ',' << csv_quote(r.status) << ',' << csv_num(r.err.rms) << ',' << csv_num(r.err.rms_u) << ','
      << csv_num(r.err.rms_v) << ',' << csv_num(r.err.max) << ',' << csv_num(r.max_div) << ',';
    if (r.ok()) {
      for (double v : {r.t_neigh, r.t_asm, r.t_fact, r.t_ctor, r.t_loop, r.per_step(), r.t_products, r.t_solves,
                       r.t_products / r.steps, r.t_solves / r.steps, r.total(), r.total_10k(), r.nb_per_particle})
        o << csv_num(v) << ',';
    } else {
      o << ",,,,,,,,,,,,,";
    }
    for (int k = 0; k < 2; ++k) {
      if (r.ok() && k < static_cast<int>(r.solvers.size())) {
        const auto& s = r.solvers[k];
        o << csv_quote(s.method) << ',' << s.nnz_A << ',' << s.nnz_factor << ',' << csv_num(fill(s)) << ','
          << csv_num(fill_vs_stored(s)) << ',';
      } else {
        o << ",,,,,";
      }
    }
    o << csv_num(paper_seconds(false, r.nx, r.hdx)) << ',' << (r.ok() ? csv_num(r.paper_scaled()) : "") << ','
      << (r.ok() ? csv_num(r.ratio()) : "") << '\n';
  }
  return o.str();
}

const Result* find(const std::vector<Result>& rs, int nx, double h) {
  for (const Result& r : rs)
    if (r.nx == nx && std::abs(r.hdx - h) < 1e-12 && r.ok()) return &r;
  return nullptr;
}

// A table with a row per h/dx and a column per Nx; cell(r) of the run, "–" where none finished.
template <class Cell>
std::string h_by_nx(const std::vector<Result>& rs, const Options& o, Cell cell) {
  std::vector<std::string> cols;
  for (int n : o.nx) cols.push_back("Nx = " + std::to_string(n));
  std::string m = md_header("h/dx", cols);
  for (double h : o.h) {
    m += "| " + num(h) + " |";
    for (int n : o.nx) {
      const Result* r = find(rs, n, h);
      m += " " + (r ? cell(*r) : std::string("–")) + " |";
    }
    m += "\n";
  }
  return m;
}

// Observed orders: in Nx at fixed h/dx (Fig. 4) and in h at fixed dx (Fig. 7).
std::string orders_md(const std::vector<Result>& rs, const Options& o) {
  auto slope = [](const Result* a, const Result* b, double xa, double xb) {
    return a && b && a->err.rms > 0 && b->err.rms > 0 ? fix(std::log(b->err.rms / a->err.rms) / std::log(xb / xa), 2)
                                                       : std::string("–");
  };
  std::ostringstream m;
  if (o.nx.size() > 1) {
    m << "\n## Observed order in Nx, log(e1/e2)/log(N2/N1) (Fig. 4; 2 = quadratic)\n\n";
    std::vector<std::string> cols;
    for (size_t k = 0; k + 1 < o.nx.size(); ++k) cols.push_back(std::to_string(o.nx[k]) + "→" + std::to_string(o.nx[k + 1]));
    m << md_header("h/dx", cols);
    for (double h : o.h) {
      m << "| " << num(h) << " |";
      for (size_t k = 0; k + 1 < o.nx.size(); ++k)  // the order is minus the slope in Nx
        m << ' ' << slope(find(rs, o.nx[k + 1], h), find(rs, o.nx[k], h), o.nx[k], o.nx[k + 1]) << " |";
      m << '\n';
    }
  }
  if (o.h.size() > 1) {
    m << "\n## Slope of log(error) vs log(h) at fixed dx between successive h (Fig. 7; +2 smoothing-, "
         "-4 discretisation-dominated)\n\n";
    std::vector<std::string> cols;
    for (size_t k = 0; k + 1 < o.h.size(); ++k) cols.push_back(num(o.h[k]) + "→" + num(o.h[k + 1]));
    m << md_header("Nx", cols);
    for (int n : o.nx) {
      m << "| " << n << " |";
      for (size_t k = 0; k + 1 < o.h.size(); ++k)
        m << ' ' << slope(find(rs, n, o.h[k]), find(rs, n, o.h[k + 1]), o.h[k], o.h[k + 1]) << " |";
      m << '\n';
    }
  }
  return m.str();
}

// Eq. (74), e = A alpha^2 dx^2 + B alpha^-4 (alpha = h/dx), fitted per dx by linear least squares.
std::string fit_md(const std::vector<Result>& rs, const Options& o) {
  std::ostringstream m;
  m << "\n## Least-squares fit of Eq. (74), e = A alpha^2 dx^2 + B alpha^-4 (alpha = h/dx), per dx\n\n"
    << "alpha_opt = (2B / (A dx^2))^(1/6), Eq. (75); the paper fits dx = 1/16 and finds alpha_opt = 1.43.\n\n"
    << md_header("Nx", {"points", "A", "B", "alpha_opt"});
  for (int n : o.nx) {
    double s11 = 0, s12 = 0, s22 = 0, b1 = 0, b2 = 0;  // normal equations
    int pts = 0;
    const double dx = 1.0 / n;
    for (double h : o.h)
      if (const Result* r = find(rs, n, h)) {
        const double f1 = h * h * dx * dx, f2 = std::pow(h, -4.0);
        s11 += f1 * f1; s12 += f1 * f2; s22 += f2 * f2; b1 += f1 * r->err.rms; b2 += f2 * r->err.rms;
        ++pts;
      }
    const double det = s11 * s22 - s12 * s12;
    m << "| " << n << " | " << pts << " |";
    if (pts >= 2 && std::abs(det) > 0) {
      const double A = (b1 * s22 - b2 * s12) / det, B = (s11 * b2 - s12 * b1) / det;
      m << ' ' << sci(A, 3) << " | " << sci(B, 3) << " | "
        << (A > 0 && B > 0 ? fix(std::pow(2 * B / (A * dx * dx), 1.0 / 6.0), 3) : "–") << " |\n";
    } else {
      m << " – | – | – |\n";
    }
  }
  return m.str();
}

std::string per_run_md(const std::vector<Result>& rs) {
  std::ostringstream m;
  m << "\n## Per run\n\n"
    << "| Nx | h/dx | status | nb/particle | neighbours s | assembly s | factorisation s | loop s | "
       "us/step | products us/step | solves us/step | total s | Crank-Nicolson: method, nnz(A), nnz(factor), "
       "fill (vs stored triangle) | Poisson: same | paper s | paper/ours |\n"
    << "|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---:|---:|\n";
  for (const Result& r : rs) {
    m << "| " << r.nx << " | " << num(r.hdx) << " | " << md_text(r.status) << " | ";
    if (!r.ok()) {
      m << "| | | | | | | | | | | | |\n";
      continue;
    }
    m << fix(r.nb_per_particle, 1) << " | " << fix(r.t_neigh, 4) << " | " << fix(r.t_asm, 4) << " | "
      << fix(r.t_fact, 4) << " | " << fix(r.t_loop, 3) << " | " << fix(1e6 * r.per_step(), 1) << " | "
      << fix(1e6 * r.t_products / r.steps, 1) << " | " << fix(1e6 * r.t_solves / r.steps, 1) << " | "
      << fix(r.total(), 3) << " | ";
    for (int k = 0; k < 2; ++k) {
      if (k < static_cast<int>(r.solvers.size())) {
        const auto& s = r.solvers[k];
        m << s.method << ", " << s.nnz_A << ", " << s.nnz_factor << ", " << fix(fill(s), 2) << " ("
          << fix(fill_vs_stored(s), 2) << ")";
      }
      m << " | ";
    }
    m << fix(r.paper_scaled(), 0) << " | " << fix(r.ratio(), 0) << " |\n";
  }
  return m.str();
}

std::string make_md(const std::vector<Result>& rs, const Options& o) {
  std::ostringstream m;
  const double t_end = o.steps * kDt;
  m << "# Start-up planar Poiseuille sweep (EPSPH), Noutcheuwa & Owens (2012) Section 5.1\n\n"
    << "Re = 0.0125 (rho = 1, mu = 1/Re = 80, F = 8/Re = 640 in x, u_max = 1), domain [0,1]^2 periodic in x, "
    << "no-slip walls at y = 0, 1, dt = 1.25e-6, " << o.steps << " steps, errors at t = " << sci(t_end, 6) << ".\n\n"
    << (o.convection ? "Convection ON (AB2, Eq. 39).\n\n"
                     : "Convection OFF (Stokes): the paper's problem is unidirectional, u = u(y, t), v = 0, so "
                       "(u.grad)u = 0 exactly.\n\n")
    << "Pressure recovery (Eq. 35) every step: " << (o.pressure ? "on" : "off (lazy, never asked for)")
    << ". Linear solvers: " << o.solver << ". Single-threaded (OMP_NUM_THREADS=1), CPU: " << cpu_model() << ".\n\n";
  if (o.steps != kPaperSteps)
    m << "**Shortened run**: " << o.steps << " of 10 000 steps; the errors are at t = " << sci(t_end, 6)
      << " (not 1.25e-2, flow not yet developed) and the paper's Table 1 times are scaled by " << o.steps
      << "/10000 for the ratio (our set-up is not scaled).\n\n";
  m << "## rms velocity error, Eq. (69) (data of Figs. 4 and 7)\n\n"
    << h_by_nx(rs, o, [](const Result& r) { return sci(r.err.rms, 3); }) << orders_md(rs, o) << fit_md(rs, o)
    << "\n## Total time, set-up + " << o.steps << " steps, seconds (cf. Table 1)\n\n"
    << h_by_nx(rs, o, [](const Result& r) { return fix(r.total(), 3); })
    << "\n## Paper Table 1 time (value x 1e5 s" << (o.steps != kPaperSteps ? ", scaled to our step count" : "")
    << ") / our total time\n\n"
    << h_by_nx(rs, o, [](const Result& r) { return fix(r.ratio(), 0); }) << per_run_md(rs);
  if (const Result* r = find(rs, 64, 1.525)) {
    m << "\n## 64 x 64, h = 1.525 dx\n\nTotal " << fix(r->total(), 2) << " s for " << r->steps << " steps";
    if (r->steps != kPaperSteps) m << " (extrapolated to 10 000 steps: " << fix(r->total_10k(), 2) << " s)";
    m << "; target " << fix(kTargetSeconds, 0) << " s; paper 54 018 s. rms error " << sci(r->err.rms, 3) << ".\n";
  }
  return m.str();
}

void print_run(const Result& r, bool verbose) {
  std::printf("Nx=%3d h/dx=%-5s ", r.nx, num(r.hdx).c_str());
  if (!r.ok()) {
    std::printf("FAILED: %s\n", r.status.c_str());
    std::fflush(stdout);
    return;
  }
  std::printf(
      "rms=%.4e  nb/p=%5.1f  setup %.3f s (nb %.3f asm %.3f fact %.3f)  loop %.3f s = %.1f us/step "
      "(products %.1f, solves %.1f)  total %.3f s",
      r.err.rms, r.nb_per_particle, r.t_ctor, r.t_neigh, r.t_asm, r.t_fact, r.t_loop, 1e6 * r.per_step(),
      1e6 * r.t_products / r.steps, 1e6 * r.t_solves / r.steps, r.total());
  if (std::isfinite(r.ratio())) std::printf("  paper/ours %.0f", r.ratio());
  std::printf("\n");
  if (verbose) {
    for (const auto& s : r.solvers) std::printf("    %s\n", s.describe().c_str());
    std::printf("    per step:");
    for (const auto& p : r.phases) std::printf("  %s %.2f us", p.name.c_str(), 1e6 * p.seconds / r.steps);
    std::printf("\n    rms u %.4e  rms v %.4e  max |e| %.4e  max |div u| %.3e\n", r.err.rms_u, r.err.rms_v, r.err.max,
                r.max_div);
  }
  std::fflush(stdout);
}

int sweep(const Options& o) {
  const std::filesystem::path dir = create_out_dir(o.out);
  std::printf("Start-up planar Poiseuille (Noutcheuwa & Owens 2012, Sec. 5.1): Re = %g, dt = %g, %ld steps, "
              "t_end = %g%s\n",
              kRe, kDt, o.steps, o.steps * kDt, o.steps == kPaperSteps ? "" : " (shortened: not the paper's 0.0125)");
  std::printf("%s; pressure recovery %s; solvers %s; single-threaded; %zu runs\n",
              o.convection ? "convection ON (AB2)"
                           : "convection OFF (Stokes: the flow is unidirectional, (u.grad)u = 0 exactly)",
              o.pressure ? "every step" : "off (lazy, never asked for)", o.solver.c_str(), o.nx.size() * o.h.size());
  std::vector<Result> rs;
  const auto t_all = Clock::now();
  for (double h : o.h)
    for (int n : o.nx) {
      rs.push_back(run_one(n, h, o));
      print_run(rs.back(), o.verbose);
      sphib::write_file_atomic((dir / "poiseuille_sweep.csv").string(), make_csv(rs, o));
      sphib::write_file_atomic((dir / "poiseuille_sweep.md").string(), make_md(rs, o));
    }
  double est = 0;
  for (const Result& r : rs)
    if (r.ok()) est += r.total_10k();
  std::printf("sweep wall time %.1f s", seconds_since(t_all));
  if (o.steps != kPaperSteps) std::printf("; these runs at the paper's 10000 steps: about %.0f s", est);
  std::printf("\n\n%s", make_md(rs, o).c_str());
  if (const Result* r = find(rs, 64, 1.525))
    std::printf("\n64 x 64, h = 1.525 dx: extrapolated to 10000 steps %.2f s (target %.0f s: %s; paper 54 018 s)\n",
                r->total_10k(), kTargetSeconds, r->total_10k() <= kTargetSeconds ? "met" : "MISSED");
  std::printf("wrote %s and %s\n", (dir / "poiseuille_sweep.csv").c_str(), (dir / "poiseuille_sweep.md").c_str());
  const long failed = std::count_if(rs.begin(), rs.end(), [](const Result& r) { return !r.ok(); });
  if (failed) std::printf("%ld run(s) failed (see status column)\n", failed);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Start-up planar Poiseuille sweep (Figs. 4, 7, Table 1) with EPSPH", "poiseuille_sweep"};
  app.add_option("--nx", o.nx, "Nx = Ny values")->delimiter(',')->check(CLI::Range(2, 1 << 16))->capture_default_str();
  app.add_option("--h", o.h, "h/dx values")->delimiter(',')->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--steps", o.steps,
                 "time steps (fewer: the error is at t = N dt and the paper's time is scaled by N/10000)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--out", o.out, "output directory")->capture_default_str();
  app.add_flag("--convection", o.convection, "keep the AB2 convection term (default: Stokes, the flow is unidirectional)");
  app.add_flag("--pressure", o.pressure, "recover the pressure (Eq. 35) after every step (the library does it lazily)");
  app.add_option("--solver", o.solver, "linear solvers for both systems (pcg: Crank-Nicolson only, Poisson gets auto)")
      ->check(CLI::IsMember({"auto", "supernodal", "simplicial", "umfpack", "pcg"}))->capture_default_str();
  app.add_flag("-v,--verbose", o.verbose, "print the per-phase breakdown and solver lines of every run");
  return run_main(app, argc, argv, [&] { return sweep(o); });
}
