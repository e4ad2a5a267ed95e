// folder_lock.hpp — an exclusive advisory lock (flock) on a file in an output folder for
// the lifetime of a command: a sweep on DIR/.lock (two sweeps into one folder would start
// the same runs twice), a run on DIR/.run.lock (a restarted sweep, or a second command,
// must not write into a folder a run still writes into). The kernel releases the lock when
// the process ends, however it ends.
#pragma once

#include <filesystem>
#include <string>

namespace cdpowder {

/// The environment variable through which a sweep hands a run the lock it took on the run's
/// folder for it: the number of an open descriptor of the lock file (inheritable_fd).
inline constexpr const char* kInheritedLockVariable = "CDPOWDER_RUN_LOCK_FD";

class FolderLock {
 public:
  /// Locks `lock_file`; throws std::runtime_error naming `folder`, the lock file and what
  /// holds it (`holder`, e.g. "another sweep") when it is taken, and OutputError with the
  /// system's reason when the lock file cannot be made (a read-only folder). A process whose
  /// parent took the lock for it (kInheritedLockVariable names a descriptor of this very
  /// file) holds it already and adopts it: the folder was never free between the two.
  FolderLock(const std::filesystem::path& lock_file, const std::string& holder);

  /// A duplicate of the lock's descriptor that a child process inherits (no close-on-exec),
  /// to be named in kInheritedLockVariable of its environment and closed by the caller once
  /// the child is started: the child then holds the lock for as long as it lives.
  [[nodiscard]] int inheritable_fd() const;

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
