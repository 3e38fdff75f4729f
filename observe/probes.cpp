// Pressure probes on the walls: the pressure a transducer of a stated width would read, averaged
// over a stated time window, so that the peak of an impact is a property of the flow rather than of
// one step (the wall loads of loads.cpp are single-step integrals over the whole wall).
//
// A probe is a point c on a wall line; its sensor is the wall segment of width `size` centred on c
// (a 2-D transducer face: a 1-D segment across the flow's plane). The pressure there is
//   p_s(t) = (1/n) sum_k p(c + s_k e),   s_k = size ((k + 1/2)/n - 1/2),  n points ~ dx/4 apart,
// e the wall's direction, each point's p the kernel interpolation of the particles' pressure with the
// hydrostatic term of Adami, Hu & Adams (2012, J. Comput. Phys. 231, Eq. 27), which extrapolates a
// fluid at rest exactly to the wall:
//   p(x) = sum_j V_j W(x - x_j) [p_j + rho0 g . (x - x_j)] / max(sum_j V_j W(x - x_j), 0.4).
// The denominator is the Shepard sum, bounded below by 0.4, under its value at a wetted wall (half the
// kernel's support filled: about 1/2, 0.495 on the lattice at h = 1.3 dx), so that a sensor point
// reached by a few splash particles reads their share, not their pressure. The reading is then averaged over the window [t - window, t] of the steps
// (window = 0: the step's own value). Columns probe_<name>; the summary adds each probe's largest
// windowed reading (probe_<name>_max) and its time (probe_<name>_max_t), over every step.
#include <algorithm>
#include <cmath>
#include <deque>

#include "observe/analysis.hpp"

namespace sphib {

namespace {

class PressureProbes final : public Analysis {
 public:
  PressureProbes(const Simulation& sim, const ProbeParams& prm) : prm_(prm) {
    const FluidSolver& fl = sim.fluid();
    const Lattice& L = fl.lattice();
    const int n = prm_.size > 0 ? std::max(2, static_cast<int>(std::ceil(prm_.size / (0.25 * std::min(L.dx, L.dy))))) : 1;
    for (const PressureProbe& pr : prm_.probes) {
      Sensor s;
      const Eigen::Vector2d e = pr.side == Left || pr.side == Right ? Eigen::Vector2d(0, 1) : Eigen::Vector2d(1, 0);
      for (int k = 0; k < n; ++k) s.points.push_back(pr.x + e * (prm_.size * ((k + 0.5) / n - 0.5)));
      sensors_.push_back(s);
    }
  }
  std::vector<std::string> columns() const override {
    std::vector<std::string> c;
    for (const PressureProbe& pr : prm_.probes) c.push_back("probe_" + pr.name);
    return c;
  }
  void after_step(const Simulation& sim) override { record(sim); }
  void sample(const Simulation& sim, std::vector<double>& row) override {
    if (sensors_.empty() || sensors_[0].window.empty()) record(sim);  // t = 0 (before the first step)
    for (const Sensor& s : sensors_) row.push_back(s.mean);
  }
  void summarize(const Simulation&, const Series&, nlohmann::json& j) const override {
    for (size_t k = 0; k < sensors_.size(); ++k) {
      const std::string name = "probe_" + prm_.probes[k].name;
      j[name + "_max"] = sensors_[k].max;
      j[name + "_max_t"] = sensors_[k].max_t;
    }
    j["probe_size"] = prm_.size;
    j["probe_window"] = prm_.window;
  }
  nlohmann::json save() const override {
    nlohmann::json a = nlohmann::json::array();
    for (const Sensor& s : sensors_) {
      nlohmann::json w = nlohmann::json::array();
      for (const auto& [t, p] : s.window) w.push_back({t, p});
      a.push_back({{"window", w}, {"mean", s.mean}, {"max", s.max}, {"max_t", s.max_t}});
    }
    return a;
  }
  void restore(const nlohmann::json& saved) override {
    if (!saved.is_array() || saved.size() != sensors_.size()) return;
    for (size_t k = 0; k < sensors_.size(); ++k) {
      Sensor& s = sensors_[k];
      const nlohmann::json& v = saved[k];
      s.window.clear();
      for (const auto& e : v.at("window")) s.window.emplace_back(e.at(0).get<double>(), e.at(1).get<double>());
      s.mean = v.at("mean").get<double>();
      s.max = v.at("max").get<double>();
      s.max_t = v.at("max_t").get<double>();
    }
  }

 private:
  struct Sensor {
    std::vector<Eigen::Vector2d> points;
    std::deque<std::pair<double, double>> window;  // (t, p_s) of the steps in the window
    double mean = 0, max = -INFINITY, max_t = NAN;
  };

  // The sensor's reading now (see the header), then its window's mean.
  void record(const Simulation& sim) {
    const FluidSolver& fl = sim.fluid();
    const Mat2& x = fl.x();
    const Vec& V = fl.volumes();
    const Vec& p = fl.p();
    const CubicSplineKernel& W = fl.kernel();
    const double reach = W.support(), rho0 = fl.params().rho, t = fl.time();
    const Eigen::Vector2d g = fl.params().gravity;
    for (Sensor& s : sensors_) {
      double ps = 0;
      for (const Eigen::Vector2d& c : s.points) {
        double num = 0, den = 0;
        for (int j = 0; j < x.rows(); ++j) {
          const double dx = c.x() - x(j, 0), dy = c.y() - x(j, 1);
          if (std::fabs(dx) >= reach || std::fabs(dy) >= reach) continue;
          const double r = std::hypot(dx, dy);
          if (r >= reach) continue;
          const double w = V[j] * W.W(r);
          num += w * (p[j] + rho0 * (g.x() * dx + g.y() * dy));  // Adami et al. (2012) Eq. (27)
          den += w;
        }
        ps += num / std::max(den, 0.4);
      }
      ps /= static_cast<double>(s.points.size());
      s.window.emplace_back(t, ps);
      while (s.window.size() > 1 && s.window.front().first < t - prm_.window * (1 + 1e-9)) s.window.pop_front();
      double sum = 0;
      for (const auto& e : s.window) sum += e.second;
      s.mean = sum / static_cast<double>(s.window.size());
      if (s.mean > s.max) { s.max = s.mean; s.max_t = t; }
    }
  }

  ProbeParams prm_;
  std::vector<Sensor> sensors_;
};

}  // namespace

std::unique_ptr<Analysis> pressure_probes(const Simulation& sim, const ProbeParams& params) {
  return std::make_unique<PressureProbes>(sim, params);
}

}  // namespace sphib
