"""The figures of `mfdem plot`: push runs side by side, drawn from OUT/figures.h5 and the runs' push.h5.

    tools/mfdem-py push_figures OUT RUN [RUN ...] [--quiet]      (`mfdem plot` calls it)

Writes OUT/figures/force_displacement (F(u) and the sleeper's heave of every run),
resistance_by_face (the first run's F split into the parts its base, crib sides and shoulder
ends carry, with the weight its base carries), displacement_section and force_chains (every run,
the first as the reference), each .png and .svg. Every number drawn was computed by mfdem.
"""
import argparse
import sys
from pathlib import Path

import matplotlib.pyplot as plt

from mfdem import compare_figures, figures, files


def force_displacement(data, pushes, title, out, quiet):
    scale, unit = figures.force_unit(max(c["mean"].max() for c in data["curves"] if len(c["mean"])))
    fig, ax = plt.subplots(figsize=(8, 5), constrained_layout=True)
    heave_ax = ax.twinx()
    for c, push, colour in zip(data["curves"], pushes, figures.model_colours(len(pushes))):
        peak = push["attrs"]["peak_force"]
        ax.plot(c["u"] * 1e3, c["mean"] * scale, color=colour, lw=1.4,
                label=f"{c['model']}: peak {peak * scale:.3g} {unit} at {push['attrs']['u_at_peak'] * 1e3:.2f} mm")
        heave_ax.plot(push["curve"]["u"] * 1e3, push["curve"]["heave"] * 1e3, color=colour, lw=0.8, ls="--")
    ax.set_xlabel("sleeper displacement u (mm)")
    ax.set_ylabel(f"lateral force on the sleeper F ({unit}), solid")
    heave_ax.set_ylabel("sleeper heave (mm), dashed")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title(f"{title}: lateral resistance F(u) and the sleeper's heave", fontsize=10)
    return figures.save(fig, out / "force_displacement", quiet)


def resistance_by_face(push, label, out, quiet):
    curve = push["curve"]
    if not all(k in curve for k in ("base", "crib", "shoulder")):
        return []  # a push written before the split by face
    scale, unit = figures.force_unit(curve["force"].max())
    u = curve["u"] * 1e3
    fig, ax = plt.subplots(figsize=(8, 5), constrained_layout=True)
    ax.plot(u, curve["force"] * scale, color="black", lw=1.4, label="F, the whole")
    for name, style in (("base", ":"), ("crib", "-."), ("shoulder", "--")):
        ax.plot(u, curve[name] * scale, lw=1.1, ls=style, label=f"carried by the {name}"
                + {"base": " (bottom face)", "crib": " sides (along the track)", "shoulder": " ends"}[name])
    if "support_base" in curve:
        ax.plot(u, curve["support_base"] * scale, color="0.6", lw=0.9,
                label="upward force on the base (the load its friction works with)")
    ax.set_xlabel("sleeper displacement u (mm)")
    ax.set_ylabel(f"force ({unit})")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title(f"{label}: where the lateral resistance comes from", fontsize=10)
    return figures.save(fig, out / "resistance_by_face", quiet)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path, help="the folder holding figures.h5 (mfdem plot --out)")
    parser.add_argument("runs", nargs="+", type=Path, help="the push folders, in figures.h5's order")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    data = files.read_compare_figures(args.out)
    pushes = [files.read_push(r) for r in args.runs]
    title = data["labels"]["config"]
    target = args.out / "figures"
    force_displacement(data, pushes, title, target, args.quiet)
    resistance_by_face(pushes[0], data["curves"][0]["model"], target, args.quiet)
    compare_figures.displacement_section(data, title, target, args.quiet)
    compare_figures.force_chains(data, title, target, args.quiet)
    return 0


if __name__ == "__main__":
    sys.exit(main())
