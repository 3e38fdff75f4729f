#include "io/run.hpp"

#include <filesystem>
#include <sstream>

#include "io/checkpoint.hpp"
#include "io/output.hpp"
#include "io/progress.hpp"
#include "io/summary.hpp"
#include "observe/guards.hpp"
#include "sphib_version.hpp"

namespace sphib {

namespace {

// The analyses a scene asks for, in the order of their columns. Reads what they need (the Ghia
// tables) now, before anything is written.
Observers observers_for(const Scene& scene, const Simulation& sim, const std::string& out_dir) {
  Observers o;
  o.add(flow_figures());
  if (scene.exact == "poiseuille") o.add(exact_series(StartUpFlow::Poiseuille, scene.sim.body_force.x()));
  if (scene.exact == "couette") o.add(exact_series(StartUpFlow::Couette, 0.0));
  if (scene.exact == "inclined_plane") {  // the layer's depth: the fill block's height
    const FluidRegion& fill = scene.sim.fluid.free_surface.fill;
    const Domain& d = scene.sim.fluid.domain;
    const double depth = fill.shape == FluidRegion::Shape::Block ? fill.y1 - fill.y0 : d.Ly();
    o.add(exact_series(StartUpFlow::InclinedPlane, scene.sim.body_force.x(), depth));
  }
  if (scene.exact == "droplet") o.add(droplet_axis(sim));
  if (scene.exact == "dam_break") o.add(dam_break_front(sim, scene.reference_dir));
  if (scene.loads) o.add(wall_loads(sim));
  if (scene.steady_eps > 0) o.add(steady_state(scene.steady_eps));
  const bool membranes = !scene.membranes.empty();
  if (scene.exact == "membrane_equilibrium" && membranes) {
    const MembraneScene& m = scene.membranes[0];
    o.add(membrane_equilibrium(sim, m.radius, m.r0, m.T0));
  }
  o.add(user_observers(scene.observers));
  o.add(membrane_shapes(sim));
  if (scene.exact == "cavity") o.add(ghia_centrelines(sim, scene.reference_dir, out_dir));
  if (scene.exact == "membrane_oscillation" && membranes) o.add(oscillation_fit());
  return o;
}

void create_directory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw std::runtime_error("output directory " + dir + " cannot be created: " + ec.message());
}

// How long, and how often a diagnostics row.
struct Schedule {
  long steps, sample_every;
  Schedule(const Scene& s, double dt)
      : steps(s.max_steps > 0 ? std::min<long>(s.max_steps, std::lround(s.t_end / dt)) : std::lround(s.t_end / dt)),
        sample_every(s.diagnostics_every > 0 ? s.diagnostics_every : std::max<long>(1, steps / 500)) {}
};

// The run log's opening: the scene, the fluid's set-up (its describe() lines), the membranes and
// the steps ahead.
std::string setup_report(const Scene& scene, const Simulation& sim, double setup_seconds, const Schedule& plan,
                         const std::string& out_dir) {
  const FluidSolver& fl = sim.fluid();
  const FluidParams& fp = fl.params();
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
  m << "\n  " << plan.steps << " steps to t = " << std::to_string(plan.steps * fp.dt) << ", output in " << out_dir;
  return m.str();
}

// One step; a failure of the method names the step and time it was attempting.
void step(Simulation& sim) {
  const long n = sim.steps();
  const double t = sim.time();
  try {
    sim.step();
  } catch (const std::exception& e) {
    std::ostringstream m;
    m << "step " << n + 1 << " (t = " << t + sim.fluid().params().dt << "): " << e.what();
    throw RunError(m.str());
  }
}

struct Timing {
  double setup, loop;
  const Profile* run;  // the loop's own phases
};

// What every summary holds, the faulty run's too: how the run ended, its timing and the fluid's
// figures.
nlohmann::json run_summary(const Scene& scene, Simulation& sim, const Timing& timing,
                           const std::string& stop_reason, const std::string& fault) {
  const FluidSolver& fl = sim.fluid();
  nlohmann::json j;
  j["sphib_version"] = SPHIB_VERSION;
  j["scene"] = scene.path;
  j["stop_reason"] = stop_reason;
  if (!fault.empty()) j["fault"] = fault;
  j["steps"] = fl.steps();
  j["time"] = fl.time();
  j["particles"] = fl.size();
  j["method"] = fl.params().method;
  j["wall_seconds"] = timing.loop + timing.setup;
  j["setup_seconds"] = timing.setup;
  j["loop_seconds"] = timing.loop;
  j["seconds_per_step"] = fl.steps() ? timing.loop / fl.steps() : 0.0;
  const Profile* profiles[] = {&fl.profile(), &sim.profile(), timing.run};
  for (const Profile* P : profiles)
    for (size_t k = 0; k < P->names().size(); ++k) j["profile_seconds"][P->names()[k]] = P->seconds(static_cast<int>(k));
  for (const auto& line : fl.describe()) j["log"].push_back(line);
  // Step time against its floor (the bare solves and products, timed alone on the final state).
  if (const double floor = fl.steps() > 0 ? fl.floor_seconds() : 0.0; floor > 0) {
    j["floor_seconds_per_step"] = floor;
    j["fluid_step_over_floor"] = fl.profile().total() / fl.steps() / floor;
    j["step_over_floor"] = timing.loop / fl.steps() / floor;
  }
  for (const auto& [k, v] : fl.figures()) j[k] = v;
  return j;
}

}  // namespace

