#!/usr/bin/python3
"""The paired multi-seed accuracy gate: does a candidate build (or setting) give the base's results?

    tools/accuracy_gate.py (--base BIN_A | --base-runs SWEEP_DIR)
        (--candidate BIN_B | --candidate-runs SWEEP_DIR) [--scene SCENE.toml] --seeds 1-10
        --points 0,0 1,1 --out DIR [--jobs N] [--set key=value ...]
        [--base-set key=value ...] [--candidate-set key=value ...] [--reuse OTHER_DIR ...]

For every point (μt, μn) and seed s it runs

    BIN compact SCENE --out DIR/<side>/<point>/seed<s> --quiet
        --set deposition.seed=s --set solver.seed=s
        --set contact.mu_roll=μt --set contact.mu_twist=μn  [--set …] [--<side>-set …]

for both sides (side = base, candidate; later overrides of a key win), --jobs at a time,
and then compares the two sides seed by seed: same seed, same deposit, so the paired
difference candidate − base carries the spread of the compaction alone. A value may name
the run's seed: `{seed}`, `{seed+N}` or `{seed-N}`, e.g. `--candidate-set
solver.seed={seed+1000}` compares a build with itself on the same deposits and another
sweep-order stream (the noise floor).

A point PASSES when (docs/performance.md, "Accuracy gate"; physics.md §17):
  (a) the mean of ΔE (final porosity) is within 2 standard errors of zero and |mean ΔE| < 0.005;
  (b) the means of Δσzz+/p and Δσzz−/p are each within 2 standard errors of zero;
  (c) every candidate run has |σzz/p − 1| ≤ 0.01;
  (d) every run (base and candidate) is blocked, not interrupted and has every field the gate
      reads (a missing one is named), and every candidate run's accuracy gauges are within the
      contract: mean overlap ≤ 1e-3 R, largest cohesive opening per step ≤ 0.1 d_coh, piston
      force imbalance ≤ the scene's run.blocked.force_balance, and the largest net force on a
      sphere ≤ force_balance × F, the piston's load (physics.md §17; the engine's own balance
      test before it adopts a blocked state, run_loop.cpp, uses the same bound).
The gate judges the candidate, not the engine's state before the change: base runs out of
the contract in (c) or (d) are counted and listed ("base N of 10") but fail nothing by
themselves. A candidate gauge out of the contract at a point where the base is out on the
same gauge in at least one run is "inherited": that gauge passes when the candidate's worst
value over the point's runs is no worse than the base's worst × (1 + INHERITED_MARGIN), and
the point then reads "PASS (inherited: opening)". Why: the quick scene's (0, 0) runs exceed
0.1 d_coh of cohesive opening per step at Δt = 0.01 before any change (7 of 10 base runs,
worst 0.165); a strict (d) there would fail every candidate whatever it does, including the
ones that leave the results alone. The adaptive time step of the speed work is what will
bring those runs within the contract; until then a change must not make them worse.
Blocked, interrupted and missing fields are never inherited, and (c) stays strict for the
candidate.
Standard errors are of the mean paired difference over the seeds (n − 1 in the variance);
the gate needs at least two seeds.

A run is reused (the gate resumes) when DIR/<side>/<point>/seed<s> (or the same place in a
--reuse folder) holds a summary.json of a finished run (not interrupted) and a gate_run.json
naming the same binary (SHA-256), the same scene file (SHA-256) and the same overrides.

Either side may instead be the finished runs of a `cdpowder sweep` (--base-runs DIR,
--candidate-runs DIR: DIR/runs/<point>/seed_<s>/summary.json, made with the sweep's default
seed keys, deposition.seed = solver.seed = s): the paper-scale gate against the committed
runs of results/table1, or a rerun of a whole table against the committed one. Such a side
never runs; a missing or unfinished run is named and nothing runs (exit status 2).

Writes DIR/gate.json (every run's numbers, the per-point statistics and checks) and
DIR/gate.md, and prints the table. Exit status 0 when every point passes (inherited
violations included), 1 when one fails
(or a run failed or was interrupted), 2 on bad arguments (also when the program rejects the
scene or an override). Debian's /usr/bin/python3 with python3-numpy.
"""
import argparse
import concurrent.futures
import hashlib
import json
import math
import os
import pathlib
import re
import shlex
import subprocess
import sys
import threading
import time

import numpy as np

from run_summary import SummaryError, read_summary

MU_T = "contact.mu_roll"
MU_N = "contact.mu_twist"
SEED_KEYS = ("deposition.seed", "solver.seed")
SIDES = ("base", "candidate")

# The gate's limits (physics.md §17; docs/performance.md "Accuracy gate").
N_STANDARD_ERRORS = 2.0          # a mean difference within this many standard errors of zero
MAX_MEAN_DELTA_POROSITY = 0.005  # |mean ΔE|: the contract's 0.5 % (absolute) porosity change
SIGMA_BALANCE_TOLERANCE = 0.01   # |σzz/p − 1| of a blocked packing
MAX_MEAN_OVERLAP = 1e-3          # mean overlap, in units of the sphere radius R
MAX_OPENING_PER_RANGE = 0.1      # largest cohesive opening per step / d_coh (physics.md §6.4)
MIN_PAIRS = 2                    # a standard error needs two pairs
# A candidate gauge out of the contract where the base is out too ("inherited") passes when
# its worst over the point's runs is ≤ the base's worst × (1 + INHERITED_MARGIN): a change
# must not make a contract violation that the engine already has worse, but the worst of ten
# runs moves from stream to stream by about this much when nothing changed (noise floor on the
# quick scene at (0, 0): base worst opening 0.165, the same program reseeded 0.167).
INHERITED_MARGIN = 0.10



