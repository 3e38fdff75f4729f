// The flow's own figures: time, step, kinetic energy, the largest divergence (Eq. 30) and speed.
#include "observe/analysis.hpp"

namespace sphib {

namespace {

class FlowFigures final : public Analysis {
 public:
  std::vector<std::string> columns() const override {
    return {"t", "step", "kinetic_energy", "max_div_u", "max_speed"};
  }
  void sample(const Simulation& sim, std::vector<double>& row) override {
    const FluidSolver& fl = sim.fluid();
    for (double v : {fl.time(), static_cast<double>(fl.steps()), fl.kinetic_energy(), fl.max_abs_divergence(),
                     fl.max_speed()})
      row.push_back(v);
  }
  void summarize(const Simulation& sim, const Series&, nlohmann::json& j) const override {
    const FluidSolver& fl = sim.fluid();
    j["kinetic_energy"] = fl.kinetic_energy();
    j["max_div_u"] = fl.max_abs_divergence();
    j["max_speed"] = fl.max_speed();
  }
};

}  // namespace

std::unique_ptr<Analysis> flow_figures() { return std::make_unique<FlowFigures>(); }

}  // namespace sphib
