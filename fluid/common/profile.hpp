#pragma once
// Timing and reporting, in one place outside the fluid methods.
//   Profile:  accumulated wall time of the named phases of a time step (a few tens of ns per
//             measurement); the coupling keeps one for its phases.
//   Profiler: what the run loop (coupling::Simulation) owns for its fluid method and hands to it at
//             construction: the method's phases (a Profile), its set-up timings, its report (run-log
//             lines, summary figures, what it keeps: Footprint) and the bare kernels of its step,
//             which the profiler times on request (the floor of a step). A method records into it
//             and registers two functions; a method that registers nothing reports nothing.
#include <algorithm>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sphib {

class Profile {
 public:
  using Clock = std::chrono::steady_clock;
  // Index of a phase, created on first use (call once at set-up, keep the index).
  int phase(const std::string& name) {
    for (size_t k = 0; k < names_.size(); ++k)
      if (names_[k] == name) return static_cast<int>(k);
    names_.push_back(name);
    seconds_.push_back(0.0);
    counts_.push_back(0);
    return static_cast<int>(names_.size() - 1);
  }
  void add(int k, double s) { seconds_[k] += s; ++counts_[k]; }
  const std::vector<std::string>& names() const { return names_; }
  double seconds(int k) const { return seconds_[k]; }
  long count(int k) const { return counts_[k]; }
  double total() const { double t = 0; for (double s : seconds_) t += s; return t; }

 private:
  std::vector<std::string> names_;
  std::vector<double> seconds_;
  std::vector<long> counts_;
};

// Seconds from t0 to now (set-up timings of the solvers and runs).
inline double seconds_since(Profile::Clock::time_point t0) {
  return std::chrono::duration<double>(Profile::Clock::now() - t0).count();
}

// The shortest of `reps` timings of kernel() (the floor of a step).
template <class F>
double best_of(int reps, F&& kernel) {
  double t = 1e300;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = Profile::Clock::now();
    kernel();
    t = std::min(t, seconds_since(t0));
  }
  return t;
}

// Times a block into one phase: { ScopedTimer t(profile, k); ... }
class ScopedTimer {
 public:
  ScopedTimer(Profile& p, int k) : p_(p), k_(k), t0_(Profile::Clock::now()) {}
  ~ScopedTimer() { p_.add(k_, std::chrono::duration<double>(Profile::Clock::now() - t0_).count()); }

 private:
  Profile& p_;
  int k_;
  Profile::Clock::time_point t0_;
};

// What a fluid method keeps for the whole run (`sphib check`'s memory estimate): the non-zeros of
// its operator matrices and of its factors (with the matrices it keeps), its neighbour pairs.
struct Footprint {
  long operator_nonzeros = 0, factor_nonzeros = 0, pairs = 0;
};

// A fluid method's report: run-log lines (particles, images, neighbours, each linear system's
// factorisation), figures for the summary (name, value), and its footprint (none for a method that
// rebuilds its operators every step).
struct FluidReport {
  std::vector<std::string> lines;
  std::vector<std::pair<std::string, double>> figures;
  std::optional<Footprint> footprint;
};

// Times the bare kernels of a step handed to it, each alone, best of `reps`, and sums them.
class FloorTimer {
 public:
  explicit FloorTimer(int reps) : reps_(reps) {}
  template <class F>
  void kernel(F&& f) { total_ += best_of(reps_, f); }
  void add(double seconds) { total_ += seconds; }  // a part timed the same way elsewhere
  int reps() const { return reps_; }
  double total() const { return total_; }

 private:
  int reps_;
  double total_ = 0;
};

class Profiler : public Profile {
 public:
  Profiler() = default;
  Profiler(const Profiler&) = delete;
  Profiler& operator=(const Profiler&) = delete;

  // A phase made on demand (the pressure for output, the markers' stream function for the
  // coupling), not part of step(): step_seconds() leaves it out.
  int on_demand_phase(const std::string& name) {
    const int k = phase(name);
    if (static_cast<int>(on_demand_.size()) <= k) on_demand_.resize(k + 1, 0);
    on_demand_[k] = 1;
    return k;
  }
  // The wall time of the steps so far: the phases of step().
  double step_seconds() const {
    double t = 0;
    for (size_t k = 0; k < names().size(); ++k)
      if (k >= on_demand_.size() || !on_demand_[k]) t += seconds(static_cast<int>(k));
    return t;
  }

  // Set-up timings: "neighbours", "assembly", "factorisation" (0 for one not recorded).
  void add_setup(const std::string& what, double s) { setup_.emplace_back(what, s); }
  double setup_seconds(const std::string& what) const {
    for (const auto& [k, s] : setup_)
      if (k == what) return s;
    return 0.0;
  }

  // The method's report of its current state, made by the function it registered.
  void set_reporter(std::function<void(FluidReport&)> r) { reporter_ = std::move(r); }
  FluidReport report() const {
    FluidReport r;
    if (reporter_) reporter_(r);
    return r;
  }

  // The floor of a step: the bare kernels it cannot avoid on the current fields, each timed alone,
  // best of `reps` (0: the method registered none). The markers' stream function's bare solve is
  // timed the same way: part of the coupling's floor (Simulation::coupling_floor_seconds).
  using Floor = std::function<void(FloorTimer&)>;
  void set_floor(Floor f) { floor_ = std::move(f); }
  void set_stream_function_floor(Floor f) { psi_floor_ = std::move(f); }
  double floor_seconds(int reps = 20) const { return timed(floor_, reps); }
  double stream_function_floor_seconds(int reps = 20) const { return timed(psi_floor_, reps); }

  // The method is gone: forget the functions it registered (its timings stay).
  void detach() {
    reporter_ = nullptr;
    floor_ = psi_floor_ = nullptr;
  }

 private:
  static double timed(const Floor& f, int reps) {
    if (!f) return 0.0;
    FloorTimer t(reps);
    f(t);
    return t.total();
  }
  std::vector<char> on_demand_;
  std::vector<std::pair<std::string, double>> setup_;
  std::function<void(FluidReport&)> reporter_;
  Floor floor_, psi_floor_;
};

}  // namespace sphib
