// atomic_file.cpp — temporary name + rename, with POSIX calls so that every failure has its
// errno (a std::ofstream says only that it failed).
#include "cdpowder/io/atomic_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

// open, write, close and getpid are POSIX
#include <fcntl.h>
#include <unistd.h>

namespace cdpowder {

namespace {

std::filesystem::path temporary_name(const std::filesystem::path& path) {
  return path.parent_path() /
         fmt::format(".{}.{}.tmp", path.filename().string(), static_cast<long>(::getpid()));
}

std::string failure(const std::filesystem::path& path, int error_number) {
  return fmt::format("cannot write {}: {}", path.string(), std::strerror(error_number));
}

int open_for_writing(const std::filesystem::path& temporary, const std::filesystem::path& path) {
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputError(failure(path, errno));
  return fd;
}

/// Writes all of `text`; the errno of the failure, or 0.
int write_all(int fd, std::string_view text) {
  while (!text.empty()) {
    const ssize_t written = ::write(fd, text.data(), text.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    text.remove_prefix(static_cast<std::size_t>(written));
  }
  return 0;
}

void remove_quietly(const std::filesystem::path& file) {
  std::error_code ignored;
  std::filesystem::remove(file, ignored);
}

/// Forces the file's bytes to the disk before it is renamed into place: after a crash of the
/// machine, a renamed file is whole, never empty. The errno of the failure, or 0 (a file
/// system that cannot sync, EINVAL, has nothing more to force).
int sync_file(int fd) {
  if (::fsync(fd) == 0 || errno == EINVAL) return 0;
  return errno;
}

/// Forces the folder's entry for a renamed file to the disk: the rename survives a crash.
void sync_folder(const std::filesystem::path& file) {
  const std::filesystem::path folder = file.has_parent_path() ? file.parent_path() : ".";
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) throw OutputError(failure(file, errno));
  const int error_number = sync_file(fd);
  ::close(fd);
  if (error_number != 0) throw OutputError(failure(file, error_number));
}

void rename_into_place(const std::filesystem::path& from, const std::filesystem::path& to) {
  std::error_code error;
  std::filesystem::rename(from, to, error);
  if (error) {
    remove_quietly(from);  // its own error code: the message keeps the rename's reason
    throw OutputError(fmt::format("cannot write {}: {}", to.string(), error.message()));
  }
  sync_folder(to);
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  const std::filesystem::path temporary = temporary_name(path);
  const int fd = open_for_writing(temporary, path);
  int error_number = write_all(fd, content);
  if (error_number == 0) error_number = sync_file(fd);
  if (::close(fd) != 0 && error_number == 0) error_number = errno;
  if (error_number != 0) {
    remove_quietly(temporary);
    throw OutputError(failure(path, error_number));
  }
  rename_into_place(temporary, path);
}

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(OutputSink&)>& fill) {
  AtomicFileStream file(path);
  fill(file);
  file.commit();
}

AtomicFileStream::AtomicFileStream(std::filesystem::path path)
    : path_(std::move(path)), temporary_(temporary_name(path_)) {
  fd_ = open_for_writing(temporary_, path_);
}

AtomicFileStream::AtomicFileStream(std::filesystem::path path,
                                   const std::filesystem::path& existing, std::uintmax_t keep_bytes)
    : path_(std::move(path)), temporary_(temporary_name(path_)) {
  std::error_code error;
  if (existing != temporary_) std::filesystem::rename(existing, temporary_, error);
  if (error) {
    throw OutputError(fmt::format("cannot continue {} from {}: {}", path_.string(),
                                  existing.string(), error.message()));
  }
  fd_ = ::open(temporary_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd_ < 0 || ::ftruncate(fd_, static_cast<off_t>(keep_bytes)) != 0) {
    const int error_number = errno;
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    throw OutputError(failure(path_, error_number));
  }
}

AtomicFileStream::~AtomicFileStream() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) remove_quietly(temporary_);
}

void AtomicFileStream::fail(int error_number) {
  if (error_.empty()) error_ = failure(path_, error_number);
}

void AtomicFileStream::flush() {
  if (!failed()) {
    const int error_number = write_all(fd_, buffer_);
    if (error_number != 0) fail(error_number);
  }
  buffer_.clear();
}

void AtomicFileStream::write(std::string_view text) {
  if (failed()) return;
  if (text.size() >= kBufferBytes) {
    flush();
    if (failed()) return;
    const int error_number = write_all(fd_, text);
    if (error_number != 0) fail(error_number);
    return;
  }
  buffer_ += text;
  if (buffer_.size() >= kBufferBytes) flush();
}

void AtomicFileStream::commit() {
  flush();
  const int fd = fd_;
  fd_ = -1;
  if (!failed()) {
    const int error_number = sync_file(fd);
    if (error_number != 0) fail(error_number);
  }
  if (::close(fd) != 0) fail(errno);
  if (failed()) {
    remove_quietly(temporary_);
    throw OutputError(error_);
  }
  rename_into_place(temporary_, path_);
  committed_ = true;
}

}  // namespace cdpowder
