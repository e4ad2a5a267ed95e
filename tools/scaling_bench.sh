#!/usr/bin/env bash
# Thread scaling of the paper example widened at the paper's height: one CSV row per run,
# appended to docs/performance/scaling_runs.csv (or --csv FILE):
#   date,commit,machine,study,point,spheres,cell,threads,steps,passes_per_step,run_seconds,
#   steps_per_second,peak_kb
# Studies (any of them; all three when none is named):
#   --weak      about 6 000 spheres a thread: N = 1015 × 6T, the cell 25 R × √(6T)
#   --strong    100 000 spheres (a 248 R cell) on each thread count
#   --million   1 000 000 spheres (a 785 R cell) on the largest thread count: the step rate
# Options:
#   --threads "1 2 4 8 16"   thread counts (default: 1, 2, 4, … up to the usable cores)
#   --span T                 simulated time of each run in t0 (default 2: the deposit and
#                            about 100 steps of compaction, the piston starting at rest)
#   --points "1,1 0,0"       (μt, μn) of each run (default both corners)
#   --bin PATH               the cdpowder to time (default: build/release/app/cdpowder, built
#                            here first)
#   --csv FILE               where the rows go
# The piston's mass is scaled with the cell's area (docs/lab/2026-11-29-what-grows-the-passes.md):
# a wider cell then has the paper's physics per area. Threads are pinned through OpenMP's
# standard environment (OMP_PROC_BIND=close, OMP_PLACES=cores) unless it is set already, and
# every step that has tiles to share runs on them (CDPOWDER_ALWAYS_THREADED=1, unless set):
# the bench measures the threads, not the run's choice between them and one thread.
# Compare timings as ratios within one session: the machine may be shared.
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"

studies=()
threads=""
span=2
points="1,1 0,0"
bin=""
csv=docs/performance/scaling_runs.csv
while [ $# -gt 0 ]; do
  case "$1" in
    --weak | --strong | --million) studies+=("${1#--}") ;;
    --threads) threads="$2"; shift ;;
    --span) span="$2"; shift ;;
    --points) points="$2"; shift ;;
    --bin) bin="$2"; shift ;;
    --csv) csv="$2"; shift ;;
    *) echo "scaling_bench: unknown argument '$1' (see the head of $0)" >&2; exit 2 ;;
  esac
  shift
done
[ ${#studies[@]} -gt 0 ] || studies=(weak strong million)
if [ -z "$bin" ]; then
  cmake --preset release >/dev/null
  cmake --build build/release --target cdpowder >/dev/null
  bin=build/release/app/cdpowder
fi
cores="$(nproc)"
if [ -z "$threads" ]; then
  threads=""
  for t in 1 2 4 8 16 32 64; do [ "$t" -le "$cores" ] && threads="$threads $t"; done
fi
export OMP_PROC_BIND="${OMP_PROC_BIND:-close}" OMP_PLACES="${OMP_PLACES:-cores}"
export CDPOWDER_ALWAYS_THREADED="${CDPOWDER_ALWAYS_THREADED:-1}"

header="date,commit,machine,study,point,spheres,cell,threads,steps,passes_per_step,run_seconds,steps_per_second,peak_kb"
mkdir -p "$(dirname "$csv")"
[ -f "$csv" ] || echo "$header" >"$csv"
commit="$(git rev-parse --short=12 HEAD 2>/dev/null || echo unknown)"

# one run: study, point "μt,μn", spheres, threads
run() {
  local study="$1" point="$2" spheres="$3" t="$4"
  local mu_t="${point%,*}" mu_n="${point#*,}"
  # the cell keeps the paper's spheres per area, the piston its mass per area
  local cell mass
  cell="$(/usr/bin/python3 -c "print(f'{25 * ($spheres / 1015) ** 0.5:.6g}')")"
  mass="$(/usr/bin/python3 -c "print(f'{1000 * $spheres / 1015:.6g}')")"
  local out
  out="$(mktemp -d)"
  /usr/bin/time -f "%M" -o "$out/peak_kb" "$bin" compact examples/paper/scene.toml --out "$out/run" \
    --quiet --set deposition.spheres="$spheres" --set system.lx="$cell" --set system.ly="$cell" \
    --set piston.mass="$mass" --set contact.mu_roll="$mu_t" --set contact.mu_twist="$mu_n" \
    --set solver.threads="$t" --set run.max_duration="$span" >/dev/null 2>&1 ||
    [ -f "$out/run/summary.json" ]  # a run that did not block (the span ran out) still times
  /usr/bin/python3 - "$out/run/summary.json" "$(tail -1 "$out/peak_kb")" "$commit" "$cores" \
    "$study" "$point" "$cell" "$t" >>"$csv" <<'PY'
import datetime, json, sys
s = json.load(open(sys.argv[1]))
r, p = s["run"], s["program"]
machine = f"{p.get('cpu') or 'unknown CPU'} x{sys.argv[4]}, {p.get('kernel') or 'unknown kernel'}"
seconds = r["wall_seconds"]
print(",".join(str(x) for x in [
    datetime.date.today().isoformat(), sys.argv[3], '"' + machine + '"', sys.argv[5],
    '"' + sys.argv[6] + '"', s["spheres"], sys.argv[7], sys.argv[8], r["steps"],
    round(r["passes_per_step"], 2), round(seconds, 3),
    round(r["steps"] / seconds, 3) if seconds > 0 else "", sys.argv[2]]))
PY
  tail -1 "$csv"
  rm -rf "$out"
}

largest="${threads##* }"
for study in "${studies[@]}"; do
  for point in $points; do
    case "$study" in
      weak) for t in $threads; do run weak "$point" $((1015 * 6 * t)) "$t"; done ;;
      strong) for t in $threads; do run strong "$point" 100000 "$t"; done ;;
      million) run million "$point" 1000000 "$largest" ;;
    esac
  done
done
