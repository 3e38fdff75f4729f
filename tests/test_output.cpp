// What a run writes about its membranes: the t = 0 snapshot holds the initial force density and
// tension (a stretched membrane starts under tension), and every snapshot's f and T belong to the
// markers written beside them.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "io/run.hpp"
#include "io/scene.hpp"
#include "membrane/force.hpp"

namespace fs = std::filesystem;
using namespace sphib;

namespace {

// A row-major double dataset as an Eigen matrix of the given width.
Eigen::MatrixXd read(hid_t f, const std::string& name, int cols) {
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(d, 0) << name;
  const hid_t s = H5Dget_space(d);
  const hssize_t n = H5Sget_simple_extent_npoints(s);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> m(n / cols, cols);
  EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.data()), 0) << name;
  H5Sclose(s);
  H5Dclose(d);
  return m;
}

}  // namespace

TEST(Output, SnapshotsHoldTheMembraneForceAndTensionOfTheirMarkers) {
  const fs::path dir = fs::temp_directory_path() / ("sphib_output_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const Scene scene = load_scene(std::string(SPHIB_SOURCE_DIR) + "/cases/membrane_oscillation.toml",
                                 {"grid.nx=32", "grid.ny=32", "membrane.nb=64", "time.dt=4e-4", "time.end=0.02",
                                  "output.interval=0.01"});
  {
    const Simulation sim(scene.sim);  // before any step: the initial force
    EXPECT_GT(sim.membranes()[0].T.maxCoeff(), 1.0);
    EXPECT_GT(sim.membranes()[0].f.norm(), 1.0);
  }
  RunOptions opt;
  opt.out_dir = dir.string();
  run_scene(scene, opt);
  const hid_t f = H5Fopen((dir / "output.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const MembraneScene& ms = scene.membranes[0];
  MembraneForce hooke(scene.sim.membranes[0].membrane);
  for (const char* g : {"/snapshots/000000", "/snapshots/000001", "/snapshots/000002"}) {
    const Mat2 X = read(f, std::string(g) + "/membrane_0/X", 2);
    const Mat2 fk = read(f, std::string(g) + "/membrane_0/f", 2);
    const Vec T = read(f, std::string(g) + "/membrane_0/T", 1);
    Mat2 f_ref;
    Vec T_ref;
    hooke.compute(X, f_ref, T_ref);
    // The ellipse rx = 0.75, ry = 0.5 on a rest circle r0 = 0.5 is stretched by 5-50%: T0 = 10.
    EXPECT_GT(T.maxCoeff(), 4.0) << g;
    EXPECT_GT(fk.rowwise().norm().maxCoeff(), 5.0) << g;
    EXPECT_EQ((T - T_ref).cwiseAbs().maxCoeff(), 0.0) << g;  // the same computation: bit for bit
    EXPECT_EQ((fk - f_ref).cwiseAbs().maxCoeff(), 0.0) << g;
  }
  H5Fclose(f);
  fs::remove_all(dir);
}
