// The unidirectional start-up flows against their exact series (fluid/common/exact.hpp): Eq. (69)'s rms
// over the particles of |u_ex - u| (rms_error), and the relative error of the profile
// (profile_error), sqrt(sum_i |u_ex - u_i|^2 / sum_i u_ex^2), the measure we take for the "numerical
// error" of Afanasiev et al. (2011), Tables 1-2 (the paper does not define it); the summary adds its
// maximum-norm form max_i |u_ex - u_i| / max_i u_ex (profile_error_max).
//  - Poiseuille (Eq. 44; body force F along x), Couette (the walls' x velocities);
//  - the inclined plane of Afanasiev et al. Section 6.2: a layer of depth H on a wall, free surface
//    on top, driven by F along x: by symmetry the lower half of the Poiseuille channel of height 2H
//    (zero shear on the centre line), steady profile F (H - y/2) y / nu (their Eq. 39).
#include <algorithm>
#include <cmath>
#include <map>

#include "fluid/algebra/row_stencil.hpp"  // kParallelRows
#include "fluid/common/exact.hpp"
#include "fluid/common/threads.hpp"
#include "observe/analysis.hpp"

namespace sphib {

namespace {

class ExactSeries final : public Analysis {
 public:
  ExactSeries(StartUpFlow flow, double F, double depth) : flow_(flow), F_(F), depth_(depth) {}

  std::vector<std::string> columns() const override { return {"rms_error", "profile_error"}; }
  void sample(const Simulation& sim, std::vector<double>& row) override {
    const Errors e = errors(sim.fluid());
    row.push_back(e.rms);
    row.push_back(e.relative);
  }
  void summarize(const Simulation& sim, const Series&, nlohmann::json& j) const override {
    const Errors e = errors(sim.fluid());
    j["rms_error"] = e.rms;
    j["profile_error"] = e.relative;
    j["profile_error_max"] = e.relative_max;
  }

 private:
  struct Errors {
    double rms, relative, relative_max;
  };
  double exact_u(const FluidSolver& fl, double y) const {
    const FluidParams& p = fl.params();
    const double nu = p.mu / p.rho;
    if (flow_ == StartUpFlow::Couette) {
      const double H = p.domain.Ly();
      const double U = p.domain.wall_velocity[Top].x() - p.domain.wall_velocity[Bottom].x();
      return p.domain.wall_velocity[Bottom].x() + exact::couette_u(y, fl.time(), nu, U, H);
    }
    // dimensional form of Eq. (44): u_max = F H^2 / (8 mu), Re = rho u_max H / mu; the inclined
    // plane is the channel of height 2 depth
    const double H = flow_ == StartUpFlow::Poiseuille ? p.domain.Ly() : 2.0 * depth_;
    const double umax = F_ * H * H / (8.0 * p.mu);
    const double Re = p.rho * umax * H / p.mu;
    return umax * exact::poiseuille_u(y / H, fl.time() * umax / H, Re);
  }
  // The sums over the particles: below kParallelRows particles in one pass, above by the threads in
  // fixed blocks (reduce_by_blocks: the same bits for any thread count; the sums differ from one
  // pass's in their rounding only, the maxima not at all).
  struct Sums {
    double e2 = 0, ue2 = 0, d2max = 0, uemax = 0;
  };
  Sums sums(const FluidSolver& fl, long at, long m) const {
    const double y0 = fl.params().domain.y0;
    const Mat2& x = fl.x();
    const Mat2& u = fl.u();
    Sums s;
    std::map<double, double> memo;  // the exact series depends on y only: once per lattice row
    double y_last = NAN, ue = 0;    // (a lattice row's particles are consecutive: one look-up per row)
    for (long i = at; i < at + m; ++i) {
      const double y = x(i, 1) - y0;
      if (y != y_last) {
        auto it = memo.find(y);
        if (it == memo.end()) it = memo.emplace(y, exact_u(fl, y)).first;
        ue = it->second;
        y_last = y;
      }
      const double d2 = (ue - u(i, 0)) * (ue - u(i, 0)) + u(i, 1) * u(i, 1);
      s.e2 += d2;
      s.ue2 += ue * ue;
      s.d2max = std::max(s.d2max, d2);  // max |u_ex - u_i| is the root of the largest square (sqrt is monotone)
      s.uemax = std::max(s.uemax, std::fabs(ue));
    }
    return s;
  }
  Errors errors(const FluidSolver& fl) const {
    const long N = fl.x().rows();
    const Sums s = N < kParallelRows ? sums(fl, 0, N)
                                     : reduce_by_blocks<Sums>(
                                           N, [&](long at, long m) { return sums(fl, at, m); },
                                           [](Sums a, const Sums& b) {
                                             a.e2 += b.e2;
                                             a.ue2 += b.ue2;
                                             a.d2max = std::max(a.d2max, b.d2max);
                                             a.uemax = std::max(a.uemax, b.uemax);
                                             return a;
                                           });
    auto ratio = [](double a, double b) { return b > 0 ? a / b : (a > 0 ? NAN : 0.0); };
    return {std::sqrt(s.e2 / N), ratio(std::sqrt(s.e2), std::sqrt(s.ue2)), ratio(std::sqrt(s.d2max), s.uemax)};
  }

  StartUpFlow flow_;
  double F_, depth_;
};

}  // namespace

std::unique_ptr<Analysis> exact_series(StartUpFlow flow, double F, double depth) {
  return std::make_unique<ExactSeries>(flow, F, depth);
}

}  // namespace sphib