def _number(x):
    """x as a float when it is a number (not a bool), else None."""
    return float(x) if isinstance(x, (int, float)) and not isinstance(x, bool) else None


# The gauges of (d) that a candidate may inherit from the base: name → (label, the gauge of
# one run's values, in the unit of the table (the overlap in R), or None when the run lacks it)
GAUGES = {
    "overlap": ("mean overlap [R]",
                lambda v: None if _number(v["mean_overlap"]) is None
                else _number(v["mean_overlap"]) / v["radius"]),
    "opening": ("largest cohesive opening per step", lambda v: _number(v["opening"])),
    "piston": ("piston force imbalance", lambda v: _number(v["piston_imbalance"])),
    "net force": ("largest net force on a sphere", lambda v: _number(v["max_net_force"])),
}

# summary.json fields the gate reads: name → path of keys
FIELDS = {
    "porosity": ("porosity",),
    "sigma": ("stress", "sigma_zz_over_pressure"),
    "sigma_plus": ("stress", "sigma_zz_compressive_over_pressure"),
    "sigma_minus": ("stress", "sigma_zz_tensile_over_pressure"),
    "mean_overlap": ("accuracy", "mean_overlap"),
    "opening": ("accuracy", "max_cohesive_opening_per_range"),
    "piston_imbalance": ("piston", "force_imbalance"),
    "max_net_force": ("accuracy", "max_net_force"),
    "force_balance": ("scene", "run", "blocked", "force_balance"),
    "load": ("piston", "applied_force"),
    "load_with_weight": ("piston", "load"),
    "blocked": ("run", "blocked"),
    "interrupted": ("run", "interrupted"),
    "wall_seconds": ("run", "wall_seconds"),
}
# The radius that scales the overlap: the smallest sphere's (units R = 1 when it is absent,
# e.g. a scene that reads its spheres from a CSV file).
RADIUS_FIELD = ("scene", "deposition", "radius_min")
# The differences the gate takes, with their names in the tables
DIFFERENCES = (("porosity", "ΔE"), ("sigma_plus", "Δσzz+/p"), ("sigma_minus", "Δσzz−/p"),
               ("sigma", "Δσzz/p"))

PLACEHOLDER = re.compile(r"\{seed(?:([+-])(\d+))?\}")
KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)+")


class BadArgument(Exception):
    """A command-line argument the gate cannot use: exit status 2."""


# ---------------------------------------------------------------------------------------------
# Arguments


def parse_seeds(text):
    """'1-3,5' → [1, 2, 3, 5]."""
    seeds = set()
    for item in text.split(","):
        m = re.fullmatch(r"\s*(\d+)\s*(?:-\s*(\d+)\s*)?", item)
        if not m or (m[2] and int(m[2]) < int(m[1])):
            raise BadArgument(f"--seeds: '{item}' in '{text}' is not a seed (an integer ≥ 0) "
                              "or a rising range of seeds; allowed: 1-10, 1,3,5, 1-3,7")
        seeds.update(range(int(m[1]), int(m[2] or m[1]) + 1))
    if len(seeds) < MIN_PAIRS:
        raise BadArgument(f"--seeds: '{text}' gives {len(seeds)} seed; the gate needs at least "
                          f"{MIN_PAIRS} (a standard error of the paired difference)")
    return sorted(seeds)


def parse_point(text):
    """'0.3,1' → (0.3, 1.0)."""
    parts = text.split(",")
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        values = ()
    if len(values) != 2 or not all(math.isfinite(v) and v >= 0 for v in values):
        raise BadArgument(f"--points: '{text}' is not a point μt,μn; allowed: two numbers ≥ 0 "
                          "separated by a comma (0,0  1,1  0.3,0.1)")
    return values


def point_label(point):
    return f"{MU_T}={point[0]:g},{MU_N}={point[1]:g}"


def parse_set(text, option):
    """'section.key=value' → (key, value); the value may hold {seed}, {seed+N}, {seed-N}."""
    key, sep, value = text.partition("=")
    key = key.strip()
    if not sep or not KEY.fullmatch(key) or value.strip() == "":
        raise BadArgument(f"{option}: '{text}' is not an override; allowed: section.key=value, "
                          "e.g. solver.tolerance=1e-4")
    if key in (MU_T, MU_N):
        raise BadArgument(f"{option}: '{text}' sets {key}, which --points sets for every run; "
                          "give the value in --points")
    for brace in re.finditer(r"\{[^{}]*\}", value):
        if "seed" in brace[0] and not PLACEHOLDER.fullmatch(brace[0]):
            raise BadArgument(f"{option}: '{text}' has the placeholder {brace[0]}; allowed: "
                              "{seed}, {seed+N}, {seed-N} (N an integer)")
    return key, value.strip()


def with_seed(value, seed):
    """The value with every {seed}, {seed+N}, {seed-N} replaced by the number."""
    def replace(m):
        offset = int(m[2]) if m[2] else 0
        return str(seed + offset if m[1] != "-" else seed - offset)
    return PLACEHOLDER.sub(replace, value)


