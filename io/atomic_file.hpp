#pragma once
// Write-then-rename: a reader sees no file or the complete file under its final name, never a
// half-written one (a killed run leaves only `<path>.part`).
#include <stdexcept>
#include <string>
#include <vector>

namespace sphib {

// A file that could not be written (disk full, quota, I/O error, permissions). A run that meets one
// stops at once with the files it completed before intact (exit status 1).
struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Name of the temporary sibling written before the rename: path + ".part".
std::string part_path(const std::string& path);

// fsync `part`, rename it over `path` (atomic on POSIX), fsync the directory.
// Throws WriteError naming both files on failure.
void commit_part(const std::string& part, const std::string& path);

// A finished file still under its .part name, and the name it is published under.
struct PartFile {
  std::string part, path;
};

// Publishes finished files together: fsyncs every part, then renames each to its name; if a rename
// fails, the ones done are renamed back (every file stays .part) and WriteError is thrown. The
// directories are fsynced at the end.
void publish_all(const std::vector<PartFile>& files);

// Writes `content` to part_path(path) and fsyncs it (not yet published). Throws WriteError.
PartFile write_part(const std::string& path, const std::string& content);

// Write `content` to part_path(path), then commit_part. Throws WriteError naming the file.
void write_file_atomic(const std::string& path, const std::string& content);

// Gives the file open as `fd` (at `path`) disk blocks for its first `size` bytes without changing its
// length (fallocate, FALLOC_FL_KEEP_SIZE), so that writes up to there cannot fail for want of space:
// a writer that cannot recover from a failed write (HDF5) reserves before it writes. Where the file
// system cannot reserve (EOPNOTSUPP), compares the free space instead. Throws WriteError naming the
// file and the space it needs.
void reserve_space(int fd, long long size, const std::string& path);

}  // namespace sphib
