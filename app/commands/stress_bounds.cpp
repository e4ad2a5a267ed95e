// stress_bounds.cpp — `cdpowder stress-bounds`: the Python module started in this process's place.
#include "commands/stress_bounds.hpp"

#include "python_child.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <unistd.h>

namespace cdpowder::app {

int run_stress_bounds(const StressBoundsOptions& options) {
  const std::string package = package_folder_of_build();
  if (!package.empty()) {
    const char* path = std::getenv("PYTHONPATH");
    const std::string joined =
        path != nullptr && *path != '\0' ? fmt::format("{}:{}", package, path) : package;
    ::setenv("PYTHONPATH", joined.c_str(), 1);
  }
  const std::string python = python_interpreter();
  std::vector<std::string> words{python, "-m", "cdpowder.stress_bounds"};
  words.insert(words.end(), options.arguments.begin(), options.arguments.end());
  std::vector<char*> argv;
  argv.reserve(words.size() + 1);
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  ::execvp(argv.front(), argv.data());
  std::fprintf(stderr,
               "error: stress-bounds: cannot start %s: %s (it needs Python 3 with NumPy, pandas "
               "and SciPy: tools/install_deps.sh; $CDPOWDER_PYTHON names another interpreter)\n",
               python.c_str(), std::strerror(errno));
  return 2;
}

}  // namespace cdpowder::app
