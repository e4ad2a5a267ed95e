// atomic_file.hpp — outputs appear whole or not at all: every file is written under a
// temporary name in its destination folder, then renamed over the final name (rename is
// atomic within a file system). A killed run leaves earlier files intact. The file is
// synced (fsync) before the rename and its folder after it, so that after a crash of the
// machine a renamed file is whole, never empty, and the rename itself is kept. Every failure
// says which file and why, in the system's words (a full disk: "No space left on device"),
// and leaves no temporary file behind.
#pragma once

#include "cdpowder/io/output_sink.hpp"

#include <cstddef>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace cdpowder {

/// An output could not be written ("cannot write PATH: No space left on device"): the
/// machine's fault, not the run's, so a sweep stops starting runs that would fail the same
/// way (app/main.cpp gives it its own exit status).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Writes `content` to `path` atomically. Throws OutputError naming the path and the
/// reason.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

/// Writes what `fill` writes into its sink to `path` atomically, as it is made (a writer that
/// hands its output over in chunks never holds the whole file). Throws OutputError naming the
/// path and the reason; when `fill` throws, no file is left, and the exception goes on.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(OutputSink&)>& fill);

/// A file that is written incrementally (a time series) and appears under its final name
/// only when commit() is called; destroyed without commit, it removes its temporary file.
/// A failed write is remembered, not thrown: the caller decides whether to go on (a run
/// keeps running and writes its other outputs) and asks failed()/error().
class AtomicFileStream final : public OutputSink {
 public:
  /// Opens the temporary file; throws OutputError naming the path and the reason.
  explicit AtomicFileStream(std::filesystem::path path);

  /// Continues the file `existing` (an earlier stream's temporary file, or its final file):
  /// renamed to this stream's temporary name, cut to its first `keep_bytes` bytes and
  /// appended to. Throws OutputError naming the path and the reason.
  AtomicFileStream(std::filesystem::path path, const std::filesystem::path& existing,
                   std::uintmax_t keep_bytes);
  ~AtomicFileStream();
  AtomicFileStream(const AtomicFileStream&) = delete;
  AtomicFileStream& operator=(const AtomicFileStream&) = delete;
  AtomicFileStream(AtomicFileStream&&) = delete;
  AtomicFileStream& operator=(AtomicFileStream&&) = delete;

  /// Appends `text` (nothing once a write has failed). Written to the file in blocks of
  /// kBufferBytes, so a failure is seen within that much output; a longer text goes to the
  /// file at once, without a copy.
  void write(std::string_view text) override;

  /// Whether a write failed, and "cannot write PATH: reason" of the first failure.
  [[nodiscard]] bool failed() const { return !error_.empty(); }

  [[nodiscard]] const std::string& error() const { return error_; }

  /// Closes and renames to the final name. Throws OutputError with the first
  /// failure's reason (the temporary file is removed) if any write, the close or the rename
  /// failed.
  void commit();

  /// Writes what is buffered to the file now (before a checkpoint: a process killed later
  /// leaves every row written so far in the temporary file).
  void flush();

  /// The temporary name the file has until commit().
  [[nodiscard]] const std::filesystem::path& temporary() const { return temporary_; }

 private:
  static constexpr std::size_t kBufferBytes = std::size_t{64} * 1024;

  void fail(int error_number);

  std::filesystem::path path_;
  std::filesystem::path temporary_;
  int fd_ = -1;
  std::string buffer_;
  std::string error_;
  bool committed_ = false;
};

}  // namespace cdpowder
