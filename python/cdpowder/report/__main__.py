"""Turns a `cdpowder sweep` folder into the figures and tables of the paper's comparison.

    python3 -m cdpowder.report SWEEP_DIR [--out DIR] [--all-runs] [--seeds LIST]
                               [--packing RUN_FOLDER] [--png-only]
    tools/report.py …  (the same, from the source tree)

Reads SWEEP_DIR/results.csv (one row per run) and writes into DIR (default SWEEP_DIR/report),
each figure as .png, .svg and .pdf (--png-only: the PNGs alone, a quicker look):

  fig5_porosity    the paper's Fig. 5: (a) porosity E against μt for each μn, (b) against μn
                   for each μt, (c) the added porosity E1 = E − E0 along the axes and the
                   diagonal; mean ± standard error over seeds, the paper's stated values as
                   open stars
  added_porosity   E1(μt, μn) = E(μt, μn) − E(0, 0) as a map
  additivity       ΔE = E1(μt, μn) − E1(μt, 0) − E1(0, μn) as a map
  table1_stress    the paper's Table 1: σzz+/p and σzz−/p beside the paper's values
  additivity_against_KEY
                   for a sweep that crosses the torque corners (μt, μn) ∈ {0, c}² with
                   another key (μ, the pressure): E and σzz+/p at the four corners and the
                   residuals of additivity across the modes, against the key
                   (interactions.py)
  energy_budget    where the piston's work goes: the runs' energy budgets (summary.json
                   "energy") as fractions of the work, beside the porosity (energy.py)
  load_path        for a Python protocol whose protocol.json holds a loading path's stages
                   (examples/paper/load_path.py): E along the path (load_path.py)
  packing          one packing before and after compaction with the bottom wall, the cell
                   and the piston (the paper's Fig. 3)
  report.md        the points table, Table 1 beside the paper, the paper's claims with
                   cdpowder's numbers ± error (E0, E(1, 1), the E1 values and their ratio, the
                   ratio along the axes, the additivity residual, saturation along three
                   lines, E(1, 1) against E_init)

Differences between points (E1, ΔE) are paired by seed: runs with the same seed start from
the same deposit, so their difference has a much smaller spread than either porosity.
Only runs that reached the blocked state count, unless --all-runs (for quick looks at
unfinished sweeps; the report then says so). --seeds 1-2 (or 1,2,5) keeps only those seeds:
a sweep that is still running has more seeds at some points than at others, and a report
over the seeds every point has compares like with like. Uses pandas, numpy and matplotlib
(Debian's python3-pandas, python3-numpy, python3-matplotlib); run with Debian's
/usr/bin/python3. The pieces are the modules of this package (python/cdpowder/report/).
"""
import argparse
import pathlib
import sys

from cdpowder.report import admissible, energy, figures, interactions, load_path, sections
from cdpowder.report.data import Stat, Sweep, parse_seeds, read_results
from cdpowder.report.packing_figure import plot_packing

ORIGIN = sections.ORIGIN


def parse_arguments():
    parser = argparse.ArgumentParser(prog="cdpowder.report", description=__doc__.split("\n\n")[0])
    parser.add_argument("sweep_dir", type=pathlib.Path)
    parser.add_argument("--out", type=pathlib.Path, help="default: SWEEP_DIR/report")
    parser.add_argument("--all-runs", action="store_true",
                        help="also use runs that did not reach the blocked state")
    parser.add_argument("--seeds", metavar="LIST",
                        help="only these seeds, e.g. 1-2 or 1,2,5 (default: all)")
    parser.add_argument("--packing", type=pathlib.Path,
                        help="run folder for the packing figure (default: a (0,0) run)")
    parser.add_argument("--png-only", action="store_true",
                        help="no SVG and PDF beside the PNGs (a quicker look)")
    args = parser.parse_args()
    if args.png_only:
        figures.formats[:] = ["png"]
    if not (args.sweep_dir / "results.csv").exists():
        sys.exit(f"error: {args.sweep_dir / 'results.csv'} not found: "
                 f"is {args.sweep_dir} a sweep folder?")
    try:
        args.seed_set = parse_seeds(args.seeds) if args.seeds is not None else None
    except ValueError as e:
        sys.exit(f"error: --seeds: {e}")
    return args


