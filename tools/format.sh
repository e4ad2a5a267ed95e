#!/usr/bin/env bash
# Formats every tracked C++ file with the repository's .clang-format.
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
git ls-files '*.cpp' '*.hpp' | xargs clang-format -i