def overrides_for(point, seed, common, side_sets):
    """The run's overrides in order, later ones winning: seeds, the point, --set, the side's."""
    out = {key: str(seed) for key in SEED_KEYS}
    out[MU_T], out[MU_N] = repr(float(point[0])), repr(float(point[1]))
    for key, value in list(common) + list(side_sets):
        out[key] = with_seed(value, seed)
    return out


def executable(text, option):
    path = pathlib.Path(text)
    if not path.is_file() or not os.access(path, os.X_OK):
        raise BadArgument(f"{option}: '{text}' is not an executable file; allowed: a cdpowder "
                          "program, e.g. build/release/app/cdpowder")
    return path.resolve()


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="tools/accuracy_gate.py",
        description="Paired multi-seed accuracy gate: base against candidate, seed by seed.")
    parser.add_argument("--base", help="the program before the change")
    parser.add_argument("--base-runs", metavar="SWEEP_DIR",
                        help="instead of --base: the finished runs of an earlier `cdpowder sweep` "
                             "(SWEEP_DIR/runs/<point>/seed_<s>/summary.json, e.g. results/table1), "
                             "made with the sweep's default seed keys (deposition.seed = "
                             "solver.seed = s)")
    parser.add_argument("--candidate", help="the program with the change")
    parser.add_argument("--candidate-runs", metavar="SWEEP_DIR",
                        help="instead of --candidate: the finished runs of a sweep (as --base-runs)")
    parser.add_argument("--scene", help="the scene, e.g. examples/quick/scene.toml (needed when "
                                        "a side runs)")
    parser.add_argument("--seeds", required=True, help="seeds: 1-10, 1,3,5 (at least 2)")
    parser.add_argument("--points", required=True, nargs="+", metavar="MUT,MUN",
                        help="points μt,μn, e.g. 0,0 1,1")
    parser.add_argument("--out", required=True, help="folder for the runs, gate.json and gate.md")
    parser.add_argument("--jobs", default="1", help="runs at a time (default 1)")
    parser.add_argument("--set", dest="common", action="append", default=[],
                        metavar="KEY=VALUE", help="override of every run (repeatable)")
    parser.add_argument("--base-set", action="append", default=[], metavar="KEY=VALUE",
                        help="override of the base runs only (repeatable; after --set)")
    parser.add_argument("--candidate-set", action="append", default=[], metavar="KEY=VALUE",
                        help="override of the candidate runs only (repeatable; after --set), "
                             "e.g. solver.seed={seed+1000}")
    parser.add_argument("--reuse", action="append", default=[], metavar="OTHER_DIR",
                        help="another gate folder whose finished runs with the same binary, "
                             "scene and overrides are used instead of running them (repeatable)")
    args = parser.parse_args(argv)
    try:
        jobs = int(args.jobs)
    except ValueError:
        jobs = 0
    if jobs < 1:
        raise BadArgument(f"--jobs: got '{args.jobs}', expected an integer ≥ 1")
    points = [parse_point(p) for p in args.points]
    if len(set(points)) != len(points):
        raise BadArgument(f"--points: {' '.join(args.points)} names a point twice")
    swept = {}
    for side, program, runs in (("base", args.base, args.base_runs),
                                ("candidate", args.candidate, args.candidate_runs)):
        if (program is None) == (runs is None):
            raise BadArgument(f"give exactly one of --{side} PROGRAM and --{side}-runs SWEEP_DIR")
        swept[side] = None
        if runs is not None:
            swept[side] = pathlib.Path(runs).resolve()
            if not (swept[side] / "runs").is_dir():
                raise BadArgument(f"--{side}-runs: '{runs}' has no runs/ folder; allowed: the "
                                  "--out of a `cdpowder sweep`, e.g. results/table1")
    runs_a_side = any(folder is None for folder in swept.values())
    if runs_a_side and args.scene is None:
        raise BadArgument("--scene: required when a side runs (--base or --candidate)")
    scene = pathlib.Path(args.scene) if args.scene is not None else None
    if scene is not None and not scene.is_file():
        raise BadArgument(f"--scene: '{args.scene}' is not a file; allowed: a scene (TOML), "
                          "e.g. examples/quick/scene.toml")
    reuse = []
    for r in args.reuse:
        if not pathlib.Path(r).is_dir():
            raise BadArgument(f"--reuse: '{r}' is not a folder; allowed: the --out of an "
                              "earlier gate")
        reuse.append(pathlib.Path(r).resolve())
    return argparse.Namespace(
        binaries={side: None if swept[side] else executable(program, f"--{side}")
                  for side, program in (("base", args.base), ("candidate", args.candidate))},
        swept=swept,
        scene=scene.resolve() if scene is not None else None, seeds=parse_seeds(args.seeds),
        points=points,
        out=pathlib.Path(args.out).resolve(), jobs=jobs, reuse=reuse,
        common=[parse_set(s, "--set") for s in args.common],
        side_sets={"base": [parse_set(s, "--base-set") for s in args.base_set],
                   "candidate": [parse_set(s, "--candidate-set") for s in args.candidate_set]},
        raw={"common": args.common, "base": args.base_set, "candidate": args.candidate_set})


