#pragma once
// Scene files (TOML): what to simulate, parsed and validated in one place.
// Every key, its type, default and allowed range is listed in scene.cpp (and the README table is
// generated from `sphib keys`). Unknown keys, wrong types and invalid values are errors that name
// the key and its line.
#include <functional>
#include <stdexcept>
#include <optional>
#include <string>
#include <vector>

#include "coupling/simulation.hpp"
#include "observe/analysis.hpp"  // Observer

namespace sphib {

// A refused scene: the message names the file, line, key, value and allowed range.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct MembraneScene {
  std::string shape = "circle";  // circle | ellipse | points
  std::string spacing = "angle";  // ellipse: markers uniform in angle (the paper's) | arclength
  double radius = 0.5, rx = 0.5, ry = 0.5, cx = 0.0, cy = 0.0;
  double r0 = 0.5;
  std::string law = "hookean";     // membrane/law.hpp's registry
  double Es = 1.0;                 // the law's modulus (hookean: T0)
  std::vector<double> law_params;  // the law's own (skalak: C)
  double Eb = 0.0;                 // bending modulus
  double tension_cutoff = -1.0;    // Material::tension_cutoff; < 0: 2 dx for law inextensible, else 0
  std::string reference = "circle";  // circle (radius r0) | initial (the initial shape / prestretch)
  double prestretch = 1.0;
  bool spontaneous = false;        // kappa0 given: uniform spontaneous curvature
  double kappa0 = 0.0;
  bool semi_implicit = false;      // the stiff-force filter (coupling/stiff_force.hpp)
  bool stiff_residual = false;     // ... with its model's residual (MembraneSetup::stiff_residual)
  int nb = 128;
  double h_star = 0.0;  // absolute h*; 0: use h_star_over_h * h
  double h_star_over_h = 1.4;
  bool fixed = false;
  double viscosity_ratio = 1.0;  // lambda = mu_in / mu_out
  Mat2 points;  // shape = "points"
};

// What to simulate and observe: read from a scene file (load_scene) or built in C++.
struct Scene {
  std::string path, title;
  FluidMethod method = FluidMethod::Eulerian;
  std::string exact = "none";  // none | poiseuille | couette | cavity | membrane_equilibrium | membrane_oscillation | inclined_plane | droplet | dam_break
  bool loads = false;          // force_<wall>, load_<wall> columns (observe/loads.cpp)
  ProbeParams probes;          // pressure probes on the walls (observe/probes.cpp)
  SimulationParams sim;
  std::vector<MembraneScene> membranes;
  double t_end = 1.0;
  long max_steps = 0;        // 0: no limit
  double steady_eps = 0.0;   // > 0: stop at steady state, Eqs. (81)-(82)
  double output_interval = 0.0;  // time between HDF5 snapshots (0: first and last only)
  std::vector<double> output_times;  // further snapshot times
  double checkpoint_interval = 0.0;  // time between checkpoints (0: only at the end)
  long diagnostics_every = 0;    // steps between diagnostics rows (0: about 500 rows)
  std::vector<std::string> fields{"u", "v", "p", "phi"};
  std::string reference_dir;     // Ghia tables for the cavity
  double memory_limit_gb = 0;    // refuse a run whose memory estimate exceeds this (0: the machine's memory)
  int threads = 0;               // threads of the step (limits.threads; 0: OMP_NUM_THREADS or the machine's cores)
  std::vector<std::pair<std::string, std::string>> resolved;  // every key = value as used (for attributes)
  std::vector<Observer> observers;                            // extra diagnostics (C++ scenes)
};

// Reads a scene file, applies `key=value` overrides (dotted keys, TOML values; a bare word is a
// string) and validates everything. Throws SceneError.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

// Same, from TOML text (for tests and the fuzzer); `name` is used in messages.
Scene parse_scene(const std::string& text, const std::string& name, const std::vector<std::string>& overrides = {});

// A membrane built by a program (markers from membrane/shapes.hpp; the Python module's
// Scene.add_membrane), added after the scene's own membranes and checked with them.
struct ProgramMembrane {
  Membrane membrane;
  double h_star = 0.0;  // absolute h*; 0: h_star_over_h * h
  double h_star_over_h = 1.4;
  bool fixed = false;
  double viscosity_ratio = 1.0;  // as membrane.viscosity_ratio
  // as membrane.semi_implicit (unset: its default, semi-implicit with bending or a law other than
  // hookean) and membrane.stiff_residual (needs the semi-implicit force)
  std::optional<bool> semi_implicit;
  bool stiff_residual = false;
  // as membrane.tension_cutoff (unset: the membrane's own Material::tension_cutoff if > 0, else its
  // default, 2 max(dx, dy) for law inextensible and 0 for the others)
  std::optional<double> tension_cutoff;
};

// load_scene (path not empty) or parse_scene of an empty text named `name`, plus membranes built by
// a program: the reader checks them as it checks a file's ([4, 1e6] markers, T0 >= 0, h* > 0, no
// crossings, none in a free-surface scene, what observe.exact needs), naming membranes[k].
// more_may_follow: the program may add membranes still (a scene built step by step, as in Python), so
// the rules that need membranes to exist (contact.strength, observe.exact without any membrane) wait
// for the build without it, which a run makes.
Scene build_scene(const std::string& path, const std::string& name, const std::vector<std::string>& overrides,
                  const std::vector<ProgramMembrane>& membranes, bool more_may_follow = false);

// The scene whose resolved values (Scene::resolved: key = value as used) are `values`, e.g. those a
// checkpoint keeps, with `overrides` applied; observe.reference_dir is taken relative to base_dir.
// `name` is used in messages. Throws SceneError.
Scene scene_from_values(const std::vector<std::pair<std::string, std::string>>& values, const std::string& name,
                        const std::vector<std::string>& overrides = {}, const std::string& base_dir = ".");

// Resolved values that only restate others: "membranes", the [[membranes]] array as the file wrote it
// (each entry's keys, membranes[k].*, carry every value). Comparisons and hashes of scenes skip them.
bool restates_other_keys(const std::string& key);

// The SHA-256 (hex) of every resolved value of the scene (Scene::resolved), each key and value
// length-prefixed: the same text for the same run, whatever the file's layout or a value's spelling.
std::string scene_hash(const Scene& s);

// Every scene key with its type, default and meaning, one per line (the `sphib keys` listing).
std::string describe_scene_keys();

// The same as JSON (`sphib keys --json`): an array of {name, type, default, required, range, help},
// the default as a JSON value of the key's type (null when the key is required or has none).
std::string scene_keys_json();

}  // namespace sphib
