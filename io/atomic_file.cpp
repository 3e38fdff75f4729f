#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
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
    throw WriteError("cannot open '" + path + "' to fsync: " + std::strerror(errno));
  }
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0 && !directory && err != EINVAL && err != EROFS)  // EINVAL: special files
    throw WriteError("fsync of '" + path + "' failed: " + std::strerror(err));
}

}  // namespace

std::string part_path(const std::string& path) { return path + ".part"; }

void commit_part(const std::string& part, const std::string& path) {
  fsync_path(part, false);
  std::error_code ec;
  fs::rename(part, path, ec);
  if (ec)
    throw WriteError("cannot rename '" + part + "' to '" + path + "': " + ec.message());
  const fs::path dir = fs::path(path).parent_path();
  fsync_path(dir.empty() ? "." : dir.string(), true);
}

void publish_all(const std::vector<PartFile>& files) {
  for (const PartFile& f : files) fsync_path(f.part, false);
  std::error_code ec;
  for (size_t k = 0; k < files.size(); ++k) {
    fs::rename(files[k].part, files[k].path, ec);
    if (!ec) continue;
    const std::string why = ec.message();
    for (size_t j = k; j-- > 0;) fs::rename(files[j].path, files[j].part, ec);
    throw WriteError("cannot rename '" + files[k].part + "' to '" + files[k].path + "': " + why +
                     " (the run's files stay .part)");
  }
  for (const PartFile& f : files) {
    const fs::path dir = fs::path(f.path).parent_path();
    fsync_path(dir.empty() ? "." : dir.string(), true);
  }
}

PartFile write_part(const std::string& path, const std::string& content) {
  const std::string part = part_path(path);
  std::FILE* f = std::fopen(part.c_str(), "wb");
  if (!f) throw WriteError("cannot open '" + part + "' for writing: " + std::strerror(errno));
  const bool written = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  const int err = errno;
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed) {
    std::remove(part.c_str());
    throw WriteError("cannot write '" + part + "': " + std::strerror(written ? errno : err));
  }
  return {part, path};
}

void write_file_atomic(const std::string& path, const std::string& content) {
  const PartFile f = write_part(path, content);
  commit_part(f.part, f.path);
}

void reserve_space(int fd, long long size, const std::string& path) {
  if (::fallocate(fd, FALLOC_FL_KEEP_SIZE, 0, static_cast<off_t>(size)) == 0) return;
  const int err = errno;
  auto mb = [](double b) { return std::to_string(static_cast<long long>(std::ceil(b / 1e6))) + " MB"; };
  if (err == ENOSPC || err == EDQUOT)
    throw WriteError("cannot write '" + path + "': " + std::strerror(err) + " (reserving " + mb(static_cast<double>(size)) +
                     " for the file and its next write)");
  if (err != EOPNOTSUPP && err != ENOSYS && err != EINVAL)
    throw WriteError("cannot reserve space for '" + path + "': " + std::strerror(err));
  struct stat st {};
  struct statvfs vfs {};
  if (::fstat(fd, &st) != 0 || ::fstatvfs(fd, &vfs) != 0) return;  // nothing to compare: write and see
  const double missing = static_cast<double>(size) - 512.0 * static_cast<double>(st.st_blocks);
  const double free = static_cast<double>(vfs.f_bavail) * static_cast<double>(vfs.f_frsize);
  if (missing > free)
    throw WriteError("cannot write '" + path + "': " + std::strerror(ENOSPC) + " (it needs " + mb(missing) + " more, " +
                     mb(free) + " free)");
}

}  // namespace sphib
