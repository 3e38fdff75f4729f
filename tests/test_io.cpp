// io/: HDF5 + XDMF snapshots, CSV diagnostics, JSON summary; atomic rename and error reporting.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "fluid/common/lattice.hpp"
#include "io/csv_writer.hpp"
#include "io/hdf5_writer.hpp"
#include "io/summary.hpp"

namespace fs = std::filesystem;
using namespace sphib;

namespace {

class IoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("sphib_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

// Reads a double/int dataset; returns its values and shape.
template <class T>
std::vector<T> read_dataset(hid_t f, const std::string& name, std::vector<hsize_t>* dims) {
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(d, 0) << name;
  if (d < 0) return {};
  const hid_t s = H5Dget_space(d);
  dims->assign(static_cast<std::size_t>(H5Sget_simple_extent_ndims(s)), 0);
  H5Sget_simple_extent_dims(s, dims->data(), nullptr);
  std::vector<T> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(s)));
  const hid_t mem = std::is_same<T, double>::value ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT;
  EXPECT_GE(H5Dread(d, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0) << name;
  H5Sclose(s);
  H5Dclose(d);
  return v;
}

double attr_double(hid_t loc, const char* obj, const char* name) {
  double v = NAN;
  const hid_t a = H5Aopen_by_name(loc, obj, name, H5P_DEFAULT, H5P_DEFAULT);
  EXPECT_GE(a, 0) << obj << " @" << name;
  if (a >= 0) {
    EXPECT_GE(H5Aread(a, H5T_NATIVE_DOUBLE, &v), 0);
    H5Aclose(a);
  }
  return v;
}

int attr_int(hid_t loc, const char* obj, const char* name) {
  int v = -1;
  const hid_t a = H5Aopen_by_name(loc, obj, name, H5P_DEFAULT, H5P_DEFAULT);
  EXPECT_GE(a, 0) << obj << " @" << name;
  if (a >= 0) {
    EXPECT_GE(H5Aread(a, H5T_NATIVE_INT, &v), 0);
    H5Aclose(a);
  }
  return v;
}

// Variable-length string attribute (scalar or 1-D array).
std::vector<std::string> attr_strings(hid_t loc, const char* obj, const char* name) {
  const hid_t a = H5Aopen_by_name(loc, obj, name, H5P_DEFAULT, H5P_DEFAULT);
  EXPECT_GE(a, 0) << obj << " @" << name;
  if (a < 0) return {};
  const hid_t s = H5Aget_space(a);
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  std::vector<char*> p(static_cast<std::size_t>(H5Sget_simple_extent_npoints(s)));
  EXPECT_GE(H5Aread(a, t, p.data()), 0);
  std::vector<std::string> out(p.begin(), p.end());
  H5Dvlen_reclaim(t, s, H5P_DEFAULT, p.data());
  H5Tclose(t);
  H5Sclose(s);
  H5Aclose(a);
  return out;
}

struct SmallRun {  // 10 particles, one membrane of 6 markers, at time t
  Mat2 x{10, 2};
  Vec u{10}, v{10}, p{10}, phi{10};
  Mat2 X{6, 2}, f{6, 2};
  Vec T{6};
  explicit SmallRun(double t) {
    for (int i = 0; i < 10; ++i) {
      x(i, 0) = 0.1 * i;
      x(i, 1) = -0.05 * i;
      u[i] = t + i;
      v[i] = t - i;
      p[i] = 100.0 * t + 0.5 * i;
      phi[i] = -i * t;
    }
    for (int k = 0; k < 6; ++k) {
      const double a = 2.0 * M_PI * k / 6.0;
      X(k, 0) = 0.25 * std::cos(a) + t;
      X(k, 1) = 0.25 * std::sin(a);
      f(k, 0) = -std::cos(a) * (1 + t);
      f(k, 1) = -std::sin(a) * (1 + t);
      T[k] = 1.0 + 0.1 * k + t;
    }
  }
  void write(Hdf5Writer& w, int step, double t) const {
    w.write_snapshot(step, t, x, {{"u", &u}, {"v", &v}, {"p", &p}, {"phi", &phi}},
                     {MembraneSnapshot{&X, &f, &T}});
  }
};

RunAttributes small_attrs() {
  return {{{"sphib.version", "0.1.0"}, {"scene", "circle relaxation"}},
          {{"membrane.radius", 0.25}, {"fluid.nu", 0.1}}};
}

}  // namespace

