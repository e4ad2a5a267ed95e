#!/usr/bin/python3
"""Every committed sweep report under results/ is what today's report makes of its folder:
each folder's report.md is made again (tools/report.py, the PNG figures alone, into a scratch
folder) and must equal the committed one byte for byte. A change of the report or of a
folder's runs without its report regenerated fails here. The packing figure needs particle
files git does not keep, so the committed one is handed to the new report as it would find
it in place."""
import pathlib
import shutil
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
REPORT = ROOT / "tools" / "report.py"

stale = []
folders = sorted(p.parent.parent for p in (ROOT / "results").glob("**/report/report.md"))
with tempfile.TemporaryDirectory() as scratch:
    for folder in folders:
        out = pathlib.Path(scratch) / folder.relative_to(ROOT / "results") / "report"
        out.mkdir(parents=True)
        for kept in ("packing.png", "packing_source.txt"):
            if (folder / "report" / kept).exists():
                shutil.copy(folder / "report" / kept, out / kept)
        # the folder as the committed report names it: relative to the repository
        done = subprocess.run([sys.executable, str(REPORT), str(folder.relative_to(ROOT)),
                               "--out", str(out), "--png-only"],
                              capture_output=True, text=True, cwd=ROOT)
        if done.returncode != 0:
            stale.append(f"{folder.relative_to(ROOT)}: the report failed:\n{done.stderr}")
        elif (out / "report.md").read_text() != (folder / "report" / "report.md").read_text():
            stale.append(f"{folder.relative_to(ROOT)}/report/report.md is stale: regenerate it "
                         f"with tools/report.py {folder.relative_to(ROOT)}")
for line in stale:
    print(line)
print(f"{len(folders) - len(stale)} of {len(folders)} reports are fresh")
sys.exit(1 if stale else 0)
