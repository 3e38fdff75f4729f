#include "io/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <numeric>
#include <ostream>
#include <sstream>

#include "coupling/interpolate.hpp"
#include "fluid/exact.hpp"
#include "fluid/projection.hpp"
#include "io/checkpoint.hpp"
#include "io/csv_writer.hpp"
#include "io/hdf5_writer.hpp"
#include "io/summary.hpp"
#include "membrane/geometry.hpp"
#include "sphib_version.hpp"

namespace sphib {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double rms(const Mat2& a) { return std::sqrt(a.squaredNorm() / a.rows()); }

// ---- Exact solutions on the particles -------------------------------------------------------

// Eq. (69): rms over particles of |u_ex - u|, for the unidirectional start-up flows.
double rms_error_unidirectional(const Scene& s, const FluidSolver& fl) {
  const FluidParams& p = fl.params();
  const double H = p.domain.Ly(), nu = p.mu / p.rho;
  const Mat2& x = fl.x();
  const Mat2& u = fl.u();
  double e = 0;
  std::map<double, double> memo;  // the exact series depends on y only: once per lattice row
  for (int i = 0; i < x.rows(); ++i) {
    const double y = x(i, 1) - p.domain.y0;
    if (auto it = memo.find(y); it != memo.end()) {
      e += (it->second - u(i, 0)) * (it->second - u(i, 0)) + u(i, 1) * u(i, 1);
      continue;
    }
    double ue = 0;
    if (s.exact == "poiseuille") {
      // dimensional form of Eq. (44): u_max = F H^2 / (8 mu), Re = rho u_max H / mu
      const double umax = s.sim.body_force.x() * H * H / (8.0 * p.mu);
      const double Re = p.rho * umax * H / p.mu;
      ue = umax * exact::poiseuille_u(y / H, fl.time() * umax / H, Re);
    } else {
      const double U = p.domain.wall_velocity[Top].x() - p.domain.wall_velocity[Bottom].x();
      ue = p.domain.wall_velocity[Bottom].x() + exact::couette_u(y, fl.time(), nu, U, H);
    }
    memo[y] = ue;
    e += (ue - u(i, 0)) * (ue - u(i, 0)) + u(i, 1) * u(i, 1);
  }
  return std::sqrt(e / x.rows());
}

// ---- Ghia, Ghia & Shin (1982) tables --------------------------------------------------------

struct Table {
  std::vector<std::string> cols;
  std::vector<std::vector<double>> rows;
  int col(const std::string& name) const {
    for (size_t k = 0; k < cols.size(); ++k)
      if (cols[k] == name) return static_cast<int>(k);
    return -1;
  }
};

Table read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw RunError("cavity: cannot read the reference table " + path);
  Table t;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    std::vector<std::string> cells;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (t.cols.empty()) { t.cols = cells; continue; }
    std::vector<double> r;
    for (const auto& c : cells) r.push_back(std::stod(c));
    t.rows.push_back(r);
  }
  return t;
}

// ---- Membrane observations -----------------------------------------------------------------

struct MembraneObs {
  MembraneDiagnostics D;
  double area0;
  std::map<int, double> area_at;  // relative area error at t = 1, 2, 5, 10
};

// The stretched membrane in equilibrium (Section 5.2.1): exact [p] = p_in - p_out =
// (T0/re)(re/r0 - 1) (Eq. 66 with the physical sign: the inside pressure is higher), u = 0.
struct Equilibrium {
  double jump, jump_exact, p_mad, u_mad;
};

