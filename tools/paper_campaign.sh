#!/usr/bin/env bash
# The paper's sweeps (results/README.md), each into results/paper/<name>, within one
# wall-time budget, such as a sitting at a shared two-core machine or a batch job: each sweep
# in turn, with the time left as its `--time-limit` (a run starts only when it is expected to
# finish), then their reports.
#
#   tools/paper_campaign.sh BUDGET [SWEEP ...]
#
# BUDGET: whole seconds, or whole numbers with units h, m, s, largest first (150m, 2h30m).
# SWEEP: names of examples/paper/<name>_sweep.toml, in the order to run them (default:
# fig5 table1 sensitivity level). Every sweep reuses the finished runs of the others (a run
# with exactly the same scene is the same run), so shared points run once.
# JOBS (default 2): runs at a time. CDPOWDER: a cdpowder binary to run instead of building
# build/release, e.g. a copy kept while the sources change (a run records the commit its
# binary was built from, with "-dirty" if the tree had uncommitted changes then).
# Ctrl-C stops the current sweep as `cdpowder sweep` does and runs no further one. Commit
# `results/` afterwards: it is how the campaign goes on in a later clone.
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
[ $# -ge 1 ] || { sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }

budget_text=$1
shift
sweeps=("$@")
[ ${#sweeps[@]} -gt 0 ] || sweeps=(fig5 table1 sensitivity level)
for name in "${sweeps[@]}"; do
  [ -f "examples/paper/${name}_sweep.toml" ] || {
    echo "paper_campaign: no sweep examples/paper/${name}_sweep.toml (choose from:" \
      "$(cd examples/paper && ls ./*_sweep.toml | sed 's|^\./||; s|_sweep.toml||' | tr '\n' ' '))" >&2
    exit 2
  }
done

# the budget in whole seconds (the same grammar as cdpowder sweep --time-limit, in whole
# numbers; 10# reads "08m" as decimal, not octal)
budget=0
if [[ $budget_text =~ ^[0-9]+$ ]]; then
  budget=$((10#$budget_text))
elif [[ $budget_text =~ ^([0-9]+h)?([0-9]+m)?([0-9]+s)?$ ]]; then
  h=${BASH_REMATCH[1]%h} m=${BASH_REMATCH[2]%m} s=${BASH_REMATCH[3]%s}
  budget=$((10#${h:-0} * 3600 + 10#${m:-0} * 60 + 10#${s:-0}))
fi
[ "$budget" -gt 0 ] || {
  echo "paper_campaign: BUDGET '$budget_text' is not a positive duration (5400, 150m, 2h30m)" >&2
  exit 2
}
deadline=$(($(date +%s) + budget))

if [ -n "${CDPOWDER:-}" ]; then
  cdpowder=$CDPOWDER
else
  cmake --preset release >/dev/null
  cmake --build build/release --target cdpowder >/dev/null
  cdpowder=build/release/app/cdpowder
fi

# A signal stops the running sweep (as Ctrl-C does: its runs write their outputs, flagged
# interrupted) and starts no further one. The sweep runs in the background, so that the
# trap runs at once and not when the sweep ends, and in a session of its own (setsid), so
# that a Ctrl-C at the terminal reaches it once, through the trap, not twice (a second
# signal would kill its runs).
stop=0
sweep_pid=""
trap 'stop=1; [ -z "$sweep_pid" ] || kill -TERM "$sweep_pid" 2>/dev/null || true' INT TERM
shopt -s nullglob
for name in "${sweeps[@]}"; do
  [ "$stop" -eq 0 ] || break
  left=$((deadline - $(date +%s)))
  [ "$left" -gt 60 ] || break
  reuse=()
  for other in results/paper/*/; do
    other=${other%/}
    [ "$other" = "results/paper/$name" ] || reuse+=(--reuse "$other")
  done
  echo "paper_campaign: $name, $((left / 60)) min left" >&2
  setsid "$cdpowder" sweep "examples/paper/${name}_sweep.toml" --out "results/paper/$name" \
    --jobs "${JOBS:-2}" --time-limit "$left" "${reuse[@]}" &
  sweep_pid=$!
  # wait returns early when a trapped signal arrives: wait again until the sweep has ended
  while kill -0 "$sweep_pid" 2>/dev/null; do wait "$sweep_pid" || true; done
  sweep_pid=""
done

for name in "${sweeps[@]}"; do
  [ -f "results/paper/$name/results.csv" ] && /usr/bin/python3 tools/report.py "results/paper/$name" >/dev/null
done
/usr/bin/python3 tools/campaign_status.py
echo "paper_campaign: commit the finished runs with: git add results && git commit" >&2
