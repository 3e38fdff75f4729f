// The steady-state criterion of Eqs. (81)-(82): the rms changes of u and p over one step.
#include <algorithm>
#include <cmath>

#include "observe/analysis.hpp"

namespace sphib {

namespace {

class SteadyState final : public Analysis {
 public:
  explicit SteadyState(double eps) : eps_(eps) {}

  std::vector<std::string> columns() const override { return {"du_rms", "dp_rms"}; }
  void before_step(const Simulation& sim) override {
    u_prev_ = sim.fluid().u();
    p_prev_ = sim.fluid().p();
  }
  void after_step(const Simulation& sim) override {
    const FluidSolver& fl = sim.fluid();
    const Mat2 du = fl.u() - u_prev_;
    du_rms_ = std::sqrt(du.squaredNorm() / du.rows());                   // Eq. (82)
    dp_rms_ = std::sqrt((fl.p() - p_prev_).squaredNorm() / fl.size());   // Eq. (81)
    steady_ = fl.steps() > 2 && std::max(du_rms_, dp_rms_) < eps_ * fl.params().dt;
  }
  void sample(const Simulation&, std::vector<double>& row) override {
    row.push_back(du_rms_);
    row.push_back(dp_rms_);
  }
  bool done() const override { return steady_; }
  void summarize(const Simulation&, const Series&, nlohmann::json& j) const override {
    j["du_rms"] = du_rms_;
    j["dp_rms"] = dp_rms_;
  }

 private:
  double eps_;
  Mat2 u_prev_;
  Vec p_prev_;
  double du_rms_ = NAN, dp_rms_ = NAN;
  bool steady_ = false;
};

}  // namespace

std::unique_ptr<Analysis> steady_state(double eps) { return std::make_unique<SteadyState>(eps); }

}  // namespace sphib
