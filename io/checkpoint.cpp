#include "io/checkpoint.hpp"

#include <hdf5.h>

#include <map>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "sphib_version.hpp"

namespace sphib {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("checkpoint " + path + ": " + what);
}

// Closes an HDF5 handle at scope exit.
struct H {
  hid_t id;
  herr_t (*close)(hid_t);
  ~H() { if (id >= 0) close(id); }
};

void write_matrix(hid_t loc, const std::string& name, const Eigen::MatrixXd& m, const std::string& path) {
  // Row-major on disk (rows x cols), as h5py shows it.
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r = m;
  hsize_t dims[2] = {static_cast<hsize_t>(m.rows()), static_cast<hsize_t>(m.cols())};
  H space{H5Screate_simple(2, dims, nullptr), H5Sclose};
  H d{H5Dcreate2(loc, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
  if (d.id < 0 || H5Dwrite(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, r.data()) < 0)
    fail(path, "cannot write " + name);
}

Eigen::MatrixXd read_matrix(hid_t loc, const std::string& name, const std::string& path) {
  H d{H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (d.id < 0) fail(path, "no dataset " + name);
  H space{H5Dget_space(d.id), H5Sclose};
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space.id) != 2) fail(path, name + " is not a matrix");
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r(dims[0], dims[1]);
  if (H5Dread(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, r.data()) < 0) fail(path, "cannot read " + name);
  return r;
}

void write_text(hid_t loc, const std::string& name, const std::string& value, const std::string& path) {
  H type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, value.size() + 1);
  H space{H5Screate(H5S_SCALAR), H5Sclose};
  H a{H5Acreate2(loc, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  if (a.id < 0 || H5Awrite(a.id, type.id, value.c_str()) < 0) fail(path, "cannot write attribute " + name);
}

std::string read_text(hid_t attr) {
  H type{H5Aget_type(attr), H5Tclose};
  std::string s(H5Tget_size(type.id), '\0');
  H mem{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(mem.id, s.size());
  H5Aread(attr, mem.id, s.data());
  return s.c_str();
}

// Keys that say how long to run and what to write; a restart may change them.
bool may_differ(const std::string& key) {
  return key.rfind("time.end", 0) == 0 || key.rfind("time.max_steps", 0) == 0 || key.rfind("output.", 0) == 0 ||
         key == "title";
}

}  // namespace

void write_checkpoint(const std::string& path, const Simulation& sim,
                      const std::vector<std::pair<std::string, std::string>>& scene) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string part = part_path(path);
  {
    H f{H5Fcreate(part.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
    if (f.id < 0) fail(path, "cannot create " + part);
    write_text(f.id, "sphib_version", SPHIB_VERSION, path);
    H sc{H5Gcreate2(f.id, "scene", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    for (const auto& [k, v] : scene) write_text(sc.id, k, v, path);
    H fl{H5Gcreate2(f.id, "fluid", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    for (const auto& [k, v] : sim.fluid().state()) write_matrix(fl.id, k, v, path);
    H mg{H5Gcreate2(f.id, "membranes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    for (size_t k = 0; k < sim.membranes().size(); ++k)
      write_matrix(mg.id, std::to_string(k), sim.membranes()[k].m.X, path);
    bool history = !sim.membranes().empty();
    for (const auto& m : sim.membranes()) history &= m.fixed || m.U_n_known;
    if (history) {  // U^n(X^n) of the last step: the marker predictor's U^{n-1} after the restart
      H vg{H5Gcreate2(f.id, "marker_velocities", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
      for (size_t k = 0; k < sim.membranes().size(); ++k) {
        if (sim.membranes()[k].fixed) continue;
        write_matrix(vg.id, std::to_string(k), sim.membranes()[k].U_n, path);
        // the next step's U^n(X^n), as the last marker update left it (linearised: not an interpolation)
        if (const Mat2* U = sim.next_marker_velocity(k)) write_matrix(vg.id, std::to_string(k) + "_next", *U, path);
      }
    }
    if (H5Fflush(f.id, H5F_SCOPE_GLOBAL) < 0) fail(path, "cannot flush (disk full?)");
  }
  commit_part(part, path);
}

Checkpoint read_checkpoint(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  H f{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  if (f.id < 0) fail(path, "cannot open it as HDF5");
  Checkpoint c;
  {
    H a{H5Aopen(f.id, "sphib_version", H5P_DEFAULT), H5Aclose};
    if (a.id < 0) fail(path, "not a sphib checkpoint (no sphib_version)");
    c.version = read_text(a.id);
  }
  H sc{H5Gopen2(f.id, "scene", H5P_DEFAULT), H5Gclose};
  if (sc.id < 0) fail(path, "no scene group");
  H5O_info_t info;
  H5Oget_info(sc.id, &info);
  for (hsize_t k = 0; k < info.num_attrs; ++k) {
    H a{H5Aopen_by_idx(sc.id, ".", H5_INDEX_CRT_ORDER, H5_ITER_INC, k, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
    if (a.id < 0) {  // creation order not tracked: by name
      H b{H5Aopen_by_idx(sc.id, ".", H5_INDEX_NAME, H5_ITER_INC, k, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
      char name[512];
      H5Aget_name(b.id, sizeof name, name);
      c.scene.emplace_back(name, read_text(b.id));
      continue;
    }
    char name[512];
    H5Aget_name(a.id, sizeof name, name);
    c.scene.emplace_back(name, read_text(a.id));
  }
  H fl{H5Gopen2(f.id, "fluid", H5P_DEFAULT), H5Gclose};
  if (fl.id < 0) fail(path, "no fluid group");
  H5G_info_t gi;
  H5Gget_info(fl.id, &gi);
  for (hsize_t k = 0; k < gi.nlinks; ++k) {
    char name[512];
    H5Lget_name_by_idx(fl.id, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT);
    c.fluid.emplace_back(name, read_matrix(fl.id, name, path));
  }
  H mg{H5Gopen2(f.id, "membranes", H5P_DEFAULT), H5Gclose};
  if (mg.id >= 0) {
    H5Gget_info(mg.id, &gi);
    for (hsize_t k = 0; k < gi.nlinks; ++k) c.markers.push_back(read_matrix(mg.id, std::to_string(k), path));
  }
  if (H5Lexists(f.id, "marker_velocities", H5P_DEFAULT) > 0) {
    H vg{H5Gopen2(f.id, "marker_velocities", H5P_DEFAULT), H5Gclose};
    c.marker_velocities.resize(c.markers.size());
    c.marker_velocities_next.resize(c.markers.size());
    for (size_t k = 0; k < c.markers.size(); ++k) {
      const std::string name = std::to_string(k);
      if (H5Lexists(vg.id, name.c_str(), H5P_DEFAULT) > 0) c.marker_velocities[k] = read_matrix(vg.id, name, path);
      if (H5Lexists(vg.id, (name + "_next").c_str(), H5P_DEFAULT) > 0)
        c.marker_velocities_next[k] = read_matrix(vg.id, name + "_next", path);
    }
  }
  return c;
}

void restore_checkpoint(const Checkpoint& c, const std::string& path,
                        const std::vector<std::pair<std::string, std::string>>& scene, Simulation& sim) {
  if (c.version != SPHIB_VERSION)
    fail(path, "written by sphib " + c.version + ", this is " + SPHIB_VERSION);
  std::map<std::string, std::string> saved(c.scene.begin(), c.scene.end()), now(scene.begin(), scene.end());
  for (const auto& [k, v] : now)
    if (!may_differ(k) && (!saved.count(k) || saved[k] != v))
      fail(path, "its scene does not match: " + k + " = " + (saved.count(k) ? saved[k] : "(unset)") +
                     " in the checkpoint, " + v + " now");
  for (const auto& [k, v] : saved)
    if (!may_differ(k) && !now.count(k)) fail(path, "its scene does not match: " + k + " = " + v + " is not set now");
  if (c.markers.size() != sim.membranes().size()) fail(path, "it has a different number of membranes");
  sim.fluid().restore(c.fluid);
  for (size_t k = 0; k < c.markers.size(); ++k) sim.set_markers(k, c.markers[k]);
  for (size_t k = 0; k < c.marker_velocities.size(); ++k)
    if (c.marker_velocities[k].rows() > 0)
      sim.set_marker_history(k, c.marker_velocities[k],
                             c.marker_velocities_next[k].rows() > 0 ? &c.marker_velocities_next[k] : nullptr);
}

}  // namespace sphib
