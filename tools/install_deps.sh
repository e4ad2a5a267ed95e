#!/usr/bin/env bash
# Installs everything cdpowder needs to build, test, benchmark and plot, from Debian's
# packages only. Idempotent; run as root (or with sudo available).
set -euo pipefail
packages=(
  build-essential cmake ninja-build git clang-format clang-tidy clang libomp-dev
  libeigen3-dev libtomlplusplus-dev libcli11-dev libfmt-dev libpcg-cpp-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev zlib1g-dev libopenmpi-dev openmpi-bin
  python3 python3-numpy python3-pandas python3-scipy python3-matplotlib python3-vtk9 help2man
  coinor-libclp1
  python3-dev pybind11-dev python3-pytest pyflakes3 python3-venv python3-pip python3-setuptools
  python3-wheel python3-sphinx python3-myst-parser
)
# clang-tidy 22 (bookworm-security) runs tools/tidy.sh in a third of clang-tidy 14's time;
# where the archive does not offer it, tools/tidy.sh uses clang-tidy 14 and says so
optional=(clang-tidy-22)
# the names among "$@" that dpkg does not have installed, one a line
not_installed() {
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || echo "$p"
  done
}
mapfile -t missing < <(not_installed "${packages[@]}")
mapfile -t missing_optional < <(not_installed "${optional[@]}")
if [ ${#missing[@]} -eq 0 ] && [ ${#missing_optional[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
sudo_cmd=""
[ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
export DEBIAN_FRONTEND=noninteractive
if [ ${#missing[@]} -gt 0 ]; then
  $sudo_cmd apt-get update -qq
  $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
  echo "install_deps: installed ${missing[*]}"
elif ! $sudo_cmd apt-get update -qq; then
  echo "install_deps: the required packages are present; apt-get update failed, so" \
    "${missing_optional[*]} stays missing"
  exit 0
fi
for p in "${missing_optional[@]}"; do
  if $sudo_cmd apt-get install -y -qq --no-install-recommends "$p"; then
    echo "install_deps: installed $p"
  else
    echo "install_deps: $p is not offered here; going on without it"
  fi
done
