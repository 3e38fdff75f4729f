#pragma once
// HDF5 output of a run, with an XDMF index that ParaView's default reader (Xdmf3) opens.
//
// File layout (written as `path`.part, renamed to `path` by close()):
//   /                         attributes: RunAttributes (text: UTF-8 strings, numbers: double)
//   /snapshots/000042         one group per output time (index of the snapshot, not the step);
//                             attributes time (double), step (int32)
//     x, y                    (N) double   particle positions
//     <scalar>                (N) double   each particle scalar, e.g. u, v, p, phi
//     velocity                (N x 3) double  (u, v, 0), when u and v are written: XDMF vectors need 3
//     xy                      (N x 2) double  positions again, moving particles only (XDMF geometry XY)
//     membrane_k/X, f         (nb x 2) double  marker positions, force density
//     membrane_k/T            (nb) double      tension
//     membrane_k/conn         (1 x nb+1) int32 0..nb-1,0: the closed polyline for XDMF
//     membrane_k/f3           (nb x 3) double  f with a zero z column
//   /diagnostics/<name>       (rows x cols) double; attribute columns (strings)
//   /xdmf/lattice_<nx>x<ny>/xy     (N x 2) double   the fixed lattice's positions (once)
//   /xdmf/lattice_<nx>x<ny>/quads  ((nx-1)(ny-1) x 4) int32  quadrilaterals joining neighbours
//   /xdmf/vertices_<N>        (N x 1) int32 0..N-1: moving particles' vertex connectivity
// close() then writes two XDMF files beside it, referencing the final file name relatively, each a
// temporal collection of one kind of grid (ParaView's default reader, Xdmf3ReaderS, merges the
// grids of one time into one partitioned dataset: kinds or arrays that differ break its colouring):
//   <stem>.xdmf            the fluid: a fixed lattice (EPSPH) as a mesh of quadrilaterals joining
//                          neighbouring particles (ParaView draws it as a coloured surface, and
//                          contours and stream-traces it); moving particles (LPSPH, WCSPH) as vertices;
//   <stem>_membranes.xdmf  every membrane as a closed polyline with f (vector) and T (only with membranes).
// (Xdmf3 reads no X_Y geometry, and crashed ParaView 5.11 on the former particle topology: hence xy.)
// Every HDF5 failure throws WriteError (io/atomic_file.hpp) naming the file, the operation and
// HDF5's cause. HDF5 (1.10) cannot close a file after a failed write of its metadata (and crashes at
// exit trying), so the writer reserves the disk space of each write before it makes it: a full disk
// is met by the reservation, with the file still closable, its earlier snapshots intact.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "fluid/common/lattice.hpp"
#include "fluid/common/types.hpp"
#include "io/atomic_file.hpp"

