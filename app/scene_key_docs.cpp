// scene_key_docs.cpp — a developer tool, not installed: writes the generated key tables of
// docs/config.md (scene_key_docs.hpp), or with --check fails when the file's copy is stale.
// A test of the default run calls it with --check.
#include "cdpowder/config/scene_key_docs.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace {

/// The first line where two texts differ (1-based), for the message.
int first_difference(const std::string& a, const std::string& b) {
  int line = 1;
  for (std::size_t i = 0; i < a.size() && i < b.size() && a[i] == b[i]; ++i) {
    if (a[i] == '\n') ++line;
  }
  return line;
}

}  // namespace

int main(int argc, char** argv) {
  const bool check = argc == 3 && std::string_view(argv[1]) == "--check";
  if (argc != 2 && !check) {
    std::fprintf(stderr, "usage: %s [--check] docs/config.md\n", argv[0]);
    return 2;
  }
  const std::string file = argv[argc - 1];
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) {
    std::fprintf(stderr, "%s: cannot read\n", file.c_str());
    return 2;
  }
  try {
    const std::string generated = cdpowder::with_generated_key_tables(text.str());
    if (check) {
      if (generated == text.str()) return 0;
      std::fprintf(stderr,
                   "%s:%d: the generated scene key tables differ from src/cdpowder/config/"
                   "scene_keys.hpp; regenerate them with:\n  %s %s\n",
                   file.c_str(), first_difference(generated, text.str()), argv[0], file.c_str());
      return 1;
    }
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << generated;
    return out ? 0 : 2;
  } catch (const std::invalid_argument& error) {
    std::fprintf(stderr, "%s: %s\n", file.c_str(), error.what());
    return 2;
  }
}