TEST_F(IoTest, Hdf5WriterWritesSnapshotsAttributesAndSeries) {
  const std::string path = file("output.h5");
  const SmallRun r0(0.0), r1(0.5);
  {
    Hdf5Writer w(path, small_attrs());
    r0.write(w, 0, 0.0);
    r1.write(w, 50, 0.5);
    w.write_series("energy", {"t", "kinetic_energy"}, {{0.0, 1.0}, {0.5, 0.25}, {1.0, 0.125}});
    EXPECT_TRUE(fs::exists(path + ".part"));  // while running: only the .part file
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(w.xdmf_path()));
    w.close();
    EXPECT_FALSE(fs::exists(path + ".part"));  // after close: only the final file
    EXPECT_TRUE(fs::exists(path));
    EXPECT_EQ(w.xdmf_path(), file("output.xdmf"));
    EXPECT_TRUE(fs::exists(file("output.xdmf")));
    EXPECT_FALSE(fs::exists(file("output.xdmf.part")));
  }

  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  EXPECT_EQ(attr_strings(f, "/", "sphib.version"), std::vector<std::string>{"0.1.0"});
  EXPECT_EQ(attr_strings(f, "/", "scene"), std::vector<std::string>{"circle relaxation"});
  EXPECT_EQ(attr_double(f, "/", "membrane.radius"), 0.25);
  EXPECT_EQ(attr_double(f, "/", "fluid.nu"), 0.1);

  const SmallRun* runs[] = {&r0, &r1};
  const double times[] = {0.0, 0.5};
  const int steps[] = {0, 50};
  for (int s = 0; s < 2; ++s) {
    const SmallRun& r = *runs[s];
    const std::string g = s == 0 ? "/snapshots/000000" : "/snapshots/000001";
    EXPECT_EQ(attr_double(f, g.c_str(), "time"), times[s]);
    EXPECT_EQ(attr_int(f, g.c_str(), "step"), steps[s]);
    std::vector<hsize_t> dims;
    auto x = read_dataset<double>(f, g + "/x", &dims);
    EXPECT_EQ(dims, std::vector<hsize_t>{10});
    auto y = read_dataset<double>(f, g + "/y", &dims);
    auto p = read_dataset<double>(f, g + "/p", &dims);
    auto phi = read_dataset<double>(f, g + "/phi", &dims);
    ASSERT_EQ(x.size(), 10u);
    for (int i = 0; i < 10; ++i) {
      EXPECT_EQ(x[i], r.x(i, 0));
      EXPECT_EQ(y[i], r.x(i, 1));
      EXPECT_EQ(p[i], r.p[i]);
      EXPECT_EQ(phi[i], r.phi[i]);
    }
    auto u = read_dataset<double>(f, g + "/u", &dims);
    auto v = read_dataset<double>(f, g + "/v", &dims);
    EXPECT_EQ(u[3], r.u[3]);
    EXPECT_EQ(v[7], r.v[7]);
    auto vel = read_dataset<double>(f, g + "/velocity", &dims);  // (u, v, 0) for XDMF
    EXPECT_EQ(dims, (std::vector<hsize_t>{10, 3}));
    EXPECT_TRUE(vel[9] == r.u[3] && vel[10] == r.v[3] && vel[11] == 0.0);
    auto xy = read_dataset<double>(f, g + "/xy", &dims);  // moving particles: positions for XDMF
    EXPECT_EQ(dims, (std::vector<hsize_t>{10, 2}));
    EXPECT_TRUE(xy[14] == r.x(7, 0) && xy[15] == r.x(7, 1));

    auto X = read_dataset<double>(f, g + "/membrane_0/X", &dims);
    EXPECT_EQ(dims, (std::vector<hsize_t>{6, 2}));
    auto F = read_dataset<double>(f, g + "/membrane_0/f", &dims);
    EXPECT_EQ(dims, (std::vector<hsize_t>{6, 2}));
    auto T = read_dataset<double>(f, g + "/membrane_0/T", &dims);
    EXPECT_EQ(dims, std::vector<hsize_t>{6});
    auto F3 = read_dataset<double>(f, g + "/membrane_0/f3", &dims);
    EXPECT_EQ(dims, (std::vector<hsize_t>{6, 3}));
    ASSERT_EQ(X.size(), 12u);
    for (int k = 0; k < 6; ++k) {
      EXPECT_EQ(X[2 * k], r.X(k, 0));  // row-major nb x 2
      EXPECT_EQ(X[2 * k + 1], r.X(k, 1));
      EXPECT_EQ(F[2 * k], r.f(k, 0));
      EXPECT_EQ(F[2 * k + 1], r.f(k, 1));
      EXPECT_EQ(T[k], r.T[k]);
      EXPECT_EQ(F3[3 * k], r.f(k, 0));
      EXPECT_EQ(F3[3 * k + 1], r.f(k, 1));
      EXPECT_EQ(F3[3 * k + 2], 0.0);
    }
    auto conn = read_dataset<int>(f, g + "/membrane_0/conn", &dims);
    EXPECT_EQ(dims, (std::vector<hsize_t>{1, 7}));
    EXPECT_EQ(conn, (std::vector<int>{0, 1, 2, 3, 4, 5, 0}));
  }
  EXPECT_EQ(H5Lexists(f, "/snapshots/000002", H5P_DEFAULT), 0);

  std::vector<hsize_t> dims;
  auto e = read_dataset<double>(f, "/diagnostics/energy", &dims);
  EXPECT_EQ(dims, (std::vector<hsize_t>{3, 2}));
  EXPECT_EQ(e, (std::vector<double>{0.0, 1.0, 0.5, 0.25, 1.0, 0.125}));
  EXPECT_EQ(attr_strings(f, "/diagnostics/energy", "columns"),
            (std::vector<std::string>{"t", "kinetic_energy"}));
  auto ids = read_dataset<int>(f, "/xdmf/vertices_10", &dims);
  EXPECT_EQ(dims, (std::vector<hsize_t>{10, 1}));
  EXPECT_EQ(ids.back(), 9);
  H5Fclose(f);

  // XDMF: the fluid and the membranes in two files (ParaView's default reader merges the grids of
  // one time into one dataset), two time steps each, the final file name relative, balanced elements.
  const std::string x = slurp(file("output.xdmf"));
  const std::string xm = slurp(file("output_membranes.xdmf"));
  for (const std::string* t : {&x, &xm}) {
    EXPECT_EQ(count(*t, "<Time Value="), 2);
    EXPECT_EQ(count(*t, "CollectionType=\"Temporal\""), 1);
    EXPECT_EQ(count(*t, "<Grid"), count(*t, "</Grid>"));
    EXPECT_EQ(count(*t, "<DataItem"), count(*t, "</DataItem>"));
    EXPECT_EQ(count(*t, "<Attribute"), count(*t, "</Attribute>"));
    EXPECT_EQ(count(*t, ".part"), 0);
    EXPECT_EQ(count(*t, dir_.string()), 0);
  }
  EXPECT_EQ(count(x, "<Grid"), 1 + 2);
  EXPECT_EQ(count(x, "membrane"), 0);
  EXPECT_EQ(count(xm, "<Grid"), 1 + 2 * 2);
  for (const char* item :
       {">output.h5:/snapshots/000000/xy<", ">output.h5:/snapshots/000001/xy<",
        ">output.h5:/snapshots/000001/p<", ">output.h5:/snapshots/000000/phi<",
        ">output.h5:/snapshots/000001/velocity<", "Attribute Name=\"velocity\" AttributeType=\"Vector\"",
        ">output.h5:/xdmf/vertices_10<", "TopologyType=\"Polyvertex\" NumberOfElements=\"10\"",
        "GeometryType=\"XY\"", "<Time Value=\"0.5\"/>"})
    EXPECT_NE(x.find(item), std::string::npos) << item;
  EXPECT_EQ(count(x, "X_Y"), 0);  // ParaView's default reader (Xdmf3) has no X_Y geometry
  EXPECT_LT(x.find("/snapshots/000000/p<"), x.find("/snapshots/000000/u<"));  // p first: coloured by p
  for (const char* item :
       {">output.h5:/snapshots/000001/membrane_0/conn<", ">output.h5:/snapshots/000001/membrane_0/X<",
        ">output.h5:/snapshots/000001/membrane_0/f3<", ">output.h5:/snapshots/000001/membrane_0/T<",
        "TopologyType=\"Polyline\" NumberOfElements=\"1\" NodesPerElement=\"7\"", "<Time Value=\"0.5\"/>"})
    EXPECT_NE(xm.find(item), std::string::npos) << item;
}

