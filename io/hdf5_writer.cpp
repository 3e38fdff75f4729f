#include "io/hdf5_writer.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "io/atomic_file.hpp"

namespace sphib {

static_assert(std::is_same<hid_t, std::int64_t>::value, "Hdf5Writer stores hid_t as int64_t");

namespace {

using RowMat2 = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

// Keeps the deepest (most specific) description on HDF5's error stack, e.g. the errno text.
herr_t keep_deepest(unsigned, const H5E_error2_t* e, void* out) {
  if (!e || !e->desc || !*e->desc) return 0;
  std::string& s = *static_cast<std::string*>(out);
  s = e->desc;
  for (char& c : s)
    if (c == '\n') c = ' ';  // HDF5 puts a ctime() line break inside write errors
  return 0;
}

[[noreturn]] void fail(const std::string& file, const std::string& op) {
  std::string cause;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, keep_deepest, &cause);
  H5Eclear2(H5E_DEFAULT);
  throw WriteError("Hdf5Writer: " + op + " failed for '" + file + "'" + (cause.empty() ? "" : ": " + cause));
}

void check(herr_t rc, const std::string& file, const std::string& op) {
  if (rc < 0) fail(file, op);
}

// Owns one HDF5 identifier; the constructor checks it.
class Handle {
 public:
  Handle(hid_t id, herr_t (*closer)(hid_t), const std::string& file, const std::string& op)
      : id_(id), closer_(closer) {
    if (id_ < 0) fail(file, op);
  }
  Handle(Handle&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = -1; }
  ~Handle() {
    if (id_ >= 0) closer_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle& operator=(Handle&&) = delete;
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*closer_)(hid_t);
};

// Variable-length UTF-8 string type (h5py reads it as str).
Handle string_type(const std::string& file) {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose, file, "H5Tcopy");
  check(H5Tset_size(t, H5T_VARIABLE), file, "H5Tset_size");
  check(H5Tset_cset(t, H5T_CSET_UTF8), file, "H5Tset_cset");
  return t;
}

void write_attr(hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type,
                hid_t space, const void* data, const std::string& file) {
  const std::string op = "attribute '" + name + "'";
  Handle a(H5Acreate2(loc, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
           file, "H5Acreate2 of " + op);
  check(H5Awrite(a, mem_type, data), file, "H5Awrite of " + op);
}

void attr_double(hid_t loc, const std::string& name, double v, const std::string& file) {
  Handle s(H5Screate(H5S_SCALAR), H5Sclose, file, "H5Screate");
  write_attr(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, s, &v, file);
}

void attr_int(hid_t loc, const std::string& name, int v, const std::string& file) {
  Handle s(H5Screate(H5S_SCALAR), H5Sclose, file, "H5Screate");
  write_attr(loc, name, H5T_STD_I32LE, H5T_NATIVE_INT, s, &v, file);
}

void attr_string(hid_t loc, const std::string& name, const std::string& v,
                 const std::string& file) {
  Handle s(H5Screate(H5S_SCALAR), H5Sclose, file, "H5Screate");
  Handle t = string_type(file);
  const char* p = v.c_str();
  write_attr(loc, name, t, t, s, &p, file);
}

void attr_strings(hid_t loc, const std::string& name, const std::vector<std::string>& v,
                  const std::string& file) {
  const hsize_t n = v.size();
  Handle s(H5Screate_simple(1, &n, nullptr), H5Sclose, file, "H5Screate_simple");
  Handle t = string_type(file);
  std::vector<const char*> p;
  for (const auto& x : v) p.push_back(x.c_str());
  write_attr(loc, name, t, t, s, p.data(), file);
}

// Contiguous dataset of `dims`, filled from `data` (row-major, may be null when empty).
void dataset(hid_t loc, const std::string& name, std::vector<hsize_t> dims, hid_t file_type,
             hid_t mem_type, const void* data, const std::string& file) {
  const std::string op = "dataset '" + name + "'";
  Handle s(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose, file,
           "H5Screate_simple of " + op);
  Handle d(H5Dcreate2(loc, name.c_str(), file_type, s, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Dclose, file, "H5Dcreate2 of " + op);
  hsize_t count = 1;
  for (hsize_t n : dims) count *= n;
  if (count > 0) check(H5Dwrite(d, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), file,
                       "H5Dwrite of " + op);
}

void doubles(hid_t loc, const std::string& name, std::vector<hsize_t> dims, const double* data,
             const std::string& file) {
  dataset(loc, name, std::move(dims), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data, file);
}

void ints(hid_t loc, const std::string& name, std::vector<hsize_t> dims, const int* data,
          const std::string& file) {
  dataset(loc, name, std::move(dims), H5T_STD_I32LE, H5T_NATIVE_INT, data, file);
}

Handle create_group(hid_t loc, const std::string& name, const std::string& file) {
  return Handle(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                file, "H5Gcreate2 of group '" + name + "'");
}

std::string xml_escape(const std::string& s) {
  std::string r;
  for (char c : s) {
    switch (c) {
      case '&': r += "&amp;"; break;
      case '<': r += "&lt;"; break;
      case '>': r += "&gt;"; break;
      case '"': r += "&quot;"; break;
      case '\'': r += "&apos;"; break;
      default: r += c;
    }
  }
  return r;
}

double attribute_bytes(const RunAttributes& attrs) {
  double b = 0;
  for (const auto& [name, value] : attrs.text) b += 128.0 + name.size() + value.size();
  return b + 128.0 * attrs.numbers.size();
}

void write_attributes(hid_t file, const RunAttributes& attrs, const std::string& part) {
  for (const auto& [name, value] : attrs.text) attr_string(file, name, value, part);
  for (const auto& [name, value] : attrs.numbers) attr_double(file, name, value, part);
}

}  // namespace

Hdf5Writer::Hdf5Writer(std::string path, const RunAttributes& attrs)
    : path_(std::move(path)), part_(part_path(path_)) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become exceptions, not stderr dumps
  file_ = H5Fcreate(part_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0) fail(part_, "H5Fcreate");
  try {
    reserve(attribute_bytes(attrs));
    writing([&] {
      write_attributes(file_, attrs, part_);
      create_group(file_, "snapshots", part_);
      check(H5Fflush(file_, H5F_SCOPE_LOCAL), part_, "H5Fflush");
    });
  } catch (...) {
    H5Fclose(file_);
    file_ = -1;
    std::remove(part_.c_str());
    throw;
  }
}

