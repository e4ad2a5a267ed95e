"""cdpowder.tables and cdpowder.summary read what a run writes, '#' lines and all."""
import os
import subprocess
from pathlib import Path

import cdpowder.summary
import cdpowder.tables

SOURCE = Path(os.environ["CDPOWDER_SOURCE_DIR"])


def test_a_runs_files_read_as_data_frames(tmp_path):
    subprocess.run([os.environ["CDPOWDER_EXE"], "compact", str(SOURCE / "examples/quick/scene.toml"),
                    "--out", str(tmp_path), "--quiet", "--set", "run.max_duration=2"],
                   capture_output=True)
    series = cdpowder.tables.read_timeseries(tmp_path / "timeseries.csv")
    assert "passes" in series and series["step"].is_monotonic_increasing
    assert series.attrs["provenance"][0].startswith("#")
    particles = cdpowder.tables.read_particles(tmp_path / "particles.csv")
    assert len(particles) == 100 and particles["fixed"].dtype == bool
    contacts = cdpowder.tables.read_contacts(tmp_path / "contacts.csv")
    assert set(contacts["state"]) <= {"open", "closed"}
    summary = cdpowder.summary.read_summary(tmp_path / "summary.json")
    assert summary["schema"] == cdpowder.summary.SCHEMA
    # a row every run.timeseries_interval: the last at or before the run's last step
    assert 0 < series["step"].iloc[-1] <= summary["run"]["steps"]


def test_a_sweep_table_of_the_former_names_reads_with_the_new(tmp_path):
    table = tmp_path / "results.csv"
    table.write_text("# cdpowder\npoint,seed,porosity,total_sweeps\na,1,0.5,100\n")
    frame = cdpowder.tables.read_sweep(table)
    assert list(frame.columns) == ["point", "seed", "porosity", "total_passes"]
