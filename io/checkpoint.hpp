#pragma once
// Checkpoints: everything a run needs to continue bit for bit (the fluid's state, e.g. u^n, the
// Adams-Bashforth history and phi^n for Eq. (42); the markers; the step counter and time), the
// scene it belongs to and the run's own record (its id, the diagnostics series so far and what its
// analyses keep, e.g. the area at t = 0), so that a restarted run reports what the straight run
// would. HDF5, written to FILE.part and renamed, so a killed run leaves the previous checkpoint intact.
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "coupling/simulation.hpp"
#include "observe/analysis.hpp"

namespace sphib {

// A checkpoint a run cannot continue from: missing, not a checkpoint, damaged (non-finite values,
// a negative clock), of another format, version or scene. The message names the file. Nothing has
// run (the command's exit status 2).
struct CheckpointError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

constexpr int kCheckpointFormat = 2;  // 2: variable-length strings, the run record

struct Checkpoint {
  std::string version;                                      // library version that wrote it
  std::vector<std::pair<std::string, std::string>> scene;   // resolved scene key = value
  NamedArrays fluid;                                        // FluidSolver::state()
  std::vector<Mat2> markers;                                // X of each membrane
  std::vector<Mat2> marker_velocities;  // U^n(X^n) of each free membrane (the predictor's history), or empty
  std::vector<Mat2> marker_velocities_next;  // U^{n+1}(X^{n+1}) as the marker update left it, or empty
  std::string run_id;                   // the run the state belongs to (its output files carry it too)
  nlohmann::json analyses;              // Observers::state()
  Series series;                        // the diagnostics series up to the checkpoint
};

// Writes the simulation's state, the scene's resolved keys and, when given, the run's id and its
// observers' series and state. Reserves its disk space first (a full disk fails before anything is
// written). Throws WriteError (io/atomic_file.hpp) naming the file on failure.
void write_checkpoint(const std::string& path, const Simulation& sim,
                      const std::vector<std::pair<std::string, std::string>>& scene, const std::string& run_id = "",
                      const Observers* observers = nullptr);

// Reads a checkpoint. Throws CheckpointError naming the file if it is missing, not one, of another
// format, or holds non-finite values.
Checkpoint read_checkpoint(const std::string& path);

// Puts the checkpoint's state into a simulation built from the same scene. Throws CheckpointError
// naming the file and the first difference if the scene or version does not match (keys that only
// say how long to run or what to write may differ), or if the restored clock is not a valid one.
void restore_checkpoint(const Checkpoint& c, const std::string& path,
                        const std::vector<std::pair<std::string, std::string>>& scene, Simulation& sim);

}  // namespace sphib
