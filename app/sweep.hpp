#pragma once
// `sphib sweep`: a scene run over every combination of parameter values, in process, with a
// table of summary figures and observed orders (the semantics of scripts/sweep.py).
#include <atomic>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

namespace sphib::app {

// Bad arguments (exit status 2).
struct UsageError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct SweepOptions {
  std::string scene;                 // scene file
  std::string out;                   // DIR: DIR/run_NNN per combination, DIR/sweep.csv, DIR/sweep.md
  std::vector<std::string> vary;     // key=v1,v2,...; the first key is the resolution of the orders
  std::vector<std::string> derive;   // key=EXPR of {varied.key} (expression.hpp)
  std::vector<std::string> set;      // key=value for every run
  std::vector<std::string> report;   // summary fields; a dotted name reaches into objects (area_relative_error_at.2)
  std::ostream* log = nullptr;       // one line per run (nullptr: silent)
  std::ostream* table = nullptr;     // the Markdown table at the end (nullptr: not printed)
  const std::atomic<int>* stop = nullptr;  // a signal's number: the current run ends cleanly, no further runs
};

struct SweepResult {
  int runs = 0, failed = 0, reused = 0;  // reused: runs whose summary.json was already there
  std::string markdown;                  // the content of DIR/sweep.md
};

// Every combination of the --vary values (the last key varying fastest) is set up first (a bad
// key or value throws SceneError before anything runs), then run with run_scene into
// DIR/run_NNN unless DIR/run_NNN/summary.json is of a run of the same scene (its scene_hash: every
// resolved value) that was not stopped by a signal; a run of another scene there is replaced. A key
// both varied and set (--set) or derived (--derive) throws UsageError. A --report field missing from the first run's summary throws UsageError
// naming the fields it has (the runs done are kept). A run that fails is reported and the sweep goes on; its row has the
// figures its summary has, if any.
// Observed orders: between successive values of the first varied key with the other varied keys
// fixed, log(e_a/e_b)/log(n_b/n_a). Throws UsageError or ExpressionError for bad arguments.
SweepResult run_sweep(const SweepOptions& options);

}  // namespace sphib::app
