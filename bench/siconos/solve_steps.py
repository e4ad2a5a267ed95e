#!/usr/bin/python3
"""Siconos' 3-D friction-contact solvers on exported cdpowder steps, judged like the engine.

    build/bench/bench/contact_problem export bench/fixtures/paper_front_mu00_t350.cdps \
        --skip 14 --count 10 --out /tmp/front
    /usr/bin/python3 bench/siconos/solve_steps.py check /tmp/front
    /usr/bin/python3 bench/siconos/solve_steps.py run /tmp/front --out /tmp/front/runs.jsonl
    /usr/bin/python3 bench/siconos/solve_steps.py table /tmp/front/runs.jsonl

`check` verifies the mapping (fc3d_mapping.py) on every step: u = W r + q against the
engine's own contact velocities for the engine's solution, and Siconos' error of that
solution. `run` solves every step with every solver from the engine's warm start and from
zero, each on a ladder of tolerances, timing the solver call only (time.perf_counter around
fc3d_driver, one BLAS thread), and judges each solution with `contact_problem judge`: one
engine sweep from it, the residual of docs/physics.md §7.3, and the §17 gauges. The engine's
own solver is timed on the same problems with `contact_problem solve`. `table` prints, per
solver and start, the time to reach the engine's own (judged) residual on each step.
`delassus` writes one step's W for factor_delassus.cpp.

Needs Debian's python3-siconos and python3-scipy (run with /usr/bin/python3); without them
it says so and exits 0.
"""
import argparse
import json
import multiprocessing
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# one thread for BLAS and the sparse direct solvers, as the engine's solver uses one core
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

try:
    import numpy as np
    import siconos.numerics as sn
except ImportError as missing:
    print(f"solve_steps.py: skipped, {missing.name} is not installed "
          "(apt-get install python3-siconos python3-scipy; run with /usr/bin/python3)")
    sys.exit(0)

from fc3d_mapping import Fc3dMapping, load_json  # noqa: E402 (needs numpy, scipy)

REPO = Path(__file__).resolve().parents[2]
DEFAULT_TOOL = REPO / "build" / "bench" / "bench" / "contact_problem"

# Solver -> (max iterations, tolerance ladder on Siconos' own error). Siconos divides its
# error by |q| + 1, and |q| is large here (open candidates carry g/dt), so the ladder is
# set where the judged residual crosses the engine's (measured on step 0).
SOLVERS = {
    "NSGS": (20000, [3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6]),
    "NSN_AC": (200, [1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 1e-8]),
    "NSN_FB": (200, [1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7]),
    "NSN_NM": (200, [1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7]),
    "ADMM": (20000, [1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7]),
    "VI_FPP": (20000, [1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7]),
    "VI_EG": (20000, [1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7]),
    "PROX": (200, [1e-4, 3e-5, 1e-5, 3e-6, 1e-6]),
}
# The engine's solver: a ladder of sweep caps, run to the cap (no early stop)
ENGINE_SWEEPS = [200, 400, 800, 1600, 3200]
REPEAT_BELOW = 2.0  # runs shorter than this [s] are timed three times (median)
GIVE_UP_AFTER = 60.0  # a ladder stops after a run this long [s]
RUN_LIMIT = 120.0  # a solve still running after this [s] is stopped and counts as failed
# Each solve runs in a forked child limited to this much memory: Siconos 4.4's Newton
# solvers leak (a process that ran NSN_AC on a few steps grew to 23 GB), and a leak must
# neither thrash the machine nor carry over into the next solve's time.
CHILD_MEMORY = 6 << 30  # [bytes]


def steps_in(folder):
    return sorted(Path(folder).glob("step_*[0-9].json"), key=lambda p: int(p.stem.split("_")[1]))


def judge(tool, problem_file, actions, presweeps=0):
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump({"actions": actions}, f)
        name = f.name
    try:
        out = subprocess.run([str(tool), "judge", str(problem_file), name, "--json",
                              "--presweeps", str(presweeps)],
                             check=True, capture_output=True, text=True).stdout
    finally:
        os.unlink(name)
    return json.loads(out)


def siconos_problem(mapping):
    W, q, mu = mapping.siconos_data()
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # index-width conversion notes
        return sn.FrictionContactProblem(3, W, q, mu)


