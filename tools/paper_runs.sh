#!/usr/bin/env bash
# The paper-scale runs of docs/lab/2026-11-23-validation-single-runs.md:
# examples/paper/scene.toml at (μ_t, μ_n) = (0, 0) and (1, 1), one after the other, into
# runs/paper_0_0 and runs/paper_1_1, then one table row per run (porosity, σ_zz±/p, steps,
# passes, wall time).
# Extra arguments go to every run, e.g.  tools/paper_runs.sh --set solver.dt=0.05
# Long: see docs/performance.md for the wall times. Ctrl-C stops the current run after its
# step and still writes its outputs (flagged interrupted).
set -euo pipefail
cd "$(git rev-parse --show-toplevel)"
cmake --preset release >/dev/null
cmake --build build/release --target cdpowder >/dev/null
stop=0
trap 'stop=1' INT TERM   # Ctrl-C: the current run writes its outputs, then no further run
for point in "0 0" "1 1"; do
  [ "$stop" -eq 0 ] || break
  read -r mu_t mu_n <<<"$point"
  out="runs/paper_${mu_t}_${mu_n}"
  build/release/app/cdpowder compact examples/paper/scene.toml --out "$out" \
    --set contact.mu_roll="$mu_t" --set contact.mu_twist="$mu_n" "$@" || true
done
python3 - <<'PY'
import json, pathlib
print("| (μt, μn) | E | σzz/p | σzz+/p | σzz−/p | blocked | steps | passes/step | wall [s] |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for point in ("0_0", "1_1"):
    f = pathlib.Path(f"runs/paper_{point}/summary.json")
    if not f.exists():
        continue
    s = json.loads(f.read_text()); st = s["stress"]; r = s["run"]
    print(f"| ({point.replace('_', ', ')}) | {s['porosity']:.4f} | {st['sigma_zz_over_pressure']:.4f} "
          f"| {st['sigma_zz_compressive_over_pressure']:.4f} | {st['sigma_zz_tensile_over_pressure']:.4f} "
          f"| {r['blocked']} | {r['steps']} | {r['passes_per_step']:.1f} | {r['wall_seconds']:.0f} |")
PY
