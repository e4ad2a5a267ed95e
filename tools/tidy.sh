#!/usr/bin/env bash
# Runs clang-tidy (config in .clang-tidy) over the library, app, tests and benchmarks,
# using the compile commands of the release build.
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
[ -f build/release/compile_commands.json ] || cmake --preset release >/dev/null
run-clang-tidy-14 -quiet -p build/release "$@" 'src/|app/|tests/|bench/'
