#include "io/csv_writer.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "io/atomic_file.hpp"

namespace sphib {

namespace {
// RFC 4180 quoting, only where a name needs it.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}
}  // namespace

CsvWriter::CsvWriter(std::string path, std::vector<std::string> columns)
    : path_(std::move(path)), part_(part_path(path_)), columns_(std::move(columns)) {
  if (columns_.empty()) throw std::invalid_argument("CsvWriter '" + path_ + "': no columns");
  file_ = std::fopen(part_.c_str(), "w");
  if (!file_)
    throw WriteError("CsvWriter: cannot open '" + part_ + "' for writing: " + std::strerror(errno));
  std::string header;
  for (std::size_t c = 0; c < columns_.size(); ++c)
    header += (c ? "," : "") + csv_field(columns_[c]);
  header += '\n';
  if (std::fputs(header.c_str(), file_) < 0 || std::fflush(file_) != 0) {
    const int err = errno;
    std::fclose(file_);
    throw WriteError("CsvWriter: cannot write '" + part_ + "': " + std::strerror(err));
  }
}

CsvWriter::~CsvWriter() {
  try {
    close();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sphib: CsvWriter: %s\n", e.what());
  }
}

void CsvWriter::fail(const std::string& what) {
  throw WriteError("CsvWriter: " + what + " '" + part_ + "' failed: " + std::strerror(errno));
}

void CsvWriter::row(const std::vector<double>& values) {
  if (!file_) throw std::logic_error("CsvWriter '" + path_ + "': row() after close()");
  if (values.size() != columns_.size())
    throw std::invalid_argument("CsvWriter '" + path_ + "': row has " +
                                std::to_string(values.size()) + " values for " +
                                std::to_string(columns_.size()) + " columns");
  std::string line;
  char buf[64];
  for (std::size_t c = 0; c < values.size(); ++c) {
    if (c) line += ',';
    if (std::isnan(values[c])) {
      line += "nan";  // not "-nan"
    } else {
      line.append(buf, std::to_chars(buf, buf + sizeof buf, values[c]).ptr);  // shortest exact
    }
  }
  line += '\n';
  if (std::fputs(line.c_str(), file_) < 0) fail("write to");
  if (std::fflush(file_) != 0) fail("flush of");
}

void CsvWriter::close() {
  if (!file_) return;
  commit_part(close_to_part().part, path_);
}

PartFile CsvWriter::close_to_part() {
  if (!file_) throw std::logic_error("CsvWriter '" + path_ + "': closed twice");
  std::FILE* f = file_;
  file_ = nullptr;  // closed even if the final flush fails: never retried
  const bool flushed = std::fflush(f) == 0;
  const int err = errno;
  if (std::fclose(f) != 0 || !flushed) {
    errno = flushed ? errno : err;
    fail("close of");
  }
  return {part_, path_};
}

void CsvWriter::abandon() {
  if (!file_) return;
  std::fclose(file_);
  file_ = nullptr;
}

}  // namespace sphib
