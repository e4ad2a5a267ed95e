#!/usr/bin/python3
"""A sweep whose runs are a Python protocol (docs/sweeps.md, "A Python protocol"): the
example's load_steps runs each point, protocol.json records it, the tables read its last
stage, a restarted sweep keeps finished runs and runs again one whose record is gone, --task
and --collect work, and a protocol that raises or names a missing function fails its run
with the reason in its log.
    check_protocol_sweep.py   (CDPOWDER_EXE, CDPOWDER_SOURCE_DIR and CDPOWDER_PYTHON set)"""
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import tomllib

exe = os.environ["CDPOWDER_EXE"]
quick = pathlib.Path(os.environ["CDPOWDER_SOURCE_DIR"]) / "examples/quick"


def sweep(sweep_file, out, *extra, expect=0):
    done = subprocess.run([exe, "sweep", str(sweep_file), "--out", str(out), *extra],
                          capture_output=True, text=True)
    if done.returncode != expect:
        sys.exit(f"sweep {extra} exited {done.returncode}, expected {expect}:\n"
                 f"{done.stdout}{done.stderr}")
    return done.stdout + done.stderr


def check(condition, what):
    if not condition:
        sys.exit(f"FAILED: {what}")


with tempfile.TemporaryDirectory() as scratch:
    scratch = pathlib.Path(scratch)
    # the example's protocol and scene; one point at (1, 1), whose compactions are short
    sweep_file = scratch / "steps.toml"
    sweep_file.write_text(f'scene = "{quick / "scene.toml"}"\ncommand = "python"\n'
                          f'protocol = "{quick / "load_steps.py"}:load_steps"\nseeds = 1\n'
                          'set = ["contact.mu_roll=1.0", "contact.mu_twist=1.0"]\n')
    out = scratch / "out"
    sweep(sweep_file, out)
    run = out / "runs/base/seed_1"
    record = json.loads((run / "protocol.json").read_text())
    summary = json.loads((run / "summary.json").read_text())
    check(record["protocol"].endswith("load_steps.py:load_steps"), "the protocol's name")
    steps = record["returned"]["porosity"]
    check(list(steps) == ["1p", "2p", "4p"], f"E after each step: {steps}")
    check(steps["4p"] == summary["porosity"], "the tables read the last stage")
    point_pressure = tomllib.loads(record["scene"])["piston"]["pressure"]
    check(summary["scene"]["piston"]["pressure"] == 4 * point_pressure,
          "the last stage ran at 4p; the record keeps the point's scene")
    rows = [line for line in (out / "results.csv").read_text().splitlines()
            if not line.startswith("#")]
    check(len(rows) == 2 and rows[1].startswith("base,"), f"results.csv: {rows}")

    # restarted: nothing to do; without its record, the run runs again
    check("1 already finished" in sweep(sweep_file, out), "a finished run is kept")
    (run / "protocol.json").unlink()
    check("--task 0" in sweep(sweep_file, out, "--list"), "--list names the run")
    sweep(sweep_file, out, "--task", "0")
    check(json.loads((run / "protocol.json").read_text())["returned"]["porosity"] == steps,
          "the run again gives the same bits")
    check("1 of 1 runs finished" in sweep(sweep_file, out, "--collect"), "--collect")

    # a protocol that raises, and one that names no function of its file
    (scratch / "broken.py").write_text("def fails(scene, out):\n    raise ValueError('no')\n")
    for function, reason in (("fails", "ValueError: no"), ("absent", "has no function 'absent'")):
        broken = scratch / f"{function}.toml"
        broken.write_text(f'scene = "{quick / "scene.toml"}"\ncommand = "python"\n'
                          f'protocol = "broken.py:{function}"\n')
        said = sweep(broken, scratch / function, expect=1)
        check("FAILED" in said, f"{function}: the run failed: {said}")
        log = (scratch / function / "runs/base/seed_1/log.txt").read_text()
        check(reason in log, f"{function}: the log says why: {log}")
        check(not (scratch / function / "runs/base/seed_1/protocol.json").exists(),
              f"{function}: not recorded as finished")
print("protocol sweep: finished, kept, rerun, collected; failures reported")
