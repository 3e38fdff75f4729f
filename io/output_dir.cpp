#include "io/output_dir.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>

#include "io/atomic_file.hpp"

namespace sphib {

namespace fs = std::filesystem;

namespace {

const char* kLock = ".sphib.lock";

std::string holder_of(int fd) {
  char buf[256] = {0};
  const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  std::string s(buf, n > 0 ? static_cast<size_t>(n) : 0);
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s.empty() ? "pid unknown" : s;
}

std::string owner_text() {
  char host[256] = {0};
  ::gethostname(host, sizeof host - 1);
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char when[64] = {0};
  std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S", std::localtime(&now));
  return "pid " + std::to_string(::getpid()) + " on " + host + ", started " + when + "\n";
}

// Why the open file is not a lock this run may write ("" if it is): a lock is a plain file with one
// name (a hard link to a user's file would be truncated and overwritten through it).
std::string not_a_lock(int fd) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) return std::string("cannot be examined: ") + std::strerror(errno);
  if (!S_ISREG(st.st_mode)) return "is not a plain file";
  if (st.st_nlink != 1) return "has " + std::to_string(st.st_nlink) + " names (a hard link to another file)";
  return "";
}

bool same_file(int fd, const std::string& path) {
  struct stat a {}, b {};
  return ::fstat(fd, &a) == 0 && ::lstat(path.c_str(), &b) == 0 && a.st_ino == b.st_ino && a.st_dev == b.st_dev;
}

}  // namespace

const std::vector<std::string>& run_file_names() {
  static const std::vector<std::string> names{"output.h5",    "output.xdmf",     "output_membranes.xdmf",
                                              "diagnostics.csv", "summary.json", "checkpoint.h5",
                                              "centreline_u.csv", "centreline_v.csv"};
  return names;
}

OutputDirectory::OutputDirectory(std::string dir) : dir_(std::move(dir)) {
  std::error_code ec;
  if (!fs::exists(dir_, ec)) created_ = fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    throw WriteError("output directory " + dir_ + " cannot be created" + (ec ? ": " + ec.message() : ": a file has its name"));
  const std::string lock = file(kLock);
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    // Never through a link: a symbolic link is not followed (O_NOFOLLOW), a FIFO does not block
    // (O_NONBLOCK), and anything but a plain file of one name is refused before it is written.
    const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
    if (fd < 0) {
      const int err = errno;
      abandon();
      if (err == ELOOP)
        throw LockRefused("output directory " + dir_ + ": its lock file " + lock +
                          " is a symbolic link (not a sphib lock; nothing was written through it): remove it, or give "
                          "this run another --out");
      throw WriteError("output directory " + dir_ + ": cannot create its lock file " + lock + ": " + std::strerror(err));
    }
    if (const std::string why = not_a_lock(fd); !why.empty()) {
      ::close(fd);
      abandon();
      throw LockRefused("output directory " + dir_ + ": its lock file " + lock + " " + why +
                        " (not a sphib lock; nothing was written to it): remove it, or give this run another --out");
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      const std::string who = holder_of(fd);
      ::close(fd);
      if (err == EWOULDBLOCK)
        throw DirectoryBusy("output directory " + dir_ + " is in use by another sphib run (" + who +
                            "); nothing was written: give this run another --out, or wait for that one to end");
      throw WriteError("output directory " + dir_ + ": cannot lock " + lock + ": " + std::strerror(err));
    }
    if (same_file(fd, lock)) fd_ = fd;  // else the run that held it ended and removed it: try again
    else ::close(fd);
  }
  if (fd_ < 0) throw DirectoryBusy("output directory " + dir_ + ": its lock changes hands too often");
  const std::string who = owner_text();
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, who.data(), who.size(), 0) != static_cast<ssize_t>(who.size())) {
    // the lock holds without its text; a full disk shows itself at the first write
  }
}

OutputDirectory::~OutputDirectory() { release(); }

void OutputDirectory::release() {
  if (fd_ < 0) return;
  ::unlink(file(kLock).c_str());  // while still locked: a run that opened it meanwhile sees it is stale
  ::close(fd_);
  fd_ = -1;
}

void OutputDirectory::abandon() {
  release();
  std::error_code ec;
  if (created_ && fs::is_empty(dir_, ec)) fs::remove(dir_, ec);
}

std::vector<std::string> OutputDirectory::earlier_files() const {
  std::vector<std::string> found;
  std::error_code ec;
  for (const std::string& name : run_file_names())
    for (const std::string& n : {name, part_path(name)})
      if (fs::exists(file(n), ec)) found.push_back(n);
  return found;
}

std::vector<std::string> OutputDirectory::remove_earlier_files(const std::vector<std::string>& keep, bool parts_only) {
  std::vector<std::string> doomed;
  std::error_code ec;
  for (const std::string& n : earlier_files()) {
    if (parts_only && (n.size() < 5 || n.compare(n.size() - 5, 5, ".part") != 0)) continue;
    if (std::any_of(keep.begin(), keep.end(), [&](const std::string& k) { return !k.empty() && fs::equivalent(file(n), k, ec); }))
      continue;
    const fs::file_status st = fs::symlink_status(file(n), ec);
    if (!fs::is_regular_file(st) && !fs::is_symlink(st))
      throw LockRefused("output directory " + dir_ + ": " + n + " is not a file a run wrote (a directory or a device): " +
                        "nothing was removed or written; move it away, or give this run another --out");
    doomed.push_back(n);
  }
  if (doomed.empty()) return doomed;
  // All or nothing: every file is first moved into a directory of its own (a rename, which needs no
  // new inode for the file), and moved back if one cannot be; only then is that directory removed.
  std::string trash = file(".sphib-removing-XXXXXX");
  if (!::mkdtemp(trash.data()))
    throw WriteError("cannot remove the earlier run's files in " + dir_ + " (nothing was removed): cannot create " + trash +
                     ": " + std::strerror(errno));
  std::vector<std::string> moved;
  for (const std::string& n : doomed) {
    fs::rename(file(n), trash + "/" + n, ec);
    if (!ec) { moved.push_back(n); continue; }
    const std::string why = ec.message();
    for (const std::string& m : moved) fs::rename(trash + "/" + m, file(m), ec);
    fs::remove(trash, ec);
    throw WriteError("cannot remove the earlier run's " + file(n) + ": " + why + " (nothing was removed)");
  }
  fs::remove_all(trash, ec);  // the run's names are free now; a leftover here is only space
  return doomed;
}

}  // namespace sphib
