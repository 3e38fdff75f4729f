#pragma once
// Checkpoints: everything a run needs to continue bit for bit (the fluid's state, e.g. u^n, the
// Adams-Bashforth history and phi^n for Eq. (42); the markers; the step counter and time), the
// scene it belongs to and the run's own record (its id, the diagnostics series so far and what its
// analyses keep, e.g. the area at t = 0), so that a restarted run reports what the straight run
// would. HDF5, written to FILE.part and renamed, so a killed run leaves the previous checkpoint intact.
// Sealed: its first 512 bytes (an HDF5 user block) hold the SHA-256 of every byte after them, and a
// reader verifies it before HDF5 parses the file, so a checkpoint changed in any bit is refused.
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "coupling/simulation.hpp"
#include "io/scene.hpp"
#include "observe/analysis.hpp"

namespace sphib {

// A checkpoint a run cannot continue from: missing, not a checkpoint, damaged (its seal does not
// hold, non-finite values, a clock that is not its steps of dt), of another format, version or scene. The message names the file. Nothing has
// run (the command's exit status 2).
struct CheckpointError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

constexpr int kCheckpointFormat = 3;  // 2: variable-length strings, the run record; 3: the seal, scene_file

struct Checkpoint {
  std::string version;                                      // library version that wrote it
  std::string scene_file;                                   // the scene file the run read ("" if none)
  std::vector<std::pair<std::string, std::string>> scene;   // resolved scene key = value
  NamedArrays fluid;                                        // FluidSolver::state()
  std::vector<Mat2> markers;                                // X of each membrane
  std::vector<Mat2> marker_velocities;  // U^n(X^n) of each free membrane (the predictor's history), or empty
  std::vector<Mat2> marker_velocities_next;  // U^{n+1}(X^{n+1}) as the marker update left it, or empty
  std::vector<Eigen::MatrixXd> stiff_filter;  // the stiff-force filter's history per membrane, or empty
  std::string run_id;                   // the run the state belongs to (its output files carry it too)
  nlohmann::json analyses;              // Observers::state()
  Series series;                        // the diagnostics series up to the checkpoint
};

// Writes the simulation's state, the scene's resolved keys and, when given, the run's id and its
// observers' series and state, and the scene file's path (so that a restart may read its scene from
// the checkpoint alone). Reserves its disk space first (a full disk fails before anything is
// written), then seals it. Throws WriteError (io/atomic_file.hpp) naming the file on failure.
void write_checkpoint(const std::string& path, const Simulation& sim,
                      const std::vector<std::pair<std::string, std::string>>& scene, const std::string& run_id = "",
                      const Observers* observers = nullptr, const std::string& scene_file = "");

// Seals the checkpoint file at path anew: its first 512 bytes get the SHA-256 of the bytes after
// them. write_checkpoint does this; call it only after changing a checkpoint on purpose (tests of
// the checks behind the seal). Throws WriteError.
void seal_checkpoint(const std::string& path);

// Reads a checkpoint, after verifying its seal. Throws CheckpointError naming the file if it is
// missing, not a plain file, not a checkpoint, damaged (its seal does not hold), locked by another
// program, of another format, or holds non-finite values.
Checkpoint read_checkpoint(const std::string& path);

// Puts the checkpoint's state into a simulation built from the same scene. Throws CheckpointError
// naming the file and the first difference if the scene or version does not match (keys that only
// say how long to run or what to write may differ: restart_may_change), or if the restored clock is
// not a valid one (negative, or not its step count of time.dt).
void restore_checkpoint(const Checkpoint& c, const std::string& path,
                        const std::vector<std::pair<std::string, std::string>>& scene, Simulation& sim);

// Keys that say how long to run, what to write and what the machine allows (time.end,
// time.max_steps, output.*, limits.*, title): a restart may change them; every other key is the
// checkpoint's.
bool restart_may_change(const std::string& key);

// The scene a checkpoint was written with (every resolved value it keeps), with `overrides`
// (key=value) of keys a restart may change; observe.reference_dir relative to the scene file it
// names. Throws CheckpointError naming an override of any other key.
Scene checkpoint_scene(const Checkpoint& c, const std::string& path, const std::vector<std::string>& overrides);

}  // namespace sphib
