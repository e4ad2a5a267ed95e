#!/usr/bin/env bash
# Times whole runs of the cdpowder command and appends one CSV row per run to
# docs/performance/whole_runs.csv:
#   date,commit,machine,scene,settings,spheres,steps,passes_per_step,wall_seconds,nlgs_seconds,porosity
# Usage:
#   tools/whole_run_bench.sh [SCENE.toml ...]        each scene as it is (default: examples/lattice)
#   tools/whole_run_bench.sh --corners [--set K=V]…  the paper example (1 015 spheres) at the four
#                                                    corners of Table 1, (μt, μn) = (0,0), (0,1),
#                                                    (1,0), (1,1), one run at a time, seed 1;
#                                                    e.g. --set solver.threads=2
# Builds the release preset first. Compare timings as ratios within one session: the machine
# may be shared.
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
cmake --preset release >/dev/null
cmake --build build/release --target cdpowder >/dev/null

corners=false
settings=()
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --corners) corners=true ;;
    --set) settings+=("--set" "$2"); shift ;;
    *) scenes+=("$1") ;;
  esac
  shift
done
runs=()  # "scene|point settings" per run
if $corners; then
  for point in "0.0 0.0" "0.0 1.0" "1.0 0.0" "1.0 1.0"; do
    read -r mu_t mu_n <<<"$point"
    runs+=("examples/paper/scene.toml|--set contact.mu_roll=$mu_t --set contact.mu_twist=$mu_n")
  done
else
  [ ${#scenes[@]} -gt 0 ] || scenes=(examples/lattice/scene.toml)
  for scene in "${scenes[@]}"; do runs+=("$scene|"); done
fi

out_csv=docs/performance/whole_runs.csv
header="date,commit,machine,scene,settings,spheres,steps,passes_per_step,wall_seconds,nlgs_seconds,porosity"
mkdir -p "$(dirname "$out_csv")"
[ -f "$out_csv" ] || echo "$header" >"$out_csv"
cores="$(nproc)"
commit="$(git rev-parse --short=12 HEAD)"
for run in "${runs[@]}"; do
  scene="${run%%|*}"
  point="${run#*|}"
  out="$(mktemp -d)"
  # shellcheck disable=SC2086  # the point's settings are words
  build/release/app/cdpowder simulate "$scene" --out "$out" --quiet $point "${settings[@]}" >/dev/null ||
    [ $? -eq 4 ]  # a run that did not block still times
  /usr/bin/python3 - "$out/summary.json" "$scene" "$commit" "$cores" \
    "$(echo "$point ${settings[*]}" | sed 's/--set //g; s/^ *//; s/ *$//')" >>"$out_csv" <<'PY'
import datetime, pathlib, sys
sys.path.insert(0, str(pathlib.Path("tools").resolve()))
from run_summary import read_summary
s = read_summary(sys.argv[1])
r = s["run"]
# the machine as the run saw it: the CPU (name, family, model), the cores, the kernel's
# instruction set (docs/outputs.md, program.cpu and program.kernel)
p = s["program"]
machine = f"{p.get('cpu') or 'unknown CPU'} x{sys.argv[4]}, {p.get('kernel') or 'unknown kernel'}"
print(",".join(str(x) for x in [
    datetime.date.today().isoformat(), sys.argv[3], '"' + machine + '"', sys.argv[2],
    '"' + sys.argv[5] + '"', s["spheres"], r["steps"], round(r["passes_per_step"], 2),
    round(r["wall_seconds"], 3), round(r["stage_seconds"]["solve_nlgs"], 3),
    round(s["porosity"], 5)]))
PY
  tail -1 "$out_csv"
  rm -rf "$out"
done