def solve_once(problem, solver, max_iter, tol, r0):
    options = sn.SolverOptions(getattr(sn, "SICONOS_FRICTION_3D_" + solver))
    options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = max_iter
    options.dparam[sn.SICONOS_DPARAM_TOL] = tol
    r = r0.copy()
    u = np.zeros_like(r)
    start = time.perf_counter()
    info = sn.fc3d_driver(problem, r, u, options)
    seconds = time.perf_counter() - start
    return r, {"info": int(info), "iterations": int(options.iparam[sn.SICONOS_IPARAM_ITER_DONE]),
               "siconos_error": float(options.dparam[sn.SICONOS_DPARAM_RESIDU]),
               "seconds": seconds}


def timed(run_once):
    """Runs once; again twice if it was short. Returns the last result, all times."""
    result, stats = run_once()
    times = [stats["seconds"]]
    if times[0] < REPEAT_BELOW:
        for _ in range(2):
            result, stats = run_once()
            times.append(stats["seconds"])
    stats["seconds"] = statistics.median(times)
    stats["all_seconds"] = times
    return result, stats


def _solve_child(pipe, problem, solver, max_iter, tol, r0):
    resource.setrlimit(resource.RLIMIT_AS, (CHILD_MEMORY, CHILD_MEMORY))
    try:
        r, stats = timed(lambda: solve_once(problem, solver, max_iter, tol, r0))
        pipe.send((r, stats))
    except MemoryError:
        pipe.send((None, {"failure": "out of memory"}))


def solve_isolated(problem, solver, max_iter, tol, r0):
    """timed(solve_once(...)) in a forked child; (None, {"failure": why}) if it fails."""
    context = multiprocessing.get_context("fork")
    receive, send = context.Pipe(duplex=False)
    child = context.Process(target=_solve_child, args=(send, problem, solver, max_iter, tol, r0))
    child.start()
    send.close()
    result = (None, {"failure": f"no result within {RUN_LIMIT:.0f} s"})
    try:
        if receive.poll(RUN_LIMIT):
            result = receive.recv()
    except EOFError:
        result = (None, {"failure": "the solver process died"})
    child.join(1.0)
    if child.is_alive():
        child.kill()
        child.join()
    return result


def check(args):
    for path in steps_in(args.folder):
        problem = load_json(path)
        mapping = Fc3dMapping(problem)
        engine = load_json(path.with_name(path.stem + "_cdpowder.json"))
        r = mapping.reactions_from_actions(engine["actions"])
        with tempfile.NamedTemporaryFile(suffix=".json") as v:
            subprocess.run([str(args.tool), "judge", str(path),
                            str(path.with_name(path.stem + "_cdpowder.json")),
                            "--velocities", v.name], check=True, capture_output=True)
            velocities = load_json(v.name)
        V = np.asarray(velocities["relative_velocity"])
        engine_u = np.column_stack([
            np.einsum("ij,ij->i", V, mapping.normals) + np.asarray(velocities["gap_rate"]),
            np.einsum("ij,ij->i", V, mapping.t1), np.einsum("ij,ij->i", V, mapping.t2)]).ravel()
        u = mapping.local_velocities(r)
        fcp = siconos_problem(mapping)
        options = sn.SolverOptions(sn.SICONOS_FRICTION_3D_NSGS)
        _, error = sn.fc3d_compute_error(fcp, r.copy(), np.zeros_like(r), 1.0, options, 1.0)
        _, q, _ = mapping.siconos_data()
        print(f"{path.name}: contacts={mapping.n_contacts} |u - engine V|max={np.abs(u - engine_u).max():.2e} "
              f"(|u|max={np.abs(engine_u).max():.2f} R/t0) siconos_error(engine solution)={error:.3e} "
              f"|q/s|={np.linalg.norm(q):.1f} engine residual={engine['stats']['residual']:.3e}")


