#!/usr/bin/env bash
# Times whole runs of the cdpowder command and appends one CSV row per run to
# docs/performance/whole_runs.csv:
#   date,commit,machine,scene,spheres,steps,sweeps_per_step,wall_seconds,nlgs_seconds,porosity
# Usage: tools/whole_run_bench.sh [SCENE.toml ...]   (default: examples/lattice/scene.toml)
# Builds the release preset first. Compare timings as ratios within one session: the
# machine may be shared.
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
cmake --preset release >/dev/null
cmake --build build/release --target cdpowder >/dev/null
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(examples/lattice/scene.toml)
out_csv=docs/performance/whole_runs.csv
mkdir -p "$(dirname "$out_csv")"
[ -f "$out_csv" ] || echo "date,commit,machine,scene,spheres,steps,sweeps_per_step,wall_seconds,nlgs_seconds,porosity" >"$out_csv"
machine="$(lscpu | sed -n 's/^Model name: *//p' | head -1) x$(nproc)"
commit="$(git rev-parse --short=12 HEAD)"
for scene in "${scenes[@]}"; do
  out="$(mktemp -d)"
  build/release/app/cdpowder simulate "$scene" --out "$out" --quiet >/dev/null
  python3 - "$out/summary.json" "$scene" "$commit" "$machine" >>"$out_csv" <<'PY'
import datetime, json, sys
s = json.load(open(sys.argv[1]))
r = s["run"]
print(",".join(str(x) for x in [
    datetime.date.today().isoformat(), sys.argv[3], '"' + sys.argv[4] + '"', sys.argv[2],
    s["spheres"], r["steps"], round(r["sweeps_per_step"], 2), round(r["wall_seconds"], 3),
    round(r["stage_seconds"]["solve_nlgs"], 3), round(s["porosity"], 5)]))
PY
  tail -1 "$out_csv"
  rm -rf "$out"
done
