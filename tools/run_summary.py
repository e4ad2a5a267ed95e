"""The tools' name for cdpowder.summary (python/cdpowder/summary.py), which reads a run's
summary.json: the tools import it from the source tree, without the compiled module."""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "python"))
from cdpowder.summary import FORMER_NAMES, SCHEMA, SummaryError, parse_summary, read_summary  # noqa: E402

__all__ = ["FORMER_NAMES", "SCHEMA", "SummaryError", "parse_summary", "read_summary"]
