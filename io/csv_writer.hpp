#pragma once
// CSV time series of diagnostics: a header row of column names, then one row per call.
// Written to path + ".part" and flushed every row (tail -f works); close() renames it to path.
// Numbers are written in the shortest form that reads back to the same double (std::to_chars):
// exact like %.17g, so regression checks and plots see the values the run computed, yet 0.1
// stays "0.1". 10 digits would lose e.g. small differences of energies near 1.
#include <cstdio>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"

namespace sphib {

class CsvWriter {
 public:
  // Throws std::runtime_error naming the file if it cannot be opened.
  CsvWriter(std::string path, std::vector<std::string> columns);
  ~CsvWriter();  // closes (renames) if close() was not called; errors go to stderr
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  // One value per column (std::invalid_argument otherwise); NaN/Inf are written as nan/inf.
  // Throws WriteError naming the file if the write fails (e.g. disk full).
  void row(const std::vector<double>& values);
  void close();  // flush, fsync, rename path.part -> path; idempotent
  // Flush and close, leaving path.part for publish_all (io/atomic_file.hpp) to rename with the run's
  // other files. Throws WriteError.
  PartFile close_to_part();
  void abandon();  // close without the rename: path.part stays, incomplete by its name (a run that failed to write)

  const std::string& path() const { return path_; }
  const std::vector<std::string>& columns() const { return columns_; }

 private:
  void fail(const std::string& what);

  std::string path_;
  std::string part_;
  std::vector<std::string> columns_;
  std::FILE* file_ = nullptr;
};

}  // namespace sphib
