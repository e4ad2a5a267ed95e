#!/usr/bin/env bash
# The README's first command: install the dependencies (Debian packages), build the
# release preset, and run the quick example: the paper's experiment with 100 spheres
# (ballistic deposit, piston compaction until the blocked state). Prints the result line
# (porosity, σ_zz and its compressive and tensile parts over the applied pressure).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install_deps.sh
cmake --preset release >/dev/null
# the program, and the Python package (build/release/python) when pybind11 was found
targets=(cdpowder)
if cmake --build build/release --target help | grep -q '^cdpowder_python:'; then
  targets+=(cdpowder_python)
fi
cmake --build build/release --target "${targets[@]}"
build/release/app/cdpowder compact examples/quick/scene.toml --out runs/quick "$@"
echo "outputs in runs/quick: summary.json, scene.toml, initial_particles.csv, particles.csv,"
echo "contacts.csv, timeseries.csv; particles.vtp, contacts.vtp and walls.vtp (the bottom wall,"
echo "piston and cell) for ParaView (docs/outputs.md)"
if [ ${#targets[@]} -gt 1 ]; then
  echo "Python: PYTHONPATH=build/release/python python3 -c 'import cdpowder' (docs/python.md)"
fi
