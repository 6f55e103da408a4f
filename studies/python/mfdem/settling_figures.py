"""How beds came to rest: the settling stages of packings, drawn from their packing.h5.

    tools/mfdem-py settling_figures OUT.png PACKING [PACKING ...] [--labels A,B,...]
                                   [--stage settle] [--ratio 1e-3] [--creep 1e-4] [--quiet]

One row per run: the mean unbalanced force ratio, the kinetic energy over M g d and (when the
packing recorded it) the creep, the stones' mean displacement over the creep window over their
mean size, against the stage's time; the targets dashed, the stage's end marked with how it
ended (force ratio, creep, or the time limit). Every number drawn was recorded by mfdem at the
stage's equilibrium checks (studies/railway/packing.hpp: /packing/stages/NAME).
"""
import argparse
import sys
from pathlib import Path

import matplotlib.pyplot as plt

from mfdem import figures, files


def how_it_ended(attrs) -> str:
    if not attrs.get("settled", 0):
        return "time limit"
    return "by creep" if attrs.get("settled_by_creep", 0) else "by force ratio"


def draw(packings, labels, stage, ratio, creep, stem, quiet):
    fig, axes = plt.subplots(len(packings), 1, figsize=(8, 2.6 * len(packings) + 0.6), sharex=True,
                             squeeze=False, constrained_layout=True)
    for ax, packing, label in zip(axes[:, 0], packings, labels):
        s = packing["stages"].get(stage)
        if s is None:
            raise ValueError(f"{packing['path']}: no stage '{stage}' (it has {', '.join(packing['stages'])})")
        t = s["time"]
        ax.semilogy(t, s["unbalanced_force_ratio"], color="C0", label="unbalanced force ratio")
        ax.semilogy(t, s["kinetic_ratio"], color="C1", label="kinetic energy / (M g d)")
        if "creep" in s:
            ax.semilogy(t, s["creep"], color="C2", label="creep: mean displacement per window / d")
        ax.axhline(ratio, color="C0", ls="--", lw=0.8, label=f"force and kinetic target {ratio:g}")
        if creep:
            ax.axhline(creep, color="C2", ls="--", lw=0.8, label=f"creep target {creep:g}")
        ax.axvline(t[-1], color="k", lw=0.8)
        ax.set_title(f"{label}: ended at {t[-1]:.3f} s, {how_it_ended(s['attrs'])}", fontsize=10)
        ax.set_ylabel("ratio (-)")
        ax.grid(True, which="major", alpha=0.3)
    axes[0, 0].legend(fontsize=7, loc="upper right")
    axes[-1, 0].set_xlabel(f"time since the '{stage}' stage began (s, simulated)")
    fig.suptitle(f"How the beds came to rest ({stage})", fontsize=11)
    figures.save(fig, stem, quiet)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, help="the figure to write (.png, and .svg beside it)")
    parser.add_argument("packings", nargs="+", type=Path, help="packing.h5 files or the folders holding them")
    parser.add_argument("--labels", help="comma-separated, one per packing (default: the folder names)")
    parser.add_argument("--stage", default="settle", help="the stage to draw (default: settle)")
    parser.add_argument("--ratio", type=float, default=1e-3, help="the equilibrium_ratio to mark")
    parser.add_argument("--creep", type=float, default=0.0, help="the creep_ratio to mark (0: none)")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    labels = args.labels.split(",") if args.labels else [Path(p).name for p in args.packings]
    if len(labels) != len(args.packings):
        parser.error(f"--labels has {len(labels)} names for {len(args.packings)} packings")
    packings = [files.read_packing(p) for p in args.packings]
    draw(packings, labels, args.stage, args.ratio, args.creep, args.out.with_suffix(""), args.quiet)
    return 0


if __name__ == "__main__":
    sys.exit(main())
