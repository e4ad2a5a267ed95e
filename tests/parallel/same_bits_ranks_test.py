#!/usr/bin/python3
"""The `parallel` label, MPI ranks: the compaction of same_bits_test.py (about 2 000 spheres in
8 × 8 tiles) ends on the same bits as one process with `mpirun -np P` for P = 1, 2, 3 and 4,
also under the relative-change stopping rule (np 3), and a run stopped on 4 ranks (SIGUSR1 to
mpirun, which forwards it: every rank stops after the same step and rank 0 writes a
checkpoint) and resumed on 2 ranks and as one process ends on the bits of the run never
stopped. On P ranks the VTK outputs are particles.pvtp and contacts.pvtp over one piece a rank,
which VTK's own reader (python3-vtk9) loads as the points and lines of one process's
particles.vtp and contacts.vtp; a run resumed on other ranks leaves no file of the ranks before. The ranks may outnumber the cores (--oversubscribe): the
bits are compared, never the times. As root (a CI container) Open MPI needs
OMPI_ALLOW_RUN_AS_ROOT=1 and OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1, which this test sets."""
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

import same_bits_test
from same_bits_test import SCENE_SETTINGS, expect_same, outputs


MPIEXEC = "mpirun"


def command(cdpowder, ranks, arguments):
    """`arguments` of cdpowder as one process (ranks 0) or under MPIEXEC with `ranks`."""
    if ranks == 0:
        return [cdpowder] + arguments
    return [MPIEXEC, "--oversubscribe", "-np", str(ranks), cdpowder] + arguments


def compact(cdpowder, scene, out, ranks, duration, extra=()):
    """Starts a compaction of `duration` t0 into `out`; returns the process."""
    arguments = ["compact", scene, "--out", str(out), "--quiet",
                 "--set", f"run.max_duration={duration}"] + list(extra)
    for setting in SCENE_SETTINGS:
        arguments += ["--set", setting]
    return subprocess.Popen(command(cdpowder, ranks, arguments), stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)


def finish(process, what, allowed=(0, 4)):
    """same_bits_test.finish, with the time several ranks on two cores may take."""
    same_bits_test.finish(process, what, allowed, timeout=900)


