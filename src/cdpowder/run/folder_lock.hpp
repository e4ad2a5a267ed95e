// folder_lock.hpp — an exclusive advisory lock (flock) on a file in an output folder for
// the lifetime of a command: a sweep on DIR/.lock (two sweeps into one folder would start
// the same runs twice), a run on DIR/.run.lock (a restarted sweep, or a second command,
// must not write into a folder a run still writes into). The kernel releases the lock when
// the process ends, however it ends.
#pragma once

#include "cdpowder/io/atomic_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

// open and flock are POSIX
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

namespace cdpowder {

class FolderLock {
 public:
  /// Locks `lock_file`; throws std::runtime_error naming `folder`, the lock file and what
  /// holds it (`holder`, e.g. "another sweep") when it is taken, and OutputError with the
  /// system's reason when the lock file cannot be made (a read-only folder).
  FolderLock(const std::filesystem::path& lock_file, const std::string& holder) {
    fd_ = open(lock_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) {  // not a lock held elsewhere: the folder cannot be written
      throw OutputError(
          fmt::format("cannot write {}: {}", lock_file.string(), std::strerror(errno)));
    }
    if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      close(fd_);
      throw std::runtime_error(
          fmt::format("{} is in use by {} (lock {}); wait for it or choose another --out",
                      lock_file.parent_path().string(), holder, lock_file.string()));
    }
  }

  ~FolderLock() { close(fd_); }

  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  FolderLock(FolderLock&&) = delete;
  FolderLock& operator=(FolderLock&&) = delete;

  /// Whether another process holds `lock_file` now (an absent file is not held).
  static bool held(const std::filesystem::path& lock_file) {
    const int fd = open(lock_file.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0) return false;
    const bool taken = flock(fd, LOCK_EX | LOCK_NB) != 0;
    close(fd);  // releases the lock if this call took it
    return taken;
  }

 private:
  int fd_ = -1;
};

/// The lock a run holds on its output folder.
inline std::filesystem::path run_lock_file(const std::filesystem::path& folder) {
  return folder / ".run.lock";
}

}  // namespace cdpowder
