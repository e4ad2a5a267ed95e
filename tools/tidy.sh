#!/usr/bin/env bash
# Runs clang-tidy (config in .clang-tidy, every warning an error) with the compile commands
# of a configured build, two files at a time (the machine has two cores):
#   tools/tidy.sh [build folder] [folders...]    default: build/ci (CI builds it first),
#                                                src app python
#   tools/tidy.sh build/ci src app tests         the tests too (docs/testing.md: their cost)
#   CDPOWDER_TIDY_ANALYZER=deep tools/tidy.sh build/ci src/cdpowder/io/vtk.cpp
#                                                the static analyzer at its full depth
# The clang static analyzer runs in its shallow mode unless CDPOWDER_TIDY_ANALYZER=deep:
# fewer paths through fewer inlined calls, about a fifth of the deep analysis's time on a
# library file (docs/testing.md, "Static analysis"). The deep analysis is for the files a
# change touches, before it is merged.
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
depth=${CDPOWDER_TIDY_ANALYZER:-shallow}
case "$depth" in
  shallow) analyzer=(-extra-arg=-Xclang -extra-arg=-analyzer-config -extra-arg=-Xclang
                     -extra-arg=mode=shallow) ;;
  deep) analyzer=() ;;
  *) echo "tidy: CDPOWDER_TIDY_ANALYZER is '$depth'; expected shallow or deep" >&2; exit 2 ;;
esac
# clang-tidy 22 (Debian's clang-tidy-22, tools/install_deps.sh) leaves the system headers'
# declarations out of its checks' matching, which clang-tidy 14 walked for every file: a
# third of the time. Where it is missing, Debian's clang-tidy (14) checks alike.
tidy=clang-tidy-22
if ! command -v "$tidy" >/dev/null || ! command -v "run-$tidy" >/dev/null; then
  echo "tidy: clang-tidy-22 is missing (apt-get install clang-tidy-22); using clang-tidy" \
    "(Debian 12: version 14, about three times slower)" >&2
  tidy=clang-tidy
fi
# clang reads the OpenMP pragmas (-fopenmp in the compile commands) and needs an omp.h.
# clang 14 finds libomp-dev's (the ThreadSanitizer build's runtime); clang 22 gets the one of
# the libgomp we compile against, alone in a folder, so that none of GCC's other headers (its
# intrinsics) come before clang's own. (clang 14 cannot read that one.)
omp_arg=()
if [ "$tidy" = clang-tidy-22 ]; then
  omp=$(mktemp -d)
  trap 'rm -rf "$omp"' EXIT
  ln -s "$(gcc -print-file-name=include/omp.h)" "$omp/omp.h"
  omp_arg=(-extra-arg=-isystem"$omp")
fi
# anchored at the source tree, so the sources CMake generates inside the build are left out
# (a folder or a single file: "src", "src/cdpowder/run/state_file.cpp")
pattern="^$PWD/($(IFS='|'; echo "${folders[*]}"))(/|\$)"
# GCC's link-time-optimisation flags (pybind11 adds -fno-fat-lto-objects to the Python module)
# mean nothing to clang: not a finding, and an error where the build has -Werror
"run-$tidy" -clang-tidy-binary "$(command -v "$tidy")" -quiet -j 2 -p "$build" \
  -extra-arg=-Wno-ignored-optimization-argument "${omp_arg[@]}" "${analyzer[@]}" \
  "$pattern"
