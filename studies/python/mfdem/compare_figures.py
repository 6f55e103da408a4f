"""The four figures of `mfdem compare`, drawn from OUT/figures.h5 and OUT/compare.csv.

    PYTHONPATH=studies/python /usr/bin/python3 -m mfdem.compare_figures OUT [--quiet]

Writes OUT/figures/{force_displacement, displacement_section, force_chains, speedup_error}.png
and .svg. `mfdem compare` calls it at its end; every number drawn was computed by it.
"""
import argparse
import sys
import textwrap
from pathlib import Path

import numpy as np
import matplotlib.pyplot as plt
from matplotlib.collections import EllipseCollection, LineCollection
from matplotlib.colors import Normalize

from mfdem import figures, files


def force_displacement(data, config, out, quiet):
    bands = [{**c, "label": f"{c['model']} ({figures.seeds_text(c['seeds'])})"} for c in data["curves"]]
    return figures.force_bands(bands, f"{config}: lateral resistance F(u), the mean over the seeds;\n"
                               "band: the lowest to the highest seed at each u", "model (the first is the reference)",
                               out, quiet)


def section_panels(data, title):
    s = data["section"]
    views = data["views"]
    width = 11.0
    ratio = (s["z_max"] - s["z_min"]) / (s["x_max"] - s["x_min"])
    fig, axes = plt.subplots(len(views), 1, figsize=(width, 1.4 + len(views) * (width * 0.82 * ratio + 0.45)),
                             constrained_layout=True, squeeze=False)
    axes = axes[:, 0]
    for ax, v in zip(axes, views):
        ax.set_xlim(s["x_min"], s["x_max"])
        ax.set_ylim(s["z_min"], s["z_max"])
        ax.set_aspect("equal")
        ax.set_title(v["model"], fontsize=9, loc="left")
        ax.set_ylabel("z (m)")
        figures.sleeper_outline(ax, s["sleeper_x0"], s["sleeper_x1"], s["sleeper_z0"], s["sleeper_z1"])
    axes[-1].set_xlabel("x across the track (m); the sleeper pushed towards +x")
    fig.suptitle("\n".join(textwrap.fill(part, 125) for part in title.split("\n")), fontsize=10)
    return fig, axes


def slab_text(s, what="the stones whose centres lie") -> str:
    return (f"seed {int(s['seed'])}: {what} within {s['slab_half_width'] * 1e3:.0f} mm of the vertical plane "
            "through the sleeper's centre, seen along the track")


def displacement_section(data, config, out, quiet):
    s = data["section"]
    clip_mm = max(s["displacement_clip"] * 1e3, 1e-6)
    fig, axes = section_panels(
        data, f"{config}: stone displacement over the push, at u_end; {slab_text(s)}, each a disc of 70 % of its "
              f"sieve size (the slab's stones overlap in projection). One colour scale for every panel, clipped at "
              f"the {100 * s['clip_percentile']:.0f}th percentile of their stones ({clip_mm:.2f} mm)")
    norm = Normalize(0.0, clip_mm)
    mappable = None
    for ax, v in zip(axes, data["views"]):
        if not len(v["x"]):
            continue
        discs = EllipseCollection(1.4 * v["radius"], 1.4 * v["radius"], np.zeros_like(v["x"]), units="xy",
                                  offsets=np.column_stack([v["x"], v["z"]]), offset_transform=ax.transData,
                                  array=np.minimum(v["displacement"] * 1e3, clip_mm), cmap="viridis", norm=norm,
                                  edgecolors="0.3", linewidths=0.2)
        ax.add_collection(discs)
        mappable = discs
    if mappable is not None:
        fig.colorbar(mappable, ax=list(axes), extend="max", shrink=0.9, aspect=35,
                     label=f"displacement (mm), clipped at {clip_mm:.2f} mm")
    return figures.save(fig, out / "displacement_section", quiet)


