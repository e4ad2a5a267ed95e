#!/usr/bin/env bash
# The README's first command: install the dependencies (Debian packages), build the
# release preset, and run the quick example: a loose cohesive packing compacted by the
# paper's piston until it blocks. Prints the result line (porosity, σ_zz and its parts).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install_deps.sh
cmake --preset release >/dev/null
cmake --build build/release --target cdpowder
build/release/app/cdpowder simulate examples/lattice/scene.toml --out runs/lattice "$@"
echo "outputs in runs/lattice: summary.json, particles.csv, contacts.csv, timeseries.csv"