# ---------------------------------------------------------------------------------------------
# Runs


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def shown(path):
    """`path` as the report shows it: relative to the working folder when inside it, so a
    committed gate.md never records this machine's absolute paths."""
    path = pathlib.Path(path)
    try:
        return str(path.relative_to(pathlib.Path.cwd()))
    except ValueError:
        return str(path)


def read_summary_or_none(path):
    try:
        return read_summary(path)
    except (OSError, SummaryError):
        return None


def finished_run(folder, identity):
    """folder's summary.json when it holds a finished run of exactly this identity, else None."""
    record = read_json(folder / "gate_run.json")
    if record is None or record.get("identity") != identity:
        return None
    summary = read_summary_or_none(folder / "summary.json")
    if summary is None or summary.get("run", {}).get("interrupted", True):
        return None
    return summary


class Runner:
    """Runs the pending runs, --jobs at a time; a progress line per finished run on stderr."""

    def __init__(self, jobs):
        self.jobs = jobs
        self.stop = threading.Event()
        self.lock = threading.Lock()
        self.done = 0

    def run_all(self, runs):
        total = len(runs)
        failures = []

        def one(run):
            if self.stop.is_set():
                return
            folder = run["folder"]
            folder.mkdir(parents=True, exist_ok=True)
            for stale in ("gate_run.json", "summary.json"):
                (folder / stale).unlink(missing_ok=True)
            command = [str(run["binary"]), "compact", str(run["scene"]), "--out", str(folder),
                       "--quiet"]
            for key, value in run["identity"]["overrides"].items():
                command += ["--set", f"{key}={value}"]
            start = time.monotonic()
            with open(folder / "log.txt", "w") as log:
                log.write("$ " + " ".join(command) + "\n")
                log.flush()
                code = subprocess.run(command, stdout=log, stderr=subprocess.STDOUT).returncode
            wall = time.monotonic() - start
            summary = read_summary_or_none(folder / "summary.json")
            finished = code == 0 and summary is not None
            if finished:
                record = {"identity": run["identity"], "binary": str(run["binary"]),
                          "command": command, "wall_seconds": wall}
                tmp = folder / "gate_run.json.tmp"
                tmp.write_text(json.dumps(record, indent=2) + "\n")
                tmp.replace(folder / "gate_run.json")
            with self.lock:
                self.done += 1
                if finished:
                    blocked = "yes" if summary.get("run", {}).get("blocked") else "no"
                    text = f"porosity={summary.get('porosity', math.nan):.5f} blocked={blocked}"
                else:
                    log_tail = (folder / "log.txt").read_text().strip().splitlines()[-3:]
                    text = f"FAILED (exit status {code}): " + " / ".join(log_tail[1:] or log_tail)
                    failures.append((run, code, "\n".join(log_tail[1:])))
                    if code == 2:
                        self.stop.set()        # bad input: every run would fail the same way
                print(f"[{self.done}/{total}] {run['side']} {run['label']} seed {run['seed']}: "
                      f"{text} wall={wall:.1f}s", file=sys.stderr, flush=True)

        pool = concurrent.futures.ThreadPoolExecutor(max_workers=self.jobs)
        try:
            for future in [pool.submit(one, r) for r in runs]:
                future.result()
        except KeyboardInterrupt:
            # The runs got the same SIGINT: each finishes its step and writes its outputs
            # flagged interrupted (run again next time).
            self.stop.set()
            pool.shutdown(wait=True, cancel_futures=True)
            raise
        pool.shutdown(wait=True)
        return failures


# ---------------------------------------------------------------------------------------------
# Statistics and the verdict (no runs: these take summaries as read from summary.json)


def dig(summary, path):
    value = summary
    for key in path:
        if not isinstance(value, dict) or key not in value:
            return None
        value = value[key]
    return value


def run_values(summary):
    """The numbers the gate needs from one summary.json, and the names of fields it lacks."""
    values = {name: dig(summary, path) for name, path in FIELDS.items()}
    missing = [".".join(FIELDS[name]) for name, v in values.items()
               if v is None and name not in ("wall_seconds", "load_with_weight")]
    radius = dig(summary, RADIUS_FIELD)
    values["radius"] = float(radius) if isinstance(radius, (int, float)) else 1.0
    values["missing"] = missing
    return values


class Sample:
    """Mean, standard error of the mean (n − 1 in the variance), sd, range of a sample."""

    def __init__(self, values):
        self.values = [float(v) for v in values]
        a = np.asarray(self.values, dtype=float)
        self.n = len(a)
        self.mean = float(a.mean()) if self.n else math.nan
        self.sd = float(a.std(ddof=1)) if self.n > 1 else math.nan
        self.se = self.sd / math.sqrt(self.n) if self.n > 1 else math.nan
        self.min = float(a.min()) if self.n else math.nan
        self.max = float(a.max()) if self.n else math.nan

    def within(self, n_se):
        """|mean| ≤ n_se standard errors (identical runs: mean = se = 0 passes)."""
        return self.n >= MIN_PAIRS and math.isfinite(self.se) and abs(self.mean) <= n_se * self.se

    def as_dict(self):
        return {"n": self.n, "mean": self.mean, "se": self.se, "sd": self.sd, "min": self.min,
                "max": self.max, "values": self.values}

    def text(self):
        if self.n == 0:
            return "–"
        if not math.isfinite(self.se):
            return f"{self.mean:+.2e} (n = 1)"
        return f"{self.mean:+.2e} ± {self.se:.2e}"


