// input_file.hpp — reading a whole input file (a scene, a sweep file), with the reason it
// cannot be read said in the file's terms: an empty name, a folder, a FIFO or device (which
// would block or never end), a missing file, or the system's reason (permission denied).
#pragma once

#include "cdpowder/config/config_error.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>

namespace cdpowder {

/// Why `file` cannot be read as `what` (e.g. "a scene file (TOML)"), or "" when it is a
/// regular file (which may still fail to open: read_input_file says why).
inline std::string input_file_problem(const std::filesystem::path& file, std::string_view what) {
  if (file.empty()) return "the file name is empty; expected " + std::string(what);
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  if (error && error != std::errc::no_such_file_or_directory) {
    return "cannot read: " + error.message();  // e.g. a folder on the way without permission
  }
  if (std::filesystem::is_directory(status)) {
    return "is a folder; expected " + std::string(what);
  }
  if (!std::filesystem::exists(status)) return "no such file; expected " + std::string(what);
  if (!std::filesystem::is_regular_file(status)) {
    return "is not a regular file (a FIFO, socket or device); expected " + std::string(what);
  }
  return {};
}

/// The whole text of `file`; throws ConfigError naming the file and why it cannot be read
/// (`what` as for input_file_problem).
inline std::string read_input_file(const std::filesystem::path& file, std::string_view what) {
  if (const std::string problem = input_file_problem(file, what); !problem.empty()) {
    throw ConfigError({{file.string(), 0, 0, "", problem}});
  }
  std::ifstream stream(file, std::ios::binary);
  if (!stream) {
    throw ConfigError(
        {{file.string(), 0, 0, "", std::string("cannot open: ") + std::strerror(errno)}});
  }
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

}  // namespace cdpowder
