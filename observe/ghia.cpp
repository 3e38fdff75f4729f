// The lid-driven cavity against Ghia, Ghia & Shin (1982): the centre-line velocities u(0.5, y) and
// v(x, 0.5) at their points, by normalised SPH interpolation (Eq. 61).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "coupling/interpolate.hpp"
#include "observe/analysis.hpp"
#include "observe/table.hpp"

namespace sphib {

namespace {

// Largest and rms absolute value.
std::pair<double, double> max_rms(const std::vector<double>& d) {
  double mx = 0, rm = 0;
  for (double x : d) { mx = std::max(mx, std::fabs(x)); rm += x * x; }
  return {mx, d.empty() ? 0 : std::sqrt(rm / d.size())};
}

class GhiaCentrelines final : public Analysis {
 public:
  GhiaCentrelines(const Simulation& sim, const std::string& reference_dir, std::string out_dir)
      : out_dir_(std::move(out_dir)),
        u_(read_table(reference_dir + "/ghia1982_u_vertical_centreline.csv", "cavity")),
        v_(read_table(reference_dir + "/ghia1982_v_horizontal_centreline.csv", "cavity")) {
    const FluidParams& fp = sim.fluid().params();
    Re_ = fp.rho * fp.domain.wall_velocity[Top].x() * fp.domain.Lx() / fp.mu;
    const std::string re = std::to_string(static_cast<long>(std::lround(Re_)));
    if (u_.col("u_re" + re) >= 0 && std::fabs(Re_ - std::lround(Re_)) < 1e-9) {
      col_u_ = "u_re" + re;
      col_v_ = "v_re" + re;
    }
  }

  void summarize(const Simulation& sim, const Series&, nlohmann::json& j) const override {
    const FluidSolver& fl = sim.fluid();
    const Domain& d = fl.params().domain;
    CellGrid grid(Eigen::Vector2d(d.x0, d.y0), Eigen::Vector2d(d.x1, d.y1), d.periodic_x, d.periodic_y, 2.0 * fl.h());
    grid.build(fl.x());
    const std::vector<double> du = profile(fl, grid, u_, true, col_u_, "centreline_u");
    const std::vector<double> dv = profile(fl, grid, v_, false, col_v_, "centreline_v");
    j["reynolds"] = Re_;
    if (col_u_.empty()) {
      j["reference"] = "none: Ghia et al. tabulate Re = 100, 400, 1000 only";
      return;
    }
    std::vector<double> all(du);
    all.insert(all.end(), dv.begin(), dv.end());
    j["reference"] = "Ghia, Ghia & Shin (1982), column " + col_u_ + "/" + col_v_;
    std::tie(j["max_deviation"], j["rms_deviation"]) = max_rms(all);
    std::tie(j["max_deviation_u"], j["rms_deviation_u"]) = max_rms(du);
    std::tie(j["max_deviation_v"], j["rms_deviation_v"]) = max_rms(dv);
  }

 private:
  // The profile along the vertical (u) or horizontal (v) centre line at the table's points, written
  // to out_dir/name.csv beside the reference column; returns the deviations at the interior points
  // (the wall points are boundary values, not computed).
  std::vector<double> profile(const FluidSolver& fl, const CellGrid& grid, const Table& t, bool vertical,
                              const std::string& col, const std::string& name) const {
    const Domain& d = fl.params().domain;
    const int n = static_cast<int>(t.rows.size());
    Mat2 X(n, 2), U(n, 2);
    for (int k = 0; k < n; ++k) {
      const double c = t.rows[k][0];
      X(k, 0) = vertical ? d.x0 + 0.5 * d.Lx() : d.x0 + c * d.Lx();
      X(k, 1) = vertical ? d.y0 + c * d.Ly() : d.y0 + 0.5 * d.Ly();
    }
    interpolate_velocity(grid, fl.kernel(), fl.volumes(), fl.u(), X, U);  // Eq. (61)
    std::ofstream out(out_dir_ + "/" + name + ".csv");
    out << (vertical ? "y,u" : "x,v") << (col.empty() ? "" : "," + col) << "\n";
    const int cc = col.empty() ? -1 : t.col(col);
    std::vector<double> dev;
    for (int k = 0; k < n; ++k) {
      const double c = t.rows[k][0], val = U(k, vertical ? 0 : 1);
      out << std::setprecision(10) << c << "," << val;
      if (cc >= 0) {
        out << "," << t.rows[k][cc];
        if (c > 0 && c < 1) dev.push_back(val - t.rows[k][cc]);
      }
      out << "\n";
    }
    return dev;
  }

  std::string out_dir_;
  Table u_, v_;
  double Re_ = 0;
  std::string col_u_, col_v_;
};

}  // namespace

std::unique_ptr<Analysis> ghia_centrelines(const Simulation& sim, const std::string& reference_dir,
                                           const std::string& out_dir) {
  return std::make_unique<GhiaCentrelines>(sim, reference_dir, out_dir);
}

}  // namespace sphib