// Particles on a fixed lattice: a mesh of quadrilaterals joining neighbours, its positions once.
TEST_F(IoTest, Hdf5WriterWritesALatticeAsAQuadMesh) {
  Domain d;
  d.x0 = -1.0, d.x1 = 2.0, d.y0 = 0.0, d.y1 = 1.0;
  const Lattice L = make_lattice(d, 4, 3);
  Vec p = Vec::LinSpaced(12, 0.0, 11.0), u = -p, v = 2.0 * p;
  {
    Hdf5Writer w(file("lat.h5"), {});
    for (int s = 0; s < 2; ++s) w.write_snapshot(s, 0.1 * s, L.x, {{"u", &u}, {"v", &v}, {"p", &p}}, {}, &L);
    EXPECT_THROW(w.write_snapshot(2, 0.2, L.x.topRows(6), {}, {}, &L), std::invalid_argument);
  }
  const hid_t f = H5Fopen(file("lat.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  std::vector<hsize_t> dims;
  const auto quads = read_dataset<int>(f, "/xdmf/lattice_4x3/quads", &dims);
  EXPECT_EQ(dims, (std::vector<hsize_t>{6, 4}));
  EXPECT_EQ(std::vector<int>(quads.begin(), quads.begin() + 4), (std::vector<int>{0, 1, 5, 4}));  // i + nx j
  EXPECT_EQ(std::vector<int>(quads.end() - 4, quads.end()), (std::vector<int>{6, 7, 11, 10}));
  const auto xy = read_dataset<double>(f, "/xdmf/lattice_4x3/xy", &dims);
  EXPECT_EQ(dims, (std::vector<hsize_t>{12, 2}));
  for (int i = 0; i < 12; ++i) EXPECT_TRUE(xy[2 * i] == L.x(i, 0) && xy[2 * i + 1] == L.x(i, 1)) << i;
  const auto vel = read_dataset<double>(f, "/snapshots/000001/velocity", &dims);
  EXPECT_EQ(dims, (std::vector<hsize_t>{12, 3}));
  for (int i = 0; i < 12; ++i) EXPECT_TRUE(vel[3 * i] == u[i] && vel[3 * i + 1] == v[i] && vel[3 * i + 2] == 0.0) << i;
  EXPECT_EQ(H5Lexists(f, "/snapshots/000000/xy", H5P_DEFAULT), 0);  // the lattice does not move
  EXPECT_EQ(H5Lexists(f, "/xdmf/vertices_12", H5P_DEFAULT), 0);
  EXPECT_EQ(H5Lexists(f, "/snapshots/000000/x", H5P_DEFAULT), 1);  // the documented layout stays
  H5Fclose(f);
  const std::string x = slurp(file("lat.xdmf"));
  EXPECT_EQ(count(x, "TopologyType=\"Quadrilateral\" NumberOfElements=\"6\""), 2);
  EXPECT_EQ(count(x, ">lat.h5:/xdmf/lattice_4x3/xy<"), 2);
  EXPECT_FALSE(fs::exists(file("lat_membranes.xdmf")));  // no membranes, no file
}

TEST_F(IoTest, Hdf5WriterDestructorRenamesUnclosedFile) {
  const std::string path = file("run.h5");
  {
    Hdf5Writer w(path, {});
    SmallRun(0.0).write(w, 0, 0.0);
  }
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".part"));
  EXPECT_TRUE(fs::exists(file("run.xdmf")));
  EXPECT_TRUE(fs::exists(file("run_membranes.xdmf")));
}

