"""Figure helpers shared by every drawing script: saving, colours, units, the sleeper."""
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PAPER_POINT = {"speedup": 2.75, "peak": -0.175, "contact": -0.28,
               "label": "paper (Table 2): 2.75x, -17.5 % / -28 %"}


def save(fig, stem, quiet: bool = False) -> list:
    """Writes STEM.png (150 dpi) and STEM.svg; returns the paths."""
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = [stem.with_suffix(".png"), stem.with_suffix(".svg")]
    for p in paths:
        fig.savefig(p, dpi=150)
    plt.close(fig)
    if not quiet:
        print(f"  wrote {paths[0]} (and .svg)")
    return paths


def seeds_text(n) -> str:
    """"1 seed", "3 seeds"."""
    n = int(n)
    return f"{n} seed" + ("s" if n != 1 else "")


def error_speedup_figure(height: float, legend_share: float):
    """Two panels side by side (peak force, contact force) over a row that holds their shared
    legend: (fig, [left, right], legend_ax). Fill the legend with `shared_legend` at the end."""
    fig = plt.figure(figsize=(11, height), constrained_layout=True)
    grid = fig.add_gridspec(2, 2, height_ratios=[1, legend_share])
    axes = [fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])]
    legend_ax = fig.add_subplot(grid[1, :])
    legend_ax.axis("off")
    return fig, axes, legend_ax


def shared_legend(legend_ax, ax) -> None:
    """The legend of `ax`'s artists, drawn in the legend row."""
    handles, labels = ax.get_legend_handles_labels()
    legend_ax.legend(handles, labels, loc="center", ncol=2, fontsize=8, frameon=False)


def error_speedup_panel(ax, output_name: str, paper_key: str, tolerance: float) -> None:
    """An axis of difference from the reference (%) against speedup: the tolerance band, zero,
    the paper's point for scale (its key "peak" or "contact"), labels and grid."""
    ax.axhspan(-100 * tolerance, 100 * tolerance, color="green", alpha=0.08, lw=0,
               label=f"within {100 * tolerance:.0f} %")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.plot([PAPER_POINT["speedup"]], [100 * PAPER_POINT[paper_key]], marker="*", ms=12, color="0.4", ls="none",
            label=PAPER_POINT["label"])
    ax.set_xlabel("speedup (x): reference wall time / model's, re-settling + push")
    ax.set_ylabel("difference from the reference (%)")
    ax.set_title(output_name, fontsize=10)
    ax.grid(alpha=0.3)


def model_colours(n: int) -> list:
    """The reference black, the others from a qualitative map in their order."""
    cycle = plt.get_cmap("tab10").colors
    return ["black"] + [cycle[k % len(cycle)] for k in range(n - 1)]


def force_unit(largest_newtons: float):
    """(scale, unit): kN for a full-size bed, N for a miniature one."""
    return (1e-3, "kN") if largest_newtons >= 1e3 else (1.0, "N")


def sleeper_outline(ax, x0, x1, z0, z1, **style) -> None:
    ax.add_patch(plt.Rectangle((x0, z0), x1 - x0, z1 - z0, fill=False, lw=1.5, ec="k", **style))


def force_bands(bands, title, legend_title, out, quiet):
    """F(u) with bands: each band a dict of u, mean, low, high (m, N) and its label; the mean as a
    line and the band from the lowest to the highest seed shaded, the first band black. Written to
    OUT/force_displacement."""
    bands = [b for b in bands if len(b["u"])]
    if not bands:
        return []
    scale, unit = force_unit(max(b["high"].max() for b in bands))
    fig, ax = plt.subplots(figsize=(8, 5), constrained_layout=True)
    for b, colour in zip(bands, model_colours(len(bands))):
        u = b["u"] * 1e3
        ax.fill_between(u, b["low"] * scale, b["high"] * scale, color=colour, alpha=0.15, lw=0)
        ax.plot(u, b["mean"] * scale, color=colour, lw=1.6, label=b["label"])
    ax.set_xlabel("sleeper displacement u (mm)")
    ax.set_ylabel(f"lateral force on the sleeper F ({unit})")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right", title=legend_title, title_fontsize=8)
    ax.set_title(title, fontsize=10)
    return save(fig, Path(out) / "force_displacement", quiet)