def run(args):
    out = open(args.out, "a")

    def record(row):
        out.write(json.dumps(row) + "\n")
        out.flush()
        print(" ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                       for k, v in row.items() if k not in ("all_seconds",)), flush=True)

    solvers = args.solvers.split(",") if args.solvers else list(SOLVERS)
    for start in args.starts.split(","):
        for path in steps_in(args.folder):
            if args.steps and int(path.stem.split("_")[1]) not in args.steps:
                continue
            problem = load_json(path)
            engine_file = path.with_name(path.stem + "_cdpowder.json")
            engine = load_json(engine_file)
            target = judge(args.tool, path, engine["actions"])["residual"]
            base = {"step": path.stem, "start": start, "target": target,
                    "engine_export_seconds": problem_seconds(path)}
            if not args.skip_engine and start != "engine":
                for sweeps in ENGINE_SWEEPS:
                    stats = engine_solve(args.tool, path, start, sweeps)
                    record({**base, "solver": "cdpowder", "setting": sweeps, **stats})
                    if stats["residual"] <= target:
                        break
            mapping = Fc3dMapping(problem)
            fcp = siconos_problem(mapping)
            r0 = {"warm": mapping.reactions_from_actions(problem["warm_start"]),
                  "zero": np.zeros(3 * mapping.n_contacts),
                  "engine": mapping.reactions_from_actions(engine["actions"])}[start]
            for solver in solvers:
                max_iter, ladder = SOLVERS[solver]
                for tol in ladder:
                    r, stats = solve_isolated(fcp, solver, max_iter, tol, r0)
                    if r is None:
                        record({**base, "solver": solver, "setting": tol, **stats})
                        break
                    actions = mapping.actions_from_reactions(r)
                    verdict = judge(args.tool, path, actions)
                    # the same solution passed through one engine sweep first: a Newton
                    # iterate outside the friction cone is projected back (~0.1 ms here)
                    swept = judge(args.tool, path, actions, presweeps=1)
                    record({**base, "solver": solver, "setting": tol, **stats, **verdict,
                            "residual_after_sweep": swept["residual"]})
                    best = min(verdict["residual"], swept["residual"])
                    reached = best <= target and not args.full_ladder
                    # a solver that missed its own tolerance within max_iter will miss tighter ones
                    stuck = stats["info"] != 0 and stats["iterations"] >= max_iter
                    if reached or stuck or stats["seconds"] > GIVE_UP_AFTER:
                        break


def problem_seconds(path):
    return load_json(path.with_name(path.stem + "_cdpowder.json"))["stats"]["solve_seconds"]


def engine_solve(tool, path, start, sweeps):
    command = [str(tool), "solve", str(path), "--repeat", "5", "--json",
               "--set", f"solver.max_passes={sweeps}", "--set", "solver.tolerance=1e-12"]
    if start == "zero":
        command.append("--cold")
    result = json.loads(subprocess.run(command, check=True, capture_output=True,
                                       text=True).stdout)
    return {"iterations": result["stats"]["sweeps"], "seconds": result["stats"]["solve_seconds"],
            "all_seconds": result["seconds"], **result["judge"]}


def table(args):
    rows = [json.loads(line) for name in args.results for line in open(name)]
    steps = sorted({r["step"] for r in rows}, key=lambda s: int(s.split("_")[1]))
    # the engine's solver time per step: re-timed beside the other solvers where it was,
    # else as recorded by the export
    engine = {s: min([r["seconds"] for r in rows if r["step"] == s and r["solver"] == "cdpowder"
                      and r["start"] == "warm" and r["setting"] == 200] or
                     [r["engine_export_seconds"] for r in rows if r["step"] == s])
              for s in steps}
    med = statistics.median
    print("Per solver and start, over the steps it was run on (medians over steps): the time\n"
          "of the first rung of the tolerance ladder whose solution has the engine's residual or\n"
          "less, the time of the rung before it (the crossing lies between), its iterations,\n"
          "and the ratio to the engine's solver time on the same step. The judged residual is\n"
          "that of the solution as returned, or (columns '+1 sweep') of the solution passed\n"
          "through one engine sweep first.\n")
    print("| solver | start | steps reaching the engine's residual | time to reach it [ms] "
          "| rung before [ms] | iterations | × engine time | +1 sweep: steps | +1 sweep: time [ms] "
          "| +1 sweep: × engine | best residual (its time [ms]) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    keys = []
    for r in rows:
        if (r["solver"], r["start"]) not in keys:
            keys.append((r["solver"], r["start"]))
    for solver, start in keys:
        ran = [s for s in steps if any(r["step"] == s and r["solver"] == solver
                                       and r["start"] == start for r in rows)]
        runs = {s: sorted((r for r in rows if r["step"] == s and r["solver"] == solver
                           and r["start"] == start and "residual" in r),
                          key=lambda r: r["seconds"]) for s in ran}
        cells = []
        for key in ("residual", "residual_after_sweep"):
            reached, before, iters, ratio = [], [], [], []
            for s, mine in runs.items():
                ok = [r for r in mine if key in r and r[key] <= r["target"]]
                if not ok:
                    continue
                first = ok[0]
                reached.append(first["seconds"] * 1e3)
                iters.append(first["iterations"])
                ratio.append(first["seconds"] / engine[s])
                short = [r["seconds"] for r in mine if key in r and r[key] > r["target"]
                         and r["seconds"] < first["seconds"]]
                before.append(max(short) * 1e3 if short else 0.0)
            have = sum(1 for mine in runs.values() if any(key in r for r in mine))
            if key == "residual":
                cells += ([f"{len(reached)}/{len(ran)}", f"{med(reached):.0f}",
                           f"{med(before):.0f}", f"{med(iters):.0f}", f"{med(ratio):.1f}"]
                          if reached else [f"0/{len(ran)}", "–", "–", "–", "–"])
            elif have:
                cells += ([f"{len(reached)}/{have}", f"{med(reached):.0f}", f"{med(ratio):.1f}"]
                          if reached else [f"0/{have}", "–", "–"])
            else:
                cells += ["–", "–", "–"]
        best = [min(mine, key=lambda r: r["residual"]) for mine in runs.values() if mine]
        best_cell = (f"{med(b['residual'] for b in best):.2g} "
                     f"({med(b['seconds'] for b in best) * 1e3:.0f})" if best else "–")
        print(f"| {solver} | {start} | " + " | ".join(cells) + f" | {best_cell} |")
    failures = [r for r in rows if "failure" in r]
    for r in failures:
        print(f"\n{r['solver']} {r['start']} {r['step']} tol {r['setting']}: {r['failure']}")
    print(f"\nengine solver (cdpowder NLGS + Anderson, 200 sweeps, warm start) re-timed here: "
          f"median {med(engine.values()) * 1e3:.1f} ms per step; at export "
          f"{med(r['engine_export_seconds'] for r in rows) * 1e3:.1f} ms; "
          f"engine residual (judged): median {med({r['step']: r['target'] for r in rows}.values()):.2g}")


def delassus(args):
    """W/s of one step in Matrix Market form, for factor_delassus.cpp."""
    import scipy.io
    mapping = Fc3dMapping(load_json(args.problem))
    W, _, _ = mapping.siconos_data()
    scipy.io.mmwrite(args.out, W)
    print(f"{args.out}: {W.shape[0]} rows, {W.nnz} non-zeros, scale s = {mapping.scale:.4g}")


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    c = sub.add_parser("check", help="verify the mapping on every exported step")
    c.add_argument("folder")
    r = sub.add_parser("run", help="solve every step with every solver, judge, record")
    r.add_argument("folder")
    r.add_argument("--out", required=True, help="results, one JSON object a line (appended)")
    r.add_argument("--solvers", default="", help="comma list (default: all of SOLVERS)")
    r.add_argument("--starts", default="warm,zero", help="warm, zero, engine (its solution)")
    r.add_argument("--steps", type=lambda t: [int(k) for k in t.split(",")], default=[],
                   help="comma list of step numbers K (default: all)")
    r.add_argument("--full-ladder", action="store_true",
                   help="go on down the ladder after reaching the engine's residual")
    r.add_argument("--skip-engine", action="store_true", help="do not time the engine")
    t = sub.add_parser("table", help="the comparison table of a results file")
    t.add_argument("results", nargs="+")
    d = sub.add_parser("delassus", help="write W/s of one step as Matrix Market")
    d.add_argument("problem")
    d.add_argument("out")
    for p in (c, r):
        p.add_argument("--tool", default=str(DEFAULT_TOOL), help="the contact_problem binary")
    args = parser.parse_args()
    {"check": check, "run": run, "table": table, "delassus": delassus}[args.command](args)


if __name__ == "__main__":
    main()
