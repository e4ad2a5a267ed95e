// folder_lock.hpp — an exclusive advisory lock (flock) on a file in an output folder for
// the lifetime of a command: a sweep on DIR/.lock (two sweeps into one folder would start
// the same runs twice), a run on DIR/.run.lock (a restarted sweep, or a second command,
// must not write into a folder a run still writes into). The kernel releases the lock when
// the process ends, however it ends.
#pragma once

#include <filesystem>
#include <string>

namespace cdpowder {

class FolderLock {
 public:
  /// Locks `lock_file`; throws std::runtime_error naming `folder`, the lock file and what
  /// holds it (`holder`, e.g. "another sweep") when it is taken, and OutputError with the
  /// system's reason when the lock file cannot be made (a read-only folder).
  FolderLock(const std::filesystem::path& lock_file, const std::string& holder);

  ~FolderLock();

  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  FolderLock(FolderLock&&) = delete;
  FolderLock& operator=(FolderLock&&) = delete;

  /// Whether another process holds `lock_file` now (an absent file is not held).
  static bool held(const std::filesystem::path& lock_file);

 private:
  int fd_ = -1;
};

/// The lock a run holds on its output folder.
std::filesystem::path run_lock_file(const std::filesystem::path& folder);

}  // namespace cdpowder
