#include "io/run.hpp"

#include <chrono>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <random>
#include <set>
#include <sstream>

#include "coupling/contact.hpp"
#include "fluid/common/threads.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/footprint.hpp"
#include "io/output.hpp"
#include "io/output_dir.hpp"
#include "io/progress.hpp"
#include "io/scene_checks.hpp"
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
  if (!scene.probes.probes.empty()) o.add(pressure_probes(sim, scene.probes));
  if (scene.steady_eps > 0) o.add(steady_state(scene.steady_eps));
  const bool membranes = !scene.membranes.empty();
  if (scene.exact == "membrane_equilibrium" && membranes) {
    const MembraneScene& m = scene.membranes[0];
    o.add(membrane_equilibrium(sim, m.radius, m.r0));
  }
  o.add(user_observers(scene.observers));
  o.add(membrane_shapes(sim));
  if (scene.exact == "cavity") o.add(ghia_centrelines(sim, scene.reference_dir, out_dir));
  if (scene.exact == "membrane_oscillation" && membranes) o.add(oscillation_fit());
  return o;
}

// How long, and how often a diagnostics row; whether time.max_steps ends the run before time.end.
struct Schedule {
  long steps, sample_every;
  bool by_max_steps;
  explicit Schedule(const Scene& s)
      : steps(planned_steps(s)),
        sample_every(s.diagnostics_every > 0 ? s.diagnostics_every : std::max<long>(1, steps / 500)),
        by_max_steps(s.max_steps > 0 && s.max_steps < std::round(s.t_end / s.sim.fluid.dt)) {}
};

