#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace sphib {
namespace fs = std::filesystem;

namespace {

// Flush a file's data to disk. Directories are best effort (some file systems refuse).
void fsync_path(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) {
    if (directory) return;
    throw std::runtime_error("cannot open '" + path + "' to fsync: " + std::strerror(errno));
  }
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0 && !directory && err != EINVAL && err != EROFS)  // EINVAL: special files
    throw std::runtime_error("fsync of '" + path + "' failed: " + std::strerror(err));
}

}  // namespace

std::string part_path(const std::string& path) { return path + ".part"; }

void commit_part(const std::string& part, const std::string& path) {
  fsync_path(part, false);
  std::error_code ec;
  fs::rename(part, path, ec);
  if (ec)
    throw std::runtime_error("cannot rename '" + part + "' to '" + path + "': " + ec.message());
  const fs::path dir = fs::path(path).parent_path();
  fsync_path(dir.empty() ? "." : dir.string(), true);
}

void write_file_atomic(const std::string& path, const std::string& content) {
  const std::string part = part_path(path);
  std::FILE* f = std::fopen(part.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot open '" + part + "' for writing: " + std::strerror(errno));
  const bool written = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  const int err = errno;
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed) {
    std::remove(part.c_str());
    throw std::runtime_error("cannot write '" + part + "': " + std::strerror(written ? errno : err));
  }
  commit_part(part, path);
}

}  // namespace sphib
