#!/usr/bin/env bash
# The README's first command: install the dependencies (Debian packages), build the
# release preset, and run the quick example: the paper's experiment with 100 spheres
# (ballistic deposit, piston compaction until the blocked state). Prints the result line
# (porosity, σ_zz and its compressive and tensile parts over the applied pressure).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install_deps.sh
cmake --preset release >/dev/null
cmake --build build/release --target cdpowder
build/release/app/cdpowder compact examples/quick/scene.toml --out runs/quick "$@"
echo "outputs in runs/quick: summary.json, scene.toml, initial_particles.csv, particles.csv,"
echo "contacts.csv, timeseries.csv; particles.vtp, contacts.vtp and walls.vtp (the bottom wall,"
echo "piston and cell) for ParaView (docs/outputs.md)"
