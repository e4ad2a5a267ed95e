// atomic_file.cpp — temporary name + rename.
#include "cdpowder/io/atomic_file.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace cdpowder {

namespace {

std::filesystem::path temporary_name(const std::filesystem::path& path) {
  return path.parent_path() /
         fmt::format(".{}.{}.tmp", path.filename().string(), static_cast<long>(::getpid()));
}

void rename_into_place(const std::filesystem::path& from, const std::filesystem::path& to) {
  std::error_code error;
  std::filesystem::rename(from, to, error);
  if (error) {
    std::filesystem::remove(from, error);
    throw std::runtime_error(fmt::format("cannot write {}: {}", to.string(), error.message()));
  }
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  const std::filesystem::path temporary = temporary_name(path);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(fmt::format("cannot write {}", path.string()));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw std::runtime_error(fmt::format("cannot write {}", path.string()));
    }
  }
  rename_into_place(temporary, path);
}

AtomicFileStream::AtomicFileStream(std::filesystem::path path)
    : path_(std::move(path)), temporary_(temporary_name(path_)) {
  stream_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!stream_) throw std::runtime_error(fmt::format("cannot write {}", path_.string()));
}

AtomicFileStream::~AtomicFileStream() {
  if (!committed_) {
    stream_.close();
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
}

void AtomicFileStream::commit() {
  stream_.flush();
  if (!stream_) throw std::runtime_error(fmt::format("cannot write {}", path_.string()));
  stream_.close();
  rename_into_place(temporary_, path_);
  committed_ = true;
}

}  // namespace cdpowder