def vtk_data(path):
    """The data set of a .vtp, or of a .pvtp with its pieces, as VTK's own readers load it."""
    import vtk
    reader = vtk.vtkXMLPPolyDataReader() if path.suffix == ".pvtp" else vtk.vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def expect_same_vtk(one, folder, ranks, what):
    """folder's VTK files are `ranks` pieces (or one process's .vtp files for 0) holding one's."""
    from vtk.util.numpy_support import vtk_to_numpy
    import numpy
    pieces = ranks > 1
    for kind in ("particles", "contacts"):
        whole, collection = folder / f"{kind}.vtp", folder / f"{kind}.pvtp"
        if whole.exists() == pieces or collection.exists() != pieces:
            sys.exit(f"{what}: expected {collection.name if pieces else whole.name} alone")
        names = sorted(p.name for p in (folder / kind).glob("*.vtp")) if pieces else []
        if pieces and names != sorted(f"{kind}_{r}.vtp" for r in range(ranks)):
            sys.exit(f"{what}: the pieces are {names}, expected one for each of {ranks} ranks")
        if not pieces and (folder / kind).exists():
            sys.exit(f"{what}: the pieces of the ranks before are left in {kind}/")
    if not pieces:
        return
    reference, got = vtk_data(one / "particles.vtp"), vtk_data(folder / "particles.pvtp")
    order = numpy.argsort(vtk_to_numpy(got.GetPointData().GetArray("id")))
    same = got.GetNumberOfPoints() == reference.GetNumberOfPoints() and numpy.array_equal(
        vtk_to_numpy(reference.GetPoints().GetData()), vtk_to_numpy(got.GetPoints().GetData())[order])
    for name in ("radius", "velocity", "angular_velocity", "coordination"):
        same = same and numpy.array_equal(vtk_to_numpy(reference.GetPointData().GetArray(name)),
                                          vtk_to_numpy(got.GetPointData().GetArray(name))[order])
    if not same:
        sys.exit(f"{what}: particles.pvtp's pieces differ from one process's particles.vtp")
    reference, got = vtk_data(one / "contacts.vtp"), vtk_data(folder / "contacts.pvtp")
    forces = [numpy.sort(vtk_to_numpy(d.GetCellData().GetArray("normal_force")))
              for d in (reference, got)]
    if got.GetNumberOfLines() != reference.GetNumberOfLines() or not numpy.array_equal(*forces):
        sys.exit(f"{what}: contacts.pvtp's pieces differ from one process's contacts.vtp")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cdpowder", required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--mpiexec", default="mpirun", help="Open MPI's launcher (default mpirun)")
    parser.add_argument("--ranks", default="1,2,3,4",
                        help="rank counts compared with one process (default 1,2,3,4)")
    parser.add_argument("--duration", type=float, default=12.0,
                        help="simulated time of each run [t0] (default 12)")
    args = parser.parse_args()
    global MPIEXEC
    MPIEXEC = args.mpiexec
    os.environ["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
    os.environ["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    with tempfile.TemporaryDirectory() as scratch:
        scratch = pathlib.Path(scratch)
        one = scratch / "one_process"
        finish(compact(args.cdpowder, args.scene, one, 0, args.duration), "one process")
        reference = outputs(one)
        if reference["summary"][1] < 50:
            sys.exit(f"too short a run to compare: {reference['summary'][1]} steps")
        for ranks in [int(r) for r in args.ranks.split(",")]:
            folder = scratch / f"ranks_{ranks}"
            finish(compact(args.cdpowder, args.scene, folder, ranks, args.duration),
                   f"{ranks} ranks")
            expect_same(reference, folder, f"{ranks} ranks")
            expect_same_vtk(one, folder, ranks, f"{ranks} ranks")
            print(f"ranks {ranks}: the bits of one process")

        # the relative-change rule sums over every contact's action after every pass: the
        # ranks share their tiles' actions for it
        relative = ["--set", 'solver.stopping_rule="relative_change"',
                    "--set", "solver.tolerance=1e-4"]
        relative_one = scratch / "relative_one_process"
        finish(compact(args.cdpowder, args.scene, relative_one, 0, 4.0, relative),
               "relative-change rule, one process")
        relative_ranks = scratch / "relative_3_ranks"
        finish(compact(args.cdpowder, args.scene, relative_ranks, 3, 4.0, relative),
               "relative-change rule, 3 ranks")
        expect_same(outputs(relative_one), relative_ranks, "relative-change rule, 3 ranks")
        print("relative-change rule, ranks 3: the bits of one process")

        # stopped on 4 ranks after its first checkpoint (every 2 t0; checkpoints change no
        # bit), resumed on 2 ranks and as one process; a run that ended first is tried again
        stopped = scratch / "stopped"
        for _ in range(3):
            shutil.rmtree(stopped, ignore_errors=True)
            process = compact(args.cdpowder, args.scene, stopped, 4, args.duration,
                              ["--checkpoint-every", "2"])
            deadline = time.monotonic() + 300
            while (time.monotonic() < deadline and process.poll() is None
                   and not (stopped / "checkpoint.cdps").exists()):
                time.sleep(0.002)
            process.send_signal(signal.SIGUSR1)
            finish(process, "the stopped run", allowed=(1, 0, 4))
            if process.returncode == 1 and (stopped / "checkpoint.cdps").exists():
                break
        else:
            sys.exit("the run ended before the signal each time; nothing to resume")
        at_step = json.loads((stopped / "summary.json").read_text())["run"]["steps"]
        print(f"stopped on 4 ranks at step {at_step} of {reference['summary'][1]}")
        for ranks in (2, 0):
            folder = scratch / f"resumed_on_{ranks}"
            shutil.copytree(stopped, folder)
            (folder / ".run.lock").unlink(missing_ok=True)
            resumed = subprocess.run(
                command(args.cdpowder, ranks, ["resume", str(folder), "--quiet"]),
                capture_output=True, text=True, timeout=900)
            if resumed.returncode not in (0, 4):
                sys.exit(f"resume on {ranks} ranks: exit {resumed.returncode}\n{resumed.stderr}")
            where = f"{ranks} ranks" if ranks else "one process"
            expect_same(reference, folder, f"stopped on 4 ranks, resumed on {where}")
            expect_same_vtk(one, folder, ranks, f"stopped on 4 ranks, resumed on {where}")
            print(f"stopped on 4 ranks, resumed on {where}: the bits of the run never stopped")


if __name__ == "__main__":
    main()