def maps(sweep, out):
    """The E1 and additivity maps; returns the additivity residual over the mesh (None
    without E(0, 0), which every E1 is paired with)."""
    if ORIGIN not in sweep:
        return None
    figures.grid_map(sweep, lambda t, n: sweep.added((t, n)),
                     r"added porosity $E_1 = E - E_0$", "added_porosity", out, r"$E_1$")

    def residual(t, n):
        # ΔE is zero by definition on the axes (t = 0 or n = 0): only off-axis points count
        if t > 0 and n > 0 and (t, 0.0) in sweep and (0.0, n) in sweep:
            return sweep.paired([(t, n), ORIGIN], [(t, 0.0), (0.0, n)])
        return Stat([])
    return figures.grid_map(sweep, residual, r"additivity residual $\Delta E = E_1(\mu_t, \mu_n) - E_1(\mu_t, 0) - E_1(0, \mu_n)$",
                            "additivity",
                            out, r"$\Delta E$", cmap="RdBu_r", symmetric=True)


def packing_section(args, sweep, out):
    """The packing figure needs a run's particle files, which stay on the machine that ran it
    (results/.gitignore): the first run of (0,0) (else of the first point) that has them.
    Where no run here has them, the figure drawn before is kept, with the run it shows
    (packing_source.txt), so regenerating a report in a fresh clone does not drop it."""
    packing = args.packing
    if packing is None and sweep.points:
        start = ORIGIN if ORIGIN in sweep else sweep.points[0]
        folders = [args.sweep_dir / f for f in sweep.runs_at(start).sort_values("seed")["folder"]]
        packing = next((f for f in folders if (f / "initial_particles.csv").exists()), None)
    elif packing is not None and not (packing / "initial_particles.csv").exists():
        print(f"report: warning: {packing} has no particle files; the packing figure is not "
              "redrawn", file=sys.stderr)
    source_file = out / "packing_source.txt"
    if packing is not None and (packing / "initial_particles.csv").exists():
        plot_packing(packing, out)
        source_file.write_text(f"{packing}\n")
    if not ((out / "packing.png").exists() and source_file.exists()):
        return []
    return ["## One packing before and after compaction (Fig. 3)", "",
            f"`{source_file.read_text().strip()}`", "", "![packing](packing.png)", ""]


def main():
    args = parse_arguments()
    out = args.out or args.sweep_dir / "report"
    out.mkdir(parents=True, exist_ok=True)
    table, provenance = read_results(args.sweep_dir / "results.csv")
    sweep = Sweep(table, args.all_runs, args.seed_set)
    md = sections.header(args.sweep_dir, provenance, sweep, args.all_runs, args.seeds)
    md += sections.accuracy(sweep) + sections.variants(sweep)
    if sweep.points:
        figures.plot_fig5(sweep, out)
        md += sections.points(sweep)
        residual_map = maps(sweep, out)
        if residual_map is not None:
            md += ["## Added porosity and additivity", "",
                   "![E1](added_porosity.png) ![ΔE](additivity.png)", ""]
        md += sections.claims(sweep, residual_map) + sections.axis_ratios(sweep)
        md += sections.table1(sweep, figures.plot_table1(sweep, out))
        md += packing_section(args, sweep, out)
    else:
        md += [f"No points that set only `{sections.MU_T}` and `{sections.MU_N}`: "
               "no paper figures.", ""]
    # any sweep: each swept key on its own axis (the paper's keys have Fig. 5 above)
    other_keys = [k for k in sweep.keys if not (sweep.points and k in (sections.MU_T,
                                                                       sections.MU_N))]
    md += sections.against_keys(sweep, {k: figures.plot_against_key(sweep, k, out)
                                        for k in other_keys})
    md += interactions.section(args.sweep_dir, sweep, out)
    md += load_path.section(args.sweep_dir, sweep, out)
    md += admissible.section(args.sweep_dir, sweep, out)
    md += energy.section(args.sweep_dir, sweep, out)
    (out / "report.md").write_text("\n".join(md) + "\n")
    print(f"report: {out / 'report.md'}")


if __name__ == "__main__":
    main()
