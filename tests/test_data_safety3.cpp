// Data safety, round three (issue 26): the reproducers of items 1-12, each as a test. Checkpoints
// are sealed and verified, a restart reads its scene from the checkpoint, sweeps are keyed by the
// scene, recursive parsers have depth limits, the lock is never written through a link, every
// terminating signal ends a run as SIGTERM does, and a failing run leaves no file under its final
// name. (Item 13's tests are in test_regression.cpp; the refused scenes in tests/bad_scenes.)
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/expression.hpp"
#include "app/sweep.hpp"
#include "helpers.hpp"
#include "process.hpp"
#include "io/checkpoint.hpp"
#include "io/footprint.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"
#include "membrane/polygon.hpp"
#include "membrane/shapes.hpp"
#include "scene_refusal.hpp"

using namespace sphib;
namespace fs = std::filesystem;

namespace {

using sphib_test::kSmall;
using sphib_test::slurp;
using sphib_test::temp_dir;
using sphib_test::command;
using sphib_test::Exit;
using sphib_test::reap;
using sphib_test::shell;
using sphib_test::spawn;
using sphib_test::wait_for;
using sphib_test::run_args;
using sphib_test::run_small;
const std::string& kScene = sphib_test::kOscillation;

nlohmann::json summary(const fs::path& dir) { return nlohmann::json::parse(slurp(dir / "summary.json")); }

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const fs::path& p, const std::string& b) { std::ofstream(p, std::ios::binary) << b; }

// Overwrites one value of a dataset of an HDF5 file in place (then the checkpoint's seal no longer holds).
void set_value(const fs::path& file, const char* dataset, int index, double value) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(f, dataset, H5P_DEFAULT);
  const hid_t sp = H5Dget_space(ds);
  std::vector<double> v(static_cast<size_t>(H5Sget_simple_extent_npoints(sp)));
  H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  v[static_cast<size_t>(index)] = value;
  H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(sp);
  H5Dclose(ds);
  H5Fclose(f);
}