Hdf5Writer::Hdf5Writer(std::string path, const RunAttributes& attrs, const std::string& source, long resume_step)
    : path_(std::move(path)), part_(part_path(path_)) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::equivalent(source, part_, ec)) {
    fs::copy_file(source, part_, fs::copy_options::overwrite_existing, ec);
    if (ec) throw WriteError("Hdf5Writer: cannot copy '" + source + "' to '" + part_ + "': " + ec.message());
  }
  file_ = H5Fopen(part_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file_ < 0) fail(part_, "H5Fopen");
  try {
    reserve(attribute_bytes(attrs));
    writing([&] {
      H5O_info_t info;
      check(H5Oget_info(file_, &info), part_, "H5Oget_info");
      for (hsize_t k = 0; k < info.num_attrs; ++k)
        check(H5Adelete_by_idx(file_, ".", H5_INDEX_NAME, H5_ITER_DEC, 0, H5P_DEFAULT), part_, "H5Adelete_by_idx");
      write_attributes(file_, attrs, part_);
      for (const char* g : {"diagnostics", "xdmf"})  // written again by close()
        if (H5Lexists(file_, g, H5P_DEFAULT) > 0) check(H5Ldelete(file_, g, H5P_DEFAULT), part_, std::string("H5Ldelete of ") + g);
      resume_snapshots(resume_step);
      check(H5Fflush(file_, H5F_SCOPE_LOCAL), part_, "H5Fflush");
    });
  } catch (...) {
    H5Fclose(file_);
    file_ = -1;
    throw;
  }
}