def gauge_problems(side, seed, v):
    """The contract's checks (c) and (d) on one run: what is wrong, as (check, gauge, text)
    with check "c" (static balance) or "d" (blocked, gauges, fields) and gauge the name in
    GAUGES of a gauge out of the contract, None for what cannot be inherited (not blocked,
    interrupted, a missing field, σzz/p)."""
    where = f"{side} seed {seed}"
    problems = [("d", None, f"{where}: summary.json has no {field}") for field in v["missing"]]
    number = lambda name: _number(v[name])  # noqa: E731

    if v["interrupted"]:
        problems.append(("d", None, f"{where}: interrupted"))
    if v["blocked"] is False:
        problems.append(("d", None, f"{where}: not blocked"))
    sigma = number("sigma")
    if sigma is not None and not abs(sigma - 1.0) <= SIGMA_BALANCE_TOLERANCE:
        problems.append(("c", None, f"{where}: σzz/p = {sigma:.4f}, more than "
                                    f"{SIGMA_BALANCE_TOLERANCE:g} from 1"))
    overlap = number("mean_overlap")
    if overlap is not None and not overlap <= MAX_MEAN_OVERLAP * v["radius"]:
        problems.append(("d", "overlap", f"{where}: mean overlap {overlap:.4g} > "
                                         f"{MAX_MEAN_OVERLAP:g} R"))
    opening = number("opening")
    if opening is not None and not opening <= MAX_OPENING_PER_RANGE:
        problems.append(("d", "opening", f"{where}: largest cohesive opening per step "
                                         f"{opening:.4g} d_coh > {MAX_OPENING_PER_RANGE:g}"))
    tolerance = number("force_balance")
    imbalance = number("piston_imbalance")  # relative to the load F already
    if imbalance is not None and tolerance is not None and not imbalance <= tolerance:
        problems.append(("d", "piston", f"{where}: piston force imbalance {imbalance:.4g} > "
                                        f"force_balance {tolerance:g}"))
    net_force = number("max_net_force")  # in F_coh: bounded by force_balance × F
    # the push plus the piston's weight where the summary has it (gravity), else the push
    load = number("load_with_weight") if number("load_with_weight") is not None \
        else number("load")
    if net_force is not None and tolerance is not None and load is not None and \
            not net_force <= tolerance * load:
        problems.append(("d", "net force", f"{where}: largest net force on a sphere "
                                           f"{net_force:.4g} F_coh > force_balance × F = "
                                           f"{tolerance:g} × {load:g}"))
    return problems


def worst_of(runs, gauge):
    """The largest value of a gauge (GAUGES) over runs ({seed: values}); NaN when a run's value
    is not finite (it cannot be compared), None when no run has it."""
    xs = [GAUGES[gauge][1](v) for v in runs.values()]
    xs = [x for x in xs if x is not None]
    if not xs:
        return None
    return max(xs) if all(math.isfinite(x) for x in xs) else math.nan


def inheritance(found, base, candidate):
    """(d)'s gauges at one point: for every gauge with a candidate run out of the contract,
    whether the base is out on it too and the candidate is no worse than the base's worst
    × (1 + INHERITED_MARGIN). found: {side: {seed: problems}}. Returns a list of dicts."""
    out = []
    for gauge, (label, _) in GAUGES.items():
        def runs_out(side):
            return sum(1 for ps in found[side].values() if any(g == gauge for _, g, _ in ps))
        if runs_out("candidate") == 0:
            continue
        base_worst, cand_worst = worst_of(base, gauge), worst_of(candidate, gauge)
        inherited = runs_out("base") > 0
        factor = f"{1.0 + INHERITED_MARGIN:g}"
        allowed = base_worst * (1.0 + INHERITED_MARGIN) if base_worst is not None else None
        ok = inherited and allowed is not None and cand_worst is not None and cand_worst <= allowed
        if not inherited:
            text = (f"not inherited (every base run is within the contract): {label}: "
                    f"candidate worst {fmt(cand_worst, '.4g')}")
        elif ok:
            text = (f"inherited from the base (not worse than its worst × {factor}): {label}: "
                    f"base worst {fmt(base_worst, '.4g')}, candidate worst "
                    f"{fmt(cand_worst, '.4g')}")
        else:
            text = (f"worse than the base (its worst × {factor}): {label}: base worst "
                    f"{fmt(base_worst, '.4g')}, candidate worst {fmt(cand_worst, '.4g')} > "
                    f"{fmt(allowed, '.4g')}")
        out.append({"gauge": gauge, "inherited": inherited, "pass": bool(ok),
                    "base_worst": base_worst, "candidate_worst": cand_worst,
                    "base_runs_out": runs_out("base"), "candidate_runs_out": runs_out("candidate"),
                    "text": text})
    return out


def worst_gauges(runs):
    """Largest value of each gauge over runs ({seed: values}); NaN when none has it."""
    def largest(f):
        xs = [f(v) for v in runs.values()]
        xs = [x for x in xs if x is not None and math.isfinite(x)]
        return max(xs) if xs else math.nan

    def get(name):
        return lambda v: float(v[name]) if isinstance(v[name], (int, float)) else None

    return {
        "mean_overlap_per_R": largest(lambda v: float(v["mean_overlap"]) / v["radius"]
                                      if isinstance(v["mean_overlap"], (int, float)) else None),
        "opening_per_range": largest(get("opening")),
        "piston_imbalance": largest(get("piston_imbalance")),
        "max_net_force": largest(get("max_net_force")),
        "sigma_off_by": largest(lambda v: abs(float(v["sigma"]) - 1.0)
                                if isinstance(v["sigma"], (int, float)) else None),
        "blocked": sum(1 for v in runs.values() if v["blocked"] is True),
        "runs": len(runs),
    }


