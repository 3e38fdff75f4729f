#include "io/progress.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace sphib {

namespace {
double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}
}  // namespace

Progress::Progress(std::ostream* log, bool bar, double every_seconds, long steps)
    : log_(log), bar_(bar), every_(bar ? 0.5 : every_seconds), steps_(steps) {}

void Progress::tick(const Simulation& sim, double area_error) {
  const auto now = Clock::now();
  if (!log_ || seconds(last_, now) <= every_) return;
  last_ = now;
  const double rate = sim.steps() / seconds(start_, now), eta = (steps_ - sim.steps()) / rate;
  std::ostringstream m;
  m << std::setprecision(4) << "  step " << sim.steps() << "/" << steps_ << " t = " << sim.time() << "  " << rate
    << " steps/s  ETA " << eta << " s  KE = " << sim.fluid().kinetic_energy();
  if (!std::isnan(area_error)) m << "  area err = " << area_error;
  if (bar_) {
    const int w = 30, done = static_cast<int>(w * sim.steps() / steps_);
    *log_ << "\r[" << std::string(done, '#') << std::string(w - done, ' ') << "]" << m.str() << "   " << std::flush;
  } else {
    *log_ << m.str() << std::endl;
  }
}

void Progress::end() {
  if (log_ && bar_) *log_ << "\n";
}

}  // namespace sphib
