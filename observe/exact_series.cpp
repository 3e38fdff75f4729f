// Eq. (69): the rms over the particles of |u_ex - u| for the unidirectional start-up flows, against
// the exact series of fluid/exact.hpp.
#include <cmath>
#include <map>

#include "fluid/exact.hpp"
#include "observe/analysis.hpp"

namespace sphib {

namespace {

class ExactSeries final : public Analysis {
 public:
  ExactSeries(StartUpFlow flow, double F) : flow_(flow), F_(F) {}

  std::vector<std::string> columns() const override { return {"rms_error"}; }
  void sample(const Simulation& sim, std::vector<double>& row) override { row.push_back(rms_error(sim.fluid())); }
  void summarize(const Simulation& sim, const Series&, nlohmann::json& j) const override {
    j["rms_error"] = rms_error(sim.fluid());
  }

 private:
  double rms_error(const FluidSolver& fl) const {
    const FluidParams& p = fl.params();
    const double H = p.domain.Ly(), nu = p.mu / p.rho;
    const Mat2& x = fl.x();
    const Mat2& u = fl.u();
    double e = 0;
    std::map<double, double> memo;  // the exact series depends on y only: once per lattice row
    for (int i = 0; i < x.rows(); ++i) {
      const double y = x(i, 1) - p.domain.y0;
      if (auto it = memo.find(y); it != memo.end()) {
        e += (it->second - u(i, 0)) * (it->second - u(i, 0)) + u(i, 1) * u(i, 1);
        continue;
      }
      double ue = 0;
      if (flow_ == StartUpFlow::Poiseuille) {
        // dimensional form of Eq. (44): u_max = F H^2 / (8 mu), Re = rho u_max H / mu
        const double umax = F_ * H * H / (8.0 * p.mu);
        const double Re = p.rho * umax * H / p.mu;
        ue = umax * exact::poiseuille_u(y / H, fl.time() * umax / H, Re);
      } else {
        const double U = p.domain.wall_velocity[Top].x() - p.domain.wall_velocity[Bottom].x();
        ue = p.domain.wall_velocity[Bottom].x() + exact::couette_u(y, fl.time(), nu, U, H);
      }
      memo[y] = ue;
      e += (ue - u(i, 0)) * (ue - u(i, 0)) + u(i, 1) * u(i, 1);
    }
    return std::sqrt(e / x.rows());
  }

  StartUpFlow flow_;
  double F_;
};

}  // namespace

std::unique_ptr<Analysis> exact_series(StartUpFlow flow, double F) { return std::make_unique<ExactSeries>(flow, F); }

}  // namespace sphib
