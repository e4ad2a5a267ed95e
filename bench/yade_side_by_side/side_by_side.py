#!/usr/bin/env python3
"""cdpowder against YADE on the paper's compaction, on the same deposit.

    bench/yade_side_by_side/side_by_side.py [--spheres N] [--repeats K] [--alternate] [--out DIR]

Makes a cdpowder deposit (or takes one with --deposit), then compacts it with
`cdpowder compact` at (mu_roll, mu_twist) = (0.3, 0.3) and with YADE (yade_compact.py, the
same parameters in YADE's soft-sphere model). By default the two run at the same time, one per
core (taskset), each single-threaded; --alternate runs them one after the other instead,
cdpowder, YADE, cdpowder, ... (three times each unless --repeats says otherwise), cdpowder on
all the given cores. Prints wall and CPU times of both, their ratio and both porosities, and
writes DIR/side_by_side.json. A smaller deposit (--spheres N) keeps the paper's number of
spheres per area: L_x = L_y = 25 R sqrt(N / 1015). Exits with a message (status 0) when
`yade` is not installed.
"""

import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools"))
from run_summary import read_summary  # noqa: E402  (the tools folder, put on the path above)

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
PAPER_SPHERES = 1015
PAPER_SIDE = 25.0  # [R]


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--spheres", type=int, default=PAPER_SPHERES, help="deposit size N")
    p.add_argument("--seed", type=int, default=1, help="deposition seed")
    p.add_argument("--deposit", help="use this particles.csv instead of a new deposit "
                   "(give its cell with --side)")
    p.add_argument("--side", type=float, help="L_x = L_y [R] (default: from --spheres)")
    p.add_argument("--mu-roll", type=float, default=0.3)
    p.add_argument("--mu-twist", type=float, default=0.3)
    p.add_argument("--repeats", type=int, help="runs of each program (default 1, "
                   "3 with --alternate)")
    p.add_argument("--alternate", action="store_true",
                   help="one after the other, alternating, instead of at the same time")
    p.add_argument("--cores", default="0,1", help="concurrent: cdpowder on the first, YADE "
                   "on the second; --alternate: cdpowder on all, YADE on the first")
    p.add_argument("--scene", default=str(ROOT / "examples/paper/scene.toml"))
    p.add_argument("--cdpowder", default=str(ROOT / "build/release/app/cdpowder"))
    p.add_argument("--yade", default="yade", help="YADE's launcher")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="extra cdpowder override (repeatable)")
    p.add_argument("--yade-arg", action="append", default=[], metavar="ARG",
                   help="extra yade_compact.py argument (repeatable), e.g. --yade-arg=--damping=0.2")
    p.add_argument("--out", default="bench_yade_side_by_side", help="output folder")
    a = p.parse_args(argv)
    if a.repeats is None:
        a.repeats = 3 if a.alternate else 1
    if a.side is None:
        a.side = PAPER_SIDE * math.sqrt(a.spheres / PAPER_SPHERES)
    a.cores = a.cores.split(",")
    return a


def run(cmd, **kw):
    print("+", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, **kw)


def make_deposit(a, out):
    """A cdpowder deposit of a.spheres spheres in an a.side x a.side cell."""
    folder = out / "deposit"
    run([a.cdpowder, "deposit", a.scene, "--out", str(folder),
         "--set", f"deposition.spheres={a.spheres}", "--set", f"deposition.seed={a.seed}",
         "--set", f"system.lx={a.side!r}", "--set", f"system.ly={a.side!r}"])
    return folder / "particles.csv"


def pinned(cores, cmd):
    """cmd on the given cores (taskset, when there is one)."""
    if shutil.which("taskset"):
        return ["taskset", "-c", ",".join(cores)] + cmd
    return cmd


class Job:
    """One program run: its command, where its output and result go, and once finished its
    wall and CPU times (process totals from wait4: user + system of all its threads)."""

    def __init__(self, name, cmd, env, log, result):
        self.name, self.cmd, self.env = name, cmd, env
        self.log_path, self.result = log, result  # result: summary.json or YADE's JSON
        self.wall = self.cpu = None

    def start(self):
        print("+", " ".join(self.cmd), flush=True)
        self.log = open(self.log_path, "w")
        self.t0 = time.perf_counter()
        self.proc = subprocess.Popen(self.cmd, env=self.env, stdout=self.log,
                                     stderr=subprocess.STDOUT)

    def finished(self, status, usage):
        self.wall = time.perf_counter() - self.t0
        self.cpu = usage.ru_utime + usage.ru_stime
        self.log.close()
        if status != 0:
            sys.exit(f"{self.name} failed (status {status}); see {self.log.name}")


def wait_all(jobs):
    """Waits for every started job, recording each one's times as it ends."""
    by_pid = {j.proc.pid: j for j in jobs}
    while by_pid:
        pid, status, usage = os.wait4(-1, 0)
        if pid in by_pid:
            by_pid.pop(pid).finished(os.waitstatus_to_exitcode(status), usage)


