// The membranes' shapes along the run (Section 5.2: half-axes, centroid, enclosed area, elastic
// energy, length, fixed-point iterations of Eq. 59), the measures of capsule and vesicle studies
// (Taylor deformation and inclination of the ellipse of the same second moments, the markers' mean
// angular velocity, the bending part of the energy, the largest stretch error) and membrane 0's area
// error at fixed times.
#include <algorithm>
#include <cmath>
#include <map>

#include "membrane/geometry.hpp"
#include "observe/analysis.hpp"

namespace sphib {

namespace {

class MembraneShapes final : public Analysis {
 public:
  explicit MembraneShapes(const Simulation& sim) {
    for (const auto& ms : sim.membranes()) {
      D_.emplace_back(ms.m.nb(), ms.m.L0());
      E_.push_back(ms.force);
      area0_.push_back(D_.back().measure(ms.m.X).area);
    }
  }

  std::vector<std::string> columns() const override {
    std::vector<std::string> c;
    for (size_t k = 0; k < D_.size(); ++k)
      for (const char* n : {"rx", "ry", "cx", "cy", "area", "area_rel_error", "elastic_energy", "length", "iterations"})
        c.push_back("m" + std::to_string(k) + "_" + n);
    for (size_t k = 0; k < D_.size(); ++k)
      for (const char* n : {"D", "inclination", "omega", "bending_energy", "strain_max"})
        c.push_back("m" + std::to_string(k) + "_" + n);
    return c;
  }
  // The relative area error of membrane 0 when t first reaches 1, 2, 5 and 10.
  void after_step(const Simulation& sim) override {
    if (D_.empty()) return;
    const double dt = sim.fluid().params().dt;
    for (int T : {1, 2, 5, 10})
      if (!area_at_.count(T) && sim.time() >= T - 0.5 * dt) {
        const Membrane& m = sim.membranes()[0].m;
        area_at_[T] = D_[0].measure(m.X).area / area0_[0] - 1.0;
      }
  }
  void sample(const Simulation& sim, std::vector<double>& row) override {
    std::vector<Measures> all;
    for (size_t k = 0; k < D_.size(); ++k) {
      const MembraneState& m = sim.membranes()[k];
      all.push_back(measure(sim, k));
      const MembraneShape& s = all.back().shape;
      for (double v : {s.rx, s.ry, s.cx, s.cy, s.area, s.area / area0_[k] - 1.0, s.energy, s.length,
                       static_cast<double>(m.last.iterations)})
        row.push_back(v);
    }
    for (const Measures& a : all)
      for (double v : {a.shape.moments.deformation(), a.shape.moments.theta, a.omega, a.bending, a.strain_max})
        row.push_back(v);
  }
  void summarize(const Simulation& sim, const Series&, nlohmann::json& j) const override {
    if (D_.empty()) return;
    const MembraneState& m0 = sim.membranes()[0];
    const Measures a = measure(sim, 0);
    const MembraneShape& s = a.shape;
    j["area"] = s.area;
    j["area_exact"] = area0_[0];
    j["area_relative_error"] = s.area / area0_[0] - 1.0;
    j["rx"] = s.rx;
    j["ry"] = s.ry;
    j["elastic_energy"] = s.energy;
    j["bending_energy"] = a.bending;
    j["deformation"] = s.moments.deformation();
    j["inclination"] = s.moments.theta;
    j["omega"] = a.omega;
    j["strain_max"] = a.strain_max;
    for (const auto& [T, e] : area_at_) j["area_relative_error_at"][std::to_string(T)] = e;
    j["marker_iterations_last"] = m0.last.iterations;
    if (m0.updates > 0) j["marker_iterations_mean"] = static_cast<double>(m0.iterations) / m0.updates;
    if (m0.updates > 0) j["marker_interpolations_mean"] = static_cast<double>(m0.interpolations) / m0.updates;
  }
  // The areas at t = 0 and the errors already measured: a restarted run measures from the same start.
  nlohmann::json save() const override { return {{"area0", area0_}, {"area_at", area_at_}}; }
  void restore(const nlohmann::json& saved) override {
    if (saved.is_null()) return;
    area0_ = saved.at("area0").get<std::vector<double>>();
    area_at_ = saved.at("area_at").get<std::map<int, double>>();
  }

 private:
  struct Measures {
    MembraneShape shape;
    double omega = 0, bending = 0, strain_max = 0;
  };
  Measures measure(const Simulation& sim, size_t k) const {
    const MembraneState& m = sim.membranes()[k];
    Measures a;
    a.shape = D_[k].measure(m.m.X);
    E_[k].compute(m.m.X, f_, T_);  // the law's energy and stretch of these markers
    const MembraneEnergy e = E_[k].energy();
    a.shape.energy = e.total();
    a.bending = e.bending;
    const KnotGeometry& g = E_[k].geometry();
    for (int i = 0; i < m.m.nb(); ++i)
      a.strain_max = std::max(a.strain_max, std::fabs(g.norm[i] / m.m.ref.a(i) - 1.0));
    // The markers' mean angular velocity about the centroid: the tank-treading frequency of a steady
    // shape. U^{n+1}(X^{n+1}) as the marker update left it, or interpolated now.
    if (m.fixed) return a;
    const Mat2* U = sim.next_marker_velocity(k);
    if (!U) {
      U_.resize(m.m.nb(), 2);  // (the interpolations write into the caller's storage)
      sim.marker_velocity(m.m.X, U_);
      U = &U_;
    }
    a.omega = mean_angular_velocity(m.m.X, *U, Eigen::Vector2d(a.shape.cx, a.shape.cy));
    return a;
  }

  mutable std::vector<MembraneDiagnostics> D_;  // workspace of the measurements
  mutable std::vector<MembraneForce> E_;
  mutable Mat2 f_, U_;
  mutable Vec T_;
  std::vector<double> area0_;
  std::map<int, double> area_at_;
};

}  // namespace

std::unique_ptr<Analysis> membrane_shapes(const Simulation& sim) { return std::make_unique<MembraneShapes>(sim); }

}  // namespace sphib
