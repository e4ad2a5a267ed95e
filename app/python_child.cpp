// python_child.cpp — the interpreter and the build tree's package (python_child.hpp).
#include "python_child.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace cdpowder::app {

std::string python_interpreter() {
  const char* chosen = std::getenv(kPythonVariable);
  return chosen != nullptr && *chosen != '\0' ? chosen : "python3";
}

std::string package_folder_of_build() {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return {};
  const std::filesystem::path python = self.parent_path().parent_path() / "python";
  return std::filesystem::is_regular_file(python / "cdpowder" / "__init__.py", error)
             ? python.string()
             : std::string();
}

std::string python_path_for_child() {
  const std::string package = package_folder_of_build();
  if (package.empty()) return {};
  const char* path = std::getenv("PYTHONPATH");
  return path != nullptr && *path != '\0' ? package + ":" + path : package;
}

}  // namespace cdpowder::app
