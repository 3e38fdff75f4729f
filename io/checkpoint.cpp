#include "io/checkpoint.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <hdf5.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "io/digest.hpp"
#include "io/hdf5_writer.hpp"
#include "sphib_version.hpp"

namespace sphib {

bool restart_may_change(const std::string& key) {
  return key == "time.end" || key == "time.max_steps" || key.rfind("output.", 0) == 0 || key.rfind("limits.", 0) == 0 ||
         key == "title";
}

namespace {

// Layout (format 3):
//   bytes 0-511          the seal (an HDF5 user block, which HDF5 skips): "sphib checkpoint 3\n"
//                        "sha256 <64 hex digits>\n", then zeros; the digest is of every byte after it
//   /                    attributes sphib_version, checkpoint_format, scene_file (text)
//   /scene               one text attribute per resolved scene key
//   /fluid/<name>        FluidSolver::state(), each a matrix
//   /membranes/<k>       X of membrane k; /marker_velocities/<k> U^n(X^n) of the free ones
//   /run                 attributes run_id, analyses (JSON text); dataset series (rows x columns)
//                        with attribute columns (text array)
// Text is stored as variable-length UTF-8 strings: a 70 kB title or a 2 000-point membrane fit (a
// fixed-length attribute is limited to 64 kB).

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
  throw CheckpointError("checkpoint " + path + ": " + what);
}

[[noreturn]] void write_failed(const std::string& path, const std::string& what) {
  throw WriteError("checkpoint " + path + ": " + what);
}

constexpr long long kSealBytes = 512;  // the user block (HDF5 needs a power of two >= 512)
const std::string kSealMagic = "sphib checkpoint " + std::to_string(kCheckpointFormat) + "\n";

// A file descriptor closed at scope exit.
struct Fd {
  int fd;
  ~Fd() { if (fd >= 0) ::close(fd); }
};

// The seal a checkpoint of these bytes carries: the magic line, the digest line, zeros.
std::string seal_text(const std::string& digest) {
  std::string s = kSealMagic + "sha256 " + digest + "\n";
  s.resize(static_cast<size_t>(kSealBytes), '\0');
  return s;
}

// Why the file at path, open as fd, is not a sealed checkpoint whose bytes are those it was sealed
// with ("" if it is). Nothing of it is parsed as HDF5 before this holds.
std::string seal_problem(int fd, const std::string& path) {
  std::string head(static_cast<size_t>(kSealBytes), '\0');
  const ssize_t n = ::pread(fd, head.data(), head.size(), 0);
  if (n < 0) return std::string("cannot be read: ") + std::strerror(errno);
  const std::string hdf5_signature = "\x89HDF\r\n\x1a\n";
  if (n < kSealBytes || head.compare(0, kSealMagic.size(), kSealMagic) != 0) {
    if (head.compare(0, hdf5_signature.size(), hdf5_signature) == 0) return "unsealed HDF5";
    if (head.compare(0, 16, kSealMagic, 0, 16) == 0 && n >= kSealBytes)
      return "it is a checkpoint of another format (" + head.substr(0, head.find('\n')) + "; this sphib reads format " +
             std::to_string(kCheckpointFormat) + "): run the scene from the start";
    return "not a sphib checkpoint (no checkpoint seal" + std::string(n < kSealBytes ? ", and shorter than one" : "") + ")";
  }
  const std::string digest_line = "sha256 ";
  const size_t at = kSealMagic.size(), end = at + digest_line.size() + 64;
  if (head.compare(at, digest_line.size(), digest_line) != 0 || head[end] != '\n' ||
      head.find_first_not_of('\0', end + 1) != std::string::npos)
    return "damaged: its seal (the first 512 bytes) is not as written";
  const std::string sealed = head.substr(at + digest_line.size(), 64);
  std::string now;
  try {
    now = sha256_file_hex(fd, kSealBytes, path);
  } catch (const std::exception& e) {
    return e.what();
  }
  if (now != sealed)
    return "damaged: its SHA-256 (" + now.substr(0, 16) + "...) is not the one sealed in it when it was written (" +
           sealed.substr(0, 16) + "...): a changed bit, a truncated or an edited file cannot be trusted";
  return "";
}

// Closes an HDF5 handle at scope exit.
struct H {
  hid_t id;
  herr_t (*close)(hid_t);
  ~H() { if (id >= 0) close(id); }
};

H text_type() {
  H t{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(t.id, H5T_VARIABLE);
  H5Tset_cset(t.id, H5T_CSET_UTF8);
  return t;
}

void write_matrix(hid_t loc, const std::string& name, const Eigen::MatrixXd& m, const std::string& path) {
  // Row-major on disk (rows x cols), as h5py shows it.
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r = m;
  hsize_t dims[2] = {static_cast<hsize_t>(m.rows()), static_cast<hsize_t>(m.cols())};
  H space{H5Screate_simple(2, dims, nullptr), H5Sclose};
  H d{H5Dcreate2(loc, name.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
  if (d.id < 0 || (r.size() > 0 && H5Dwrite(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, r.data()) < 0))
    write_failed(path, "cannot write " + name);
}

Eigen::MatrixXd read_matrix(hid_t loc, const std::string& name, const std::string& path) {
  H d{H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (d.id < 0) refuse(path, "no dataset " + name);
  H space{H5Dget_space(d.id), H5Sclose};
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space.id) != 2) refuse(path, name + " is not a matrix");
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r(dims[0], dims[1]);
  if (r.size() > 0 && H5Dread(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, r.data()) < 0)
    refuse(path, "cannot read " + name);
  return r;
}

void write_text(hid_t loc, const std::string& name, const std::string& value, const std::string& path) {
  H type = text_type();
  H space{H5Screate(H5S_SCALAR), H5Sclose};
  H a{H5Acreate2(loc, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  const char* p = value.c_str();
  if (a.id < 0 || H5Awrite(a.id, type.id, &p) < 0) write_failed(path, "cannot write attribute " + name);
}

void write_texts(hid_t loc, const std::string& name, const std::vector<std::string>& v, const std::string& path) {
  H type = text_type();
  const hsize_t n = v.size();
  H space{H5Screate_simple(1, &n, nullptr), H5Sclose};
  H a{H5Acreate2(loc, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  std::vector<const char*> p;
  for (const auto& s : v) p.push_back(s.c_str());
  if (a.id < 0 || (n > 0 && H5Awrite(a.id, type.id, p.data()) < 0)) write_failed(path, "cannot write attribute " + name);
}

// The strings of a text attribute (scalar or array, variable-length).
std::vector<std::string> read_texts(hid_t attr, const std::string& path, const std::string& name) {
  H type{H5Aget_type(attr), H5Tclose};
  H space{H5Aget_space(attr), H5Sclose};
  const hssize_t n = H5Sget_simple_extent_npoints(space.id);
  if (H5Tget_class(type.id) != H5T_STRING || H5Tis_variable_str(type.id) <= 0 || n < 0)
    refuse(path, "attribute " + name + " is not variable-length text (an older checkpoint format?)");
  std::vector<char*> p(static_cast<size_t>(n), nullptr);
  H mem = text_type();
  if (n > 0 && H5Aread(attr, mem.id, p.data()) < 0) refuse(path, "cannot read attribute " + name);
  std::vector<std::string> out;
  for (char* s : p) out.emplace_back(s ? s : "");
  if (n > 0) H5Dvlen_reclaim(mem.id, space.id, H5P_DEFAULT, p.data());
  return out;
}

std::string read_text(hid_t loc, const std::string& name, const std::string& path) {
  H a{H5Aopen(loc, name.c_str(), H5P_DEFAULT), H5Aclose};
  if (a.id < 0) refuse(path, "no attribute " + name);
  const auto v = read_texts(a.id, path, name);
  if (v.size() != 1) refuse(path, "attribute " + name + " is not one text");
  return v[0];
}

double checkpoint_bytes(const Simulation& sim, const std::vector<std::pair<std::string, std::string>>& scene,
                        const Observers* observers) {
  double b = 0;
  for (const auto& [k, v] : sim.fluid().state()) b += 8.0 * v.size() + 4096;
  for (const auto& m : sim.membranes())  // X, U^n, U^{n+1}; the stiff-force filter's history (12 reals by mode)
    b += 48.0 * m.m.X.rows() + 12288 + (m.filter ? 48.0 * m.m.X.rows() + 4096 : 0.0);
  for (const auto& [k, v] : scene) b += 128.0 + k.size() + v.size();
  if (observers) b += 8.0 * observers->series().rows.size() * observers->columns().size() + 65536;
  return b;
}

void write_state(hid_t f, const Simulation& sim, const std::vector<std::pair<std::string, std::string>>& scene,
                 const std::string& scene_file, const std::string& path) {
  write_text(f, "sphib_version", SPHIB_VERSION, path);
  write_text(f, "checkpoint_format", std::to_string(kCheckpointFormat), path);
  write_text(f, "scene_file", scene_file, path);
  H sc{H5Gcreate2(f, "scene", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
  for (const auto& [k, v] : scene) write_text(sc.id, k, v, path);
  H fl{H5Gcreate2(f, "fluid", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
  for (const auto& [k, v] : sim.fluid().state()) write_matrix(fl.id, k, v, path);
  H mg{H5Gcreate2(f, "membranes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
  for (size_t k = 0; k < sim.membranes().size(); ++k) write_matrix(mg.id, std::to_string(k), sim.membranes()[k].m.X, path);
  bool history = !sim.membranes().empty();
  for (const auto& m : sim.membranes()) history &= m.fixed || m.U_n_known;
  if (history) {  // U^n(X^n) of the last step: the marker predictor's U^{n-1} after the restart
    H vg{H5Gcreate2(f, "marker_velocities", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    for (size_t k = 0; k < sim.membranes().size(); ++k) {
      if (sim.membranes()[k].fixed) continue;
      write_matrix(vg.id, std::to_string(k), sim.membranes()[k].U_n, path);
      // the next step's U^n(X^n), as the last marker update left it (linearised: not an interpolation)
      if (const Mat2* U = sim.next_marker_velocity(k)) write_matrix(vg.id, std::to_string(k) + "_next", *U, path);
    }
  }
  bool filters = false;  // the stiff-force filters' history (U^{n-1}, f~^{n-1}, G by mode)
  for (size_t k = 0; k < sim.membranes().size(); ++k) filters |= sim.stiff_filter_state(k).size() > 0;
  if (filters) {
    H sg{H5Gcreate2(f, "stiff_filter", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    for (size_t k = 0; k < sim.membranes().size(); ++k) {
      const Eigen::MatrixXd s = sim.stiff_filter_state(k);
      if (s.size() > 0) write_matrix(sg.id, std::to_string(k), s, path);
    }
  }
}

void write_run(hid_t f, const std::string& run_id, const Observers& observers, const std::string& path) {
  H rg{H5Gcreate2(f, "run", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
  write_text(rg.id, "run_id", run_id, path);
  write_text(rg.id, "analyses", observers.state().dump(), path);
  const Series& s = observers.series();
  Eigen::MatrixXd rows(static_cast<Eigen::Index>(s.rows.size()), static_cast<Eigen::Index>(s.columns.size()));
  for (size_t r = 0; r < s.rows.size(); ++r)
    for (size_t c = 0; c < s.columns.size(); ++c) rows(r, c) = s.rows[r][c];
  write_matrix(rg.id, "series", rows, path);
  H d{H5Dopen2(rg.id, "series", H5P_DEFAULT), H5Dclose};
  write_texts(d.id, "columns", s.columns, path);
}

void read_run(hid_t f, Checkpoint& c, const std::string& path) {
  H rg{H5Gopen2(f, "run", H5P_DEFAULT), H5Gclose};
  if (rg.id < 0) return;  // a checkpoint written outside a run (no record)
  c.run_id = read_text(rg.id, "run_id", path);
  try {
    c.analyses = nlohmann::json::parse(read_text(rg.id, "analyses", path));
  } catch (const nlohmann::json::exception&) {
    refuse(path, "its run record is damaged");
  }
  const Eigen::MatrixXd rows = read_matrix(rg.id, "series", path);
  H d{H5Dopen2(rg.id, "series", H5P_DEFAULT), H5Dclose};
  H a{H5Aopen(d.id, "columns", H5P_DEFAULT), H5Aclose};
  if (a.id < 0) refuse(path, "no series columns");
  c.series.columns = read_texts(a.id, path, "columns");
  if (static_cast<size_t>(rows.cols()) != c.series.columns.size() && rows.rows() > 0) refuse(path, "its series is damaged");
  for (Eigen::Index r = 0; r < rows.rows(); ++r) {
    std::vector<double> row(static_cast<size_t>(rows.cols()));
    for (Eigen::Index k = 0; k < rows.cols(); ++k) row[k] = rows(r, k);
    c.series.rows.push_back(std::move(row));
  }
}

// Every attribute of a group, as (name, text).
std::vector<std::pair<std::string, std::string>> read_group_texts(hid_t g, const std::string& path) {
  std::vector<std::pair<std::string, std::string>> out;
  H5O_info_t info;
  H5Oget_info(g, &info);
  for (hsize_t k = 0; k < info.num_attrs; ++k) {
    H a{H5Aopen_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, k, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
    if (a.id < 0) refuse(path, "cannot read its scene");
    const ssize_t len = H5Aget_name(a.id, 0, nullptr);
    std::string name(static_cast<size_t>(std::max<ssize_t>(len, 0)), '\0');
    H5Aget_name(a.id, name.size() + 1, name.data());
    const auto v = read_texts(a.id, path, name);
    if (v.size() != 1) refuse(path, "scene value " + name + " is not one text");
    out.emplace_back(name, v[0]);
  }
  return out;
}

void require_finite(const Eigen::MatrixXd& m, const std::string& what, const std::string& path) {
  if (!m.allFinite()) refuse(path, "it holds non-finite values in " + what + " (a damaged or blown-up state)");
}

}  // namespace

void write_checkpoint(const std::string& path, const Simulation& sim,
                      const std::vector<std::pair<std::string, std::string>>& scene, const std::string& run_id,
                      const Observers* observers, const std::string& scene_file) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string part = part_path(path);
  {
    errno = 0;
    H fcpl{H5Pcreate(H5P_FILE_CREATE), H5Pclose};
    H5Pset_userblock(fcpl.id, static_cast<hsize_t>(kSealBytes));  // room for the seal
    H f{H5Fcreate(part.c_str(), H5F_ACC_TRUNC, fcpl.id, H5P_DEFAULT), H5Fclose};
    if (f.id < 0) {  // (a full disk: HDF5 may have made the file without its superblock)
      const std::string why = errno ? std::string(": ") + std::strerror(errno) : "";
      std::remove(part.c_str());
      write_failed(path, "cannot create " + part + why);
    }
    try {
      reserve_hdf5_space(f.id, checkpoint_bytes(sim, scene, observers), part);
      write_state(f.id, sim, scene, scene_file, path);
      if (observers) write_run(f.id, run_id, *observers, path);
      if (H5Fflush(f.id, H5F_SCOPE_GLOBAL) < 0) write_failed(path, "cannot flush (disk full?)");
    } catch (...) {
      H5Fclose(f.id);
      f.id = -1;
      std::remove(part.c_str());
      throw;
    }
    const hid_t id = f.id;
    f.id = -1;
    if (H5Fclose(id) < 0) {
      std::remove(part.c_str());
      write_failed(path, "cannot close " + part + " (disk full?)");
    }
  }
  try {
    seal_checkpoint(part);
  } catch (const std::exception& e) {
    std::remove(part.c_str());
    write_failed(path, e.what());
  }
  commit_part(part, path);
}

void seal_checkpoint(const std::string& path) {
  const Fd f{::open(path.c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW)};
  if (f.fd < 0) throw WriteError("cannot open " + path + " to seal it: " + std::strerror(errno));
  const std::string seal = seal_text(sha256_file_hex(f.fd, kSealBytes, path));
  if (::pwrite(f.fd, seal.data(), seal.size(), 0) != static_cast<ssize_t>(seal.size()))
    throw WriteError("cannot write the seal of " + path + ": " + std::strerror(errno));
}

namespace {

// Why an HDF5 file without a seal is not a checkpoint this sphib reads (it never was one, so no
// damage of a sealed checkpoint is parsed here: one changed bit cannot move the seal's HDF5
// signature from byte 512 to byte 0).
std::string unsealed_kind(const std::string& path) {
  H f{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  if (f.id >= 0 && H5Lexists(f.id, "snapshots", H5P_DEFAULT) > 0)
    return "a run's output file (its snapshots), not a checkpoint: restart from the checkpoint.h5 beside it";
  if (f.id >= 0 && H5Aexists(f.id, "checkpoint_format") > 0)
    return "written in checkpoint format " + read_text(f.id, "checkpoint_format", path) + " (this sphib reads format " +
           std::to_string(kCheckpointFormat) + ", sealed with its SHA-256): run the scene from the start";
  return "an HDF5 file, not a sphib checkpoint (no checkpoint seal)";
}

// Opens the verified file: a failure now is HDF5's file locking (another program has it open for
// writing) or a file that changed since it was verified.
hid_t open_verified(const std::string& path) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f >= 0) return f;
  H fapl{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
  H5Pset_file_locking(fapl.id, false, true);
  H unlocked{H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.id), H5Fclose};
  if (unlocked.id >= 0)
    refuse(path, "it is locked by another program that has it open for writing (HDF5 file locking, e.g. h5py's 'r+'): "
                 "close it there first");
  refuse(path, "cannot open it as HDF5 although its seal holds (changed while it was read?)");
}

}  // namespace

Checkpoint read_checkpoint(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  // A plain file, verified against its seal before HDF5 parses a byte of it (a FIFO would block, a
  // damaged file could mislead or crash HDF5).
  struct stat st {};
  if (path.empty()) refuse("\"\"", "no file named (an empty --restart)");
  if (::stat(path.c_str(), &st) != 0) refuse(path, std::string("cannot be read: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) refuse(path, "not a plain file (a directory, a FIFO or a device): not a checkpoint");
  {
    const Fd fd{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK)};
    if (fd.fd < 0) refuse(path, std::string("cannot be read: ") + std::strerror(errno));
    // HDF5 locks a file it writes (flock, exclusive): such a file is changing under the reader.
    if (::flock(fd.fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK)
      refuse(path, "it is locked by another program that has it open for writing (HDF5 file locking, e.g. h5py's "
                   "'r+'): close it there first");
    const std::string why = seal_problem(fd.fd, path);
    if (why == "unsealed HDF5") refuse(path, unsealed_kind(path));
    if (!why.empty()) refuse(path, why);
  }
  H f{open_verified(path), H5Fclose};
  Checkpoint c;
  if (H5Aexists(f.id, "sphib_version") <= 0) refuse(path, "not a sphib checkpoint (no sphib_version)");
  if (H5Aexists(f.id, "checkpoint_format") <= 0 || read_text(f.id, "checkpoint_format", path) != std::to_string(kCheckpointFormat))
    refuse(path, "not written in checkpoint format " + std::to_string(kCheckpointFormat) + ": run the scene from the start");
  c.version = read_text(f.id, "sphib_version", path);
  if (H5Aexists(f.id, "scene_file") > 0) c.scene_file = read_text(f.id, "scene_file", path);
  H sc{H5Gopen2(f.id, "scene", H5P_DEFAULT), H5Gclose};
  if (sc.id < 0) refuse(path, "no scene group");
  c.scene = read_group_texts(sc.id, path);
  H fl{H5Gopen2(f.id, "fluid", H5P_DEFAULT), H5Gclose};
  if (fl.id < 0) refuse(path, "no fluid group");
  H5G_info_t gi;
  H5Gget_info(fl.id, &gi);
  for (hsize_t k = 0; k < gi.nlinks; ++k) {
    char name[512];
    H5Lget_name_by_idx(fl.id, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT);
    c.fluid.emplace_back(name, read_matrix(fl.id, name, path));
    require_finite(c.fluid.back().second, std::string("fluid/") + name, path);
  }
  H mg{H5Gopen2(f.id, "membranes", H5P_DEFAULT), H5Gclose};
  if (mg.id >= 0) {
    H5Gget_info(mg.id, &gi);
    for (hsize_t k = 0; k < gi.nlinks; ++k) {
      c.markers.push_back(read_matrix(mg.id, std::to_string(k), path));
      require_finite(c.markers.back(), "membranes/" + std::to_string(k), path);
    }
  }
  if (H5Lexists(f.id, "marker_velocities", H5P_DEFAULT) > 0) {
    H vg{H5Gopen2(f.id, "marker_velocities", H5P_DEFAULT), H5Gclose};
    c.marker_velocities.resize(c.markers.size());
    c.marker_velocities_next.resize(c.markers.size());
    for (size_t k = 0; k < c.markers.size(); ++k) {
      const std::string name = std::to_string(k);
      if (H5Lexists(vg.id, name.c_str(), H5P_DEFAULT) > 0) {
        c.marker_velocities[k] = read_matrix(vg.id, name, path);
        require_finite(c.marker_velocities[k], "marker_velocities/" + name, path);
      }
      if (H5Lexists(vg.id, (name + "_next").c_str(), H5P_DEFAULT) > 0) {
        c.marker_velocities_next[k] = read_matrix(vg.id, name + "_next", path);
        require_finite(c.marker_velocities_next[k], "marker_velocities/" + name + "_next", path);
      }
    }
  }
  c.stiff_filter.resize(c.markers.size());
  if (H5Lexists(f.id, "stiff_filter", H5P_DEFAULT) > 0) {
    H sg{H5Gopen2(f.id, "stiff_filter", H5P_DEFAULT), H5Gclose};
    for (size_t k = 0; k < c.markers.size(); ++k) {
      const std::string name = std::to_string(k);
      if (H5Lexists(sg.id, name.c_str(), H5P_DEFAULT) > 0) {
        c.stiff_filter[k] = read_matrix(sg.id, name, path);
        require_finite(c.stiff_filter[k], "stiff_filter/" + name, path);
      }
    }
  }
  if (H5Lexists(f.id, "run", H5P_DEFAULT) > 0) read_run(f.id, c, path);
  return c;
}

void restore_checkpoint(const Checkpoint& c, const std::string& path,
                        const std::vector<std::pair<std::string, std::string>>& scene, Simulation& sim) {
  if (c.version != SPHIB_VERSION)
    refuse(path, "written by sphib " + c.version + ", this is " + SPHIB_VERSION);
  std::map<std::string, std::string> saved(c.scene.begin(), c.scene.end()), now(scene.begin(), scene.end());
  for (const auto& [k, v] : now)
    if (!restart_may_change(k) && !restates_other_keys(k) && (!saved.count(k) || saved[k] != v))
      refuse(path, "its scene does not match: " + k + " = " + (saved.count(k) ? saved[k] : "(unset)") +
                       " in the checkpoint, " + v + " now");
  for (const auto& [k, v] : saved)
    if (!restart_may_change(k) && !restates_other_keys(k) && !now.count(k)) refuse(path, "its scene does not match: " + k + " = " + v + " is not set now");
  if (c.markers.size() != sim.membranes().size()) refuse(path, "it has a different number of membranes");
  try {
    sim.fluid().restore(c.fluid);
    for (size_t k = 0; k < c.markers.size(); ++k) sim.set_markers(k, c.markers[k]);
    for (size_t k = 0; k < c.marker_velocities.size(); ++k)
      if (c.marker_velocities[k].rows() > 0)
        sim.set_marker_history(k, c.marker_velocities[k],
                               c.marker_velocities_next[k].rows() > 0 ? &c.marker_velocities_next[k] : nullptr);
    for (size_t k = 0; k < c.stiff_filter.size(); ++k) sim.set_stiff_filter_state(k, c.stiff_filter[k]);
  } catch (const std::exception& e) {  // sizes that do not fit the scene's lattice or membranes
    refuse(path, e.what());
  }
  if (!(std::isfinite(sim.time()) && sim.time() >= 0) || sim.steps() < 0)
    refuse(path, "its clock is not valid (t = " + std::to_string(sim.time()) + ", step " + std::to_string(sim.steps()) + ")");
  // t is the sum of `steps` steps of dt: each addition rounds by at most eps t <= eps n dt, so
  // |t - n dt| <= n^2 eps dt (and never half a step).
  const double dt = sim.fluid().params().dt, n = static_cast<double>(sim.steps());
  const double tol = std::min(0.5, 1e-9 + n * n * 2.3e-16) * dt;
  if (!(std::fabs(sim.time() - n * dt) <= tol)) {
    std::ostringstream m;
    m.precision(17);
    m << "its clock is not valid: t = " << sim.time() << " at step " << sim.steps() << " is not " << sim.steps()
      << " steps of time.dt = " << dt << " (" << n * dt << ")";
    refuse(path, m.str());
  }
}

Scene checkpoint_scene(const Checkpoint& c, const std::string& path, const std::vector<std::string>& overrides) {
  for (const std::string& kv : overrides) {
    const std::string key = kv.substr(0, kv.find('='));
    if (!restart_may_change(key))
      refuse(path, "--set " + key + ": a restart keeps the checkpoint's scene; it may change only time.end, "
                   "time.max_steps, output.*, limits.* and title (run the scene from the start to change " + key + ")");
  }
  namespace fs = std::filesystem;
  const std::string name = c.scene_file.empty() ? path + " (its scene)" : c.scene_file;
  const std::string base = c.scene_file.empty() ? fs::path(path).parent_path().string() : fs::path(c.scene_file).parent_path().string();
  Scene s;
  try {
    s = scene_from_values(c.scene, name, overrides, base.empty() ? "." : base);
  } catch (const SceneError& e) {
    refuse(path, std::string("its scene: ") + e.what());
  }
  s.path = name;
  return s;
}

}  // namespace sphib
