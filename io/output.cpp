#include "io/output.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "io/checkpoint.hpp"
#include "io/scene_checks.hpp"
#include "sphib_version.hpp"

namespace sphib {

namespace {

// The scene, the library version and the derived lengths, as the HDF5 file's root attributes.
RunAttributes attributes(const Scene& scene, const Simulation& sim) {
  const FluidSolver& fl = sim.fluid();
  RunAttributes a;
  a.text.emplace_back("sphib_version", SPHIB_VERSION);
  a.text.emplace_back("scene", scene.path);
  for (const auto& [k, v] : scene.resolved) a.text.emplace_back(k, v);
  a.numbers.emplace_back("derived.h", fl.h());
  a.numbers.emplace_back("derived.dx", fl.lattice().dx);
  a.numbers.emplace_back("derived.dy", fl.lattice().dy);
  if (!scene.membranes.empty()) {
    a.numbers.emplace_back("derived.membrane_radius", scene.membranes[0].radius);
    a.numbers.emplace_back("derived.membrane_r0", scene.membranes[0].r0);
    a.numbers.emplace_back("derived.membrane_h_star", sim.membranes()[0].h_star);
  }
  return a;
}

// The scene's path made absolute ("" if it has none): a restart from the checkpoint alone takes
// observe.reference_dir relative to it.
std::string scene_file(const Scene& scene) {
  std::error_code ec;
  if (scene.path.empty()) return "";
  const std::filesystem::path p = std::filesystem::absolute(scene.path, ec);
  return ec ? "" : p.lexically_normal().string();
}

// Steps between outputs (0: none); an interval longer than any run never falls due.
long steps_per(double interval, double dt) {
  if (!(interval > 0)) return 0;
  const double k = std::round(interval / dt);
  return k > kMaxSteps ? kMaxSteps + 1 : std::max<long>(1, static_cast<long>(k));
}

std::unique_ptr<Hdf5Writer> open_hdf5(const Scene& scene, const Simulation& sim, const OutputTarget& t) {
  RunAttributes a = attributes(scene, sim);
  a.text.emplace_back("run_id", t.run_id);
  const std::string path = t.dir + "/output.h5";
  if (t.resume_from.empty()) return std::make_unique<Hdf5Writer>(path, a);
  return std::make_unique<Hdf5Writer>(path, a, t.resume_from, sim.steps());
}

}  // namespace

RunOutput::RunOutput(const Scene& scene, const Simulation& sim, const Observers& observers, const OutputTarget& target)
    : scene_(scene),
      observers_(observers),
      run_id_(target.run_id),
      h5_(open_hdf5(scene, sim, target)),
      dir_(target.dir),
      checkpoint_path_(target.dir + "/checkpoint.h5"),
      scene_file_(scene_file(scene)),
      snapshot_every_(steps_per(scene.output_interval, sim.fluid().params().dt)),
      checkpoint_every_(steps_per(scene.checkpoint_interval, sim.fluid().params().dt)),
      u_(sim.fluid().size()),
      v_(sim.fluid().size()) {
  for (double t : scene.output_times) snapshot_steps_.push_back(std::lround(t / sim.fluid().params().dt));
  try {  // a failure leaves output.h5.part as it is: never completed under its final name
    csv_ = std::make_unique<CsvWriter>(target.dir + "/diagnostics.csv", observers.columns());
    for (const auto& r : observers.series().rows) csv_->row(r);  // a restart's series so far
  } catch (...) {
    h5_->abandon();
    if (csv_) csv_->abandon();
    throw;
  }
}

RunOutput::~RunOutput() { abandon(); }

bool RunOutput::due(long step) const {
  return snapshot_due(step) || (checkpoint_every_ && step % checkpoint_every_ == 0);
}

bool RunOutput::snapshot_due(long step) const {
  return (snapshot_every_ && step % snapshot_every_ == 0) ||
         std::find(snapshot_steps_.begin(), snapshot_steps_.end(), step) != snapshot_steps_.end();
}

void RunOutput::write_due(const Simulation& sim) {  // the restart point first: it matters more
  if (checkpoint_every_ && sim.steps() % checkpoint_every_ == 0) checkpoint(sim);
  if (snapshot_due(sim.steps())) snapshot(sim);
}

void RunOutput::checkpoint(const Simulation& sim) {
  write_checkpoint(checkpoint_path_, sim, scene_.resolved, run_id_, &observers_, scene_file_);
  checkpoint_time_ = sim.time();
}

void RunOutput::snapshot(const Simulation& sim) {
  const FluidSolver& fl = sim.fluid();
  u_ = fl.u().col(0);
  v_ = fl.u().col(1);
  std::vector<std::pair<std::string, const Vec*>> fields;
  for (const auto& f : scene_.fields) {
    if (f == "u") fields.emplace_back("u", &u_);
    if (f == "v") fields.emplace_back("v", &v_);
    if (f == "p") fields.emplace_back("p", &fl.p());
    if (f == "phi") fields.emplace_back("phi", &fl.phi());
    if (f == "surface") {  // 1 on the free surface (0 everywhere without one)
      const std::vector<char>* flags = fl.surface();
      surface_ = Vec::Zero(fl.size());
      for (int i = 0; flags && i < fl.size(); ++i) surface_[i] = (*flags)[i];
      fields.emplace_back("surface", &surface_);
    }
  }
  std::vector<MembraneSnapshot> ms;
  for (const auto& m : sim.membranes()) ms.push_back({&m.m.X, &m.f, &m.T});
  h5_->write_snapshot(static_cast<int>(fl.steps()), fl.time(), fl.x(), fields, ms,
                      fl.particles_move() ? nullptr : &fl.lattice());  // a fixed lattice: a quadrilateral mesh
}

void RunOutput::finish(const Simulation& sim, bool good) {
  if (good) snapshot(sim);
  h5_->write_series("diagnostics", observers_.columns(), observers_.series().rows);
  done_ = true;  // from here on, what is closed stays .part unless published
  try {
    parts_ = h5_->close_to_parts();
  } catch (...) {
    csv_->abandon();
    throw;
  }
  parts_.push_back(csv_->close_to_part());
  if (good && sim.steps() > 0) checkpoint(sim);
}

void RunOutput::publish(const std::string& summary) {
  std::vector<PartFile> all = parts_;
  all.push_back(write_part(dir_ + "/summary.json", summary));
  publish_all(all);
  parts_.clear();
}

void RunOutput::abandon() {
  if (done_) return;
  done_ = true;
  h5_->abandon();
  csv_->abandon();
}

}  // namespace sphib
