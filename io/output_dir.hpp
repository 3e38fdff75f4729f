#pragma once
// One run owns its output directory. The lock (flock on DIR/.sphib.lock) is taken before the run
// writes or removes anything there, so a second run into the same directory is refused before it
// touches a file, and the first run's output stays intact. The lock file holds the owner's pid and
// start time, and is removed when the run ends (a killed run's stale lock file is taken over: the
// kernel released its lock). It is opened without following links and written only when it is a plain
// file with one name.
#include <stdexcept>
#include <string>
#include <vector>

namespace sphib {

// Another run holds the directory (nothing was written; the command's exit status 2).
struct DirectoryBusy : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// DIR/.sphib.lock is not a lock this run may write (a symbolic link, a hard link to another file, not
// a plain file), or a run's file name there is not a file: nothing was written (exit status 2).
struct LockRefused : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// The files a run writes into its directory (final names; each may also exist as NAME.part).
const std::vector<std::string>& run_file_names();

class OutputDirectory {
 public:
  // Creates the directory if it is missing, then takes its lock. Throws DirectoryBusy naming the
  // holder, or WriteError if the directory cannot be created or locked.
  explicit OutputDirectory(std::string dir);
  ~OutputDirectory();  // releases the lock and removes the lock file
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  const std::string& path() const { return dir_; }
  std::string file(const std::string& name) const { return dir_ + "/" + name; }

  // The run was refused before writing: releases the lock and removes the lock file, and the
  // directory itself if this run created it and it is empty.
  void abandon();

  // The files of earlier runs present now (run_file_names() and their .part siblings).
  std::vector<std::string> earlier_files() const;
  // Removes them (only the .part ones if parts_only), but not those in `keep` (e.g. the checkpoint a
  // restart reads); returns their names. All or nothing: a name that is not a file (a directory)
  // throws LockRefused and one that cannot be moved throws WriteError, with every file still there.
  std::vector<std::string> remove_earlier_files(const std::vector<std::string>& keep = {}, bool parts_only = false);

 private:
  void release();

  std::string dir_;
  bool created_ = false;  // this run made the directory
  int fd_ = -1;           // the lock file, locked
};

}  // namespace sphib