// The snapshots of the earlier file before resume_step, as the XDMF needs them; later ones deleted.
void Hdf5Writer::resume_snapshots(long resume_step) {
  Handle g(H5Gopen2(file_, "snapshots", H5P_DEFAULT), H5Gclose, part_, "H5Gopen2 of group 'snapshots'");
  H5G_info_t gi;
  check(H5Gget_info(g, &gi), part_, "H5Gget_info");
  std::vector<std::string> later;
  for (hsize_t k = 0; k < gi.nlinks; ++k) {
    char name[64] = {0};
    if (H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT) < 0) fail(part_, "H5Lget_name_by_idx");
    Handle s(H5Gopen2(g, name, H5P_DEFAULT), H5Gclose, part_, std::string("H5Gopen2 of snapshot ") + name);
    int step = 0;
    SnapshotInfo info;
    {
      Handle a(H5Aopen(s, "step", H5P_DEFAULT), H5Aclose, part_, "H5Aopen of step");
      check(H5Aread(a, H5T_NATIVE_INT, &step), part_, "H5Aread of step");
      Handle b(H5Aopen(s, "time", H5P_DEFAULT), H5Aclose, part_, "H5Aopen of time");
      check(H5Aread(b, H5T_NATIVE_DOUBLE, &info.t), part_, "H5Aread of time");
    }
    if (step >= resume_step) { later.emplace_back(name); continue; }
    info.group = std::string("/snapshots/") + name;
    next_index_ = std::max(next_index_, std::atoi(name) + 1);
    H5G_info_t si;
    check(H5Gget_info(s, &si), part_, "H5Gget_info");
    for (hsize_t j = 0; j < si.nlinks; ++j) {
      char item[256] = {0};
      if (H5Lget_name_by_idx(s, ".", H5_INDEX_NAME, H5_ITER_INC, j, item, sizeof item, H5P_DEFAULT) < 0) fail(part_, "H5Lget_name_by_idx");
      const std::string it(item);
      if (it == "x") {
        Handle d(H5Dopen2(s, item, H5P_DEFAULT), H5Dclose, part_, "H5Dopen2 of x");
        Handle sp(H5Dget_space(d), H5Sclose, part_, "H5Dget_space of x");
        hsize_t n = 0;
        H5Sget_simple_extent_dims(sp, &n, nullptr);
        info.n = static_cast<long>(n);
      } else if (it == "velocity") {
        info.velocity = true;
      } else if (it.rfind("membrane_", 0) == 0) {
        Handle d(H5Dopen2(s, (it + "/X").c_str(), H5P_DEFAULT), H5Dclose, part_, "H5Dopen2 of " + it + "/X");
        Handle sp(H5Dget_space(d), H5Sclose, part_, "H5Dget_space of " + it + "/X");
        hsize_t dims[2] = {0, 0};
        H5Sget_simple_extent_dims(sp, dims, nullptr);
        const size_t k = std::stoul(it.substr(9));
        if (info.nb.size() <= k) info.nb.resize(k + 1);
        info.nb[k] = static_cast<long>(dims[0]);
      } else if (it != "y" && it != "xy") {
        info.scalars.push_back(it);
      }
    }
    info.lattice_pending = H5Lexists(s, "xy", H5P_DEFAULT) <= 0;
    snapshots_.push_back(std::move(info));
  }
  for (const auto& name : later) check(H5Ldelete(g, name.c_str(), H5P_DEFAULT), part_, "H5Ldelete of snapshot " + name);
}

template <class F>
void Hdf5Writer::writing(F&& write) {
  try {
    write();
  } catch (...) {
    broken_ = true;
    throw;
  }
}

std::string root_text_attribute(const std::string& path, const std::string& name) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return "";
  std::string out;
  if (H5Aexists(f, name.c_str()) > 0) {
    const hid_t a = H5Aopen(f, name.c_str(), H5P_DEFAULT);
    const hid_t t = a >= 0 ? H5Aget_type(a) : -1;
    if (t >= 0 && H5Tget_class(t) == H5T_STRING && H5Tis_variable_str(t) > 0) {
      char* p = nullptr;
      const hid_t mem = H5Tcopy(H5T_C_S1);
      H5Tset_size(mem, H5T_VARIABLE);
      H5Tset_cset(mem, H5T_CSET_UTF8);
      if (H5Aread(a, mem, &p) >= 0 && p) {
        out = p;
        H5free_memory(p);
      }
      H5Tclose(mem);
    }
    if (t >= 0) H5Tclose(t);
    if (a >= 0) H5Aclose(a);
  }
  H5Fclose(f);
  return out;
}

