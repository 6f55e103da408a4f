"""The figures of `mfdem stats`, drawn from OUT/stats.h5.

    tools/mfdem-py stats_figures OUT [--quiet]

Writes OUT/figures/ (PNG and SVG):
  distributions      every output's values over the seeds (a violin and the seeds as points), the
                     mean with its 95 % Student-t interval and the bootstrap interval beside it
  running_mean       the mean and its 95 % band after 2, 3, ... seeds, in the order they were run
  force_displacement F(u): the mean over the seeds and the band from the lowest to the highest seed
  control_variate    with --control: the model's output against the cheap model's on the paired
                     seeds, the control-variate line (slope alpha), both estimates of the mean
Every number drawn was computed by mfdem.
"""
import argparse
import sys
from pathlib import Path

import numpy as np
import matplotlib.pyplot as plt

from mfdem import figures, files


def _panels(n):
    cols = 2
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(10, 3.6 * rows), constrained_layout=True, squeeze=False)
    return fig, axes.ravel()


def _per_output(outputs, draw, suptitle, stem, out, quiet, legend_first=True):
    """One panel per output, drawn by draw(ax, output, scale, unit) in the output's force unit."""
    fig, axes = _panels(len(outputs))
    for ax, o in zip(axes, outputs):
        scale, unit = figures.force_unit(np.nanmax(np.abs(o["values"])))
        draw(ax, o, scale, unit)
    if legend_first:
        axes[0].legend(fontsize=7, loc="best")
    for ax in axes[len(outputs):]:
        ax.axis("off")
    fig.suptitle(suptitle, fontsize=10)
    return figures.save(fig, out / stem, quiet)


def _title(labels):
    return f"{labels['model']} on {labels['config']}, {figures.seeds_text(labels['seeds'])} (each its own packing)"


def distributions(data, out, quiet):
    def draw(ax, o, scale, unit):
        v = o["values"] * scale
        if len(v) >= 3:
            parts = ax.violinplot([v], positions=[0], showextrema=False, widths=0.7)
            for body in parts["bodies"]:
                body.set_alpha(0.25)
        jitter = np.linspace(-0.12, 0.12, len(v)) if len(v) > 1 else np.zeros(1)
        ax.plot(jitter, v, "o", color="0.25", ms=4, label="one seed")
        mean, half = o["mean"] * scale, o["half_width"] * scale
        if np.isfinite(half):
            ax.errorbar([0.55], [mean], yerr=[half], fmt="s", color="C0", capsize=5, label="mean, 95 % t interval")
        else:
            ax.plot([0.55], [mean], "s", color="C0", label="mean (one seed: no interval)")
        if np.isfinite(o["bootstrap_low"]):
            lo, hi = o["bootstrap_low"] * scale, o["bootstrap_high"] * scale
            ax.errorbar([0.8], [mean], yerr=[[mean - lo], [hi - mean]], fmt="D", color="C1", capsize=5,
                        label="mean, 95 % bootstrap interval")
        ax.set_xlim(-0.6, 1.1)
        ax.set_xticks([])
        ax.set_ylabel(f"{o['label']} ({unit})")
        cv = o["standard_deviation"] / abs(o["mean"]) if o["mean"] else 0.0
        ax.set_title(f"{o['label']}: sd {o['standard_deviation'] * scale:.3g} {unit} (cv {100 * cv:.1f} %)", fontsize=9)
        ax.grid(alpha=0.3, axis="y")
    return _per_output(data["outputs"], draw, f"{_title(data['labels'])}: the scatter between packings",
                       "distributions", out, quiet)


