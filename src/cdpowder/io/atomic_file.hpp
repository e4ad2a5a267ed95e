// atomic_file.hpp — outputs appear whole or not at all: every file is written under a
// temporary name in its destination folder, flushed, then renamed over the final name
// (rename is atomic within a file system). A killed run leaves earlier files intact.
#pragma once

#include <filesystem>
#include <fstream>
#include <string_view>

namespace cdpowder {

/// Writes `content` to `path` atomically. Throws std::runtime_error naming the path.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

/// A file that is written incrementally (a time series) and appears under its final name
/// only when commit() is called; destroyed without commit, it removes its temporary file.
class AtomicFileStream {
 public:
  explicit AtomicFileStream(std::filesystem::path path);
  ~AtomicFileStream();
  AtomicFileStream(const AtomicFileStream&) = delete;
  AtomicFileStream& operator=(const AtomicFileStream&) = delete;

  std::ofstream& stream() { return stream_; }

  /// Flushes, closes and renames to the final name.
  void commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path temporary_;
  std::ofstream stream_;
  bool committed_ = false;
};

}  // namespace cdpowder