bool snapshots_readable(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return false;
  bool ok = true;
  try {
    Handle g(H5Gopen2(f, "snapshots", H5P_DEFAULT), H5Gclose, path, "H5Gopen2");
    H5G_info_t gi;
    check(H5Gget_info(g, &gi), path, "H5Gget_info");
    for (hsize_t k = 0; k < gi.nlinks; ++k) {
      char name[64] = {0};
      if (H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name, H5P_DEFAULT) < 0) fail(path, "H5Lget_name_by_idx");
      Handle s(H5Gopen2(g, name, H5P_DEFAULT), H5Gclose, path, "H5Gopen2");
      Handle a(H5Aopen(s, "step", H5P_DEFAULT), H5Aclose, path, "H5Aopen");
      int step = 0;
      check(H5Aread(a, H5T_NATIVE_INT, &step), path, "H5Aread");
      Handle x(H5Dopen2(s, "x", H5P_DEFAULT), H5Dclose, path, "H5Dopen2");
    }
  } catch (const std::exception&) {
    ok = false;
  }
  H5Fclose(f);
  return ok;
}

void Hdf5Writer::reserve(double bytes) { reserve_hdf5_space(file_, bytes, part_); }

void reserve_hdf5_space(std::int64_t file, double bytes, const std::string& path) {
  hsize_t size = 0;
  if (H5Fget_filesize(file, &size) < 0) fail(path, "H5Fget_filesize");
  void* handle = nullptr;
  if (H5Fget_vfd_handle(file, H5P_DEFAULT, &handle) < 0 || !handle) return;  // no POSIX file: nothing to reserve
  // HDF5's own metadata (object headers, B-trees, heaps: under 1 kB per dataset): a quarter of the data
  // and 256 kB more.
  reserve_space(*static_cast<int*>(handle), static_cast<long long>(size + 1.25 * bytes + (256 << 10)), path);
}

Hdf5Writer::~Hdf5Writer() {
  try {
    close();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sphib: %s\n", e.what());
  }
}

std::string Hdf5Writer::xdmf_path() const {
  return std::filesystem::path(path_).replace_extension(".xdmf").string();
}

std::string Hdf5Writer::membranes_xdmf_path() const {
  const std::filesystem::path p(path_);
  return (p.parent_path() / (p.stem().string() + "_membranes.xdmf")).string();
}

void Hdf5Writer::require_open(const char* what) const {
  if (file_ < 0) throw std::logic_error(std::string("Hdf5Writer: ") + what + " after close() of '" +
                                        path_ + "'");
}

void Hdf5Writer::write_snapshot(
    int step, double t, const Mat2& x,
    const std::vector<std::pair<std::string, const Vec*>>& particle_scalars,
    const std::vector<MembraneSnapshot>& membranes, const Lattice* lattice) {
  require_open("write_snapshot");
  const long n = static_cast<long>(x.rows());
  SnapshotInfo info;
  info.t = t;
  info.n = n;
  for (const auto& [name, v] : particle_scalars) {  // validate everything before writing
    if (name.empty() || name == "x" || name == "y" || name == "xy" || name == "velocity" ||
        name.rfind("membrane_", 0) == 0 ||
        name.find('/') != std::string::npos ||
        std::find(info.scalars.begin(), info.scalars.end(), name) != info.scalars.end())
      throw std::invalid_argument("Hdf5Writer: bad particle scalar name '" + name + "'");
    if (!v || v->size() != n)
      throw std::invalid_argument("Hdf5Writer: particle scalar '" + name + "' has " +
                                  std::to_string(v ? v->size() : 0) + " values for " +
                                  std::to_string(n) + " particles");
    info.scalars.push_back(name);
  }
  for (std::size_t k = 0; k < membranes.size(); ++k) {
    const MembraneSnapshot& m = membranes[k];
    if (!m.X || !m.f || !m.T || m.f->rows() != m.X->rows() || m.T->size() != m.X->rows())
      throw std::invalid_argument("Hdf5Writer: membrane " + std::to_string(k) +
                                  ": X, f, T missing or of different lengths");
    info.nb.push_back(static_cast<long>(m.X->rows()));
  }
  const Vec* u = nullptr;
  const Vec* v = nullptr;
  for (const auto& [sname, a] : particle_scalars) {
    if (sname == "u") u = a;
    if (sname == "v") v = a;
  }
  info.velocity = u && v;
  if (lattice) {
    if (lattice->size() != n)
      throw std::invalid_argument("Hdf5Writer: a lattice of " + std::to_string(lattice->size()) + " particles for " +
                                  std::to_string(n) + " positions");
    info.lattice = "/xdmf/lattice_" + std::to_string(lattice->nx) + "x" + std::to_string(lattice->ny);
    info.cells = static_cast<long>(lattice->nx - 1) * (lattice->ny - 1);
    if (std::none_of(lattices_.begin(), lattices_.end(), [&](const auto& l) { return l.first == info.lattice; }))
      lattices_.emplace_back(info.lattice, *lattice);
    for (SnapshotInfo& s : snapshots_)  // resumed ones: the same scene, the same lattice
      if (s.lattice_pending && s.n == n) s.lattice = info.lattice, s.cells = info.cells, s.lattice_pending = false;
  }
  double bytes = 8.0 * n * (2 + particle_scalars.size() + (info.velocity ? 3 : 0) + (info.lattice.empty() ? 2 : 0));
  for (long nb : info.nb) bytes += 8.0 * nb * 8 + 4.0 * (nb + 1) + 4096;
  reserve(bytes + 4096.0 * (4 + particle_scalars.size()));
  writing([&] { write_snapshot_data(info, step, t, x, particle_scalars, membranes, u, v); });
  snapshots_.push_back(std::move(info));
}

