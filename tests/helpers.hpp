#pragma once
// What several test files share: the small oscillating membrane runs of the reliability tests, fresh
// temporary directories, a file's text.
#include <unistd.h>

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sphib_test {

// cases/membrane_oscillation.toml at 24 x 24, 48 markers, dt = 1e-3: a step in well under a millisecond.
inline const std::string kOscillation = std::string(SPHIB_SOURCE_DIR) + "/cases/membrane_oscillation.toml";
inline const std::vector<std::string> kSmall{"grid.nx=24", "grid.ny=24", "membrane.nb=48", "time.dt=1e-3"};

// The smallest valid scene (16 x 16, Stokes-free defaults): tests append the tables they test.
inline const char* const kMinimalScene = R"(
[grid]
nx = 16
ny = 16
[fluid]
rho = 1.0
mu = 1.0
[time]
dt = 0.001
end = 0.01
)";

// A smooth asymmetric closed curve of nb markers (no symmetry to cancel errors), anticlockwise.
inline Eigen::Matrix<double, Eigen::Dynamic, 2> blob(int nb) {
  Eigen::Matrix<double, Eigen::Dynamic, 2> X(nb, 2);
  for (int k = 0; k < nb; ++k) {
    const double th = 2.0 * 3.14159265358979323846 * k / nb;
    const double r = 0.6 + 0.08 * std::cos(2 * th + 0.3) + 0.05 * std::sin(3 * th);
    X(k, 0) = 0.2 + 1.1 * r * std::cos(th);
    X(k, 1) = -0.1 + r * std::sin(th);
  }
  return X;
}

// An empty directory of its own under the system's temporary directory (this process, this name).
inline std::filesystem::path temp_dir(const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path d = fs::temp_directory_path() / ("sphib_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace sphib_test