namespace sphib {

// Scene parameters and library version, stored as attributes of the root group.
struct RunAttributes {
  std::vector<std::pair<std::string, std::string>> text;
  std::vector<std::pair<std::string, double>> numbers;
};

// One membrane at one output time; the pointers are read during write_snapshot only.
struct MembraneSnapshot {
  const Mat2* X;  // marker positions (nb x 2)
  const Mat2* f;  // marker force density (nb x 2)
  const Vec* T;   // tension (nb)
};

// Reserves disk space for `bytes` more data (and HDF5's metadata for them) in the open HDF5 file
// `file` (a hid_t) at `path`: a write of them cannot then fail for want of space. Throws WriteError.
void reserve_hdf5_space(std::int64_t file, double bytes, const std::string& path);

// A text attribute of the root group of the HDF5 file at path ("" if the file does not open or has
// no such attribute), e.g. the run_id of a run's output.
std::string root_text_attribute(const std::string& path, const std::string& name);

// The file at path opens read-only and every /snapshots group in it reads (its step attribute, its x):
// a run may continue it (a killed run's .part may not).
bool snapshots_readable(const std::string& path);

class Hdf5Writer {
 public:
  // Creates path.part (truncating it). Disables HDF5's automatic error printing process-wide.
  Hdf5Writer(std::string path, const RunAttributes& attrs);
  // Continues the file of an earlier part of the same run: `source` (path, or path.part of a killed
  // run) copied to path.part (opened in place if it is path.part), keeping its snapshots of steps
  // before `resume_step` (later ones are written again), the root attributes replaced by attrs;
  // /diagnostics and /xdmf are written again by close(). path stays as it was until close().
  Hdf5Writer(std::string path, const RunAttributes& attrs, const std::string& source, long resume_step);
  ~Hdf5Writer();  // close() if not closed; errors go to stderr
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  // Appends /snapshots/<index> and flushes the file. Sizes must match x.rows() (particle
  // scalars) and X.rows() (f, T); scalar names are unique, not x, y, xy, velocity or membrane_*,
  // without '/'. `lattice`: the particles sit on it (x is its x, index i + nx j), so the XDMF
  // shows them as a structured mesh; nullptr: moving particles, shown as vertices.
  void write_snapshot(int step, double t, const Mat2& x,
                      const std::vector<std::pair<std::string, const Vec*>>& particle_scalars,
                      const std::vector<MembraneSnapshot>& membranes, const Lattice* lattice = nullptr);

  // /diagnostics/<name>: every row has columns.size() values. Call once per name.
  void write_series(const std::string& name, const std::vector<std::string>& columns,
                    const std::vector<std::vector<double>>& rows);

  // Closes the HDF5 file, renames path.part -> path, writes the XDMF (tmp + rename). Idempotent.
  // After a failed write it only closes (what HDF5 still can): path.part stays, incomplete by name.
  void close();
  // The same, but leaves path.part and the XDMF files' .part for publish_all (io/atomic_file.hpp) to
  // rename with the run's other files; returns them. Throws WriteError (every file stays .part).
  std::vector<PartFile> close_to_parts();
  // Closes without completing: path.part stays (a run that could not write its output). Idempotent.
  void abandon();

  const std::string& path() const { return path_; }
  std::string xdmf_path() const;            // the fluid's XDMF: path with extension .xdmf
  std::string membranes_xdmf_path() const;  // the membranes' XDMF: <stem>_membranes.xdmf
  int num_snapshots() const { return static_cast<int>(snapshots_.size()); }  // complete ones

 private:
  struct SnapshotInfo {  // what the XDMF needs to know about one written snapshot
    std::string group;   // e.g. /snapshots/000042
    double t = 0;
    long n = 0;                        // particles
    std::vector<std::string> scalars;  // particle scalar names
    bool velocity = false;             // a velocity (N x 3) dataset
    std::string lattice;               // on a fixed lattice: the /xdmf group of its mesh; "": moving
    bool lattice_pending = false;      // resumed from an earlier file: on the lattice of the next snapshot
    long cells = 0;                    // quadrilaterals of that mesh
    std::vector<long> nb;              // markers per membrane
  };

  void require_open(const char* what) const;
  std::string xdmf_text(bool membranes) const;
  void reserve(double bytes);
  void write_snapshot_data(SnapshotInfo& info, int step, double t, const Mat2& x,
                           const std::vector<std::pair<std::string, const Vec*>>& particle_scalars,
                           const std::vector<MembraneSnapshot>& membranes, const Vec* u, const Vec* v);  // disk space for the next `bytes` of data and their metadata
  void resume_snapshots(long resume_step);
  template <class F>
  void writing(F&& write);  // runs a write; a failure marks the file broken (never completed)

  std::string path_;
  std::string part_;
  std::int64_t file_ = -1;  // hid_t
  int next_index_ = 0;      // of the next /snapshots group
  bool broken_ = false;     // a write failed: HDF5's state is not trusted, the file is never completed
  std::vector<SnapshotInfo> snapshots_;
  std::vector<std::pair<std::string, Lattice>> lattices_;  // the meshes written by close()
};

}  // namespace sphib