void Hdf5Writer::write_snapshot_data(SnapshotInfo& info, int step, double t, const Mat2& x,
                                     const std::vector<std::pair<std::string, const Vec*>>& particle_scalars,
                                     const std::vector<MembraneSnapshot>& membranes, const Vec* u, const Vec* v) {
  const long n = info.n;
  char name[32];
  std::snprintf(name, sizeof name, "/snapshots/%06d", next_index_);
  info.group = name;
  Handle g = create_group(file_, info.group, part_);
  ++next_index_;  // a snapshot that fails half-way keeps its index but stays out of the XDMF
  attr_double(g, "time", t, part_);
  attr_int(g, "step", step, part_);
  const hsize_t N = static_cast<hsize_t>(n);
  doubles(g, "x", {N}, x.col(0).data(), part_);  // Mat2 is column-major: columns are contiguous
  doubles(g, "y", {N}, x.col(1).data(), part_);
  for (const auto& [sname, a] : particle_scalars) doubles(g, sname, {N}, a->data(), part_);
  if (info.velocity) {  // (u, v, 0): ParaView's vectors (glyphs, stream traces) have three components
    std::vector<double> w(3 * N, 0.0);
    for (hsize_t i = 0; i < N; ++i) w[3 * i] = (*u)[i], w[3 * i + 1] = (*v)[i];
    doubles(g, "velocity", {N, 3}, w.data(), part_);
  }
  if (info.lattice.empty()) {  // moving particles: interleaved positions for the XDMF geometry XY
    const RowMat2 xy = x;
    doubles(g, "xy", {N, 2}, xy.data(), part_);
  }

  for (std::size_t k = 0; k < membranes.size(); ++k) {
    const MembraneSnapshot& m = membranes[k];
    const hsize_t nb = static_cast<hsize_t>(info.nb[k]);
    Handle mg = create_group(g, "membrane_" + std::to_string(k), part_);
    const RowMat2 X = *m.X, f = *m.f;  // HDF5 is row-major
    doubles(mg, "X", {nb, 2}, X.data(), part_);
    doubles(mg, "f", {nb, 2}, f.data(), part_);
    doubles(mg, "T", {nb}, m.T->data(), part_);
    std::vector<int> conn(nb + 1);
    for (hsize_t i = 0; i < nb; ++i) conn[i] = static_cast<int>(i);
    conn[nb] = 0;  // closes the polyline
    ints(mg, "conn", {1, nb + 1}, conn.data(), part_);
    std::vector<double> f3(3 * nb, 0.0);
    for (hsize_t i = 0; i < nb; ++i) f3[3 * i] = f(i, 0), f3[3 * i + 1] = f(i, 1);
    doubles(mg, "f3", {nb, 3}, f3.data(), part_);
  }
  check(H5Fflush(file_, H5F_SCOPE_LOCAL), part_, "H5Fflush");
}