// The run log's opening: the scene, the fluid's set-up (its report's lines), the membranes and
// the steps ahead.
std::string setup_report(const Scene& scene, const Simulation& sim, double setup_seconds, const Schedule& plan,
                         const std::string& out_dir) {
  const FluidSolver& fl = sim.fluid();
  const FluidParams& fp = fl.params();
  std::ostringstream m;
  m << "sphib " << SPHIB_VERSION << ": " << (scene.title.empty() ? scene.path : scene.title) << "\n"
    << "  rho = " << fp.rho << ", mu = " << fp.mu << ", dt = " << fp.dt << "\n";
  for (const auto& line : fl.profiler().report().lines) m << "  " << line << "\n";
  m << "  set-up " << setup_seconds << " s (neighbours " << fl.profiler().setup_seconds("neighbours") << " s, assembly "
    << fl.profiler().setup_seconds("assembly") << " s, factorisation " << fl.profiler().setup_seconds("factorisation") << " s)";
  for (size_t k = 0; k < sim.membranes().size(); ++k) {
    const auto& ms = sim.membranes()[k];
    m << "\n  membrane " << k << ": Nb = " << ms.m.nb() << ", L0 = " << ms.m.L0() << ", " << describe(ms.m.mat)
      << ", h* = " << ms.h_star << (ms.fixed ? ", fixed" : ", free") << (ms.filter ? ", semi-implicit force" : "")
      << ", markers per grid spacing " << fl.lattice().dx / ms.m.ds();
  }
  if (!sim.membranes().empty()) {
    const MarkerInterpolation i = sim.interpolation();
    m << "\n  marker velocity: "
      << (i == MarkerInterpolation::Sph       ? "normalised SPH interpolation (Eq. 63)"
          : i == MarkerInterpolation::BSpline ? "curl of the stream function, tensor cubic B-splines (divergence-free)"
          : i == MarkerInterpolation::SpreadingKernel
              ? "curl of the stream function, SPH kernel of the spreading radius h* (divergence-free)"
                                              : "curl of the stream function, SPH kernel (divergence-free)");
  }
  if (const ContactForce* c = sim.contact()) {
    const ContactParams& q = c->params();
    m << "\n  contact: Morse repulsion De = " << q.strength << ", r0 = " << q.range << ", beta = "
      << (q.beta > 0 ? q.beta : 2.0 / q.range) << (q.walls ? ", walls push too" : ", between membranes only");
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
  double steps_loop;   // the loop less the run's opening and closing writes: what seconds_per_step divides
  long steps;          // taken by this run (a restart's count from the checkpoint)
  const Profile* run;  // the loop's own phases
};

// How the loop ended: its reason, the fault or write error, and the last good state.
struct Ending {
  std::string reason = "end time";
  std::string fault;
  bool write_error = false;
  long good_steps = 0;
  double good_time = 0;
  int signal = 0;  // the signal that stopped it (0: none)
};

// What every summary holds, the faulty run's too: how the run ended, its timing and the fluid's
// figures. After a fault, steps and time are the last good state's (fault_step the one that failed).
nlohmann::json run_summary(const Scene& scene, Simulation& sim, const Timing& timing, const Ending& end,
                           const std::string& run_id) {
  const FluidSolver& fl = sim.fluid();
  nlohmann::json j;
  j["sphib_version"] = SPHIB_VERSION;
  j["scene"] = scene.path;
  j["scene_hash"] = scene_hash(scene);
  j["run_id"] = run_id;
  j["stop_reason"] = end.reason;
  if (end.signal) j["stop_signal"] = end.signal;
  if (!end.fault.empty()) j["fault"] = end.fault;
  j["steps"] = end.fault.empty() ? fl.steps() : end.good_steps;
  j["time"] = end.fault.empty() ? fl.time() : end.good_time;
  if (!end.fault.empty()) j["fault_step"] = end.good_steps + 1;
  j["particles"] = fl.size();
  j["method"] = fl.params().method;
  j["wall_seconds"] = timing.loop + timing.setup;
  j["setup_seconds"] = timing.setup;
  j["loop_seconds"] = timing.loop;
  j["seconds_per_step"] = timing.steps ? timing.steps_loop / timing.steps : 0.0;
  j["threads"] = thread_count();  // limits.threads, OMP_NUM_THREADS or the machine's idle cores
  const Profile* profiles[] = {&fl.profiler(), &sim.profile(), timing.run};
  for (const Profile* P : profiles)
    for (size_t k = 0; k < P->names().size(); ++k) j["profile_seconds"][P->names()[k]] = P->seconds(static_cast<int>(k));
  for (const auto& line : fl.profiler().report().lines) j["log"].push_back(line);
  // Step time against its floor (the fluid's bare solves and products, timed alone on the final
  // state): the fluid step (its own phases), and the whole step (the loop: fluid, membranes,
  // coupling, checks, output); with membranes, also against the fluid's and the coupling's floors
  // together (Simulation::coupling_floor_seconds), and the coupling's share of that whole floor.
  if (const double floor = timing.steps > 0 && end.fault.empty() ? fl.profiler().floor_seconds() : 0.0; floor > 0) {
    const double step = timing.steps_loop / timing.steps;
    j["floor_seconds_per_step"] = floor;
    j["fluid_step_over_floor"] = fl.profiler().step_seconds() / timing.steps / floor;
    j["step_over_floor"] = step / floor;
    if (const double cf = sim.coupling_floor_seconds(); cf > 0) {
      j["coupling_floor_seconds_per_step"] = cf;
      j["coupling_floor_share"] = cf / (floor + cf);
      j["step_over_whole_floor"] = step / (floor + cf);
    }
  }
  // The membranes and their coupling (force, spreading, interpolation, marker update with the
  // markers' stream function) as a share of the whole step.
  if (!sim.membranes().empty() && timing.steps_loop > 0) j["coupling_share"] = sim.profile().total() / timing.steps_loop;
  for (const auto& [k, v] : fl.profiler().report().figures) j[k] = v;
  return j;
}

// The fields run_summary writes for every run: an observer of the user's may not take their names
// (its last value would replace the run's own figure in summary.json).
const std::set<std::string>& run_summary_fields() {
  static const std::set<std::string> f{"sphib_version", "scene", "scene_hash", "run_id", "stop_reason", "stop_signal",
                                       "fault", "steps", "time", "fault_step", "particles", "method", "wall_seconds",
                                       "setup_seconds", "loop_seconds", "seconds_per_step", "profile_seconds", "log",
                                       "floor_seconds_per_step", "fluid_step_over_floor", "step_over_floor",
                                       "coupling_floor_seconds_per_step", "coupling_floor_share", "step_over_whole_floor",
                                       "coupling_share", "threads"};
  return f;
}

// The user's observers have names of their own: not a field of every run's summary, nor one of the
// fluid's figures (a column of another analysis is refused by Observers::add).
void check_observer_names(const Scene& scene, const Simulation& sim) {
  std::set<std::string> taken = run_summary_fields();
  for (const auto& [k, v] : sim.fluid().profiler().report().figures) taken.insert(k);
  for (const Observer& o : scene.observers) {
    if (o.name.empty()) throw SceneError(scene.path + ": an observer has an empty name");
    if (taken.count(o.name))
      throw SceneError(scene.path + ": observer '" + o.name + "': the name of a field every run's summary.json has " +
                       "(it would replace the run's own " + o.name + "): give it another name");
  }
}

std::string new_run_id() {
  std::random_device rd;
  const auto t = static_cast<std::uint64_t>(std::chrono::system_clock::now().time_since_epoch().count());
  std::ostringstream s;
  s << std::hex << std::setw(16) << std::setfill('0') << ((static_cast<std::uint64_t>(rd()) << 32 ^ rd()) ^ t);
  return s.str();
}

// Everything before the first write: the simulation, its analyses (built on the state at t = 0, so
// that a restart measures from the same start), a restart's state and record, the caller's checks.
struct Prepared {
  std::unique_ptr<Simulation> sim;
  Observers observers;
  std::string run_id;
  bool resumed_series = false;  // the series so far came with the checkpoint
  double seconds = 0;
};

Prepared prepare(const Scene& scene, const RunOptions& opt) {
  const auto t0 = Profile::Clock::now();
  Prepared p;
  p.sim = std::make_unique<Simulation>(scene.sim);
  check_observer_names(scene, *p.sim);
  p.observers = observers_for(scene, *p.sim, opt.out_dir);
  if (!opt.restart.empty()) {
    const Checkpoint c = read_checkpoint(opt.restart);
    restore_checkpoint(c, opt.restart, scene.resolved, *p.sim);
    if (!c.run_id.empty()) {
      try {
        p.observers.restore(c.analyses, c.series);
      } catch (const nlohmann::json::exception&) {  // a value of the wrong kind in an analysis's record
        throw CheckpointError("checkpoint " + opt.restart + ": its run record (the analyses' state) is damaged");
      } catch (const std::exception& e) {
        throw CheckpointError("checkpoint " + opt.restart + ": " + e.what());
      }
      p.run_id = c.run_id;
      p.resumed_series = true;
    }
    if (planned_steps(scene) <= p.sim->steps())
      throw SceneError(scene.path + ": time.end: " + std::to_string(scene.t_end) + " (step " +
                       std::to_string(planned_steps(scene)) + ") is not after the checkpoint's t = " +
                       std::to_string(p.sim->time()) + " (step " + std::to_string(p.sim->steps()) + "): no step would run");
  }
  if (p.run_id.empty()) p.run_id = new_run_id();
  if (opt.before_run) opt.before_run(*p.sim);
  p.seconds = seconds_since(t0);
  return p;
}

// A restart into the checkpoint's own directory continues that run's output.h5 (the .part of a
// killed run first, if it opens), if it carries the same run id. A complete output.h5 there that
// cannot be read (open for writing elsewhere, truncated, damaged) is refused, not removed: its
// snapshots may be the only copy of the run's history.
std::string resumable_output(const OutputDirectory& dir, const RunOptions& opt, const std::string& run_id) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (opt.restart.empty() || !fs::equivalent(fs::path(opt.restart).parent_path().empty() ? "." : fs::path(opt.restart).parent_path(), dir.path(), ec))
    return "";
  const std::string part = part_path(dir.file("output.h5")), final_name = dir.file("output.h5");
  if (fs::exists(part, ec) && root_text_attribute(part, "run_id") == run_id && snapshots_readable(part)) return part;
  if (!fs::exists(final_name, ec)) return "";
  if (root_text_attribute(final_name, "run_id") == run_id && snapshots_readable(final_name)) return final_name;
  if (!snapshots_readable(final_name))
    throw CheckpointError(
        final_name + " cannot be read (open for writing by another program, truncated or damaged): a restart into the "
                     "checkpoint's own directory continues that file and will not remove what it cannot read; close or "
                     "move it, or give this restart another --out (nothing was written)");
  return "";  // another run's readable output: replaced, as a new run replaces an earlier run's files
}

