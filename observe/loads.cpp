// Hydrodynamic loads on the walls, Afanasiev et al. (2011) Section 4: force_<wall> = int p dGamma
// and load_<wall> = int [p(t) - p(0)] dGamma (Eq. 31), from the fluid method's wall pressure
// (FluidSolver::wall_forces, fluid/loads.hpp: Eq. 32 over wall particles, or the pressure at the
// wall line for image walls).
#include <cmath>

#include "observe/analysis.hpp"

namespace sphib {

namespace {

class WallLoads final : public Analysis {
 public:
  explicit WallLoads(const Simulation& sim) : F0_(sim.fluid().wall_forces()) {
    for (int s = 0; s < 4; ++s)
      if (std::isfinite(F0_[s])) walls_.push_back(s);
  }
  std::vector<std::string> columns() const override {
    std::vector<std::string> c;
    for (int s : walls_) c.push_back(std::string("force_") + side_name(static_cast<Side>(s)));
    for (int s : walls_) c.push_back(std::string("load_") + side_name(static_cast<Side>(s)));
    return c;
  }
  void sample(const Simulation& sim, std::vector<double>& row) override {
    const WallForces F = sim.fluid().wall_forces();
    for (int s : walls_) row.push_back(F[s]);
    for (int s : walls_) row.push_back(F[s] - F0_[s]);  // Eq. (31)
  }
  void summarize(const Simulation& sim, const Series& series, nlohmann::json& j) const override {
    const WallForces F = sim.fluid().wall_forces();
    const int ct = series.column("t");
    for (int s : walls_) {
      const std::string name = std::string("load_") + side_name(static_cast<Side>(s));
      j["force_" + std::string(side_name(static_cast<Side>(s)))] = F[s];
      j[name] = F[s] - F0_[s];
      const int c = series.column(name);
      if (c < 0 || ct < 0 || series.rows.empty()) continue;
      size_t lo = 0, hi = 0;  // the sampled extremes of the load and their times
      for (size_t r = 1; r < series.rows.size(); ++r) {
        if (series.rows[r][c] < series.rows[lo][c]) lo = r;
        if (series.rows[r][c] > series.rows[hi][c]) hi = r;
      }
      j[name + "_max"] = series.rows[hi][c];
      j[name + "_max_t"] = series.rows[hi][ct];
      j[name + "_min"] = series.rows[lo][c];
      j[name + "_min_t"] = series.rows[lo][ct];
    }
  }

 private:
  WallForces F0_;
  std::vector<int> walls_;
};

}  // namespace

std::unique_ptr<Analysis> wall_loads(const Simulation& sim) { return std::make_unique<WallLoads>(sim); }

}  // namespace sphib
