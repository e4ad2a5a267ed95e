// folder_lock.cpp — flock(2) on a lock file of the folder, released by the kernel when the
// process ends.
#include "cdpowder/run/folder_lock.hpp"

#include "cdpowder/io/atomic_file.hpp"

#include <climits>
#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

// open and flock are POSIX
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace cdpowder {

namespace {

/// The descriptor a parent passed down for `lock_file` (kInheritedLockVariable), or −1.
int inherited_fd(const std::filesystem::path& lock_file) {
  const char* text = std::getenv(kInheritedLockVariable);
  if (text == nullptr) return -1;
  char* end = nullptr;
  const long fd = std::strtol(text, &end, 10);

  struct stat passed {};

  struct stat named {};

  if (end == text || *end != '\0' || fd < 0 || fd > INT_MAX ||
      fstat(static_cast<int>(fd), &passed) != 0 || stat(lock_file.c_str(), &named) != 0 ||
      passed.st_dev != named.st_dev || passed.st_ino != named.st_ino) {
    return -1;  // not this lock: taken as any other
  }
  unsetenv(kInheritedLockVariable);  // adopted once, and not passed on further
  fcntl(static_cast<int>(fd), F_SETFD, FD_CLOEXEC);
  return static_cast<int>(fd);
}

}  // namespace

FolderLock::FolderLock(const std::filesystem::path& lock_file, const std::string& holder) {
  fd_ = inherited_fd(lock_file);
  if (fd_ >= 0) return;
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

int FolderLock::inheritable_fd() const {
  const int fd = fcntl(fd_, F_DUPFD, 3);  // a duplicate without FD_CLOEXEC, above stderr
  if (fd < 0) throw OutputError(fmt::format("cannot pass on a lock: {}", std::strerror(errno)));
  return fd;
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