// Where this run writes: a new run removes an earlier run's files first (a summary of another run
// never sits beside this one's files); a run continuing its own directory removes only the
// incomplete .part files of the earlier part that it does not continue.
OutputTarget claim(OutputDirectory& dir, const RunOptions& opt, const std::string& run_id, std::ostream* log) {
  OutputTarget t{dir.path(), run_id, resumable_output(dir, opt, run_id)};
  const bool continuing = !t.resume_from.empty();
  const std::vector<std::string> removed = dir.remove_earlier_files({opt.restart, t.resume_from}, continuing);
  if (log && continuing) *log << "  continuing this run's files in " << dir.path() << " (from " << t.resume_from << ")\n";
  if (log && !removed.empty()) {
    *log << "  removed " << (continuing ? "the incomplete files of the earlier part" : "the earlier run's files") << ":";
    for (const auto& f : removed) *log << " " << f;
    *log << "\n";
  }
  return t;
}

std::string stop_reason(int signal) {
  if (signal == SIGINT) return "interrupted";
  if (signal == SIGTERM) return "terminated";
  const char* name = sigabbrev_np(signal);
  return "signal " + std::to_string(signal) + (name ? std::string(" (SIG") + name + ")" : "");
}

// The loop: step; guards; observers; output; progress. A fault of the method or a write error ends it.
Ending run_loop(Simulation& sim, Observers& observers, RunOutput& output, const Schedule& plan, const Scene& scene,
                const RunOptions& opt, Profile& prof) {
  Guards guards(scene.sim, sim);
  Progress progress(opt.log, opt.progress_bar, opt.log_every_seconds, plan.steps);
  const int k_checks = prof.phase("run-time checks and diagnostics"), k_output = prof.phase("output");
  Ending end;
  if (plan.by_max_steps) end.reason = "time.max_steps";
  try {
    while (sim.steps() < plan.steps) {
      if (const int sig = opt.stop ? opt.stop->load() : 0) { end.reason = stop_reason(sig); end.signal = sig; break; }
      end.good_steps = sim.steps();
      end.good_time = sim.time();
      observers.before_step(sim);
      step(sim);
      const auto t_checks = Profile::Clock::now();
      guards.check(sim);
      observers.after_step(sim);
      const bool last = sim.steps() == plan.steps || observers.done();
      if (last || sim.steps() % plan.sample_every == 0) output.row(observers.sample(sim));
      prof.add(k_checks, seconds_since(t_checks));
      if (!last && output.due(sim.steps())) { ScopedTimer t(prof, k_output); output.write_due(sim); }
      if (observers.done()) { end.reason = "steady state"; break; }
      progress.tick(sim, observers.last("m0_area_rel_error"));
    }
  } catch (const WriteError& e) {
    end = Ending{"write error", e.what(), true, sim.steps(), sim.time()};
  } catch (const std::exception& e) {
    end.fault = e.what();
    end.reason = "fault";
  }
  progress.end();
  return end;
}

