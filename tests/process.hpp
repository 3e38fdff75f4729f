#pragma once
// What the reliability and data-safety tests share: the `sphib` command run in a shell or spawned,
// its exit status, and the small oscillating membrane run in process.
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "helpers.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"

extern char** environ;

namespace sphib_test {

// The arguments quoted for a shell command line.
inline std::string command(const std::vector<std::string>& args) {
  std::string c;
  for (const auto& a : args) c += "'" + a + "' ";
  return c;
}

struct Exit {
  int status = -1;  // the exit status, or 128 + the signal that ended it
  std::string err;
};

// Runs a command line (its stderr captured in tmp/stderr.txt).
inline Exit shell(const std::string& cmd, const std::filesystem::path& tmp) {
  const std::filesystem::path err = tmp / "stderr.txt";
  const int s = std::system((cmd + " 2> '" + err.string() + "'").c_str());
  return {WIFEXITED(s) ? WEXITSTATUS(s) : 128 + WTERMSIG(s), slurp(err)};
}

// Starts the sphib command with `args` (args[0] is its path) without waiting for it.
inline pid_t spawn(std::vector<std::string> args) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  posix_spawn(&pid, SPHIB_BINARY, nullptr, nullptr, argv.data(), environ);
  return pid;
}

// Waits for a spawned process: its exit status, or 128 + the signal that ended it.
inline int reap(pid_t pid) {
  int s = 0;
  waitpid(pid, &s, 0);
  return WIFEXITED(s) ? WEXITSTATUS(s) : 128 + WTERMSIG(s);
}

// Whether `p` exists within `seconds`.
inline bool wait_for(const std::filesystem::path& p, double seconds) {
  for (auto t0 = std::chrono::steady_clock::now(); std::chrono::steady_clock::now() - t0 < std::chrono::duration<double>(seconds);
       std::this_thread::sleep_for(std::chrono::milliseconds(5)))
    if (std::filesystem::exists(p)) return true;
  return false;
}

// `sphib run` of the small oscillating membrane into `out` (--quiet), `more` as --set after kSmall.
inline std::vector<std::string> run_args(const std::filesystem::path& out, const std::vector<std::string>& more) {
  std::vector<std::string> a{SPHIB_BINARY, "run", kOscillation, "--out", out.string(), "--quiet"};
  for (const auto& s : kSmall) a.insert(a.end(), {"--set", s});
  for (const auto& s : more) a.insert(a.end(), {"--set", s});
  return a;
}

// A run of the small oscillating membrane in process, `sets` after kSmall, optionally a restart.
inline nlohmann::json run_small(const std::filesystem::path& dir, std::vector<std::string> sets, const std::string& restart = "") {
  sets.insert(sets.begin(), kSmall.begin(), kSmall.end());
  sphib::RunOptions o;
  o.out_dir = dir.string();
  o.restart = restart;
  return sphib::run_scene(sphib::load_scene(kOscillation, sets), o);
}

}  // namespace sphib_test
