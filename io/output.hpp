#pragma once
// What a run writes as it goes: HDF5 snapshots (+ XDMF) every output.interval, the diagnostics
// CSV row by row, checkpoints every output.checkpoint_interval; at the end the last good state,
// the whole series into the HDF5 file, and every file closed (renamed from .part).
#include <string>
#include <vector>

#include "io/csv_writer.hpp"
#include "io/hdf5_writer.hpp"
#include "io/scene.hpp"

namespace sphib {

class RunOutput {
 public:
  // Creates dir/output.h5.part and dir/diagnostics.csv.part with the scene as attributes.
  RunOutput(const Scene& scene, const Simulation& sim, const std::vector<std::string>& columns, const std::string& dir);

  void row(const std::vector<double>& values) { csv_.row(values); }
  bool due(long step) const;            // a snapshot or a checkpoint falls on this step
  bool snapshot_due(long step) const;   // a snapshot (output.interval or output.times) falls on this step
  void write_due(const Simulation& sim);  // the snapshot and checkpoint due now
  void snapshot(const Simulation& sim);
  // The last good state (none after a fault: a faulty state is never written), the series, close.
  void finish(const Simulation& sim, const std::vector<std::string>& columns,
              const std::vector<std::vector<double>>& series, bool good);

 private:
  const Scene& scene_;
  Hdf5Writer h5_;
  CsvWriter csv_;
  std::string checkpoint_path_;
  long snapshot_every_ = 0, checkpoint_every_ = 0;  // steps (0: only the first and last snapshot, the last checkpoint)
  std::vector<long> snapshot_steps_;                 // output.times as steps
  Vec u_, v_, surface_;  // velocity components and free-surface flags as particle scalars
};

}  // namespace sphib
