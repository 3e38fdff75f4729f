// The sphib command: run a scene, check it, sweep its parameters, list the scene keys.
// Exit status: 0 done; 2 refused, nothing run or written (a bad scene or argument, an output
// directory another run holds, a checkpoint that does not fit); 1 a run failed (a fault of the
// method, a write error); 128 + n stopped by signal n (130 SIGINT, 143 SIGTERM, 129 SIGHUP, ...: every
// signal that would end the process), after the current step with complete output (a second signal
// ends the process at once).
#include <hdf5.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>

#include "io/check.hpp"
#include "app/sweep.hpp"
#include "io/checkpoint.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"
#include "sphib_version.hpp"

namespace {
std::atomic<int> g_stop{0};
// The first signal is the one reported (a later SIGPIPE from the closed log does not replace it).
extern "C" void on_signal(int sig) {
  int none = 0;
  g_stop.compare_exchange_strong(none, sig);
}

// Every signal whose default action ends the process, except the faults of the process itself
// (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS), ends the run after the current step
// with complete output, as SIGTERM does; the handler is reset by its first call (a second signal of
// the same kind ends the process at once). SIGPIPE (the log's reader went away) stays handled: the
// log's later writes fail quietly instead of ending the process before its files are complete.
void handle_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGXCPU, SIGVTALRM, SIGPROF, SIGIO,
                  SIGPWR, SIGSTKFLT})
    sigaction(sig, &sa, nullptr);
  for (int sig = SIGRTMIN; sig <= SIGRTMAX; ++sig) sigaction(sig, &sa, nullptr);
  sa.sa_flags = 0;
  sigaction(SIGPIPE, &sa, nullptr);
  // A file size limit (ulimit -f) is a write error: the write fails (EFBIG) and the run stops with
  // exit status 1, the files completed before intact.
  std::signal(SIGXFSZ, SIG_IGN);
}

int stopped_status() { return g_stop.load() ? 128 + g_stop.load() : 0; }
}  // namespace