nlohmann::json run_scene(const Scene& scene, const RunOptions& opt) {
  // Set-up: everything that can refuse the scene happens before anything is written.
  const auto t_setup = Profile::Clock::now();
  Simulation sim(scene.sim);
  if (!opt.restart.empty()) restore_checkpoint(read_checkpoint(opt.restart), opt.restart, scene.resolved, sim);
  if (opt.before_run) opt.before_run(sim);
  const double setup_seconds = seconds_since(t_setup);
  Observers observers = observers_for(scene, sim, opt.out_dir);
  create_directory(opt.out_dir);
  const Schedule plan(scene, sim.fluid().params().dt);
  auto say = [&](const std::string& s) { if (opt.log) *opt.log << s << std::endl; };
  say(setup_report(scene, sim, setup_seconds, plan, opt.out_dir));
  RunOutput output(scene, sim, observers.columns(), opt.out_dir);
  output.snapshot(sim);
  output.row(observers.sample(sim));
  Guards guards(scene.sim, sim);
  Progress progress(opt.log, opt.progress_bar, opt.log_every_seconds, plan.steps);
  Profile prof;  // the loop's own work
  const int k_checks = prof.phase("run-time checks and diagnostics"), k_output = prof.phase("output");

  // The loop: step; guards; observers; output; progress.
  std::string stop_reason = "end time", fault;
  const auto t_loop = Profile::Clock::now();
  try {
    while (sim.steps() < plan.steps) {
      if (opt.stop && opt.stop->load()) { stop_reason = "interrupted"; break; }
      observers.before_step(sim);
      step(sim);
      const auto t_checks = Profile::Clock::now();
      guards.check(sim);
      observers.after_step(sim);
      const bool last = sim.steps() == plan.steps || observers.done();
      if (last || sim.steps() % plan.sample_every == 0) output.row(observers.sample(sim));
      prof.add(k_checks, seconds_since(t_checks));
      if (!last && output.due(sim.steps())) { ScopedTimer t(prof, k_output); output.write_due(sim); }
      if (observers.done()) { stop_reason = "steady state"; break; }
      progress.tick(sim, observers.last("m0_area_rel_error"));
    }
  } catch (const std::exception& e) {
    fault = e.what();
    stop_reason = "fault";
  }
  const Timing timing{setup_seconds, seconds_since(t_loop), &prof};
  progress.end();
  output.finish(sim, observers.columns(), observers.series().rows, fault.empty());

  nlohmann::json j = run_summary(scene, sim, timing, stop_reason, fault);
  if (!fault.empty()) {  // the state is not trustworthy: no figures from it
    write_json_atomic(opt.out_dir + "/summary.json", j);
    say("  stopped by a fault at step " + std::to_string(sim.steps()) + ": " + fault);
    throw RunError(fault + "; the last good state is in " + opt.out_dir);
  }
  observers.summarize(sim, j);
  write_json_atomic(opt.out_dir + "/summary.json", j);
  say("  " + stop_reason + " after " + std::to_string(sim.steps()) + " steps, t = " + std::to_string(sim.time()) +
      ", loop " + std::to_string(timing.loop) + " s (" + std::to_string(1e6 * j["seconds_per_step"].get<double>()) +
      " us/step); output in " + opt.out_dir);
  return j;
}

}  // namespace sphib
