#!/usr/bin/python3
"""A sweep folder's figures and report.md: `python3 -m cdpowder.report` (python/cdpowder/report/)
from the source tree, without the compiled module.

    tools/report.py SWEEP_DIR [--out DIR] [--all-runs] [--seeds LIST] [--packing RUN_FOLDER]
                    [--png-only]"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "python"))
from cdpowder.report.__main__ import main  # noqa: E402

if __name__ == "__main__":
    main()
