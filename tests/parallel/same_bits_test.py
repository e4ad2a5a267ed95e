#!/usr/bin/python3
"""The `parallel` label: a compaction of about 2 000 spheres in 8 × 8 tiles ends on the same
bits with solver.threads = 1, 2, 3 and 4, and a run stopped (SIGINT writes a checkpoint) on 4
threads and resumed on 2 and on 1 ends on the bits of the run never stopped. The threads are
allowed past the machine's cores (CDPOWDER_OVERSUBSCRIBE=1): the bits are compared, never the
times. On 3 and 4 threads every step that has tiles to share runs on them
(CDPOWDER_ALWAYS_THREADED=1); on 2, the choice by time decides, as in a run. The outputs compared are particles.csv and contacts.csv (shortest round-trip decimals,
so equal text is equal bits) and the summary's porosity, steps and passes."""
import argparse
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import tempfile
import time

# about 2 000 spheres at the paper's area density (1 015 in 25 R × 25 R), strong contact
# torques (a fast block), tiles of 4.4 R: 8 × 8 tiles, 16 a phase
SCENE_SETTINGS = [
    "deposition.spheres=2000", "system.lx=35.1", "system.ly=35.1",
    "contact.mu_roll=1", "contact.mu_twist=1", "solver.tile_width=4.0",
    "run.timeseries_interval=0.5",
]


def compact(cdpowder, scene, out, threads, duration, extra=(), always=False):
    """Starts a compaction of `duration` t0 into `out` on `threads` threads, every step on
    them with `always` (CDPOWDER_ALWAYS_THREADED=1), else as the choice by time has it;
    returns the process."""
    command = [cdpowder, "compact", scene, "--out", str(out), "--quiet",
               "--set", f"solver.threads={threads}", "--set", f"run.max_duration={duration}"]
    for setting in SCENE_SETTINGS:
        command += ["--set", setting]
    env = dict(os.environ, CDPOWDER_ALWAYS_THREADED="1") if always else None
    return subprocess.Popen(command + list(extra), stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, env=env)


def finish(process, what, allowed=(0, 4), timeout=600):
    """Waits for `process`; fails unless it exited with one of `allowed` (4: not blocked in
    the run's time, expected of a short run)."""
    _, err = process.communicate(timeout=timeout)
    if process.returncode not in allowed:
        sys.exit(f"{what}: exit {process.returncode}\n{err}")


def outputs(folder):
    """What must be equal: the data rows of the CSVs, the summary's results and its energy
    budget."""
    def rows(name):
        text = (folder / name).read_text()
        return [line for line in text.splitlines() if not line.startswith("#")]
    summary = json.loads((folder / "summary.json").read_text())
    run = summary["run"]
    energy = summary["energy"]
    return {"particles.csv": rows("particles.csv"), "contacts.csv": rows("contacts.csv"),
            "summary": (summary["porosity"], run["steps"], run["total_passes"]),
            "energy": (energy["dissipated"], energy["bonds_formed"], energy["bonds_broken"])}


def threaded_steps(folder):
    return json.loads((folder / "summary.json").read_text())["run"]["threaded_steps"]


def expect_same(reference, folder, what):
    got = outputs(folder)
    for key, value in reference.items():
        if got[key] != value:
            sys.exit(f"{what}: {key} differs from the run on one thread")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cdpowder", required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--threads", default="2,3,4",
                        help="thread counts compared with one thread (default 2,3,4)")
    parser.add_argument("--resume-threads", default="2,1",
                        help="thread counts the run stopped on 4 resumes on (default 2,1)")
    parser.add_argument("--duration", type=float, default=12.0,
                        help="simulated time of each run [t0] (default 12)")
    args = parser.parse_args()
    counts = [int(t) for t in args.threads.split(",")]
    resume_counts = [int(t) for t in args.resume_threads.split(",")]
    os.environ["CDPOWDER_OVERSUBSCRIBE"] = "1"
    with tempfile.TemporaryDirectory() as scratch:
        scratch = pathlib.Path(scratch)
        one = scratch / "threads_1"
        finish(compact(args.cdpowder, args.scene, one, 1, args.duration), "1 thread")
        reference = outputs(one)
        if reference["summary"][1] < 50:
            sys.exit(f"too short a run to compare: {reference['summary'][1]} steps")
        if threaded_steps(one) != 0:
            sys.exit(f"1 thread: {threaded_steps(one)} steps counted as threaded")
        # on two threads as the choice by time has it (on two cores one thread mostly wins
        # there: the first block and the tries run on the threads); on three and four every
        # step that has tiles to share
        for threads in counts:
            folder = scratch / f"threads_{threads}"
            always = threads > 2
            finish(compact(args.cdpowder, args.scene, folder, threads, args.duration,
                           always=always), f"{threads} threads")
            expect_same(reference, folder, f"{threads} threads")
            steps = reference["summary"][1]
            on_threads = threaded_steps(folder)
            # the first block of steps runs on the threads whatever the times
            if not 0 < on_threads <= steps or (always and on_threads < steps // 2):
                sys.exit(f"{threads} threads: {on_threads} of {steps} steps on the threads")
            print(f"threads {threads}: the bits of one thread ({on_threads} of {steps} steps "
                  f"on the threads)")
        # stopped on 4 threads a while after it began (SIGINT: it writes a checkpoint and
        # exits 1), resumed on 2 and on 1; a run that ended first is tried with a shorter wait
        stopped = scratch / "stopped"
        for wait in (0.3, 0.1, 0.0):
            shutil.rmtree(stopped, ignore_errors=True)
            process = compact(args.cdpowder, args.scene, stopped, 4, args.duration)
            deadline = time.monotonic() + 300
            while (time.monotonic() < deadline and process.poll() is None
                   and not (stopped / "scene.toml").exists()):
                time.sleep(0.002)
            time.sleep(wait)
            process.send_signal(signal.SIGINT)
            finish(process, "the stopped run", allowed=(1, 0, 4))
            if process.returncode == 1:
                break
        else:
            sys.exit("the run ended before the signal each time; nothing to resume")
        at_step = json.loads((stopped / "summary.json").read_text())["run"]["steps"]
        print(f"stopped on 4 threads at step {at_step} of {reference['summary'][1]}")
        for threads in resume_counts:
            folder = scratch / f"resumed_on_{threads}"
            shutil.copytree(stopped, folder)
            (folder / ".run.lock").unlink(missing_ok=True)
            resumed = subprocess.run(
                [args.cdpowder, "resume", str(folder), "--quiet", "--threads", str(threads)],
                capture_output=True, text=True, timeout=600)
            if resumed.returncode not in (0, 4):
                sys.exit(f"resume on {threads}: exit {resumed.returncode}\n{resumed.stderr}")
            expect_same(reference, folder, f"stopped on 4 threads, resumed on {threads}")
            print(f"stopped on 4 threads, resumed on {threads}: the bits of one thread")


if __name__ == "__main__":
    main()