void Hdf5Writer::write_series(const std::string& name, const std::vector<std::string>& columns,
                              const std::vector<std::vector<double>>& rows) {
  require_open("write_series");
  if (name.empty() || name.find('/') != std::string::npos)
    throw std::invalid_argument("Hdf5Writer: bad series name '" + name + "'");
  const hsize_t nc = columns.size();
  std::vector<double> data;
  data.reserve(rows.size() * nc);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].size() != nc)
      throw std::invalid_argument("Hdf5Writer: series '" + name + "' row " + std::to_string(r) +
                                  " has " + std::to_string(rows[r].size()) + " values for " +
                                  std::to_string(nc) + " columns");
    data.insert(data.end(), rows[r].begin(), rows[r].end());
  }
  double names = 0;
  for (const auto& c : columns) names += 64.0 + c.size();
  reserve(8.0 * data.size() + names + 8192);
  writing([&] {
    const htri_t exists = H5Lexists(file_, "diagnostics", H5P_DEFAULT);
    if (exists < 0) fail(part_, "H5Lexists of group 'diagnostics'");
    if (!exists) create_group(file_, "diagnostics", part_);
    const std::string dname = "/diagnostics/" + name;
    doubles(file_, dname, {static_cast<hsize_t>(rows.size()), nc}, data.data(), part_);
    Handle d(H5Dopen2(file_, dname.c_str(), H5P_DEFAULT), H5Dclose, part_, "H5Dopen2 of " + dname);
    attr_strings(d, "columns", columns, part_);
    check(H5Fflush(file_, H5F_SCOPE_LOCAL), part_, "H5Fflush");
  });
}

void Hdf5Writer::abandon() {
  if (file_ < 0) return;
  H5Fclose(file_);  // after a failed write HDF5 may refuse; the .part stays either way
  file_ = -1;
}

void Hdf5Writer::close() {
  if (file_ < 0) return;
  if (broken_) {  // HDF5 cannot complete a file whose write failed: leave the .part
    abandon();
    return;
  }
  publish_all(close_to_parts());
}

std::vector<PartFile> Hdf5Writer::close_to_parts() {
  if (file_ < 0 || broken_) {
    abandon();
    throw WriteError("'" + part_ + "' cannot be completed (closed, or a write to it failed)");
  }
  std::set<long> counts;  // one vertex connectivity per count of moving particles
  for (const auto& s : snapshots_)
    if (s.lattice.empty() && !s.lattice_pending) counts.insert(s.n);
  double bytes = 0;
  for (long n : counts) bytes += 4.0 * n;
  for (const auto& [name, L] : lattices_) bytes += 16.0 * L.size() + 16.0 * (L.nx - 1) * (L.ny - 1);
  try {
    reserve(bytes);
  } catch (...) {
    abandon();
    throw;
  }
  const hid_t file = file_;
  file_ = -1;  // never retried: a failed close leaves only the .part file
  try {
    if (!counts.empty() || !lattices_.empty()) {
      Handle g = create_group(file, "xdmf", part_);
      for (long n : counts) {
        std::vector<int> ids(static_cast<std::size_t>(n));
        for (long i = 0; i < n; ++i) ids[i] = static_cast<int>(i);
        ints(g, "vertices_" + std::to_string(n), {static_cast<hsize_t>(n), 1}, ids.data(), part_);
      }
      for (const auto& [name, L] : lattices_) {  // particle i + nx j: quads (i, j), (i+1, j), (i+1, j+1), (i, j+1)
        Handle lg = create_group(file, name, part_);
        const RowMat2 xy = L.x;
        doubles(lg, "xy", {static_cast<hsize_t>(L.size()), 2}, xy.data(), part_);
        std::vector<int> q;
        q.reserve(4 * static_cast<std::size_t>(L.nx - 1) * (L.ny - 1));
        for (int j = 0; j + 1 < L.ny; ++j)
          for (int i = 0; i + 1 < L.nx; ++i)
            for (int c : {i + L.nx * j, i + 1 + L.nx * j, i + 1 + L.nx * (j + 1), i + L.nx * (j + 1)}) q.push_back(c);
        ints(lg, "quads", {q.size() / 4, 4}, q.data(), part_);
      }
    }
  } catch (...) {
    broken_ = true;
    H5Fclose(file);
    throw;
  }
  check(H5Fclose(file), part_, "H5Fclose");
  std::vector<PartFile> parts{{part_, path_}, write_part(xdmf_path(), xdmf_text(false))};
  const bool membranes = std::any_of(snapshots_.begin(), snapshots_.end(), [](const auto& s) { return !s.nb.empty(); });
  if (membranes) parts.push_back(write_part(membranes_xdmf_path(), xdmf_text(true)));
  return parts;
}

