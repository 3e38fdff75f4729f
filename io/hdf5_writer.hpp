#pragma once
// HDF5 output of a run, with an XDMF index so ParaView opens particles and membranes directly.
//
// File layout (written as `path`.part, renamed to `path` by close()):
//   /                         attributes: RunAttributes (text: UTF-8 strings, numbers: double)
//   /snapshots/000042         one group per output time (index of the snapshot, not the step);
//                             attributes time (double), step (int32)
//     x, y                    (N) double   particle positions
//     <scalar>                (N) double   each particle scalar, e.g. u, v, p, phi
//     membrane_k/X, f         (nb x 2) double  marker positions, force density
//     membrane_k/T            (nb) double      tension
//     membrane_k/conn         (1 x nb+1) int32 0..nb-1,0: the closed polyline for XDMF
//     membrane_k/f3           (nb x 3) double  f with a zero z column: XDMF vectors need 3
//   /diagnostics/<name>       (rows x cols) double; attribute columns (strings)
//   /xdmf/vertices_<N>        (N x 1) int32 0..N-1: particle Polyvertex connectivity
// close() then writes `path` with extension .xdmf (a temporal collection of spatial
// collections: particles + membrane_k), referencing the final file name relatively.
// Every HDF5 failure throws std::runtime_error naming the file, the operation and HDF5's cause.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "fluid/types.hpp"

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

class Hdf5Writer {
 public:
  // Creates path.part (truncating it). Disables HDF5's automatic error printing process-wide.
  Hdf5Writer(std::string path, const RunAttributes& attrs);
  ~Hdf5Writer();  // close() if not closed; errors go to stderr
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  // Appends /snapshots/<index> and flushes the file. Sizes must match x.rows() (particle
  // scalars) and X.rows() (f, T); scalar names are unique, not x, y or membrane_*, without '/'.
  void write_snapshot(int step, double t, const Mat2& x,
                      const std::vector<std::pair<std::string, const Vec*>>& particle_scalars,
                      const std::vector<MembraneSnapshot>& membranes);

  // /diagnostics/<name>: every row has columns.size() values. Call once per name.
  void write_series(const std::string& name, const std::vector<std::string>& columns,
                    const std::vector<std::vector<double>>& rows);

  // Closes the HDF5 file, renames path.part -> path, writes the XDMF (tmp + rename). Idempotent.
  void close();

  const std::string& path() const { return path_; }
  std::string xdmf_path() const;  // path with extension .xdmf
  int num_snapshots() const { return static_cast<int>(snapshots_.size()); }  // complete ones

 private:
  struct SnapshotInfo {  // what the XDMF needs to know about one written snapshot
    std::string group;   // e.g. /snapshots/000042
    double t;
    long n;                            // particles
    std::vector<std::string> scalars;  // particle scalar names
    std::vector<long> nb;              // markers per membrane
  };

  void require_open(const char* what) const;
  std::string xdmf_text() const;

  std::string path_;
  std::string part_;
  std::int64_t file_ = -1;  // hid_t
  int next_index_ = 0;      // of the next /snapshots group
  std::vector<SnapshotInfo> snapshots_;
};

}  // namespace sphib