def evaluate_point(base, candidate, seeds):
    """The gate at one point. base, candidate: {seed: run_values(summary)} of the runs that
    finished; seeds: the seeds asked for. Returns a dict (stats, checks, verdict)."""
    lacking = [f"{side} seed {s}" for s in seeds for side, runs in (("base", base),
               ("candidate", candidate)) if s not in runs]
    pairs = [s for s in seeds if s in base and s in candidate]

    def diff(name):
        values = []
        for s in pairs:
            b, c = base[s][name], candidate[s][name]
            if isinstance(b, (int, float)) and isinstance(c, (int, float)):
                values.append(float(c) - float(b))
        return Sample(values)

    stats = {name: diff(name) for name, _ in DIFFERENCES}
    de, dplus, dminus = stats["porosity"], stats["sigma_plus"], stats["sigma_minus"]
    checks = []

    def check(name, ok, detail):
        checks.append({"check": name, "pass": bool(ok), "detail": detail})

    check("runs", not lacking and len(pairs) >= MIN_PAIRS,
          "every run finished" if not lacking else "no finished run: " + ", ".join(lacking))
    check("(a) mean ΔE within 2 se", de.within(N_STANDARD_ERRORS),
          f"ΔE = {de.text()} (n = {de.n})")
    check("(a) |mean ΔE| < 0.005", de.n > 0 and abs(de.mean) < MAX_MEAN_DELTA_POROSITY,
          f"|mean ΔE| = {abs(de.mean):.2e}")
    check("(b) mean Δσzz+/p within 2 se", dplus.within(N_STANDARD_ERRORS),
          f"Δσzz+/p = {dplus.text()}")
    check("(b) mean Δσzz−/p within 2 se", dminus.within(N_STANDARD_ERRORS),
          f"Δσzz−/p = {dminus.text()}")
    # (c) and (d) on every run, with a count per side. They judge the candidate: base runs
    # out of the contract are listed but fail nothing by themselves; a candidate gauge out
    # where the base is out too is inherited (see INHERITED_MARGIN); a run not blocked,
    # interrupted or lacking a field fails (d) on either side.
    found = {side: {s: gauge_problems(side, s, runs[s]) for s in sorted(runs)}
             for side, runs in (("base", base), ("candidate", candidate))}
    gauges = inheritance(found, base, candidate)
    for name, tag in (("(c) every candidate σzz/p within 0.01 of 1", "c"),
                      ("(d) every run blocked, candidate gauges within the contract", "d")):
        per_side = {side: {s: [(g, text) for t, g, text in ps if t == tag]
                           for s, ps in by_seed.items()} for side, by_seed in found.items()}
        if tag == "c":
            ok = not any(per_side["candidate"].values())
            notes = []
        else:
            ok = (not any(g is None for ps in list(per_side["base"].values()) +
                          list(per_side["candidate"].values()) for g, _ in ps)
                  and all(x["pass"] for x in gauges))
            notes = [x["text"] for x in gauges]
        listed = [text for by_seed in per_side.values() for ps in by_seed.values()
                  for _, text in ps]
        counts = ", ".join(f"{side} {sum(1 for ps in by_seed.values() if ps)} of {len(by_seed)}"
                           for side, by_seed in per_side.items())
        lines = notes + listed
        checks.append({"check": name, "pass": bool(ok),
                       "detail": f"runs out ({counts}): " + "; ".join(lines) if listed
                       else "all runs",
                       "lines": lines, "head": f"runs out ({counts})" if listed else "all runs",
                       "remark": bool(listed)})
    inherited = [x["gauge"] for x in gauges if x["inherited"] and x["pass"]]
    passed = all(c["pass"] for c in checks)
    return {
        "pairs": pairs,
        "n": len(pairs),
        "stats": {name: s.as_dict() for name, s in stats.items()},
        "per_seed": [{"seed": s, "base": base[s], "candidate": candidate[s],
                      "diff": {name: (float(candidate[s][name]) - float(base[s][name])
                                      if isinstance(candidate[s][name], (int, float)) and
                                      isinstance(base[s][name], (int, float)) else None)
                               for name, _ in DIFFERENCES}} for s in pairs],
        "worst": {"base": worst_gauges(base), "candidate": worst_gauges(candidate)},
        "checks": checks,
        "inherited": inherited,
        "gauges": gauges,
        "verdict": ("FAIL" if not passed else
                    f"PASS (inherited: {', '.join(inherited)})" if inherited else "PASS"),
    }


# ---------------------------------------------------------------------------------------------
# Tables


def fmt_row(cells):
    return "| " + " | ".join(cells) + " |"


def fmt(x, spec=".2g"):
    return "–" if x is None or not math.isfinite(x) else format(x, spec)


