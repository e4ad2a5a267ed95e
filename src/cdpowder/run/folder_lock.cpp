// folder_lock.cpp — flock(2) on a lock file of the folder, released by the kernel when the
// process ends.
#include "cdpowder/run/folder_lock.hpp"

#include "cdpowder/io/atomic_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

// open and flock are POSIX
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

namespace cdpowder {

FolderLock::FolderLock(const std::filesystem::path& lock_file, const std::string& holder) {
  fd_ = open(lock_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {  // not a lock held elsewhere: the folder cannot be written
    throw OutputError(fmt::format("cannot write {}: {}", lock_file.string(), std::strerror(errno)));
  }
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    close(fd_);
    throw std::runtime_error(
        fmt::format("{} is in use by {} (lock {}); wait for it or choose another --out",
                    lock_file.parent_path().string(), holder, lock_file.string()));
  }
}

FolderLock::~FolderLock() {
  close(fd_);
}

bool FolderLock::held(const std::filesystem::path& lock_file) {
  const int fd = open(lock_file.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return false;
  const bool taken = flock(fd, LOCK_EX | LOCK_NB) != 0;
  close(fd);  // releases the lock if this call took it
  return taken;
}

std::filesystem::path run_lock_file(const std::filesystem::path& folder) {
  return folder / ".run.lock";
}

}  // namespace cdpowder
