// The adversarial corpus tests/bad_scenes/ (one small scene per file, also the fuzzer's seeds):
// the command refuses every file with exit status 2 and a message holding the fragment its first line
// names (`# expect: fluid.mu: ...`), and writes nothing: the output directory does not appear.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "helpers.hpp"

namespace fs = std::filesystem;

using sphib_test::slurp;

TEST(BadScenes, EveryFileIsRefusedNamingItsKeyAndWritesNothing) {
  const fs::path corpus = fs::path(SPHIB_SOURCE_DIR) / "tests" / "bad_scenes";
  const fs::path tmp = fs::temp_directory_path() / "sphib_bad_scenes";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(corpus))
    if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.filename().string());
    std::string first;
    std::getline(std::ifstream(f) >> std::ws, first);
    const std::string tag = "# expect: ";
    ASSERT_EQ(first.rfind(tag, 0), 0u) << "the first line must be '# expect: <message fragment>'";
    const std::string expect = first.substr(tag.size());
    const fs::path out = tmp / f.stem(), err = tmp / (f.stem().string() + ".err");
    const std::string cmd = std::string(SPHIB_BINARY) + " run " + f.string() + " --out " + out.string() + " --quiet 2> " +
                            err.string();
    const int status = std::system(cmd.c_str());
    const std::string msg = slurp(err);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << "status " << status << ": " << msg;
    EXPECT_NE(msg.find(expect), std::string::npos) << "expected '" << expect << "' in: " << msg;
    EXPECT_FALSE(fs::exists(out)) << "the refused scene wrote " << out;
  }
  EXPECT_GE(files.size(), 60u);
  fs::remove_all(tmp);
}
