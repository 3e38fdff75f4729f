#pragma once
// What several test files share: the small oscillating membrane runs of the reliability tests, fresh
// temporary directories, a file's text.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sphib_test {

// cases/membrane_oscillation.toml at 24 x 24, 48 markers, dt = 1e-3: a step in well under a millisecond.
inline const std::string kOscillation = std::string(SPHIB_SOURCE_DIR) + "/cases/membrane_oscillation.toml";
inline const std::vector<std::string> kSmall{"grid.nx=24", "grid.ny=24", "membrane.nb=48", "time.dt=1e-3"};

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
