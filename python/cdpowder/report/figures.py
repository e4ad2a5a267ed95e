"""The report's figures: the paper's Fig. 5 with its added porosity, the maps of E1 and of
the additivity residual, and Table 1 as a figure. Each is saved as PNG (to look at) and SVG
and PDF (vector, for a paper), byte for byte the same when the data are (fixed SVG ids, no
dates). The paper's stated values are drawn as open stars beside cdpowder's mean ± standard
error over seeds."""
import matplotlib

matplotlib.use("Agg")
# Same data, same bytes: SVG element ids from a fixed salt and no creation date, so a
# regenerated report changes in git only where its numbers do.
matplotlib.rcParams["svg.hashsalt"] = "cdpowder-report"
matplotlib.rcParams["font.size"] = 9
# Text stays text in the vector files, so labels can be edited and searched: SVG <text>
# elements, and TrueType (Type 42) fonts in the PDF, which journals accept (Type 3 they don't)
matplotlib.rcParams["svg.fonttype"] = "none"
matplotlib.rcParams["pdf.fonttype"] = 42
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import paper  # noqa: E402
from .data import Stat  # noqa: E402

FORMATS = ("png", "svg", "pdf")
formats = list(FORMATS)  # the ones written (report.py --png-only: the first alone)
# metadata that would make two renderings of the same data differ
_NO_DATES = {"png": {"Software": None}, "svg": {"Date": None}, "pdf": {"CreationDate": None}}
PAPER_STYLE = dict(marker="*", markersize=11, markerfacecolor="none", markeredgewidth=1.2,
                   linestyle="none")


def save(fig, out, name):
    for ext in formats:
        fig.savefig(out / f"{name}.{ext}", dpi=150, bbox_inches="tight",
                    metadata=_NO_DATES[ext])
    plt.close(fig)


def label_panel(ax, label):
    """(a), (b), … at the top left corner, outside the axes."""
    ax.text(-0.12, 1.04, label, transform=ax.transAxes, fontsize=11, fontweight="bold",
            va="bottom", ha="left")


def ordered_colours(count):
    """Colours for an ordered parameter, dark (small) to light (large); viridis stops short of
    its palest yellow, which is hard to see on white."""
    return plt.cm.viridis(np.linspace(0.0, 0.85, max(count, 1)))


def _porosity_panel(ax, sweep, axis):
    """E against μt (axis 0) or μn (axis 1), one curve per value of the other coefficient,
    with the paper's porosities at the corners of the mesh."""
    along, across = sweep.mus(axis), sweep.mus(1 - axis)
    names = (r"$\mu_t$", r"$\mu_n$")
    for colour, c in zip(ordered_colours(len(across)), across):
        points = [((x, c) if axis == 0 else (c, x)) for x in along]
        stats = [(p[axis], sweep.stat(p, "porosity")) for p in points if p in sweep]
        if stats:
            ax.errorbar([x for x, _ in stats], [s.mean for _, s in stats],
                        yerr=[s.error_bar() for _, s in stats], marker="o", markersize=4,
                        capsize=2.5, color=colour, label=f"{c:g}")
    # the paper's porosities, each in the colour of the curve its point lies on
    colour_of = dict(zip(across, ordered_colours(len(across))))
    corners = {(0.0, 0.0): paper.E0, (1.0, 1.0): paper.E11,
               (1.0, 0.0): paper.E0 + paper.E1_ROLL, (0.0, 1.0): paper.E0 + paper.E1_TWIST}
    for p, e in corners.items():
        if p in sweep:
            ax.plot(p[axis], e, color=colour_of[p[1 - axis]], **PAPER_STYLE)
    ax.plot([], [], color="black", label="paper (text)", **PAPER_STYLE)
    ax.set_xlabel(names[axis])
    ax.grid(alpha=0.3)
    # under the axes: inside, it would hide curves or the paper's stars
    ax.legend(title=f"{names[1 - axis]} =", fontsize=7, title_fontsize=7, ncol=5,
              loc="upper center", bbox_to_anchor=(0.5, -0.14), columnspacing=0.8,
              handlelength=1.6)