int main(int argc, char** argv) {
  // HDF5 1.10 crashes at exit on a file whose metadata write failed (it tries again); every file
  // the command completes is closed explicitly, so nothing is lost without that clean-up.
  H5dont_atexit();
  CLI::App app{"sphib: immersed-boundary fluid-structure interaction with projection SPH"};
  app.set_version_flag("--version", std::string("sphib ") + SPHIB_VERSION);
  app.require_subcommand(1);

  std::string scene_path, out_dir = "out";
  std::vector<std::string> sets;
  bool quiet = false;
  auto* run = app.add_subcommand("run", "run a scene");
  run->add_option("scene", scene_path, "scene file (TOML); with --restart it may be left out (the checkpoint's scene)");
  run->add_option("--out", out_dir, "output directory (default: out)");
  run->add_option("--set", sets, "override a scene value: key=value (dotted key, e.g. grid.nx=32)");
  run->add_flag("--quiet", quiet, "no run log");
  std::string threads;  // as --set limits.threads=N (the scene's reader checks it and names the key)
  run->add_option("--threads", threads, "threads of the step (limits.threads; default: the cores not busy with other work)");
  std::string restart;
  auto* restart_option = run->add_option(
      "--restart", restart,
      "continue from a checkpoint (DIR/checkpoint.h5 of an earlier run); its scene unless a scene file is given (which "
      "must agree); --set only time.end, time.max_steps, output.*, limits.*, title");
  bool strict = false;
  run->add_flag("--strict", strict, "refuse the scene when a warning is raised (sparse markers, dt above an estimate)");

  auto* check = app.add_subcommand("check", "validate a scene and print what it will compute");
  check->add_option("scene", scene_path, "scene file (TOML)")->required();
  check->add_option("--set", sets, "override a scene value: key=value");
  bool build = false;
  check->add_flag("--build", build, "build the simulation even when its memory estimate is above 1 GB");

  sphib::app::SweepOptions sw;
  std::string report;
  auto* sweep = app.add_subcommand("sweep", "run a scene over every combination of parameter values, in process, "
                                            "and tabulate summary figures with observed orders");
  sweep->add_option("scene", sw.scene, "scene file (TOML)")->required();
  sweep->add_option("--vary", sw.vary, "key=v1,v2,... (repeatable; the first key orders the observed orders)")
      ->required();
  sweep->add_option("--derive", sw.derive, "key=EXPR of {varied.key}: numbers, + - * / ** ( ), sqrt, pi");
  sweep->add_option("--set", sw.set, "key=value for every run");
  sweep->add_option("--report", report, "comma-separated summary fields (dotted names reach into objects)")
      ->required();
  sweep->add_option("--out", sw.out, "output directory: DIR/run_NNN, DIR/sweep.csv, DIR/sweep.md")->required();
  sweep->add_flag("--quiet", quiet, "no line per run");
  sweep->add_option("--threads", threads, "threads of every run's step (limits.threads; default: the cores not busy with other work)");

  auto* keys = app.add_subcommand("keys", "list every scene key with its type, default and meaning");
  bool keys_json = false;
  keys->add_flag("--json", keys_json, "as JSON: [{name, type, default, required, range, help}, ...]");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, version or the error
    return code == 0 ? 0 : 2;
  }
  try {
    if (keys->parsed() && keys_json) {
      std::cout << sphib::scene_keys_json();
      return 0;
    }
    if (keys->parsed()) {
      std::cout << "| key | type | default | allowed | meaning |\n|---|---|---|---|---|\n"
                << sphib::describe_scene_keys();
      return 0;
    }
    if (!threads.empty()) (sweep->parsed() ? sw.set : sets).push_back("limits.threads=" + threads);
    if (sweep->parsed()) {
      std::stringstream ss(report);
      for (std::string r; std::getline(ss, r, ',');)
        if (!r.empty()) sw.report.push_back(r);
      handle_stop_signals();
      sw.log = quiet ? nullptr : &std::cerr;
      sw.table = &std::cout;
      sw.stop = &g_stop;
      const auto res = sphib::app::run_sweep(sw);
      if (g_stop.load()) return stopped_status();
      return res.failed ? 1 : 0;
    }
    if (run->parsed() && restart_option->count() > 0 && restart.empty())
      throw sphib::app::UsageError("--restart: an empty file name (give DIR/checkpoint.h5, or leave --restart out to run "
                                   "from the start)");
    if (run->parsed() && scene_path.empty() && restart.empty())
      throw sphib::app::UsageError("run: give a scene file, or --restart DIR/checkpoint.h5 to continue a run");
    sphib::Scene scene = !scene_path.empty() ? sphib::load_scene(scene_path, sets)
                                             : sphib::checkpoint_scene(sphib::read_checkpoint(restart), restart, sets);
    if (scene_path.empty()) scene_path = scene.path;
    if (check->parsed()) {
      const int warnings = sphib::check_scene(scene, std::cout, build);
      if (warnings) std::cout << "  " << warnings << " warning(s)\n";
      return 0;
    }
    handle_stop_signals();
    sphib::RunOptions opt;
    opt.out_dir = out_dir;
    opt.log = quiet ? nullptr : &std::cerr;
    opt.progress_bar = isatty(2);
    opt.stop = &g_stop;
    opt.restart = restart;
    opt.before_run = [&](const sphib::Simulation& sim) {
      std::ostringstream w;
      const int n = sphib::time_step_warnings(scene, sim, w);
      if (n == 0) return;
      std::cerr << w.str();
      if (strict)
        throw sphib::SceneError(scene_path + ": refused by --strict: " + std::to_string(n) +
                                " warning(s) above (see `sphib check`)");
    };
    const auto summary = sphib::run_scene(scene, opt);
    // The run's own ending decides: a signal that came after its last step changed nothing (exit 0).
    const int sig = summary.value("stop_signal", 0);
    if (sig)
      std::cerr << "sphib: " << summary.value("stop_reason", "stopped") << " by signal " << sig
                << "; consistent output written to " << out_dir << "\n";
    return sig ? 128 + sig : 0;
  } catch (const sphib::StoppedBeforeStart& e) {
    std::cerr << "sphib: " << e.what() << "\n";
    return 128 + e.signal;
  } catch (const sphib::SceneError& e) {
    std::cerr << "sphib: error: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {  // refused at set-up (UsageError, ExpressionError, geometry)
    std::cerr << "sphib: error: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {  // the set-up (a run's loop reports its own as a fault)
    std::cerr << "sphib: error: out of memory while setting up the run: nothing was run or written (see `sphib check` "
                 "for its memory estimate, and limits.memory_gb)\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "sphib: error: " << e.what() << "\n";
    return 1;
  }
}