TEST_F(IoTest, Hdf5WriterRejectsMismatchedSizes) {
  Hdf5Writer w(file("bad.h5"), {});
  const SmallRun r(0.0);
  const Vec short_p = Vec::Zero(9);
  EXPECT_THROW(w.write_snapshot(0, 0.0, r.x, {{"p", &short_p}}, {}), std::invalid_argument);
  EXPECT_THROW(w.write_snapshot(0, 0.0, r.x, {{"x", &r.u}}, {}), std::invalid_argument);
  EXPECT_THROW(w.write_snapshot(0, 0.0, r.x, {{"velocity", &r.u}}, {}), std::invalid_argument);
  EXPECT_THROW(w.write_snapshot(0, 0.0, r.x, {{"p", &r.p}, {"p", &r.u}}, {}), std::invalid_argument);
  const Vec short_T = Vec::Zero(5);
  EXPECT_THROW(w.write_snapshot(0, 0.0, r.x, {}, {MembraneSnapshot{&r.X, &r.f, &short_T}}),
               std::invalid_argument);
  EXPECT_THROW(w.write_series("s", {"a", "b"}, {{1.0}}), std::invalid_argument);
  EXPECT_EQ(w.num_snapshots(), 0);
  w.close();
  EXPECT_THROW(r.write(w, 0, 0.0), std::logic_error);
}

