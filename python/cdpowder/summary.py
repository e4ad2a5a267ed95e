"""cdpowder.summary: reading a run's summary.json, the one place Python does it (the package,
its report and the tools under tools/).

The file and its schema are documented in docs/outputs.md ("summary.json"); the program
writes and reads it in src/cdpowder/run/run_summary.cpp. A summary without a "schema" key was
written before the number existed and reads as schema 0: the fields it lacks are absent (use
dict.get). A schema newer than SCHEMA is refused, since a renamed or re-meant field would be
read wrongly. Schema 2 renamed the NLGS pass counts from "sweeps" to "passes"; an older
summary is read with the new names, so the tools use one spelling.
"""
import json
import pathlib

SCHEMA = 2  # kRunSummarySchema of run_summary.hpp

# The fields of schema 0 and 1 that schema 2 renamed: section → {old name: new name}.
FORMER_NAMES = {
    "run": {"total_sweeps": "total_passes", "sweeps_per_step": "passes_per_step",
            "repeated_sweeps": "repeated_passes", "probe_sweeps": "probe_passes"},
    "final_solve": {"sweeps": "passes"},
}


def _rename_former_fields(summary):
    sections = [summary.get("run"), (summary.get("accuracy") or {}).get("final_solve")]
    for section, names in zip(sections, FORMER_NAMES.values()):
        if isinstance(section, dict):
            for old, new in names.items():
                if old in section:
                    section.setdefault(new, section.pop(old))


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
    if schema < 2:
        _rename_former_fields(summary)
    return summary


def read_summary(path):
    """The summary.json at `path` as a dict. Raises OSError or SummaryError."""
    path = pathlib.Path(path)
    return parse_summary(path.read_text(), str(path))
