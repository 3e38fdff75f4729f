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
// diagnostics.csv and the HDF5 series, its last value into summary.json under `name`. The name is
// its own: a run refuses one that another column or a field of every run's summary has.
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
  void add(std::unique_ptr<Analysis> a);  // std::invalid_argument if a column of it is already there
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

// exact_series.cpp: rms_error, Eq. (69), and the relative profile_error against the start-up series
// of Poiseuille (Eq. 44; body force F per unit volume along x), Couette flow (the walls' x
// velocities) or the inclined plane of Afanasiev et al. Section 6.2 (a layer of depth `depth` on
// the bottom wall, free surface on top, F along x).
enum class StartUpFlow { Poiseuille, Couette, InclinedPlane };
std::unique_ptr<Analysis> exact_series(StartUpFlow flow, double F, double depth = 0.0);

// loads.cpp: for every wall, force_<wall> = int p dGamma (FluidSolver::wall_forces) and
// load_<wall> = force_<wall>(t) - force_<wall>(0), the load of Afanasiev et al. Eqs. (31)-(32)
// (t = 0: the first sample, the restart time for a restarted run); the summary adds each load's
// extremes and their times.
std::unique_ptr<Analysis> wall_loads(const Simulation& sim);

// droplet.cpp: the elliptic drop of Afanasiev et al. Section 6.3: droplet_a, its semi-axis along x
// measured as (I_xx / I_yy)^(1/4) from the particles' centred second moments (exact for the affine
// flow of Eq. 40 from any initial set with I_xx = I_yy), against droplet_a_exact (RK4 of Eq. 42,
// fluid/common/exact.hpp); droplet_axis_error = |a - a_exact| / a_exact at t = t_error (0.8, Table 3), and
// droplet_axis_error_extent the same for a measured as the largest |x - x_c| over the outermost
// particle's initial radius.
std::unique_ptr<Analysis> droplet_axis(const Simulation& sim, double t_error = 0.8);

// dam_break.cpp: front_x, the leading edge on the floor (surge_front_x + dx/2 with a band of two
// spacings above the bottom wall and the kernel's support 2h as the reach) from the left wall; with the surge-front experiments of
// reference_dir/dam_break_front.csv (Z = x/a against T = t sqrt(2g/a), a the column's width) the
// summary's front_deviation_<series> (rms of Z - Z_exp over the experiment's points up to Z = 3.5;
// <series> the file's name with '.' as '_': martin_moyce_1952_a1_125in).
// Throws std::runtime_error naming a reference file it cannot read.
std::unique_ptr<Analysis> dam_break_front(const Simulation& sim, const std::string& reference_dir);

// The leading edge of a surge on the floor y = y0: the largest x of the particles (rows of x) within
// `band` above the floor that have another particle closer than `reach`. A particle with no other
// particle within the kernel's support is a splash that has left the surge, not its front (measured,
// ISPH dam break at 5000 particles, t = 0.195: one floor particle 2.8 dx ahead of the rest). If every
// particle in the band is alone, their largest x; -infinity when the band is empty.
double surge_front_x(const Mat2& x, double y0, double band, double reach);

// probes.cpp: pressure probes on the walls (see its header): a probe is a point of a wall line (its
// side given), its sensor the wall segment of width `size` around it, its reading the kernel
// interpolation of the particles' pressure (with the hydrostatic term of Adami et al. 2012) averaged
// over the sensor and over the time window [t - window, t] of the steps; columns probe_<name>, the
// summary's probe_<name>_max and probe_<name>_max_t over every step.
struct PressureProbe {
  std::string name;
  Eigen::Vector2d x = Eigen::Vector2d::Zero();
  Side side = Right;  // the wall it sits on
};
struct ProbeParams {
  std::vector<PressureProbe> probes;
  double size = 0.0;    // the sensor's width along the wall (0: a point)
  double window = 0.0;  // the averaging time (0: each step's own value)
};
std::unique_ptr<Analysis> pressure_probes(const Simulation& sim, const ProbeParams& params);

// steady.cpp: du_rms, dp_rms (Eqs. 81-82); done once both are below eps dt.
std::unique_ptr<Analysis> steady_state(double eps);

// equilibrium.cpp: the stretched membrane 0 in equilibrium (Section 5.2.1), radius re, rest
// radius r0: pressure_jump against (T0/re)(re/r0 - 1), pressure_mad_error (Eq. 80),
// velocity_mad_error (Eq. 83).
std::unique_ptr<Analysis> membrane_equilibrium(const Simulation& sim, double re, double r0);

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
