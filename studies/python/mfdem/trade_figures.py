"""The figure of `mfdem trade`, drawn from OUT/trade.csv.

    tools/mfdem-py trade_figures OUT [--compare COMPARE_OUT] [--quiet]

Writes OUT/figures/trade.png and .svg: for the peak lateral force and the maximum contact force,
each setting's mean paired difference from the reference setting (with its 95 % Student-t
interval over the seeds) against its speedup (preparation + push), one line per knob from the
reference outwards, values labelled; a knob's first unsafe value (refused before it ran, or
stopped by a guard) is named under the panels. With --compare, the models of an `mfdem compare`
study on the same axes (open squares), so that a coarser model and a coarser numerical setting
can be set side by side. Every number drawn was computed by mfdem.
"""
import argparse
import sys
from pathlib import Path

import numpy as np

from mfdem import figures, files


def trade(rows, compare_rows, out: Path, quiet: bool):
    fig, axes, legend_ax = figures.error_speedup_figure(6.2, 0.32)
    reference = rows[0]
    knobs = list(dict.fromkeys(r["knob"] for r in rows[1:]))
    colours = figures.model_colours(len(knobs) + 1)[1:]
    unsafe = []
    for ax, (column, name, paper_key) in zip(axes, [("peak", "peak lateral force", "peak"),
                                                    ("contact", "maximum contact force", "contact")]):
        figures.error_speedup_panel(ax, name, paper_key, 0.05)
        ax.set_xlabel("speedup against the reference setting (x), preparation + push")
        ax.set_ylabel("difference from the reference setting (%)")
        ax.plot([1.0], [0.0], "o", color="black", ms=7, label=reference["label"])
        for knob, colour in zip(knobs, colours):
            # trade.csv lists a knob's values from its accurate end outwards.
            own = [r for r in rows if r["knob"] == knob and str(r["status"]).startswith("ran")]
            if not own:
                continue  # every value past the edge: named under the panels
            x = np.array([1.0] + [r["total_speedup"] for r in own])
            y = np.array([0.0] + [100 * r[f"{column}_diff"] for r in own])
            half = np.array([0.0] + [100 * r[f"{column}_diff_half_width"] for r in own])
            ax.errorbar(x, y, yerr=np.where(np.isfinite(half), half, 0.0), fmt="o-", color=colour, capsize=3, ms=5,
                        label=f"{knob}")
            for r in own:
                ax.annotate(f"{r['value']:g}", (r["total_speedup"], 100 * r[f"{column}_diff"]), fontsize=7,
                            xytext=(4, 4), textcoords="offset points", color=colour)
        prefix = "peak_force" if column == "peak" else "max_contact_force"
        for r in compare_rows:
            if r.get("reference") == 1:
                continue
            y, low, high = (100 * r.get(f"{prefix}_diff{s}", np.nan) for s in ("", "_low", "_high"))
            if np.isfinite(y) and np.isfinite(r.get("total_speedup", np.nan)):
                yerr = [[y - low], [high - y]] if np.isfinite(low) and np.isfinite(high) else None
                ax.errorbar([r["total_speedup"]], [y], yerr=yerr, fmt="s", mfc="none", color="0.3", capsize=3, ms=7,
                            label=f"model: {r['model']}")
        # The axes follow the means: two seeds give intervals 12.7 standard errors wide.
        means = [0.0, 5.0, -5.0] + [100 * r[f"{column}_diff"] for r in rows[1:] if str(r["status"]).startswith("ran")]
        span = max(means) - min(means)
        ax.set_ylim(min(means) - 0.3 * span, max(means) + 0.3 * span)
        speedups = [1.0] + [r["total_speedup"] for r in rows[1:] if str(r["status"]).startswith("ran")]
        ax.set_xlim(0, 1.1 * max(speedups + [3.0]))
    for r in rows[1:]:
        status = str(r["status"])
        if status.startswith("failed") or status.startswith("refused"):
            unsafe.append(f"{r['label']}: {status[:160]}")
    figures.shared_legend(legend_ax, axes[0])
    if unsafe:
        legend_ax.text(0.5, -0.05, "past the stability edge:\n" + "\n".join(unsafe), transform=legend_ax.transAxes,
                       ha="center", va="top", fontsize=7, color="darkred")
    fig.suptitle(f"What the numerical knobs buy, {figures.seeds_text(reference['seeds'])}: the mean paired difference "
                 "with its 95 % Student-t interval\n(clipped to the axes) against the speedup", fontsize=10)
    return figures.save(fig, out / "trade", quiet)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, help="the folder of an `mfdem trade` study")
    parser.add_argument("--compare", type=Path, help="the folder of an `mfdem compare` study, drawn on the same axes")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    rows = files.read_csv(args.out / "trade.csv")
    compare_rows = files.read_csv(args.compare / "compare.csv") if args.compare else []
    trade(rows, compare_rows, args.out / "figures", args.quiet)
    return 0


if __name__ == "__main__":
    sys.exit(main())
