#pragma once
// What every benchmark program shares: one-core runs and reading its own CSV back (--keep,
// --report-only). Header-only; the benchmarks are single files.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace sphib::bench {

// Re-executes the program once with OMP_NUM_THREADS=1 and the BLAS equivalents, so that every
// figure it prints is one core's; in the re-executed process it returns at once.
inline void ensure_single_thread(const char* program, char** argv) {
  if (std::getenv("SPHIB_BENCH_SINGLE_THREAD")) return;
  setenv("SPHIB_BENCH_SINGLE_THREAD", "1", 1);
  setenv("OMP_NUM_THREADS", "1", 1);
  setenv("OPENBLAS_NUM_THREADS", "1", 1);
  setenv("MKL_NUM_THREADS", "1", 1);
  setenv("GOTO_NUM_THREADS", "1", 1);
  execv("/proc/self/exe", argv);
  std::fprintf(stderr, "%s: warning: could not re-execute single-threaded (%s)\n", program, std::strerror(errno));
}

// The rows of a CSV file a benchmark wrote (no quoted fields), each as header -> value (a missing
// or trailing empty field is ""). Empty if the file cannot be read.
using CsvRow = std::map<std::string, std::string>;
inline std::vector<CsvRow> read_csv_rows(const std::string& path) {
  std::vector<CsvRow> rows;
  std::ifstream in(path);
  if (!in) return rows;
  auto split = [](const std::string& l) {
    std::vector<std::string> v;
    std::stringstream ss(l);
    for (std::string c; std::getline(ss, c, ',');) v.push_back(c);
    if (!l.empty() && l.back() == ',') v.emplace_back();
    return v;
  };
  std::string line;
  if (!std::getline(in, line)) return rows;
  const std::vector<std::string> head = split(line);
  while (std::getline(in, line)) {
    const auto v = split(line);
    CsvRow r;
    for (size_t k = 0; k < head.size(); ++k) r[head[k]] = k < v.size() ? v[k] : "";
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace sphib::bench
