#pragma once
// Write-then-rename: a reader sees no file or the complete file under its final name, never a
// half-written one (a killed run leaves only `<path>.part`).
#include <string>

namespace sphib {

// Name of the temporary sibling written before the rename: path + ".part".
std::string part_path(const std::string& path);

// fsync `part`, rename it over `path` (atomic on POSIX), fsync the directory.
// Throws std::runtime_error naming both files on failure.
void commit_part(const std::string& part, const std::string& path);

// Write `content` to part_path(path), then commit_part. Throws std::runtime_error naming the file.
void write_file_atomic(const std::string& path, const std::string& content);

}  // namespace sphib