// XDMF (read by ParaView 5.11's Xdmf3 reader, its default, and its legacy XDMF reader): a temporal
// collection of the fluid's grids, or of spatial collections of the membranes' polylines.
std::string Hdf5Writer::xdmf_text(bool membranes) const {
  const std::string h5 = xml_escape(std::filesystem::path(path_).filename().string());
  std::ostringstream o;
  o.precision(17);
  auto item = [&](const std::string& dims, const std::string& type, int prec,
                  const std::string& where) {
    o << "<DataItem Dimensions=\"" << dims << "\" NumberType=\"" << type << "\" Precision=\""
      << prec << "\" Format=\"HDF\">" << h5 << ":" << xml_escape(where) << "</DataItem>";
  };
  auto attribute = [&](const std::string& name, bool vector, const std::string& dims, const std::string& where) {
    o << "     <Attribute Name=\"" << xml_escape(name) << "\" AttributeType=\"" << (vector ? "Vector" : "Scalar")
      << "\" Center=\"Node\">\n      ";
    item(dims, "Float", 8, where);
    o << "\n     </Attribute>\n";
  };
  o << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
    << "<Xdmf Version=\"2.0\">\n <Domain>\n"
    << "  <Grid Name=\"" << (membranes ? "membranes" : "fluid")
    << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const SnapshotInfo& s : snapshots_) {
    const std::string n = std::to_string(s.n);
    if (!membranes && s.lattice_pending) continue;  // never happens: a resumed run writes its lattice at once
    if (!membranes) {
      o << "   <Grid Name=\"" << (s.lattice.empty() ? "particles" : "fluid") << "\" GridType=\"Uniform\">\n"
        << "    <Time Value=\"" << s.t << "\"/>\n";
      if (!s.lattice.empty()) {  // the fixed lattice: quadrilaterals joining neighbouring particles
        o << "     <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"" << s.cells << "\">\n      ";
        item(std::to_string(s.cells) + " 4", "Int", 4, s.lattice + "/quads");
        o << "\n     </Topology>\n     <Geometry GeometryType=\"XY\">\n      ";
        item(n + " 2", "Float", 8, s.lattice + "/xy");
      } else {  // moving particles: one vertex each
        o << "     <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\" NodesPerElement=\"1\">\n      ";
        item(n + " 1", "Int", 4, "/xdmf/vertices_" + n);
        o << "\n     </Topology>\n     <Geometry GeometryType=\"XY\">\n      ";
        item(n + " 2", "Float", 8, s.group + "/xy");
      }
      o << "\n     </Geometry>\n";
      std::vector<std::string> order(s.scalars);  // p first: ParaView colours by the first scalar it reads
      std::stable_partition(order.begin(), order.end(), [](const std::string& a) { return a == "p"; });
      for (const std::string& a : order) attribute(a, false, n, s.group + "/" + a);
      if (s.velocity) attribute("velocity", true, n + " 3", s.group + "/velocity");
      o << "   </Grid>\n";
      continue;
    }
    if (s.nb.empty()) continue;
    o << "   <Grid Name=\"" << s.group.substr(s.group.rfind('/') + 1)
      << "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
      << "    <Time Value=\"" << s.t << "\"/>\n";
    for (std::size_t k = 0; k < s.nb.size(); ++k) {
      const std::string m = "membrane_" + std::to_string(k);
      const std::string g = s.group + "/" + m + "/";
      const std::string nb = std::to_string(s.nb[k]), nb1 = std::to_string(s.nb[k] + 1);
      o << "    <Grid Name=\"" << m << "\" GridType=\"Uniform\">\n"
        << "     <Topology TopologyType=\"Polyline\" NumberOfElements=\"1\" NodesPerElement=\""
        << nb1 << "\">\n      ";
      item("1 " + nb1, "Int", 4, g + "conn");
      o << "\n     </Topology>\n     <Geometry GeometryType=\"XY\">\n      ";
      item(nb + " 2", "Float", 8, g + "X");
      o << "\n     </Geometry>\n";
      attribute("f", true, nb + " 3", g + "f3");
      attribute("T", false, nb, g + "T");
      o << "    </Grid>\n";
    }
    o << "   </Grid>\n";
  }
  o << "  </Grid>\n </Domain>\n</Xdmf>\n";
  return o.str();
}

}  // namespace sphib