def tables(results):
    """Markdown tables of the per-point results: differences, gauges, failed checks."""
    md = [fmt_row(["point", "n", "mean ΔE ± se", "sd ΔE (range)", "mean Δσzz+/p ± se",
                   "mean Δσzz−/p ± se", "verdict"]), fmt_row(["---"] * 7)]
    for r in results:
        s = r["stats"]
        de, dp, dm = (Sample(s[k]["values"]) for k in ("porosity", "sigma_plus", "sigma_minus"))
        spread = (f"{fmt(de.sd, '.2e')} ({fmt(de.min, '+.2e')} … {fmt(de.max, '+.2e')})"
                  if de.n else "–")
        md.append(fmt_row([f"({r['point'][0]:g}, {r['point'][1]:g})", str(r["n"]), de.text(),
                           spread, dp.text(), dm.text(), f"**{r['verdict']}**"]))
    md += ["", "Worst accuracy gauges over each side's runs (contract: mean overlap ≤ 1e-3 R, "
           "opening ≤ 0.1 d_coh, piston imbalance ≤ force_balance, net force ≤ "
           "force_balance × F, "
           "|σzz/p − 1| ≤ 0.01, every run blocked):", "",
           fmt_row(["point", "side", "mean overlap [R]", "opening/step [d_coh]",
                    "piston imbalance", "net force [F_coh]", "max \\|σzz/p − 1\\|", "blocked"]),
           fmt_row(["---"] * 8)]
    for r in results:
        for side in SIDES:
            w = r["worst"][side]
            md.append(fmt_row([f"({r['point'][0]:g}, {r['point'][1]:g})", side,
                               fmt(w["mean_overlap_per_R"]), fmt(w["opening_per_range"], ".3f"),
                               fmt(w["piston_imbalance"]), fmt(w["max_net_force"]),
                               fmt(w["sigma_off_by"]), f"{w['blocked']}/{w['runs']}"]))
    def listing(r, c):
        head = c.get("head", c["detail"]) if c.get("lines") else c["detail"]
        return ([f"- ({r['point'][0]:g}, {r['point'][1]:g}) {c['check']}: {head}"] +
                [f"  - {line}" for line in c.get("lines", [])])

    failed = [(r, c) for r in results for c in r["checks"] if not c["pass"]]
    remarks = [(r, c) for r in results for c in r["checks"] if c["pass"] and c.get("remark")]
    md += [""]
    if failed:
        md += ["Failed checks:", ""]
        for r, c in failed:
            md += listing(r, c)
    else:
        md.append("Every check passed at every point.")
    if remarks:
        md += ["", "Passed checks with runs out of the contract (base runs fail nothing by "
               "themselves; a candidate gauge the base already violates passes when no worse "
               f"than the base's worst × {1.0 + INHERITED_MARGIN:g}):", ""]
        for r, c in remarks:
            md += listing(r, c)
    return md


# ---------------------------------------------------------------------------------------------
# The command


def seeds_text(seeds):
    """[1, 2, 3, 5] → '1-3,5'."""
    ranges, start = [], seeds[0]
    for a, b in zip(seeds, seeds[1:] + [None]):
        if b != a + 1:
            ranges.append(f"{start}-{a}" if a > start else f"{a}")
            start = b
    return ",".join(ranges)


def version_of(binary):
    try:
        out = subprocess.run([str(binary), "--version"], capture_output=True, text=True,
                             timeout=60)
        return out.stdout.strip() or out.stderr.strip()
    except (OSError, subprocess.SubprocessError) as e:
        return f"unknown ({e})"


def sweep_run_folder(sweep_dir, point, seed):
    """The folder of point (μt, μn) and seed in a sweep's runs/, whatever the number format of
    its name (contact.mu_roll=0.3,contact.mu_twist=0.0); None when the sweep has no such run."""
    for folder in sorted((sweep_dir / "runs").iterdir()):
        values = dict(part.split("=", 1) for part in folder.name.split(",") if "=" in part)
        try:
            found = (float(values.get("contact.mu_roll", "nan")),
                     float(values.get("contact.mu_twist", "nan")))
        except ValueError:
            continue
        if len(values) == 2 and found == tuple(point):
            run = folder / f"seed_{seed}"
            return run if run.is_dir() else None
    return None


def swept_run(sweep_dir, point, seed):
    """(folder, summary) of a finished run of an earlier sweep, or (place, None)."""
    folder = sweep_run_folder(sweep_dir, point, seed)
    if folder is None:
        return sweep_dir / "runs" / f"{point_label(point)}" / f"seed_{seed}", None
    summary = read_summary_or_none(folder / "summary.json")
    if summary is None or summary.get("run", {}).get("interrupted", True):
        return folder, None
    return folder, summary


def plan(args):
    """Every run: side, point, seed, its folder, identity and (if finished) summary."""
    hashes = {side: (sha256(b) if b is not None else None) for side, b in args.binaries.items()}
    scene_hash = sha256(args.scene) if args.scene is not None else None
    runs = []
    for s in args.seeds:
        for point in args.points:
            for side in SIDES:
                label = point_label(point)
                if args.swept[side] is not None:
                    folder, summary = swept_run(args.swept[side], point, s)
                    runs.append({"side": side, "point": point, "label": label, "seed": s,
                                 "folder": folder, "source": folder, "binary": None,
                                 "scene": None, "identity": None, "summary": summary,
                                 "swept": True})
                    continue
                identity = {"binary_sha256": hashes[side], "scene_sha256": scene_hash,
                            "overrides": overrides_for(point, s, args.common,
                                                       args.side_sets[side])}
                folder = args.out / side / label / f"seed{s}"
                summary, source = finished_run(folder, identity), folder
                for other in args.reuse:
                    if summary is not None:
                        break
                    for other_side in SIDES:
                        candidate_folder = other / other_side / label / f"seed{s}"
                        summary = finished_run(candidate_folder, identity)
                        if summary is not None:
                            source = candidate_folder
                            break
                runs.append({"side": side, "point": point, "label": label, "seed": s,
                             "folder": folder, "source": source, "binary": args.binaries[side],
                             "scene": args.scene, "identity": identity, "summary": summary})
    return runs, hashes


