#pragma once
// Accumulated wall time of the named phases of a time step (a few tens of ns per measurement).
#include <algorithm>
#include <chrono>
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

// The shortest of `reps` timings of kernel() (the floor of a step: fluid/solver.hpp).
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

}  // namespace sphib
