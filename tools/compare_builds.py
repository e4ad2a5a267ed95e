#!/usr/bin/python3
"""Times two builds of cdpowder on the same runs, side by side: for each point (μt, μn) the
two builds compact the same scene and seed at the same time, one per core, so both see the
same machine (on a shared machine compare the ratio, not the seconds). Prints one row per
point and writes them to OUT/compare.json.

usage: tools/compare_builds.py --before EXE --after EXE [--scene examples/paper/scene.toml]
           [--points 0,0 0,1 1,0 1,1] [--seed 1] [--set KEY=VALUE ...] --out DIR
Debian python3, standard library only.
"""
import argparse
import json
import pathlib
import subprocess
import sys

from run_summary import read_summary


def start(exe, scene, out, point, seed, overrides):
    mu_t, mu_n = point.split(",")
    command = [exe, "compact", scene, "--out", str(out), "--quiet",
               "--set", f"contact.mu_roll={mu_t}", "--set", f"contact.mu_twist={mu_n}",
               "--set", f"deposition.seed={seed}", "--set", f"solver.seed={seed}"]
    for item in overrides:
        command += ["--set", item]
    return subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)


def measured(folder):
    s = read_summary(pathlib.Path(folder, "summary.json"))
    r = s["run"]
    return {"porosity": s["porosity"], "steps": r["steps"], "passes": r["total_passes"],
            "wall_seconds": r["wall_seconds"], "nlgs_seconds": r["stage_seconds"]["solve_nlgs"],
            "blocked": r["blocked"]}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--before", required=True)
    parser.add_argument("--after", required=True)
    parser.add_argument("--scene", default="examples/paper/scene.toml")
    parser.add_argument("--points", nargs="+", default=["0,0", "0,1", "1,0", "1,1"])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--set", action="append", default=[], dest="overrides")
    parser.add_argument("--out", required=True, type=pathlib.Path)
    args = parser.parse_args()
    rows = []
    print("| point | before: wall [s], steps, passes, E | after: wall [s], steps, passes, E "
          "| before/after (wall) |")
    print("| --- | --- | --- | --- |")
    for point in args.points:
        folders = {side: args.out / side / point.replace(",", "_") for side in ("before", "after")}
        runs = {side: start(getattr(args, side), args.scene, folders[side], point, args.seed,
                            args.overrides) for side in ("before", "after")}
        for side, run in runs.items():
            _, err = run.communicate()
            if run.returncode != 0:
                print(f"{side} at ({point}) exited with {run.returncode}: {err.strip()}",
                      file=sys.stderr)
                return 1
        row = {"point": point, **{side: measured(folders[side]) for side in runs}}
        rows.append(row)
        b, a = row["before"], row["after"]
        print(f"| ({point}) | {b['wall_seconds']:.1f}, {b['steps']}, {b['passes']}, "
              f"{b['porosity']:.5f} | {a['wall_seconds']:.1f}, {a['steps']}, {a['passes']}, "
              f"{a['porosity']:.5f} | {b['wall_seconds'] / a['wall_seconds']:.2f} |", flush=True)
    (args.out / "compare.json").write_text(json.dumps(
        {"before": args.before, "after": args.after, "scene": args.scene, "seed": args.seed,
         "overrides": args.overrides, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