TEST_F(IoTest, UnwritableDirectoryThrowsNamingThePath) {
  const std::string h5 = "/proc/forbidden/x.h5";
  try {
    Hdf5Writer w(h5, small_attrs());
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(h5), std::string::npos) << e.what();
  }
  try {
    CsvWriter c("/proc/forbidden/d.csv", {"t"});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/forbidden/d.csv"), std::string::npos) << e.what();
  }
  try {
    write_json_atomic("/proc/forbidden/s.json", nlohmann::json{{"a", 1}});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/forbidden/s.json"), std::string::npos) << e.what();
  }
}

TEST_F(IoTest, DiskFullThrowsNamingThePath) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  // The .part file is a symlink to /dev/full: every write fails with ENOSPC.
  fs::create_symlink("/dev/full", file("full.csv.part"));
  try {
    CsvWriter w(file("full.csv"), {"t", "e"});
    w.row({1.0, 2.0});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file("full.csv")), std::string::npos) << e.what();
  }

  fs::create_symlink("/dev/full", file("full.h5.part"));
  try {
    Hdf5Writer w(file("full.h5"), small_attrs());
    SmallRun(0.0).write(w, 0, 0.0);
    w.close();
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file("full.h5")), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(file("full.h5")));
}

TEST_F(IoTest, CsvWriterRoundTripFullPrecision) {
  const std::string path = file("diagnostics.csv");
  const std::vector<std::vector<double>> rows = {
      {0.0, 0.1, 1.0 / 3.0}, {1e-300, -2.5e17, M_PI}, {3.0, std::nan(""), 4.0}};
  {
    CsvWriter w(path, {"t", "m0_rx", "kinetic_energy"});
    for (const auto& r : rows) w.row(r);
    EXPECT_THROW(w.row({1.0}), std::invalid_argument);
    EXPECT_TRUE(fs::exists(path + ".part"));
    EXPECT_FALSE(fs::exists(path));
    // flushed every row: the .part file already holds header and rows
    EXPECT_EQ(count(slurp(path + ".part"), "\n"), 4);
    w.close();
  }
  EXPECT_FALSE(fs::exists(path + ".part"));
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,m0_rx,kinetic_energy");
  for (const auto& r : rows) {
    ASSERT_TRUE(std::getline(in, line));
    std::stringstream s(line);
    std::string cell;
    for (double expected : r) {
      ASSERT_TRUE(std::getline(s, cell, ','));
      const double got = std::strtod(cell.c_str(), nullptr);
      if (std::isnan(expected)) EXPECT_TRUE(std::isnan(got)) << cell;
      else EXPECT_EQ(got, expected) << cell;  // bit-exact round trip
    }
  }
  EXPECT_FALSE(std::getline(in, line));
}