std::string checkpoint_refusal(const fs::path& p) {
  try {
    read_checkpoint(p.string());
  } catch (const CheckpointError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// Item 1: a restart into the run's own directory deleted output.h5 (every snapshot before the
// restart) when that file was open for writing elsewhere or truncated. It is refused now, the file
// as it was.
TEST(DataSafety3, ARestartIntoItsOwnDirectoryNeverRemovesAnOutputItCannotRead) {
  const fs::path tmp = temp_dir("own_dir"), d = tmp / "D";
  run_small(d, {"time.end=0.02"});
  const std::string whole = bytes(d / "output.h5");
  const auto restart = [&] {
    return shell(command(run_args(d, {"time.end=0.04", "output.interval=0.01"})) + " --restart '" +
                     (d / "checkpoint.h5").string() + "'",
                 tmp);
  };
  // Open for writing by another program (HDF5 file locking), as h5py's 'r+' holds it.
  const hid_t f = H5Fopen((d / "output.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  Exit e = restart();
  H5Fclose(f);
  EXPECT_EQ(e.status, 2) << e.err;
  EXPECT_NE(e.err.find("output.h5 cannot be read (open for writing by another program, truncated or damaged)"),
            std::string::npos) << e.err;
  EXPECT_TRUE(fs::exists(d / "output.h5"));
  // Truncated.
  write_bytes(d / "output.h5", whole.substr(0, whole.size() / 2));
  e = restart();
  EXPECT_EQ(e.status, 2) << e.err;
  EXPECT_EQ(bytes(d / "output.h5"), whole.substr(0, whole.size() / 2));
  EXPECT_TRUE(fs::exists(d / "summary.json"));  // nothing of the earlier run removed
  // Whole again: the restart continues it.
  write_bytes(d / "output.h5", whole);
  e = restart();
  EXPECT_EQ(e.status, 0) << e.err;
  EXPECT_EQ(summary(d)["steps"], 40);
  fs::remove_all(tmp);
}

// Item 2: a second sweep into the same DIR reused DIR/run_NNN by index (another fluid.mu, other
// values, another time.end: the old numbers under the new labels), and --set of the varied key won
// silently over --vary. Runs are reused only for the same scene (its hash), and the --set is refused.
TEST(DataSafety3, SweepsReuseARunOnlyForTheSameSceneAndRefuseASetOfAVariedKey) {
  const fs::path tmp = temp_dir("sweep");
  app::SweepOptions o;
  o.scene = std::string(SPHIB_SOURCE_DIR) + "/cases/couette.toml";
  o.out = (tmp / "sw").string();
  o.vary = {"grid.nx=8,12"};
  o.derive = {"grid.ny={grid.nx}"};
  o.set = {"time.max_steps=3", "time.dt=1e-3"};
  o.report = {"kinetic_energy"};
  auto energies = [&] {
    const app::SweepResult r = app::run_sweep(o);
    const std::string csv = slurp(tmp / "sw" / "sweep.csv");
    return std::make_pair(r, csv);
  };
  const auto [first, csv1] = energies();
  EXPECT_EQ(first.runs, 2);
  EXPECT_EQ(first.reused, 0);
  const auto [again, csv2] = energies();  // the same sweep: both reused, the same table
  EXPECT_EQ(again.reused, 2);
  EXPECT_EQ(csv1.substr(0, csv1.rfind("run_")), csv2.substr(0, csv2.rfind("run_")));
  o.set = {"time.max_steps=3", "time.dt=1e-3", "fluid.mu=0.25"};  // another scene: run again
  const auto [other, csv3] = energies();
  EXPECT_EQ(other.reused, 0);
  EXPECT_EQ(other.runs, 2);
  const nlohmann::json s0 = summary(tmp / "sw" / "run_000");
  EXPECT_EQ(s0["scene_hash"], scene_hash(load_scene(o.scene, {"grid.nx=8", "grid.ny=8", "time.max_steps=3", "time.dt=1e-3",
                                                               "fluid.mu=0.25"})));
  o.set = {"time.max_steps=4", "time.dt=1e-3", "fluid.mu=0.25"};  // another length: run again
  EXPECT_EQ(energies().first.reused, 0);
  EXPECT_EQ(summary(tmp / "sw" / "run_001")["steps"], 4);
  // --set of a varied (or derived) key: refused before anything runs.
  o.set = {"grid.nx=16"};
  try {
    app::run_sweep(o);
    ADD_FAILURE() << "--set of the varied key was accepted";
  } catch (const app::UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--set grid.nx: the key is varied (--vary grid.nx)"), std::string::npos) << e.what();
  }
  o.set = {"grid.ny=16"};
  EXPECT_THROW(app::run_sweep(o), app::UsageError);
  fs::remove_all(tmp);
}

// Item 3: one flipped exponent bit in a marker coordinate ran (kinetic energy 2.13 instead of
// 0.118), and a clock t = 100 at step 300 ran to t = 100.3. The seal refuses every changed bit, and
// the clock must be its steps of dt.
TEST(DataSafety3, CheckpointsAreVerifiedBitForBitAndTheirClockAgainstStepsAndDt) {
  const fs::path tmp = temp_dir("sealed");
  run_small(tmp / "a", {"time.end=0.02"});
  const fs::path ckpt = tmp / "a" / "checkpoint.h5";
  EXPECT_EQ(checkpoint_refusal(ckpt), "");
  const std::string good = bytes(ckpt);
  // Every one of 300 random single-bit flips, anywhere in the file, is refused before HDF5 reads it.
  std::mt19937_64 rng(26);
  int refused = 0;
  for (int k = 0; k < 300; ++k) {
    std::string b = good;
    const size_t bit = rng() % (8 * b.size());
    b[bit / 8] = static_cast<char>(b[bit / 8] ^ (1 << (bit % 8)));
    write_bytes(tmp / "flip.h5", b);
    const std::string why = checkpoint_refusal(tmp / "flip.h5");
    refused += !why.empty();
    EXPECT_FALSE(why.empty()) << "bit " << bit << " flipped was accepted";
  }
  EXPECT_EQ(refused, 300);
  // And bits of the seal itself (its first line, the digest, the zeros after it).
  for (size_t bit = 3; bit < 8 * 512; bit += 61) {
    std::string b = good;
    b[bit / 8] = static_cast<char>(b[bit / 8] ^ (1 << (bit % 8)));
    write_bytes(tmp / "flip.h5", b);
    EXPECT_FALSE(checkpoint_refusal(tmp / "flip.h5").empty()) << "seal bit " << bit << " flipped was accepted";
  }
  // The reproducer: a marker coordinate's exponent bit, changed through HDF5.
  fs::copy_file(ckpt, tmp / "marker.h5");
  set_value(tmp / "marker.h5", "/membranes/0", 3, 0.5 * 1024);
  EXPECT_NE(checkpoint_refusal(tmp / "marker.h5").find("damaged: its SHA-256"), std::string::npos);
  // A clock of t = 100 at step 20 (sealed anew, as a deliberate edit would be): refused at restore.
  fs::copy_file(ckpt, tmp / "clock.h5");
  set_value(tmp / "clock.h5", "/fluid/clock", 0, 100.0);
  seal_checkpoint((tmp / "clock.h5").string());
  try {
    run_small(tmp / "b", {"time.end=0.6"}, (tmp / "clock.h5").string());
    ADD_FAILURE() << "a clock of t = 100 at step 20 was accepted";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("its clock is not valid: t = 100 at step 20 is not 20 steps of time.dt = 0.001"),
              std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(tmp / "b"));
  // The untouched checkpoint restarts.
  EXPECT_EQ(run_small(tmp / "c", {"time.end=0.03"}, ckpt.string())["steps"], 30);
  fs::remove_all(tmp);
}

// Issue 25's restart item: `sphib run --restart DIR/checkpoint.h5` alone takes the checkpoint's
// scene; --set only of keys a restart may change; a scene file given too must agree.
TEST(DataSafety3, ARestartFromTheCheckpointAloneContinuesItsSceneBitForBit) {
  const fs::path tmp = temp_dir("alone");
  run_small(tmp / "a", {"time.end=0.02"});
  run_small(tmp / "straight", {"time.end=0.04", "output.diagnostics_every=1"});
  const std::string ckpt = (tmp / "a" / "checkpoint.h5").string();
  const std::string base = std::string(SPHIB_BINARY) + " run --restart '" + ckpt + "' --quiet";
  Exit e = shell(base + " --out '" + (tmp / "alone").string() + "' --set time.end=0.04 --set output.diagnostics_every=1", tmp);
  ASSERT_EQ(e.status, 0) << e.err;
  e = shell(command(run_args(tmp / "with_file", {"time.end=0.04", "output.diagnostics_every=1"})) + " --restart '" + ckpt + "'", tmp);
  ASSERT_EQ(e.status, 0) << e.err;
  const std::string last_straight = slurp(tmp / "straight" / "diagnostics.csv");
  const std::string last_alone = slurp(tmp / "alone" / "diagnostics.csv");
  EXPECT_EQ(last_alone, slurp(tmp / "with_file" / "diagnostics.csv"));
  EXPECT_EQ(last_straight.substr(last_straight.rfind("\n0.04")), last_alone.substr(last_alone.rfind("\n0.04")));
  EXPECT_EQ(summary(tmp / "alone")["scene_hash"], summary(tmp / "with_file")["scene_hash"]);
  // A key a restart may not change, named; a scene file that disagrees, named; nothing written.
  e = shell(base + " --out '" + (tmp / "mu").string() + "' --set fluid.mu=0.5", tmp);
  EXPECT_EQ(e.status, 2) << e.err;
  EXPECT_NE(e.err.find("--set fluid.mu: a restart keeps the checkpoint's scene"), std::string::npos) << e.err;
  e = shell(command(run_args(tmp / "other", {"time.end=0.04", "membrane.T0=2"})) + " --restart '" + ckpt + "'", tmp);
  EXPECT_EQ(e.status, 2) << e.err;
  EXPECT_NE(e.err.find("its scene does not match: membrane.T0"), std::string::npos) << e.err;
  EXPECT_FALSE(fs::exists(tmp / "mu"));
  EXPECT_FALSE(fs::exists(tmp / "other"));
  // [[membranes]], one of them a point list, and arrays of numbers and strings: the checkpoint's
  // values read back as the same scene (the same hash, the same numbers).
  std::ofstream(tmp / "two.toml") << R"(title = "two \"membranes\""
[domain]
x = [0.0, 2.0]
y = [0.0, 2.0]
[grid]
nx = 32
ny = 32
[fluid]
rho = 1.0
mu = 0.1
[time]
dt = 1e-3
end = 0.01
[output]
fields = ["u", "p"]
times = [0.005]
[[membranes]]
r0 = 0.3
T0 = 1.0
nb = 64
centre = [0.5, 1.0]
[[membranes]]
shape = "points"
points = [[1.2, 0.8], [1.8, 0.8], [1.8, 1.2], [1.5, 1.4], [1.2, 1.2]]
r0 = 0.25
T0 = 2.0
nb = 64
)";
  const std::string two = std::string(SPHIB_BINARY) + " run '" + (tmp / "two.toml").string() + "' --quiet --out ";
  ASSERT_EQ(shell(two + "'" + (tmp / "t1").string() + "'", tmp).status, 0);
  ASSERT_EQ(shell(two + "'" + (tmp / "t2").string() + "' --set time.end=0.02", tmp).status, 0);
  e = shell(std::string(SPHIB_BINARY) + " run --quiet --restart '" + (tmp / "t1" / "checkpoint.h5").string() + "' --out '" +
                (tmp / "t3").string() + "' --set time.end=0.02",
            tmp);
  ASSERT_EQ(e.status, 0) << e.err;
  const std::string straight = slurp(tmp / "t2" / "diagnostics.csv"), restarted = slurp(tmp / "t3" / "diagnostics.csv");
  EXPECT_EQ(straight.substr(straight.rfind("\n0.02")), restarted.substr(restarted.rfind("\n0.02")));
  EXPECT_EQ(summary(tmp / "t2")["scene_hash"], summary(tmp / "t3")["scene_hash"]);
  fs::remove_all(tmp);
}

// Item 4: membranes crossing through a periodic side were accepted, and a membrane wider than the
// period; the same pair inside the domain was refused.
TEST(DataSafety3, MembranesMeetingAcrossAPeriodicSideAreRefused) {
  const std::string base = R"(
[domain]
x = [0.0, 2.0]
y = [0.0, 2.0]
periodic_x = true
[grid]
nx = 32
ny = 32
[fluid]
rho = 1.0
mu = 0.1
[time]
dt = 1e-3
end = 0.01
)";
  auto two = [&](double c0, double c1) {
    std::ostringstream s;
    s << base << "[[membranes]]\nr0 = 0.4\nT0 = 1.0\nnb = 64\ncentre = [" << c0 << ", 1.0]\n[[membranes]]\nr0 = 0.4\nT0 = 1.0\nnb = 64\ncentre = ["
      << c1 << ", 1.0]\n";
    return test::refusal(s.str());
  };
  EXPECT_NE(two(0.2, 1.8).find("membranes[1]: membrane 1's periodic image crosses or touches membrane 0"), std::string::npos)
      << two(0.2, 1.8);
  EXPECT_NE(two(0.8, 1.2).find("membrane 1 crosses or touches membrane 0"), std::string::npos);  // inside: as before
  EXPECT_EQ(two(0.5, 1.5), "");  // apart both ways
  // One membrane across the seam is fine; one as wide as the period is not.
  EXPECT_EQ(test::refusal(base + "[membrane]\nr0 = 0.4\nT0 = 1.0\nnb = 64\ncentre = [0.1, 1.0]\n"), "");
  const std::string wide = test::refusal(base + "[membrane]\nr0 = 0.5\nT0 = 1.0\nnb = 64\nshape = \"ellipse\"\nrx = 1.2\nry = 0.3\n"
                                                "centre = [1.0, 1.0]\n");
  EXPECT_NE(wide.find("membrane: membrane 0 is 2.4 wide along the periodic x axis, not less than its period 2"),
            std::string::npos) << wide;
}

// Item 5: a dotted key of 15 000 parts (in the file or via --set) and 30 000 nested parentheses in
// --derive overflowed the stack (SIGSEGV). Each is refused with a message.
TEST(DataSafety3, DeepInputIsRefusedNotAStackOverflow) {
  std::string key = "a";
  for (int k = 0; k < 15000; ++k) key += ".a";
  const std::string text = "title = \"deep\"\n" + key + " = 1\n";
  EXPECT_NE(test::refusal(text).find("scene.toml:2: a key of 15001 dotted parts"), std::string::npos) << test::refusal(text).substr(0, 200);
  EXPECT_NE(test::refusal("[" + key + "]\nb = 1\n").find("a key of 15001 dotted parts"), std::string::npos);
  EXPECT_NE(test::refusal("x = {" + key + " = 1}\n").find("a key of 15001 dotted parts"), std::string::npos);
  std::string quoted_key = "\"a\"";
  for (int k = 0; k < 100; ++k) quoted_key += ".\"a\"";
  EXPECT_NE(test::refusal(quoted_key + " = 1\n").find("a key of 101 dotted parts"), std::string::npos);
  EXPECT_EQ(test::refusal("title = \"" + key + "\"\n").find("dotted parts"), std::string::npos);  // a string value
  EXPECT_NE(test::refusal("title = \"x\"\n", {key + "=1"}).find("--set a.a.a"), std::string::npos);
  // A deep key inside a multi-line string is text, not a key.
  const std::string in_string = "title = \"\"\"\n" + key + " = 1\n\"\"\"\n";
  EXPECT_EQ(test::refusal(in_string).find("dotted parts"), std::string::npos);
  const std::string parens = std::string(30000, '(') + "1" + std::string(30000, ')');
  try {
    app::evaluate(parens);
    ADD_FAILURE() << "30 000 parentheses evaluated";
  } catch (const app::ExpressionError& e) {
    EXPECT_NE(std::string(e.what()).find("nested more than 200 deep"), std::string::npos) << e.what();
  }
  EXPECT_THROW(app::evaluate(std::string(30000, '-') + "1"), app::ExpressionError);
  EXPECT_EQ(app::evaluate(std::string(150, '(') + "2" + std::string(150, ')')).value, 2.0);  // deep enough for any use
}

// Item 6: a .sphib.lock that was a symbolic or a hard link to a user's file: that file was truncated
// and overwritten. The run is refused and the file keeps its content.
TEST(DataSafety3, TheLockIsNeverWrittenThroughALink) {
  const fs::path tmp = temp_dir("lock_links"), d = tmp / "D";
  fs::create_directories(d);
  write_bytes(tmp / "precious.txt", "the user's data\n");
  fs::create_symlink(tmp / "precious.txt", d / ".sphib.lock");
  Exit e = shell(command(run_args(d, {"time.max_steps=2"})), tmp);
  EXPECT_EQ(e.status, 2) << e.err;
  EXPECT_NE(e.err.find(".sphib.lock is a symbolic link (not a sphib lock"), std::string::npos) << e.err;
  EXPECT_EQ(slurp(tmp / "precious.txt"), "the user's data\n");
  fs::remove(d / ".sphib.lock");
  fs::create_hard_link(tmp / "precious.txt", d / ".sphib.lock");
  e = shell(command(run_args(d, {"time.max_steps=2"})), tmp);
  EXPECT_EQ(e.status, 2) << e.err;
  EXPECT_NE(e.err.find("has 2 names (a hard link to another file)"), std::string::npos) << e.err;
  EXPECT_EQ(slurp(tmp / "precious.txt"), "the user's data\n");
  EXPECT_FALSE(fs::exists(d / "output.h5"));
  fs::remove(d / ".sphib.lock");
  EXPECT_EQ(shell(command(run_args(d, {"time.max_steps=2"})), tmp).status, 0);  // a plain lock again
  fs::remove_all(tmp);
}

// Item 7: the memory estimate ignored the markers (nb = 1e6: estimated 52 MB, peak 583 MB).
TEST(DataSafety3, TheMemoryEstimateCountsTheMarkers) {
  std::vector<std::string> sets{"membrane.nb=1000000"};
  const MemoryEstimate many = estimate_memory(load_scene(kScene, sets));
  const MemoryEstimate few = estimate_memory(load_scene(kScene));
  // Measured peaks (docs/data_safety.md, "Memory"): 583 MB at nb = 1e6 on the 64^2 lattice; the
  // estimate must not fall below it.
  EXPECT_GT(many.bytes, 583e6);
  EXPECT_LT(many.bytes, 2 * 583e6);
  EXPECT_EQ(many.marker_count, 1000000);
  EXPECT_EQ(few.marker_count, 128);
  EXPECT_LT(few.markers, 1e6);
}

// Item 8: a failing run left files under their final names (ulimit -n 5: output.h5 with no snapshot
// and output.xdmf, exit 1), and removing an earlier run's files was not all or nothing.
TEST(DataSafety3, AFailingRunLeavesNoFileUnderItsFinalName) {
  const fs::path tmp = temp_dir("final_names"), d = tmp / "D";
  for (int n = 5; n <= 8; ++n) {  // too few descriptors at each point of the set-up (4: the loader fails)
    fs::remove_all(d);
    const Exit e = shell("bash -c \"ulimit -n " + std::to_string(n) + "; exec " + command(run_args(d, {"time.max_steps=3"})) + "\"", tmp);
    SCOPED_TRACE("ulimit -n " + std::to_string(n) + ": exit " + std::to_string(e.status) + ": " + e.err);
    if (e.status == 0) continue;
    EXPECT_TRUE(e.status == 1 || e.status == 2);
    for (const char* f : {"output.h5", "output.xdmf", "output_membranes.xdmf", "diagnostics.csv", "summary.json"})
      EXPECT_FALSE(fs::exists(d / f)) << f;
  }
  // An inode-starved disk (a tmpfs of a few inodes; mounting needs root, elsewhere this part skips).
  const fs::path mnt = tmp / "mnt";
  fs::create_directories(mnt);
  for (int inodes = 3; inodes <= 9; ++inodes) {
    if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, ("size=8m,nr_inodes=" + std::to_string(inodes)).c_str()) != 0) break;
    const fs::path md = mnt / "D";
    const Exit e = shell(command(run_args(md, {"time.max_steps=3"})), tmp);
    SCOPED_TRACE(std::to_string(inodes) + " inodes: exit " + std::to_string(e.status) + ": " + e.err);
    if (e.status != 0) {
      EXPECT_TRUE(e.status == 1 || e.status == 2);
      for (const char* f : {"output.h5", "output.xdmf", "output_membranes.xdmf", "diagnostics.csv", "summary.json"})
        EXPECT_FALSE(fs::exists(md / f)) << f;
    }
    ::umount(mnt.c_str());
  }
  // An earlier run's files, one of which cannot be removed (a directory under its name): none removed.
  fs::remove_all(d);
  run_small(d, {"time.max_steps=3"});
  fs::remove(d / "summary.json");
  fs::create_directories(d / "summary.json" / "notes");
  const Exit e = shell(command(run_args(d, {"time.max_steps=3"})), tmp);
  EXPECT_EQ(e.status, 2) << e.err;
  EXPECT_NE(e.err.find("summary.json is not a file a run wrote"), std::string::npos) << e.err;
  for (const char* f : {"output.h5", "output.xdmf", "diagnostics.csv", "checkpoint.h5"}) EXPECT_TRUE(fs::exists(d / f)) << f;
  EXPECT_TRUE(fs::exists(d / "summary.json" / "notes"));
  fs::remove_all(tmp);
}

