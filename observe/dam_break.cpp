// The dam break of Afanasiev et al. (2011), Section 7: the surge front on the floor against the
// experiments of Martin & Moyce (1952) and Koshizuka & Oka (1996) (cases/reference/).
#include <algorithm>
#include <cmath>

#include "observe/analysis.hpp"
#include "observe/table.hpp"

namespace sphib {

namespace {

struct Experiment {
  std::string name;
  Table points;  // T, Z
};

class DamBreakFront final : public Analysis {
 public:
  DamBreakFront(const Simulation& sim, const std::string& reference_dir) {
    const FluidParams& p = sim.fluid().params();
    const FluidRegion& fill = p.free_surface.fill;
    x0_ = p.domain.x0;
    floor_ = p.domain.y0;
    band_ = 2.0 * sim.fluid().lattice().dy;
    half_dx_ = 0.5 * sim.fluid().lattice().dx;
    a_ = fill.shape == FluidRegion::Shape::Block ? fill.x1 - fill.x0 : p.domain.Lx();
    g_ = p.gravity.norm();
    for (const char* name : {"martin_moyce_1952_a1.125in", "martin_moyce_1952_a2.25in", "koshizuka_oka_1996"})
      experiments_.push_back({name, read_table(reference_dir + "/dam_break_front_" + name + ".csv", "dam_break")});
  }
  std::vector<std::string> columns() const override { return {"front_x"}; }
  void sample(const Simulation& sim, std::vector<double>& row) override { row.push_back(front(sim.fluid())); }
  void summarize(const Simulation& sim, const Series& series, nlohmann::json& j) const override {
    j["front_x"] = front(sim.fluid());
    j["front_Z"] = front(sim.fluid()) / a_;
    const int ct = series.column("t"), cf = series.column("front_x");
    if (ct < 0 || cf < 0 || series.rows.size() < 2 || !(g_ > 0)) return;
    const double T_scale = std::sqrt(2.0 * g_ / a_);  // T = t sqrt(2 g / a)
    for (const Experiment& e : experiments_) {
      double sum = 0;
      int n = 0;
      for (const auto& pt : e.points.rows) {
        const double T = pt[0], Z = pt[1];
        if (Z > 3.5 || T / T_scale > series.rows.back()[ct]) continue;  // before the front meets the far wall
        sum += std::pow(interpolate(series, ct, cf, T / T_scale) / a_ - Z, 2);
        ++n;
      }
      if (n > 0) {
        std::string key = e.name;  // summary keys without dots (a dot reads as a nested key)
        std::replace(key.begin(), key.end(), '.', '_');
        j["front_deviation_" + key] = std::sqrt(sum / n);  // rms of Z - Z_exp
        j["front_points_" + key] = n;
      }
    }
  }

 private:
  double front(const FluidSolver& fl) const {
    return surge_front_x(fl.x(), floor_, band_, fl.kernel().support()) + half_dx_ - x0_;
  }
  // The sampled column c at time t, linear between samples.
  static double interpolate(const Series& s, int ct, int c, double t) {
    size_t k = 1;
    while (k + 1 < s.rows.size() && s.rows[k][ct] < t) ++k;
    const auto& r0 = s.rows[k - 1];
    const auto& r1 = s.rows[k];
    const double w = r1[ct] > r0[ct] ? std::clamp((t - r0[ct]) / (r1[ct] - r0[ct]), 0.0, 1.0) : 0.0;
    return r0[c] + w * (r1[c] - r0[c]);
  }

  double x0_, floor_, band_, half_dx_, a_, g_;
  std::vector<Experiment> experiments_;
};

}  // namespace

double surge_front_x(const Mat2& x, double y0, double band, double reach) {
  std::vector<int> floor;  // the particles in the band, leading one first
  for (int i = 0; i < x.rows(); ++i)
    if (x(i, 1) - y0 < band) floor.push_back(i);
  if (floor.empty()) return -INFINITY;
  std::sort(floor.begin(), floor.end(), [&](int a, int b) { return x(a, 0) > x(b, 0); });
  const double r2 = reach * reach;
  for (int i : floor)
    for (int j = 0; j < x.rows(); ++j)
      if (j != i && (x.row(j) - x.row(i)).squaredNorm() < r2) return x(i, 0);
  return x(floor.front(), 0);
}

std::unique_ptr<Analysis> dam_break_front(const Simulation& sim, const std::string& reference_dir) {
  return std::make_unique<DamBreakFront>(sim, reference_dir);
}

}  // namespace sphib