def main(argv=None):
    try:
        args = parse_arguments(sys.argv[1:] if argv is None else argv)
    except BadArgument as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    runs, hashes = plan(args)
    missing = [r for r in runs if r.get("swept") and r["summary"] is None]
    if missing:
        names = ", ".join(f"{r['folder']}" for r in missing[:5])
        sides = sorted({r["side"] for r in missing})
        print(f"error: --{'/'.join(sides)}-runs: {len(missing)} "
              f"{' and '.join(sides)} runs missing or unfinished: {names}", file=sys.stderr)
        return 2
    pending = [r for r in runs if r["summary"] is None]
    print(f"accuracy gate: {len(runs)} runs, {len(runs) - len(pending)} finished before, "
          f"{len(pending)} to run, {args.jobs} at a time", file=sys.stderr, flush=True)
    try:
        failures = Runner(args.jobs).run_all(pending)
    except KeyboardInterrupt:
        print("interrupted: run the same command again to go on", file=sys.stderr)
        return 1
    if any(code == 2 for _, code, _ in failures):
        run, _, message = next(f for f in failures if f[1] == 2)
        print(f"error: {run['binary']} rejected the scene or an override ({run['side']}, "
              f"{run['label']}, seed {run['seed']}):\n{message}", file=sys.stderr)
        return 2
    for r in pending:
        r["summary"] = finished_run(r["folder"], r["identity"])

    results = []
    for point in args.points:
        sides = {side: {r["seed"]: run_values(r["summary"]) for r in runs
                        if r["point"] == point and r["side"] == side and r["summary"] is not None}
                 for side in SIDES}
        result = evaluate_point(sides["base"], sides["candidate"], args.seeds)
        result["point"] = list(point)
        result["label"] = point_label(point)
        results.append(result)
    verdict = "PASS" if all(r["verdict"].startswith("PASS") for r in results) else "FAIL"

    command = shlex.join([sys.argv[0]] + (sys.argv[1:] if argv is None else list(argv)))
    programs = {side: ({"binary": shown(args.binaries[side]), "sha256": hashes[side],
                        "version": version_of(args.binaries[side])}
                       if args.binaries[side] is not None else
                       {"binary": f"runs of {shown(args.swept[side])}", "sha256": "-",
                        "version": "as each run's summary.json records"})
                for side in SIDES}
    gate = {
        "verdict": verdict,
        "command": command,
        "programs": programs,
        "scene": shown(args.scene) if args.scene else None,
        "seeds": args.seeds,
        "set": args.raw["common"],
        "base_set": args.raw["base"],
        "candidate_set": args.raw["candidate"],
        "limits": {"n_standard_errors": N_STANDARD_ERRORS,
                   "max_mean_delta_porosity": MAX_MEAN_DELTA_POROSITY,
                   "sigma_balance_tolerance": SIGMA_BALANCE_TOLERANCE,
                   "max_mean_overlap_per_R": MAX_MEAN_OVERLAP,
                   "max_opening_per_range": MAX_OPENING_PER_RANGE,
                   "inherited_margin": INHERITED_MARGIN,
                   "force_balance": "each run's scene run.blocked.force_balance",
                   "max_net_force": "force_balance × the run's piston.applied_force"},
        "runs": [{"side": r["side"], "label": r["label"], "seed": r["seed"],
                  "folder": shown(r["source"]), "finished": r["summary"] is not None}
                 for r in runs],
        "points": results,
    }
    text = tables(results)
    (args.out / "gate.json").write_text(json.dumps(gate, indent=2, ensure_ascii=False) + "\n")
    inherited = "; ".join(f"({r['point'][0]:g}, {r['point'][1]:g}): {', '.join(r['inherited'])}"
                          for r in results if r["inherited"] and r["verdict"].startswith("PASS"))
    note = f" (inherited from the base: {inherited})" if inherited else ""
    md = ["# Accuracy gate", "", f"**{verdict}**{note}", "", "```", command, "```", ""]
    md += [f"- {side}: `{p['binary']}` ({p['version']}, sha256 {p['sha256'][:12]})"
           for side, p in programs.items()]
    md += [f"- scene `{shown(args.scene) if args.scene else None}`, seeds {seeds_text(args.seeds)} ({len(args.seeds)}), "
           "differences candidate − base paired by seed, "
           "± one standard error of the mean difference", ""]
    (args.out / "gate.md").write_text("\n".join(md + text) + "\n")
    print("\n".join(text))
    note = f" (inherited from the base: {inherited})" if inherited else ""
    print(f"\naccuracy gate: {verdict}{note} (details in {shown(args.out / 'gate.md')}, "
          f"{shown(args.out / 'gate.json')})")
    return 0 if verdict == "PASS" and not failures else 1


if __name__ == "__main__":
    sys.exit(main())
