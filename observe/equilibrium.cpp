// The stretched membrane in equilibrium (Section 5.2.1): exact [p] = p_in - p_out =
// (T0/re)(re/r0 - 1) (Eq. 66 with the physical sign: the inside pressure is higher), u = 0. Any law on
// the circle reference: Laplace's [p] = (T(re/r0) + T_b)/re, T_b = -Eb/2 (1/re^2 - kappa0^2) the
// bending's tension (membrane/laws/bending.hpp; kappa0 = 1/r0 or the spontaneous curvature).
#include <algorithm>
#include <cmath>

#include "membrane/geometry.hpp"
#include "membrane/laws/bending.hpp"
#include "observe/analysis.hpp"

namespace sphib {

namespace {

class MembraneEquilibrium final : public Analysis {
 public:
  MembraneEquilibrium(const Simulation& sim, double re, double r0)
      : re_(re), jump_exact_(exact_jump(sim.membranes()[0].m.mat, re, r0)),
        D_(sim.membranes()[0].m.nb(), sim.membranes()[0].m.L0()) {}

  std::vector<std::string> columns() const override {
    return {"pressure_jump", "pressure_mad_error", "velocity_mad_error"};
  }
  void sample(const Simulation& sim, std::vector<double>& row) override {
    const Errors e = measure(sim);
    row.push_back(e.jump);
    row.push_back(e.p_mad);
    row.push_back(e.u_mad);
  }
  void summarize(const Simulation& sim, const Series&, nlohmann::json& j) const override {
    const Errors e = measure(sim);
    j["pressure_jump"] = e.jump;
    j["pressure_jump_exact"] = jump_exact_;
    j["pressure_jump_regions"] = "inside r < re - 2h* - 2h, outside r > re + 2h* + 2h and > 2h from walls";
    j["pressure_mad_error"] = e.p_mad;
    j["velocity_mad_error"] = e.u_mad;
  }

 private:
  struct Errors {
    double jump = 0, p_mad = 0, u_mad = 0;
  };
  static double exact_jump(const Material& mat, double re, double r0) {
    if (mat.law == "hookean" && mat.Eb == 0.0) return mat.Es / re * (re / r0 - 1.0);  // Eq. (66)
    const double T = make_tension_law(mat)->tension(re / r0);
    const double kappa0 = mat.spontaneous ? mat.spontaneous_curvature : 1.0 / r0, kappa = 1.0 / re;
    return (T + bending_tension(bending_moment(mat.Eb, kappa, kappa0), kappa, kappa0)) / re;
  }

  // Regions for the measured jump: inside r < re - 2h* - 2h, outside r > re + 2h* + 2h and more
  // than 2h from a wall, r from the membrane's centroid: both clear of the smoothed jump
  // (spreading support 2h*, SPH support 2h).
  Errors measure(const Simulation& sim) const {
    D_.fit(sim.membranes()[0].m.X);
    const Eigen::Vector2d c = D_.centroid();
    const FluidSolver& fl = sim.fluid();
    const Domain& d = fl.params().domain;
    const double band = 2.0 * sim.membranes()[0].h_star + 2.0 * fl.h();
    const Mat2& x = fl.x();
    const Vec& p = fl.p();
    const int N = fl.size();
    Errors e;
    double pin = 0, pout = 0;
    int nin = 0, nout = 0;
    std::vector<double> shifted(N);
    for (int i = 0; i < N; ++i) {
      const double r = std::hypot(x(i, 0) - c.x(), x(i, 1) - c.y());
      double wall_gap = INFINITY;
      if (!d.periodic_x) wall_gap = std::min({wall_gap, x(i, 0) - d.x0, d.x1 - x(i, 0)});
      if (!d.periodic_y) wall_gap = std::min({wall_gap, x(i, 1) - d.y0, d.y1 - x(i, 1)});
      if (r < re_ - band) { pin += p[i]; ++nin; }
      if (r > re_ + band && wall_gap > 2.0 * fl.h()) { pout += p[i]; ++nout; }
      shifted[i] = p[i] - (r < re_ ? jump_exact_ : 0.0);
      e.u_mad += std::fabs(fl.u()(i, 0)) + std::fabs(fl.u()(i, 1));  // Eq. (83), u_ex = 0
    }
    e.u_mad /= N;
    // Eq. (80) with the free constant of p_ex chosen optimally: the median minimises the mean |.|
    std::vector<double> sorted(shifted);
    std::nth_element(sorted.begin(), sorted.begin() + N / 2, sorted.end());
    const double c_opt = sorted[N / 2];
    for (double s : shifted) e.p_mad += std::fabs(s - c_opt);
    e.p_mad /= N;
    e.jump = (nin && nout) ? pin / nin - pout / nout : NAN;
    return e;
  }

  double re_, jump_exact_;
  mutable MembraneDiagnostics D_;  // workspace of measure()
};

}  // namespace

std::unique_ptr<Analysis> membrane_equilibrium(const Simulation& sim, double re, double r0) {
  return std::make_unique<MembraneEquilibrium>(sim, re, r0);
}

}  // namespace sphib
