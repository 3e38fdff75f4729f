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
  const std::atomic<bool>* stop = nullptr;   // set (e.g. by SIGINT) to end cleanly after the current step
  std::string restart;                       // a checkpoint to continue from (same scene and version)
  // Called once the simulation is set up, before anything is written (e.g. warnings; a throw
  // refuses the run with nothing written).
  std::function<void(const Simulation&)> before_run;
};

// A run that went wrong (blow-up, solver failure) after outputs were opened; what was written
// before the fault is complete and closed.
struct RunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Runs the scene and writes DIR/output.h5 (+ .xdmf), DIR/diagnostics.csv, DIR/summary.json and,
// every output.checkpoint_interval and at the end, DIR/checkpoint.h5. Returns the summary.
// Nothing is written if the simulation cannot be set up (or the restart file does not match).
nlohmann::json run_scene(const Scene& scene, const RunOptions& options);

}  // namespace sphib
