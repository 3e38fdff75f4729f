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
// Every HDF5 failure throws std::runtime_error naming the file, the operation and HDF5's cause.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "fluid/lattice.hpp"
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
  void close();

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
    long cells = 0;                    // quadrilaterals of that mesh
    std::vector<long> nb;              // markers per membrane
  };

  void require_open(const char* what) const;
  std::string xdmf_text(bool membranes) const;

  std::string path_;
  std::string part_;
  std::int64_t file_ = -1;  // hid_t
  int next_index_ = 0;      // of the next /snapshots group
  std::vector<SnapshotInfo> snapshots_;
  std::vector<std::pair<std::string, Lattice>> lattices_;  // the meshes written by close()
};

}  // namespace sphib
