"""cdpowder.tables: the CSV files a run and a sweep write, as pandas DataFrames.

Every file starts with '#' provenance lines (program, commit, scene: docs/outputs.md); these
readers skip them and return them apart, so `pd.read_csv` needs no `comment="#"` of its own:

    frame = cdpowder.tables.read_timeseries("out/timeseries.csv")
    frame.attrs["provenance"]   # the '#' lines
"""
import io
import pathlib

import pandas as pd

# results.csv columns of tables written before the NLGS pass was called a pass (CHANGELOG.md)
_FORMER_COLUMNS = {"total_sweeps": "total_passes", "sweeps": "passes"}


def read_table(path, dtype=None):
    """A cdpowder CSV file as a DataFrame; its '#' lines in frame.attrs["provenance"]."""
    lines = pathlib.Path(path).read_text().splitlines(keepends=True)
    provenance = [line.rstrip("\n") for line in lines if line.startswith("#")]
    body = "".join(line for line in lines if not line.startswith("#"))
    frame = pd.read_csv(io.StringIO(body), dtype=dtype).rename(columns=_FORMER_COLUMNS)
    frame.attrs["provenance"] = provenance
    return frame


def read_timeseries(path):
    """timeseries.csv: one row every K steps (docs/outputs.md)."""
    return read_table(path)


def read_particles(path):
    """particles.csv (or initial_particles.csv): one row a sphere; `fixed` as booleans."""
    frame = read_table(path)
    if "fixed" in frame:
        frame["fixed"] = frame["fixed"].astype(bool)
    return frame


def read_contacts(path):
    """contacts.csv: one row a contact; a = −1 is the bottom wall, −2 the piston."""
    return read_table(path, dtype={"state": str})


def read_sweep(path):
    """A sweep's results.csv (one row a run) or points.csv (one row a point)."""
    return read_table(path, dtype={"point": str, "folder": str})
