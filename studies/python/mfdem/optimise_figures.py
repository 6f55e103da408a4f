"""The front of `mfdem optimise-layer`, drawn from OUT/optimise_layer.csv and OUT/optimise_layer.toml.

    tools/mfdem-py optimise_figures OUT [--quiet]

Writes OUT/figures/front.png and .svg: for the peak lateral force and the contact force, each
candidate's calibrated error (the mean paired difference from the reference with its 95 %
Student-t interval over the seeds) against its speedup, one line per family from the dearest
extent to the cheapest, the chosen layer starred, the uncalibrated models and the paper's point
for scale. Every number drawn was computed by mfdem.
"""
import argparse
import sys
import tomllib
from pathlib import Path

import numpy as np

from mfdem import figures, files


def front(rows, labels, out: Path, quiet: bool):
    fig, axes, legend_ax = figures.error_speedup_figure(5.8, 0.24)
    contact_name = "99.9 % quantile of the contact force" if labels["contact_quantile"] else "maximum contact force"
    families = list(dict.fromkeys(r["family"] for r in rows if r["calibrated"] == 1))
    colours = figures.model_colours(len(families) + 1)[1:]
    uncalibrated = [r for r in rows if r["calibrated"] == 0]
    for ax, (column, name, paper_key) in zip(axes, [("peak", "peak lateral force", "peak"),
                                                    ("contact", contact_name, "contact")]):
        figures.error_speedup_panel(ax, name, paper_key, labels["tolerance"])
        for family, colour in zip(families, colours):
            own = sorted((r for r in rows if r["family"] == family and r["calibrated"] == 1), key=lambda r: r["speedup"])
            x = np.array([r["speedup"] for r in own])
            y = np.array([100 * r[f"{column}_diff"] for r in own])
            half = np.array([100 * r[f"{column}_diff_half_width"] for r in own])
            ax.errorbar(x, y, yerr=np.where(np.isfinite(half), half, 0.0), fmt="o-", color=colour, capsize=4, ms=5,
                        label=f"{family}, mu_r calibrated at each {own[0]['extent_name']}")
            for r in own:
                ax.annotate(f"{r['extent']:.3g}", (r["speedup"], 100 * r[f"{column}_diff"]), fontsize=7,
                            xytext=(4, 4), textcoords="offset points", color=colour)
            chosen = [r for r in own if r["chosen"] == 1]
            if chosen:
                ax.plot([chosen[0]["speedup"]], [100 * chosen[0][f"{column}_diff"]], marker="*", ms=16, color=colour,
                        mec="k", ls="none", label=f"{family}: chosen")
        for r in uncalibrated:
            half = 100 * r[f"{column}_diff_half_width"]
            ax.errorbar([r["speedup"]], [100 * r[f"{column}_diff"]], yerr=half if np.isfinite(half) else None,
                        fmt="s", mfc="none", color="0.3", capsize=3, ms=7, label=f"{r['family']} (uncalibrated)")
        ax.set_xlim(0, max(3.0, 1.1 * max(r["speedup"] for r in rows)))
    figures.shared_legend(legend_ax, axes[0])
    fig.suptitle(f"{labels['config']}: the cheapest layer within {100 * labels['tolerance']:.0f} % "
                 f"(extents labelled), {figures.seeds_text(labels['seeds'])}; mean paired difference with its 95 % "
                 "Student-t interval", fontsize=10)
    return figures.save(fig, out / "front", quiet)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, help="the folder of an `mfdem optimise-layer` study")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    rows = files.read_csv(args.out / "optimise_layer.csv")
    with open(args.out / "optimise_layer.toml", "rb") as f:
        labels = tomllib.load(f)
    front(rows, labels, args.out / "figures", args.quiet)
    return 0


if __name__ == "__main__":
    sys.exit(main())
