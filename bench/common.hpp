#pragma once
// What every benchmark program shares: one-core runs, timing, number formatting and reading its
// own CSV back (--keep, --report-only). Header-only; the benchmarks are single files.
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
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

// Seconds of wall time since t0, and CPU seconds (user + system) of this process so far.
inline double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
inline double cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + ru.ru_stime.tv_sec + 1e-6 * ru.ru_stime.tv_usec;
}

// Numbers for tables: plain (prec significant digits), fixed and scientific (prec decimals; "–" for
// non-finite), and for CSV (10 digits, empty for non-finite).
inline std::string num(double v, int prec = 10) {
  std::ostringstream s;
  s << std::setprecision(prec) << v;
  return s.str();
}
inline std::string fix(double v, int prec = 2) {
  if (!std::isfinite(v)) return "–";
  std::ostringstream s;
  s << std::fixed << std::setprecision(prec) << v;
  return s.str();
}
inline std::string sci(double v, int prec = 2) {
  if (!std::isfinite(v)) return "–";
  std::ostringstream s;
  s << std::scientific << std::setprecision(prec) << v;
  return s.str();
}
inline std::string csv_num(double v) { return std::isfinite(v) ? num(v, 10) : std::string(); }

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