TEST_F(IoTest, JsonAtomicRoundTripWithNonFiniteAsNull) {
  const std::string path = file("summary.json");
  nlohmann::json j;
  j["pressure_jump_exact"] = 4.0;
  j["area_rel_error"] = std::numeric_limits<double>::quiet_NaN();
  j["rate"] = std::numeric_limits<double>::infinity();
  j["scene"] = "circle";
  j["rx"] = {0.1, 0.2};
  write_json_atomic(path, j);
  EXPECT_FALSE(fs::exists(path + ".part"));
  const std::string text = slurp(path);
  EXPECT_NE(text.find("\n  \""), std::string::npos);  // pretty, indent 2
  const auto back = nlohmann::json::parse(text);
  EXPECT_EQ(back["pressure_jump_exact"].get<double>(), 4.0);
  EXPECT_TRUE(back["area_rel_error"].is_null());
  EXPECT_TRUE(back["rate"].is_null());
  EXPECT_EQ(back["scene"], "circle");
  EXPECT_EQ(back["rx"][1].get<double>(), 0.2);
  write_json_atomic(path, nlohmann::json{{"a", 1}});  // replaces an existing file
  EXPECT_EQ(nlohmann::json::parse(slurp(path))["a"], 1);
}

// A restart into its own directory continues the earlier file: its snapshots before the resume step
// are kept, later ones dropped (written again), the attributes and series replaced, the XDMF lists
// every snapshot; the earlier file stays as it was until close().
TEST_F(IoTest, Hdf5WriterResumesAnEarlierFileOfTheSameRun) {
  const std::string path = file("run.h5");
  {
    Hdf5Writer w(path, {{{"run_id", "r1"}, {"time.end", "0.3"}}, {}});
    for (int k = 0; k < 4; ++k) SmallRun(0.1 * k).write(w, 10 * k, 0.1 * k);
    w.write_series("diagnostics", {"t"}, {{0.0}, {0.3}});
    w.close();
  }
  EXPECT_EQ(root_text_attribute(path, "run_id"), "r1");
  EXPECT_TRUE(snapshots_readable(path));
  const auto before = fs::file_size(path);
  {
    Hdf5Writer w(path, {{{"run_id", "r1"}, {"time.end", "0.5"}}, {}}, path, 20);  // the checkpoint of step 20
    EXPECT_EQ(w.num_snapshots(), 2);                                              // steps 0 and 10 kept
    EXPECT_EQ(fs::file_size(path), before);                                       // untouched until close
    for (int k = 2; k < 6; ++k) SmallRun(0.1 * k).write(w, 10 * k, 0.1 * k);
    w.write_series("diagnostics", {"t"}, {{0.0}, {0.5}});
    w.close();
  }
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  EXPECT_EQ(root_text_attribute(path, "time.end"), "0.5");
  H5G_info_t gi;
  const hid_t g = H5Gopen2(f, "snapshots", H5P_DEFAULT);
  H5Gget_info(g, &gi);
  EXPECT_EQ(gi.nlinks, 6u);
  for (int k = 0; k < 6; ++k) {
    char name[16];
    std::snprintf(name, sizeof name, "%06d", k);
    int step = -1;
    const hid_t a = H5Aopen_by_name(g, name, "step", H5P_DEFAULT, H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_INT, &step);
    H5Aclose(a);
    EXPECT_EQ(step, 10 * k) << name;
  }
  std::vector<hsize_t> dims;
  EXPECT_EQ(read_dataset<double>(f, "/diagnostics/diagnostics", &dims)[1], 0.5);
  H5Gclose(g);
  H5Fclose(f);
  EXPECT_EQ(count(slurp(file("run.xdmf")), "<Time Value="), 6);
  EXPECT_EQ(count(slurp(file("run_membranes.xdmf")), "<Time Value="), 6);
}

// abandon() closes without completing: the .part stays, the final name is never written.
TEST_F(IoTest, AbandonedWritersLeaveOnlyTheirPartFiles) {
  {
    Hdf5Writer w(file("a.h5"), small_attrs());
    SmallRun(0.0).write(w, 0, 0.0);
    w.abandon();
    CsvWriter c(file("a.csv"), {"t"});
    c.row({1.0});
    c.abandon();
  }
  EXPECT_TRUE(fs::exists(file("a.h5.part")));
  EXPECT_TRUE(fs::exists(file("a.csv.part")));
  EXPECT_FALSE(fs::exists(file("a.h5")));
  EXPECT_FALSE(fs::exists(file("a.csv")));
  EXPECT_FALSE(fs::exists(file("a.xdmf")));
}
