// The elliptic drop of Afanasiev et al. (2011), Section 6.3: its semi-axis a(t) against the RK4
// solution of Eq. (42) and the relative error at t = 0.8 (Table 3).
#include <cmath>

#include "fluid/common/exact.hpp"
#include "observe/analysis.hpp"

namespace sphib {

namespace {

class DropletAxis final : public Analysis {
 public:
  DropletAxis(const Simulation& sim, double t_error) : t_error_(t_error) {
    const Mat2& x = sim.fluid().x();
    const Eigen::RowVector2d c = x.colwise().mean();
    r0_ = (x.rowwise() - c).rowwise().norm().maxCoeff();
  }

  std::vector<std::string> columns() const override { return {"droplet_a", "droplet_a_exact"}; }
  void after_step(const Simulation& sim) override {
    const double t = sim.time(), dt = sim.fluid().params().dt;
    if (!std::isnan(error_) || t < t_error_ - 0.5 * dt) return;
    const double a_ex = exact_at(t);  // the step nearest t_error (dt divides it in the cases)
    error_ = std::fabs(measured(sim.fluid()) - a_ex) / a_ex;
    // the other measure: the particle farthest along x, over the outermost particle's initial radius
    const Mat2& x = sim.fluid().x();
    const double extent = (x.col(0).array() - x.col(0).mean()).abs().maxCoeff() / r0_;
    error_extent_ = std::fabs(extent - a_ex) / a_ex;
    error_t_ = t;
  }
  void sample(const Simulation& sim, std::vector<double>& row) override {
    row.push_back(measured(sim.fluid()));
    row.push_back(exact_at(sim.time()));
  }
  void summarize(const Simulation& sim, const Series&, nlohmann::json& j) const override {
    j["droplet_a"] = measured(sim.fluid());
    if (std::isnan(error_)) return;  // the run ended before t_error
    j["droplet_axis_error"] = error_;
    j["droplet_axis_error_extent"] = error_extent_;
    j["droplet_axis_error_t"] = error_t_;
  }

 private:
  // (I_xx / I_yy)^(1/4): the flow of Eq. (40) maps x -> a x, y -> y / a, so I_xx = a^2 I_xx(0) and
  // I_yy = I_yy(0) / a^2, with I_xx(0) = I_yy(0) for the symmetric initial circle.
  static double measured(const FluidSolver& fl) {
    const Mat2& x = fl.x();
    const Eigen::RowVector2d c = x.colwise().mean();
    const double Ixx = (x.col(0).array() - c(0)).square().sum(), Iyy = (x.col(1).array() - c(1)).square().sum();
    return std::pow(Ixx / Iyy, 0.25);
  }
  double exact_at(double t) {
    if (t < rk_.t) rk_ = exact::DropletAxis{};  // (samples come in order; a restart starts again)
    rk_.advance_to(t);
    return rk_.a;
  }

  double t_error_, r0_ = 1.0, error_ = NAN, error_extent_ = NAN, error_t_ = NAN;
  exact::DropletAxis rk_;
};

}  // namespace

std::unique_ptr<Analysis> droplet_axis(const Simulation& sim, double t_error) {
  return std::make_unique<DropletAxis>(sim, t_error);
}

}  // namespace sphib
