#pragma once
// Checkpoints: everything a run needs to continue bit for bit (the fluid's state, e.g. u^n, the
// Adams-Bashforth history and phi^n for Eq. (42); the markers; the step counter and time) and
// the scene it belongs to. HDF5, written to FILE.part and renamed, so a killed run leaves the
// previous checkpoint intact.
#include <string>
#include <utility>
#include <vector>

#include "coupling/simulation.hpp"

namespace sphib {

struct Checkpoint {
  std::string version;                                      // library version that wrote it
  std::vector<std::pair<std::string, std::string>> scene;   // resolved scene key = value
  NamedArrays fluid;                                        // FluidSolver::state()
  std::vector<Mat2> markers;                                // X of each membrane
  std::vector<Mat2> marker_velocities;  // U^n(X^n) of each free membrane (the predictor's history), or empty
  std::vector<Mat2> marker_velocities_next;  // U^{n+1}(X^{n+1}) as the marker update left it, or empty
};

// Writes the simulation's state and the scene's resolved keys. Throws std::runtime_error naming
// the file on failure.
void write_checkpoint(const std::string& path, const Simulation& sim,
                      const std::vector<std::pair<std::string, std::string>>& scene);

// Reads a checkpoint. Throws std::runtime_error naming the file if it is missing or not one.
Checkpoint read_checkpoint(const std::string& path);

// Puts the checkpoint's state into a simulation built from the same scene. Throws
// std::runtime_error naming the first difference if the scene or version does not match
// (keys that only say how long to run or what to write may differ).
void restore_checkpoint(const Checkpoint& c, const std::string& path,
                        const std::vector<std::pair<std::string, std::string>>& scene, Simulation& sim);

}  // namespace sphib