def force_chains(data, config, out, quiet):
    s = data["section"]
    scale, unit = figures.force_unit(s["largest_chain_force"])
    clip = max(s["chain_clip"], s["chain_threshold"], 1e-12)
    fig, axes = section_panels(
        data, f"{config}: force chains at u_end; {slab_text(s, 'the stone-stone contacts')}, carrying at least "
              f"{s['chain_threshold'] * scale:.3g} {unit} (the reference's mean contact force), each a line between "
              f"the two stones' centres. Width and colour by force on one scale for every panel, clipped at the "
              f"{100 * s['clip_percentile']:.0f}th percentile of the chains drawn ({clip * scale:.3g} {unit}; "
              f"the largest {s['largest_chain_force'] * scale:.3g} {unit})")
    norm = Normalize(s["chain_threshold"] * scale, clip * scale)
    mappable = None
    for ax, v in zip(axes, data["views"]):
        if not len(v["force"]):
            continue
        order = np.argsort(v["force"])  # the strongest drawn last, on top
        segments = np.stack([np.column_stack([v["x1"], v["z1"]]), np.column_stack([v["x2"], v["z2"]])], axis=1)
        lines = LineCollection(segments[order], linewidths=0.6 + 3.4 * np.minimum(v["force"][order] / clip, 1.0),
                               array=np.minimum(v["force"][order], clip) * scale, cmap="inferno_r", norm=norm)
        ax.add_collection(lines)
        mappable = lines
    if mappable is not None:
        fig.colorbar(mappable, ax=list(axes), extend="max", shrink=0.9, aspect=35,
                     label=f"contact force ({unit}), clipped at {clip * scale:.3g}")
    return figures.save(fig, out / "force_chains", quiet)


def speedup_error(rows, config, seeds, out, quiet, tolerance):
    fig, axes, legend_ax = figures.error_speedup_figure(5.6, 0.22)
    outputs = [("peak_force", "peak lateral force", "peak"), ("max_contact_force", "maximum contact force", "contact")]
    colours = figures.model_colours(len(rows))
    reference = next(r for r in rows if r["reference"] == 1)
    ordered = [reference] + [r for r in rows if r is not reference]
    for ax, (column, name, paper_key) in zip(axes, outputs):
        figures.error_speedup_panel(ax, name, paper_key, tolerance)
        for r, colour in zip(ordered, colours):
            x, y = r["total_speedup"], 100 * r[f"{column}_diff"]
            if not np.isfinite(x) or not np.isfinite(y):
                continue
            low, high = 100 * r[f"{column}_diff_low"], 100 * r[f"{column}_diff_high"]
            yerr = None if not (np.isfinite(low) and np.isfinite(high)) else [[y - low], [high - y]]
            ax.errorbar([x], [y], yerr=yerr, fmt="o", color=colour, capsize=4, ms=6, label=r["model"])
            # Each seed's own difference: with few seeds it says more than an interval with n - 1
            # degrees of freedom (two seeds: t = 12.7).
            per_seed = [100 * float(v) for v in str(r.get(f"{column}_diff_per_seed") or "").split()]
            if len(per_seed) > 1 and not r["reference"]:
                ax.plot([x] * len(per_seed), per_seed, marker="x", ms=7, mew=1.5, color=colour, ls="none")
            # The push alone, hollow: the paper's 2.75x is of its push, which was its whole cost.
            push = r["push_speedup"]
            if np.isfinite(push) and not r["reference"]:
                ax.plot([x, push], [y, y], color=colour, lw=0.8, ls=":")
                ax.plot([push], [y], marker="o", ms=6, mfc="white", mec=colour, ls="none")
        ax.plot([], [], marker="o", ms=6, mfc="white", mec="0.3", ls="none", label="the same model, push alone")
        ax.plot([], [], marker="x", ms=7, mew=1.5, color="0.3", ls="none", label="one seed's paired difference")
        ax.set_xlabel("speedup (x): the reference's wall time over the model's;\n"
                      "filled: re-settling + push, hollow: the push alone (as the paper's)")
        largest = max(max(r["total_speedup"], r["push_speedup"]) for r in rows
                      if np.isfinite(r["total_speedup"]) and np.isfinite(r["push_speedup"]))
        ax.set_xlim(0, max(3.0, 1.1 * largest))
    figures.shared_legend(legend_ax, axes[0])
    fig.suptitle(f"{config}: what each model saved and what it cost, {figures.seeds_text(seeds)}; the mean paired "
                 "difference\nwith its 95 % Student-t interval over the seeds (none with one seed)", fontsize=10)
    return figures.save(fig, out / "speedup_error", quiet)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, help="the folder of an `mfdem compare` study")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    data = files.read_compare_figures(args.out)
    rows = files.read_csv(args.out / "compare.csv")
    config = data["labels"]["config"]
    seeds = data["labels"]["seeds"]
    target = args.out / "figures"
    force_displacement(data, config, target, args.quiet)
    displacement_section(data, config, target, args.quiet)
    force_chains(data, config, target, args.quiet)
    speedup_error(rows, config, seeds, target, args.quiet, data["labels"]["tolerance"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