// Item 9: the self-intersection test of membrane.points was quadratic (20k points 7.1 s, 100k > 120 s).
// The sweep (is_simple) agrees with the test of every pair (is_simple_plain) on random small
// polygons with integer corners, where edges touch, overlap and cross in every degenerate way.
TEST(DataSafety3, TheSweepFindsExactlyTheSelfIntersectionsThatEveryPairFinds) {
  std::mt19937 rng(9);
  int simple = 0, total = 0;
  for (int trial = 0; trial < 40000; ++trial) {
    const int n = 3 + static_cast<int>(rng() % 7), grid = 2 + static_cast<int>(rng() % 4);
    Mat2 X(n, 2);
    for (int i = 0; i < n; ++i) X(i, 0) = rng() % grid, X(i, 1) = rng() % grid;
    const bool plain = is_simple_plain(X);
    ASSERT_EQ(is_simple(X), plain) << "polygon " << X.transpose();
    simple += plain;
    ++total;
  }
  EXPECT_GT(simple, total / 50);  // both kinds are tested
  EXPECT_LT(simple, total - total / 50);
  // Large: a 100 000-point circle is simple, the same with one point pulled across is not.
  Mat2 C(100000, 2);
  for (int i = 0; i < C.rows(); ++i) C(i, 0) = std::cos(2 * M_PI * i / C.rows()), C(i, 1) = std::sin(2 * M_PI * i / C.rows());
  EXPECT_TRUE(is_simple(C));
  C.row(500) << -1.5, 0.03;  // its two edges cross the circle's far side
  EXPECT_FALSE(is_simple(C));
  Mat2 c1000 = circle(1000, 0, 0, 1);
  EXPECT_TRUE(is_simple(c1000) && is_simple_plain(c1000));
  c1000.row(5) << -1.5, 0.03;
  EXPECT_FALSE(is_simple(c1000) || is_simple_plain(c1000));
  // from_points at 20 000 points (7.1 s before).
  EXPECT_EQ(from_points(circle(20000, 0, 0, 1), 64).rows(), 64);
}