def running_mean(data, out, quiet):
    labels = data["labels"]
    width = labels["until_width"] if labels["until_width"] > 0 else labels["report_width"]

    def draw(ax, o, scale, unit):
        n = np.arange(1, len(o["running_mean"]) + 1)
        m, h = o["running_mean"] * scale, o["running_half_width"] * scale
        ax.plot(n, o["values"] * scale, ".", color="0.6", ms=5, label="one seed")
        ax.plot(n, m, "-o", color="C0", ms=3, label="running mean")
        ok = np.isfinite(h)
        ax.fill_between(n[ok], (m - h)[ok], (m + h)[ok], color="C0", alpha=0.2, lw=0, label="its 95 % t interval")
        final = o["mean"] * scale
        ax.axhspan(final * (1 - width), final * (1 + width), color="green", alpha=0.08, lw=0,
                   label=f"+-{100 * width:g} % of the final mean")
        # The first intervals are wide (t(0.975, 1) = 12.7): the axis follows the seeds' values.
        v = o["values"] * scale
        span = max(np.ptp(v), 0.1 * abs(final))
        ax.set_ylim(v.min() - 0.6 * span, v.max() + 0.6 * span)
        ax.set_xlabel("seeds run")
        ax.set_ylabel(f"{o['label']} ({unit})")
        ax.set_title(f"{o['label']} (band clipped to the axis)", fontsize=9)
        ax.grid(alpha=0.3)
        ax.xaxis.get_major_locator().set_params(integer=True)
    return _per_output(data["outputs"], draw, f"{_title(labels)}: the mean as seeds were added", "running_mean", out,
                       quiet)


def force_displacement(data, out, quiet):
    band = {**data["curve"], "label": "mean over the seeds"}
    return figures.force_bands([band], f"{_title(data['labels'])}: F(u);\nband: the lowest to the highest seed at each u",
                               None, out, quiet)


def control_variate(data, out, quiet):
    labels = data["labels"]
    outputs = [o for o in data["outputs"] if "cheap_paired" in o]
    if not outputs:
        return []

    def draw(ax, o, scale, unit):
        hi, lo = o["model_paired"] * scale, o["cheap_paired"] * scale
        ax.plot(lo, hi, "o", color="C0", ms=5, label=f"paired seeds ({len(lo)})")
        for k, x in enumerate(o["cheap_extra"] * scale):  # no model run there: ticks on the axis
            ax.axvline(x, ymax=0.04, color="C1", lw=1, label=f"cheap model alone ({len(o['cheap_extra'])} seeds)"
                       if k == 0 else None)
        x = np.linspace(lo.min(), lo.max(), 2)
        ax.plot(x, hi.mean() + o["alpha"] * (x - lo.mean()), "-", color="0.3", lw=1,
                label=f"alpha = {o['alpha']:.3g}, rho = {o['correlation']:.2f}")
        ax.axhline(o["estimate"] * scale, color="C2", lw=1.2,
                   label=f"control-variate mean {o['estimate'] * scale:.4g} +- {o['estimate_half_width'] * scale:.3g}")
        ax.axhline(hi.mean(), color="C0", lw=1, ls="--", label=f"model's runs alone {hi.mean():.4g}")
        ax.set_xlabel(f"cheap model: {o['label']} ({unit})")
        ax.set_ylabel(f"model: {o['label']} ({unit})")
        verdict = "pays" if o["variance_ratio_optimal"] < 1 else "does not pay"
        ax.set_title(f"{o['label']}\nvariance {o['variance_ratio_optimal']:.2f} x the model's runs alone at equal "
                     f"cost, best split: {verdict}", fontsize=8)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, loc="best")
    return _per_output(outputs, draw, f"{_title(labels)}; {labels['control_model']} as a control variate",
                       "control_variate", out, quiet, legend_first=False)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, help="the folder of an `mfdem stats` study")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    data = files.read_stats(args.out)
    target = args.out / "figures"
    distributions(data, target, args.quiet)
    running_mean(data, target, args.quiet)
    force_displacement(data, target, args.quiet)
    control_variate(data, target, args.quiet)
    return 0


if __name__ == "__main__":
    sys.exit(main())