// A write error: this run's files stay .part, the ones completed before stay intact; no summary.
[[noreturn]] void stop_writing(RunOutput& output, const std::string& error, const Simulation& sim, const std::string& dir) {
  output.abandon();
  std::ostringstream m;
  m << error << "; the run stopped at step " << sim.steps() << " (t = " << sim.time() << "), its unfinished files in "
    << dir << " stay .part; ";
  if (output.checkpoint_time() >= 0)
    m << "the last complete checkpoint is " << output.checkpoint_path() << " (t = " << output.checkpoint_time() << ")";
  else
    m << "no checkpoint of this run was completed";
  throw RunError(m.str());
}

// Every file of the run under its final name together, the summary last; a failure leaves them .part.
void publish(RunOutput& output, const nlohmann::json& summary, const Simulation& sim, const std::string& dir) {
  try {
    output.publish(json_text(summary));
  } catch (const WriteError& e) {
    stop_writing(output, e.what(), sim, dir);
  }
}

}  // namespace

nlohmann::json run_scene(const Scene& scene, const RunOptions& opt) {
  if (const std::string why = steps_problem(scene); !why.empty()) throw SceneError(scene.path + ": time.end: " + why);
  refuse_if_too_large(scene);        // before any allocation
  // limits.threads, else the idle cores (fluid/common/threads.hpp), for this run (the caller's count after it)
  const ThreadCount threads(scene.threads > 0 ? scene.threads : default_thread_count());
  OutputDirectory dir(opt.out_dir);  // the lock, before anything is written
  Prepared p;
  try {
    p = prepare(scene, opt);
  } catch (...) {
    dir.abandon();  // refused: nothing written, the directory as it was
    throw;
  }
  if (const int sig = opt.stop ? opt.stop->load() : 0) {
    dir.abandon();
    throw StoppedBeforeStart(sig, stop_reason(sig) + " during the set-up: nothing was written to " + opt.out_dir);
  }
  Simulation& sim = *p.sim;
  Observers& observers = p.observers;
  const Schedule plan(scene);
  auto say = [&](const std::string& s) { if (opt.log) *opt.log << s << std::endl; };
  say(setup_report(scene, sim, p.seconds, plan, opt.out_dir));
  const OutputTarget target = claim(dir, opt, p.run_id, opt.log);
  const long first_step = sim.steps();
  Profile prof;  // the loop's own work
  RunOutput output(scene, sim, observers, target);
  Ending end;
  // The run's opening and closing writes (the first snapshot and checkpoint, the last ones) are a
  // phase of their own, outside the steps' time: seconds_per_step is the steps' cost at any run length.
  const int k_ends = prof.phase("opening and closing writes");
  const auto t_loop = Profile::Clock::now();
  double steps_loop = 0.0;
  try {
    {
      ScopedTimer t(prof, k_ends);
      output.snapshot(sim);
      if (!p.resumed_series) output.row(observers.sample(sim));
      if (target.resume_from.empty()) output.checkpoint(sim);  // a restart point from the start: checkpoints work
    }
    const auto t_steps = Profile::Clock::now();
    end = run_loop(sim, observers, output, plan, scene, opt, prof);
    steps_loop = seconds_since(t_steps);
    if (end.write_error) stop_writing(output, end.fault, sim, opt.out_dir);
    ScopedTimer t(prof, k_ends);
    output.finish(sim, end.fault.empty());
  } catch (const WriteError& e) {
    stop_writing(output, e.what(), sim, opt.out_dir);
  }
  const Timing timing{p.seconds, seconds_since(t_loop), steps_loop, sim.steps() - first_step, &prof};
  nlohmann::json j = run_summary(scene, sim, timing, end, p.run_id);
  if (!end.fault.empty()) {  // the state is not trustworthy: no figures from it
    publish(output, j, sim, opt.out_dir);
    say("  stopped by a fault in step " + std::to_string(end.good_steps + 1) + ": " + end.fault);
    throw RunError(end.fault + "; the output written before it is complete in " + opt.out_dir + " (the last good step " +
                   std::to_string(end.good_steps) + ", t = " + std::to_string(end.good_time) + ")");
  }
  observers.summarize(sim, j);
  publish(output, j, sim, opt.out_dir);
  say("  " + end.reason + " after " + std::to_string(sim.steps()) + " steps, t = " + std::to_string(sim.time()) +
      ", loop " + std::to_string(timing.loop) + " s (" + std::to_string(1e6 * j["seconds_per_step"].get<double>()) +
      " us/step); output in " + opt.out_dir);
  return j;
}

}  // namespace sphib