def _added_porosity_panel(ax, sweep):
    """E1 = E − E0 along the two axes and the diagonal, paired by seed, with the paper's E1
    at μ = 1 and the μ from which it says E1 saturates."""
    lines = (("rolling only, $E_1(\\mu, 0)$", lambda m: (m, 0.0), paper.E1_ROLL, "C0"),
             ("torsion only, $E_1(0, \\mu)$", lambda m: (0.0, m), paper.E1_TWIST, "C1"),
             ("both, $E_1(\\mu, \\mu)$", lambda m: (m, m), paper.E1_BOTH, "C2"))
    for label, point, paper_value, colour in lines:
        stats = [(m, sweep.added(point(m))) for m in sweep.mus(0) if point(m) in sweep]
        stats = [(m, s) for m, s in stats if s.n]
        if stats:
            ax.errorbar([m for m, _ in stats], [s.mean for _, s in stats],
                        yerr=[s.error_bar() for _, s in stats], marker="o", markersize=4,
                        capsize=2.5, color=colour, label=label)
        if point(1.0) in sweep:
            ax.plot(1.0, paper_value, color=colour, **PAPER_STYLE)
    ax.plot([], [], color="black", label="paper (text), μ = 1", **PAPER_STYLE)
    ax.axvline(paper.SATURATION_MU, color="grey", linestyle=":", linewidth=1)
    ax.text(paper.SATURATION_MU, 0.01, " paper: saturates\n from μ ≈ 0.4", color="grey",
            fontsize=7, va="bottom", transform=ax.get_xaxis_transform())
    ax.set_xlabel(r"$\mu$")
    ax.set_ylabel(r"added porosity $E_1 = E - E_0$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")


def plot_fig5(sweep, out):
    """The paper's Fig. 5: (a) E against μt, (b) E against μn and, where the sweep has
    (0, 0), (c) the added porosity along the axes and the diagonal."""
    with_added = (0.0, 0.0) in sweep
    fig, axes = plt.subplots(1, 3 if with_added else 2, figsize=(13 if with_added else 9, 4),
                             gridspec_kw=dict(wspace=0.3))
    _porosity_panel(axes[0], sweep, 0)
    _porosity_panel(axes[1], sweep, 1)
    axes[1].sharey(axes[0])
    axes[0].set_ylabel("porosity E")
    if with_added:
        _added_porosity_panel(axes[2], sweep)
    for ax, label in zip(axes, "abc"):
        label_panel(ax, f"({label})")
    fig.suptitle("Porosity after compaction, mean ± standard error over seeds", y=1.02)
    save(fig, out, "fig5_porosity")


def _annotate_cells(ax, image, data):
    """Each cell's value, in black on light colours and white on dark ones."""
    for (i, j), value in np.ndenumerate(data):
        if np.isfinite(value):
            r, g, b, _ = image.cmap(image.norm(value))
            light = 0.299 * r + 0.587 * g + 0.114 * b > 0.5
            ax.text(j, i, f"{value:.3f}", ha="center", va="center", fontsize=6.5,
                    color="black" if light else "white")


def grid_map(sweep, values, title, name, out, colour_label, cmap="viridis", symmetric=False):
    """values(μt, μn) → Stat over the mesh as a coloured map with each cell's mean written in
    it; returns the means (rows μn, columns μt). A symmetric map (a residual around 0) uses a
    diverging colour map centred on 0."""
    mu_ts, mu_ns = sweep.mus(0), sweep.mus(1)
    data = np.full((len(mu_ns), len(mu_ts)), np.nan)
    for (i, n), (j, t) in ((a, b) for a in enumerate(mu_ns) for b in enumerate(mu_ts)):
        s = values(t, n)
        data[i, j] = s.mean if s.n else np.nan
    fig, ax = plt.subplots(figsize=(5.6, 4.6))
    limits = {}
    if symmetric and np.isfinite(data).any():
        lim = max(float(np.nanmax(np.abs(data))), 1e-12)
        limits = dict(vmin=-lim, vmax=lim)
    image = ax.imshow(data, origin="lower", cmap=cmap, **limits)
    ax.set_xticks(range(len(mu_ts)), [f"{t:g}" for t in mu_ts])
    ax.set_yticks(range(len(mu_ns)), [f"{n:g}" for n in mu_ns])
    ax.set_xlabel(r"$\mu_t$ (rolling)")
    ax.set_ylabel(r"$\mu_n$ (torsion)")
    _annotate_cells(ax, image, data)
    fig.colorbar(image, ax=ax, label=colour_label)
    ax.set_title(title)
    save(fig, out, name)
    return data


