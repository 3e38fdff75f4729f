#pragma once
// What every benchmark program shares: its command line (CLI11), one-core runs, CPU time, number
// formatting for tables and CSV, Markdown tables and reading its own CSV back (--keep,
// --report-only). Header-only; the benchmarks are single files. Wall time: sphib::seconds_since.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "fluid/common/profile.hpp"  // seconds_since
#include "io/atomic_file.hpp"

namespace sphib::bench {

using Clock = Profile::Clock;

// Re-executes the program once with OMP_NUM_THREADS=threads and the BLAS libraries on one thread,
// so that every figure it prints is that many cores' (libgomp reads OMP_NUM_THREADS at load time, so
// setting it from main is too late); in the re-executed process it returns at once.
inline void ensure_threads(const std::string& program, char** argv, int threads) {
  if (std::getenv("SPHIB_BENCH_THREADS")) return;
  const std::string n = std::to_string(threads);
  setenv("SPHIB_BENCH_THREADS", n.c_str(), 1);
  setenv("OMP_NUM_THREADS", n.c_str(), 1);
  for (const char* v : {"OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "GOTO_NUM_THREADS"}) setenv(v, "1", 1);
  execv("/proc/self/exe", argv);
  std::fprintf(stderr, "%s: warning: could not re-execute with %s thread(s) (%s)\n", program.c_str(), n.c_str(),
               std::strerror(errno));
}

// A benchmark's main: parses the command line (--help; a bad option is named, status 2), re-executes
// once on `*threads` threads (one when null: every benchmark's default), then runs `body`, which
// returns the exit status; an exception ends the program with its message, status 1.
template <class Body>
int run_main(CLI::App& app, int argc, char** argv, Body body, const int* threads = nullptr) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  ensure_threads(app.get_name(), argv, threads ? *threads : 1);
  try {
    return body();
  } catch (const std::exception& e) {
    std::cerr << app.get_name() << ": " << e.what() << "\n";
    return 1;
  }
}

// --parts: a string of letters, each one of `letters` (the benchmark's parts).
inline CLI::Option* add_parts(CLI::App& app, std::string& parts, const std::string& letters, const std::string& what) {
  return app.add_option("--parts", parts, what + " (default " + parts + ")")
      ->check(CLI::Validator(
          [letters](std::string& s) {
            return s.find_first_not_of(letters) == std::string::npos ? std::string()
                                                                      : "letters of " + letters + " only";
          },
          "[" + letters + "]"));
}
// --parts, --out DIR, --cases DIR and --quick: the options of the benchmarks that run scene files.
template <class Options>
void add_scene_options(CLI::App& app, Options& o, const std::string& letters, const std::string& parts_help) {
  add_parts(app, o.parts, letters, parts_help);
  app.add_option("--out", o.out, "output directory")->capture_default_str();
  app.add_option("--cases", o.cases, "scene directory")->capture_default_str();
  app.add_flag("--quick", o.quick, "a few runs per part (smoke test)");
}

inline bool wants(const std::string& parts, char part) { return parts.find(part) != std::string::npos; }

inline std::filesystem::path create_out_dir(const std::string& dir) {
  std::filesystem::create_directories(dir);
  return dir;
}

// CPU seconds (user + system) of this process so far.
inline double cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + ru.ru_stime.tv_sec + 1e-6 * ru.ru_stime.tv_usec;
}

// A field of /proc/self/status in kB (VmHWM: peak resident memory, VmRSS: resident now); -1 if absent.
inline long status_kb(const char* key) {
  std::ifstream f("/proc/self/status");
  std::string line;
  const std::string k = std::string(key) + ":";
  while (std::getline(f, line))
    if (line.rfind(k, 0) == 0) return std::strtol(line.c_str() + k.size(), nullptr, 10);
  return -1;
}

// This program run again as a child (/proc/self/exe with `args`, which start with the program name):
// what it wrote on standard output, its exit status (as waitpid gives it), its peak resident memory
// (wait4's ru_maxrss, kB) and its wall time. Memory figures per size need a fresh process each.
struct ChildRun {
  std::string out;
  int status = 0;
  long maxrss_kb = 0;
  double wall_s = 0;
};
inline ChildRun run_self(const std::vector<std::string>& args) {
  int fd[2];
  if (pipe(fd) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  const auto t0 = Clock::now();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    dup2(fd[1], 1);
    close(fd[0]);
    close(fd[1]);
    std::vector<char*> av;
    for (const auto& a : args) av.push_back(const_cast<char*>(a.c_str()));
    av.push_back(nullptr);
    execv("/proc/self/exe", av.data());
    _exit(127);
  }
  close(fd[1]);
  ChildRun r;
  char buf[4096];
  for (ssize_t n; (n = read(fd[0], buf, sizeof buf)) > 0;) r.out.append(buf, n);
  close(fd[0]);
  rusage ru{};
  wait4(pid, &r.status, 0, &ru);
  r.maxrss_kb = ru.ru_maxrss;
  r.wall_s = seconds_since(t0);
  return r;
}

// The last line of `out` that starts with '{' (a child's JSON report), or "".
inline std::string last_json_line(const std::string& out) {
  std::stringstream ss(out);
  std::string last;
  for (std::string line; std::getline(ss, line);)
    if (!line.empty() && line[0] == '{') last = line;
  return last;
}

// The load average over the last minute (/proc/loadavg), NAN if unreadable.
inline double load_average() {
  std::ifstream f("/proc/loadavg");
  double l = NAN;
  f >> l;
  return l;
}

inline std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) return line.substr(line.find(':') + 2);
  return "unknown";
}

