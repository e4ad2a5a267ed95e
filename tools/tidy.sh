#!/usr/bin/env bash
# Runs clang-tidy (config in .clang-tidy, every warning an error) with the compile commands
# of a configured build, two files at a time (the machine has two cores):
#   tools/tidy.sh [build folder] [folders...]    default: build/ci (CI builds it first),
#                                                src app python
#   tools/tidy.sh build/ci src app tests         the tests too (docs/testing.md: their cost)
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
build=${1:-build/ci}
[ $# -eq 0 ] || shift
folders=("$@")
[ ${#folders[@]} -gt 0 ] || folders=(src app python)
if [ ! -f "$build/compile_commands.json" ]; then
  echo "tidy: $build/compile_commands.json is missing: configure that build first" \
    "(CMakeLists.txt sets CMAKE_EXPORT_COMPILE_COMMANDS)" >&2
  exit 2
fi
# anchored at the source tree, so the sources CMake generates inside the build are left out
# (a folder or a single file: "src", "src/cdpowder/run/state_file.cpp")
pattern="^$PWD/($(IFS='|'; echo "${folders[*]}"))(/|\$)"
# GCC's link-time-optimisation flags (pybind11 adds -fno-fat-lto-objects to the Python module)
# mean nothing to clang: not a finding, and an error where the build has -Werror
run-clang-tidy -quiet -j 2 -p "$build" -extra-arg=-Wno-ignored-optimization-argument "$pattern"