Equilibrium measure_equilibrium(const Scene& scene, const Simulation& sim, const Eigen::Vector2d& c) {
  // Regions for the measured jump: inside r < re - 2h* - 2h, outside r > re + 2h* + 2h and more
  // than 2h from a wall, r from the membrane's centroid: both clear of the smoothed jump
  // (spreading support 2h*, SPH support 2h).
  const FluidSolver& fl = sim.fluid();
  const FluidParams& fp = fl.params();
  const MembraneScene& ms = scene.membranes[0];
  const double re = ms.radius;
  Equilibrium e{};
  e.jump_exact = ms.T0 / re * (re / ms.r0 - 1.0);
  const double band = 2.0 * sim.membranes()[0].h_star + 2.0 * fl.h();
  const Mat2& x = fl.x();
  const Vec& p = fl.p();
  const int N = fl.size();
  double pin = 0, pout = 0;
  int nin = 0, nout = 0;
  std::vector<double> shifted(N);
  for (int i = 0; i < N; ++i) {
    const double r = std::hypot(x(i, 0) - c.x(), x(i, 1) - c.y());
    double wall_gap = INFINITY;
    if (!fp.domain.periodic_x) wall_gap = std::min({wall_gap, x(i, 0) - fp.domain.x0, fp.domain.x1 - x(i, 0)});
    if (!fp.domain.periodic_y) wall_gap = std::min({wall_gap, x(i, 1) - fp.domain.y0, fp.domain.y1 - x(i, 1)});
    if (r < re - band) { pin += p[i]; ++nin; }
    if (r > re + band && wall_gap > 2.0 * fl.h()) { pout += p[i]; ++nout; }
    shifted[i] = p[i] - (r < re ? e.jump_exact : 0.0);
    e.u_mad += std::fabs(fl.u()(i, 0)) + std::fabs(fl.u()(i, 1));  // Eq. (83), u_ex = 0
  }
  e.u_mad /= N;
  // Eq. (80) with the free constant of p_ex chosen optimally: the median minimises the mean |.|
  std::vector<double> sorted(shifted);
  std::nth_element(sorted.begin(), sorted.begin() + N / 2, sorted.end());
  const double c_opt = sorted[N / 2];
  for (int i = 0; i < N; ++i) e.p_mad += std::fabs(shifted[i] - c_opt);
  e.p_mad /= N;
  e.jump = (nin && nout) ? pin / nin - pout / nout : NAN;
  return e;
}

}  // namespace

