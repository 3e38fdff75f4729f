// Hydrodynamic loads on the walls, Afanasiev et al. (2011) Section 4: force_<wall> = int p dGamma
// and load_<wall> = int [p(t) - p(0)] dGamma (Eq. 31), from the fluid method's wall pressure
// (FluidSolver::wall_forces, fluid/common/loads.hpp: Eq. 32 over wall particles, or the pressure at the
// wall line for image walls). On the fixed lattice also the tangential load: shear_<wall>, the
// fluid's shear stress at the wall (fluid/common/loads.hpp, wall_shear_stress), and for a box sheared by
// its bottom and top walls the effective viscosity mu_eff = (shear_bottom + shear_top) / (2 G),
// G = (U_top - U_bottom) / (y1 - y0) the walls' shear rate: the viscosity of the fluid that would
// carry the same wall stress in plain Couette flow (a suspension's, once its flow is steady).
#include <cmath>

#include "fluid/common/loads.hpp"
#include "observe/analysis.hpp"

namespace sphib {

namespace {

class WallLoads final : public Analysis {
 public:
  explicit WallLoads(const Simulation& sim) : F0_(sim.fluid().wall_forces()) {
    for (int s = 0; s < 4; ++s)
      if (std::isfinite(F0_[s])) walls_.push_back(s);
    const FluidSolver& f = sim.fluid();
    if (f.particles_move()) return;  // the shear stress needs the fixed lattice's rows
    const WallForces tau = shear(sim);
    for (int s = 0; s < 4; ++s)
      if (std::isfinite(tau[s])) sheared_.push_back(s);
    const Domain& d = f.params().domain;
    G_ = std::isfinite(tau[Bottom]) && std::isfinite(tau[Top])
             ? (d.wall_velocity[Top].x() - d.wall_velocity[Bottom].x()) / d.Ly()
             : 0.0;
  }
  std::vector<std::string> columns() const override {
    std::vector<std::string> c;
    for (int s : walls_) c.push_back(std::string("force_") + side_name(static_cast<Side>(s)));
    for (int s : walls_) c.push_back(std::string("load_") + side_name(static_cast<Side>(s)));
    for (int s : sheared_) c.push_back(std::string("shear_") + side_name(static_cast<Side>(s)));
    if (G_ != 0.0) c.push_back("mu_eff");
    return c;
  }
  void sample(const Simulation& sim, std::vector<double>& row) override {
    const WallForces F = sim.fluid().wall_forces();
    for (int s : walls_) row.push_back(F[s]);
    for (int s : walls_) row.push_back(F[s] - F0_[s]);  // Eq. (31)
    if (sheared_.empty()) return;
    const WallForces tau = shear(sim);
    for (int s : sheared_) row.push_back(tau[s]);
    if (G_ != 0.0) row.push_back(0.5 * (tau[Bottom] + tau[Top]) / G_);  // mu_eff
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
    if (sheared_.empty()) return;
    const WallForces tau = shear(sim);
    for (int s : sheared_) j[std::string("shear_") + side_name(static_cast<Side>(s))] = tau[s];
    if (G_ == 0.0) return;
    j["mu_eff"] = 0.5 * (tau[Bottom] + tau[Top]) / G_;
    // its mean over the samples of the run's second half (a suspension's stress fluctuates)
    const int c = series.column("mu_eff");
    if (c < 0 || ct < 0 || series.rows.empty()) return;
    const double t_half = 0.5 * series.rows.back()[ct];
    double sum = 0.0;
    int n = 0;
    for (const auto& r : series.rows)
      if (r[ct] >= t_half) sum += r[c], ++n;
    if (n > 0) j["mu_eff_mean_second_half"] = sum / n;
  }

 private:
  static WallForces shear(const Simulation& sim) {
    const FluidSolver& f = sim.fluid();
    return wall_shear_stress(f.lattice(), f.u(), f.params().mu);
  }
  WallForces F0_;
  std::vector<int> walls_, sheared_;
  double G_ = 0.0;  // the walls' shear rate, 0: no mu_eff column
};

}  // namespace

std::unique_ptr<Analysis> wall_loads(const Simulation& sim) { return std::make_unique<WallLoads>(sim); }

}  // namespace sphib
