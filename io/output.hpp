#pragma once
// What a run writes as it goes: HDF5 snapshots (+ XDMF) every output.interval, the diagnostics
// CSV row by row, checkpoints every output.checkpoint_interval; at the end the last good state,
// the whole series into the HDF5 file, and every file closed (renamed from .part). A run that
// cannot write abandons its files: the .part files stay, the files completed before stay intact.
#include <memory>
#include <string>
#include <vector>

#include "io/csv_writer.hpp"
#include "io/hdf5_writer.hpp"
#include "io/scene.hpp"

namespace sphib {

// Where a run writes, under which run id, and the earlier part of the same run it continues.
struct OutputTarget {
  std::string dir;
  std::string run_id;
  std::string resume_from;  // a restart into its own directory: the earlier output.h5 (or .part); "": a new file
};

class RunOutput {
 public:
  // Creates dir/output.h5.part (or continues target.resume_from, keeping its snapshots before the
  // current step) and dir/diagnostics.csv.part holding the series so far, with the scene as attributes.
  RunOutput(const Scene& scene, const Simulation& sim, const Observers& observers, const OutputTarget& target);
  ~RunOutput();  // neither finished nor abandoned (an exception on its way out): abandons

  void row(const std::vector<double>& values) { csv_->row(values); }
  bool due(long step) const;            // a snapshot or a checkpoint falls on this step
  bool snapshot_due(long step) const;   // a snapshot (output.interval or output.times) falls on this step
  void write_due(const Simulation& sim);  // the snapshot and checkpoint due now
  void snapshot(const Simulation& sim);
  void checkpoint(const Simulation& sim);  // dir/checkpoint.h5 with the observers' series and state
  // The last good state (none after a fault: a faulty state is never written), the series, closed
  // but still .part; then the checkpoint of that state.
  void finish(const Simulation& sim, bool good);
  // After finish: writes the summary (JSON text) and renames every file of the run to its final
  // name together, summary.json last (publish_all: a failure leaves them all .part).
  void publish(const std::string& summary);
  void abandon();  // closes without completing (after a write error): the .part files stay

  // The last checkpoint written by this run (t < 0: none).
  double checkpoint_time() const { return checkpoint_time_; }
  std::string checkpoint_path() const { return checkpoint_path_; }

 private:
  const Scene& scene_;
  const Observers& observers_;
  std::string run_id_;
  std::unique_ptr<Hdf5Writer> h5_;
  std::unique_ptr<CsvWriter> csv_;
  std::string dir_;
  std::vector<PartFile> parts_;  // finished, not yet published
  std::string checkpoint_path_;
  std::string scene_file_;  // kept in checkpoints
  double checkpoint_time_ = -1;
  long snapshot_every_ = 0, checkpoint_every_ = 0;  // steps (0: only the first and last snapshot, the last checkpoint)
  bool done_ = false;
  std::vector<long> snapshot_steps_;                 // output.times as steps
  Vec u_, v_, surface_;  // velocity components and free-surface flags as particle scalars
};

}  // namespace sphib
