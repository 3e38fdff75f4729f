#pragma once
// The run log's progress: on a terminal one updating bar, elsewhere a line every few seconds
// (step, time, steps per second, time to go, kinetic energy and, with membranes, the area error).
#include <chrono>
#include <ostream>

#include "coupling/simulation.hpp"

namespace sphib {

class Progress {
 public:
  // Silent if log is nullptr; a bar every 0.5 s, or a line every `every_seconds`.
  Progress(std::ostream* log, bool bar, double every_seconds, long steps);
  void tick(const Simulation& sim, double area_error);  // area_error: NaN without membranes
  void end();  // ends the bar's line

 private:
  using Clock = std::chrono::steady_clock;
  std::ostream* log_;
  bool bar_;
  double every_;
  long steps_;
  Clock::time_point start_ = Clock::now(), last_ = start_;
};

}  // namespace sphib