def _table1_legend_rank(label):
    return (0 if "+" in label else 1 if "-" in label else 2, "paper" in label)


def plot_table1(sweep, out):
    """Table 1 as a figure: σzz+/p and σzz−/p at the paper's eight points, cdpowder's mean ±
    standard error beside the paper's values; σzz/p = 1 is static balance."""
    present = [p for p in paper.TABLE1 if p in sweep]
    if not present:
        return False
    fig, ax = plt.subplots(figsize=(8, 4))
    x = np.arange(len(present))
    for k, (column, label, colour, marker) in enumerate((
            ("sigma_zz_compressive_over_p", r"$\sigma_{zz}^+/p$ (compressive)", "C0", "o"),
            ("sigma_zz_tensile_over_p", r"$\sigma_{zz}^-/p$ (tensile)", "C3", "s"))):
        stats = [sweep.stat(p, column) for p in present]
        ax.errorbar(x - 0.1, [s.mean for s in stats], yerr=[s.error_bar() for s in stats],
                    marker=marker, markersize=5, capsize=3, linestyle="none", color=colour,
                    label=f"{label}, cdpowder")
        ax.plot(x + 0.1, [paper.TABLE1[p][k + 1] for p in present], color=colour,
                label=f"{label}, paper", **PAPER_STYLE)
    sigma = [sweep.stat(p, "sigma_zz_over_p") for p in present]
    ax.plot(x - 0.1, [s.mean for s in sigma], marker="d", markersize=4, linestyle="none",
            color="black", label=r"$\sigma_{zz}/p$, cdpowder")
    ax.axhline(1.0, color="black", linewidth=0.8, linestyle="--")
    ax.axhline(0.0, color="grey", linewidth=0.6)
    ax.set_xticks(x, [f"({p[0]:g}, {p[1]:g})" for p in present])
    ax.set_xlabel(r"$(\mu_t, \mu_n)$")
    ax.set_ylabel("stress / applied pressure p")
    ax.grid(alpha=0.3, axis="y")
    # column by column: the compressive pair, the tensile pair, σzz
    handles, labels = ax.get_legend_handles_labels()
    order = [labels.index(name) for name in sorted(labels, key=_table1_legend_rank)]
    ax.legend([handles[k] for k in order], [labels[k] for k in order], fontsize=7, ncol=3,
              loc="lower center", bbox_to_anchor=(0.5, 1.01))
    save(fig, out, "table1_stress")
    return True


def plot_against_key(sweep, key, out):
    """E, σzz+/p and σzz−/p against a swept key, one curve per group of the other keys' values
    (mean ± standard error over seeds); returns the figure's name, or None for no curve."""
    groups = sweep.against(key)
    if not groups:
        return None
    quantities = (("porosity", "porosity E"), ("sigma_zz_compressive_over_p", r"$\sigma_{zz}^+/p$"),
                  ("sigma_zz_tensile_over_p", r"$\sigma_{zz}^-/p$"))
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
    for ax, (column, label) in zip(axes, quantities):
        for colour, (group, by_value) in zip(ordered_colours(len(groups)), groups.items()):
            xs = list(by_value)
            stats = [Stat(by_value[x][column]) if column in by_value[x] else Stat([]) for x in xs]
            ax.errorbar(xs, [s.mean for s in stats], yerr=[s.error_bar() for s in stats],
                        marker="o", markersize=4, capsize=2.5, color=colour, label=group or None)
        ax.set_xlabel(key)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        if len(set(float(x) for by in groups.values() for x in by)) > 2 and \
                min(float(x) for by in groups.values() for x in by) > 0:
            ax.set_xscale("log")
    if any(groups):
        axes[0].legend(fontsize=7)
    fig.tight_layout()  # the panels' y labels clear their neighbours
    name = "against_" + "".join(c if c.isalnum() else "_" for c in key)
    save(fig, out, name)
    return name