nlohmann::json run_scene(const Scene& scene, const RunOptions& opt) {
  namespace fs = std::filesystem;
  std::ostream* log = opt.log;
  auto say = [&](const std::string& s) { if (log) *log << s << std::endl; };

  // Set-up: everything that can refuse the scene happens before anything is written.
  const auto t_setup = Clock::now();
  Simulation sim(scene.sim);
  if (!opt.restart.empty()) restore_checkpoint(read_checkpoint(opt.restart), opt.restart, scene.resolved, sim);
  if (opt.before_run) opt.before_run(sim);
  const double setup_seconds = since(t_setup);
  FluidSolver& fl = sim.fluid();
  const FluidParams& fp = fl.params();
  const int N = fl.size();
  Table ghia_u, ghia_v;
  std::string ghia_col_u, ghia_col_v;
  double Re_cavity = 0;
  if (scene.exact == "cavity") {
    const double U = fp.domain.wall_velocity[Top].x();
    Re_cavity = fp.rho * U * fp.domain.Lx() / fp.mu;
    ghia_u = read_csv(scene.reference_dir + "/ghia1982_u_vertical_centreline.csv");
    ghia_v = read_csv(scene.reference_dir + "/ghia1982_v_horizontal_centreline.csv");
    const std::string re = std::to_string(static_cast<long>(std::lround(Re_cavity)));
    if (ghia_u.col("u_re" + re) >= 0 && std::fabs(Re_cavity - std::lround(Re_cavity)) < 1e-9) {
      ghia_col_u = "u_re" + re;
      ghia_col_v = "v_re" + re;
    }
  }
  std::error_code ec;
  fs::create_directories(opt.out_dir, ec);
  if (ec || !fs::is_directory(opt.out_dir))
    throw std::runtime_error("output directory " + opt.out_dir + " cannot be created: " + ec.message());

  {
    std::ostringstream m;
    m << "sphib " << SPHIB_VERSION << ": " << (scene.title.empty() ? scene.path : scene.title) << "\n"
      << "  rho = " << fp.rho << ", mu = " << fp.mu << ", dt = " << fp.dt << "\n";
    for (const auto& line : fl.describe()) m << "  " << line << "\n";
    m << "  set-up " << setup_seconds << " s (neighbours " << fl.setup_seconds("neighbours") << " s, assembly "
      << fl.setup_seconds("assembly") << " s, factorisation " << fl.setup_seconds("factorisation") << " s)";
    for (size_t k = 0; k < sim.membranes().size(); ++k) {
      const auto& ms = sim.membranes()[k];
      m << "\n  membrane " << k << ": Nb = " << ms.m.nb() << ", L0 = " << ms.m.L0 << ", T0 = " << ms.m.T0
        << ", h* = " << ms.h_star << (ms.fixed ? ", fixed" : ", free") << ", markers per grid spacing "
        << fl.lattice().dx / ms.m.ds();
    }
    say(m.str());
  }

  // Observers
  std::vector<MembraneObs> mobs;
  for (const auto& ms : sim.membranes()) {
    MembraneObs o{MembraneDiagnostics(ms.m.nb(), ms.m.L0), 0.0, {}};
    o.area0 = o.D.measure(ms.m.X, ms.m.T0).area;
    mobs.push_back(std::move(o));
  }
  const bool unidirectional = scene.exact == "poiseuille" || scene.exact == "couette";
  std::vector<std::string> cols{"t", "step", "kinetic_energy", "max_div_u", "max_speed"};
  if (unidirectional) cols.push_back("rms_error");
  if (scene.steady_eps > 0) { cols.push_back("du_rms"); cols.push_back("dp_rms"); }
  const bool equilibrium = scene.exact == "membrane_equilibrium" && !scene.membranes.empty();
  if (equilibrium) { cols.push_back("pressure_jump"); cols.push_back("pressure_mad_error"); cols.push_back("velocity_mad_error"); }
  for (const auto& o : scene.observers) cols.push_back(o.name);
  for (size_t k = 0; k < mobs.size(); ++k) {
    const std::string p = "m" + std::to_string(k) + "_";
    for (const char* c : {"rx", "ry", "cx", "cy", "area", "area_rel_error", "elastic_energy", "length", "iterations"})
      cols.push_back(p + c);
  }

  const size_t col_area0 = std::find(cols.begin(), cols.end(), "m0_area_rel_error") - cols.begin();
  RunAttributes attrs;
  attrs.text.emplace_back("sphib_version", SPHIB_VERSION);
  attrs.text.emplace_back("scene", scene.path);
  for (const auto& [k, v] : scene.resolved) attrs.text.emplace_back(k, v);
  attrs.numbers.emplace_back("derived.h", fl.h());
  attrs.numbers.emplace_back("derived.dx", fl.lattice().dx);
  attrs.numbers.emplace_back("derived.dy", fl.lattice().dy);
  if (!scene.membranes.empty()) {
    attrs.numbers.emplace_back("derived.membrane_radius", scene.membranes[0].radius);
    attrs.numbers.emplace_back("derived.membrane_r0", scene.membranes[0].r0);
    attrs.numbers.emplace_back("derived.membrane_h_star", sim.membranes()[0].h_star);
  }
  Hdf5Writer h5(opt.out_dir + "/output.h5", attrs);
  CsvWriter csv(opt.out_dir + "/diagnostics.csv", cols);
  std::vector<std::vector<double>> series;

  const long n_total = scene.max_steps > 0
                           ? std::min<long>(scene.max_steps, std::lround(scene.t_end / fp.dt))
                           : std::lround(scene.t_end / fp.dt);
  const long diag_every = scene.diagnostics_every > 0 ? scene.diagnostics_every : std::max<long>(1, n_total / 500);
  const long out_every = scene.output_interval > 0 ? std::max<long>(1, std::lround(scene.output_interval / fp.dt)) : 0;
  const long ckpt_every =
      scene.checkpoint_interval > 0 ? std::max<long>(1, std::lround(scene.checkpoint_interval / fp.dt)) : 0;
  const std::string ckpt_path = opt.out_dir + "/checkpoint.h5";

  Vec u_field(N), v_field(N);
  auto snapshot = [&]() {
    u_field = fl.u().col(0);
    v_field = fl.u().col(1);
    std::vector<std::pair<std::string, const Vec*>> fields;
    for (const auto& f : scene.fields) {
      if (f == "u") fields.emplace_back("u", &u_field);
      if (f == "v") fields.emplace_back("v", &v_field);
      if (f == "p") fields.emplace_back("p", &fl.p());
      if (f == "phi") fields.emplace_back("phi", &fl.phi());
    }
    std::vector<MembraneSnapshot> ms;
    for (const auto& m : sim.membranes()) ms.push_back({&m.m.X, &m.f, &m.T});
    h5.write_snapshot(static_cast<int>(fl.steps()), fl.time(), fl.x(), fields, ms,
                      fl.particles_move() ? nullptr : &fl.lattice());  // a fixed lattice: a quadrilateral mesh
  };

  Mat2 u_prev;
  Vec p_prev;
  double du_rms = NAN, dp_rms = NAN;
  auto diagnostics_row = [&]() {
    std::vector<double> r{fl.time(), static_cast<double>(fl.steps()), fl.kinetic_energy(), fl.max_abs_divergence(),
                          fl.u().rowwise().norm().maxCoeff()};
    if (unidirectional) r.push_back(rms_error_unidirectional(scene, fl));
    if (scene.steady_eps > 0) { r.push_back(du_rms); r.push_back(dp_rms); }
    if (equilibrium) {
      mobs[0].D.fit(sim.membranes()[0].m.X);
      const Equilibrium e = measure_equilibrium(scene, sim, mobs[0].D.centroid());
      r.push_back(e.jump);
      r.push_back(e.p_mad);
      r.push_back(e.u_mad);
    }
    for (const auto& o : scene.observers) r.push_back(o.value(sim));
    for (size_t k = 0; k < mobs.size(); ++k) {
      const auto& m = sim.membranes()[k];
      const MembraneShape s = mobs[k].D.measure(m.m.X, m.m.T0);
      for (double v : {s.rx, s.ry, s.cx, s.cy, s.area, s.area / mobs[k].area0 - 1.0, s.energy, s.length,
                       static_cast<double>(m.last.iterations)})
        r.push_back(v);
    }
    csv.row(r);
    series.push_back(r);
  };

  say("  " + std::to_string(n_total) + " steps to t = " + std::to_string(n_total * fp.dt) + ", output in " + opt.out_dir);
  snapshot();
  diagnostics_row();
  const double h_min = std::min(fl.lattice().dx, fl.lattice().dy);
  bool unforced = !mobs.empty() && !scene.sim.body_force_field && scene.sim.body_force.norm() == 0.0;
  for (int k = 0; k < 4; ++k)
    unforced &= !fp.domain.is_wall(static_cast<Side>(k)) || fp.domain.wall_velocity[k].norm() == 0.0;
  double energy_bound = 0;
  if (unforced) {
    double E0 = fl.kinetic_energy();
    for (size_t k = 0; k < mobs.size(); ++k) {
      mobs[k].D.fit(sim.membranes()[k].m.X);
      E0 += mobs[k].D.energy(sim.membranes()[k].m.T0);
    }
    energy_bound = E0 > 0 ? 10.0 * E0 : 0.0;
  }
  Profile run_prof;  // the loop's own work: blow-up checks and diagnostics, output
  const int k_checks = run_prof.phase("run-time checks and diagnostics"), k_output = run_prof.phase("output");
  const auto t_loop = Clock::now();
  auto t_log = t_loop;
  std::string stop_reason = "end time";
  std::string fault;
  try {
    while (fl.steps() < n_total) {
      if (opt.stop && opt.stop->load()) { stop_reason = "interrupted"; break; }
      if (scene.steady_eps > 0) { u_prev = fl.u(); p_prev = fl.p(); }
      const long n_before = fl.steps();
      const double t_before = fl.time();
      try {
        sim.step();
      } catch (const std::exception& e) {
        std::ostringstream m;
        m << "step " << n_before + 1 << " (t = " << t_before + fp.dt << "): " << e.what();
        throw RunError(m.str());
      }
      // A blow-up stops the run within the step it appears in, before anything of it is written.
      auto t_checks = Clock::now();
      const double ke = fl.kinetic_energy();
      if (!std::isfinite(ke)) {
        std::ostringstream m;
        m << "the velocity field became non-finite at step " << fl.steps() << " (t = " << fl.time() << ")";
        throw RunError(m.str());
      }
      // Blow-up: no particle may move by more than a lattice spacing in one step (u_max dt < dx).
      // The explicit convection (AB2) and the marker update are unstable long before that.
      const double cfl = std::sqrt(2.0 * ke / (fp.rho * fl.volumes().minCoeff())) * fp.dt / h_min;
      if (cfl > 1.0) {
        const double umax = fl.u().rowwise().norm().maxCoeff();
        if (umax * fp.dt > h_min) {
          std::ostringstream m;
          m << "blow-up at step " << fl.steps() << " (t = " << fl.time() << "): max |u| = " << umax
            << " moves a particle by " << umax * fp.dt / h_min << " lattice spacings in one step (limit 1)";
          throw RunError(m.str());
        }
      }
      for (size_t k = 0; k < sim.membranes().size(); ++k)
        if (!sim.membranes()[k].m.X.allFinite()) {
          std::ostringstream m;
          m << "membrane " << k << " markers became non-finite at step " << fl.steps() << " (t = " << fl.time() << ")";
          throw RunError(m.str());
        }
      // Unforced membranes can only lose energy (viscous dissipation): a total energy past ten times
      // its initial value is a blow-up of the explicit elastic force, caught before fields overflow.
      if (energy_bound > 0) {
        double E = ke;
        for (size_t k = 0; k < mobs.size(); ++k) {
          mobs[k].D.fit(sim.membranes()[k].m.X);
          E += mobs[k].D.energy(sim.membranes()[k].m.T0);
        }
        if (!(E <= energy_bound)) {
          std::ostringstream m;
          m << "blow-up at step " << fl.steps() << " (t = " << fl.time() << "): kinetic + elastic energy " << E
            << " exceeds ten times its initial value (" << energy_bound / 10.0 << ") in an unforced flow";
          throw RunError(m.str());
        }
      }
      for (auto& o : mobs)
        for (int T : {1, 2, 5, 10})
          if (!o.area_at.count(T) && fl.time() >= T - 0.5 * fp.dt) {
            const auto& m = sim.membranes()[&o - &mobs[0]];
            o.area_at[T] = o.D.measure(m.m.X, m.m.T0).area / o.area0 - 1.0;
          }
      bool steady = false;
      if (scene.steady_eps > 0) {
        du_rms = rms(fl.u() - u_prev);                                                 // Eq. (82)
        dp_rms = std::sqrt((fl.p() - p_prev).squaredNorm() / N);                       // Eq. (81)
        steady = fl.steps() > 2 && std::max(du_rms, dp_rms) < scene.steady_eps * fp.dt;
      }
      const bool last = fl.steps() == n_total || steady;
      if (fl.steps() % diag_every == 0 || last) diagnostics_row();
      run_prof.add(k_checks, since(t_checks));
      if ((out_every && fl.steps() % out_every == 0 && !last) || (ckpt_every && fl.steps() % ckpt_every == 0 && !last)) {
        ScopedTimer tm(run_prof, k_output);
        if (out_every && fl.steps() % out_every == 0) snapshot();
        if (ckpt_every && fl.steps() % ckpt_every == 0) write_checkpoint(ckpt_path, sim, scene.resolved);
      }
      if (steady) { stop_reason = "steady state"; break; }
      if (log && since(t_log) > (opt.progress_bar ? 0.5 : opt.log_every_seconds)) {
        t_log = Clock::now();
        const double el = since(t_loop), rate = fl.steps() / el, eta = (n_total - fl.steps()) / rate;
        std::ostringstream m;
        m << std::setprecision(4) << "  step " << fl.steps() << "/" << n_total << " t = " << fl.time() << "  "
          << rate << " steps/s  ETA " << eta << " s  KE = " << ke;
        if (!mobs.empty()) m << "  area err = " << series.back()[col_area0];
        if (opt.progress_bar) {
          const int w = 30, done = static_cast<int>(w * fl.steps() / n_total);
          *log << "\r[" << std::string(done, '#') << std::string(w - done, ' ') << "]" << m.str() << "   " << std::flush;
        } else {
          say(m.str());
        }
      }
    }
  } catch (const std::exception& e) {
    fault = e.what();
    stop_reason = "fault";
  }
  const double loop_seconds = since(t_loop);
  if (log && opt.progress_bar) *log << "\n";
  if (fault.empty()) {  // the last good state (a faulty one is never written)
    snapshot();
    if (fl.steps() > 0) {
      try {
        write_checkpoint(ckpt_path, sim, scene.resolved);
      } catch (const std::runtime_error& e) {
        if (fl.params().method == "eulerian") throw;  // other methods may have no checkpoints yet
      }
    }
  }
  h5.write_series("diagnostics", cols, series);
  h5.close();
  csv.close();

  // Summary
  nlohmann::json j;
  j["sphib_version"] = SPHIB_VERSION;
  j["scene"] = scene.path;
  j["stop_reason"] = stop_reason;
  if (!fault.empty()) j["fault"] = fault;
  j["steps"] = fl.steps();
  j["time"] = fl.time();
  j["particles"] = N;
  j["method"] = fp.method;
  j["wall_seconds"] = loop_seconds + setup_seconds;
  j["setup_seconds"] = setup_seconds;
  j["loop_seconds"] = loop_seconds;
  j["seconds_per_step"] = fl.steps() ? loop_seconds / fl.steps() : 0.0;
  nlohmann::json prof;
  for (const Profile* P : {&fl.profile(), &sim.profile(), &run_prof})
    for (size_t k = 0; k < P->names().size(); ++k) prof[P->names()[k]] = P->seconds(static_cast<int>(k));
  j["profile_seconds"] = prof;
  for (const auto& line : fl.describe()) j["log"].push_back(line);
  if (const auto* epsph = dynamic_cast<const Fluid*>(&fl); epsph && fl.steps() > 0) {
    // Step time against its floor (the bare solves and products, timed alone on the final state).
    double fluid_seconds = 0;
    for (size_t k = 0; k < fl.profile().names().size(); ++k) fluid_seconds += fl.profile().seconds(static_cast<int>(k));
    const double floor = epsph->floor_seconds();
    j["floor_seconds_per_step"] = floor;
    j["fluid_step_over_floor"] = fluid_seconds / fl.steps() / floor;
    j["step_over_floor"] = loop_seconds / fl.steps() / floor;
  }
  for (const auto& [k, v] : fl.figures()) j[k] = v;
  if (!fault.empty()) {  // the state is not trustworthy: no figures from it
    write_json_atomic(opt.out_dir + "/summary.json", j);
    say("  stopped by a fault at step " + std::to_string(fl.steps()) + ": " + fault);
    throw RunError(fault + "; the last good state is in " + opt.out_dir);
  }
  j["kinetic_energy"] = fl.kinetic_energy();
  j["max_div_u"] = fl.max_abs_divergence();
  j["max_speed"] = fl.u().rowwise().norm().maxCoeff();
  if (unidirectional) j["rms_error"] = rms_error_unidirectional(scene, fl);
  for (const auto& o : scene.observers) j[o.name] = o.value(sim);
  if (scene.steady_eps > 0) { j["du_rms"] = du_rms; j["dp_rms"] = dp_rms; }

  if (scene.exact == "cavity") {
    // Centre-line profiles by normalised SPH interpolation (Eq. 61) at Ghia's points; the wall
    // points (boundary values, not computed) are left out.
    CellGrid grid(Eigen::Vector2d(fp.domain.x0, fp.domain.y0), Eigen::Vector2d(fp.domain.x1, fp.domain.y1),
                  fp.domain.periodic_x, fp.domain.periodic_y, 2.0 * fl.h());
    grid.build(fl.x());
    auto profile = [&](const Table& t, bool vertical, const std::string& col, const std::string& name) {
      std::vector<double> dev;
      Mat2 X(static_cast<int>(t.rows.size()), 2), U(static_cast<int>(t.rows.size()), 2);
      for (size_t k = 0; k < t.rows.size(); ++k) {
        const double c = t.rows[k][0];
        X(k, 0) = vertical ? fp.domain.x0 + 0.5 * fp.domain.Lx() : fp.domain.x0 + c * fp.domain.Lx();
        X(k, 1) = vertical ? fp.domain.y0 + c * fp.domain.Ly() : fp.domain.y0 + 0.5 * fp.domain.Ly();
      }
      interpolate_velocity(grid, fl.kernel(), fl.volumes(), fl.u(), X, U);
      std::ofstream out(opt.out_dir + "/" + name + ".csv");
      out << (vertical ? "y,u" : "x,v") << (col.empty() ? "" : "," + col) << "\n";
      const int cc = col.empty() ? -1 : t.col(col);
      for (size_t k = 0; k < t.rows.size(); ++k) {
        const double c = t.rows[k][0], val = U(k, vertical ? 0 : 1);
        out << std::setprecision(10) << c << "," << val;
        if (cc >= 0) {
          out << "," << t.rows[k][cc];
          if (c > 0 && c < 1) dev.push_back(val - t.rows[k][cc]);
        }
        out << "\n";
      }
      return dev;
    };
    std::vector<double> du = profile(ghia_u, true, ghia_col_u, "centreline_u");
    std::vector<double> dv = profile(ghia_v, false, ghia_col_v, "centreline_v");
    j["reynolds"] = Re_cavity;
    if (!ghia_col_u.empty()) {
      auto stats = [](const std::vector<double>& d, double& mx, double& rm) {
        mx = 0; rm = 0;
        for (double x : d) { mx = std::max(mx, std::fabs(x)); rm += x * x; }
        rm = d.empty() ? 0 : std::sqrt(rm / d.size());
      };
      double mu_, ru, mv, rv;
      stats(du, mu_, ru);
      stats(dv, mv, rv);
      std::vector<double> all(du);
      all.insert(all.end(), dv.begin(), dv.end());
      double ma, ra;
      stats(all, ma, ra);
      j["reference"] = "Ghia, Ghia & Shin (1982), column " + ghia_col_u + "/" + ghia_col_v;
      j["max_deviation"] = ma;
      j["rms_deviation"] = ra;
      j["max_deviation_u"] = mu_;
      j["rms_deviation_u"] = ru;
      j["max_deviation_v"] = mv;
      j["rms_deviation_v"] = rv;
    } else {
      j["reference"] = "none: Ghia et al. tabulate Re = 100, 400, 1000 only";
    }
  }

  if (!sim.membranes().empty()) {
    const auto& m0 = sim.membranes()[0];
    const MembraneShape s = mobs[0].D.measure(m0.m.X, m0.m.T0);
    j["area"] = s.area;
    j["area_exact"] = mobs[0].area0;
    j["area_relative_error"] = s.area / mobs[0].area0 - 1.0;
    j["rx"] = s.rx;
    j["ry"] = s.ry;
    j["elastic_energy"] = s.energy;
    for (const auto& [T, e] : mobs[0].area_at) j["area_relative_error_at"][std::to_string(T)] = e;
    j["marker_iterations_last"] = m0.last.iterations;
    if (m0.updates > 0) j["marker_iterations_mean"] = static_cast<double>(m0.iterations) / m0.updates;
  }

  if (scene.exact == "membrane_equilibrium" && !sim.membranes().empty()) {
    const Equilibrium e = measure_equilibrium(scene, sim, mobs[0].D.centroid());
    j["pressure_jump"] = e.jump;
    j["pressure_jump_exact"] = e.jump_exact;
    j["pressure_jump_regions"] = "inside r < re - 2h* - 2h, outside r > re + 2h* + 2h and > 2h from walls";
    j["pressure_mad_error"] = e.p_mad;
    j["velocity_mad_error"] = e.u_mad;
  }

  if (scene.exact == "membrane_oscillation" && !series.empty() && !mobs.empty()) {
    // Period and decay of rx(t): extrema of the m0_rx series; period = 2 x mean spacing of
    // successive extrema; amplitudes A_k = |rx_k - rx_eq| with rx_eq the mean of the last two
    // extrema (the final value if fewer than two); amplitude_decay = A(t + period)/A(t) from a
    // least-squares fit of log A_k = a - lambda t_k.
    const int ct = 0, crx = static_cast<int>(std::find(cols.begin(), cols.end(), "m0_rx") - cols.begin());
    std::vector<double> te, xe;
    for (size_t k = 1; k + 1 < series.size(); ++k) {
      const double a = series[k - 1][crx], b = series[k][crx], c = series[k + 1][crx];
      if ((b > a && b >= c) || (b < a && b <= c)) { te.push_back(series[k][ct]); xe.push_back(b); }
    }
    if (te.size() >= 3) {
      double gaps = 0;
      for (size_t k = 1; k < te.size(); ++k) gaps += te[k] - te[k - 1];
      const double period = 2.0 * gaps / (te.size() - 1);
      const double rx_eq = 0.5 * (xe[xe.size() - 1] + xe[xe.size() - 2]);
      double st = 0, sa = 0, stt = 0, sta = 0;
      int n = 0;
      for (size_t k = 0; k + 1 < te.size(); ++k) {
        const double A = std::fabs(xe[k] - rx_eq);
        if (A <= 0) continue;
        st += te[k]; sa += std::log(A); stt += te[k] * te[k]; sta += te[k] * std::log(A); ++n;
      }
      j["period"] = period;
      j["extrema"] = te.size();
      if (n >= 2) {
        const double lambda = -(n * sta - st * sa) / (n * stt - st * st);
        j["amplitude_decay_rate"] = lambda;
        j["amplitude_decay"] = std::exp(-lambda * period);
      }
    } else {
      j["period"] = nullptr;  // not measurable: monotone or too short
    }
    j["rx_first_minimum"] = nullptr;
    for (size_t k = 0; k < te.size(); ++k) {
      const auto it = std::find_if(series.begin(), series.end(), [&](const auto& r) { return r[ct] == te[k]; });
      const size_t i = it - series.begin();
      if (i > 0 && series[i - 1][crx] > xe[k]) {  // a minimum
        j["rx_first_minimum"] = xe[k];
        j["t_first_minimum"] = te[k];
        break;
      }
    }
  }

  write_json_atomic(opt.out_dir + "/summary.json", j);
  say("  " + stop_reason + " after " + std::to_string(fl.steps()) + " steps, t = " + std::to_string(fl.time()) +
      ", loop " + std::to_string(loop_seconds) + " s (" + std::to_string(1e6 * j["seconds_per_step"].get<double>()) +
      " us/step); output in " + opt.out_dir);
  return j;
}

}  // namespace sphib
