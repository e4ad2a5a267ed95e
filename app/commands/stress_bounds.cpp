// stress_bounds.cpp — `cdpowder stress-bounds`: the Python module started in this process's
// place, or as a child of a sweep (`cdpowder sweep --stress-bounds`).
#include "commands/stress_bounds.hpp"

#include "python_child.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace cdpowder::app {

namespace {

/// The command line of the module: interpreter, -m cdpowder.stress_bounds, the arguments.
std::vector<std::string> module_words(const std::vector<std::string>& arguments) {
  std::vector<std::string> words{python_interpreter(), "-m", "cdpowder.stress_bounds"};
  words.insert(words.end(), arguments.begin(), arguments.end());
  return words;
}

/// PYTHONPATH with the build tree's package first, or as it is for an installed program.
void put_package_on_python_path() {
  const std::string path = python_path_for_child();
  if (!path.empty()) ::setenv("PYTHONPATH", path.c_str(), 1);
}

std::vector<char*> pointers(std::vector<std::string>& words) {
  std::vector<char*> argv;
  argv.reserve(words.size() + 1);
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  return argv;
}

void say_cannot_start(const std::string& python, int error) {
  std::fprintf(stderr,
               "error: stress-bounds: cannot start %s: %s (it needs Python 3 with NumPy, pandas "
               "and SciPy: tools/install_deps.sh; $CDPOWDER_PYTHON names another interpreter)\n",
               python.c_str(), std::strerror(error));
}

}  // namespace

int run_stress_bounds(const StressBoundsOptions& options) {
  put_package_on_python_path();
  std::vector<std::string> words = module_words(options.arguments);
  std::vector<char*> argv = pointers(words);
  std::fflush(stdout);
  std::fflush(stderr);
  ::execvp(argv.front(), argv.data());
  say_cannot_start(words.front(), errno);
  return 2;
}

int spawn_stress_bounds(const std::vector<std::string>& arguments) {
  put_package_on_python_path();
  std::vector<std::string> words = module_words(arguments);
  std::vector<char*> argv = pointers(words);
  std::fflush(stdout);
  std::fflush(stderr);
  pid_t child = 0;
  const int error = ::posix_spawnp(&child, argv.front(), nullptr, nullptr, argv.data(), environ);
  if (error != 0) {
    say_cannot_start(words.front(), error);
    return 2;
  }
  int status = 0;
  while (::waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) return 1;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 1;
}

}  // namespace cdpowder::app
