#pragma once
// What is observed while a simulation runs: analyses that add columns to the diagnostics series
// and figures to the summary, one file each in observe/ (the blow-up guards are in guards.hpp).
// An analysis reads the simulation and never changes it; io/ decides what is written where and
// which analyses a scene asks for.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "coupling/simulation.hpp"

namespace sphib {

// A diagnostics column of the user's choice: evaluated with the other diagnostics, written to
// diagnostics.csv and the HDF5 series, its last value into summary.json under `name`.
struct Observer {
  std::string name;
  std::function<double(const Simulation&)> value;
};

// The diagnostics time series: named columns, one row per sample.
struct Series {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  int column(const std::string& name) const;  // its index, -1 if there is none
};

// One analysis of a run. Every hook is optional.
class Analysis {
 public:
  virtual ~Analysis() = default;
  virtual std::vector<std::string> columns() const { return {}; }  // its columns of the series
  virtual void before_step(const Simulation&) {}
  virtual void after_step(const Simulation&) {}                     // after every step
  virtual void sample(const Simulation&, std::vector<double>& /*row*/) {}  // appends one value per column
  virtual bool done() const { return false; }  // what the run waits for has happened (a steady state)
  // Figures of the final state (and of the series) for summary.json.
  virtual void summarize(const Simulation&, const Series&, nlohmann::json& /*summary*/) const {}
  // What a restart must carry that the simulation's state does not (e.g. the area at t = 0): kept in
  // checkpoints and given back to the same analysis of the restarted run.
  virtual nlohmann::json save() const { return nullptr; }
  virtual void restore(const nlohmann::json& /*saved*/) {}
};

// The analyses of one run, in the order of their columns, and the series they sampled.
class Observers {
 public:
  void add(std::unique_ptr<Analysis> a);
  const std::vector<std::string>& columns() const { return series_.columns; }
  const Series& series() const { return series_; }
  double last(const std::string& column) const;  // the latest sample of a column (NaN: none)

  void before_step(const Simulation& sim);
  void after_step(const Simulation& sim);
  const std::vector<double>& sample(const Simulation& sim);  // a new row of the series
  bool done() const;
  void summarize(const Simulation& sim, nlohmann::json& summary) const;
  // A restart: every analysis's save() in order, and their return with the series so far (std::invalid_argument
  // if its columns are not these).
  nlohmann::json state() const;
  void restore(const nlohmann::json& state, const Series& series);

 private:
  std::vector<std::unique_ptr<Analysis>> analyses_;
  Series series_;
};

// ---- The analyses.

// flow.cpp: t, step, kinetic_energy, max_div_u, max_speed.
std::unique_ptr<Analysis> flow_figures();

// exact_series.cpp: rms_error, Eq. (69), against the start-up series of Poiseuille (Eq. 44; body
// force F along x) or Couette flow (the walls' x velocities).
enum class StartUpFlow { Poiseuille, Couette };
std::unique_ptr<Analysis> exact_series(StartUpFlow flow, double F);

// steady.cpp: du_rms, dp_rms (Eqs. 81-82); done once both are below eps dt.
std::unique_ptr<Analysis> steady_state(double eps);

// equilibrium.cpp: the stretched membrane 0 in equilibrium (Section 5.2.1), radius re, rest
// radius r0: pressure_jump against (T0/re)(re/r0 - 1), pressure_mad_error (Eq. 80),
// velocity_mad_error (Eq. 83).
std::unique_ptr<Analysis> membrane_equilibrium(const Simulation& sim, double re, double r0, double T0);

// analysis.cpp: the user's own columns.
std::unique_ptr<Analysis> user_observers(std::vector<Observer> observers);

// membranes.cpp: per membrane k the shape mk_rx ... mk_iterations; area, rx, ry, elastic energy
// and marker iterations of membrane 0, its area error at t = 1, 2, 5, 10.
std::unique_ptr<Analysis> membrane_shapes(const Simulation& sim);

// ghia.cpp: the lid-driven cavity's centre-line velocities against Ghia, Ghia & Shin (1982) read
// from reference_dir; writes out_dir/centreline_u.csv and centreline_v.csv with the summary.
// Throws std::runtime_error naming a table it cannot read.
std::unique_ptr<Analysis> ghia_centrelines(const Simulation& sim, const std::string& reference_dir,
                                           const std::string& out_dir);

// oscillation.cpp: period and amplitude decay of the m0_rx series (Section 5.2.2).
std::unique_ptr<Analysis> oscillation_fit();

}  // namespace sphib
