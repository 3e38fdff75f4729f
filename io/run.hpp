#pragma once
// Runs a scene: the time loop with its observers, progress, HDF5/XDMF snapshots, CSV diagnostics
// and the summary. Cases and the command never copy this loop.
#include <atomic>
#include <functional>
#include <iosfwd>
#include <string>

#include <nlohmann/json.hpp>

#include "io/scene.hpp"

namespace sphib {

struct RunOptions {
  std::string out_dir = "out";
  std::ostream* log = nullptr;               // run log (nullptr: silent)
  bool progress_bar = false;                 // a terminal: one updating line; else periodic log lines
  double log_every_seconds = 5.0;            // plain progress lines this often
  // Set to a signal's number (SIGINT, SIGTERM, ...) to end cleanly after the current step; the
  // summary's stop_reason says which: "interrupted" (SIGINT), "terminated" (SIGTERM), "signal N
  // (SIGNAME)" (another), and stop_signal holds N.
  const std::atomic<int>* stop = nullptr;
  // A checkpoint to continue from (same scene and version). Into the checkpoint's own directory the
  // run continues that run's files (its snapshots kept, its series extended); into another directory
  // it starts new ones (snapshots from the restart, the series from t = 0).
  std::string restart;
  // Called once the simulation is set up, before anything is written (e.g. warnings; a throw
  // refuses the run with nothing written).
  std::function<void(const Simulation&)> before_run;
};

// A run that went wrong after outputs were opened: a fault of the method (blow-up, solver failure),
// whose output up to the last good state is complete and closed; or a write error (disk full), after
// which the files completed before stay intact and this run's files stay .part.
struct RunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A stop signal arrived while the run was being set up: nothing was written (the directory is as it
// was). signal is its number.
struct StoppedBeforeStart : std::runtime_error {
  StoppedBeforeStart(int sig, const std::string& what) : std::runtime_error(what), signal(sig) {}
  int signal;
};

// Runs the scene and writes DIR/output.h5 (+ .xdmf), DIR/diagnostics.csv, DIR/summary.json and
// DIR/checkpoint.h5 (at the start, every output.checkpoint_interval and at the end). Returns the
// summary. The run owns DIR: it takes DIR's lock before anything (DirectoryBusy if another run holds
// it), and removes the files of an earlier run there before it writes (a restart into its own
// directory continues them instead). Nothing is written if the scene is refused, the directory is
// busy, the simulation cannot be set up or the restart file does not fit (CheckpointError). The
// run's files are published together at its end, summary.json last (a run that fails leaves its
// files .part); the summary's stop_signal names a signal that stopped it.
nlohmann::json run_scene(const Scene& scene, const RunOptions& options);

}  // namespace sphib