def cdpowder_job(a, deposit, out, k, cores):
    folder = out / f"cdpowder_{k}"
    cmd = [a.cdpowder, "compact", a.scene, "--out", str(folder), "--particles", str(deposit),
           "--set", f"system.lx={a.side!r}", "--set", f"system.ly={a.side!r}",
           "--set", f"contact.mu_roll={a.mu_roll!r}", "--set", f"contact.mu_twist={a.mu_twist!r}",
           "-q"]
    for s in a.set:
        cmd += ["--set", s]
    env = dict(os.environ, OMP_NUM_THREADS=str(len(cores)))
    return Job("cdpowder", pinned(cores, cmd), env, out / f"cdpowder_{k}.log",
               folder / "summary.json")


def yade_job(a, deposit, out, k, cores):
    result = out / f"yade_{k}.json"
    cmd = [a.yade, "-n", "-j1", "-x", str(HERE / "yade_compact.py"),
           "--particles", str(deposit), "--out", str(result),
           "--lx", repr(a.side), "--ly", repr(a.side),
           "--mu-roll", repr(a.mu_roll), "--mu-twist", repr(a.mu_twist)] + a.yade_arg
    env = dict(os.environ, OMP_NUM_THREADS="1")
    return Job("yade", pinned(cores, cmd), env, out / f"yade_{k}.log", result)


def cdpowder_figures(job):
    s = read_summary(job.result)
    return {"wall": job.wall, "cpu": job.cpu, "loop_wall": s["run"]["wall_seconds"],
            "porosity": s["porosity"], "steps": s["run"]["steps"], "time": s["time"],
            "blocked": s["run"]["blocked"]}


def yade_figures(job):
    r = json.load(open(job.result))
    return {"wall": job.wall, "cpu": job.cpu, "loop_wall": r["wall_seconds"],
            "loop_cpu": r["cpu_seconds"], "bond_pass_cpu": r["bond_pass_cpu_seconds"],
            "porosity": r["porosity"], "steps": r["steps"], "time": r["time"],
            "rested": r["rested"], "escaped": r["escaped_spheres"]}


def run_pairs(a, deposit, out):
    """Runs the repeats; returns a list of (cdpowder figures, yade figures)."""
    pairs = []
    for k in range(a.repeats):
        if a.alternate:
            c = cdpowder_job(a, deposit, out, k, a.cores)
            y = yade_job(a, deposit, out, k, a.cores[:1])
            for job in (c, y):
                job.start()
                wait_all([job])
        else:
            c = cdpowder_job(a, deposit, out, k, a.cores[:1])
            y = yade_job(a, deposit, out, k, a.cores[1:2] or a.cores[:1])
            c.start()
            y.start()
            wait_all([c, y])
        pairs.append((cdpowder_figures(c), yade_figures(y)))
        report_pair(k, *pairs[-1])
    return pairs


def report_pair(k, c, y):
    print(f"run {k}: cdpowder wall {c['wall']:.1f} s  CPU {c['cpu']:.1f} s  "
          f"E {c['porosity']:.5f}  steps {c['steps']}  t {c['time']:.0f} t0  "
          f"blocked {c['blocked']}")
    print(f"run {k}: YADE     wall {y['wall']:.1f} s  CPU {y['cpu']:.1f} s  "
          f"(bond passes {y['bond_pass_cpu']:.1f} s)  E {y['porosity']:.5f}  "
          f"steps {y['steps']}  t {y['time']:.0f} t0  rested {y['rested']}  "
          f"escaped {y['escaped']}")
    print(f"run {k}: YADE / cdpowder: wall {y['wall'] / c['wall']:.2f}  "
          f"CPU {y['cpu'] / c['cpu']:.2f}", flush=True)


def summary(pairs):
    ratios = {
        "wall": [y["wall"] / c["wall"] for c, y in pairs],
        "cpu": [y["cpu"] / c["cpu"] for c, y in pairs],
        "cpu_without_bond_passes": [(y["cpu"] - y["bond_pass_cpu"]) / c["cpu"]
                                    for c, y in pairs],
    }
    return {name: {"each": r, "median": statistics.median(r)} for name, r in ratios.items()}


def main(argv):
    a = parse_args(argv)
    if shutil.which(a.yade) is None:
        print(f"'{a.yade}' is not installed: skipping the side-by-side benchmark "
              "(Debian: apt-get install yade)")
        return 0
    out = Path(a.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    deposit = Path(a.deposit).resolve() if a.deposit else make_deposit(a, out)
    load_before = os.getloadavg()
    pairs = run_pairs(a, deposit, out)
    load_after = os.getloadavg()
    ratios = summary(pairs)
    print(f"YADE / cdpowder, median of {len(pairs)}: wall {ratios['wall']['median']:.2f}, "
          f"CPU {ratios['cpu']['median']:.2f} "
          f"({ratios['cpu_without_bond_passes']['median']:.2f} without the bond passes)")
    print(f"load average (1, 5, 15 min) before {load_before}, after {load_after}")
    record = {"arguments": {k: v for k, v in vars(a).items()}, "deposit": str(deposit),
              "mode": "alternate" if a.alternate else "concurrent",
              "load_before": load_before, "load_after": load_after,
              "runs": [{"cdpowder": c, "yade": y} for c, y in pairs], "ratios": ratios}
    with open(out / "side_by_side.json", "w") as f:
        json.dump(record, f, indent=2)
    print(f"written: {out / 'side_by_side.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