// Numbers for tables: plain (prec significant digits), fixed and scientific (prec decimals; "–" for
// non-finite), percent, and for CSV (10 digits, empty for non-finite).
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
inline std::string pct(double v, int prec = 2) { return std::isfinite(v) ? fix(100.0 * v, prec) + "%" : "–"; }
inline std::string csv_num(double v) { return std::isfinite(v) ? num(v, 10) : std::string(); }

// Text for a CSV field (separators and quotes replaced) and for a Markdown cell ('|' escaped).
inline std::string csv_text(std::string s) {
  for (char& c : s)
    if (c == ',' || c == '\n' || c == '"') c = ';';
  return s;
}
inline std::string md_text(std::string s) {
  for (size_t p = 0; (p = s.find('|', p)) != std::string::npos; p += 2) s.replace(p, 1, "\\|");
  return s;
}

// A Markdown table's header: | corner | c1 | c2 | ... with right-aligned number columns.
inline std::string md_header(const std::string& corner, const std::vector<std::string>& cols) {
  std::string m = "| " + corner + " |";
  for (const auto& c : cols) m += " " + c + " |";
  m += "\n|---|";
  for (size_t k = 0; k < cols.size(); ++k) m += "---:|";
  return m + "\n";
}

// The exponent a of y ~ x^a: least squares of log y against log x over the positive points.
inline double power_law_exponent(const std::vector<std::pair<double, double>>& pts) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (auto [x, y] : pts) {
    if (!(y > 0) || !(x > 0)) continue;
    const double lx = std::log(x), ly = std::log(y);
    sx += lx; sy += ly; sxx += lx * lx; sxy += lx * ly; ++n;
  }
  return n >= 2 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : NAN;
}

// The rows of a CSV file a benchmark wrote (no quoted fields), each as header -> value (a missing
// or trailing empty field is ""). Empty if the file cannot be read.
using CsvRow = std::map<std::string, std::string>;
inline std::vector<CsvRow> read_csv_rows(const std::string& path) {
  std::vector<CsvRow> rows;
  std::ifstream in(path);
  auto split = [](const std::string& l) {
    std::vector<std::string> v;
    std::stringstream ss(l);
    for (std::string c; std::getline(ss, c, ',');) v.push_back(c);
    if (!l.empty() && l.back() == ',') v.emplace_back();
    return v;
  };
  std::string line;
  if (!in || !std::getline(in, line)) return rows;
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