// Item 10: stop_reason was "end time" when time.max_steps stopped the run; an observer named like a
// summary field replaced it, and one named like a column gave duplicate columns.
TEST(DataSafety3, StopReasonAndObserverNamesTellTheTruth) {
  const fs::path tmp = temp_dir("stop_reason");
  EXPECT_EQ(run_small(tmp / "a", {"time.max_steps=3"})["stop_reason"], "time.max_steps");
  EXPECT_EQ(run_small(tmp / "b", {"time.end=0.003"})["stop_reason"], "end time");
  for (const std::string name : {"stop_reason", "steps", "kinetic_energy", "t"}) {
    Scene s = load_scene(kScene, {"grid.nx=24", "grid.ny=24", "membrane.nb=48", "time.dt=1e-3", "time.max_steps=2"});
    s.observers.push_back({name, [](const Simulation&) { return 42.0; }});
    RunOptions o;
    o.out_dir = (tmp / ("obs_" + name)).string();
    try {
      run_scene(s, o);
      ADD_FAILURE() << "an observer named " << name << " ran";
    } catch (const std::exception& e) {  // SceneError, or std::invalid_argument for a column twice: exit status 2
      EXPECT_TRUE(dynamic_cast<const SceneError*>(&e) || dynamic_cast<const std::invalid_argument*>(&e)) << e.what();
      EXPECT_NE(std::string(e.what()).find("'" + name + "'"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(tmp / ("obs_" + name)));
  }
  fs::remove_all(tmp);
}

// Item 11: HUP, QUIT, USR1, USR2, ALRM and PIPE killed a run leaving only .part files. Each now ends
// it as SIGTERM does: complete files, exit status 128 + n, the signal in the summary.
TEST(DataSafety3, EveryTerminatingSignalEndsARunWithCompleteFiles) {
  const fs::path tmp = temp_dir("signals");
  for (int sig : {SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGPIPE}) {
    const fs::path d = tmp / ("sig" + std::to_string(sig));
    const pid_t pid = spawn(run_args(d, {"time.end=1000", "output.checkpoint_interval=0.005"}));
    ASSERT_TRUE(wait_for(d / "checkpoint.h5", 20)) << "the run did not start";
    kill(pid, sig);
    EXPECT_EQ(reap(pid), 128 + sig) << "signal " << sig;
    const nlohmann::json j = summary(d);
    EXPECT_EQ(j["stop_signal"], sig);
    EXPECT_EQ(j["stop_reason"].get<std::string>().rfind("signal " + std::to_string(sig) + " (SIG", 0), 0u) << j["stop_reason"];
    for (const char* f : {"output.h5", "output.xdmf", "diagnostics.csv", "checkpoint.h5"}) EXPECT_TRUE(fs::exists(d / f)) << f;
    EXPECT_FALSE(fs::exists(d / "output.h5.part"));
  }
  // A finished run whose log's reader has gone exits 0 (it exited 141).
  const fs::path d = tmp / "pipe_log";
  std::vector<std::string> args = run_args(d, {"time.max_steps=30"});
  args.erase(std::find(args.begin(), args.end(), "--quiet"));
  const int s = std::system(("bash -c \"" + command(args) + " 2>&1 | head -c 1 > /dev/null; exit \\${PIPESTATUS[0]}\"").c_str());
  const int status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  const nlohmann::json j = summary(d);
  EXPECT_EQ(status, j.contains("stop_signal") ? 141 : 0) << j.dump();
  EXPECT_TRUE(fs::exists(d / "output.h5"));
  fs::remove_all(tmp);
}

// Item 12: misleading messages and exit statuses.
TEST(DataSafety3, MessagesNameTheRealProblem) {
  const fs::path tmp = temp_dir("messages");
  run_small(tmp / "a", {"time.end=0.02"});
  const std::string restart = std::string(SPHIB_BINARY) + " run --quiet --out '" + (tmp / "b").string() + "' --restart ";
  Exit e = shell(restart + "'" + (tmp / "a" / "output.h5").string() + "'", tmp);  // "older checkpoint format" before
  EXPECT_EQ(e.status, 2);
  EXPECT_NE(e.err.find("a run's output file (its snapshots), not a checkpoint"), std::string::npos) << e.err;
  const hid_t f = H5Fopen((tmp / "a" / "checkpoint.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);  // "missing, or not a checkpoint"
  e = shell(restart + "'" + (tmp / "a" / "checkpoint.h5").string() + "'", tmp);
  H5Fclose(f);
  EXPECT_EQ(e.status, 2);
  EXPECT_NE(e.err.find("locked by another program that has it open for writing"), std::string::npos) << e.err;
  e = shell(restart + "''", tmp);  // ran from scratch
  EXPECT_EQ(e.status, 2);
  EXPECT_NE(e.err.find("--restart: an empty file name"), std::string::npos) << e.err;
  ASSERT_EQ(mkfifo((tmp / "fifo").c_str(), 0600), 0);  // blocked forever holding the lock
  e = shell("timeout 20 " + restart + "'" + (tmp / "fifo").string() + "'", tmp);
  EXPECT_EQ(e.status, 2);
  EXPECT_NE(e.err.find("not a plain file (a directory, a FIFO or a device)"), std::string::npos) << e.err;
  EXPECT_FALSE(fs::exists(tmp / "b"));
  // An analysis's record of the wrong kind (sealed anew): no JSON library text.
  fs::copy_file(tmp / "a" / "checkpoint.h5", tmp / "record.h5");
  {
    const hid_t g = H5Fopen((tmp / "record.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t r = H5Gopen2(g, "run", H5P_DEFAULT);
    H5Adelete(r, "analyses");
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(r, "analyses", type, space, H5P_DEFAULT, H5P_DEFAULT);
    const char* text = "[null, null, {\"area0\": \"text\"}, \"x\", 7]";
    H5Awrite(a, type, &text);
    H5Aclose(a), H5Sclose(space), H5Tclose(type), H5Gclose(r), H5Fclose(g);
  }
  seal_checkpoint((tmp / "record.h5").string());
  e = shell(restart + "'" + (tmp / "record.h5").string() + "' " + command({"--set", "time.end=0.04"}), tmp);
  EXPECT_EQ(e.status, 2) << e.err;
  EXPECT_EQ(e.err.find("json.exception"), std::string::npos) << e.err;
  EXPECT_FALSE(fs::exists(tmp / "b"));
  // Out of memory while setting up: exit status 2, nothing written (it was 1). (Not under
  // AddressSanitizer: its shadow memory needs more address space than the limit leaves.)
#ifndef __SANITIZE_ADDRESS__
  e = shell("bash -c \"ulimit -v 600000; exec " + command(run_args(tmp / "big", {"grid.nx=1400", "grid.ny=1400",
                                                                               "limits.memory_gb=1000"})) + "\"", tmp);
  EXPECT_EQ(e.status, 2) << e.err;
  EXPECT_NE(e.err.find("out of memory while setting up the run"), std::string::npos) << e.err;
  EXPECT_FALSE(fs::exists(tmp / "big" / "output.h5"));
#endif
  fs::remove_all(tmp);
}
