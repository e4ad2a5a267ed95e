#!/usr/bin/python3
"""The `parallel` label: OpenMP's binding does not shrink the CPU budget. With OMP_PROC_BIND
set, the OpenMP runtime binds the initial thread to its first place before main, so the
thread's affinity mask is then that place alone; `solver.threads = "auto"` must still take
every core the process may use (the processors of its places: libomp 14 may put two in one
place). The run's first line names its thread count: the same with and without the binding."""
import argparse
import os
import re
import subprocess
import sys
import tempfile


def threads_of(cdpowder, scene, environment):
    """The thread count a short compaction of `scene` reports under `environment`."""
    with tempfile.TemporaryDirectory() as out:
        result = subprocess.run(
            [cdpowder, "compact", scene, "--out", os.path.join(out, "run"),
             "--set", 'solver.threads="auto"', "--set", "run.max_duration=0.05"],
            env={**os.environ, **environment}, capture_output=True, text=True, check=False)
    if result.returncode not in (0, 4):  # 4: not blocked within the duration
        sys.exit(f"binding_test: cdpowder exited with {result.returncode}:\n{result.stderr}")
    found = re.search(r"(\d+) threads?\b", result.stderr + result.stdout)
    if not found:
        sys.exit(f"binding_test: no thread count in the output:\n{result.stderr}")
    return int(found.group(1))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cdpowder", required=True)
    parser.add_argument("--scene", required=True)
    args = parser.parse_args()
    free = {"OMP_PROC_BIND": "false", "CDPOWDER_MAX_THREADS": "4"}
    bound = {"OMP_PROC_BIND": "close", "OMP_PLACES": "cores", "CDPOWDER_MAX_THREADS": "4"}
    unbound = threads_of(args.cdpowder, args.scene, free)
    pinned = threads_of(args.cdpowder, args.scene, bound)
    print(f"auto: {unbound} threads unbound, {pinned} with OMP_PROC_BIND=close")
    if pinned != unbound:
        sys.exit(f"binding_test: OMP_PROC_BIND=close gave {pinned} threads, {unbound} without")


if __name__ == "__main__":
    main()
