"""Reading a run's summary.json, the one place the Python tools do it.

The file and its schema are documented in docs/outputs.md ("summary.json"); the program
writes and reads it in src/cdpowder/run/run_summary.cpp. A summary without a "schema" key was
written before the number existed and reads as schema 0: the fields it lacks are absent (use
dict.get). A schema newer than SCHEMA is refused, since a renamed or re-meant field would be
read wrongly.
"""
import json
import pathlib

SCHEMA = 1  # kRunSummarySchema of run_summary.hpp


class SummaryError(ValueError):
    """A summary.json that is not JSON, not an object, or of a newer schema."""


def parse_summary(text, where="summary.json"):
    """The summary in `text` as a dict, with "schema" set (0 when the file has none)."""
    try:
        summary = json.loads(text)
    except json.JSONDecodeError as error:
        raise SummaryError(f"{where}: not JSON ({error})") from None
    if not isinstance(summary, dict):
        raise SummaryError(f"{where}: not a JSON object")
    schema = summary.setdefault("schema", 0)
    if not isinstance(schema, int) or not 0 <= schema <= SCHEMA:
        raise SummaryError(f"{where}: schema {schema!r} is not one this tool reads (0 to {SCHEMA}):"
                           " written by a newer cdpowder?")
    return summary


def read_summary(path):
    """The summary.json at `path` as a dict. Raises OSError or SummaryError."""
    path = pathlib.Path(path)
    return parse_summary(path.read_text(), str(path))
